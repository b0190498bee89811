//! The hostile cases of trust (beside `hostile.rs`, which covers bad input): a cache that was damaged, edited or
//! replaced by something that is not a file; output that goes to a closed pipe; output names that are not UTF-8
//! or would overwrite files a run did not create; runs killed while they write. Each must end with the right
//! result and no panic: a damaged cache entry is recomputed with one note, never used, and never hangs or fills
//! memory; a closed pipe ends a command quietly; no temporary file outlives the next run in its folder.

mod common;

use std::ffi::OsString;
use std::os::unix::ffi::OsStringExt;
use std::os::unix::process::ExitStatusExt;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

/// A fresh folder under the target's scratch space.
fn folder(name: &str) -> PathBuf {
    let dir = common::place::scratch_root().join("hostile-trust").join(name);
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn command(cache: &Path, args: &[&std::ffi::OsStr]) -> Command {
    let mut c = Command::new(common::place::diffract_bin());
    c.args(args).env_remove("DIFFRACT_VALIDATION").env("DIFFRACT_CACHE", cache).stdin(Stdio::null());
    c
}

/// Runs diffract with its cache in `cache`, stopped after `limit`.
fn run(cache: &Path, args: &[&std::ffi::OsStr], limit: Duration) -> Output {
    let mut child = command(cache, args).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > limit {
            let _ = child.kill();
            let o = child.wait_with_output().unwrap();
            panic!("still running after {limit:?}: {}", String::from_utf8_lossy(&o.stderr));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

fn os(args: &[&str]) -> Vec<OsString> {
    args.iter().map(OsString::from).collect()
}

fn refs(args: &[OsString]) -> Vec<&std::ffi::OsStr> {
    args.iter().map(|a| a.as_os_str()).collect()
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Success, no panic, no error line, and exactly `notes` lines that are cache notes.
fn assert_ok_with_notes(o: &Output, notes: usize, what: &str) {
    let err = stderr(o);
    assert!(o.status.success(), "{what}: {err}");
    assert!(!err.contains("panicked") && !err.lines().any(|l| l.starts_with("error")), "{what}: {err}");
    let n = err.lines().filter(|l| l.starts_with("note: the cached")).count();
    assert_eq!(n, notes, "{what}: {err}");
}

/// The cache's entries whose names start with `kind`.
fn entries(cache: &Path, kind: &str) -> Vec<PathBuf> {
    let mut v: Vec<PathBuf> = std::fs::read_dir(cache)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.file_name().unwrap().to_string_lossy().starts_with(&format!("{kind}-")))
        .collect();
    v.sort();
    v
}

/// A small sinusoidal grating's baked BRDF map (PNG) in `dir`, with its cache in `cache`.
fn baked_map(dir: &Path, cache: &Path, out: &str) -> (Output, Vec<u8>) {
    let patch = dir.join("sine.gsf");
    if !patch.exists() {
        common::sine_patch(&patch);
    }
    let png = dir.join(out);
    let args = os(&["map", "--heightfield", patch.to_str().unwrap(), "--light-theta", "20", "--approach", "baked"]);
    let args = [args, os(&["--size", "24", "--exposure", "4", "--out", png.to_str().unwrap()])].concat();
    let o = run(cache, &refs(&args), Duration::from_secs(300));
    let bytes = std::fs::read(&png).unwrap_or_default();
    (o, bytes)
}

#[test]
fn a_damaged_edited_or_replaced_cache_entry_is_rebuilt_with_one_note() {
    let dir = folder("cache-entries");
    let cache = dir.join("cache");
    let (o, clean) = baked_map(&dir, &cache, "clean.png");
    assert_ok_with_notes(&o, 0, "the first run");
    let (table, estimate) = (entries(&cache, "baked"), entries(&cache, "estimate"));
    assert_eq!((table.len(), estimate.len()), (1, 1), "{table:?} {estimate:?}");
    let (table, estimate) = (&table[0], &estimate[0]);
    let original = std::fs::read(table).unwrap();
    let (o, again) = baked_map(&dir, &cache, "again.png");
    assert_ok_with_notes(&o, 0, "from the cache");
    assert_eq!(again, clean, "the cached table draws the same map");

    // Damage to the table's texels: an exponent bit flipped, a NaN written over a texel.
    let at = (original.len() * 3 / 5) & !3;
    let mut flipped = original.clone();
    flipped[at + 3] ^= 0x40;
    let mut nan = original.clone();
    nan[at..at + 4].copy_from_slice(&f32::NAN.to_le_bytes());
    for (what, bytes) in [("a flipped exponent bit", flipped), ("a NaN texel", nan)] {
        std::fs::write(table, bytes).unwrap();
        let (o, image) = baked_map(&dir, &cache, "damaged.png");
        assert_ok_with_notes(&o, 1, what);
        assert!(stderr(&o).contains("fails its checksum"), "{what}: {}", stderr(&o));
        assert_eq!(image, clean, "{what}: the map is drawn from a rebuilt table");
        assert_eq!(std::fs::read(table).unwrap(), original, "{what}: the rebuilt entry replaces the damaged one");
    }

    // The estimate edited to 1 term: refused by its checksum. Forged with a valid checksum, it is obeyed as an
    // estimate only: the build still certifies the degree, and the map is the same.
    let good = std::fs::read(estimate).unwrap();
    let terms_at = good.len() - 32;
    let mut edited = good.clone();
    edited[terms_at..terms_at + 8].copy_from_slice(&1u64.to_le_bytes());
    std::fs::write(estimate, &edited).unwrap();
    let (o, image) = baked_map(&dir, &cache, "edited.png");
    assert_ok_with_notes(&o, 1, "an edited estimate");
    assert_eq!(image, clean);
    let crc_at = terms_at - 4;
    let mut crc = crc32fast::Hasher::new();
    crc.update(&edited[..crc_at]);
    crc.update(&edited[terms_at..]);
    edited[crc_at..terms_at].copy_from_slice(&crc.finalize().to_le_bytes());
    std::fs::write(estimate, &edited).unwrap();
    let (o, image) = baked_map(&dir, &cache, "forged.png");
    assert_ok_with_notes(&o, 0, "a forged estimate");
    assert!(stderr(&o).contains("about 1 terms in w") || stdout_or_err_has(&o, "about 1 terms"), "{}", stderr(&o));
    assert_eq!(image, clean, "a forged estimate cannot change the certified table");
    std::fs::write(estimate, &good).unwrap();

    // A FIFO in the table's place would block a plain open: it is passed over and replaced.
    std::fs::remove_file(table).unwrap();
    let ok = Command::new("mkfifo").arg(table).status().map(|s| s.success()).unwrap_or(false);
    assert!(ok, "mkfifo (coreutils) is needed");
    let (o, image) = baked_map(&dir, &cache, "fifo.png");
    assert_ok_with_notes(&o, 1, "a FIFO entry");
    assert!(stderr(&o).contains("not a regular file"), "{}", stderr(&o));
    assert_eq!(image, clean);
    assert!(std::fs::metadata(table).unwrap().is_file(), "the FIFO was replaced by the rebuilt entry");

    // A 6 GiB sparse entry is refused from its header, not read.
    std::fs::OpenOptions::new().write(true).open(table).unwrap().set_len(6 << 30).unwrap();
    let patch = dir.join("sine.gsf");
    let png = dir.join("sparse.png");
    let args = os(&["map", "--heightfield", patch.to_str().unwrap(), "--light-theta", "20", "--approach", "baked"]);
    let args = [args, os(&["--size", "24", "--exposure", "4", "--out", png.to_str().unwrap()])].concat();
    let (o, max_rss_kib) = run_measured(&cache, &refs(&args));
    assert_ok_with_notes(&o, 1, "a 6 GiB entry");
    assert!(stderr(&o).contains("where its header says"), "{}", stderr(&o));
    assert!(max_rss_kib < 2 << 20, "resident memory {max_rss_kib} KiB: the entry was read");
    assert_eq!(std::fs::read(&png).unwrap(), clean);
}

fn stdout_or_err_has(o: &Output, needle: &str) -> bool {
    String::from_utf8_lossy(&o.stdout).contains(needle) || stderr(o).contains(needle)
}

/// Runs to the end and returns the output with the child's peak resident memory (KiB, from wait4, which reaps it:
/// std's handle is not waited on).
#[allow(clippy::zombie_processes)]
fn run_measured(cache: &Path, args: &[&std::ffi::OsStr]) -> (Output, i64) {
    let out = common::place::scratch_root().join("hostile-trust").join("measured.err");
    let child =
        command(cache, args).stdout(Stdio::null()).stderr(std::fs::File::create(&out).unwrap()).spawn().unwrap();
    let mut status = 0;
    // SAFETY: a zeroed rusage is a valid value for wait4 to fill in.
    let mut usage: libc::rusage = unsafe { std::mem::zeroed() };
    // SAFETY: waits for our own child by its pid (std's handle is not waited on afterwards).
    let pid = unsafe { libc::wait4(child.id() as libc::pid_t, &mut status, 0, &mut usage) };
    assert_eq!(pid, child.id() as libc::pid_t);
    let o = Output {
        status: std::process::ExitStatus::from_raw(status),
        stdout: Vec::new(),
        stderr: std::fs::read(&out).unwrap(),
    };
    (o, usage.ru_maxrss)
}

#[test]
fn a_damaged_profiler_reference_is_recomputed_not_measured_against() {
    let dir = folder("reference");
    let patch = dir.join("sine.gsf");
    common::sine_patch(&patch);
    let refs_dir = dir.join("references");
    let args = os(&["profile", "--heightfield", patch.to_str().unwrap(), "--width", "12", "--frames", "1"]);
    let args =
        [args, os(&["--warmup", "0", "--sweep", "approach=flss", "--reference-cache", refs_dir.to_str().unwrap()])]
            .concat();
    let mean_de = |o: &Output| -> String {
        let out = String::from_utf8_lossy(&o.stdout).into_owned();
        let row = out.lines().find(|l| l.starts_with("| flss")).unwrap_or_else(|| panic!("no row: {out}")).to_string();
        row.split('|').nth(10).unwrap().trim().to_string()
    };
    let first = run(&dir.join("cache"), &refs(&args), Duration::from_secs(300));
    assert_ok_with_notes(&first, 0, "the first profile");
    let entry = entries(&refs_dir, "reference");
    assert_eq!(entry.len(), 1);
    let mut bytes = std::fs::read(&entry[0]).unwrap();
    // Overwrite some pixels' XYZ (f64, the payload's bulk) with a plausible but wrong value.
    let at = bytes.len() / 2;
    for chunk in bytes[at..at + 200].chunks_exact_mut(8) {
        chunk.copy_from_slice(&0.5f64.to_le_bytes());
    }
    std::fs::write(&entry[0], &bytes).unwrap();
    let second = run(&dir.join("cache"), &refs(&args), Duration::from_secs(300));
    assert_ok_with_notes(&second, 1, "a damaged reference");
    assert!(stderr(&second).contains("reference image"), "{}", stderr(&second));
    assert_eq!(mean_de(&second), mean_de(&first), "measured against the recomputed reference");
}

/// Every command, small, writing its files (if any) into `dir`, with the file each writes.
fn every_command(dir: &Path) -> Vec<(Vec<String>, Option<PathBuf>)> {
    let patch = dir.join("sine.gsf");
    common::sine_patch(&patch);
    let p = patch.to_str().unwrap();
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let commands: Vec<Vec<String>> = vec![
        vec!["devices".into()],
        vec!["terms".into(), "--heightfield".into(), p.into()],
        ["brdf", "--heightfield", p, "--light-theta", "0", "--view-theta", "0:80:0.01", "--lambda", "550"]
            .map(String::from)
            .to_vec(),
        ["map", "--heightfield", p, "--light-theta", "0", "--approach", "gem", "--size", "16", "--out", &out("m.png")]
            .map(String::from)
            .to_vec(),
        ["render", "--approach", "gem", "--width", "16", "--height", "16", "--out", &out("r.png")]
            .map(String::from)
            .to_vec(),
        ["gen", "patch", "flat", "--size-um", "2", "--out", &out("g.gsf")].map(String::from).to_vec(),
        ["profile", "--heightfield", p, "--width", "8", "--frames", "1", "--no-reference", "--sweep", "approach=gem"]
            .map(String::from)
            .to_vec(),
        ["gen", "sky", "--width", "32", "--out", &out("s.exr")].map(String::from).to_vec(),
        vec!["--help".into()],
        vec!["render".into(), "--help".into()],
    ];
    commands
        .into_iter()
        .map(|args| {
            let written = args.iter().position(|a| a == "--out").map(|i| PathBuf::from(&args[i + 1]));
            (args, written)
        })
        .collect()
}

#[test]
fn a_closed_pipe_ends_every_command_quietly() {
    let dir = folder("pipes");
    for (args, _) in every_command(&dir) {
        let args: Vec<OsString> = args.iter().map(OsString::from).collect();
        // stdout is a pipe whose reading end is closed before the command writes to it.
        let mut child =
            command(&dir.join("cache"), &refs(&args)).stdout(Stdio::piped()).stderr(Stdio::piped()).spawn().unwrap();
        drop(child.stdout.take());
        let o = child.wait_with_output().unwrap();
        let err = stderr(&o);
        let quiet = o.status.success() || o.status.signal() == Some(libc::SIGPIPE);
        assert!(quiet, "{args:?}: {:?}: {err}", o.status);
        let error_line = err.lines().any(|l| l.starts_with("error"));
        assert!(!err.contains("panicked") && !err.contains("Broken pipe") && !error_line, "{args:?}: {err}");
    }
}

/// A stream that cannot be written (`> /dev/full`, `2> /dev/full`: a full disk) fails the run in one line and a
/// non-zero status, never a panic, and what the command writes to files is written all the same.
#[test]
fn a_full_stdout_or_stderr_fails_every_command_without_a_panic() {
    let dir = folder("full");
    for (args, written) in every_command(&dir) {
        if args.iter().any(|a| a == "--help") {
            continue; // clap writes help itself; it ignores a failed write
        }
        let args: Vec<OsString> = args.iter().map(OsString::from).collect();
        let full = || std::fs::OpenOptions::new().write(true).open("/dev/full").unwrap();
        // stdout on a full disk: one error line naming it, status 1.
        let o = command(&dir.join("cache"), &refs(&args)).stdout(full()).stderr(Stdio::piped()).output().unwrap();
        let err = stderr(&o);
        let last = err.lines().last().unwrap_or("");
        assert_eq!(o.status.code(), Some(1), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(last.starts_with("error: could not write to standard output"), "{args:?}: {err}");
        assert_eq!(err.lines().filter(|l| l.starts_with("error")).count(), 1, "{args:?}: {err}");
        // stderr on a full disk: no panic (status 101), the files written; status 1 where it had lines to write.
        if let Some(path) = &written {
            let _ = std::fs::remove_file(path);
        }
        let o = command(&dir.join("cache"), &refs(&args)).stdout(Stdio::piped()).stderr(full()).output().unwrap();
        assert!(matches!(o.status.code(), Some(0 | 1)), "{args:?}: {:?}", o.status);
        if let Some(path) = &written {
            assert!(path.exists(), "{args:?}: {} not written", path.display());
        }
    }
}

/// A scene that renders fast (a flat patch, Stam's analytic grating).
fn quick_scene(dir: &Path) -> PathBuf {
    let path = dir.join("quick.toml");
    std::fs::write(
        &path,
        "[camera]\nposition = [0.0, 0.5, 3.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 30.0\n\n[light]\ndirection = [0.3, 1.0, 0.5]\n\n\
         [[object]]\nshape = \"sphere\"\nmaterial = \"m\"\n\n[material.m]\ngenerate = \"flat\"\nsize_um = 2.0\n\
         approach = \"gem\"\n",
    )
    .unwrap();
    path
}

#[test]
fn output_names_are_used_as_given_and_sequences_do_not_overwrite_other_files() {
    let dir = folder("names");
    let scene = quick_scene(&dir);
    let cache = dir.join("cache");
    let unrelated = dir.join("frame_0001.png");
    std::fs::write(&unrelated, "an unrelated file").unwrap();
    // A name that is not UTF-8 (as LANG=C shells pass $'\xff\xfe.png'): its frames keep its bytes.
    let odd = dir.join(OsString::from_vec(b"\xff\xfe.png".to_vec()));
    let args = [
        os(&["render", scene.to_str().unwrap(), "--frames", "2", "--orbit", "--width", "16", "--height", "16"]),
        vec![OsString::from("--out"), odd.clone().into_os_string()],
    ]
    .concat();
    let o = run(&cache, &refs(&args), Duration::from_secs(300));
    assert!(o.status.success(), "{}", stderr(&o));
    for f in [b"\xff\xfe_0001.png", b"\xff\xfe_0002.png"] {
        assert!(dir.join(OsString::from_vec(f.to_vec())).is_file(), "{:?}", String::from_utf8_lossy(f));
    }
    assert_eq!(std::fs::read_to_string(&unrelated).unwrap(), "an unrelated file");
    // A single frame and a map with such a name are written under it.
    let map_out = dir.join(OsString::from_vec(b"map-\xff.png".to_vec()));
    let patch = dir.join("flat.gsf");
    let g = run(
        &cache,
        &refs(&os(&["gen", "patch", "flat", "--size-um", "2", "--out", patch.to_str().unwrap()])),
        Duration::from_secs(60),
    );
    assert!(g.status.success(), "{}", stderr(&g));
    let args = [
        os(&[
            "map",
            "--heightfield",
            patch.to_str().unwrap(),
            "--light-theta",
            "0",
            "--approach",
            "gem",
            "--size",
            "8",
        ]),
        vec![OsString::from("--out"), map_out.clone().into_os_string()],
    ]
    .concat();
    let o = run(&cache, &refs(&args), Duration::from_secs(120));
    assert!(o.status.success() && map_out.is_file(), "{}", stderr(&o));

    // A sequence whose frame file exists already is refused before any work, the file kept; --overwrite lets it.
    let existing = dir.join("s_0002.png");
    std::fs::write(&existing, "not a frame of this run").unwrap();
    let base = os(&["render", scene.to_str().unwrap(), "--frames", "2", "--light-sweep", "--width", "16"]);
    let args = [base.clone(), os(&["--height", "16", "--out", dir.join("s.png").to_str().unwrap()])].concat();
    let o = run(&cache, &refs(&args), Duration::from_secs(120));
    common::assert_one_line_error(&o, "--overwrite");
    assert!(stderr(&o).contains("s_0002.png"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&existing).unwrap(), "not a frame of this run");
    assert!(!dir.join("s_0001.png").exists(), "refused before any frame was written");
    let args = [args, os(&["--overwrite"])].concat();
    let o = run(&cache, &refs(&args), Duration::from_secs(120));
    assert!(o.status.success(), "{}", stderr(&o));
    assert!(std::fs::read(&existing).unwrap().starts_with(b"\x89PNG"), "replaced by the sequence's frame");
}

/// The temporary files in `dir`.
fn temporaries(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".diffract-tmp-"))
        .collect()
}

/// Starts writing a large GSF into `dir` and sends `signal` once its temporary file is there; returns the exit
/// status, or None where the write finished before the temporary file was seen.
fn interrupt_a_write(dir: &Path, signal: i32) -> Option<std::process::ExitStatus> {
    let out = dir.join("big.gsf");
    let args = os(&["gen", "patch", "flat", "--size-um", "300", "--pixel-um", "0.05", "--out", out.to_str().unwrap()]);
    let mut child =
        command(&dir.join("cache"), &refs(&args)).stdout(Stdio::null()).stderr(Stdio::null()).spawn().unwrap();
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            assert!(status.success());
            return None;
        }
        if !temporaries(dir).is_empty() {
            // SAFETY: signals our own child, which is still running (not yet waited for).
            unsafe { libc::kill(child.id() as libc::pid_t, signal) };
            return Some(child.wait().unwrap());
        }
        assert!(start.elapsed() < Duration::from_secs(120), "no temporary file appeared");
        std::thread::sleep(Duration::from_millis(1));
    }
}

#[test]
fn runs_killed_while_writing_leave_no_temporary_file_behind() {
    let dir = folder("kills");
    let big = dir.join("big.gsf");
    let gen_small = |name: &str| {
        let args = os(&["gen", "patch", "flat", "--size-um", "2", "--out", dir.join(name).to_str().unwrap()]);
        let o = run(&dir.join("cache"), &refs(&args), Duration::from_secs(60));
        assert!(o.status.success(), "{}", stderr(&o));
    };
    // A temporary file of a process that is gone is removed by the next write in its folder; one whose writer
    // still runs (this test) is not.
    let mut gone = Command::new("true").spawn().unwrap();
    let dead = gone.id();
    gone.wait().unwrap();
    let stale = dir.join(format!(".diffract-tmp-{dead}-0-old.png"));
    let live = dir.join(format!(".diffract-tmp-{}-0-live.png", std::process::id()));
    std::fs::write(&stale, "left by a killed run").unwrap();
    std::fs::write(&live, "being written").unwrap();
    gen_small("a.gsf");
    assert!(!stale.exists() && live.exists());
    std::fs::remove_file(&live).unwrap();

    // Ctrl-C (SIGINT) and SIGTERM while a temporary file is written: removed before the process ends (130); the
    // earlier output is kept.
    for (signal, name) in [(libc::SIGINT, "SIGINT"), (libc::SIGTERM, "SIGTERM")] {
        std::fs::write(&big, "an earlier big.gsf").unwrap();
        let status = (0..3).find_map(|_| interrupt_a_write(&dir, signal));
        let Some(status) = status else { panic!("{name}: the write never overlapped the signal in 3 tries") };
        assert_eq!(status.code(), Some(130), "{name}: {status:?}");
        assert_eq!(temporaries(&dir), Vec::<String>::new(), "{name}");
        assert_eq!(std::fs::read_to_string(&big).unwrap(), "an earlier big.gsf", "{name}");
    }

    // SIGKILL cannot be caught: its temporary file stays until the next run that writes in the folder.
    std::fs::write(&big, "an earlier big.gsf").unwrap();
    let status = (0..3).find_map(|_| interrupt_a_write(&dir, libc::SIGKILL));
    assert_eq!(status.and_then(|s| s.signal()), Some(libc::SIGKILL));
    assert_eq!(temporaries(&dir).len(), 1);
    gen_small("b.gsf");
    assert_eq!(temporaries(&dir), Vec::<String>::new());
    assert_eq!(std::fs::read_to_string(&big).unwrap(), "an earlier big.gsf");
}
