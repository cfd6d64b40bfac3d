//! What every method's inputs share, computed on the CPU from the
//! profile core: the thin-slab transmittance table the scene pass reads,
//! the surface colour, and whether anything scatters. Each method's own
//! inputs are its file's `Inputs` under `sss/`, gathered with these in
//! [`super::sss::ProfileInputs`].

use crate::model::{RadialProfile, Rgb};
pub use crate::settings::albedo::{look_colour, KERNEL_SURFACE_ALBEDO};
use crate::settings::ProfileSpec;

/// What every method shares for one look.
#[derive(Debug, Clone)]
pub struct Shared {
    /// False when no channel scatters (e.g. Jimenez strength 0): SSS passes are skipped.
    pub scatters: bool,
    /// Normalised thin-slab transmittance T(d)/total at d = range·i/63
    /// (the scene pass's, for every method).
    pub transmittance: Vec<[f32; 4]>,
    pub transmittance_range_mm: f32,
    /// The look's colour: its total diffuse reflectance ∫2πr R(r) dr per
    /// channel (Burley's A), clamped to [0, 1]. The scattering kernels are
    /// energy-normalised, as in the engines, so this is where the look's
    /// colour enters: the base colour of a surface whose map only
    /// modulates (the default head), while a colour map of the artist's
    /// own is the albedo (HDRP, Unreal, Cycles: the material's base colour,
    /// the profile normalised).
    pub surface_albedo: [f32; 3],
}

impl Shared {
    /// For the look `spec` (if any) built as `profile`.
    pub fn new(spec: Option<&ProfileSpec>, profile: &dyn RadialProfile) -> Self {
        let total = profile.total_reflectance();
        let r_max = table_radius_mm(profile);
        let dirac = profile.dirac_weight();
        Self {
            scatters: (0..3).any(|c| total[c] - dirac[c] > 1e-9 * total[c].max(1e-300)),
            transmittance: transmittance_table(profile, r_max, total),
            transmittance_range_mm: r_max as f32,
            surface_albedo: match spec {
                Some(spec) => look_colour(spec, profile),
                None => total.map(|t| t.clamp(0.0, 1.0) as f32),
            },
        }
    }

    /// Feeds everything the GPU receives from these to `h`.
    pub fn fingerprint_into(&self, h: &mut impl std::hash::Hasher) {
        use std::hash::Hash;
        h.write(bytemuck::cast_slice(&self.transmittance));
        h.write(bytemuck::cast_slice(&[self.transmittance_range_mm]));
        self.scatters.hash(h);
    }
}

/// How far the profile's tables reach (mm): the widest channel's
/// 0.999-energy radius.
pub fn table_radius_mm(profile: &dyn RadialProfile) -> f64 {
    profile
        .radius_for_energy(0.999)
        .into_iter()
        .fold(1e-6, f64::max)
}

/// The thin-slab transmittance T(d)/total per channel at 64 thicknesses
/// d = r_max·i/63 (`shaders/scene.wgsl` `transmittance_at`).
fn transmittance_table(profile: &dyn RadialProfile, r_max: f64, total: Rgb) -> Vec<[f32; 4]> {
    (0..64)
        .map(|i| {
            let t = profile.transmittance(r_max * i as f64 / 63.0);
            let n = |c: usize| {
                if total[c] > 0.0 {
                    (t[c] / total[c]) as f32
                } else {
                    0.0
                }
            };
            [n(0), n(1), n(2), 0.0]
        })
        .collect()
}
