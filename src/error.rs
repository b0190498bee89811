//! The library's error type. Every variant renders as one line a user can act on; the command line prints it
//! after `error: ` and exits non-zero. A Vulkan failure names the call that failed (`.vk("vkCreateBuffer")?`).

use ash::vk;

pub type Result<T, E = Error> = std::result::Result<T, E>;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("cannot load the Vulkan loader ({0}); install libvulkan1 and mesa-vulkan-drivers")]
    NoLoader(String),
    #[error("no Vulkan device found; install mesa-vulkan-drivers (lavapipe) or a GPU driver")]
    NoDevice,
    #[error("no Vulkan device matches --device {selector:?}; `diffract devices` lists them: {available}")]
    UnknownDevice { selector: String, available: String },
    #[error("device {name:?} cannot run diffract: {reason}")]
    UnsuitableDevice { name: String, reason: String },
    #[error("the validation layer VK_LAYER_KHRONOS_validation is not installed; install vulkan-validationlayers")]
    NoValidationLayer,
    #[error("{call} failed: {result}")]
    Vulkan { call: &'static str, result: vk::Result },
    // Causes are part of the message (not `#[source]`) so that the one-line report shows them exactly once.
    #[error("GPU memory allocation {name:?} failed: {cause}")]
    Allocation { name: String, cause: gpu_allocator::AllocationError },
    #[error("invalid SPIR-V for shader {name:?}: {cause}")]
    Spirv { name: String, cause: std::io::Error },
    /// A setting, flag or parameter out of its range or malformed: `name` says which (a setting's key, a flag, a
    /// parameter such as `turbidity`), the message what is wrong and what is accepted.
    #[error("{message}")]
    Setting { name: String, message: String },
    /// A height field diffract cannot use: its size, pixel size or heights.
    #[error("{0}")]
    HeightField(String),
    /// A scene file's mistake, at its line where one is known.
    #[error("{}", scene_message(file, *line, message))]
    Scene { file: String, line: Option<usize>, message: String },
    /// One material of a scene could not be prepared (`part`: what of it, or empty).
    #[error("material {name:?}: {part}{cause}")]
    Material { name: String, part: &'static str, cause: Box<Error> },
    /// One configuration of a profile failed.
    #[error("configuration {label}: {cause}")]
    Configuration { label: String, cause: Box<Error> },
    /// What the device lacks or cannot hold for this work (a feature, a format, an image size).
    #[error("{message}")]
    Unsupported { device: String, message: String },
    /// More than diffract handles: memory for terms, objects or triangles in one buffer.
    #[error("{0}")]
    TooLarge(String),
    /// Arithmetic that cannot reach the asked accuracy, or values that came out non-finite.
    #[error("{0}")]
    Precision(String),
    /// Light that cannot be used so: an environment that gives none, a table that diffracts nothing, relative units.
    #[error("{0}")]
    Light(String),
    /// The window system: no display, a window that cannot be opened or read.
    #[error("{0}")]
    Window(String),
    /// Anything else a caller passed that does not fit (sizes that do not match, a buffer too small).
    #[error("{0}")]
    Invalid(String),
    #[error("{path}: {message}")]
    Input { path: String, message: String },
    #[error("cannot write {path}: {message}")]
    Output { path: String, message: String },
}

fn scene_message(file: &str, line: Option<usize>, message: &str) -> String {
    match line {
        Some(line) => format!("{file}:{line}: {message}"),
        None => format!("{file}: {message}"),
    }
}

impl Error {
    /// A setting or parameter `name` out of range (see [`Error::Setting`]).
    pub fn setting(name: &str, message: String) -> Self {
        Error::Setting { name: name.to_string(), message }
    }

    /// What `device` cannot do (see [`Error::Unsupported`]).
    pub fn unsupported(device: &str, message: String) -> Self {
        Error::Unsupported { device: device.to_string(), message }
    }

    /// A user-facing error about an input file.
    pub fn input(path: impl AsRef<std::path::Path>, message: impl Into<String>) -> Self {
        Error::Input { path: path.as_ref().display().to_string(), message: message.into() }
    }

    /// A user-facing error about an output file.
    pub fn output(path: impl AsRef<std::path::Path>, message: impl std::fmt::Display) -> Self {
        Error::Output { path: path.as_ref().display().to_string(), message: message.to_string() }
    }
}

/// Attaches the name of the failing Vulkan call to an `ash` result.
pub trait VkResultExt<T> {
    fn vk(self, call: &'static str) -> Result<T>;
}

impl<T> VkResultExt<T> for std::result::Result<T, vk::Result> {
    fn vk(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { call, result })
    }
}

/// Shortest round-trip text of `x` for messages and CSV: plain for ordinary magnitudes, scientific for tiny or
/// huge ones (a hostile 1e300 stays one short line); −0 is 0.
pub fn number(x: f64) -> String {
    let x = x + 0.0;
    if x == 0.0 || (1e-4..1e7).contains(&x.abs()) || !x.is_finite() {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}
