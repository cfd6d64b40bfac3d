//! Per-profile GPU inputs: sample patterns, tables and taps, computed on
//! the CPU from the profile core and rebuilt only when the profile or the
//! counts change.

use super::gpu_types::{GpuSample, GpuTap};
use super::settings::BurleySampling;
use super::sss::Reads;
use crate::model::sampling::{AngleSequence, SamplePattern};
use crate::model::separable::SeparableKernel;
use crate::model::{ModelError, RadialProfile, Rgb};

/// Per-profile GPU inputs, computed on the CPU and rebuilt only when the
/// profile or the counts change.
/// Base colour for kernels without a colour (see [`ProfileInputs::for_look`]).
pub const KERNEL_SURFACE_ALBEDO: [f32; 3] = [0.91058, 0.338275, 0.2718];

#[derive(Debug, Clone)]
pub struct ProfileInputs {
    pub samples: Vec<GpuSample>,
    /// The profile as the ground truth (`reference`) integrates it.
    pub ground_truth: std::sync::Arc<super::ground_truth::ProfileTable>,
    /// The short pattern the Burley LOD uses for 1–4 px disks.
    pub low_samples: Vec<GpuSample>,
    /// The widest channel's 0.997-energy radius (mm): the LOD's disk size.
    pub filter_radius_mm: f32,
    /// False when no channel scatters (e.g. Jimenez strength 0): SSS passes are skipped.
    pub scatters: bool,
    /// Normalised thin-slab transmittance T(d)/total at d = range·i/63.
    pub transmittance: Vec<[f32; 4]>,
    pub transmittance_range_mm: f32,
    /// Penner's table as FaceWorks stores it, D(θ, κ) − saturate(cos θ)
    /// (row-major, 64×64), and its layout. The shader adds saturate(N·L)
    /// back, so clamping to the edge texels (N·L = ±0.984) costs nothing
    /// at N·L = ±1.
    pub preintegrated_lut: Vec<[f32; 4]>,
    pub lut_layout: crate::model::lut::LutLayout,
    /// Penner's penumbra table (row-major) and its layout.
    pub penumbra_lut: Vec<[f32; 4]>,
    pub penumbra_layout: crate::model::lut::ShadowLayout,
    /// Per channel, how far `preintegrated` bends the detail normal back to
    /// the smooth one: r/(r + 1 mm) for the channel's 0.997-energy radius r
    /// (Penner 2011's per-channel normals; wide red light ignores pores).
    pub normal_blend: [f32; 3],
    /// The look's colour: its total diffuse reflectance ∫2πr R(r) dr per
    /// channel (Burley's A), clamped to [0, 1]. The scattering kernels are
    /// energy-normalised, as in the engines, so this is where the look's
    /// colour enters: the base colour of a surface whose map only
    /// modulates (the default head), while a colour map of the artist's
    /// own is the albedo (HDRP, Unreal, Cycles: the material's base colour,
    /// the profile normalised).
    pub surface_albedo: [f32; 3],
    /// (σ mm, normalised RGB weight) of each Gaussian for the `gaussians`
    /// method; empty until [`ProfileInputs::set_gaussians`].
    pub gaussians: Vec<(f32, [f32; 3])>,
    /// Taps of each 1D Gaussian pass (odd; [`GAUSSIAN_TAPS`] by default).
    pub gaussian_taps: usize,
    pub lut: Vec<[f32; 4]>,
    pub lut_radius_mm: f32,
    pub taps: Vec<GpuTap>,
    /// How `separable` follows the surface across depth: σ (mm) of Jimenez
    /// 2015 eq. 7's depth weight e^(−Δz²/2σ²) for the pre-integrated kernel
    /// (its widest channel's RMS width), or 0 for the Jimenez 2012 demo
    /// kernel's lerp towards the centre.
    pub separable_depth_sigma_mm: f32,
    /// How `burley` samples (the pattern here, the rest in the shader).
    pub burley_sampling: BurleySampling,
    /// Which of the method-specific tables hold the profile (the others
    /// are neutral placeholders of the same sizes; the Gaussians are
    /// set afterwards, [`ProfileInputs::set_gaussians`]).
    baked: Reads,
}

pub(super) const LUT_SIZE: usize = 256;

impl ProfileInputs {
    /// Everything `method` needs for the look `spec` (built as `profile`):
    /// a Jimenez 2012 look keeps the demo's kernel for `separable`, any
    /// other profile uses the importance-sampled pre-integrated kernel
    /// (Jimenez 2015 §4, §7); `gaussians` uses a Gaussian-sum look as it is
    /// and fits six Gaussians to any other.
    /// The colour under a look that is only a blur kernel (Jimenez 2012,
    /// the artist two-Gaussian model): the default skin's albedo A
    /// (presets/skin_default.ron, Unreal's default SurfaceAlbedo).
    pub fn for_look(
        spec: &crate::settings::ProfileSpec,
        profile: &dyn RadialProfile,
        method: super::Method,
        (samples, taps): (usize, usize),
        gaussian_taps: usize,
    ) -> Result<Self, ModelError> {
        let mut inputs = Self::new(profile, samples, taps)?;
        inputs.finish_look(spec, profile, method, taps, gaussian_taps)?;
        Ok(inputs)
    }

    /// What a look adds to a profile's inputs: the surface colour of
    /// colourless kernels, Jimenez 2012's own kernel, the Gaussians.
    fn finish_look(
        &mut self,
        spec: &crate::settings::ProfileSpec,
        profile: &dyn RadialProfile,
        method: super::Method,
        taps: usize,
        gaussian_taps: usize,
    ) -> Result<(), ModelError> {
        use crate::settings::ProfileSpec;
        let inputs = self;
        inputs.surface_albedo = look_colour(spec, profile);
        if let ProfileSpec::Jimenez2012(j) = spec {
            inputs.set_separable_kernel(
                &crate::model::jimenez::Jimenez2012::new(j.strength, j.falloff)?.kernel(taps)?,
                true,
            );
        }
        if method.sss().reads.gaussians {
            inputs.set_gaussians(&gaussian_terms(spec, profile)?);
            inputs.gaussian_taps = gaussian_taps;
        }
        Ok(())
    }

    /// As [`ProfileInputs::for_look`], baking only the tables `method`
    /// reads: the importance-sampled separable kernel (about 45 ms for the
    /// default skin) for `separable`, the pre-integrated and penumbra tables
    /// (25 ms) for `preintegrated`. The others hold neutral placeholders of
    /// the same sizes, so these inputs must not render another method. The
    /// editor's live viewport uses it: a dragged slider rebuilds the inputs
    /// every frame.
    pub fn for_method(
        spec: &crate::settings::ProfileSpec,
        profile: &dyn RadialProfile,
        method: super::Method,
        (samples, taps): (usize, usize),
        gaussian_taps: usize,
    ) -> Result<Self, ModelError> {
        let mut inputs = Self::with_tables(profile, samples, taps, method.sss().reads)?;
        inputs.finish_look(spec, profile, method, taps, gaussian_taps)?;
        Ok(inputs)
    }

    /// Burley disk samples, the r·R_N(r) table and separable taps for `profile`.
    pub fn new(
        profile: &dyn RadialProfile,
        samples: usize,
        taps: usize,
    ) -> Result<Self, ModelError> {
        Self::with_tables(
            profile,
            samples,
            taps,
            Reads {
                separable_kernel: true,
                penner_tables: true,
                gaussians: false,
            },
        )
    }

    fn with_tables(
        profile: &dyn RadialProfile,
        samples: usize,
        taps: usize,
        tables: Reads,
    ) -> Result<Self, ModelError> {
        let sampling = BurleySampling::default();
        let (gpu_samples, low_samples) = burley_patterns(profile, samples, sampling)?;
        let total = profile.total_reflectance();
        let filter_radius_mm = profile
            .radius_for_energy(crate::model::DEFAULT_ENERGY_FRACTION)
            .into_iter()
            .fold(0.0, f64::max) as f32;
        let ground_truth = std::sync::Arc::new(super::ground_truth::ProfileTable::new(profile));
        let r_max = profile
            .radius_for_energy(0.999)
            .into_iter()
            .fold(1e-6, f64::max);
        let lut = profile_lut(profile, r_max, total);
        let (taps, separable_depth_sigma_mm) = if tables.separable_kernel {
            let kernel = SeparableKernel::importance_sampled(profile, taps)?;
            (gpu_taps(&kernel), rms_width_mm(&kernel))
        } else {
            // One tap of weight 1 at the centre: the identity blur.
            (
                vec![GpuTap {
                    weight_offset: [1.0, 1.0, 1.0, 0.0],
                }],
                0.0,
            )
        };
        let lut_layout = crate::model::lut::LutLayout {
            width: 64,
            height: 64,
            curvature_radius_min_mm: 2.0,
            curvature_radius_max_mm: 200.0,
        };
        let penumbra_layout = crate::model::lut::ShadowLayout::default();
        let (preintegrated_lut, penumbra_lut) =
            penner_tables(profile, tables.penner_tables, lut_layout, penumbra_layout)?;
        let radii = profile.radius_for_energy(crate::model::DEFAULT_ENERGY_FRACTION);
        let normal_blend = radii.map(|r| (r / (r + 1.0)) as f32);
        let transmittance_range_mm = r_max as f32;
        let transmittance = transmittance_table(profile, r_max, total);
        let dirac = profile.dirac_weight();
        let scatters = (0..3).any(|c| total[c] - dirac[c] > 1e-9 * total[c].max(1e-300));
        Ok(Self {
            low_samples,
            filter_radius_mm,
            scatters,
            samples: gpu_samples,
            ground_truth,
            transmittance,
            transmittance_range_mm,
            preintegrated_lut,
            lut_layout,
            penumbra_lut,
            penumbra_layout,
            normal_blend,
            surface_albedo: total.map(|t| t.clamp(0.0, 1.0) as f32),
            gaussians: Vec::new(),
            gaussian_taps: GAUSSIAN_TAPS,
            lut,
            lut_radius_mm: r_max as f32,
            taps,
            separable_depth_sigma_mm,
            burley_sampling: sampling,
            baked: tables,
        })
    }

    /// Why these inputs cannot render `method` (the table it reads holds a
    /// placeholder), or `None` when they can: B of a comparison drawn with
    /// A's inputs drew `gaussians` as `none` and said nothing (issue 22).
    pub fn missing_for(&self, method: super::Method) -> Option<&'static str> {
        let reads = method.sss().reads;
        if reads.separable_kernel && !self.baked.separable_kernel {
            Some("the separable kernel's taps")
        } else if reads.penner_tables && !self.baked.penner_tables {
            Some("Penner's pre-integrated and penumbra tables")
        } else if reads.gaussians && self.gaussians.is_empty() {
            Some("the Gaussians")
        } else {
            None
        }
    }

    /// Rebuilds the `burley` patterns for another count or sampling strategy.
    pub fn set_burley(
        &mut self,
        profile: &dyn RadialProfile,
        samples: usize,
        sampling: BurleySampling,
    ) -> Result<(), ModelError> {
        (self.samples, self.low_samples) = burley_patterns(profile, samples, sampling)?;
        self.burley_sampling = sampling;
        Ok(())
    }
}

/// The colour a look gives the surface (`ProfileInputs::surface_albedo`):
/// its profile's total reflectance, clamped to [0, 1]; kernels without a
/// colour of their own (energy-conserving blurs, total 1: Jimenez 2012,
/// the artist model) leave it to the surface, as in the engines, and the
/// default skin's albedo stands in for a colour map.
pub fn look_colour(spec: &crate::settings::ProfileSpec, profile: &dyn RadialProfile) -> [f32; 3] {
    use crate::settings::ProfileSpec;
    if matches!(spec, ProfileSpec::Jimenez2012(_) | ProfileSpec::Artist(_)) {
        return KERNEL_SURFACE_ALBEDO;
    }
    profile
        .total_reflectance()
        .map(|t| t.clamp(0.0, 1.0) as f32)
}

/// The Gaussians `gaussians` blurs with for the look `spec`: a Gaussian-sum
/// look's own terms, else six Gaussians fitted to `profile`; each term is
/// (variance mm², RGB weight).
pub fn gaussian_terms(
    spec: &crate::settings::ProfileSpec,
    profile: &dyn RadialProfile,
) -> Result<Vec<(f64, crate::model::Rgb)>, ModelError> {
    use crate::settings::ProfileSpec;
    Ok(match spec {
        ProfileSpec::Gaussians(g) => {
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

/// The full and the short (LOD) `burley` pattern: Golubev 2018's quantiles
/// of the widest channel, in antithetic pairs, or MIS across the channels.
fn burley_patterns(
    profile: &dyn RadialProfile,
    samples: usize,
    sampling: BurleySampling,
) -> Result<(Vec<GpuSample>, Vec<GpuSample>), ModelError> {
    let pattern = |n| {
        if sampling.antithetic {
            SamplePattern::new_antithetic(profile, n, AngleSequence::GoldenAngle)
        } else if sampling.mis {
            SamplePattern::new_mis(profile, n, AngleSequence::GoldenAngle)
        } else {
            SamplePattern::new(profile, n, AngleSequence::GoldenAngle)
        }
    };
    // The shader weighs a sample by R(ρ)/q(r): inv_pdf = 1/q.
    let gpu = |p: SamplePattern| -> Vec<GpuSample> {
        p.samples
            .iter()
            .map(|s| GpuSample {
                radius_mm: s.radius_mm as f32,
                angle: s.angle_rad as f32,
                inv_pdf: if s.density_per_mm2 > 0.0 {
                    (1.0 / s.density_per_mm2) as f32
                } else {
                    0.0
                },
                pad: 0.0,
            })
            .collect()
    };
    Ok((
        gpu(pattern(samples)?),
        gpu(pattern((samples / 3).clamp(5, samples.max(5)))?),
    ))
}

/// The RMS width √(Σ w x² / Σ w) (mm) of a 1D kernel's widest channel:
/// the σ of Jimenez 2015 eq. 7's depth weight (σ_max, the widest Gaussian
/// of their two-Gaussian kernel; for any other kernel, its spread).
fn rms_width_mm(kernel: &SeparableKernel) -> f32 {
    (0..3)
        .map(|c| {
            let (m2, w) = kernel.taps.iter().fold((0.0f64, 0.0f64), |(m2, w), t| {
                (
                    m2 + t.weight[c] * t.offset_mm * t.offset_mm,
                    w + t.weight[c],
                )
            });
            if w > 0.0 {
                (m2 / w).sqrt()
            } else {
                0.0
            }
        })
        .fold(0.0f64, f64::max) as f32
}

impl ProfileInputs {
    /// A hash of everything the GPU receives from these inputs: the renderer
    /// re-uploads tables, patterns and kernels only when it changes.
    pub fn fingerprint(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        let mut bytes = |b: &[u8]| b.hash(&mut h);
        bytes(bytemuck::cast_slice(&self.samples));
        bytes(&self.ground_truth.fingerprint().to_le_bytes());
        bytes(bytemuck::cast_slice(&self.low_samples));
        bytes(bytemuck::cast_slice(&self.transmittance));
        bytes(bytemuck::cast_slice(&self.preintegrated_lut));
        bytes(bytemuck::cast_slice(&self.penumbra_lut));
        bytes(bytemuck::cast_slice(&self.normal_blend));
        bytes(bytemuck::cast_slice(&[
            self.penumbra_layout.penumbra_min_mm,
            self.penumbra_layout.penumbra_max_mm,
        ]));
        bytes(bytemuck::cast_slice(&[
            self.penumbra_layout.width as u64,
            self.penumbra_layout.height as u64,
        ]));
        bytes(bytemuck::cast_slice(&self.lut));
        bytes(bytemuck::cast_slice(&self.taps));
        bytes(bytemuck::bytes_of(&self.separable_depth_sigma_mm));
        bytes(bytemuck::cast_slice(&[self.gaussian_taps as u64]));
        let b = self.burley_sampling;
        bytes(&[b.shader_flags() as u8, b.mis as u8, b.antithetic as u8]);
        for (sigma, w) in &self.gaussians {
            bytes(bytemuck::bytes_of(sigma));
            bytes(bytemuck::cast_slice(w));
        }
        bytes(bytemuck::cast_slice(&[
            self.filter_radius_mm,
            self.transmittance_range_mm,
            self.lut_radius_mm,
        ]));
        self.scatters.hash(&mut h);
        (self.lut_layout.width, self.lut_layout.height).hash(&mut h);
        self.lut_layout
            .curvature_radius_min_mm
            .to_bits()
            .hash(&mut h);
        self.lut_layout
            .curvature_radius_max_mm
            .to_bits()
            .hash(&mut h);
        h.finish()
    }

    /// Replaces the separable taps (e.g. with the Jimenez 2012 demo kernel
    /// of a Jimenez 2012 profile instead of the pre-integrated one):
    /// `demo_2012` keeps the demo's follow-surface lerp, otherwise the depth
    /// weight's σ is the kernel's RMS width.
    pub fn set_separable_kernel(&mut self, kernel: &SeparableKernel, demo_2012: bool) {
        self.baked.separable_kernel = true;
        self.taps = gpu_taps(kernel);
        self.separable_depth_sigma_mm = if demo_2012 { 0.0 } else { rms_width_mm(kernel) };
    }

    /// Sets the Gaussians of the `gaussians` method from (variance mm²,
    /// RGB weight) terms; weights are normalised per channel (the albedo is
    /// applied separately).
    pub fn set_gaussians(&mut self, terms: &[(f64, [f64; 3])]) {
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

/// A separable kernel's taps as the GPU reads them: rgb weight, offset (mm).
fn gpu_taps(kernel: &SeparableKernel) -> Vec<GpuTap> {
    kernel
        .taps
        .iter()
        .map(|t| GpuTap {
            weight_offset: [
                t.weight[0] as f32,
                t.weight[1] as f32,
                t.weight[2] as f32,
                t.offset_mm as f32,
            ],
        })
        .collect()
}

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

/// Rows of RGBA texels or entries, as uploaded.
type RgbaTable = Vec<[f32; 4]>;

/// r·R(r)/total per channel at r = r_max·t², t = i/(LUT_SIZE − 1), then
/// the CDF at the same radii (Burley's weights and centre weight;
/// `shaders/sss_burley.wgsl` reads both halves).
fn profile_lut(profile: &dyn RadialProfile, r_max: f64, total: Rgb) -> RgbaTable {
    (0..LUT_SIZE)
        .map(|i| {
            let t = i as f64 / (LUT_SIZE - 1) as f64;
            let rr = profile.r_reflectance(r_max * t * t);
            let n = |c: usize| {
                if total[c] > 0.0 {
                    (rr[c] / total[c]) as f32
                } else {
                    0.0
                }
            };
            [n(0), n(1), n(2), 0.0]
        })
        // Then the CDF at the same radii (Burley's centre weight).
        .chain((0..LUT_SIZE).map(|i| {
            let t = i as f64 / (LUT_SIZE - 1) as f64;
            let c = profile.cdf(r_max * t * t);
            [c[0] as f32, c[1] as f32, c[2] as f32, 0.0]
        }))
        .collect()
}

/// Penner's D(θ, κ) − saturate(N·L) table and scattered-shadow table, or
/// zeros when `bake` is off (a method that never reads them).
fn penner_tables(
    profile: &dyn RadialProfile,
    bake: bool,
    lut_layout: crate::model::lut::LutLayout,
    penumbra_layout: crate::model::lut::ShadowLayout,
) -> Result<(RgbaTable, RgbaTable), ModelError> {
    Ok(if bake {
        let d = crate::model::lut::Lut::bake(profile, lut_layout)?
            .d
            .iter()
            .enumerate()
            .map(|(k, v)| {
                let lit = lut_layout.n_dot_l(k % lut_layout.width).max(0.0);
                [0, 1, 2].map(|c| (v[c] - lit) as f32)
            })
            .map(|d| [d[0], d[1], d[2], 1.0])
            .collect();
        let penumbra = crate::model::lut::bake_shadow(profile, penumbra_layout)?
            .iter()
            .map(|v| [v[0] as f32, v[1] as f32, v[2] as f32, 1.0])
            .collect();
        (d, penumbra)
    } else {
        // Zero: D(θ, κ) − saturate(N·L) of a profile that does not
        // scatter, and an unscattered shadow; never read by the others.
        (
            vec![[0.0, 0.0, 0.0, 1.0]; lut_layout.width * lut_layout.height],
            vec![[0.0, 0.0, 0.0, 1.0]; penumbra_layout.width * penumbra_layout.height],
        )
    })
}

/// The thin-slab transmittance T(d)/total per channel at 64 thicknesses
/// d = r_max·i/63 (`shaders/scene.wgsl` `transmittance_at`).
fn transmittance_table(profile: &dyn RadialProfile, r_max: f64, total: Rgb) -> RgbaTable {
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
