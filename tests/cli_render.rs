//! `diffract render` with scenes: sequences, a user's own OBJ and GSF, and mistakes in scene files.

mod common;

use std::path::PathBuf;

use common::{assert_one_line_error, diffract};

fn scratch(name: &str) -> PathBuf {
    common::scratch("cli_render", name)
}

fn s(p: &std::path::Path) -> &str {
    p.to_str().unwrap()
}

/// A scene of the user's own: an OBJ without normals or UVs and a generated GSF, paths relative to the scene.
fn own_scene(name: &str) -> PathBuf {
    let dir = scratch(name);
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("quad.obj"), "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3\nf 1 3 4\n").unwrap();
    common::sine_patch(&dir.join("sine.gsf"));
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        r#"[camera]
position = [0.0, 0.0, 3.0]
target = [0.0, 0.0, 0.0]
fov_y_deg = 40.0

[light]
direction = [0.0, 0.0, 1.0]

[[object]]
mesh = "quad.obj"
material = "sine"

[material.sine]
heightfield = "sine.gsf"
coherence_um = 8.0
lambda_step_nm = 10.0
"#,
    )
    .unwrap();
    scene
}

#[test]
fn a_users_obj_and_gsf_render_validation_clean() {
    let scene = own_scene("own-render");
    let out = scratch("own.png");
    let exr = scratch("own.exr");
    let o = diffract(&[
        "render",
        s(&scene),
        "--out",
        s(&out),
        "--exr",
        s(&exr),
        "--width",
        "48",
        "--height",
        "48",
        "--exposure",
        "2",
        "--validation",
        "--device",
        &common::place::test_device(),
    ]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && !err.contains("validation"), "{err}");
    let img = image::open(&out).unwrap().to_rgb8();
    assert!(img.pixels().filter(|p| p.0 != [0, 0, 0]).count() > 10, "the quad is lit");
    assert!(image::open(&exr).is_ok());
}

/// A scene that sets no exposure gets one measured from its frame (stated on stderr): the picture is neither
/// black nor white; a flag that sets a hopeless one is told so in one line, and still obeyed.
#[test]
fn a_scene_without_exposure_is_exposed_from_its_frame() {
    let scene = own_scene("own-auto");
    let out = scratch("auto.png");
    let device = common::place::test_device();
    let render = |extra: &[&str]| {
        let mut args = vec!["render", s(&scene), "--out", s(&out), "--width", "48", "--height", "48", "--validation"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--device", &device]);
        let o = diffract(&args);
        let err = String::from_utf8_lossy(&o.stderr).to_string();
        assert!(o.status.success() && !err.contains("validation"), "{err}");
        let img = image::open(&out).unwrap().to_rgb8();
        let black = img.pixels().filter(|p| p.0.iter().all(|&c| c <= 12)).count();
        // At the top of the tone curve: 255 through clip, 250 through AgX (the default).
        let top = if extra.contains(&"clip") { 254 } else { 249 };
        let white = img.pixels().filter(|p| p.0.iter().any(|&c| c >= top)).count();
        (err, black as f64 / 2304.0, white as f64 / 2304.0)
    };
    let (err, black, white) = render(&[]);
    assert!(err.contains("EV, measured (the median of the objects' pixels' luminance"), "{err}");
    assert!(!err.contains("almost all") && !err.contains("mostly white"), "{err}");
    assert!(black < 0.99 && white < 0.3, "auto: {black} black, {white} clipped");
    let (err, black, white) = render(&["--tone", "clip"]);
    assert!(err.contains("EV, measured (the 99.5th percentile of the lit pixels'"), "{err}");
    assert!(black < 0.99 && white < 0.3, "auto, clip: {black} black, {white} clipped");
    let (err, black, _) = render(&["--exposure", "-30"]);
    assert!(err.contains("almost all black at -30.00 EV") && black >= 0.99, "{err}");
    let (err, _, white) = render(&["--exposure", "30"]);
    assert!(err.contains("mostly white at +30.00 EV") && white > 0.3, "{err}");
}

/// A scene lit by a measured lamp (an SPD file beside it) renders; a broken SPD ends in one line naming the
/// file and the row, and a name outside the CIE's list names what is accepted.
#[test]
fn a_measured_illuminant_lights_the_scene_and_bad_ones_are_refused() {
    let scene = own_scene("own-lamp");
    let dir = scene.parent().unwrap();
    let text = std::fs::read_to_string(&scene).unwrap();
    let lit = |illuminant: &str| {
        let with = dir.join("lamp-scene.toml");
        std::fs::write(&with, text.replace("[light]\n", &format!("[light]\nilluminant = \"{illuminant}\"\n"))).unwrap();
        let out = scratch("lamp.png");
        diffract(&[
            "render",
            s(&with),
            "--out",
            s(&out),
            "--width",
            "24",
            "--height",
            "24",
            "--validation",
            "--device",
            &common::place::test_device(),
        ])
    };
    std::fs::write(dir.join("lamp.csv"), "nm,relative power\n380,20\n560,100\n780,160\n").unwrap();
    let o = lit("lamp.csv");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::write(dir.join("bad.csv"), "380,20\n560,100\n500,160\n").unwrap();
    assert_one_line_error(&lit("bad.csv"), "bad.csv: line 3: the wavelengths must increase");
    std::fs::write(dir.join("neg.csv"), "380,20\n560,-1\n").unwrap();
    assert_one_line_error(&lit("neg.csv"), "non-negative");
    std::fs::write(dir.join("far.csv"), "300,20\n560,1\n").unwrap();
    assert_one_line_error(&lit("far.csv"), "outside 360–830 nm");
    assert_one_line_error(&lit("sunlight"), "F1 … F12");
    assert_one_line_error(&lit("missing.csv"), "missing.csv");
}

/// `diffract render SCENE --out OUT` of a 24² sequence with `extra` flags.
fn render_sequence(scene: &std::path::Path, out: &std::path::Path, extra: &[&str]) -> std::process::Output {
    // Earlier runs of the test left the frames: this run replaces them.
    let mut args = vec!["render", s(scene), "--out", s(out), "--width", "24", "--height", "24", "--overwrite"];
    args.extend_from_slice(extra);
    diffract(&args)
}

#[test]
fn sequences_write_numbered_frames() {
    let scene = own_scene("own-sequence");
    let out = scratch("turn.png");
    let o = render_sequence(&scene, &out, &["--frames", "3", "--orbit"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    for f in 1..=3 {
        assert!(scratch(&format!("turn_{f:04}.png")).exists(), "frame {f}");
    }
    let o = render_sequence(&scene, &scratch("sweep.png"), &["--frames", "2", "--light-sweep"]);
    assert!(o.status.success());
    assert!(scratch("sweep_0002.png").exists());
    assert_one_line_error(&diffract(&["render", s(&scene), "--out", s(&out), "--frames", "3"]), "--orbit");
    let o = render_sequence(&scene, &scratch("arc.png"), &["--frames", "3", "--light-sweep", "--turn-deg", "60"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(scratch("arc_0003.png").exists());
    assert_one_line_error(&diffract(&["render", s(&scene), "--out", s(&out), "--turn-deg", "60"]), "--light-sweep");
    for bad in ["0", "400", "nan"] {
        let o = render_sequence(&scene, &out, &["--orbit", "--frames", "2", "--turn-deg", bad]);
        assert_one_line_error(&o, "(0, 360]");
    }
}

#[test]
fn a_broken_scene_names_its_line() {
    let scene = own_scene("own-broken");
    let text = std::fs::read_to_string(&scene).unwrap();
    let bad = scratch("own-broken/bad.toml");
    for (from, to, line) in [
        ("fov_y_deg = 40.0", "fov_y_deg = 40.0\nzoom = 2", "bad.toml:5: unknown field `zoom`"),
        ("mesh = \"quad.obj\"", "mesh = \"missing.obj\"", "bad.toml:10:"),
        (
            "heightfield = \"sine.gsf\"",
            "heightfield = \"missing.gsf\"",
            "bad.toml:14: heightfield \"missing.gsf\": no such file",
        ),
        ("material = \"sine\"", "material = \"gold\"", "bad.toml:11: no [material.gold]"),
        ("direction = [0.0, 0.0, 1.0]", "direction = [0.0, 0.0]", "bad.toml:7:"),
    ] {
        std::fs::write(&bad, text.replace(from, to)).unwrap();
        assert_one_line_error(&diffract(&["render", s(&bad), "--out", s(&scratch("never.png"))]), line);
    }
    assert_one_line_error(
        &diffract(&["render", "/no/such/scene.toml", "--out", s(&scratch("never.png"))]),
        "cannot open",
    );
}

#[test]
fn gen_snake_writes_an_obj_a_scene_can_use() {
    let dir = scratch("snake");
    std::fs::create_dir_all(&dir).unwrap();
    let o =
        diffract(&["gen", "snake", "--out", s(&dir.join("snake.obj")), "--scale-rows", "20", "--scales-around", "8"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "[camera]\nposition = [0.0, 1.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 40.0\n[light]\ndirection = [0.0, 1.0, 0.0]\nambient = 0.1\n\
         [[object]]\nmesh = \"snake.obj\"\nmaterial = \"m\"\n[material.m]\ngenerate = \"flat\"\nsize_um = 2.0\npigment = [0.5, 0.5, 0.5]\n",
    )
    .unwrap();
    let out = dir.join("snake.png");
    let o = diffract(&[
        "render",
        s(&scene),
        "--out",
        s(&out),
        "--width",
        "64",
        "--height",
        "32",
        "--validation",
        "--device",
        &common::place::test_device(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().to_rgb8();
    assert!(img.pixels().filter(|p| p.0[0] > 20).count() > 20, "the snake's pigment shows");
    let preview = dir.join("preview.png");
    assert!(diffract(&["render", s(&scene), "--out", s(&preview), "--width", "32", "--height", "32", "--preview"])
        .status
        .success());
}

#[test]
fn a_preview_shows_each_materials_pigment() {
    // An orange sphere and a material of diffraction alone: the preview shows the orange (it showed every
    // object grey-green), and the pigmentless one in the preview's grey-green.
    let dir = scratch("preview-pigment");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("scene.toml");
    let text = "[camera]\nposition = [0.0, 0.0, 6.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 30.0\n\
                [light]\ndirection = [0.0, 0.0, 1.0]\nenvironment = \"none\"\n\
                [[object]]\nshape = \"sphere\"\nmaterial = \"orange\"\ntranslate = [-1.2, 0.0, 0.0]\n\
                [[object]]\nshape = \"sphere\"\nmaterial = \"bare\"\ntranslate = [1.2, 0.0, 0.0]\n\
                [material.orange]\npigment = [0.6, 0.15, 0.02]\n\
                [material.bare]\ngenerate = \"flat\"\nsize_um = 2.0\n";
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("preview.png");
    let args = ["render", s(&scene), "--out", s(&out), "--width", "64", "--height", "32", "--preview"];
    let o = diffract(&args);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let img = image::open(&out).unwrap().to_rgb8();
    // The sphere's lit centre on each side (the light is the camera's direction).
    let [r, g, b] = img.get_pixel(16, 16).0;
    assert!(u32::from(r) > u32::from(g) + 40 && g > b, "the orange sphere is orange: {r} {g} {b}");
    let [r, g, b] = img.get_pixel(48, 16).0;
    assert!(g > r && g > b, "the pigmentless sphere is grey-green: {r} {g} {b}");
}

/// Runs `diffract` (with `--validation` among `args`), checks that it succeeds without a validation message and
/// returns what it printed, stdout then stderr.
fn render_clean(args: &[&str]) -> String {
    let o = diffract(args);
    let text = String::from_utf8_lossy(&o.stdout).to_string() + &String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success() && !text.contains("validation"), "{text}");
    text
}

/// `--path auto` (the default) draws a multisampled frame through the visibility buffer on lavapipe, where it was
/// measured faster, and forward at one sample or on a GPU; a chosen path is taken as chosen. The two paths'
/// pictures agree (the GPU tests compare them closely).
#[test]
fn the_default_path_is_the_visibility_buffer_on_lavapipe_at_several_samples() {
    let device = common::place::test_device();
    let render = |extra: &[&str], name: &str| {
        let out = scratch(name);
        let mut args = vec!["render", "--out", s(&out), "--width", "32", "--height", "32", "--validation"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--device", &device]);
        let text = render_clean(&args);
        (text.contains("through a visibility buffer"), image::open(&out).unwrap().to_rgb8())
    };
    let (auto, auto_image) = render(&["--samples", "4"], "auto.png");
    assert_eq!(auto, common::place::on_lavapipe(), "auto at 4 samples: visibility on lavapipe, forward on a GPU");
    assert!(!render(&["--samples", "1"], "one.png").0, "one sample: forward");
    let (chosen, forward_image) = render(&["--samples", "4", "--path", "forward"], "forward.png");
    assert!(!chosen, "--path forward is taken as chosen");
    assert!(render(&["--samples", "4", "--path", "visibility"], "visibility.png").0);
    let differences = auto_image.pixels().zip(forward_image.pixels());
    let mean =
        differences.map(|(a, b)| a.0.iter().zip(b.0).map(|(&x, y)| x.abs_diff(y) as f64).sum::<f64>()).sum::<f64>()
            / (3.0 * 32.0 * 32.0);
    assert!(mean < 2.0, "the paths' pictures agree: mean 8-bit difference {mean}");
}

/// A scene beyond the visibility buffer's limits (256 objects; its ids tell 255 apart): `auto` draws it forward
/// and says why in one line, and `--path visibility` refuses it, its last line saying why.
#[test]
fn a_scene_beyond_the_visibility_buffers_limits_is_drawn_forward_unless_that_path_is_chosen() {
    let dir = scratch("many");
    std::fs::create_dir_all(&dir).unwrap();
    let mut text = String::from(
        "[camera]\nposition = [0.0, 0.0, 3.0]\ntarget = [0.0, 0.0, 0.0]\nfov_y_deg = 40.0\n[light]\n\
         direction = [0.0, 0.0, 1.0]\n[material.m]\ngenerate = \"flat\"\nsize_um = 2.0\npigment = [0.5, 0.5, 0.5]\n",
    );
    text += &"[[object]]\nshape = \"plane\"\nmaterial = \"m\"\n".repeat(256);
    let scene = dir.join("scene.toml");
    std::fs::write(&scene, text).unwrap();
    let out = dir.join("many.png");
    let device = common::place::test_device();
    let args = ["render", s(&scene), "--out", s(&out), "--width", "16", "--height", "16", "--samples", "4"];
    let text = render_clean(&[&args[..], &["--validation", "--device", &device]].concat());
    assert!(!text.contains("through a visibility buffer"), "{text}");
    if common::place::on_lavapipe() {
        assert!(text.contains("drawing forward: the visibility buffer tells at most 255 objects apart"), "{text}");
    }
    // Refused once the scene is prepared (the material's table line comes first): the last line says why.
    let chosen = diffract(&[&args[..], &["--path", "visibility", "--device", &device]].concat());
    let err = String::from_utf8_lossy(&chosen.stderr);
    assert!(!chosen.status.success() && !err.contains("panicked"), "{err}");
    let last = err.trim_end().lines().last().unwrap_or_default();
    assert!(last.starts_with("error: ") && last.contains("at most 255 objects"), "{err}");
}

#[test]
fn a_frame_of_sky_alone_is_metered_on_the_sky() {
    // The camera looks up into the clear sky, its one object behind it: the filmic meter has no object's pixels
    // to read and meters the sky (it wrote a black PNG at 0 EV, saying nothing was lit).
    let dir = scratch("sky-alone");
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("scene.toml");
    let text = "[camera]\nposition = [0.0, 0.0, 0.0]\ntarget = [0.0, 1.0, 0.3]\nfov_y_deg = 40.0\n\
                [light]\ndirection = [0.3, 1.0, 0.5]\n\
                [[object]]\nshape = \"sphere\"\nmaterial = \"m\"\ntranslate = [0.0, -20.0, -5.0]\n\
                [material.m]\npigment = [0.5, 0.5, 0.5]\n";
    std::fs::write(&scene, text).unwrap();
    for tone in ["filmic", "clip"] {
        let out = dir.join(format!("{tone}.png"));
        let args = ["render", s(&scene), "--out", s(&out), "--width", "32", "--height", "32", "--tone", tone];
        let o = diffract(&args);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(o.status.success(), "{err}");
        assert!(!err.contains("nothing in the first frame is lit"), "{tone}: {err}");
        let img = image::open(&out).unwrap().to_rgb8();
        let mean = img.pixels().map(|p| u32::from(p.0[2])).sum::<u32>() / (32 * 32);
        assert!(mean > 60, "{tone}: the sky shows, blue {mean}: {err}");
        if tone == "filmic" {
            assert!(err.contains("no object is in view"), "{err}");
        }
    }
}

/// A frame lit by a lamp alone is in cd/m², and its EXR says so (OpenEXR's whiteLuminance: the luminance of RGB
/// (1, 1, 1), here 1 cd/m²): a white-0.5 matte ground 1 m under a 2 cd lamp reads 0.5·2/π cd/m² at the lamp's foot
/// (the frame's middle pixel, seen from straight above). A frame beside the sun says the sun's luminance; one under
/// the sun alone says it is relative and carries no whiteLuminance.
#[test]
fn a_lamp_lit_frame_is_in_candela_per_square_metre_and_its_exr_says_so() {
    let head = "[camera]\nposition = [0.0, 3.0, 0.0]\ntarget = [0.0, 0.0, 0.0]\nup = [0.0, 0.0, -1.0]\n\
                fov_y_deg = 40.0\n\n[[object]]\nshape = \"ground\"\nmaterial = \"white\"\n\n[material.white]\n\
                pigment = [0.5, 0.5, 0.5]\n";
    let lamp = "\n[[lamp]]\nkind = \"point\"\nposition = [0.0, 1.0, 0.0]\nintensity_cd = 2.0\nradius_m = 0.001\n";
    let header = |light: &str, with_lamp: bool| {
        let scene = scratch(&format!("lamp-{}-{with_lamp}.toml", light.len()));
        std::fs::write(&scene, format!("{head}\n[light]\n{light}\n{}", if with_lamp { lamp } else { "" })).unwrap();
        let (png, exr) = (scene.with_extension("png"), scene.with_extension("exr"));
        let o = diffract(&[
            "render",
            s(&scene),
            "--width",
            "33",
            "--height",
            "33",
            "--samples",
            "1",
            "--out",
            s(&png),
            "--exr",
            s(&exr),
        ]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let meta = exr::meta::MetaData::read_from_file(&exr, false).unwrap();
        let layer = &meta.headers[0].own_attributes;
        let comment = layer.comments.as_ref().map(|c| c.to_string()).unwrap_or_default();
        let middle = image::open(&exr).unwrap().into_rgb32f().get_pixel(16, 16).0;
        (layer.white_luminance, comment, middle)
    };
    let (white, comment, middle) = header("environment = \"none\"", true);
    assert_eq!(white, Some(1.0));
    assert!(comment.contains("(1, 1, 1) is 1 cd/m² (lamps alone)"), "{comment}");
    let luminance = 0.2126 * middle[0] + 0.7152 * middle[1] + 0.0722 * middle[2];
    let expected = 0.5 * 2.0 / std::f32::consts::PI;
    assert!((luminance / expected - 1.0).abs() < 0.01, "{luminance} cd/m² against {expected}");
    let (white, comment, _) = header("environment = \"none\"\ndirection = [0.0, 1.0, 1.0]", true);
    assert!(white.is_some_and(|l| l > 1e8) && comment.contains("the sun's luminance"), "{white:?} {comment}");
    let (white, comment, _) = header("environment = \"none\"\ndirection = [0.0, 1.0, 1.0]", false);
    assert!(white.is_none() && comment.contains("relative"), "{white:?} {comment}");
}

/// A lamp placed inside an object that casts shadows casts none, and one line says so; the frame renders,
/// validation-clean.
#[test]
fn a_lamp_inside_a_caster_says_it_casts_no_shadows() {
    let scene = scratch("lamp-inside.toml");
    std::fs::write(
        &scene,
        "[camera]\nposition = [0.0, 2.0, 4.0]\ntarget = [0.0, 0.5, 0.0]\nfov_y_deg = 40.0\n\n[light]\nenvironment = \"none\"\n\n\
         [[lamp]]\nkind = \"point\"\nposition = [0.0, 0.5, 0.0]\nintensity_cd = 2.0\nradius_m = 0.01\n\n\
         [[object]]\nshape = \"sphere\"\nmaterial = \"white\"\ntranslate = [0.0, 0.5, 0.0]\n\n\
         [[object]]\nshape = \"ground\"\nmaterial = \"white\"\n\n[material.white]\npigment = [0.5, 0.5, 0.5]\n",
    )
    .unwrap();
    let out = scratch("lamp-inside.png");
    let args = ["render", s(&scene), "--width", "24", "--height", "16", "--out", s(&out), "--validation"];
    let text = render_clean(&args);
    assert_eq!(text.matches("casts no shadows").count(), 1, "{text}");
    assert!(text.contains("lamp 1 casts no shadows: it lies within the box of an object"), "{text}");
}
