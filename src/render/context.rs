//! Headless GPU context: instance, adapter and device for commands and tests without a window.
//!
//! - The viewer uses eframe's device instead and never creates one of these.
//! - The adapter is the one `WGPU_BACKEND` / `WGPU_ADAPTER_NAME` choose if set, else the default
//!   (a discrete or integrated GPU before a software one).

use crate::error::{Error, Result};

pub use crate::error::NO_ADAPTER_HELP;

pub struct GpuContext {
    pub instance: wgpu::Instance,
    pub adapter: wgpu::Adapter,
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
}

impl GpuContext {
    /// Opens the adapter chosen by `WGPU_BACKEND` / `WGPU_ADAPTER_NAME` if set, else the default
    /// (a discrete or integrated GPU before a software one).
    pub fn headless() -> Result<GpuContext> {
        // Native APIs first; OpenGL only when none has an adapter (probing it is noisy and slow).
        let tries = match wgpu::Backends::from_env() {
            Some(b) => vec![b],
            None => vec![wgpu::Backends::PRIMARY, wgpu::Backends::GL],
        };
        let mut last_error = String::new();
        for backends in tries {
            let mut desc = wgpu::InstanceDescriptor::new_without_display_handle();
            desc.backends = backends;
            let instance = wgpu::Instance::new(desc);
            match pollster::block_on(wgpu::util::initialize_adapter_from_env_or_default(&instance, None)) {
                Ok(adapter) => return Self::open(instance, adapter),
                Err(e) => last_error = e.to_string(),
            }
        }
        Err(Error::NoAdapter { tried: last_error })
    }

    fn open(instance: wgpu::Instance, adapter: wgpu::Adapter) -> Result<GpuContext> {
        let limits =
            wgpu::Limits { max_buffer_size: adapter.limits().max_buffer_size, ..wgpu::Limits::downlevel_defaults() }
                .using_resolution(adapter.limits());
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("vbrain headless"),
            required_limits: limits,
            required_features: adapter.features() & super::WANTED_FEATURES,
            ..Default::default()
        }))
        .map_err(|e| Error::Device { adapter: adapter.get_info().name, message: e.to_string() })?;
        super::guard::log_uncaptured(&device);
        Ok(GpuContext { instance, adapter, device, queue })
    }

    /// "name (backend, device type)" of the adapter, for reports.
    pub fn adapter_description(&self) -> String {
        let i = self.adapter.get_info();
        format!("{} ({:?}, {:?})", i.name, i.backend, i.device_type)
    }
}
