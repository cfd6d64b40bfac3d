//! The presets shipped in `presets/`, embedded so the editor lists them
//! wherever it runs.

use super::{Preset, PresetError};
use std::path::Path;

/// (file name, RON text) of every shipped preset.
pub const PRESETS: [(&str, &str); 17] = [
    (
        "apple_jensen2001.ron",
        include_str!("../../presets/apple_jensen2001.ron"),
    ),
    ("jade.ron", include_str!("../../presets/jade.ron")),
    (
        "ketchup_jensen2001.ron",
        include_str!("../../presets/ketchup_jensen2001.ron"),
    ),
    (
        "layered_donner2006.ron",
        include_str!("../../presets/layered_donner2006.ron"),
    ),
    (
        "marble_jensen2001.ron",
        include_str!("../../presets/marble_jensen2001.ron"),
    ),
    (
        "skin1_jensen2001.ron",
        include_str!("../../presets/skin1_jensen2001.ron"),
    ),
    (
        "skin2_jensen2001.ron",
        include_str!("../../presets/skin2_jensen2001.ron"),
    ),
    (
        "skin_default.ron",
        include_str!("../../presets/skin_default.ron"),
    ),
    (
        "skin_deon_six_gaussians.ron",
        include_str!("../../presets/skin_deon_six_gaussians.ron"),
    ),
    (
        "skin_jimenez2012_demo.ron",
        include_str!("../../presets/skin_jimenez2012_demo.ron"),
    ),
    (
        "skin_jimenez2015_multi_layer.ron",
        include_str!("../../presets/skin_jimenez2015_multi_layer.ron"),
    ),
    (
        "skin_jimenez2015_production.ron",
        include_str!("../../presets/skin_jimenez2015_production.ron"),
    ),
    (
        "skin_jimenez2015_single_layer.ron",
        include_str!("../../presets/skin_jimenez2015_single_layer.ron"),
    ),
    (
        "skin_unity_hdrp_default.ron",
        include_str!("../../presets/skin_unity_hdrp_default.ron"),
    ),
    (
        "skin_unreal_default.ron",
        include_str!("../../presets/skin_unreal_default.ron"),
    ),
    ("wax.ron", include_str!("../../presets/wax.ron")),
    (
        "whole_milk_jensen2001.ron",
        include_str!("../../presets/whole_milk_jensen2001.ron"),
    ),
];

/// Parses the shipped preset `file`.
pub fn load(file: &str) -> Result<Preset, PresetError> {
    let text = PRESETS
        .iter()
        .find(|(f, _)| *f == file)
        .map(|(_, t)| *t)
        .unwrap_or("");
    Preset::from_ron(text, Path::new(file))
}

/// Whether `dir` is the shipped presets' folder (it holds every shipped
/// preset file).
pub fn is_shipped_presets(dir: &Path) -> bool {
    PRESETS.iter().all(|(file, _)| dir.join(file).is_file())
}

#[cfg(test)]
mod tests {
    /// Every file in presets/ is embedded (a new file must be added here).
    #[test]
    fn every_shipped_preset_is_embedded_and_loads() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("presets");
        let on_disk = std::fs::read_dir(dir)
            .unwrap()
            .filter(|e| {
                e.as_ref()
                    .is_ok_and(|e| crate::settings::is_preset_file(&e.path()))
            })
            .count();
        assert_eq!(on_disk, super::PRESETS.len());
        for (f, _) in super::PRESETS {
            super::load(f).unwrap_or_else(|e| panic!("{e}"));
        }
    }
}
