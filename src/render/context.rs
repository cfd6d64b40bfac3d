//! The wgpu device: any adapter, lavapipe included, with validation
//! errors captured rather than panicking.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found (install a Vulkan driver such as mesa-vulkan-drivers/lavapipe): {0}"
    )]
    NoAdapter(String),
    #[error("the GPU device could not be created: {0}")]
    Device(String),
    #[error("GPU validation error in {stage}: {message}")]
    Validation {
        stage: &'static str,
        message: String,
    },
    #[error("reading the frame back failed: {0}")]
    Readback(String),
}

/// A device and queue plus what the adapter is.
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter_info: wgpu::AdapterInfo,
    pub timestamps: bool,
    /// Format of the specular target (RG11B10 where renderable).
    pub specular_format: wgpu::TextureFormat,
}

impl GpuContext {
    /// A headless device on the best available adapter.
    pub fn new_headless() -> Result<Self, GpuError> {
        pollster::block_on(Self::create())
    }

    async fn create() -> Result<Self, GpuError> {
        let instance =
            wgpu::Instance::new(wgpu::InstanceDescriptor::new_without_display_handle_from_env());
        let adapter = instance
            .request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                apply_limit_buckets: false,
            })
            .await
            .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let timestamps = adapter.features().contains(wgpu::Features::TIMESTAMP_QUERY);
        // Specular in 4 bytes a pixel where the adapter can render to
        // RG11B10 (the 4K target budget); 8 bytes otherwise.
        let rg11b10 = adapter
            .features()
            .contains(wgpu::Features::RG11B10UFLOAT_RENDERABLE);
        let mut required_features = wgpu::Features::empty();
        if timestamps {
            required_features |= wgpu::Features::TIMESTAMP_QUERY;
        }
        if rg11b10 {
            required_features |= wgpu::Features::RG11B10UFLOAT_RENDERABLE;
        }
        let (device, queue) = adapter
            .request_device(&wgpu::DeviceDescriptor {
                label: Some("scatterlab"),
                required_features,
                required_limits: wgpu::Limits::downlevel_defaults()
                    .using_resolution(adapter.limits()),
                ..Default::default()
            })
            .await
            .map_err(|e| GpuError::Device(e.to_string()))?;
        Ok(Self {
            device,
            queue,
            adapter_info: adapter.get_info(),
            timestamps,
            specular_format: if rg11b10 {
                wgpu::TextureFormat::Rg11b10Ufloat
            } else {
                wgpu::TextureFormat::Rgba16Float
            },
        })
    }

    /// Runs `f` inside a validation error scope and reports what it caught.
    pub fn checked<T>(&self, stage: &'static str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let scope = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        match pollster::block_on(scope.pop()) {
            Some(e) => Err(GpuError::Validation {
                stage,
                message: e.to_string(),
            }),
            None => Ok(out),
        }
    }
}
