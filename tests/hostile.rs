//! Hostile input, as a careless user or an attacker would give it: broken and oversized files, special files
//! where a file is expected, absurd and non-finite numbers in flags and scenes, outputs that cannot be written.
//! Every case must end in bounded time and memory with exactly one `error:` line on stderr (its last line) and
//! a non-zero exit that is not a panic (101) or an abort (134), and must leave the outputs already in its
//! folder byte for byte as they were, with no temporary file behind.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// The longest a case may take (a debug build on a slow machine; the failures are meant to be immediate).
const TIME_LIMIT: Duration = Duration::from_secs(120);
/// The address space a case may use, KiB (lavapipe maps a few GiB of virtual memory for its JIT).
const MEMORY_LIMIT_KIB: u64 = 8 << 20;

/// The fixtures every case may name, in one folder (relative paths below are relative to it).
fn fixtures() -> &'static Path {
    static DIR: OnceLock<PathBuf> = OnceLock::new();
    DIR.get_or_init(|| {
        let dir = common::place::scratch_root().join("hostile-fixtures");
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(dir.join("folder.gsf")).unwrap();
        let write = |name: &str, bytes: &[u8]| std::fs::write(dir.join(name), bytes).unwrap();
        let heights = vec![0.0f32; 64];
        write("good.gsf", &gsf("XRes = 8\nYRes = 8\nXReal = 8e-7\nYReal = 8e-7\n", &heights));
        write("truncated.gsf", &gsf("XRes = 8\nYRes = 8\nXReal = 8e-7\nYReal = 8e-7\n", &heights[..40]));
        write("huge-res.gsf", &gsf("XRes = 1000000000\nYRes = 1000000000\nXReal = 1\nYReal = 1\n", &heights));
        write("huge-real.gsf", &gsf("XRes = 8\nYRes = 8\nXReal = 1e30\nYReal = 1e30\n", &heights));
        write("nan-real.gsf", &gsf("XRes = 8\nYRes = 8\nXReal = nan\nYReal = 1e-6\n", &heights));
        let mut nan_data = heights.clone();
        nan_data[9] = f32::NAN;
        write("nan-data.gsf", &gsf("XRes = 8\nYRes = 8\nXReal = 8e-7\nYReal = 8e-7\n", &nan_data));
        write("deep.gsf", &gsf("XRes = 8\nYRes = 8\nXReal = 8e-7\nYReal = 8e-7\n", &deep_grating()));
        write("twice.gsf", &gsf("XRes = 8\nYRes = 8\nXReal = 8e-7\nXReal = 8e-4\nYReal = 8e-7\n", &heights));
        write("no-magic.gsf", b"Gwyddion Complex Field\nXRes = 8\n\0\0\0");
        write("text.png", b"this is not a PNG");
        image::RgbImage::from_fn(4, 4, |x, _| image::Rgb([x as u8 * 60, 0, 0])).save(dir.join("colour.png")).unwrap();
        image::GrayImage::from_fn(8, 8, |x, y| image::Luma([(x * y) as u8])).save(dir.join("grey.png")).unwrap();
        write("no-faces.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n");
        write("missing-vertex.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n");
        write("nan-vertex.obj", b"v 0 0 nan\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        image::RgbImage::from_pixel(4, 4, image::Rgb([128, 128, 40])).save(dir.join("inward.png")).unwrap();
        image::GrayImage::new(20000, 1).save(dir.join("wide.png")).unwrap();
        let quad = b"mtllib quad.mtl\nusemtl skin\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\n";
        write("mtl-missing-map.obj", quad);
        write("quad.mtl", b"newmtl skin\nmap_Kd -bm 1.0 nowhere.png\n");
        let quad = String::from_utf8_lossy(quad).replace("quad.mtl", "colour.mtl");
        write("mtl-colour.obj", quad.as_bytes());
        write("colour.mtl", b"newmtl skin\nmap_Kd colour.png\n");
        let env = |name: &str, width: u32, height: u32, bad: Option<f32>| {
            let mut rgba = vec![1.0f32; (width * height * 4) as usize];
            if let Some(b) = bad {
                rgba[4 * 5 + 1] = b;
            }
            diffract::io::output::write_exr_rgb(&dir.join(name), width, height, &rgba).unwrap();
        };
        env("env-good.exr", 16, 8, None);
        diffract::io::output::write_exr_rgb(&dir.join("env-black.exr"), 16, 8, &[0.0; 16 * 8 * 4]).unwrap();
        env("env-3to1.exr", 24, 8, None);
        env("env-nan.exr", 16, 8, Some(f32::NAN));
        env("env-negative.exr", 16, 8, Some(-2.0));
        env("env-inf.exr", 16, 8, Some(f32::INFINITY));
        env("env-sun.exr", 16, 8, Some(1e9));
        env("env-overflow.exr", 16, 8, Some(3e38));
        // A map whose sun (its one bright texel) is below its horizon: upside down.
        let mut below = vec![1.0f32; 16 * 8 * 4];
        below[4 * (7 * 16 + 5) + 1] = 1e9;
        diffract::io::output::write_exr_rgb(&dir.join("env-sun-below.exr"), 16, 8, &below).unwrap();
        write("env-huge.hdr", b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 8192 +X 16384\n");
        write("env-text.exr", b"this is not an EXR");
        write("not-utf8.toml", &[0xff, 0xfe, b'[', 0x80]);
        write("huge.toml", &vec![b'#'; (1 << 20) + 10]);
        for (name, target) in [("zero.gsf", "/dev/zero"), ("zero.obj", "/dev/zero"), ("zero.toml", "/dev/zero")] {
            std::os::unix::fs::symlink(target, dir.join(name)).unwrap();
        }
        // An output's name that is an input: a symlink named as a PNG to the height field good.gsf.
        std::os::unix::fs::symlink("good.gsf", dir.join("good-link.png")).unwrap();
        for name in ["fifo.gsf", "fifo.toml", "fifo.png", "fifo.ttf"] {
            let ok = Command::new("mkfifo").arg(dir.join(name)).status().map(|s| s.success()).unwrap_or(false);
            assert!(ok, "mkfifo (coreutils) is needed for the special-file cases");
        }
        dir
    })
}

/// A Gwyddion Simple Field: magic, `fields`, NUL padding to a multiple of 4, then f32 heights in metres.
fn gsf(fields: &str, heights: &[f32]) -> Vec<u8> {
    let mut bytes = format!("Gwyddion Simple Field 1.0\n{fields}").into_bytes();
    let padding = 4 - bytes.len() % 4;
    bytes.extend(std::iter::repeat_n(0, padding));
    bytes.extend(heights.iter().flat_map(|h| h.to_le_bytes()));
    bytes
}

/// A staircase grating 2.1 µm deep (in metres): k·w·h reaches ~35 at 380 nm, where the Taylor terms grow to
/// 10¹⁴ before they cancel: beyond the f64 sum's tolerance.
fn deep_grating() -> Vec<f32> {
    (0..64).map(|i| (i % 4) as f32 * 0.7e-6).collect()
}

/// A scene whose one material and object are quick to load, with `edit` applied to its text.
fn scene(name: &str, edit: impl Fn(String) -> String) -> String {
    let base = r#"[camera]
position = [0.0, 0.5, 3.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 30.0

[light]
direction = [0.3, 1.0, 0.5]

[[object]]
shape = "sphere"
material = "m"

[material.m]
generate = "flat"
size_um = 2.0
"#;
    let path = fixtures().join(name);
    std::fs::write(&path, edit(base.to_string())).unwrap();
    path.to_str().unwrap().to_string()
}

/// One case: its arguments (the word `OUT` is a fresh folder holding `keep.png`, `keep.exr` and `keep.csv`)
/// and a fragment its error line must contain.
struct Case {
    name: &'static str,
    args: Vec<String>,
    needle: &'static str,
    /// Run through `sh -c` with this prefix (a resource limit that simulates a full disk).
    shell_prefix: Option<&'static str>,
    /// Lines other than the error are allowed before it (the work had started: plans, cache warnings).
    after_work: bool,
}

fn case(name: &'static str, args: &[&str], needle: &'static str) -> Case {
    Case { name, args: args.iter().map(|s| s.to_string()).collect(), needle, shell_prefix: None, after_work: false }
}

fn with_scene(name: &'static str, scene_path: String, needle: &'static str) -> Case {
    let mut c = case(name, &["render", "--out", "OUT/keep.png", "--width", "16", "--height", "16"], needle);
    c.args.insert(1, scene_path);
    c
}

const KEPT: [&str; 3] = ["keep.png", "keep.exr", "keep.csv"];

fn run(c: &Case) -> Result<(), String> {
    let out = common::place::scratch_root().join("hostile-out").join(c.name);
    let _ = std::fs::remove_dir_all(&out);
    std::fs::create_dir_all(&out).unwrap();
    for name in KEPT {
        std::fs::write(out.join(name), format!("an earlier {name}, to be kept")).unwrap();
    }
    let args: Vec<String> = c.args.iter().map(|a| a.replace("OUT", out.to_str().unwrap())).collect();
    let bin = common::place::diffract_bin();
    let prefix = c.shell_prefix.unwrap_or("");
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(format!("ulimit -v {MEMORY_LIMIT_KIB}; {prefix} exec \"$0\" \"$@\""))
        .arg(bin)
        .args(&args)
        .current_dir(fixtures())
        .env_remove("DIFFRACT_VALIDATION")
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .env("DIFFRACT_CACHE", common::place::scratch_root().join("cache"))
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().unwrap() {
            break status;
        }
        if start.elapsed() > TIME_LIMIT {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("still running after {TIME_LIMIT:?}"));
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let mut err = String::new();
    std::io::Read::read_to_string(&mut child.stderr.take().unwrap(), &mut err).unwrap();
    let lines: Vec<&str> = err.lines().filter(|l| !l.trim().is_empty()).collect();
    let errors = lines.iter().filter(|l| l.starts_with("error")).count();
    let problem = match status.code() {
        None => Some(format!("killed by a signal ({status})")),
        Some(0) => Some("exit status 0".to_string()),
        Some(101) => Some("a panic (exit 101)".to_string()),
        Some(134) => Some("an abort (exit 134)".to_string()),
        Some(_) if err.contains("panicked") || err.contains("backtrace") => Some("a panic message".to_string()),
        Some(_) if errors != 1 || !lines.last().is_some_and(|l| l.starts_with("error: ")) => {
            Some("not exactly one `error: ` line, last".to_string())
        }
        Some(_) if lines.len() != 1 && !c.after_work => Some("more than one line".to_string()),
        Some(_) if !err.contains(c.needle) => Some(format!("no {:?} in the message", c.needle)),
        Some(_) => None,
    };
    if let Some(p) = problem {
        return Err(format!("{p}; stderr: {err}"));
    }
    for name in KEPT {
        let now = std::fs::read_to_string(out.join(name)).unwrap_or_default();
        if now != format!("an earlier {name}, to be kept") {
            return Err(format!("{name} was changed"));
        }
    }
    let stray: Vec<_> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| !KEPT.contains(&n.as_str()))
        .collect();
    if !stray.is_empty() {
        return Err(format!("left files behind: {stray:?}"));
    }
    Ok(())
}

fn run_all(cases: &[Case]) {
    let failures: Vec<String> =
        cases.iter().filter_map(|c| run(c).err().map(|e| format!("{} ({}): {e}", c.name, c.args.join(" ")))).collect();
    println!("{} hostile cases, {} failed", cases.len(), failures.len());
    assert!(failures.is_empty(), "{} of {} cases failed:\n{}", failures.len(), cases.len(), failures.join("\n"));
}

const VIEW: [&str; 6] = ["--light-theta", "0", "--view", "10,0", "--lambda", "500"];

/// `brdf` of the small good patch with the usual view and `extra` flags.
fn brdf(name: &'static str, extra: &[&str], needle: &'static str) -> Case {
    brdf_of(name, "good.gsf", &[&VIEW[..], extra].concat(), needle)
}

/// `brdf --heightfield FILE` with `rest`, to build the cases that vary the views themselves.
fn brdf_of(name: &'static str, file: &str, rest: &[&str], needle: &'static str) -> Case {
    case(name, &[&["brdf", "--heightfield", file][..], rest].concat(), needle)
}

#[test]
fn hostile_height_field_files() {
    let png = ["--pixel-size-um", "0.065", "--height-um", "0.3"];
    let hf = |name: &'static str, file: &'static str, extra: &[&str], needle: &'static str| {
        brdf_of(name, file, &[&VIEW[..], extra].concat(), needle)
    };
    run_all(&[
        hf("missing file", "nope.gsf", &[], "cannot open"),
        hf("a folder", "folder.gsf", &[], "folder"),
        hf("a FIFO", "fifo.gsf", &[], "not a regular file"),
        hf("a FIFO named .png", "fifo.png", &png, "not a regular file"),
        hf("a link to /dev/zero", "zero.gsf", &[], "not a regular file"),
        hf("truncated data", "truncated.gsf", &[], "truncated"),
        hf("a billion-pixel header", "huge-res.gsf", &[], "more than diffract handles"),
        hf("1e30 m wide", "huge-real.gsf", &[], "pixel size"),
        hf("NaN width", "nan-real.gsf", &[], "XReal"),
        hf("NaN height", "nan-data.gsf", &[], "not a finite number"),
        hf("no magic line", "no-magic.gsf", &[], "not a Gwyddion Simple Field"),
        hf("a key given twice", "twice.gsf", &[], "XReal is given a second time"),
        hf("text named .png", "text.png", &png, "PNG"),
        hf("colour PNG", "colour.png", &png, "grey"),
        hf("PNG without units", "grey.png", &[], "--pixel-size-um"),
        hf("1 km pixels", "grey.png", &["--pixel-size-um", "1e9", "--height-um", "0.3"], "pixel size"),
        hf("1e6 m heights", "grey.png", &["--pixel-size-um", "0.065", "--height-um", "1e12"], "were metres"),
        hf("a tiling of 10^10 pixels", "good.gsf", &["--tile", "100000"], "more than diffract handles"),
        hf("unknown extension", "huge.toml", &[], "unknown height-field format"),
    ]);
}

#[test]
fn hostile_scenes_and_meshes() {
    let mesh = |file: &'static str| move |s: String| s.replace("shape = \"sphere\"", &format!("mesh = \"{file}\""));
    run_all(&[
        with_scene("scene: a FIFO", "fifo.toml".into(), "not a regular file"),
        with_scene("scene: /dev/zero", "zero.toml".into(), "not a regular file"),
        with_scene("scene: not UTF-8", "not-utf8.toml".into(), "UTF-8"),
        with_scene("scene: over 1 MiB", "huge.toml".into(), "at most 1 MiB"),
        with_scene("scene: a folder", "folder.gsf".into(), "folder"),
        with_scene("scene: unknown key", scene("s1.toml", |s| s.replace("fov_y_deg", "fov")), "unknown field"),
        with_scene("scene: NaN camera", scene("s2.toml", |s| s.replace("[0.0, 0.5, 3.0]", "[nan, 0.5, 3.0]")), ":2:"),
        with_scene(
            "scene: up along the line of sight",
            scene("s3.toml", |s| s.replace("fov_y_deg = 30.0", "fov_y_deg = 30.0\nup = [0.0, -0.5, -3.0]")),
            "parallel",
        ),
        with_scene(
            "scene: infinite far plane",
            scene("s4.toml", |s| s.replace("fov_y_deg = 30.0", "fov_y_deg = 30.0\nfar = inf")),
            "near < far",
        ),
        with_scene("scene: exposure NaN", scene("s5.toml", |s| s + "\n[render]\nexposure_ev = nan\n"), "exposure_ev"),
        with_scene(
            "scene: 1e30 translation",
            scene("s6.toml", |s| s.replace("material = \"m\"", "material = \"m\"\ntranslate = [1e30, 0.0, 0.0]")),
            "translate",
        ),
        with_scene("scene: coherence 0", scene("s7.toml", |s| s + "coherence_um = 0.0\n"), "coherence"),
        with_scene("scene: window radius 1000", scene("s8.toml", |s| s + "window_radius = 1000\n"), "window_radius"),
        with_scene("scene: tiling 10^5", scene("s9.toml", |s| s + "tile = 100000\n"), "more than diffract handles"),
        with_scene("scene: render 10^5 wide", scene("s10.toml", |s| s + "\n[render]\nwidth = 100000\n"), "width"),
        with_scene("scene: mesh /dev/zero", scene("s11.toml", mesh("zero.obj")), "not a regular file"),
        with_scene("scene: mesh without faces", scene("s12.toml", mesh("no-faces.obj")), "no faces"),
        with_scene(
            "scene: face past the vertices",
            scene("s13.toml", mesh("missing-vertex.obj")),
            "missing-vertex.obj",
        ),
        with_scene("scene: NaN vertex", scene("s14.toml", mesh("nan-vertex.obj")), "not finite"),
        with_scene("scene: missing mesh", scene("s15.toml", mesh("nope.obj")), "nope.obj"),
    ]);
}

/// Pigment and normal maps: every way a map or its key can be wrong ends in one line naming it.
#[test]
fn hostile_surface_maps() {
    let map = |key: &'static str, file: &'static str| move |s: String| s + &format!("{key} = \"{file}\"\n");
    run_all(&[
        with_scene("maps: missing pigment map", scene("m1.toml", map("pigment_map", "nope.png")), "nope.png"),
        with_scene("maps: text as a PNG", scene("m2.toml", map("normal_map", "text.png")), "not a readable PNG map"),
        with_scene("maps: a FIFO", scene("m3.toml", map("pigment_map", "fifo.png")), "not a regular file"),
        with_scene("maps: 20000 texels wide", scene("m4.toml", map("pigment_map", "wide.png")), "not a readable PNG"),
        with_scene(
            "maps: a normal into the surface",
            scene("m5.toml", map("normal_map", "inward.png")),
            "into the surface",
        ),
        with_scene(
            "maps: map_size_m on a sphere",
            scene("m6.toml", |s| s + "pigment_map = \"colour.png\"\nmap_size_m = 0.1\n"),
            "for the ground and planes",
        ),
        with_scene("maps: map_size_m without a map", scene("m7.toml", |s| s + "map_size_m = 0.1\n"), "no pigment_map"),
        with_scene(
            "maps: map_size_m negative",
            scene("m8.toml", |s| s + "pigment_map = \"colour.png\"\nmap_size_m = -1.0\n"),
            "map_size_m",
        ),
        {
            let mut c = with_scene(
                "maps: render --out over an MTL's map",
                scene("m10.toml", |s| s.replace("shape = \"sphere\"", "mesh = \"mtl-colour.obj\"")),
                "from its MTL",
            );
            c.args[3] = "colour.png".into();
            c
        },
        {
            let mut c = with_scene(
                "maps: render --out over the pigment map",
                scene("m11.toml", map("pigment_map", "colour.png")),
                "pigment map",
            );
            c.args[3] = "colour.png".into();
            c
        },
        with_scene(
            "maps: an MTL's missing map",
            scene("m9.toml", |s| s.replace("shape = \"sphere\"", "mesh = \"mtl-missing-map.obj\"")),
            "nowhere.png",
        ),
    ]);
}

/// `[light] environment = "FILE"`: every way a map can be wrong ends in one line that names the scene's line.
#[test]
fn hostile_environment_maps() {
    let env = |file: &'static str| {
        move |s: String| {
            s.replace("direction = [0.3, 1.0, 0.5]", &format!("direction = [0.3, 1.0, 0.5]\nenvironment = \"{file}\""))
        }
    };
    run_all(&[
        with_scene("environment: 3:1", scene("e1.toml", env("env-3to1.exr")), "twice as wide as high"),
        with_scene("environment: NaN texel", scene("e2.toml", env("env-nan.exr")), "the first at (5, 0)"),
        with_scene("environment: negative texel", scene("e3.toml", env("env-negative.exr")), "non-negative"),
        with_scene("environment: infinite texel", scene("e4.toml", env("env-inf.exr")), "not finite"),
        with_scene(
            "environment: over the size cap",
            scene("e5.toml", env("env-huge.hdr")),
            "larger than the 8192×4096",
        ),
        with_scene("environment: not an EXR", scene("e6.toml", env("env-text.exr")), "env-text.exr"),
        with_scene("environment: missing", scene("e7.toml", env("env-nope.exr")), "env-nope.exr"),
        with_scene("environment: spaces after the name", scene("e12.toml", env("env-good.exr  ")), "used as written"),
        with_scene(
            "environment: its sun below the horizon",
            scene("e8.toml", env("env-sun-below.exr")),
            "below the horizon",
        ),
        with_scene("environment: a PNG", scene("e9.toml", env("env.png")), "expected \"sky\""),
        with_scene(
            "environment: negative intensity",
            scene("e10.toml", |s| env("env-good.exr")(s).replace("[light]", "[light]\nintensity = -1.0")),
            "intensity",
        ),
        with_scene(
            "environment: sun below the horizon",
            scene("e11.toml", |s| env("env-good.exr")(s).replace("[0.3, 1.0, 0.5]", "[0.3, -1.0, 0.5]")),
            "horizon",
        ),
    ]);
}

/// `map --environment FILE`: a bad map or flag ends in one line.
#[test]
fn hostile_environment_maps_of_a_map() {
    let map = |name: &'static str, file: &'static str, extra: &[&str], needle: &'static str| {
        let args = [
            &["map", "--heightfield", "good.gsf", "--size", "8", "--out", "OUT/keep.png", "--environment", file][..],
            extra,
        ];
        case(name, &args.concat(), needle)
    };
    run_all(&[
        map("map environment: 3:1", "env-3to1.exr", &[], "twice as wide as high"),
        map("map environment: NaN texel", "env-nan.exr", &[], "the first at (5, 0)"),
        map("map environment: not an EXR", "env-text.exr", &[], "env-text.exr"),
        map("map environment: missing", "env-nope.exr", &[], "env-nope.exr"),
        map("map environment: black", "env-black.exr", &[], "no light"),
        map("map environment: flss", "env-good.exr", &["--approach", "flss"], "--approach baked"),
        map("map environment: intensity 0", "env-good.exr", &["--env-intensity", "0"], "positive"),
        map("map environment: and a light", "env-good.exr", &["--light-theta", "10"], "cannot be used with"),
        map("map environment: 1 sample", "env-good.exr", &["--env-samples", "1"], "2..=65536"),
        map("map environment: 3e38 texel", "env-overflow.exr", &[], "brighter than 1e20"),
        map("map environment: intensity 1e32", "env-good.exr", &["--env-intensity", "1e32"], "beyond 1e20"),
        case("map: no light", &["map", "--heightfield", "good.gsf", "--out", "OUT/keep.png"], "--light-theta"),
    ]);
}

#[test]
fn hostile_flags() {
    let render = |name: &'static str, extra: &[&str], needle: &'static str| {
        let mut args = vec!["render", "--out", "OUT/keep.png", "--width", "16", "--height", "16"];
        args.extend(extra);
        case(name, &args, needle)
    };
    run_all(&[
        render("exposure NaN", &["--exposure", "nan"], "finite"),
        render("exposure inf", &["--exposure", "inf"], "finite"),
        render("exposure 1000", &["--exposure", "1000"], "within ±100"),
        case("gen sky: a TIFF", &["gen", "sky", "--out", "OUT/keep.tif"], ".exr or .hdr (radiance) or .png"),
        case(
            "gen sky: wider than a scene loads",
            &["gen", "sky", "--width", "16384", "--out", "OUT/s.exr"],
            "8..=8192",
        ),
        case("width 0", &["render", "--out", "OUT/keep.png", "--width", "0"], "width"),
        case("width 10^5", &["render", "--out", "OUT/keep.png", "--width", "100000"], "width"),
        render("unknown device", &["--device", "no-such-gpu"], "no-such-gpu"),
        render("window radius 4e9", &["--window-radius", "4000000000"], "window radius"),
        render("unknown approach", &["--approach", "magic"], "magic"),
        render("sky at nowhere", &["--sky-at", "sideways"], "vertex, pixel"),
        render("table mips cubic", &["--table-mips", "cubic"], "auto, linear, nearest"),
        render("tone aces", &["--tone", "aces"], "filmic and clip"),
        render("tone of a preview", &["--tone", "clip", "--preview"], "cannot be used with"),
        render("extend to 2 µm", &["--extend-um", "2"], "smaller than the patch"),
        render("extend to 10⁶ µm", &["--extend-um", "1e6"], "within 1000 µm"),
        case(
            "map: extend and tile",
            &[
                "map",
                "--heightfield",
                "good.gsf",
                "--light-theta",
                "0",
                "--out",
                "OUT/keep.png",
                "--tile",
                "2",
                "--extend-um",
                "20",
            ],
            "cannot be used with",
        ),
        case(
            "map: sky at",
            &["map", "--heightfield", "good.gsf", "--light-theta", "0", "--out", "OUT/keep.png", "--sky-at", "pixel"],
            "--sky-at has no effect",
        ),
        brdf("coherence 1e-9 µm", &["--coherence-um", "1e-9"], "coherence"),
        brdf("coherence 1e300 µm", &["--coherence-um", "1e300"], "coherence"),
        brdf("brdf window radius 4e9", &["--window-radius", "4000000000"], "window radius"),
        brdf("tolerance 0", &["--tolerance", "0", "--method", "taylor"], "tolerance"),
        brdf("10^5 Taylor terms", &["--terms", "100000", "--method", "taylor"], "terms"),
        brdf_of(
            "10^300 wavelengths",
            "good.gsf",
            &["--light-theta", "0", "--view", "10,0", "--lambda", "1:1e300:1"],
            "at most",
        ),
        brdf_of("λ 1e300 nm", "good.gsf", &["--light-theta", "0", "--view", "10,0", "--lambda", "1e300"], "outside"),
        brdf_of(
            "light at the horizon",
            "good.gsf",
            &["--light-theta", "90", "--view", "10,0", "--lambda", "500"],
            "horizon",
        ),
        brdf_of(
            "a zero view step",
            "good.gsf",
            &["--light-theta", "0", "--view-theta", "0:80:0", "--lambda", "500"],
            "step",
        ),
        brdf_of(
            "f64 Taylor on a deep grating",
            "deep.gsf",
            &["--light-theta", "0", "--view", "10,0", "--lambda", "380", "--method", "taylor"],
            "use --method exact",
        ),
        brdf_of(
            "GPU on a deep grating",
            "deep.gsf",
            &["--light-theta", "0", "--view", "10,0", "--lambda", "380", "--gpu"],
            "f32",
        ),
        case(
            "map of a deep grating",
            &[
                "map",
                "--heightfield",
                "deep.gsf",
                "--light-theta",
                "0",
                "--size",
                "16",
                "--out",
                "OUT/keep.png",
                "--approach",
                "flss",
            ],
            "f32",
        ),
        case("terms window radius 17", &["terms", "--heightfield", "good.gsf", "--window-radius", "17"], "radius"),
        case(
            "gen: 1e-300 µm pixels",
            &["gen", "patch", "cd", "--out", "OUT/p.gsf", "--pixel-um", "1e-300"],
            "more than diffract handles",
        ),
        case(
            "gen: 1e308 µm deep",
            &["gen", "patch", "blazed", "--out", "OUT/p.gsf", "--height-um", "1e308", "--size-um", "2"],
            "deep",
        ),
        case(
            "gen: 10^7 scales",
            &["gen", "snake", "--out", "OUT/s.obj", "--scale-rows", "10000", "--scales-around", "1000"],
            "scales",
        ),
        case("profile: unknown sweep key", &["profile", "--sweep", "colour=red", "--width", "8"], "colour"),
        case("view without a display", &["view", "--frames", "1"], "display"),
    ]);
}

#[test]
fn hostile_outputs() {
    let full_disk = Case {
        shell_prefix: Some("trap '' XFSZ; ulimit -f 1;"),
        after_work: true,
        ..case(
            "a full disk",
            &["render", "--out", "OUT/keep.png", "--width", "64", "--height", "64", "--approach", "gem"],
            "File too large",
        )
    };
    let gen_full = Case {
        shell_prefix: Some("trap '' XFSZ; ulimit -f 1;"),
        ..case("gen on a full disk", &["gen", "patch", "flat", "--out", "OUT/keep.gsf", "--size-um", "30"], "large")
    };
    run_all(&[
        case("--exr a folder", &["render", "--out", "OUT/keep.png", "--exr", "folder.gsf"], "cannot write"),
        case("--exr into a folder named .exr", &["render", "--out", "OUT/keep.png", "--exr", "OUT"], ".exr"),
        case("--out in a missing folder", &["render", "--out", "OUT/nope/x.png"], "does not exist"),
        case("--out with the wrong extension", &["render", "--out", "OUT/keep.exr"], ".png"),
        case("--out a FIFO", &["render", "--out", "fifo.png"], "not a regular file"),
        case(
            "--out a folder",
            &["map", "--heightfield", "good.gsf", "--light-theta", "0", "--out", "folder.gsf"],
            ".png",
        ),
        case("--csv a folder", &["profile", "--csv", "folder.gsf", "--width", "8"], ".csv"),
        case("--plot in a missing folder", &["profile", "--plot", "OUT/nope/p.png", "--width", "8"], "does not exist"),
        case("--screenshot a FIFO", &["view", "--frames", "1", "--screenshot", "fifo.png"], "not a regular file"),
        case("a missing argument", &["map", "--light-theta", "0", "--out", "OUT/keep.png"], "--heightfield"),
        case("gen --preview a folder", &["gen", "patch", "flat", "--out", "OUT/p.gsf", "--preview", "OUT"], ".png"),
        full_disk,
        gen_full,
    ]);
}

/// Issue 62's cases: an output that is one of the run's inputs (by name, through `./` or a symlink), unbounded
/// reads of a font, help on a full stdout, finite values too large to use, and a file-size limit whose signal
/// is not ignored by the shell.
#[test]
fn hostile_fourth_round() {
    let grey = ["--heightfield", "grey.png", "--pixel-size-um", "0.1", "--height-um", "0.2", "--light-theta", "10"];
    let map = |name: &'static str, extra: &[&str], needle: &'static str| {
        case(name, &[&["map"][..], &grey[..], extra].concat(), needle)
    };
    let env_scene = |name: &str, extra: &str| {
        scene(name, |s| {
            s.replace(
                "direction = [0.3, 1.0, 0.5]",
                &format!("direction = [0.3, 1.0, 0.5]\nenvironment = \"env-good.exr\"{extra}"),
            )
        })
    };
    let mut exr_over_env = with_scene("render --exr over its environment", env_scene("f1.toml", ""), "environment map");
    exr_over_env.args.extend(["--exr".to_string(), "env-good.exr".to_string()]);
    // Loading the scene said what it found in its map before the outputs could be checked against it.
    exr_over_env.after_work = true;
    let full_stdout = |name: &'static str, args: &[&str]| Case {
        shell_prefix: Some("exec >/dev/full;"),
        ..case(name, args, "could not write to standard output")
    };
    let file_size_limit = Case {
        shell_prefix: Some("ulimit -f 1;"),
        after_work: true,
        ..case(
            "a file-size limit, its signal not ignored",
            &["render", "--out", "OUT/keep.png", "--width", "64", "--height", "64", "--approach", "gem"],
            "File too large",
        )
    };
    run_all(&[
        map("map --out its own height field", &["--out", "grey.png"], "height field"),
        map("map --out its height field through ./", &["--out", "./grey.png"], "height field"),
        case(
            "map --out a symlink to its height field",
            &["map", "--heightfield", "good.gsf", "--light-theta", "10", "--out", "good-link.png"],
            "height field",
        ),
        case(
            "map --exr over its environment",
            &[
                "map",
                "--heightfield",
                "good.gsf",
                "--size",
                "8",
                "--out",
                "OUT/keep.png",
                "--environment",
                "env-good.exr",
                "--exr",
                "env-good.exr",
            ],
            "environment map",
        ),
        exr_over_env,
        case(
            "profile --plot-font a FIFO",
            &["profile", "--plot", "OUT/p.png", "--plot-font", "fifo.ttf", "--width", "8"],
            "not a regular file",
        ),
        case(
            "profile --plot-font /dev/zero",
            &["profile", "--plot", "OUT/p.png", "--plot-font", "zero.gsf", "--width", "8"],
            "not a regular file",
        ),
        full_stdout("--help on a full stdout", &["--help"]),
        full_stdout("--version on a full stdout", &["--version"]),
        full_stdout("render --help on a full stdout", &["render", "--help"]),
        with_scene("environment: intensity 1e308", env_scene("f2.toml", "\nintensity = 1e308"), "intensity 1e308"),
        with_scene("environment: rotation 1e308", env_scene("f3.toml", "\nrotation_deg = 1e308"), "rotation 1e308"),
        case("gen sky --width 9", &["gen", "sky", "--out", "OUT/s.exr", "--width", "9"], "8 and 8192"),
        with_scene(
            "scene: a camera 1e308 away",
            scene("f4.toml", |s| s.replace("[0.0, 0.5, 3.0]", "[1e308, 0.0, 1.0]")),
            "[1e308, 0, 1]",
        ),
        with_scene(
            "scene: ambient 3e38",
            scene("f5.toml", |s| s.replace("[light]", "[light]\nambient = 3e38\nenvironment = \"none\"")),
            "ambient = 3e38",
        ),
        file_size_limit,
    ]);
}

/// `DIFFRACT_CACHE` naming a file that is no folder (`/dev/null`): one warning that nothing is cached, and the
/// command does its work.
#[test]
fn a_cache_that_is_not_a_folder_is_said_once_and_the_work_done() {
    let out = common::place::scratch_root().join("cache-not-a-folder.png");
    let o = Command::new(common::place::diffract_bin())
        .args(["render", "--out", out.to_str().unwrap(), "--width", "16", "--height", "16", "--approach", "gem"])
        .env("DIFFRACT_CACHE", "/dev/null")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert_eq!(err.matches("DIFFRACT_CACHE=/dev/null is not a folder").count(), 1, "{err}");
    assert!(!err.contains("os error"), "{err}");
}
