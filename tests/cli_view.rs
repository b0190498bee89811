//! `diffract view` in a real window under Xvfb (started by the test), and its refusal without a display.

mod common;

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use common::assert_one_line_error;

/// An Xvfb server on a free display, stopped when dropped.
struct Xvfb {
    child: Child,
    display: String,
}

impl Xvfb {
    fn start() -> Self {
        let n = (90..130)
            .find(|n| {
                !std::path::Path::new(&format!("/tmp/.X11-unix/X{n}")).exists()
                    && !std::path::Path::new(&format!("/tmp/.X{n}-lock")).exists()
            })
            .expect("a free X display number");
        let child = Command::new("Xvfb")
            .args([format!(":{n}").as_str(), "-screen", "0", "1024x768x24", "-nolisten", "tcp"])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb must be installed for the window tests (scripts/setup-debian.sh installs it)");
        let socket = format!("/tmp/.X11-unix/X{n}");
        let start = Instant::now();
        while !std::path::Path::new(&socket).exists() {
            assert!(start.elapsed() < Duration::from_secs(10), "Xvfb did not start");
            std::thread::sleep(Duration::from_millis(50));
        }
        Self { child, display: format!(":{n}") }
    }
}

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn scene() -> PathBuf {
    let path = common::scratch("cli_view", "sphere.toml");
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
    let o = Command::new(env!("CARGO_BIN_EXE_diffract"))
        .args(["view", scene().to_str().unwrap(), "--width", "96", "--height", "72", "--frames", "8"])
        .args(["--screenshot", shot.to_str().unwrap(), "--resize-after", "3", "--validation", "--device", "llvmpipe"])
        .env("DISPLAY", &x.display)
        .env_remove("WAYLAND_DISPLAY")
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

#[test]
fn view_without_a_display_refuses_in_one_line() {
    let o = Command::new(env!("CARGO_BIN_EXE_diffract"))
        .args(["view", "--frames", "1"])
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert_one_line_error(&o, "diffract render");
}
