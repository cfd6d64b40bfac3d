//! wgpu renderer (never egui): offscreen HDR targets, the SSS methods and
//! readback, so the same code serves the viewport, `render` and the tests.

pub mod compare;
pub mod context;
pub mod gpu_types;
pub mod mesh;
pub mod renderer;

pub use context::{GpuContext, GpuError};
pub use mesh::Mesh;
pub use renderer::{
    FrameStats, IrradiancePattern, Method, ProfileInputs, RenderSettings, Renderer, Specular,
    TexturingMode, Transmission,
};
