//! wgpu renderer (never egui): offscreen HDR targets, the SSS methods and
//! readback, so the same code serves the viewport, `render` and the tests.

//!
//! Without the `gpu` feature (the fuzz targets) only the CPU side is built:
//! meshes, surface maps, environments and settings.

pub mod compare;
#[cfg(feature = "gpu")]
pub mod context;
#[cfg(feature = "gpu")]
pub mod driver;
pub mod environment;
#[cfg(feature = "gpu")]
mod frame;
#[cfg(feature = "gpu")]
mod framing;
pub mod gpu_types;
pub mod ground_truth;
#[cfg(feature = "gpu")]
pub mod inputs;
#[cfg(feature = "gpu")]
mod layers;
pub mod mesh;
#[cfg(feature = "gpu")]
mod passes;
#[cfg(feature = "gpu")]
pub mod pipelines;
#[cfg(feature = "gpu")]
mod profile_gpu;
#[cfg(feature = "gpu")]
pub mod readback;
#[cfg(feature = "gpu")]
pub mod renderer;
pub mod scene_cpu;
pub mod settings;
#[cfg(feature = "gpu")]
pub mod sss;
#[cfg(feature = "gpu")]
mod targets;
pub mod textures;
#[cfg(feature = "gpu")]
pub mod timing;
pub mod tonemap;
pub mod uv_layout;

#[cfg(feature = "gpu")]
pub use context::{GpuContext, GpuError};
#[cfg(feature = "gpu")]
pub use layers::{luminance, FrameLayers, SceneLinear, StopsHistogram};
pub use mesh::{procedural, Mesh};
#[cfg(feature = "gpu")]
pub use renderer::Renderer;
#[cfg(feature = "gpu")]
pub use settings::{CameraRecord, FrameStats};
pub use settings::{
    IrradiancePattern, Method, Progressive, RenderSettings, Specular, TexturingMode, Transmission,
    TruthProgress, TruthTiles,
};
#[cfg(feature = "gpu")]
pub use sss::burley::BurleySampling;
#[cfg(feature = "gpu")]
pub use sss::gaussians::{gaussian_taps, gaussian_terms};
#[cfg(feature = "gpu")]
pub use sss::{Knob, MethodInfo, Quality};
#[cfg(feature = "gpu")]
pub use sss::{MethodOptions, ProfileInputs};
#[cfg(feature = "gpu")]
pub use timing::PassStats;
