//! The ground truth's floor on a scene: how far the yardstick is from two
//! answers it must give exactly (issue 22). Differences between methods
//! smaller than the floor are the yardstick's noise, not theirs.
//!
//! - **d → 0.** A profile that scatters nothing (Burley with the look's
//!   colour and d = 1 µm on every channel) must give back the unscattered
//!   frame: the ground truth against `none`, relative RMSE over SSS
//!   pixels. It measures how well the CPU twin of the scene pass, its
//!   texture filtering at the pixel's footprint and the exact near field
//!   reproduce what the GPU draws.
//! - **Finer sampling.** The ground truth gathered at 2 × 2 points of each
//!   pixel's footprint and averaged (each with the maps read over the
//!   pixel's footprint, the scene pass's filter that defines a pixel's
//!   value for every method) against the plain one (a point per pixel),
//!   over the pixels whose footprint is one surface
//!   (`Cloud::gather_supersampled`; the others, at silhouettes and creases,
//!   are counted in `mixed_fraction`).

use super::metrics;
use crate::model::burley::Burley;
use crate::render::{Method, ProfileInputs, RenderSettings, Renderer};
use anyhow::{Context, Result};

/// Scattering distance (mm) of the profile that scatters nothing: far
/// under every bench pixel. At 5 µm the planes' 62.5 µm pixels beside a
/// checker edge, 31 µm from it, took a real share of light across it
/// (the strip CDF's tail): plane_checker's "floor" was 0.0072 at
/// 640×360, and 1.2·10⁻⁵ at 1 µm; the heads gave 0.0059/0.0027 at 5 µm
/// and 0.0060/0.0028 at 1 µm (back-lit ear, front).
pub const D_ZERO_MM: f64 = 0.001;

/// The floor of one scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Floor {
    /// Relative RMSE of the d → 0 ground truth against the `none` frame.
    pub d_to_zero: f64,
    /// Relative RMSE of the 2 × 2-supersampled ground truth against the
    /// plain one, over pixels whose footprint is one surface.
    pub supersampled: f64,
    /// Fraction of SSS pixels whose footprint is not one surface.
    pub mixed_fraction: f64,
}

/// The look's inputs with its profile replaced by one that scatters
/// nothing and the same colour (so the scene pass, and with it the ground
/// truth's cells, are the look's own).
pub fn d_to_zero_inputs(look: &ProfileInputs) -> Result<ProfileInputs> {
    let profile = d_to_zero_profile(look)?;
    let mut inputs = ProfileInputs::new(&profile, 21, 17)?;
    inputs.shared.surface_albedo = look.shared.surface_albedo;
    Ok(inputs)
}

/// The profile of [`d_to_zero_inputs`]: Burley with the look's colour and
/// d = [`D_ZERO_MM`].
pub fn d_to_zero_profile(look: &ProfileInputs) -> Result<Burley> {
    let albedo = look
        .shared
        .surface_albedo
        .map(|a| (a as f64).clamp(1e-3, 1.0));
    Ok(Burley::from_scattering_distance(albedo, [D_ZERO_MM; 3])?)
}

/// Measures the floor of the scene `settings` with the look `look`, given
/// the plain ground truth of that look already rendered (`plain`, its
/// scattered diffuse).
pub fn measure(
    renderer: &mut Renderer,
    look: &ProfileInputs,
    settings: &RenderSettings,
    plain: &[[f32; 4]],
) -> Result<Floor> {
    let with = |method: Method| RenderSettings {
        method,
        ..settings.clone()
    };
    let zero = d_to_zero_inputs(look)?;
    let (_, none, _) = renderer
        .render_with_diffuse(&zero, &with(Method::baseline()))
        .context("floor: the none frame at d → 0")?;
    let (_, truth, _) = renderer
        .render_with_diffuse(&zero, &with(Method::ground_truth()))
        .context("floor: the ground truth at d → 0")?;
    let mask = metrics::sss_mask(&none);
    let d_to_zero = metrics::relative_rmse(&truth, &none, &mask);
    // The ground truth's own option: 2 × 2 points a pixel.
    let mut supersampled = look.clone();
    supersampled.options.reference.supersample = 2;
    let (_, fine, _) = renderer
        .render_with_diffuse(&supersampled, &with(Method::ground_truth()))
        .context("floor: the supersampled ground truth")?;
    let sss = metrics::sss_mask(plain);
    let one_surface: Vec<bool> = sss
        .iter()
        .zip(&fine)
        .map(|(m, f)| *m && f[..3].iter().all(|v| v.is_finite()))
        .collect();
    let (n_sss, n_one) = (count(&sss), count(&one_surface));
    Ok(Floor {
        d_to_zero,
        supersampled: metrics::relative_rmse(&fine, plain, &one_surface),
        mixed_fraction: if n_sss > 0 {
            1.0 - n_one as f64 / n_sss as f64
        } else {
            0.0
        },
    })
}

fn count(mask: &[bool]) -> usize {
    mask.iter().filter(|m| **m).count()
}
