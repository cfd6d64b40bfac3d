//! scatterlab: author subsurface-scattering diffusion profiles.
//!
//! Layering (see ARCHITECTURE.md): `model` is pure math (profiles, kernels,
//! sampling, lookup tables, fits, unit conversions) tested against
//! independent references; `settings` holds the serde types of a look and
//! its RON presets; `cli` drives them without a window. The renderer
//! (`render`, wgpu) and the editor (`app`, egui) build on these.

pub mod cli;
pub mod fsutil;
pub mod model;
pub mod settings;
