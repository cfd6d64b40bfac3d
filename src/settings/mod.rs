//! Serde types that describe a look. Presets are these types written as
//! RON. Every struct is `#[serde(default)]` so older files still load, and
//! validation errors name the field (and the loader adds the file).

pub mod albedo;
pub mod library;
pub mod preset;
pub mod profile;
pub mod rendering;
pub mod view;

pub use preset::{is_preset_file, Preset, PresetError, PRESET_EXTENSION};
pub use profile::ProfileSpec;
pub use rendering::RenderingSpec;
pub use view::{OrbitView, RigLight};
