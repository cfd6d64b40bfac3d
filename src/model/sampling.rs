//! Disk sample patterns for the screen-space Burley method (Golubev 2018,
//! Golubev 2018 "Sampling the Diffusion Profile"): radii by the inverse CDF of
//! the channel with the longest scattering distance at ξᵢ = (i + ½)/N,
//! angles by the golden angle (Fibonacci) or the Hammersley radical
//! inverse, and per-channel weights R_c(r)/pdf(r) so that
//! Σᵢ wᵢ·L(xᵢ) estimates ∫R_c(|x|)L(x) dA over the continuous part
//! (Σᵢ w_c,i → A_c minus any Dirac weight, which the pass takes from the
//! centre pixel).

use super::{check_range, rgb_map, ModelError, RadialProfile, Rgb, DEFAULT_ENERGY_FRACTION};
use std::f64::consts::PI;

/// Allowed sample counts.
pub const SAMPLES_RANGE: (usize, usize) = (1, 4096);

/// 1/φ, the golden ratio's reciprocal (Unity HDRP `Golden2dSeq`).
const INV_GOLDEN_RATIO: f64 = 0.618_033_988_749_894_9;

/// How sample angles are generated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AngleSequence {
    /// θᵢ = 2π·frac(i/φ): the Fibonacci/golden-angle spiral (Golubev 2018).
    GoldenAngle,
    /// θᵢ = 2π·Φ₂(i), the base-2 radical inverse (Hammersley).
    Hammersley,
}

impl AngleSequence {
    pub fn id(self) -> &'static str {
        match self {
            AngleSequence::GoldenAngle => "golden-angle",
            AngleSequence::Hammersley => "hammersley",
        }
    }
}

/// One disk sample: radius (mm), angle (radians) and per-channel weight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiskSample {
    pub radius_mm: f64,
    pub angle_rad: f64,
    pub weight: Rgb,
    /// The planar density (mm⁻²) the radius was drawn from: R_dom(r)/A_dom
    /// for one channel, the mixture Σ_c (n_c/N)·R_c(r)/A_c under MIS.
    pub density_per_mm2: f64,
}

/// A precomputed sample pattern.
#[derive(Debug, Clone, PartialEq)]
pub struct SamplePattern {
    pub samples: Vec<DiskSample>,
    /// The channel whose CDF placed the radii (under MIS: the widest, which
    /// also places the first sample of every three).
    pub sampled_channel: usize,
    pub angles: AngleSequence,
}

/// θᵢ of sample `i` of `angles`.
fn angle(angles: AngleSequence, i: usize) -> f64 {
    2.0 * PI
        * match angles {
            AngleSequence::GoldenAngle => (i as f64 * INV_GOLDEN_RATIO).fract(),
            AngleSequence::Hammersley => radical_inverse_base2(i as u32),
        }
}

/// The quantile of the continuous part of channel `c` at ξ ∈ (0, 1): a
/// Dirac weight at r = 0 (Jimenez 2012's 1 − strength) is not sampled
/// (the pass keeps that share of the centre pixel itself, per channel:
/// `fs_burley`'s centre weight); ξ covers the CDF from the Dirac's share up.
fn continuous_quantile(profile: &dyn RadialProfile, c: usize, xi: f64) -> f64 {
    let dirac = profile.cdf(0.0)[c].clamp(0.0, 1.0);
    profile.inverse_cdf(c, dirac + (1.0 - dirac) * xi)
}

/// One of N samples at the quantile ξ of channel `dom`'s continuous part,
/// weighted w_c = R_c(r)/(N·q(r)) with q = R_dom(r)/(A_dom − D_dom), the
/// planar density (D the Dirac weight), so that Σ w_c → A_c − D_c.
fn quantile_sample(
    profile: &dyn RadialProfile,
    dom: usize,
    n: usize,
    xi: f64,
    angle_rad: f64,
) -> DiskSample {
    let total = profile.total_reflectance();
    let continuous = (total[dom] - profile.dirac_weight()[dom]).max(0.0);
    let r = continuous_quantile(profile, dom, xi);
    let rr = profile.r_reflectance(r);
    let weight = rgb_map(|c| {
        if rr[dom] > 0.0 {
            continuous * rr[c] / (n as f64 * rr[dom])
        } else {
            0.0
        }
    });
    let density_per_mm2 = if continuous > 0.0 {
        profile.reflectance(r)[dom] / continuous
    } else {
        0.0
    };
    DiskSample {
        radius_mm: r,
        angle_rad,
        weight,
        density_per_mm2,
    }
}

/// The channel with the largest 0.997-energy radius.
pub fn widest_channel(profile: &dyn RadialProfile) -> usize {
    let widest = profile.radius_for_energy(DEFAULT_ENERGY_FRACTION);
    (0..3)
        .max_by(|&a, &b| widest[a].total_cmp(&widest[b]))
        .unwrap_or(0)
}

impl SamplePattern {
    /// Golubev 2018's pattern for `profile` with `n` samples.
    pub fn new(
        profile: &dyn RadialProfile,
        n: usize,
        angles: AngleSequence,
    ) -> Result<Self, ModelError> {
        check_samples(n)?;
        let dom = widest_channel(profile);
        let samples = (0..n)
            .map(|i| {
                quantile_sample(
                    profile,
                    dom,
                    n,
                    (i as f64 + 0.5) / n as f64,
                    angle(angles, i),
                )
            })
            .collect();
        Ok(Self {
            samples,
            sampled_channel: dom,
            angles,
        })
    }

    /// Golubev's quantile radii in point-symmetric (antithetic) pairs: the
    /// N strata are paired, each pair shares the radius at the quantile
    /// between its two strata and takes angles θ_k and θ_k + π (θ_k by the
    /// sequence); an odd N keeps the innermost stratum single (its radius,
    /// the 1/(2N) quantile, is mostly inside the centre pixel). The pairs'
    /// odd moments vanish, so the linear part of the irradiance around a
    /// pixel cancels exactly in each pair instead of turning into noise
    /// under the per-pixel rotation (antithetic variates; Hammersley
    /// & Morton 1956). Weights as in [`SamplePattern::new`].
    pub fn new_antithetic(
        profile: &dyn RadialProfile,
        n: usize,
        angles: AngleSequence,
    ) -> Result<Self, ModelError> {
        check_samples(n)?;
        let dom = widest_channel(profile);
        let sample = |xi: f64, angle_rad: f64| quantile_sample(profile, dom, n, xi, angle_rad);
        let first = n % 2;
        let mut samples = Vec::with_capacity(n);
        if first == 1 {
            samples.push(sample(0.5 / n as f64, angle(angles, 0)));
        }
        for k in 0..n / 2 {
            let xi = (first + 2 * k + 1) as f64 / n as f64;
            let theta = angle(angles, k + first);
            samples.push(sample(xi, theta));
            samples.push(sample(xi, theta + PI));
        }
        Ok(Self {
            samples,
            sampled_channel: dom,
            angles,
        })
    }

    /// Multiple importance sampling across the channels (one-sample model,
    /// balance heuristic; Veach 1997 §9.2): sample i draws its radius from
    /// the CDF of channel (widest + i) mod 3 at that channel's stratum
    /// (k + ½)/n_c, and every sample is weighted by the mixture density
    /// q(r) = Σ_c (n_c/N)·R_c(r)/A_c, so narrow channels get samples where
    /// their energy is instead of the widest channel's quantiles alone.
    /// Channels with no energy are left out of the mixture.
    pub fn new_mis(
        profile: &dyn RadialProfile,
        n: usize,
        angles: AngleSequence,
    ) -> Result<Self, ModelError> {
        check_samples(n)?;
        let dom = widest_channel(profile);
        let total = profile.total_reflectance();
        let lit: Vec<usize> = (0..3)
            .map(|k| (dom + k) % 3)
            .filter(|&c| total[c] > 0.0)
            .collect();
        if lit.is_empty() {
            return Self::new(profile, n, angles);
        }
        // Sample i belongs to channel lit[i mod m], stratum i div m.
        let m = lit.len();
        let count = |j: usize| (n + m - 1 - j) / m;
        // Each channel's continuous part (a Dirac weight is not sampled).
        let dirac = profile.dirac_weight();
        let density = |r: f64| -> f64 {
            let v = profile.reflectance(r);
            lit.iter()
                .enumerate()
                .map(|(j, &c)| {
                    count(j) as f64 / n as f64 * v[c] / (total[c] - dirac[c]).max(1e-300)
                })
                .sum()
        };
        let samples = (0..n)
            .map(|i| {
                let (j, k) = (i % m, i / m);
                let r = continuous_quantile(profile, lit[j], (k as f64 + 0.5) / count(j) as f64);
                let q = density(r);
                let v = profile.reflectance(r);
                let weight = rgb_map(|c| if q > 0.0 { v[c] / (n as f64 * q) } else { 0.0 });
                DiskSample {
                    radius_mm: r,
                    angle_rad: angle(angles, i),
                    weight,
                    density_per_mm2: q,
                }
            })
            .collect();
        Ok(Self {
            samples,
            sampled_channel: dom,
            angles,
        })
    }

    /// Σᵢ w_c,i per channel: the estimate of the total reflectance.
    pub fn weight_sum(&self) -> Rgb {
        rgb_map(|c| self.samples.iter().map(|s| s.weight[c]).sum())
    }
}

fn check_samples(n: usize) -> Result<(), ModelError> {
    check_range(
        "samples",
        n as f64,
        SAMPLES_RANGE.0 as f64,
        SAMPLES_RANGE.1 as f64,
        "",
    )
    .map(|_| ())
}

/// Van der Corput radical inverse in base 2.
pub fn radical_inverse_base2(i: u32) -> f64 {
    i.reverse_bits() as f64 / 4_294_967_296.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::burley::Burley;

    #[test]
    fn weights_estimate_the_albedo() {
        let b = Burley::from_scattering_distance([0.9, 0.5, 0.3], [1.0, 0.4, 0.2]).unwrap();
        let p = SamplePattern::new(&b, 4096, AngleSequence::GoldenAngle).unwrap();
        assert_eq!(p.sampled_channel, 0);
        let s = p.weight_sum();
        for c in 0..3 {
            assert!((s[c] - b.albedo()[c]).abs() < 2e-3, "{s:?}");
        }
        // Sampled channel: every weight is exactly A/N.
        assert!(p
            .samples
            .iter()
            .all(|x| (x.weight[0] - 0.9 / 4096.0).abs() < 1e-15));
    }

    #[test]
    fn radii_are_the_quantiles_and_angles_follow_the_sequences() {
        let b = Burley::from_scattering_distance([1.0; 3], [0.5, 1.0, 0.2]).unwrap();
        let p = SamplePattern::new(&b, 21, AngleSequence::Hammersley).unwrap();
        assert_eq!(p.sampled_channel, 1);
        for (i, s) in p.samples.iter().enumerate() {
            let cdf = b.cdf(s.radius_mm)[1];
            assert!((cdf - (i as f64 + 0.5) / 21.0).abs() < 1e-12);
            assert!((s.angle_rad - 2.0 * PI * radical_inverse_base2(i as u32)).abs() < 1e-15);
        }
        assert_eq!(radical_inverse_base2(1), 0.5);
        assert_eq!(radical_inverse_base2(3), 0.75);
        let g = SamplePattern::new(&b, 3, AngleSequence::GoldenAngle).unwrap();
        // Golden angle: consecutive samples 2π(1 − 1/φ) ≈ 137.5° apart.
        let d = (g.samples[1].angle_rad - g.samples[0].angle_rad).rem_euclid(2.0 * PI);
        assert!((2.0 * PI - d - 2.0 * PI * (1.0 - INV_GOLDEN_RATIO)).abs() < 1e-12);
        assert!(SamplePattern::new(&b, 0, AngleSequence::Hammersley).is_err());
    }

    /// Antithetic pairs: N samples, equal dominant-channel weights, zero
    /// first moment Σ w·x over the pairs (to rounding; an odd N's single
    /// innermost sample is all that is left), radii at the paired strata.
    #[test]
    fn antithetic_pairs_cancel_the_first_moment() {
        let b = Burley::from_scattering_distance([0.9, 0.5, 0.3], [1.0, 0.4, 0.1]).unwrap();
        for n in [7, 21, 54] {
            let p = SamplePattern::new_antithetic(&b, n, AngleSequence::GoldenAngle).unwrap();
            assert_eq!(p.samples.len(), n);
            let (mut mx, mut my) = (0.0, 0.0);
            for s in &p.samples {
                assert!((s.weight[0] - 0.9 / n as f64).abs() < 1e-15);
            }
            for s in &p.samples[n % 2..] {
                mx += s.weight[1] * s.radius_mm * s.angle_rad.cos();
                my += s.weight[1] * s.radius_mm * s.angle_rad.sin();
            }
            assert!(mx.abs() < 1e-12 && my.abs() < 1e-12, "{n}: {mx} {my}");
            // The golden-angle pattern's first moment does not vanish.
            let g = SamplePattern::new(&b, n, AngleSequence::GoldenAngle).unwrap();
            let gx: f64 = g
                .samples
                .iter()
                .map(|s| s.weight[1] * s.radius_mm * s.angle_rad.cos())
                .sum();
            assert!(gx.abs() > 1e-6, "{n}: {gx}");
        }
        let p = SamplePattern::new_antithetic(&b, 5, AngleSequence::GoldenAngle).unwrap();
        let quantile = |k: usize| b.cdf(p.samples[k].radius_mm)[0];
        assert!((quantile(0) - 0.1).abs() < 1e-12);
        assert!((quantile(1) - 0.4).abs() < 1e-12 && (quantile(3) - 0.8).abs() < 1e-12);
    }

    /// Under MIS every channel's weights still estimate its albedo (the
    /// integral ∫R_c dA = A_c, Burley's closed-form total), and the narrow
    /// blue channel's estimate is closer at a low count than with the red
    /// channel's quantiles alone.
    #[test]
    fn mis_weights_estimate_the_albedo_and_help_narrow_channels() {
        let b = Burley::from_scattering_distance([0.9, 0.5, 0.3], [1.0, 0.4, 0.1]).unwrap();
        let p = SamplePattern::new_mis(&b, 3000, AngleSequence::GoldenAngle).unwrap();
        let s = p.weight_sum();
        for c in 0..3 {
            assert!((s[c] / b.albedo()[c] - 1.0).abs() < 3e-3, "{s:?}");
        }
        // Radii of channel c come from c's quantiles: sample 1 is green's first.
        let g = b.cdf(p.samples[1].radius_mm)[1];
        assert!((g - 0.5 / 1000.0).abs() < 1e-9, "{g}");
        let err = |p: &SamplePattern| (p.weight_sum()[2] / 0.3 - 1.0).abs();
        let mis = SamplePattern::new_mis(&b, 21, AngleSequence::GoldenAngle).unwrap();
        let one = SamplePattern::new(&b, 21, AngleSequence::GoldenAngle).unwrap();
        assert!(err(&mis) < err(&one), "{} vs {}", err(&mis), err(&one));
    }
}
