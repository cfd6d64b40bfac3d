//! Separable kernels (Jimenez et al. 2015, Jimenez et al. 2015).
//!
//! - The pre-integrated kernel a_p(x) = ∫R(√(x²+y²)) dy of any radial
//!   profile (§4, eq. 4–5): exact for additively separable irradiance such
//!   as a straight shadow edge.
//! - The artist-friendly model (§5, eq. 6): a_m(x) = w·G(x, σn) + (1−w)·G(x, σf)
//!   with σ = σ′·s. Seed 004 prints G(x, σ) = e^(−x²/2σ²)/(2πσ); that does
//!   not integrate to 1 (it gives 1/√(2π)), so we use the normalised
//!   1/(√(2π)σ) (see `printed_artist_normalisation_is_not_unit`). Its
//!   radial profile is the unique one whose pre-integration is a_m: the 2D
//!   Gaussians w·G₂(σn²) + (1−w)·G₂(σf²) (inverse Abel transform).
//! - Importance-sampled 1D taps for both (§7): positions at the quantiles
//!   (i + ½)/N of the dominant channel's strip CDF, per-channel weights by
//!   integrating each channel's kernel over the tap's interval, so weights
//!   sum to exactly one.

use super::gaussian::{GaussianSum, Term};
use super::quad;
use super::{check_range, check_rgb, rgb_map, ModelError, RadialProfile, Rgb};

/// One tap of a 1D kernel: per-channel weight and offset in mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tap {
    pub weight: Rgb,
    pub offset_mm: f64,
}

/// A 1D separable kernel, centre tap first (the Jimenez demo's order).
#[derive(Debug, Clone, PartialEq)]
pub struct SeparableKernel {
    pub taps: Vec<Tap>,
}

impl SeparableKernel {
    /// Sum of weights per channel.
    pub fn sum(&self) -> Rgb {
        rgb_map(|c| self.taps.iter().map(|t| t.weight[c]).sum())
    }

    /// Importance-sampled taps of the pre-integrated kernel of `profile`
    /// (Jimenez 2015 §4 and §7). `taps` must be odd. A Dirac part (the
    /// Jimenez 2012 strength lerp) goes to the centre tap; the continuous
    /// part is sampled at the quantiles of the dominant channel.
    pub fn importance_sampled(
        profile: &dyn RadialProfile,
        taps: usize,
    ) -> Result<Self, ModelError> {
        super::jimenez::check_taps(taps)?;
        let total = profile.total_reflectance();
        let dirac = profile.dirac_weight();
        let frac = rgb_map(|c| {
            if total[c] > 0.0 {
                dirac[c] / total[c]
            } else {
                1.0
            }
        });
        // Continuous strip CDF per channel, renormalised without the Dirac.
        let phi_cont = |x: f64| -> Rgb {
            let phi = profile.strip_cdf(x);
            rgb_map(|c| {
                if frac[c] >= 1.0 {
                    return if x >= 0.0 { 1.0 } else { 0.0 };
                }
                let jump = if x >= 0.0 { frac[c] } else { 0.0 };
                ((phi[c] - jump) / (1.0 - frac[c])).clamp(0.0, 1.0)
            })
        };
        let radius = profile.radius_for_energy(super::DEFAULT_ENERGY_FRACTION);
        let dom = (0..3)
            .filter(|&c| frac[c] < 1.0)
            .max_by(|&a, &b| radius[a].total_cmp(&radius[b]));
        let Some(dom) = dom else {
            // Nothing scatters: the identity kernel.
            let mut out = vec![
                Tap {
                    weight: [0.0; 3],
                    offset_mm: 0.0
                };
                taps
            ];
            out[0].weight = rgb_map(|c| if total[c] > 0.0 { 1.0 } else { 0.0 });
            return Ok(Self { taps: out });
        };
        let scale = profile.length_scale_mm();
        let quantile = |p: f64| invert_monotone(|x| phi_cont(x)[dom], p, scale);
        let cum: Vec<Rgb> = (0..=taps)
            .map(|i| match i {
                0 => [0.0; 3],
                i if i == taps => [1.0; 3],
                i => phi_cont(quantile(i as f64 / taps as f64)),
            })
            .collect();
        let mut out: Vec<Tap> = (0..taps)
            .map(|i| {
                let centre = 2 * i + 1 == taps;
                let offset = if centre {
                    0.0
                } else {
                    quantile((i as f64 + 0.5) / taps as f64)
                };
                let weight = rgb_map(|c| {
                    let cont = (1.0 - frac[c]) * (cum[i + 1][c] - cum[i][c]).max(0.0);
                    let energy = if total[c] > 0.0 { 1.0 } else { 0.0 };
                    energy * (cont + if centre { frac[c] } else { 0.0 })
                });
                Tap {
                    weight,
                    offset_mm: offset,
                }
            })
            .collect();
        let centre = out.remove(taps / 2);
        out.insert(0, centre);
        Ok(Self { taps: out })
    }
}

/// Solves Φ(x) = p for a monotone Φ by bracketing and bisection.
fn invert_monotone(phi: impl Fn(f64) -> f64, p: f64, scale: f64) -> f64 {
    let (mut lo, mut hi) = (-scale.max(1e-9), scale.max(1e-9));
    while phi(lo) > p && lo > -1e12 {
        lo *= 2.0;
    }
    while phi(hi) < p && hi < 1e12 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let m = 0.5 * (lo + hi);
        if phi(m) < p {
            lo = m;
        } else {
            hi = m;
        }
        if hi - lo <= 1e-13 * hi.abs().max(lo.abs()).max(1e-300) {
            break;
        }
    }
    0.5 * (lo + hi)
}

/// The pre-integrated kernel a_p(x) = ∫R(√(x²+y²)) dy (mm⁻¹) of any radial
/// profile, by adaptive quadrature (continuous part; the Dirac adds δ(x)).
/// At x = 0 a profile with a 1/r singularity diverges logarithmically;
/// x is then floored at the profile's `r_floor_mm`.
pub fn preintegrated(profile: &dyn RadialProfile, x_mm: f64) -> Rgb {
    let x = x_mm.abs().max(profile.r_floor_mm());
    let scale = profile.length_scale_mm();
    rgb_map(|c| {
        // y = x·sinh(t) removes the 1/ρ behaviour near y = 0 when x is small.
        let f = |y: f64| {
            let rho = (x * x + y * y).sqrt();
            2.0 * profile.r_reflectance(rho)[c] / rho
        };
        if x > 0.0 {
            let g = |t: f64| f(x * t.sinh()) * x * t.cosh();
            let t_max = (2.0 * (scale / x).max(1.0) * 60.0).asinh();
            quad::integrate(&g, 0.0, t_max, 1e-300, 1e-11)
        } else {
            quad::integrate_to_infinity(&f, 0.0, scale, 1e-300, 1e-11)
        }
    })
}

/// Jimenez 2015 Table 2 kernel presets: (name, s mm, σ′n RGB, σ′f RGB, w).
pub const TABLE2_PRESETS: [(&str, f64, Rgb, Rgb, f64); 3] = [
    (
        "single-layer",
        10.34,
        [0.077, 0.034, 0.02],
        [1.0, 0.45, 0.25],
        0.5,
    ),
    (
        "multi-layer",
        9.27,
        [0.055, 0.044, 0.038],
        [1.0, 0.2, 0.13],
        0.5,
    ),
    (
        "production",
        9.9,
        [0.22, 0.07, 0.07],
        [1.0, 0.3, 0.15],
        0.65,
    ),
];

/// The artist-friendly two-Gaussian model (Jimenez 2015 §5).
#[derive(Debug, Clone, PartialEq)]
pub struct ArtistTwoGaussian {
    sigma_near: Rgb,
    sigma_far: Rgb,
    weight: f64,
    scale_mm: f64,
    profile: GaussianSum,
}

/// Valid widths σ′ (relative to the scale), near weight w and scale s (mm)
/// of the artist model (`ArtistTwoGaussian::new` checks them; the editor's
/// fields take their range from here).
pub const ARTIST_SIGMA_RANGE: (f64, f64) = (1e-6, 1.0);
pub const ARTIST_WEIGHT_RANGE: (f64, f64) = (0.0, 1.0);
pub const ARTIST_SCALE_RANGE_MM: (f64, f64) = (1e-4, 1e3);

impl ArtistTwoGaussian {
    /// σ′n, σ′f ∈ (0, 1] per channel, w ∈ [0, 1], s ∈ [1e-4, 1e3] mm.
    pub fn new(
        sigma_near: Rgb,
        sigma_far: Rgb,
        weight: f64,
        scale_mm: f64,
    ) -> Result<Self, ModelError> {
        let (s0, s1) = ARTIST_SIGMA_RANGE;
        check_rgb("sigma_near", sigma_near, s0, s1, " (relative to scale)")?;
        check_rgb("sigma_far", sigma_far, s0, s1, " (relative to scale)")?;
        let (w0, w1) = ARTIST_WEIGHT_RANGE;
        check_range("weight", weight, w0, w1, "")?;
        let (m0, m1) = ARTIST_SCALE_RANGE_MM;
        check_range("scale_mm", scale_mm, m0, m1, " mm")?;
        let channels: [Vec<Term>; 3] = [0, 1, 2].map(|c| {
            let vn = (sigma_near[c] * scale_mm).powi(2);
            let vf = (sigma_far[c] * scale_mm).powi(2);
            vec![
                Term {
                    weight,
                    variance_mm2: vn,
                },
                Term {
                    weight: 1.0 - weight,
                    variance_mm2: vf,
                },
            ]
        });
        Ok(Self {
            sigma_near,
            sigma_far,
            weight,
            scale_mm,
            profile: GaussianSum::from_channels(channels, [0.0; 3]),
        })
    }

    /// One of [`TABLE2_PRESETS`] by name.
    pub fn table2(name: &str) -> Result<Self, ModelError> {
        let (_, s, n, f, w) = TABLE2_PRESETS.iter().find(|p| p.0 == name).ok_or_else(|| {
            let known: Vec<&str> = TABLE2_PRESETS.iter().map(|p| p.0).collect();
            ModelError::invalid(
                "artist preset",
                format!("unknown `{name}`; known: {}", known.join(", ")),
            )
        })?;
        Self::new(*n, *f, *w, *s)
    }

    pub fn sigma_near(&self) -> Rgb {
        self.sigma_near
    }
    pub fn sigma_far(&self) -> Rgb {
        self.sigma_far
    }
    pub fn weight(&self) -> f64 {
        self.weight
    }
    pub fn scale_mm(&self) -> f64 {
        self.scale_mm
    }

    /// a_m(x) (mm⁻¹), normalised to integrate to 1 per channel.
    pub fn kernel_1d(&self, x_mm: f64) -> Rgb {
        self.profile.preintegrated(x_mm)
    }
}

super::delegate_radial_profile!(ArtistTwoGaussian, profile);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::burley::Burley;
    use std::f64::consts::PI;

    /// K0 by Abramowitz & Stegun 9.8.5–9.8.6 (|ε| < 2e-7), an independent
    /// closed form for Burley's pre-integrated kernel.
    fn bessel_k0(x: f64) -> f64 {
        if x <= 2.0 {
            let t = x / 3.75;
            let t2 = t * t;
            let i0 = 1.0
                + t2 * (3.5156229
                    + t2 * (3.0899424
                        + t2 * (1.2067492 + t2 * (0.2659732 + t2 * (0.0360768 + t2 * 0.0045813)))));
            let y = x * x / 4.0;
            -(x / 2.0).ln() * i0 - 0.57721566
                + y * (0.42278420
                    + y * (0.23069756
                        + y * (0.03488590 + y * (0.00262698 + y * (0.00010750 + y * 0.0000074)))))
        } else {
            let y = 2.0 / x;
            (-x).exp() / x.sqrt()
                * (1.25331414
                    + y * (-0.07832358
                        + y * (0.02189568
                            + y * (-0.01062446
                                + y * (0.00587872 + y * (-0.00251540 + y * 0.00053208))))))
        }
    }

    /// Burley: a_p(x) = A·s·(K0(s|x|) + K0(s|x|/3))/(4π).
    #[test]
    fn preintegrated_burley_matches_bessel_closed_form() {
        let p = Burley::from_scattering_distance([0.8, 0.6, 0.4], [1.0, 0.5, 0.25]).unwrap();
        for &x in &[0.01, 0.2, 1.0, 3.0] {
            let a = preintegrated(&p, x);
            for c in 0..3 {
                let s = p.shape_per_mm()[c];
                let reference =
                    p.albedo()[c] * s * (bessel_k0(s * x) + bessel_k0(s * x / 3.0)) / (4.0 * PI);
                assert!(
                    (a[c] - reference).abs() < 2e-6 * reference,
                    "x={x} c={c}: {} vs {reference}",
                    a[c]
                );
            }
        }
    }

    /// Generic a_p agrees with the Gaussian closed form (d'Eon skin).
    #[test]
    fn preintegrated_generic_matches_gaussian_closed_form() {
        let p = GaussianSum::deon_skin();
        for &x in &[0.05, 0.5, 2.0] {
            let a = preintegrated(&p, x);
            let b = p.preintegrated(x);
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() < 1e-8 * b[c].max(1e-9),
                    "x={x}: {a:?} {b:?}"
                );
            }
        }
    }

    /// The strip CDF by numerics (Burley) equals ∫ a_p dx by quadrature.
    #[test]
    fn strip_cdf_is_the_integral_of_the_preintegrated_kernel() {
        let p = Burley::from_scattering_distance([1.0; 3], [1.0, 0.5, 0.25]).unwrap();
        let x = 0.7;
        let phi = p.strip_cdf(x);
        let f = |t: f64| preintegrated(&p, t)[0];
        let half = 0.5 + quad::integrate(&f, 1e-9, x, 1e-12, 1e-9);
        assert!((phi[0] - half).abs() < 1e-6, "{} vs {half}", phi[0]);
    }

    /// Seed 004 eq. 6 prints G(x,σ) = e^(−x²/2σ²)/(2πσ): it integrates to
    /// 1/√(2π), not 1. Our a_m uses 1/(√(2π)σ) and integrates to 1.
    #[test]
    fn printed_artist_normalisation_is_not_unit() {
        let sigma = 0.7;
        let printed = |x: f64| (-x * x / (2.0 * sigma * sigma)).exp() / (2.0 * PI * sigma);
        let v = quad::integrate(&printed, -20.0, 20.0, 1e-14, 1e-13);
        assert!((v - 1.0 / (2.0 * PI).sqrt()).abs() < 1e-12);
        let m = ArtistTwoGaussian::table2("production").unwrap();
        for c in 0..3 {
            let v = quad::integrate(&|x: f64| m.kernel_1d(x)[c], -200.0, 200.0, 1e-14, 1e-12);
            assert!((v - 1.0).abs() < 1e-10, "{v}");
        }
    }

    /// Importance-sampled taps: weights sum to one; the dominant channel
    /// gets 1/N per tap; taps are symmetric; offsets are the quantiles.
    #[test]
    fn importance_sampled_taps_are_normalised_and_symmetric() {
        let m = ArtistTwoGaussian::table2("multi-layer").unwrap();
        let k = SeparableKernel::importance_sampled(&m, 7).unwrap();
        let s = k.sum();
        for c in 0..3 {
            assert!((s[c] - 1.0).abs() < 1e-12, "{s:?}");
        }
        assert_eq!(k.taps[0].offset_mm, 0.0);
        for t in &k.taps {
            assert!((t.weight[0] - 1.0 / 7.0).abs() < 1e-9, "{t:?}");
        }
        let mut offs: Vec<f64> = k.taps.iter().map(|t| t.offset_mm).collect();
        offs.sort_by(f64::total_cmp);
        for i in 0..7 {
            assert!((offs[i] + offs[6 - i]).abs() < 1e-9);
        }
        let j = crate::model::jimenez::Jimenez2012::new([0.5; 3], [1.0, 0.4, 0.3]).unwrap();
        let kj = SeparableKernel::importance_sampled(&j, 9).unwrap();
        // The Dirac (1 − strength) lands on the centre tap.
        assert!(kj.taps[0].weight[1] >= 0.5);
    }
}
