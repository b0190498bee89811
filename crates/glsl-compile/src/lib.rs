//! GLSL to SPIR-V for diffract's build script, through shaderc's C API (`shaderc/shaderc.h`), which the build
//! script of this crate links from the system's static archives (see `build.rs` for why not the `shaderc` crate).
//! Only what diffract's shaders need: a shader kind, macros, the Vulkan 1.3 / SPIR-V 1.6 target, debug info or
//! optimisation, and an include callback.

use std::ffi::{c_char, c_int, c_void, CString};

/// The stage a source is compiled for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShaderKind {
    Vertex,
    Fragment,
    Compute,
}

/// Where an `#include "name"` is read: (a unique name for messages, the text), or an error message.
pub type Include<'a> = &'a dyn Fn(&str) -> Result<(String, String), String>;

/// How to compile: macros (`NAME` or `NAME=value`), debug info (else optimised for performance), and where an
/// `#include "name"` is read: the include callback returns (a unique name, the text) or an error message.
pub struct Options<'a> {
    pub macros: Vec<(String, Option<String>)>,
    pub debug_info: bool,
    pub include: Include<'a>,
}

/// A compiled module: its SPIR-V bytes and shaderc's warnings (empty where there were none).
pub struct Compiled {
    pub spirv: Vec<u8>,
    pub warnings: String,
}

#[allow(non_camel_case_types)]
type shaderc_include_resolve_fn =
    extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, usize) -> *mut IncludeResult;
#[allow(non_camel_case_types)]
type shaderc_include_result_release_fn = extern "C" fn(*mut c_void, *mut IncludeResult);

/// `shaderc_include_result`.
#[repr(C)]
struct IncludeResult {
    source_name: *const c_char,
    source_name_length: usize,
    content: *const c_char,
    content_length: usize,
    user_data: *mut c_void,
}

extern "C" {
    fn shaderc_compiler_initialize() -> *mut c_void;
    fn shaderc_compiler_release(compiler: *mut c_void);
    fn shaderc_compile_options_initialize() -> *mut c_void;
    fn shaderc_compile_options_release(options: *mut c_void);
    fn shaderc_compile_options_add_macro_definition(
        options: *mut c_void,
        name: *const c_char,
        name_length: usize,
        value: *const c_char,
        value_length: usize,
    );
    fn shaderc_compile_options_set_generate_debug_info(options: *mut c_void);
    fn shaderc_compile_options_set_optimization_level(options: *mut c_void, level: c_int);
    fn shaderc_compile_options_set_target_env(options: *mut c_void, env: c_int, version: u32);
    fn shaderc_compile_options_set_target_spirv(options: *mut c_void, version: c_int);
    fn shaderc_compile_options_set_include_callbacks(
        options: *mut c_void,
        resolver: shaderc_include_resolve_fn,
        releaser: shaderc_include_result_release_fn,
        user_data: *mut c_void,
    );
    fn shaderc_compile_into_spv(
        compiler: *mut c_void,
        source: *const c_char,
        source_size: usize,
        kind: c_int,
        input_file_name: *const c_char,
        entry_point: *const c_char,
        options: *mut c_void,
    ) -> *mut c_void;
    fn shaderc_result_release(result: *mut c_void);
    fn shaderc_result_get_length(result: *mut c_void) -> usize;
    fn shaderc_result_get_num_warnings(result: *mut c_void) -> usize;
    fn shaderc_result_get_bytes(result: *mut c_void) -> *const c_char;
    fn shaderc_result_get_compilation_status(result: *mut c_void) -> c_int;
    fn shaderc_result_get_error_message(result: *mut c_void) -> *const c_char;
}

// shaderc's enum values (env.h, shaderc.h, status.h).
const TARGET_ENV_VULKAN: c_int = 0;
const ENV_VERSION_VULKAN_1_3: u32 = (1 << 22) | (3 << 12);
const SPIRV_VERSION_1_6: c_int = 0x010600;
const OPTIMIZATION_PERFORMANCE: c_int = 2;
const STATUS_SUCCESS: c_int = 0;

/// A shaderc compiler (one per build script; not shared between threads).
pub struct Compiler(*mut c_void);

impl Compiler {
    pub fn new() -> Result<Self, String> {
        // SAFETY: a plain constructor; null means shaderc could not start.
        let raw = unsafe { shaderc_compiler_initialize() };
        if raw.is_null() {
            return Err("shaderc could not be initialised".into());
        }
        Ok(Self(raw))
    }

    /// Compiles `source` (named `file_name` in messages) for Vulkan 1.3 and SPIR-V 1.6, entry point `main`.
    /// Err: shaderc's messages (`file:line: error: …`).
    pub fn compile(
        &self,
        source: &str,
        kind: ShaderKind,
        file_name: &str,
        options: &Options<'_>,
    ) -> Result<Compiled, String> {
        let c_source = CString::new(source).map_err(|_| format!("{file_name}: a NUL byte in the source"))?;
        let c_file = CString::new(file_name).map_err(|_| format!("{file_name}: a NUL byte in the name"))?;
        let entry = c"main";
        let kind = match kind {
            ShaderKind::Vertex => 0,
            ShaderKind::Fragment => 1,
            ShaderKind::Compute => 2,
        };
        let macros: Vec<(CString, Option<CString>)> = options
            .macros
            .iter()
            .map(|(n, v)| {
                let c = |s: &str| CString::new(s).map_err(|_| format!("{file_name}: a NUL byte in a macro"));
                Ok((c(n)?, v.as_deref().map(c).transpose()?))
            })
            .collect::<Result<_, String>>()?;
        // The callback's context: the caller's include function, behind a thin pointer.
        let mut include: Include<'_> = options.include;
        // SAFETY: every pointer passed lives until the compilation returns (`macros`, the strings, `include`);
        // the options and the result are released on every path.
        unsafe {
            let raw_options = shaderc_compile_options_initialize();
            if raw_options.is_null() {
                return Err("shaderc could not make its options".into());
            }
            for (name, value) in &macros {
                let (value_ptr, value_len) =
                    value.as_ref().map_or((std::ptr::null(), 0), |v| (v.as_ptr(), v.as_bytes().len()));
                shaderc_compile_options_add_macro_definition(
                    raw_options,
                    name.as_ptr(),
                    name.as_bytes().len(),
                    value_ptr,
                    value_len,
                );
            }
            shaderc_compile_options_set_target_env(raw_options, TARGET_ENV_VULKAN, ENV_VERSION_VULKAN_1_3);
            shaderc_compile_options_set_target_spirv(raw_options, SPIRV_VERSION_1_6);
            if options.debug_info {
                shaderc_compile_options_set_generate_debug_info(raw_options);
            } else {
                shaderc_compile_options_set_optimization_level(raw_options, OPTIMIZATION_PERFORMANCE);
            }
            let user_data = (&mut include as *mut Include<'_>).cast();
            shaderc_compile_options_set_include_callbacks(raw_options, resolve, release, user_data);
            let result = shaderc_compile_into_spv(
                self.0,
                c_source.as_ptr(),
                source.len(),
                kind,
                c_file.as_ptr(),
                entry.as_ptr(),
                raw_options,
            );
            shaderc_compile_options_release(raw_options);
            if result.is_null() {
                return Err(format!("{file_name}: shaderc returned no result"));
            }
            let message = text(shaderc_result_get_error_message(result));
            let outcome = if shaderc_result_get_compilation_status(result) == STATUS_SUCCESS {
                let bytes = shaderc_result_get_bytes(result).cast::<u8>();
                let spirv = std::slice::from_raw_parts(bytes, shaderc_result_get_length(result)).to_vec();
                let warnings = if shaderc_result_get_num_warnings(result) > 0 { message } else { String::new() };
                Ok(Compiled { spirv, warnings })
            } else {
                Err(message)
            };
            shaderc_result_release(result);
            outcome
        }
    }
}

impl Drop for Compiler {
    fn drop(&mut self) {
        // SAFETY: made by shaderc_compiler_initialize, released once.
        unsafe { shaderc_compiler_release(self.0) }
    }
}

/// A C string shaderc owns, as text (empty for null).
unsafe fn text(p: *const c_char) -> String {
    if p.is_null() {
        return String::new();
    }
    std::ffi::CStr::from_ptr(p).to_string_lossy().into_owned()
}

/// What one include request holds until shaderc releases it: the strings the result points into (`repr(C)`:
/// the result first, so that a pointer to it is a pointer to the whole).
#[repr(C)]
struct Included {
    result: IncludeResult,
    _name: Vec<u8>,
    _content: Vec<u8>,
}

extern "C" fn resolve(
    user_data: *mut c_void,
    requested: *const c_char,
    _kind: c_int,
    _requesting: *const c_char,
    _depth: usize,
) -> *mut IncludeResult {
    // SAFETY: `user_data` is the `&dyn Fn` that `compile` passed, alive for the compilation; `requested` is a C
    // string shaderc owns for this call.
    let (include, requested) = unsafe { (&**user_data.cast::<Include<'_>>(), text(requested)) };
    // A panic must not cross into C: it becomes a failed include.
    let found = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| include(&requested)))
        .unwrap_or_else(|_| Err(format!("reading {requested} panicked")));
    // A failed include has an empty name and the error message as its content.
    let (name, content) = match found {
        Ok((name, content)) => (name.into_bytes(), content.into_bytes()),
        Err(message) => (Vec::new(), message.into_bytes()),
    };
    let included = Box::new(Included {
        result: IncludeResult {
            source_name: name.as_ptr().cast(),
            source_name_length: name.len(),
            content: content.as_ptr().cast(),
            content_length: content.len(),
            user_data: std::ptr::null_mut(),
        },
        _name: name,
        _content: content,
    });
    // `result` is the first field: shaderc hands this pointer back to `release`.
    Box::into_raw(included).cast()
}

extern "C" fn release(_user_data: *mut c_void, result: *mut IncludeResult) {
    if !result.is_null() {
        // SAFETY: `resolve` made it from a Box<Included> whose first field it points to.
        drop(unsafe { Box::from_raw(result.cast::<Included>()) });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn compiles_with_an_include_and_a_macro_and_reports_errors() {
        let compiler = Compiler::new().unwrap();
        let include = |name: &str| match name {
            "value.glsl" => Ok(("inc/value.glsl".to_string(), "const float VALUE = 2.0;".to_string())),
            _ => Err(format!("no {name}")),
        };
        let options = Options { macros: vec![("TWICE".into(), None)], debug_info: false, include: &include };
        let source = "#version 450\n#include \"value.glsl\"\nlayout(location = 0) out vec4 c;\n\
                      void main() {\n#ifdef TWICE\n c = vec4(VALUE * 2.0);\n#endif\n}\n";
        let out = compiler.compile(source, ShaderKind::Fragment, "t.frag", &options).unwrap();
        assert_eq!(&out.spirv[..4], &0x0723_0203u32.to_le_bytes());
        let missing = "#version 450\n#include \"nothing.glsl\"\nvoid main() {}\n";
        let e = compiler.compile(missing, ShaderKind::Fragment, "m.frag", &options).err().unwrap();
        assert!(e.contains("no nothing.glsl"), "{e}");
        let e = compiler.compile("#version 450\nvoid main() { x; }\n", ShaderKind::Compute, "e.comp", &options);
        assert!(e.err().unwrap().contains("e.comp:2"));
    }
}
