//! The Vulkan loader, the instance and, when asked for, the Khronos validation layer with a debug messenger
//! that prints every message to stderr and counts it, so tests can fail on any message.

use std::ffi::{c_void, CStr};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use ash::vk;

use crate::error::{Error, Result, VkResultExt};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Messages the validation layer reported, shared between the messenger callback and its readers.
#[derive(Debug, Default)]
pub struct ValidationLog {
    count: AtomicUsize,
    messages: Mutex<Vec<String>>,
}

impl ValidationLog {
    /// Number of warnings and errors reported so far.
    pub fn count(&self) -> usize {
        self.count.load(Ordering::SeqCst)
    }

    /// The text of every message reported so far.
    pub fn messages(&self) -> Vec<String> {
        self.messages.lock().map(|m| m.clone()).unwrap_or_default()
    }

    fn record(&self, line: String) {
        log::warn!(target: crate::io::LOG_VALIDATION, "{line}");
        self.count.fetch_add(1, Ordering::SeqCst);
        if let Ok(mut m) = self.messages.lock() {
            m.push(line);
        }
    }
}

/// The instance and, when validation is on, its messenger. Destroyed by [`Instance::destroy`].
pub struct Instance {
    pub entry: ash::Entry,
    pub raw: ash::Instance,
    pub debug_utils: Option<ash::ext::debug_utils::Instance>,
    messenger: vk::DebugUtilsMessengerEXT,
    /// Owns the log the messenger callback writes to (its pointer is the callback's user data).
    pub validation: Arc<ValidationLog>,
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data for the duration of the call, and `user` points at the
    // `ValidationLog` kept alive by `Instance::validation` until the messenger is destroyed.
    unsafe {
        let log = &*(user as *const ValidationLog);
        let data = &*data;
        let text = if data.p_message.is_null() {
            "(no message)".into()
        } else {
            CStr::from_ptr(data.p_message).to_string_lossy()
        };
        let level = if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) { "error" } else { "warning" };
        log.record(format!("validation {level} ({kind:?}): {text}"));
    }
    vk::FALSE
}

fn messenger_info(log: &Arc<ValidationLog>) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR)
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(Arc::as_ptr(log) as *mut c_void)
}

/// The Vulkan loader, loaded once per process, with the drivers pinned for the process's life.
///
/// The loader opens the drivers (ICDs) when an instance is created and closes them when the last instance is
/// destroyed. NVIDIA's driver does not survive being closed and opened again in one process: on an H200 (driver
/// 580.159.04) the GPU test binary, whose tests each open and close their own contexts, found no device from its
/// ninth test on when the tests ran one at a time, and crashed (SIGSEGV) on an H100 and an H200 when two ran at
/// once; every test passed in a process of its own. So the first use creates one bare instance (no layer, no
/// extension) that is never destroyed: the drivers it opened stay open, and later instances only share them.
fn loader() -> Result<ash::Entry> {
    static LOADER: std::sync::OnceLock<std::result::Result<ash::Entry, String>> = std::sync::OnceLock::new();
    let loaded = LOADER.get_or_init(|| {
        // SAFETY: loading the system's libvulkan; failure is reported, not assumed away.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| e.to_string())?;
        let app = vk::ApplicationInfo::default().application_name(c"diffract (drivers kept open)");
        let info = vk::InstanceCreateInfo::default().application_info(&app);
        // SAFETY: every pointer in `info` outlives the call. The instance is deliberately never destroyed; a
        // machine with no driver fails here, and the real instance reports it.
        let _pinned = unsafe { entry.create_instance(&info, None) };
        Ok(entry)
    });
    loaded.clone().map_err(Error::NoLoader)
}

impl Instance {
    /// Loads the Vulkan loader and creates an instance for Vulkan 1.3, with the validation layer if asked.
    pub fn new(validation: bool, extra_extensions: &[*const std::ffi::c_char]) -> Result<Self> {
        let entry = loader()?;
        if validation {
            // SAFETY: a plain query on a loaded entry.
            let layers =
                unsafe { entry.enumerate_instance_layer_properties() }.vk("vkEnumerateInstanceLayerProperties")?;
            let found = layers.iter().any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER));
            if !found {
                return Err(Error::NoValidationLayer);
            }
        }
        let log = Arc::new(ValidationLog::default());
        let app = vk::ApplicationInfo::default()
            .application_name(c"diffract")
            .engine_name(c"diffract")
            .api_version(vk::API_VERSION_1_3);
        let layer_names = [VALIDATION_LAYER.as_ptr()];
        let mut extensions: Vec<*const std::ffi::c_char> = extra_extensions.to_vec();
        if validation {
            extensions.push(ash::ext::debug_utils::NAME.as_ptr());
            extensions.push(ash::ext::validation_features::NAME.as_ptr());
        }
        // Synchronisation validation catches missing or wrong barriers, which the core validation does not.
        let sync_features = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&sync_features);
        let mut early_messenger = messenger_info(&log);
        let mut info = vk::InstanceCreateInfo::default().application_info(&app).enabled_extension_names(&extensions);
        if validation {
            // Chained so that messages from vkCreateInstance/vkDestroyInstance are caught too.
            info = info.enabled_layer_names(&layer_names).push_next(&mut early_messenger).push_next(&mut features);
        }
        // SAFETY: every pointer in `info` outlives the call.
        let raw = unsafe { entry.create_instance(&info, None) }.map_err(|result| match result {
            vk::Result::ERROR_INCOMPATIBLE_DRIVER => Error::NoDevice,
            result => Error::Vulkan { call: "vkCreateInstance", result },
        })?;
        let (debug_utils, messenger) = if validation {
            let du = ash::ext::debug_utils::Instance::new(&entry, &raw);
            // SAFETY: the callback's user data (the log) is owned by the returned Instance.
            let m = unsafe { du.create_debug_utils_messenger(&messenger_info(&log), None) };
            match m {
                Ok(m) => (Some(du), m),
                Err(result) => {
                    // SAFETY: nothing else was created from this instance yet.
                    unsafe { raw.destroy_instance(None) };
                    return Err(Error::Vulkan { call: "vkCreateDebugUtilsMessengerEXT", result });
                }
            }
        } else {
            (None, vk::DebugUtilsMessengerEXT::null())
        };
        Ok(Self { entry, raw, debug_utils, messenger, validation: log })
    }

    /// # Safety
    /// Every object created from this instance must already be destroyed.
    pub unsafe fn destroy(self) {
        if let Some(du) = &self.debug_utils {
            du.destroy_debug_utils_messenger(self.messenger, None);
        }
        self.raw.destroy_instance(None);
    }
}
