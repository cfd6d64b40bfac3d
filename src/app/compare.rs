//! What the compare toolbar edits (`toolbars::CompareBar`), as one value
//! the toolbar returns in `Action::SetCompare`.

use super::state::{CompareB, CompareMode};
use super::AbView;
use crate::settings::albedo::MaterialAlbedo;

/// What the compare toolbar edits (`toolbars::CompareBar`).
#[derive(Debug, Clone, PartialEq)]
pub struct CompareSettings {
    pub mode: CompareMode,
    pub b: CompareB,
    /// Both sides, or one alone.
    pub ab: AbView,
    /// The look before the last edit is shown ("before", F).
    pub show_before: bool,
    /// White in the difference view (ΔL*), or each view's own largest.
    pub difference_scale: f32,
    pub difference_auto: bool,
    /// Where the split line sits (0–1).
    pub split: f32,
    /// The albedo B is drawn with when its engine keeps it in the material.
    pub b_albedo: MaterialAlbedo,
}
