//! wgpu renderer (never egui): offscreen HDR targets, the SSS methods and
//! readback, so the same code serves the viewport, `render` and the tests.

pub mod compare;
pub mod context;
pub mod environment;
mod frame;
mod gltf_mesh;
pub mod gpu_types;
pub mod inputs;
pub mod mesh;
pub mod pipelines;
pub mod procedural;
mod profile_gpu;
pub mod readback;
pub mod renderer;
pub mod settings;
mod sss;
pub mod textures;
pub mod timing;

pub use context::{GpuContext, GpuError};
pub use mesh::Mesh;
pub use renderer::{
    FrameStats, IrradiancePattern, Method, ProfileInputs, RenderSettings, Renderer, Specular,
    TexturingMode, Transmission,
};
pub use timing::PassStats;
