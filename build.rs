//! Compiles every `glsl/<name>.<stage>.glsl` to SPIR-V with shaderc into `$OUT_DIR` (never into the source
//! tree) and writes `$OUT_DIR/shaders.rs`, which `src/shaders.rs` includes: one `pub const NAME_STAGE: &[u8]`
//! per shader, embedded with `include_bytes!`.
//!
//! `#include "x.glsl"` resolves against `glsl/include/`, then `$OUT_DIR/include/`, where `interface.glsl` is
//! generated from `src/gpu/interface.rs` (the one source of the numbers both sides use: every
//! `pub const NAME: u32 | f64 = value;` becomes `#define NAME value`). Every file read is announced with
//! `rerun-if-changed`, so editing an include rebuilds its users.
//! A compile error fails the build with shaderc's `file:line: error: ...` lines.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Further builds of a shader with macros defined: (source `<name>.<stage>`, variant `<name>.<stage>`, macros
/// separated by spaces). `BAKED` makes the diffraction shaders read the baked colour table instead of the Taylor
/// terms, `COUNT_FETCHES` makes them count their texel fetches and shadings per pixel; `SKY_DIFFRACTION_AT_VERTEX` makes
/// the surface's vertex shader evaluate the environment's diffraction (sky_diffraction.glsl).
const VARIANTS: &[(&str, &str, &str)] = &[
    ("map.frag", "map_count.frag", "COUNT_FETCHES"),
    ("map.frag", "map_baked.frag", "BAKED"),
    ("map.frag", "map_baked_count.frag", "BAKED COUNT_FETCHES"),
    ("map.comp", "map_baked.comp", "BAKED"),
    ("surface.frag", "surface_count.frag", "COUNT_FETCHES"),
    ("surface.frag", "surface_baked.frag", "BAKED"),
    ("surface.frag", "surface_baked_count.frag", "BAKED COUNT_FETCHES"),
    ("surface.vert", "surface_sky.vert", "SKY_DIFFRACTION_AT_VERTEX"),
    ("surface.vert", "surface_visibility.vert", "VISIBILITY"),
    ("surface.vert", "surface_sky_visibility.vert", "SKY_DIFFRACTION_AT_VERTEX VISIBILITY"),
    ("surface_resolve.frag", "surface_resolve_baked.frag", "BAKED"),
    ("surface_resolve.frag", "surface_resolve_one.frag", "ONE_SAMPLE"),
    ("surface_resolve.frag", "surface_resolve_baked_one.frag", "BAKED ONE_SAMPLE"),
    ("surface_edges.comp", "surface_edges_baked.comp", "BAKED"),
];

/// The uniform blocks whose GLSL is generated from their Rust structs (std140): (source file, struct, descriptor
/// binding's name in interface.rs, GLSL instance name, generated include). Their fields must be 16-byte types
/// (`[f32; 4]`, `[i32; 4]`, `[u32; 4]`, `[[f32; 4]; 4]` as a mat4, `[[f32; 4]; N]` as a vec4 array), whose
/// std140 offsets are their `repr(C)` offsets.
const UNIFORM_BLOCKS: &[(&str, &str, &str, &str, &str)] = &[
    ("src/material/prepare.rs", "DiffractionParams", "BINDING_PARAMS", "params", "diffraction_params.glsl"),
    ("src/render/surface.rs", "SurfaceUniforms", "BINDING_FRAME", "frame", "surface_uniforms.glsl"),
    ("src/render/preview.rs", "FrameUniforms", "BINDING_FRAME", "frame", "preview_uniforms.glsl"),
    ("src/render/background.rs", "BackgroundUniforms", "BINDING_FRAME", "background", "background_uniforms.glsl"),
];

/// Push-constant blocks generated from Rust structs in src/gpu/interface.rs: (struct, GLSL instance name,
/// include file). Fields are f32, u32 or [f32; 2], laid out as the push-constant (std430) rules place them.
const PUSH_BLOCKS: &[(&str, &str, &str)] = &[
    ("MapPush", "map", "map_push.glsl"),
    ("EnvMapPush", "map", "env_map_push.glsl"),
    ("EvalPush", "eval", "eval_push.glsl"),
    ("SelftestPush", "pc", "selftest_push.glsl"),
    ("VisibilityPush", "visibility", "visibility_push.glsl"),
];

/// Shader stages recognised from the second-to-last component of a file name.
const STAGES: &[(&str, shaderc::ShaderKind)] = &[
    ("vert", shaderc::ShaderKind::Vertex),
    ("frag", shaderc::ShaderKind::Fragment),
    ("comp", shaderc::ShaderKind::Compute),
];

fn main() {
    let root = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("cargo sets CARGO_MANIFEST_DIR"));
    let out = PathBuf::from(std::env::var("OUT_DIR").expect("cargo sets OUT_DIR"));
    let glsl = root.join("glsl");
    let include_dir = glsl.join("include");
    println!("cargo:rerun-if-changed={}", glsl.display());
    println!("cargo:rerun-if-changed={}", include_dir.display());

    let generated = out.join("include");
    std::fs::create_dir_all(&generated).expect("create $OUT_DIR/include");
    let header = interface_header(&root.join("src/gpu/interface.rs"));
    std::fs::write(generated.join("interface.glsl"), header).expect("write interface.glsl");
    let inputs = vertex_inputs(&root.join("src/render/surface.rs"));
    std::fs::write(generated.join("vertex_inputs.glsl"), inputs).expect("write vertex_inputs.glsl");
    for &(file, name, binding, instance, include) in UNIFORM_BLOCKS {
        let block = uniform_block(&root.join(file), name, binding, instance);
        std::fs::write(generated.join(include), block).expect("write a uniform block");
    }
    for &(name, instance, include) in PUSH_BLOCKS {
        let block = push_block(&root.join("src/gpu/interface.rs"), name, instance);
        std::fs::write(generated.join(include), block).expect("write a push-constant block");
    }

    let compiler = shaderc::Compiler::new().expect("shaderc compiler");
    let debug = std::env::var("PROFILE").map(|p| p == "debug").unwrap_or(false);

    let mut sources: Vec<PathBuf> = std::fs::read_dir(&glsl)
        .expect("glsl/ exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "glsl"))
        .collect();
    sources.sort();
    for entry in std::fs::read_dir(&include_dir).expect("glsl/include exists").flatten() {
        println!("cargo:rerun-if-changed={}", entry.path().display());
    }

    let mut module = String::from("// Generated by build.rs: SPIR-V of every glsl/<name>.<stage>.glsl.\n");
    let mut failed = false;
    for src in &sources {
        println!("cargo:rerun-if-changed={}", src.display());
        let file = src.file_name().unwrap().to_string_lossy().to_string();
        let stem = file.trim_end_matches(".glsl");
        let Some((_, stage)) = stem.rsplit_once('.') else {
            eprintln!("{file}: shader files are named <name>.<stage>.glsl");
            failed = true;
            continue;
        };
        let Some(&(_, kind)) = STAGES.iter().find(|(s, _)| *s == stage) else {
            eprintln!("{file}: unknown shader stage `{stage}` (expected vert, frag or comp)");
            failed = true;
            continue;
        };
        let text = std::fs::read_to_string(src).expect("read shader");
        let display = format!("glsl/{file}");
        let variants = VARIANTS.iter().filter(|v| v.0 == stem).map(|&(_, variant, define)| (variant, Some(define)));
        for (variant, define) in std::iter::once((stem, None)).chain(variants) {
            match compile(&compiler, &text, kind, &display, [&include_dir, &generated], debug, define) {
                Ok(spirv) => {
                    let spv = out.join(format!("{variant}.spv"));
                    std::fs::write(&spv, spirv).expect("write .spv");
                    let konst = variant.replace(['-', '.'], "_").to_uppercase();
                    writeln!(module, "pub const {konst}: &[u8] = include_bytes!({:?});", spv.display().to_string())
                        .unwrap();
                }
                Err(msg) => {
                    eprintln!("{msg}");
                    failed = true;
                }
            }
        }
    }
    if failed {
        eprintln!("GLSL compilation failed (see the file:line messages above)");
        std::process::exit(1);
    }
    std::fs::write(out.join("shaders.rs"), module).expect("write shaders.rs");
}

fn compile(
    compiler: &shaderc::Compiler,
    text: &str,
    kind: shaderc::ShaderKind,
    display: &str,
    include_dirs: [&Path; 2],
    debug: bool,
    define: Option<&str>,
) -> Result<Vec<u8>, String> {
    let mut options = shaderc::CompileOptions::new().map_err(|e| e.to_string())?;
    for define in define.into_iter().flat_map(str::split_whitespace) {
        options.add_macro_definition(define, None);
    }
    options.set_target_env(shaderc::TargetEnv::Vulkan, shaderc::EnvVersion::Vulkan1_3 as u32);
    options.set_target_spirv(shaderc::SpirvVersion::V1_6);
    if debug {
        options.set_generate_debug_info();
    } else {
        options.set_optimization_level(shaderc::OptimizationLevel::Performance);
    }
    let [include_dir, generated] = include_dirs.map(Path::to_path_buf);
    options.set_include_callback(move |requested, _ty, _requester, _depth| {
        let found = [(&include_dir, "glsl/include"), (&generated, "$OUT_DIR/include")]
            .into_iter()
            .find_map(|(dir, name)| Some((std::fs::read_to_string(dir.join(requested)).ok()?, name)));
        match found {
            Some((content, dir)) => {
                Ok(shaderc::ResolvedInclude { resolved_name: format!("{dir}/{requested}"), content })
            }
            None => Err(format!("cannot read {requested} in glsl/include or $OUT_DIR/include")),
        }
    });
    compiler
        .compile_into_spirv(text, kind, display, "main", Some(&options))
        .map(|a| {
            let warnings = a.get_warning_messages();
            if !warnings.is_empty() {
                println!("cargo:warning={}", warnings.replace('\n', " | "));
            }
            a.as_binary_u8().to_vec()
        })
        .map_err(|e| e.to_string())
}

/// The shaders' `interface.glsl`: a `#define NAME value` for every `pub const NAME: u32 | f64 = value;` line of
/// `src/gpu/interface.rs` (u32 as integer literals, f64 as float literals), with its `//` comments.
fn interface_header(rust: &Path) -> String {
    println!("cargo:rerun-if-changed={}", rust.display());
    let text = std::fs::read_to_string(rust).unwrap_or_else(|e| panic!("cannot read {}: {e}", rust.display()));
    let mut out = String::from(
        "// Generated by build.rs from src/gpu/interface.rs, the one source of these numbers: edit them there.\n\
         #ifndef INTERFACE_GLSL\n#define INTERFACE_GLSL\n",
    );
    let mut count = 0;
    for line in text.lines().map(str::trim) {
        if let Some(comment) = line.strip_prefix("// ") {
            writeln!(out, "\n// {comment}").unwrap();
            continue;
        }
        let Some(rest) = line.strip_prefix("pub const ") else { continue };
        let Some((name, rest)) = rest.split_once(": ") else { continue };
        let Some((ty, value)) = rest.split_once(" = ") else { continue };
        let value = value.trim_end_matches(';').replace('_', "");
        let literal = match ty {
            // Beyond i32's range GLSL needs the literal marked unsigned (smaller ones stay plain: layout qualifiers).
            "u32" => value
                .parse::<u32>()
                .map(|v| if v > i32::MAX as u32 { format!("{v}u") } else { v.to_string() })
                .map_err(|e| e.to_string()),
            "f64" => value.parse::<f64>().map(|v| format!("{v:?}")).map_err(|e| e.to_string()),
            _ => continue,
        };
        let literal = literal.unwrap_or_else(|e| panic!("{}: {name} = {value} is not a literal ({e})", rust.display()));
        writeln!(out, "#define {name} {literal}").unwrap();
        count += 1;
    }
    assert!(count > 0, "{} declares no constants", rust.display());
    out.push_str("\n#endif\n");
    out
}

/// The GLSL of the uniform block `name` (std140, set 0, `binding`) declared as `pub struct name { … }` in `rust`,
/// its fields in their order with their `///` comments, as `instance`.
fn uniform_block(rust: &Path, name: &str, binding: &str, instance: &str) -> String {
    println!("cargo:rerun-if-changed={}", rust.display());
    let text = std::fs::read_to_string(rust).unwrap_or_else(|e| panic!("cannot read {}: {e}", rust.display()));
    let start = text
        .find(&format!("pub struct {name} {{"))
        .unwrap_or_else(|| panic!("{}: no `pub struct {name} {{`", rust.display()));
    let body = &text[start..];
    let body = &body[body.find('{').unwrap() + 1..body.find("\n}").expect("the struct's closing brace")];
    let mut out = format!(
        "// Generated by build.rs from `{name}` in {}: edit the Rust struct, the GLSL follows.\n\
         #include \"interface.glsl\"\n\
         layout(std140, set = 0, binding = {binding}) uniform {name} {{\n",
        rust.display().to_string().rsplit("src/").next().map(|p| format!("src/{p}")).unwrap_or_default()
    );
    let mut comment = Vec::new();
    for line in body.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if let Some(doc) = line.strip_prefix("///") {
            comment.push(doc.trim().to_string());
            continue;
        }
        let field = line.strip_prefix("pub ").unwrap_or_else(|| panic!("{name}: a field that is not pub: {line}"));
        let (field, ty) = field.trim_end_matches(',').split_once(": ").expect("field: type");
        // An array of vec4 (`[[f32; 4]; N]`, N ≠ 4) has std140's 16-byte stride, as in Rust.
        let array = ty.strip_prefix("[[f32; 4]; ").and_then(|n| n.strip_suffix(']')).filter(|n| *n != "4");
        let (glsl, suffix) = match (ty, array) {
            (_, Some(n)) => ("vec4", format!("[{n}]")),
            ("[[f32; 4]; 4]", _) => ("mat4", String::new()),
            ("[f32; 4]", _) => ("vec4", String::new()),
            ("[i32; 4]", _) => ("ivec4", String::new()),
            ("[u32; 4]", _) => ("uvec4", String::new()),
            _ => panic!("{name}.{field}: {ty} has no std140 twin here (use a 16-byte type: [f32; 4], mat4, …)"),
        };
        for c in comment.drain(..) {
            writeln!(out, "    // {c}").unwrap();
        }
        writeln!(out, "    {glsl} {field}{suffix};").unwrap();
    }
    writeln!(out, "}} {instance};").unwrap();
    out
}

/// The push-constant block of the Rust struct `name` in `rust`: each field's GLSL type from its Rust type, and a
/// refusal where the GLSL rules would place a field elsewhere than `repr(C)` does (a vec2 aligns to 8 bytes).
fn push_block(rust: &Path, name: &str, instance: &str) -> String {
    println!("cargo:rerun-if-changed={}", rust.display());
    let text = std::fs::read_to_string(rust).unwrap_or_else(|e| panic!("cannot read {}: {e}", rust.display()));
    let start = text.find(&format!("pub struct {name} {{")).unwrap_or_else(|| panic!("no `pub struct {name} {{`"));
    let body = &text[start..];
    let body = &body[body.find('{').unwrap() + 1..body.find("\n}").expect("the struct's closing brace")];
    let mut fields = Vec::new();
    let mut offset = 0;
    for line in body.lines().map(str::trim).filter(|l| !l.is_empty() && !l.starts_with("//")) {
        let field = line.strip_prefix("pub ").unwrap_or_else(|| panic!("{name}: a field that is not pub: {line}"));
        let (field, ty) = field.trim_end_matches(',').split_once(": ").expect("field: type");
        let (glsl, size) = match ty {
            "f32" => ("float", 4),
            "u32" => ("uint", 4),
            "i32" => ("int", 4),
            "[f32; 2]" => ("vec2", 8),
            _ => panic!("{name}.{field}: {ty} has no push-constant twin here (f32, u32, i32, [f32; 2])"),
        };
        assert!(offset % size == 0, "{name}.{field}: a {glsl} at byte {offset} is not where GLSL puts it; reorder");
        offset += size;
        fields.push(format!("{glsl} {field};"));
    }
    format!(
        "// Generated by build.rs from `{name}` in src/gpu/interface.rs: edit the Rust struct, the GLSL follows.\n\
         layout(push_constant) uniform {name} {{ {} }} {instance};\n",
        fields.join(" ")
    )
}

/// The vertex shaders' inputs, from `VERTEX_ATTRIBUTES` in `rust` (render/surface.rs): for each
/// `VertexAttribute { location: N, format: vk::Format::F, offset: offset_of!(Vertex, field) … }` the line
/// `layout(location = N) in T in_field;`, T from the format.
fn vertex_inputs(rust: &Path) -> String {
    println!("cargo:rerun-if-changed={}", rust.display());
    let text = std::fs::read_to_string(rust).unwrap_or_else(|e| panic!("cannot read {}: {e}", rust.display()));
    let start = text.find("pub const VERTEX_ATTRIBUTES").expect("VERTEX_ATTRIBUTES in render/surface.rs");
    let list = &text[start..start + text[start..].find("];").expect("the array's end")];
    let mut out = String::from(
        "// Generated by build.rs from VERTEX_ATTRIBUTES in src/render/surface.rs (offsets from mesh::Vertex): edit\n\
         // them there, the shaders follow.\n",
    );
    let mut count = 0;
    for entry in list.split("VertexAttribute {").skip(1) {
        let words: String = entry.split_whitespace().collect::<Vec<_>>().join(" ");
        let after = |key: &str| words.split(key).nth(1).map(|r| r.trim_start());
        let location = after("location:").and_then(|r| r.split(',').next()).expect("a location");
        let format = after("vk::Format::").and_then(|r| r.split(',').next()).expect("a format");
        let field = after("offset_of!(Vertex,").and_then(|r| r.split(')').next()).expect("an offset_of!(Vertex, …)");
        let ty = match format.trim() {
            "R32_SFLOAT" => "float",
            "R32G32_SFLOAT" => "vec2",
            "R32G32B32_SFLOAT" => "vec3",
            "R32G32B32A32_SFLOAT" => "vec4",
            f => panic!("VERTEX_ATTRIBUTES: no GLSL type for {f}"),
        };
        writeln!(out, "layout(location = {}) in {ty} in_{};", location.trim(), field.trim()).unwrap();
        count += 1;
    }
    assert!(count > 0, "VERTEX_ATTRIBUTES lists no attribute");
    out
}
