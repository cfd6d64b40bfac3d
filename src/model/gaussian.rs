//! Sums of normalized 2D Gaussians (d'Eon & Luebke 2007, GPU Gems 3 ch. 14):
//! R(r) = Σ w_k · e^(−r²/2v_k) / (2π v_k),  v_k in mm².
//!
//! Each 2D Gaussian integrates to 1, so the total per channel is Σ w_k; the
//! CDF and the thin-slab transmittance Σ w_k e^(−d²/2v_k) are closed forms,
//! and the pre-integrated 1D kernel is Σ w_k e^(−x²/2v_k)/√(2π v_k).

use super::{check_range, rgb_map, ModelError, RadialProfile, Rgb, CHANNEL_NAMES};
use std::f64::consts::PI;

/// d'Eon's six-Gaussian skin fit: (variance mm², weights R, G, B), verbatim
/// from `assets/data/deon2007_skin_six_gaussians.csv` (GPU Gems 3 ch. 14;
/// also Mikkelsen 2009 Table 4).
pub const DEON_SKIN: [(f64, Rgb); 6] = [
    (0.0064, [0.233, 0.455, 0.649]),
    (0.0484, [0.100, 0.336, 0.344]),
    (0.187, [0.118, 0.198, 0.0]),
    (0.567, [0.113, 0.007, 0.007]),
    (1.99, [0.358, 0.004, 0.0]),
    (7.41, [0.078, 0.0, 0.0]),
];

/// Documented variance range (mm²).
pub const VARIANCE_RANGE_MM2: (f64, f64) = (1e-10, 1e6);
/// Weight of one term per channel.
pub const WEIGHT_RANGE: (f64, f64) = (0.0, 1e6);

/// One Gaussian term of one channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Term {
    pub weight: f64,
    pub variance_mm2: f64,
}

/// A sum of 2D Gaussians per channel, plus an optional Dirac delta at r = 0.
#[derive(Debug, Clone, PartialEq)]
pub struct GaussianSum {
    channels: [Vec<Term>; 3],
    dirac: Rgb,
    /// When all channels share their variances (d'Eon's table): one
    /// exponential per term serves three channels.
    shared: Option<Vec<(f64, Rgb)>>,
}

fn share(channels: &[Vec<Term>; 3]) -> Option<Vec<(f64, Rgb)>> {
    let n = channels[0].len();
    if channels[1].len() != n || channels[2].len() != n {
        return None;
    }
    (0..n)
        .map(|k| {
            let v = channels[0][k].variance_mm2;
            (channels[1][k].variance_mm2 == v && channels[2][k].variance_mm2 == v).then(|| {
                (
                    v,
                    [
                        channels[0][k].weight,
                        channels[1][k].weight,
                        channels[2][k].weight,
                    ],
                )
            })
        })
        .collect()
}

impl GaussianSum {
    /// Shared variances with RGB weights, as d'Eon tabulates them.
    pub fn new(terms: &[(f64, Rgb)]) -> Result<Self, ModelError> {
        if terms.is_empty() {
            return Err(ModelError::invalid(
                "gaussians",
                "at least one Gaussian is required",
            ));
        }
        let mut channels: [Vec<Term>; 3] = Default::default();
        for (k, (v, w)) in terms.iter().enumerate() {
            check_range(
                &format!("gaussians[{k}].variance_mm2"),
                *v,
                VARIANCE_RANGE_MM2.0,
                VARIANCE_RANGE_MM2.1,
                " mm²",
            )?;
            for c in 0..3 {
                let field = format!("gaussians[{k}].weights.{}", CHANNEL_NAMES[c]);
                check_range(&field, w[c], WEIGHT_RANGE.0, WEIGHT_RANGE.1, "")?;
                channels[c].push(Term {
                    weight: w[c],
                    variance_mm2: *v,
                });
            }
        }
        Ok(Self::from_channels(channels, [0.0; 3]))
    }

    /// [`GaussianSum::new`] with a share of each channel's light that
    /// leaves where it entered (a Dirac part at r = 0, as Jimenez 2012's
    /// 1 − strength), ≥ 0 per channel.
    pub fn with_dirac(terms: &[(f64, Rgb)], dirac: Rgb) -> Result<Self, ModelError> {
        for c in 0..3 {
            check_range(
                &format!("dirac.{}", CHANNEL_NAMES[c]),
                dirac[c],
                0.0,
                1e6,
                "",
            )?;
        }
        let s = Self::new(terms)?;
        Ok(Self::from_channels(s.channels, dirac))
    }

    /// d'Eon's six-Gaussian skin profile.
    pub fn deon_skin() -> Self {
        // The table is a valid constant; construct directly.
        let mut channels: [Vec<Term>; 3] = Default::default();
        for (v, w) in DEON_SKIN {
            for c in 0..3 {
                channels[c].push(Term {
                    weight: w[c],
                    variance_mm2: v,
                });
            }
        }
        Self::from_channels(channels, [0.0; 3])
    }

    /// Per-channel terms and Dirac weights, already validated by the caller.
    pub(crate) fn from_channels(channels: [Vec<Term>; 3], dirac: Rgb) -> Self {
        let shared = share(&channels);
        Self {
            channels,
            dirac,
            shared,
        }
    }

    pub fn channel_terms(&self, channel: usize) -> &[Term] {
        &self.channels[channel]
    }

    /// Pre-integrated 1D kernel a_p(x) = ∫R(√(x²+y²))dy, closed form.
    pub fn preintegrated(&self, x_mm: f64) -> Rgb {
        rgb_map(|c| {
            self.channels[c]
                .iter()
                .map(|t| {
                    t.weight * (-x_mm * x_mm / (2.0 * t.variance_mm2)).exp()
                        / (2.0 * PI * t.variance_mm2).sqrt()
                })
                .sum()
        })
    }
}

impl RadialProfile for GaussianSum {
    fn reflectance(&self, radius_mm: f64) -> Rgb {
        let r2 = radius_mm * radius_mm;
        if let Some(terms) = &self.shared {
            let mut out = [0.0; 3];
            for (v, w) in terms {
                let g = (-r2 / (2.0 * v)).exp() / (2.0 * PI * v);
                for c in 0..3 {
                    out[c] += w[c] * g;
                }
            }
            return out;
        }
        rgb_map(|c| {
            self.channels[c]
                .iter()
                .map(|t| {
                    t.weight * (-r2 / (2.0 * t.variance_mm2)).exp() / (2.0 * PI * t.variance_mm2)
                })
                .sum()
        })
    }

    fn total_reflectance(&self) -> Rgb {
        rgb_map(|c| self.dirac[c] + self.channels[c].iter().map(|t| t.weight).sum::<f64>())
    }

    fn dirac_weight(&self) -> Rgb {
        self.dirac
    }

    fn cdf(&self, radius_mm: f64) -> Rgb {
        let total = self.total_reflectance();
        let r2 = radius_mm * radius_mm;
        rgb_map(|c| {
            if total[c] <= 0.0 {
                return 1.0;
            }
            let inside: f64 = self.channels[c]
                .iter()
                .map(|t| -t.weight * (-r2 / (2.0 * t.variance_mm2)).exp_m1())
                .sum();
            ((self.dirac[c] + inside) / total[c]).clamp(0.0, 1.0)
        })
    }

    fn tail(&self, radius_mm: f64) -> Rgb {
        let total = self.total_reflectance();
        let r2 = radius_mm * radius_mm;
        rgb_map(|c| {
            if total[c] <= 0.0 {
                return 0.0;
            }
            let outside: f64 = self.channels[c]
                .iter()
                .map(|t| t.weight * (-r2 / (2.0 * t.variance_mm2)).exp())
                .sum();
            (outside / total[c]).clamp(0.0, 1.0)
        })
    }

    fn length_scale_mm(&self) -> f64 {
        self.channels
            .iter()
            .flatten()
            .filter(|t| t.weight > 0.0)
            .map(|t| t.variance_mm2.sqrt())
            .fold(1e-6, f64::max)
    }

    fn strip_cdf(&self, x_mm: f64) -> Rgb {
        let total = self.total_reflectance();
        rgb_map(|c| {
            if total[c] <= 0.0 {
                return if x_mm >= 0.0 { 1.0 } else { 0.0 };
            }
            let cont: f64 = self.channels[c]
                .iter()
                .map(|t| t.weight * 0.5 * libm::erfc(-x_mm / (2.0 * t.variance_mm2).sqrt()))
                .sum();
            let dirac = if x_mm >= 0.0 { self.dirac[c] } else { 0.0 };
            ((cont + dirac) / total[c]).clamp(0.0, 1.0)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::quad;

    /// The constant equals the shared CSV (d'Eon 2007 via iryoku/separable-sss).
    #[test]
    fn table_matches_shared_csv() {
        let text = include_str!("../../assets/data/deon2007_skin_six_gaussians.csv");
        let rows: Vec<Vec<f64>> = text
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("variance"))
            .map(|l| {
                l.split(',')
                    .map(|x| x.trim().parse::<f64>().unwrap())
                    .collect()
            })
            .collect();
        assert_eq!(rows.len(), 6);
        for (row, (v, w)) in rows.iter().zip(DEON_SKIN) {
            assert_eq!(row[0], v);
            assert_eq!(&row[1..4], &w[..]);
            // FaceWorks stores σ = √v to three digits.
            assert!(
                (row[4] - v.sqrt()).abs() < 6e-4,
                "{} vs {}",
                row[4],
                v.sqrt()
            );
        }
    }

    /// d'Eon's weights sum to 1 per channel, and quadrature of 2πrR agrees.
    #[test]
    fn deon_total_is_one_per_channel_by_quadrature() {
        let p = GaussianSum::deon_skin();
        for c in 0..3 {
            let v = quad::integrate_to_infinity(
                &|r: f64| 2.0 * PI * r * p.reflectance(r)[c],
                0.0,
                0.5,
                1e-14,
                1e-13,
            );
            assert!((v - 1.0).abs() < 1e-9, "channel {c}: {v}");
            assert!((p.total_reflectance()[c] - 1.0).abs() < 1e-12);
        }
    }

    /// Closed-form pre-integrated kernel against ∫R(√(x²+y²))dy by quadrature.
    #[test]
    fn preintegrated_matches_quadrature() {
        let p = GaussianSum::deon_skin();
        for &x in &[0.0, 0.1, 0.7, 2.5] {
            let a = p.preintegrated(x);
            for c in 0..3 {
                let f = |y: f64| 2.0 * p.reflectance((x * x + y * y).sqrt())[c];
                let v = quad::integrate_to_infinity(&f, 0.0, 0.1, 1e-15, 1e-13);
                assert!(
                    (v - a[c]).abs() < 1e-9 * a[c].max(1e-6),
                    "x={x} c={c}: {v} vs {}",
                    a[c]
                );
            }
        }
    }
}
