//! Links shaderc and what it is built from (glslang, SPIRV-Tools) from the system's static archives.
//!
//! Debian's `libshaderc-dev` ships `libshaderc_combined.a` without glslang and SPIRV-Tools inside it, and its
//! `libshaderc.so` leaves 36 glslang symbols undefined, so a crate that links either alone fails ("undefined
//! reference: glslang::TProgram::getInfoLog()"); the shaderc crate's own build script does exactly that. The
//! archives of glslang and SPIRV-Tools that the same package pulls in complete it, and since this script emits
//! them, any crate that depends on diffract links without a `.cargo/config.toml` of its own.
//!
//! `SHADERC_LIB_DIR` names another folder; by default the Debian multiarch one (`/usr/lib/<arch>-linux-gnu`),
//! then `/usr/lib64` and `/usr/lib`.

use std::path::{Path, PathBuf};

/// The archives, shaderc's first: GNU ld takes them in this order (lld in any).
const ARCHIVES: &[&str] = &[
    "shaderc_combined",
    "glslang",
    "MachineIndependent",
    "OSDependent",
    "GenericCodeGen",
    "OGLCompiler",
    "SPIRV",
    "HLSL",
    "glslang-default-resource-limits",
    "SPIRV-Tools-opt",
    "SPIRV-Tools",
];

fn main() {
    println!("cargo:rerun-if-env-changed=SHADERC_LIB_DIR");
    let arch = std::env::var("CARGO_CFG_TARGET_ARCH").unwrap_or_default();
    let debian_arch = if arch == "x86" { "i386".to_string() } else { arch };
    let candidates: Vec<PathBuf> = match std::env::var_os("SHADERC_LIB_DIR") {
        Some(dir) => vec![dir.into()],
        None => [format!("/usr/lib/{debian_arch}-linux-gnu"), "/usr/lib64".into(), "/usr/lib".into()]
            .into_iter()
            .map(PathBuf::from)
            .collect(),
    };
    let has = |dir: &Path, name: &str| dir.join(format!("lib{name}.a")).is_file();
    let Some(dir) = candidates.iter().find(|d| has(d, ARCHIVES[0])) else {
        panic!(
            "no libshaderc_combined.a in {}: install Debian's libshaderc-dev (diffract's scripts/setup-debian.sh does), \
             or set SHADERC_LIB_DIR to the folder of shaderc's static archives",
            candidates.iter().map(|d| d.display().to_string()).collect::<Vec<_>>().join(", ")
        )
    };
    let missing: Vec<&str> = ARCHIVES.iter().copied().filter(|a| !has(dir, a)).collect();
    assert!(
        missing.is_empty(),
        "{}: lib{}.a missing (glslang-dev and spirv-tools come with libshaderc-dev)",
        dir.display(),
        missing.join(".a, lib")
    );
    println!("cargo:rustc-link-search=native={}", dir.display());
    for archive in ARCHIVES {
        // Not bundled into this crate's rlib: the final link reads the system's archives.
        println!("cargo:rustc-link-lib=static:-bundle={archive}");
    }
    println!("cargo:rustc-link-lib=dylib=stdc++");
}
