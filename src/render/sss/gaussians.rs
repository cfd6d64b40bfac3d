//! `gaussians` (d'Eon 2007, Jimenez 2009 in screen space): the profile as
//! a sum of Gaussians, each blurred in two depth-aware 1D passes; each
//! vertical pass adds its Gaussian's RGB weight × result into the output
//! (additive blending), so N Gaussians cost 2N passes.

use super::separable::{self, Into};
use super::{Knob, Look, MethodInputs, Scattered, SssFrame, SssPipelines};
use crate::model::{ModelError, RadialProfile};
use crate::render::context::GpuError;
use crate::render::frame::FrameEncoder;
use crate::render::gpu_types::GpuTap;
use crate::render::profile_gpu::storage;
use crate::render::targets::HdrTarget;

/// `gaussians` in the registry (`sss::Method::sss`).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "gaussians",
    label: "gaussians (d'Eon 2007)",
    slow_bake: true,
    colour: [148, 103, 189],
    bench: || {
        vec![Knob {
            variant: "6x2-passes",
            series: (" (6x2-passes)", None),
            ..Knob::FIXED
        }]
    },
    encode,
    ..super::MethodInfo::BASE
};

/// `gaussians`' command-line options.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::Args)]
#[group(skip)]
pub struct Options {
    /// Taps of each 1D Gaussian pass of `gaussians` (odd, 3–63; 7 is
    /// d'Eon 2007's kernel, 13 follows edges more closely at about twice
    /// the cost).
    #[arg(id = "gaussian_taps", long = "gaussian-taps", value_name = "GAUSSIAN_TAPS", default_value_t = GAUSSIAN_TAPS, value_parser = odd_taps)]
    pub taps: usize,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            taps: GAUSSIAN_TAPS,
        }
    }
}

/// `--gaussian-taps`: an odd count from 3 to 63.
fn odd_taps(text: &str) -> Result<usize, String> {
    let n: usize = text
        .parse()
        .map_err(|_| format!("{text:?} is not a whole number"))?;
    if !(3..=63).contains(&n) {
        return Err(format!("gaussian_taps = {n} is outside its range [3, 63]"));
    }
    if n.is_multiple_of(2) {
        return Err(format!("gaussian_taps = {n} must be odd"));
    }
    Ok(n)
}

/// Nothing is kept between frames.
pub(in crate::render) type State = ();

/// It draws with `separable`'s 1D pass.
pub(in crate::render) type Pipelines = ();

/// `gaussians`' share of the profile on the GPU: one tap buffer per
/// Gaussian, with its RGB weight and σ (mm).
pub(in crate::render) struct Buffers {
    gaussians: Vec<(wgpu::Buffer, [f32; 3], f32)>,
    /// Taps of each 1D pass.
    tap_count: u32,
}

impl super::MethodBuffers<Inputs> for Buffers {
    fn new(device: &wgpu::Device, _: &wgpu::Queue, inputs: &Inputs) -> Self {
        Self {
            gaussians: inputs
                .gaussians
                .iter()
                .map(|(sigma, weight)| {
                    let taps: Vec<GpuTap> = gaussian_taps(*sigma, inputs.taps);
                    let buffer = storage(device, "gaussian taps", bytemuck::cast_slice(&taps));
                    (buffer, *weight, *sigma)
                })
                .collect(),
            tap_count: gaussian_taps(1.0, inputs.taps).len() as u32,
        }
    }
}

fn encode(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
    _: &mut super::State,
) -> Result<Scattered, GpuError> {
    let gpu = &io.profile.methods.gaussians;
    let taps = gpu.tap_count;
    if gpu.gaussians.is_empty() {
        // No Gaussians set: nothing to add, the diffuse stays unscattered.
        return Ok(Scattered::in_target(HdrTarget::Diffuse, 0));
    }
    for (k, (buffer, weight, sigma)) in gpu.gaussians.iter().enumerate() {
        // Each Gaussian follows the surface with its own σ (Jimenez 2015
        // eq. 7 before its σ_max approximation: exact for a Gaussian).
        separable::blur_xy(
            f,
            p,
            io,
            (buffer, taps),
            *sigma,
            Into::Add {
                weight: *weight,
                first: k == 0,
            },
            ["sss gaussian x", "sss gaussian y"],
        );
    }
    Ok(Scattered::in_target(
        HdrTarget::Pong,
        2 * taps * gpu.gaussians.len() as u32,
    ))
}

/// `gaussians`' CPU inputs: each Gaussian's σ and weight, and the taps of
/// each 1D pass.
#[derive(Debug, Clone)]
pub struct Inputs {
    /// (σ mm, normalised RGB weight) of each Gaussian; empty until
    /// [`Inputs::set`].
    pub gaussians: Vec<(f32, [f32; 3])>,
    /// Taps of each 1D Gaussian pass (odd; [`GAUSSIAN_TAPS`] by default).
    pub taps: usize,
}

impl MethodInputs for Inputs {
    /// With `bake`, the look's Gaussians ([`gaussian_terms`]: a fit for
    /// any profile but a Gaussian sum, about a second); none otherwise.
    fn new(look: &Look<'_>, bake: bool) -> Result<Self, ModelError> {
        let mut inputs = Self {
            gaussians: Vec::new(),
            taps: look.options.gaussians.taps,
        };
        if bake {
            inputs.set(&terms_for(look.spec, look.profile)?);
        }
        Ok(inputs)
    }

    fn missing(&self) -> Option<&'static str> {
        self.gaussians.is_empty().then_some("the Gaussians")
    }

    /// Its one configuration: the look's Gaussians.
    fn bench(&mut self, look: &Look<'_>, _: &Knob) -> Result<(), ModelError> {
        self.set(&terms_for(look.spec, look.profile)?);
        Ok(())
    }

    fn fingerprint_into(&self, h: &mut impl std::hash::Hasher) {
        h.write(bytemuck::cast_slice(&[self.taps as u64]));
        for (sigma, w) in &self.gaussians {
            h.write(bytemuck::bytes_of(sigma));
            h.write(bytemuck::cast_slice(w));
        }
    }
}

impl Inputs {
    /// Sets the Gaussians from (variance mm², RGB weight) terms; weights
    /// are normalised per channel (the albedo is applied separately).
    pub fn set(&mut self, terms: &[(f64, [f64; 3])]) {
        let sum = [0, 1, 2].map(|c| terms.iter().map(|t| t.1[c]).sum::<f64>());
        self.gaussians = terms
            .iter()
            .map(|(v, w)| {
                (
                    v.sqrt() as f32,
                    [0, 1, 2].map(|c| {
                        if sum[c] > 0.0 {
                            (w[c] / sum[c]) as f32
                        } else {
                            0.0
                        }
                    }),
                )
            })
            .collect();
    }
}

/// The Gaussians `gaussians` blurs with for the look `spec`: a Gaussian-sum
/// look's own terms, else six Gaussians fitted to `profile`; each term is
/// (variance mm², RGB weight).
pub fn gaussian_terms(
    spec: &crate::settings::ProfileSpec,
    profile: &dyn RadialProfile,
) -> Result<Vec<(f64, crate::model::Rgb)>, ModelError> {
    terms_for(Some(spec), profile)
}

/// [`gaussian_terms`], or with no look the six fitted to `profile`.
fn terms_for(
    spec: Option<&crate::settings::ProfileSpec>,
    profile: &dyn RadialProfile,
) -> Result<Vec<(f64, crate::model::Rgb)>, ModelError> {
    use crate::settings::ProfileSpec;
    Ok(match spec {
        Some(ProfileSpec::Gaussians(g)) => {
            let mut terms: Vec<(f64, crate::model::Rgb)> = g
                .gaussians
                .iter()
                .map(|t| (t.variance_mm2, t.weights))
                .collect();
            // Its Dirac share (a Godot import's unblurred light), as below.
            if g.dirac.iter().any(|d| *d > 0.0) {
                terms.push((DIRAC_VARIANCE_MM2, g.dirac));
            }
            terms
        }
        _ => {
            let m = crate::model::fit::fit_gaussians(profile, 6)?.model;
            let mut terms: Vec<(f64, crate::model::Rgb)> = (0..m.channel_terms(0).len())
                .map(|k| {
                    (
                        m.channel_terms(0)[k].variance_mm2,
                        [0, 1, 2].map(|c| m.channel_terms(c)[k].weight),
                    )
                })
                .collect();
            // A Dirac weight (Jimenez 2012's 1 − strength) as a Gaussian
            // narrower than any pixel: its taps all read the centre.
            let dirac = m.dirac_weight();
            if dirac.iter().any(|d| *d > 0.0) {
                terms.push((DIRAC_VARIANCE_MM2, dirac));
            }
            terms
        }
    })
}

/// The variance (mm²) of the Gaussian that stands for a Dirac weight in
/// `gaussians`: σ = 0.1 µm, under a pixel at any distance the renderer
/// frames.
pub const DIRAC_VARIANCE_MM2: f64 = 1e-8;

/// Default taps per 1D Gaussian pass of the `gaussians` method: d'Eon
/// 2007's seven. Finer kernels follow a lit edge more closely in screen
/// space, where a Gaussian can span many pixels (worst deviation on
/// tests/render_physics.rs's edge, R/G/B: 0.127/0.071/0.042 with 7 taps,
/// 0.054/0.015/0.006 with 13) at about twice the pass time on lavapipe.
pub const GAUSSIAN_TAPS: usize = 7;

/// A 1D kernel for a Gaussian of standard deviation σ (mm) with `n` (odd,
/// ≥ 3) taps at offsets kh, h = 6σ/(n − 1), over ±3σ: each weight is the
/// Gaussian's mass over [k − ½, k + ½]h, the outer taps taking the tails,
/// so the weights sum to one. n = 7 is d'Eon 2007's kernel (GPU Gems 3
/// ch. 14). Centre first.
pub fn gaussian_taps(sigma_mm: f32, n: usize) -> Vec<GpuTap> {
    let m = (n.max(3) / 2) as i32;
    let h = 3.0 / m as f64;
    let phi = |x: f64| 0.5 * (1.0 + libm::erf(x / std::f64::consts::SQRT_2));
    let mass = |k: i32| {
        let lo = if k == -m {
            f64::NEG_INFINITY
        } else {
            (k as f64 - 0.5) * h
        };
        let hi = if k == m {
            f64::INFINITY
        } else {
            (k as f64 + 0.5) * h
        };
        (phi(hi) - phi(lo)) as f32
    };
    std::iter::once(0)
        .chain((-m..=m).filter(|k| *k != 0))
        .map(|k| {
            let w = mass(k);
            GpuTap {
                weight_offset: [w, w, w, (k as f64 * h) as f32 * sigma_mm],
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// GPU Gems 3 ch. 14 (d'Eon & Luebke 2007) prints the seven weights
    /// 0.006, 0.061, 0.242, 0.382, 0.242, 0.061, 0.006 at offsets −3σ…3σ.
    #[test]
    fn seven_gaussian_taps_are_deons_published_kernel() {
        let taps = gaussian_taps(2.0, 7);
        let mut by_offset: Vec<(f32, f32)> = taps
            .iter()
            .map(|t| (t.weight_offset[3], t.weight_offset[0]))
            .collect();
        by_offset.sort_by(|a, b| a.0.total_cmp(&b.0));
        let published = [0.006, 0.061, 0.242, 0.382, 0.242, 0.061, 0.006];
        for ((offset, w), (k, p)) in by_offset.iter().zip((-3..=3).zip(published)) {
            assert!((offset - 2.0 * k as f32).abs() < 1e-6);
            // Printed to three decimals and rounded to sum to one.
            assert!((w - p).abs() < 1.5e-3, "offset {offset}: {w} vs {p}");
        }
        assert_eq!(taps[0].weight_offset[3], 0.0, "centre first");
    }

    /// Any tap count: weights sum to one, offsets span ±3σ, and the
    /// kernel's variance approaches σ² as the taps get finer.
    #[test]
    fn gaussian_taps_sum_to_one_and_converge_to_the_variance() {
        for n in [3, 7, 13, 31] {
            let taps = gaussian_taps(1.5, n);
            assert_eq!(taps.len(), n);
            let sum: f32 = taps.iter().map(|t| t.weight_offset[0]).sum();
            assert!((sum - 1.0).abs() < 1e-6, "{n}: {sum}");
            let max = taps
                .iter()
                .map(|t| t.weight_offset[3].abs())
                .fold(0.0, f32::max);
            assert!((max - 4.5).abs() < 1e-5, "{n}: {max}");
        }
        let var = |n| {
            gaussian_taps(1.0, n)
                .iter()
                .map(|t| t.weight_offset[0] * t.weight_offset[3].powi(2))
                .sum::<f32>()
        };
        assert!((var(31) - 1.0).abs() < (var(7) - 1.0).abs());
        assert!((var(31) - 1.0).abs() < 0.02, "{}", var(31));
    }
}
