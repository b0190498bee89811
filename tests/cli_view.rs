//! `diffract view` in a real window under Xvfb (started by the test), and its refusal without a display.

mod common;

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::assert_one_line_error;

/// An Xvfb server on a free display, stopped when dropped. The window tests hold `X_SERVERS` while they run:
/// two Xvfb started at once can pick the same display.
struct Xvfb {
    child: Child,
    display: String,
    _serial: std::sync::MutexGuard<'static, ()>,
}

static X_SERVERS: std::sync::Mutex<()> = std::sync::Mutex::new(());

impl Xvfb {
    /// Starts Xvfb on a display it picks itself (`-displayfd`), so parallel tests never share one.
    fn start() -> Self {
        use std::io::BufRead;
        let serial = X_SERVERS.lock().unwrap_or_else(|e| e.into_inner());
        let mut child = Command::new("Xvfb")
            .args(["-displayfd", "1", "-screen", "0", "1024x768x24", "-nolisten", "tcp"])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb must be installed for the window tests (scripts/setup-debian.sh installs it)");
        let mut line = String::new();
        std::io::BufReader::new(child.stdout.take().expect("piped"))
            .read_line(&mut line)
            .expect("Xvfb reports its display");
        let n: u32 = line.trim().parse().unwrap_or_else(|_| panic!("Xvfb did not report a display: {line:?}"));
        // The number may come a moment before the server accepts connections: wait until its local socket
        // takes a connection (no X client program needed, so nothing beyond Xvfb has to be installed).
        let display = format!(":{n}");
        let socket = format!("/tmp/.X11-unix/X{n}");
        let start = Instant::now();
        while std::os::unix::net::UnixStream::connect(&socket).is_err() {
            assert!(start.elapsed() < Duration::from_secs(10), "Xvfb {display} accepts no connection");
            std::thread::sleep(Duration::from_millis(50));
        }
        Self { child, display, _serial: serial }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

/// A small scene, written under `name` (each test its own file: tests run in parallel).
fn scene(name: &str) -> PathBuf {
    let path = common::scratch("cli_view", name);
    std::fs::write(
        &path,
        r#"[camera]
position = [0.0, 0.0, 3.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 30.0
[light]
direction = [0.0, 0.5, 0.866]
ambient = 0.05
[[object]]
shape = "sphere"
material = "e"
[material.e]
generate = "elaphe"
size_um = 6.5
coherence_um = 6.5
lambda_step_nm = 40.0
pigment = [0.3, 0.3, 0.3]
[render]
exposure_ev = 4.0
"#,
    )
    .unwrap();
    path
}

#[test]
fn view_renders_frames_survives_a_resize_and_writes_a_screenshot() {
    let x = Xvfb::start();
    let shot = common::scratch("cli_view", "shot.png");
    let _ = std::fs::remove_file(&shot);
    let o = Command::new(common::place::diffract_bin())
        .args(["view", scene("frames.toml").to_str().unwrap(), "--width", "96", "--height", "72", "--frames", "30"])
        .args([
            "--screenshot",
            shot.to_str().unwrap(),
            "--resize-after",
            "10",
            "--validation",
            "--device",
            &common::place::test_device(),
        ])
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .env("DIFFRACT_CACHE", common::place::scratch_root().join("cache"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("validation"), "{err}");
    let img = image::open(&shot).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (72, 54), "the window was resized to 3/4 and the last frame has that size");
    let lit = img.pixels().filter(|p| p.0.iter().any(|&c| c > 30)).count();
    assert!(lit > 100, "the sphere shows ({lit} lit pixels)");
    assert!(String::from_utf8_lossy(&o.stdout).contains("BRDF map"), "the key bindings are printed");
}

/// A table that is not in the cache is baked on another thread while gem stands in; the scripted frames are
/// counted once the baked materials are drawn. (`DIFFRACT_VIEW_WAIT_MS=0`: the window does not wait for them.)
#[test]
fn view_shows_a_stand_in_while_its_table_bakes() {
    let x = Xvfb::start();
    let cache = common::scratch("cli_view", "cold-cache");
    let _ = std::fs::remove_dir_all(&cache);
    let shot = common::scratch("cli_view", "cold.png");
    // Without an exposure: it is measured from the baked materials once they are in, not from the stand-in.
    let cold = scene("cold.toml");
    let text = std::fs::read_to_string(&cold).unwrap().replace("[render]\nexposure_ev = 4.0\n", "");
    std::fs::write(&cold, text).unwrap();
    let o = Command::new(common::place::diffract_bin())
        .args(["view", cold.to_str().unwrap(), "--width", "64", "--height", "48", "--frames", "3"])
        .args(["--screenshot", shot.to_str().unwrap(), "--validation", "--device", &common::place::test_device()])
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .env("DIFFRACT_CACHE", &cache)
        .env("DIFFRACT_VIEW_WAIT_MS", "0")
        .output()
        .unwrap();
    let (out, err) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success() && !err.contains("validation"), "{err}");
    for line in ["gem stands in until they are ready", "first frame (the stand-in) after", "materials are ready after"]
    {
        assert!(out.contains(line), "no {line:?} in {out}");
    }
    // The frames' summary comes after the materials are in: they are the baked approach's.
    let ready = out.find("materials are ready").unwrap();
    assert!(out[ready..].contains("frames at 64×48 after the first"), "{out}");
    assert!(out[ready..].contains("view: exposure +") && out[ready..].contains("EV, measured"), "{out}");
    assert!(!out[..ready].contains("EV, measured"), "the stand-in is not measured: {out}");
    assert!(image::open(&shot).is_ok());
}

#[test]
fn view_without_a_display_refuses_in_one_line() {
    let o = Command::new(common::place::diffract_bin())
        .args(["view", "--frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert_one_line_error(&o, "diffract render");
}

/// A short soak: 260 frames, the window resized and the approach switched every 50 (a round of all five),
/// under the validation layer: no message, no GPU allocation live at teardown, resident memory reported.
/// (`scripts/soak-view.sh` runs the default scene for 1000 frames.)
#[test]
fn view_survives_a_soak_of_resizes_and_approach_switches() {
    let x = Xvfb::start();
    let o = Command::new(common::place::diffract_bin())
        .args(["view", scene("soak.toml").to_str().unwrap(), "--width", "64", "--height", "48", "--frames", "260"])
        .args(["--soak", "--vsync", "off", "--validation", "--device", &common::place::test_device()])
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
        .env("DIFFRACT_CACHE", common::place::scratch_root().join("cache"))
        .output()
        .unwrap();
    let (out, err) = (String::from_utf8_lossy(&o.stdout), String::from_utf8_lossy(&o.stderr));
    assert!(o.status.success(), "{err}");
    assert!(!err.contains("validation"), "{err}");
    assert!(out.contains("soak: 260 frames, 5 resizes, 5 approach switches"), "{out}");
    assert!(out.contains("MiB at the end"), "{out}");
    assert!(out.contains("soak: 0 GPU allocations live at teardown"), "{out}");
}
