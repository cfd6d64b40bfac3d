#![cfg_attr(test, allow(clippy::unwrap_used))]
// `!(x > 0.0)` is deliberate throughout: it is true for NaN as well.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Per-channel numerics index several arrays with one channel index.
#![allow(clippy::needless_range_loop)]
//! scatterlab: author subsurface-scattering diffusion profiles.
//!
//! Layering (see ARCHITECTURE.md): `model` is pure math (profiles, kernels,
//! sampling, lookup tables, fits, unit conversions) tested against
//! independent references; `settings` holds the serde types of a look and
//! its RON presets; `cli` drives them without a window. The renderer
//! (`render`, wgpu) and the editor (`app`, egui) build on these; `export`
//! writes engine assets and images; `bench` measures every method's run
//! time against its error and proves that unused work is skipped.

#[cfg(feature = "gpu")]
pub mod app;
#[cfg(feature = "gpu")]
pub mod bench;
#[cfg(feature = "gpu")]
pub mod cli;
pub mod export;
pub mod fsutil;
pub mod model;
pub mod render;
pub mod settings;

/// ARCHITECTURE.md's layering, checked on the source: `model` imports
/// neither `render`, `settings`' callers (`app`, `cli`, `bench`, `export`)
/// nor a GPU or UI crate; `render` imports neither egui/eframe nor `app`,
/// `cli` or `bench`; no circle of imports in `render/` or `app/`, and
/// none running up `render/`'s layers. Comments are skipped (they may
/// name what is absent).
#[cfg(test)]
mod layering;
