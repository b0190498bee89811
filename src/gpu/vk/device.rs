//! Physical-device listing and choice, and the logical device with its one graphics+compute queue.
//!
//! Default choice: a discrete GPU, then an integrated one, then a virtual one, then a CPU implementation
//! (lavapipe). `--device N` picks by index (as `diffract devices` prints it), anything else by a
//! case-insensitive substring of the name.

use std::ffi::CStr;

use ash::vk;

use crate::error::{Error, Result, VkResultExt};

/// Device extensions diffract needs beyond Vulkan 1.3 core.
const REQUIRED_EXTENSIONS: &[&CStr] = &[ash::khr::push_descriptor::NAME];

/// How the user asked for a device.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum DeviceSelector {
    /// The preferred device by type.
    #[default]
    Auto,
    /// By index in enumeration order.
    Index(usize),
    /// By case-insensitive substring of the device name.
    Name(String),
}

impl DeviceSelector {
    /// Parses `--device` text: a number is an index, anything else a name substring.
    ///
    /// ```
    /// use diffract::gpu::vk::DeviceSelector;
    /// assert_eq!(DeviceSelector::parse("1"), DeviceSelector::Index(1));
    /// assert_eq!(DeviceSelector::parse("llvmpipe"), DeviceSelector::Name("llvmpipe".into()));
    /// ```
    pub fn parse(text: &str) -> Self {
        match text.trim().parse::<usize>() {
            Ok(i) => DeviceSelector::Index(i),
            Err(_) => DeviceSelector::Name(text.trim().to_string()),
        }
    }
}

/// What `diffract devices` prints about one physical device.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    pub index: usize,
    pub raw: vk::PhysicalDevice,
    pub name: String,
    pub kind: vk::PhysicalDeviceType,
    pub api_version: u32,
    pub driver: String,
    pub timestamp_period_ns: f32,
    pub limits: vk::PhysicalDeviceLimits,
}

impl DeviceInfo {
    pub fn kind_name(&self) -> &'static str {
        match self.kind {
            vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
            vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
            vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
            vk::PhysicalDeviceType::CPU => "CPU",
            _ => "other",
        }
    }

    pub fn api_version_string(&self) -> String {
        let v = self.api_version;
        format!("{}.{}.{}", vk::api_version_major(v), vk::api_version_minor(v), vk::api_version_patch(v))
    }

    fn preference(&self) -> u32 {
        match self.kind {
            vk::PhysicalDeviceType::DISCRETE_GPU => 0,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
            vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
            vk::PhysicalDeviceType::CPU => 3,
            _ => 4,
        }
    }
}

/// Lists every physical device the loader reports.
pub fn list(instance: &ash::Instance) -> Result<Vec<DeviceInfo>> {
    // SAFETY: plain queries on a live instance.
    let raws = unsafe { instance.enumerate_physical_devices() }.vk("vkEnumeratePhysicalDevices")?;
    Ok(raws
        .into_iter()
        .enumerate()
        .map(|(index, raw)| {
            let mut driver = vk::PhysicalDeviceDriverProperties::default();
            let mut props2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
            // SAFETY: `raw` came from this instance; the chain outlives the call.
            unsafe { instance.get_physical_device_properties2(raw, &mut props2) };
            let p = props2.properties;
            let name = p.device_name_as_c_str().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            let drv_name = driver.driver_name_as_c_str().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            let drv_info = driver.driver_info_as_c_str().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            DeviceInfo {
                index,
                raw,
                name,
                kind: p.device_type,
                api_version: p.api_version,
                driver: format!("{drv_name} {drv_info}").trim().to_string(),
                timestamp_period_ns: p.limits.timestamp_period,
                limits: p.limits,
            }
        })
        .collect())
}

/// Picks a device from `list` according to `selector`.
pub fn choose(devices: &[DeviceInfo], selector: &DeviceSelector) -> Result<DeviceInfo> {
    if devices.is_empty() {
        return Err(Error::NoDevice);
    }
    let available = || devices.iter().map(|d| format!("{}: {}", d.index, d.name)).collect::<Vec<_>>().join(", ");
    let found = match selector {
        DeviceSelector::Auto => devices.iter().min_by_key(|d| (d.preference(), d.index)),
        DeviceSelector::Index(i) => devices.iter().find(|d| d.index == *i),
        DeviceSelector::Name(s) => {
            let s = s.to_lowercase();
            devices.iter().find(|d| d.name.to_lowercase().contains(&s))
        }
    };
    let selector_text = match selector {
        DeviceSelector::Auto => "auto".to_string(),
        DeviceSelector::Index(i) => i.to_string(),
        DeviceSelector::Name(s) => s.clone(),
    };
    found.cloned().ok_or_else(|| Error::UnknownDevice { selector: selector_text, available: available() })
}

/// The logical device, its queue and the extension loaders built on it.
pub struct Device {
    pub raw: ash::Device,
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub timestamp_valid_bits: u32,
    pub push_descriptor: ash::khr::push_descriptor::Device,
    pub debug_utils: Option<ash::ext::debug_utils::Device>,
    pub pipeline_statistics: bool,
    /// Whether the device can draw a visibility buffer (`render::visibility`): a triangle's index in the fragment
    /// shader (`geometryShader`) and stores from the vertex shader.
    pub visibility_buffer: bool,
    /// Whether samplers may filter anisotropically (`samplerAnisotropy`; the surface maps ask for it).
    pub sampler_anisotropy: bool,
}

impl Device {
    /// Creates the logical device with synchronization2, dynamic rendering and push descriptors (and
    /// `VK_KHR_swapchain` when `window`).
    pub fn new(instance: &ash::Instance, info: &DeviceInfo, debug_names: bool, window: bool) -> Result<Self> {
        let unsuitable = |reason: String| Error::UnsuitableDevice { name: info.name.clone(), reason };
        if info.api_version < vk::API_VERSION_1_3 {
            return Err(unsuitable(format!("it supports Vulkan {}, diffract needs 1.3", info.api_version_string())));
        }
        // SAFETY: plain queries on a physical device of this instance.
        let (families, extensions, features) = unsafe {
            (
                instance.get_physical_device_queue_family_properties(info.raw),
                instance.enumerate_device_extension_properties(info.raw).vk("vkEnumerateDeviceExtensionProperties")?,
                instance.get_physical_device_features(info.raw),
            )
        };
        let mut wanted_extensions: Vec<&CStr> = REQUIRED_EXTENSIONS.to_vec();
        if window {
            wanted_extensions.push(ash::khr::swapchain::NAME);
        }
        for ext in &wanted_extensions {
            if !extensions.iter().any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == *ext)) {
                return Err(unsuitable(format!("it lacks {}", ext.to_string_lossy())));
            }
        }
        let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
        let (queue_family, family) = families
            .iter()
            .enumerate()
            .find(|(_, f)| f.queue_flags.contains(wanted))
            .ok_or_else(|| unsuitable("it has no graphics+compute queue".into()))?;
        let priorities = [1.0f32];
        let queue_info = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(queue_family as u32)
            .queue_priorities(&priorities)];
        let ext_names: Vec<_> = wanted_extensions.iter().map(|e| e.as_ptr()).collect();
        // maintenance4 is mandatory in 1.3; SPIR-V 1.6 compute shaders declare their work-group size with LocalSizeId.
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default()
            .synchronization2(true)
            .dynamic_rendering(true)
            .maintenance4(true);
        let pipeline_statistics = features.pipeline_statistics_query == vk::TRUE;
        let visibility_buffer = features.geometry_shader == vk::TRUE
            && features.vertex_pipeline_stores_and_atomics == vk::TRUE
            && features.fragment_stores_and_atomics == vk::TRUE;
        let base = vk::PhysicalDeviceFeatures::default()
            .pipeline_statistics_query(pipeline_statistics)
            .geometry_shader(visibility_buffer)
            .vertex_pipeline_stores_and_atomics(visibility_buffer)
            .fragment_stores_and_atomics(features.fragment_stores_and_atomics == vk::TRUE)
            .sampler_anisotropy(features.sampler_anisotropy == vk::TRUE);
        let create = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_info)
            .enabled_extension_names(&ext_names)
            .enabled_features(&base)
            .push_next(&mut f13);
        // SAFETY: every pointer in `create` outlives the call.
        let raw = unsafe { instance.create_device(info.raw, &create, None) }.vk("vkCreateDevice")?;
        // SAFETY: the queue family and index were requested above.
        let queue = unsafe { raw.get_device_queue(queue_family as u32, 0) };
        let push_descriptor = ash::khr::push_descriptor::Device::new(instance, &raw);
        let debug_utils = debug_names.then(|| ash::ext::debug_utils::Device::new(instance, &raw));
        Ok(Self {
            raw,
            queue,
            queue_family: queue_family as u32,
            timestamp_valid_bits: family.timestamp_valid_bits,
            push_descriptor,
            debug_utils,
            pipeline_statistics,
            visibility_buffer,
            sampler_anisotropy: features.sampler_anisotropy == vk::TRUE,
        })
    }

    /// Gives a Vulkan object a debug name (visible in validation messages and GPU debuggers).
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        let Some(du) = &self.debug_utils else { return };
        let Ok(cname) = std::ffi::CString::new(name) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default().object_handle(handle).object_name(&cname);
        // SAFETY: `handle` is a live object of this device; naming is best-effort.
        let _ = unsafe { du.set_debug_utils_object_name(&info) };
    }
}
