//! The wgpu device: any adapter, lavapipe included, with validation
//! errors captured rather than panicking.

use thiserror::Error;

#[derive(Debug, Error)]
pub enum GpuError {
    #[error(
        "no GPU adapter found (install a Vulkan driver such as mesa-vulkan-drivers/lavapipe): {0}"
    )]
    NoAdapter(String),
    #[error(
        "the GPU adapter {adapter} cannot render to {format:?}, which the renderer needs: install Mesa's Vulkan driver (Debian/Ubuntu: apt-get install mesa-vulkan-drivers) or update the GPU driver, then run with WGPU_BACKEND=vulkan"
    )]
    Unsupported {
        adapter: String,
        format: wgpu::TextureFormat,
    },
    #[error("the GPU device could not be created: {0}")]
    Device(String),
    #[error("GPU validation error in {stage}: {message}")]
    Validation {
        stage: &'static str,
        message: String,
    },
    #[error("reading the frame back failed: {0}")]
    Readback(String),
    #[error(
        "the ground truth (`reference`) reads the shadow map back, which the adapter {adapter} cannot (no depth-texture copies, as on GL): run it on Vulkan (Debian/Ubuntu: apt-get install mesa-vulkan-drivers, then WGPU_BACKEND=vulkan), or pick another method"
    )]
    NoGroundTruth { adapter: String },
    #[error(
        "the profile's inputs were made without what `{method}` reads ({missing}): build them for that method (ProfileInputs::for_look or for_method with it)"
    )]
    InputsLack {
        method: &'static str,
        missing: &'static str,
    },
    #[error(
        "{what} take {bytes} bytes, over the {limit} bytes the GPU allows in one storage buffer: use the CPU ground truth (`reference`), or a coarser mesh"
    )]
    TooLarge {
        what: &'static str,
        bytes: u64,
        limit: u64,
    },
    #[error(
        "`texture-space --probe-rays on` needs ray queries: {0}; or gather through the UV layout alone (--probe-rays off)"
    )]
    NoRayQueries(String),
    #[error(
        "`texture-space --neighbours 3d`: the point cloud's tree of a {size}² atlas takes {bytes} bytes, over the {limit} bytes this GPU binds in one storage buffer: use --atlas-size {half} or smaller"
    )]
    AtlasTreeTooLarge {
        size: u32,
        half: u32,
        bytes: u64,
        limit: u64,
    },
    /// A newer request asked for the ground truth running now to stop
    /// (`Renderer::cancel_with`): not a failure, nothing to show.
    #[error("the ground truth was cancelled by a newer request")]
    Cancelled,
}

/// Linear-depth formats, best first (see [`GpuContext::linear_depth_format`]).
pub const LINEAR_DEPTH_CANDIDATES: [wgpu::TextureFormat; 3] = [
    wgpu::TextureFormat::R32Float,
    wgpu::TextureFormat::R16Float,
    wgpu::TextureFormat::Rgba16Float,
];

/// Formats the renderer draws into with no fallback: the HDR targets, the
/// albedo target, the output, the depth-stencil and shadow depth buffers.
const REQUIRED_RENDERABLE: [wgpu::TextureFormat; 5] = [
    wgpu::TextureFormat::Rgba16Float,
    wgpu::TextureFormat::Rgba8Unorm,
    wgpu::TextureFormat::Rgba8UnormSrgb,
    wgpu::TextureFormat::Depth24PlusStencil8,
    wgpu::TextureFormat::Depth32Float,
];

/// Whether a device has ray queries, or why not.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum RayQueries {
    Available,
    /// Why not, in words an artist can act on.
    Missing(String),
}

/// Set to 1, devices are made without ray queries where the adapter has
/// them (the tests of the fallback; a driver whose ray queries misbehave).
pub const NO_RAY_QUERY_ENV: &str = "SCATTERLAB_NO_RAY_QUERY";

impl RayQueries {
    fn of(adapter: &wgpu::Adapter) -> Self {
        if std::env::var(NO_RAY_QUERY_ENV).is_ok_and(|v| v == "1") {
            return Self::Missing(format!("{NO_RAY_QUERY_ENV}=1 turned them off"));
        }
        if adapter
            .features()
            .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY)
        {
            return Self::Available;
        }
        let info = adapter.get_info();
        Self::Missing(format!(
            "the adapter \"{}\" ({:?}, driver {}) has no ray queries: Mesa's lavapipe has them from 25 on (Debian 12: bookworm-backports' mesa-vulkan-drivers, tools/setup-debian.sh), GPUs through Vulkan's VK_KHR_ray_query",
            info.name, info.backend, info.driver_info
        ))
    }

    pub fn available(&self) -> bool {
        *self == Self::Available
    }

    /// `limits` with the adapter's acceleration-structure limits where ray
    /// queries are on (wgpu's defaults are 0 for them).
    fn limits(&self, limits: wgpu::Limits, adapter: &wgpu::Limits) -> wgpu::Limits {
        if !self.available() {
            return limits;
        }
        wgpu::Limits {
            max_blas_primitive_count: adapter.max_blas_primitive_count,
            max_blas_geometry_count: adapter.max_blas_geometry_count,
            max_tlas_instance_count: adapter.max_tlas_instance_count,
            max_acceleration_structures_per_shader_stage: adapter
                .max_acceleration_structures_per_shader_stage,
            ..limits
        }
    }

    /// wgpu's token for its `EXPERIMENTAL_` features, enabled only where
    /// the adapter offers ray queries (the device then has them whether
    /// or not a frame casts probe rays: it is made before any frame).
    #[allow(unsafe_code)]
    fn token(&self) -> wgpu::ExperimentalFeatures {
        if !self.available() {
            return wgpu::ExperimentalFeatures::disabled();
        }
        // SAFETY: the one `unsafe` in the crate. wgpu asks its users to
        // acknowledge that its experimental APIs may still hold bugs; the
        // only one used is EXPERIMENTAL_RAY_QUERY (`texture-space
        // --probe-rays on`: an acceleration structure built from the mesh
        // and queried in one fragment shader), and the known one is
        // avoided: wgpu 30.0.1's naga emits invalid SPIR-V for a
        // `ray_query` declared inside a loop, so the shader declares it at
        // the function's top level (shaders/texture_space_rays.wgsl). The
        // shader is validated by naga in tests/shaders.rs, and the gather
        // is tested on lavapipe against closed forms
        // (tests/render_physics.rs, `texture_space_probe_rays_*` and
        // `texture_space_follows_the_strip_cdf_across_an_edge`). A driver
        // that refuses the feature gets a device without it (`create`).
        unsafe { wgpu::ExperimentalFeatures::enabled() }
    }
}

/// A device and queue plus what the adapter is.
pub struct GpuContext {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    pub adapter_info: wgpu::AdapterInfo,
    pub timestamps: bool,
    /// Format of the linear-depth target: R32Float where the adapter can
    /// render to it (Vulkan, Metal, D3D12); R16Float or Rgba16Float on GL
    /// ES and older adapters (half precision: depth steps of ~1/2048 of
    /// the distance, enough for the depth-aware SSS weights at a head).
    pub linear_depth_format: wgpu::TextureFormat,
    /// Format of the specular target (RG11B10 where renderable).
    pub specular_format: wgpu::TextureFormat,
    /// Whether depth textures can be copied to buffers (not on GL): the
    /// ground truth reads the shadow map back.
    pub depth_copies: bool,
    /// Whether the device was made with ray queries (wgpu's
    /// `EXPERIMENTAL_RAY_QUERY`: Vulkan's `VK_KHR_ray_query`, lavapipe 25
    /// and newer, most GPUs since 2018), or why not: `texture-space`
    /// gathers by probe rays only with them ([`RayQueries`]).
    pub ray_queries: RayQueries,
    /// Why the device was lost, once wgpu's device-lost callback has said
    /// so (a driver reset, a GPU removed, `Device::destroy`).
    lost: std::sync::Arc<std::sync::Mutex<Option<String>>>,
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
        let mut ray_queries = RayQueries::of(&adapter);
        let renderable = |f: wgpu::TextureFormat| {
            adapter
                .get_texture_format_features(f)
                .allowed_usages
                .contains(wgpu::TextureUsages::RENDER_ATTACHMENT)
        };
        let info = adapter.get_info();
        let depth_copies = adapter
            .get_downlevel_capabilities()
            .flags
            .contains(wgpu::DownlevelFlags::DEPTH_TEXTURE_AND_BUFFER_COPIES);
        let unsupported = |format| GpuError::Unsupported {
            adapter: format!("\"{}\" ({:?})", info.name, info.backend),
            format,
        };
        let linear_depth_format = LINEAR_DEPTH_CANDIDATES
            .into_iter()
            .find(|f| renderable(*f))
            .ok_or_else(|| unsupported(LINEAR_DEPTH_CANDIDATES[0]))?;
        for f in REQUIRED_RENDERABLE {
            if !renderable(f) {
                return Err(unsupported(f));
            }
        }
        let descriptor = |ray_queries: &RayQueries| wgpu::DeviceDescriptor {
            label: Some("scatterlab"),
            required_features: match ray_queries.available() {
                true => required_features | wgpu::Features::EXPERIMENTAL_RAY_QUERY,
                false => required_features,
            },
            required_limits: wgpu::Limits {
                // The GPU ground truth reads seven storage buffers in
                // one compute shader (ground_truth/gpu.rs); downlevel
                // devices that have fewer fall back to the CPU's.
                max_storage_buffers_per_shader_stage: adapter
                    .limits()
                    .max_storage_buffers_per_shader_stage
                    .clamp(4, 8),
                ..ray_queries.limits(
                    wgpu::Limits::downlevel_defaults().using_resolution(adapter.limits()),
                    &adapter.limits(),
                )
            },
            experimental_features: ray_queries.token(),
            ..Default::default()
        };
        // Ray queries are experimental in wgpu: a driver that refuses a
        // device with them still gets one without them, and says why.
        let (device, queue) = match adapter.request_device(&descriptor(&ray_queries)).await {
            Ok(made) => made,
            Err(e) if ray_queries.available() => {
                ray_queries =
                    RayQueries::Missing(format!("the driver refused a device with them ({e})"));
                adapter
                    .request_device(&descriptor(&ray_queries))
                    .await
                    .map_err(|e| GpuError::Device(e.to_string()))?
            }
            Err(e) => return Err(GpuError::Device(e.to_string())),
        };
        let lost = std::sync::Arc::new(std::sync::Mutex::new(None));
        let slot = lost.clone();
        device.set_device_lost_callback(move |reason, message| {
            if let Ok(mut s) = slot.lock() {
                *s = Some(match message.is_empty() {
                    true => format!("{reason:?}"),
                    false => format!("{reason:?}: {message}"),
                });
            }
        });
        Ok(Self {
            device,
            queue,
            adapter_info: info,
            timestamps,
            linear_depth_format,
            depth_copies,
            ray_queries,
            lost,
            specular_format: if rg11b10 {
                wgpu::TextureFormat::Rg11b10Ufloat
            } else {
                wgpu::TextureFormat::Rgba16Float
            },
        })
    }

    /// Why the device was lost, if it was: nothing made on it can be used
    /// again, and the renderer must be made anew on a new device.
    pub fn lost(&self) -> Option<String> {
        self.lost.lock().ok().and_then(|s| s.clone())
    }

    /// Destroys the device, as a driver reset would (tests of the
    /// recovery; nothing in the editor calls it), and waits for wgpu to
    /// report the loss.
    #[doc(hidden)]
    pub fn destroy_device(&self) {
        self.device.destroy();
        let _ = self.device.poll(wgpu::PollType::wait_indefinitely());
    }

    /// Runs `f` inside validation and internal error scopes and reports
    /// what they caught (an internal error is a shader the backend cannot
    /// compile, e.g. WGSL the GL backend does not support), with the fix.
    pub fn checked<T>(&self, stage: &'static str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
        let internal = self.device.push_error_scope(wgpu::ErrorFilter::Internal);
        let validation = self.device.push_error_scope(wgpu::ErrorFilter::Validation);
        let out = f();
        let v = pollster::block_on(validation.pop());
        let i = pollster::block_on(internal.pop());
        match (v, i) {
            (Some(e), _) => Err(GpuError::Validation {
                stage,
                message: e.to_string(),
            }),
            (None, Some(e)) => Err(GpuError::Validation {
                stage,
                message: format!(
                    "{e} (the {:?} backend cannot run this renderer: install Mesa's Vulkan driver, Debian/Ubuntu: apt-get install mesa-vulkan-drivers, and run with WGPU_BACKEND=vulkan)",
                    self.adapter_info.backend
                ),
            }),
            (None, None) => Ok(out),
        }
    }
}
