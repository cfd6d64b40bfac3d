//! Disk sample patterns for the screen-space Burley method (Golubev 2018,
//! seed 001 "Sampling the Diffusion Profile"): radii by the inverse CDF of
//! the channel with the longest scattering distance at ξᵢ = (i + ½)/N,
//! angles by the golden angle (Fibonacci) or the Hammersley radical
//! inverse, and per-channel weights R_c(r)/pdf(r) so that
//! Σᵢ wᵢ·L(xᵢ) estimates ∫R_c(|x|)L(x) dA (Σᵢ w_c,i → A_c).

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
}

/// A precomputed sample pattern.
#[derive(Debug, Clone, PartialEq)]
pub struct SamplePattern {
    pub samples: Vec<DiskSample>,
    /// The channel whose CDF placed the radii.
    pub sampled_channel: usize,
    pub angles: AngleSequence,
}

impl SamplePattern {
    /// Golubev 2018's pattern for `profile` with `n` samples.
    pub fn new(
        profile: &dyn RadialProfile,
        n: usize,
        angles: AngleSequence,
    ) -> Result<Self, ModelError> {
        check_range(
            "samples",
            n as f64,
            SAMPLES_RANGE.0 as f64,
            SAMPLES_RANGE.1 as f64,
            "",
        )?;
        let widest = profile.radius_for_energy(DEFAULT_ENERGY_FRACTION);
        let dom = (0..3)
            .max_by(|&a, &b| widest[a].total_cmp(&widest[b]))
            .unwrap_or(0);
        let total = profile.total_reflectance();
        let samples = (0..n)
            .map(|i| {
                let xi = (i as f64 + 0.5) / n as f64;
                let r = profile.inverse_cdf(dom, xi);
                let angle = 2.0
                    * PI
                    * match angles {
                        AngleSequence::GoldenAngle => (i as f64 * INV_GOLDEN_RATIO).fract(),
                        AngleSequence::Hammersley => radical_inverse_base2(i as u32),
                    };
                // w_c = R_c(r) / (N·q(r)), q = area density = R_dom(r)/A_dom.
                let rr = profile.r_reflectance(r);
                let weight = rgb_map(|c| {
                    if rr[dom] > 0.0 {
                        total[dom] * rr[c] / (n as f64 * rr[dom])
                    } else {
                        0.0
                    }
                });
                DiskSample {
                    radius_mm: r,
                    angle_rad: angle,
                    weight,
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
}
