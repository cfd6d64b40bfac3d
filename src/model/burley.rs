//! Burley normalized diffusion (Christensen & Burley 2015), parameterised as
//! Unity HDRP does it: a volume albedo A and a scattering distance d = 1/s
//! per channel (Christensen & Burley 2015; Golubev 2018).
//!
//! R(r) = A·s·(e^(−sr) + e^(−sr/3)) / (8πr)                    [mm⁻²]
//! ∫2πr R dr = A;  P(r) = 1 − e^(−sr)/4 − 3e^(−sr/3)/4 (Golubev 2018)
//! T(d) = A/4·(e^(−sd) + 3e^(−sd/3))                          (Christensen & Burley 2015; Golubev 2018)

use super::{check_range, check_rgb, check_xi, rgb_map, ModelError, RadialProfile, Rgb};
use std::f64::consts::PI;

/// Documented range of the scattering distance d (mm).
pub const DISTANCE_RANGE_MM: (f64, f64) = (1e-4, 1e3);
/// Volume albedo A per channel.
pub const ALBEDO_RANGE: (f64, f64) = (0.0, 1.0);
/// Mean free path ℓ per channel (mm), before the fit turns it into d.
pub const MEAN_FREE_PATH_RANGE_MM: (f64, f64) = (1e-6, 1e6);

/// The three published fits s(A) of Christensen & Burley 2015 that turn a
/// mean free path ℓ into the shape s = fit(A)/ℓ. Presets store it by its
/// variant's name (`fit: DiffuseSurface`), the command line by clap's
/// (`--fit diffuse-surface`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize, clap::ValueEnum,
)]
pub enum ScalingFit {
    /// Eq. 5, searchlight (perpendicular) configuration with the mean free
    /// path: s = 1.85 − A + 7|A − 0.8|³ (Unreal's `GetPerpendicularScalingFactor`).
    Perpendicular,
    /// Eq. 6, diffuse surface transmission with the mean free path:
    /// s = 1.9 − A + 3.5(A − 0.8)² (Cycles' `bssrdf_burley_fitting`).
    DiffuseSurface,
    /// Eq. 8, searchlight with the diffuse mean free path:
    /// s = 3.5 + 100(A − 0.33)⁴ (Unreal's `GetSearchLightDiffuseScalingFactor`).
    DiffuseMeanFreePath,
}

impl ScalingFit {
    pub const ALL: [ScalingFit; 3] = [
        ScalingFit::Perpendicular,
        ScalingFit::DiffuseSurface,
        ScalingFit::DiffuseMeanFreePath,
    ];

    /// The dimensionless scaling s(A).
    pub fn scale(self, albedo: f64) -> f64 {
        let a = albedo;
        match self {
            ScalingFit::Perpendicular => 1.85 - a + 7.0 * (a - 0.8).abs().powi(3),
            ScalingFit::DiffuseSurface => 1.9 - a + 3.5 * (a - 0.8).powi(2),
            ScalingFit::DiffuseMeanFreePath => 3.5 + 100.0 * (a - 0.33).powi(4),
        }
    }

    /// Human-readable name with the equation it comes from.
    pub fn describe(self) -> &'static str {
        match self {
            ScalingFit::Perpendicular => {
                "Christensen-Burley 2015 eq. 5 (searchlight/perpendicular, mean free path)"
            }
            ScalingFit::DiffuseSurface => {
                "Christensen-Burley 2015 eq. 6 (diffuse surface transmission, mean free path)"
            }
            ScalingFit::DiffuseMeanFreePath => {
                "Christensen-Burley 2015 eq. 8 (searchlight, diffuse mean free path)"
            }
        }
    }

    /// Stable identifier used in presets and on the command line.
    pub fn id(self) -> &'static str {
        match self {
            ScalingFit::Perpendicular => "perpendicular",
            ScalingFit::DiffuseSurface => "diffuse-surface",
            ScalingFit::DiffuseMeanFreePath => "diffuse-mean-free-path",
        }
    }
}

/// Burley's normalized diffusion per RGB channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Burley {
    albedo: Rgb,
    shape_per_mm: Rgb,
}

impl Burley {
    /// A ∈ [0, 1] and d ∈ [1e-4, 1e3] mm per channel (Unity's parameters).
    pub fn from_scattering_distance(albedo: Rgb, distance_mm: Rgb) -> Result<Self, ModelError> {
        check_rgb("albedo", albedo, ALBEDO_RANGE.0, ALBEDO_RANGE.1, "")?;
        check_rgb(
            "scattering_distance_mm",
            distance_mm,
            DISTANCE_RANGE_MM.0,
            DISTANCE_RANGE_MM.1,
            " mm",
        )?;
        Ok(Self {
            albedo,
            shape_per_mm: rgb_map(|c| 1.0 / distance_mm[c]),
        })
    }

    /// A plus a (diffuse) mean free path ℓ per channel through one of the
    /// published fits: s = fit(A)/ℓ. The resulting d = 1/s must stay in range.
    pub fn from_mean_free_path(
        albedo: Rgb,
        mfp_mm: Rgb,
        fit: ScalingFit,
    ) -> Result<Self, ModelError> {
        check_rgb("albedo", albedo, ALBEDO_RANGE.0, ALBEDO_RANGE.1, "")?;
        let (lo, hi) = MEAN_FREE_PATH_RANGE_MM;
        check_rgb("mean_free_path_mm", mfp_mm, lo, hi, " mm")?;
        let d = rgb_map(|c| mfp_mm[c] / fit.scale(albedo[c]));
        for (c, v) in d.iter().enumerate() {
            check_range(
                &format!(
                    "mean_free_path_mm.{} (as scattering distance ℓ/s(A))",
                    super::CHANNEL_NAMES[c]
                ),
                *v,
                DISTANCE_RANGE_MM.0,
                DISTANCE_RANGE_MM.1,
                " mm",
            )?;
        }
        Self::from_scattering_distance(albedo, d)
    }

    pub fn albedo(&self) -> Rgb {
        self.albedo
    }

    /// Shape s = 1/d (mm⁻¹).
    pub fn shape_per_mm(&self) -> Rgb {
        self.shape_per_mm
    }

    /// Scattering distance d = 1/s (mm).
    pub fn scattering_distance_mm(&self) -> Rgb {
        rgb_map(|c| 1.0 / self.shape_per_mm[c])
    }

    /// The mean free path that gives this profile's shape through `fit`.
    pub fn mean_free_path_mm(&self, fit: ScalingFit) -> Rgb {
        rgb_map(|c| fit.scale(self.albedo[c]) / self.shape_per_mm[c])
    }

    /// Index of the channel with the longest scattering distance (the one
    /// Golubev 2018 importance-samples).
    pub fn widest_channel(&self) -> usize {
        let s = self.shape_per_mm;
        if s[0] <= s[1] && s[0] <= s[2] {
            0
        } else if s[1] <= s[2] {
            1
        } else {
            2
        }
    }
}

impl RadialProfile for Burley {
    fn reflectance(&self, radius_mm: f64) -> Rgb {
        rgb_map(|c| {
            let s = self.shape_per_mm[c];
            // Burley 2015 eq. 2 is finite for every r > 0 and is returned
            // as such down to 1e-300 mm (below that 1/r would overflow f64);
            // only r = 0, where it diverges like 1/r, takes the documented
            // value at `r_floor_mm`, 1e-6·d (`reflectance_below_the_floor_is_the_closed_form`).
            let r = if radius_mm > 0.0 {
                radius_mm.max(1e-300)
            } else {
                1e-6 / s
            };
            let x = (-s * r / 3.0).exp(); // e^(−sr/3); e^(−sr) = x³
            self.albedo[c] * s * (x * x * x + x) / (8.0 * PI * r)
        })
    }

    fn r_reflectance(&self, radius_mm: f64) -> Rgb {
        rgb_map(|c| {
            let s = self.shape_per_mm[c];
            let x = (-s * radius_mm / 3.0).exp();
            self.albedo[c] * s * (x * x * x + x) / (8.0 * PI)
        })
    }

    fn total_reflectance(&self) -> Rgb {
        self.albedo
    }

    fn cdf(&self, radius_mm: f64) -> Rgb {
        rgb_map(|c| cdf_unit(self.shape_per_mm[c] * radius_mm))
    }

    fn tail(&self, radius_mm: f64) -> Rgb {
        rgb_map(|c| tail_unit(self.shape_per_mm[c] * radius_mm))
    }

    fn inverse_cdf(&self, channel: usize, xi: f64) -> f64 {
        sample_radius(xi, self.shape_per_mm[channel])
    }

    fn length_scale_mm(&self) -> f64 {
        self.scattering_distance_mm()
            .into_iter()
            .fold(0.0, f64::max)
    }

    fn r_floor_mm(&self) -> f64 {
        1e-6 * self
            .scattering_distance_mm()
            .into_iter()
            .fold(f64::INFINITY, f64::min)
    }

    /// Strip CDF (the pre-integrated kernel's CDF): for X ≥ 0,
    /// P(x > X) = [Ki₁(sX) + 3·Ki₁(sX/3)]/(4π), where Ki₁ is the Bickley–Naylor
    /// function ∫_x^∞ K₀; derived by integrating acos(X/r) by parts against
    /// p(r) = (s/4)(e^(−sr) + e^(−sr/3)). Checked against the generic quadrature.
    fn strip_cdf(&self, x_mm: f64) -> Rgb {
        rgb_map(|c| {
            let s = self.shape_per_mm[c];
            let x = x_mm.abs();
            let beyond = (bickley_ki1(s * x) + 3.0 * bickley_ki1(s * x / 3.0)) / (4.0 * PI);
            if x_mm >= 0.0 {
                1.0 - beyond
            } else {
                beyond
            }
        })
    }

    /// Closed form A/4·(e^(−sd) + 3e^(−sd/3)) (Golubev 2018).
    fn transmittance(&self, thickness_mm: f64) -> Rgb {
        rgb_map(|c| {
            let x = (-self.shape_per_mm[c] * thickness_mm.max(0.0) / 3.0).exp();
            0.25 * self.albedo[c] * (x * x * x + 3.0 * x)
        })
    }
}

/// Bickley–Naylor Ki₁(x) = ∫₀^∞ e^(−x·cosh u)/cosh u du (= ∫_x^∞ K₀), by
/// adaptive quadrature of that smooth integrand; Ki₁(0) = π/2.
pub fn bickley_ki1(x: f64) -> f64 {
    let f = |u: f64| {
        let c = u.cosh();
        (-x * c).exp() / c
    };
    // The integrand is below 1e-300 once x·cosh u > 690 or cosh u > 1e300.
    let u_max = if x > 0.0 {
        (690.0 / x).max(1.0).acosh()
    } else {
        700.0
    };
    super::quad::integrate(&f, 0.0, u_max.min(700.0), 1e-16, 1e-13)
}

/// P(t) for t = s·r, written with expm1 so small t keeps full precision.
fn cdf_unit(t: f64) -> f64 {
    -0.25 * (-t).exp_m1() - 0.75 * (-t / 3.0).exp_m1()
}

/// 1 − P(t) = e^(−t)/4 + 3e^(−t/3)/4.
fn tail_unit(t: f64) -> f64 {
    let x = (-t / 3.0).exp();
    0.25 * x * x * x + 0.75 * x
}

/// φ² = (9 + 4√5)^(1/3): the value of G^(1/3) at ξ = 0.
const GOLDEN_SQUARED: f64 = 2.618_033_988_749_895;

/// Closed-form inverse of the Burley CDF (Golubev 2018, as in Unity HDRP's
/// `SampleBurleyDiffusionProfile`):
///
/// r = (3/s)·ln((1 + G^(−1/3) + G^(1/3)) / (4u)),  G = 1 + 4u(2u + √(1 + 4u²)),  u = 1 − ξ.
///
/// The logarithm is the natural one: the survey we started from prints log₂, which does not
/// invert P (see the test `log2_reading_of_seed_000_does_not_invert_the_cdf`).
/// For ξ < ½ the argument is 1 + O(ξ), so the difference is formed
/// analytically (G − G(ξ=0) and G^(1/3) − φ² without cancellation) and fed
/// to ln_1p; this keeps full relative precision down to ξ → 0.
#[inline]
pub fn sample_radius(xi: f64, shape_per_mm: f64) -> f64 {
    if !(xi > 0.0) {
        return 0.0;
    }
    let u = 1.0 - xi;
    let root = (1.0 + 4.0 * u * u).sqrt();
    let big_g = 1.0 + 4.0 * u * (2.0 * u + root);
    let z = inv_cbrt_1_to_18(big_g); // G^(−1/3)
    let g = big_g * z * z; // G^(1/3)
    let t = if xi < 0.5 {
        // G − G₁ = −ξ(1+u)(8a + 4(4u² + 5))/a with a = u√(1+4u²) + √5, and
        // g − g₁ = (G − G₁)/(g² + g·g₁ + g₁²) (difference of cubes), so the
        // excess (1 + g + 1/g) − 4u = (g − g₁)(g·g₁ − 1)/(g·g₁) + 4ξ = N/D + 4ξ
        // is formed without cancellation, with one division.
        let g1 = GOLDEN_SQUARED;
        let a = u * root + 5f64.sqrt();
        let d = a * (g * g + g * g1 + g1 * g1) * g * g1;
        let n = -xi * (1.0 + u) * (8.0 * a + 4.0 * (4.0 * u * u + 5.0)) * (g * g1 - 1.0);
        3.0 * ((n + 4.0 * xi * d) / (4.0 * u * d)).ln_1p()
    } else {
        3.0 * ((1.0 + g + z) / (4.0 * u)).ln()
    };
    t / shape_per_mm
}

/// G^(−1/3) for G ∈ [1, 18] (the range of G(u) above): a least-squares cubic
/// first guess (within 13 %) and five division-free Newton steps
/// z ← z(4 − G z³)/3, which square the error each time (1e-1 → … → below
/// rounding). `inv_cbrt_matches_std` checks it to 4 ulp.
#[inline]
fn inv_cbrt_1_to_18(g: f64) -> f64 {
    let mut z = 0.983_280_454_107_464_1
        + g * (-0.112_355_168_633_411
            + g * (0.007_999_267_736_024_293 - 0.000_203_127_212_300_871_27 * g));
    for _ in 0..5 {
        z *= (4.0 - g * z * z * z) * (1.0 / 3.0);
    }
    z
}

/// The same inverse by Halley's method, as Golubev 2018 describes and Unity
/// implements it (`DisneyProfileCdfInverse`), iterated to full precision.
/// For ξ > ½ the residual is taken on the tail so precision holds near 1.
pub fn sample_radius_halley(xi: f64, shape_per_mm: f64) -> f64 {
    if !(xi > 0.0) {
        return 0.0;
    }
    let s = shape_per_mm;
    let use_tail = xi > 0.5;
    let u = 1.0 - xi;
    // Unity's first guess (10^ξ − 1)/s; near 1 the asymptote 3/s·ln(3/(4u)).
    let mut r = if use_tail {
        3.0 * (0.75 / u).ln().max(0.0) / s
    } else {
        (10f64.powf(xi) - 1.0) / s
    };
    let mut last = f64::INFINITY;
    for _ in 0..100 {
        let e1 = (-s * r).exp();
        let e3 = (-s * r / 3.0).exp();
        let f0 = if use_tail {
            u - tail_unit(s * r)
        } else {
            cdf_unit(s * r) - xi
        };
        let f1 = 0.25 * s * (e1 + e3);
        let f2 = -s * s / 12.0 * (3.0 * e1 + e3);
        let dr = f0 / (f1 * (1.0 - f0 * f2 / (2.0 * f1 * f1)));
        if !dr.is_finite() || dr.abs() >= last {
            break;
        }
        r = (r - dr).max(0.5 * r);
        last = dr.abs();
        if last <= 1e-16 * r {
            break;
        }
    }
    r
}

/// Checked entry point for the CLI: validates ξ and s.
pub fn sample_radius_checked(xi: f64, shape_per_mm: f64) -> Result<f64, ModelError> {
    check_xi("xi", xi)?;
    check_range(
        "shape_per_mm",
        shape_per_mm,
        1.0 / DISTANCE_RANGE_MM.1,
        1.0 / DISTANCE_RANGE_MM.0,
        " 1/mm",
    )?;
    Ok(sample_radius(xi, shape_per_mm))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::quad;

    fn skin() -> Burley {
        // Unity HDRP default skin scattering distance, as Golubev 2018 ships it in HDRP.
        Burley::from_scattering_distance([0.9, 0.5, 0.3], [0.756_862_8, 0.321_568_64, 0.2]).unwrap()
    }

    /// `model::axis_sigma_mm` against two closed forms. Burley: the radial
    /// density 2πr R(r)/A = (e^(−r/d) + e^(−r/3d))/(4d) (Christensen &
    /// Burley 2015 eq. 2) has ⟨r²⟩ = (2d³ + 2·27d³)/(4d) = 14d², so σ = √7·d.
    /// d'Eon's six Gaussians: a Gaussian of variance v has ⟨r²⟩ = 2v, so
    /// σ² = Σ wᵢvᵢ / Σ wᵢ per channel, red √(0.4935) from the table's own
    /// numbers; and one Gaussian of 7.41 mm² alone is σ = 2.72 mm, the
    /// "2.7 mm" diffusion radius FaceWorks gives for skin.
    #[test]
    fn axis_sigma_matches_burley_and_deon() {
        let p = skin();
        let sigma = crate::model::axis_sigma_mm(&p);
        for c in 0..3 {
            let want = 7f64.sqrt() * p.scattering_distance_mm()[c];
            assert!(
                (sigma[c] / want - 1.0).abs() < 1e-6,
                "channel {c}: {} vs {want}",
                sigma[c]
            );
        }
        let deon = crate::model::gaussian::GaussianSum::deon_skin();
        let sigma = crate::model::axis_sigma_mm(&deon);
        for c in 0..3 {
            let terms = crate::model::gaussian::DEON_SKIN;
            let w: f64 = terms.iter().map(|t| t.1[c]).sum();
            let wv: f64 = terms.iter().map(|t| t.1[c] * t.0).sum();
            let want = (wv / w).sqrt();
            assert!(
                (sigma[c] / want - 1.0).abs() < 1e-6,
                "d'Eon channel {c}: {} vs {want}",
                sigma[c]
            );
        }
        let widest = crate::model::gaussian::GaussianSum::new(&[(7.41, [1.0; 3])]).unwrap();
        let sigma = crate::model::axis_sigma_mm(&widest);
        assert!((sigma[0] - 2.722).abs() < 1e-3, "{}", sigma[0]);
    }

    /// Christensen & Burley 2015: ∫2πr R(r) dr = A, by adaptive quadrature.
    #[test]
    fn integrates_to_albedo() {
        let p = skin();
        for c in 0..3 {
            let f = |r: f64| 2.0 * PI * p.r_reflectance(r)[c];
            let v = quad::integrate_to_infinity(&f, 0.0, 1.0, 1e-13, 1e-13);
            assert!((v - p.albedo()[c]).abs() < 1e-10, "channel {c}: {v}");
        }
    }

    /// The CDF equals the running quadrature of the PDF (Golubev 2018 slide "PDF/CDF").
    #[test]
    fn cdf_matches_quadrature_of_pdf() {
        let p = skin();
        for &r in &[1e-4, 0.01, 0.3, 1.0, 4.0] {
            for c in 0..3 {
                let f = |x: f64| 2.0 * PI * p.r_reflectance(x)[c] / p.albedo()[c];
                let v = quad::integrate(&f, 0.0, r, 1e-15, 1e-14);
                assert!(
                    (v - p.cdf(r)[c]).abs() < 1e-12,
                    "r={r} c={c}: {v} vs {}",
                    p.cdf(r)[c]
                );
            }
        }
    }

    /// Transmittance closed form (Christensen & Burley 2015; Golubev 2018) against direct 2D quadrature.
    #[test]
    fn transmittance_closed_form_matches_quadrature() {
        let p = skin();
        for &d in &[0.0, 0.05, 0.5, 2.0, 6.0] {
            let a = p.transmittance(d);
            let b = crate::model::transmittance_by_quadrature(&p, d);
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() < 1e-9 * a[c].max(1e-12),
                    "d={d}: {a:?} {b:?}"
                );
            }
        }
    }

    /// Closed form and Halley agree to 1e-6 relative over ξ ∈ [0, 1), edges included.
    #[test]
    fn closed_form_and_halley_agree() {
        let mut xis: Vec<f64> = (0..2000).map(|i| i as f64 / 2000.0).collect();
        xis.extend([
            1e-300,
            1e-16,
            1e-9,
            0.5,
            0.999,
            1.0 - 1e-9,
            1.0 - 1e-15,
            1.0 - f64::EPSILON / 2.0,
        ]);
        for s in [1e-3, 1.0, 1e4] {
            for &xi in &xis {
                let a = sample_radius(xi, s);
                let b = sample_radius_halley(xi, s);
                assert!(a.is_finite() && b.is_finite());
                assert!(
                    (a - b).abs() <= 1e-6 * a.max(1e-300),
                    "xi={xi} s={s}: {a} vs {b}"
                );
            }
        }
    }

    /// Round trip: P(P⁻¹(ξ)) = ξ to near machine precision (on the tail near 1).
    #[test]
    fn inverse_round_trips() {
        for &xi in &[1e-12, 1e-6, 0.01, 0.3, 0.5, 0.7, 0.997, 1.0 - 1e-10] {
            let r = sample_radius(xi, 2.0);
            let back = if xi > 0.5 {
                1.0 - tail_unit(2.0 * r)
            } else {
                cdf_unit(2.0 * r)
            };
            let err = if xi > 0.5 {
                ((1.0 - back) - (1.0 - xi)).abs() / (1.0 - xi)
            } else {
                (back - xi).abs() / xi
            };
            assert!(err < 1e-12, "xi={xi}: {back} ({err})");
        }
    }

    /// Seed 000 writes the inverse with log₂. Evaluated that way the CDF of
    /// the result is not ξ, so the natural logarithm is the right reading.
    #[test]
    fn log2_reading_of_seed_000_does_not_invert_the_cdf() {
        let (xi, s): (f64, f64) = (0.5, 1.0);
        let u = 1.0 - xi;
        let g = (1.0 + 4.0 * u * (2.0 * u + (1.0 + 4.0 * u * u).sqrt())).cbrt();
        let arg = (1.0 + g + 1.0 / g) / (4.0 * u);
        let r_log2 = 3.0 * arg.log2() / s;
        let r_ln = 3.0 * arg.ln() / s;
        assert!((cdf_unit(s * r_ln) - xi).abs() < 1e-14);
        assert!((cdf_unit(s * r_log2) - xi).abs() > 0.05);
    }

    /// Unity HDRP's filter radius for its default skin (d_R = 0.7568628 mm):
    /// the 0.997 quantile. Reference: bisection on the closed-form CDF.
    #[test]
    fn radius_997_matches_bisection() {
        let s = 1.0 / 0.756_862_8;
        let (mut lo, mut hi) = (0.0, 100.0);
        for _ in 0..200 {
            let m = 0.5 * (lo + hi);
            if cdf_unit(s * m) < 0.997 {
                lo = m
            } else {
                hi = m
            }
        }
        assert!((sample_radius(0.997, s) - lo).abs() < 1e-12 * lo);
    }

    #[test]
    fn fits_match_published_equations_at_sample_points() {
        // Values of the printed polynomials at A = 0.5 (C&B 2015 eqs. 5, 6, 8).
        assert!((ScalingFit::Perpendicular.scale(0.5) - (1.35 + 7.0 * 0.027)).abs() < 1e-15);
        assert!((ScalingFit::DiffuseSurface.scale(0.5) - (1.4 + 3.5 * 0.09)).abs() < 1e-15);
        assert!(
            (ScalingFit::DiffuseMeanFreePath.scale(0.5) - (3.5 + 100.0 * 0.17f64.powi(4))).abs()
                < 1e-15
        );
        let b =
            Burley::from_mean_free_path([0.5; 3], [2.0; 3], ScalingFit::DiffuseSurface).unwrap();
        assert!((b.mean_free_path_mm(ScalingFit::DiffuseSurface)[0] - 2.0).abs() < 1e-12);
    }

    /// Ki₁(0) = π/2, and the closed-form strip CDF equals the generic
    /// acos-weighted quadrature of the radial PDF.
    #[test]
    fn strip_cdf_matches_generic_quadrature() {
        assert!((bickley_ki1(0.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
        let p = skin();
        for x in [-2.0, -0.1, 0.0, 0.03, 0.4, 1.5, 6.0] {
            let (a, b) = (p.strip_cdf(x), crate::model::strip_cdf_numerically(&p, x));
            for c in 0..3 {
                assert!(
                    (a[c] - b[c]).abs() < 1e-9,
                    "x={x} c={c}: {} vs {}",
                    a[c],
                    b[c]
                );
            }
        }
    }

    #[test]
    fn inv_cbrt_matches_std() {
        for i in 0..=100_000 {
            let g = 1.0 + 17.0 * i as f64 / 100_000.0;
            let (a, b) = (inv_cbrt_1_to_18(g), 1.0 / g.cbrt());
            assert!((a - b).abs() <= 4.0 * f64::EPSILON * b, "{g}: {a} vs {b}");
        }
        // The end points G(u = 0) = 1 and G(u = 1) = 9 + 4√5.
        assert!((inv_cbrt_1_to_18(9.0 + 4.0 * 5f64.sqrt()) - 1.0 / GOLDEN_SQUARED).abs() < 1e-15);
    }

    #[test]
    fn rejects_out_of_range_with_field_name() {
        let e = Burley::from_scattering_distance([0.5, 1.5, 0.5], [1.0; 3]).unwrap_err();
        assert!(e.to_string().contains("albedo.g"), "{e}");
        let e = Burley::from_scattering_distance([0.5; 3], [1.0, f64::NAN, 1.0]).unwrap_err();
        assert!(e.to_string().contains("scattering_distance_mm.g"), "{e}");
        assert!(sample_radius_checked(1.0, 1.0)
            .unwrap_err()
            .to_string()
            .contains("xi"));
    }

    /// Below 1e-6·d the closed form still holds (it used to return R at
    /// 1e-6·d): with A = 1 and d = 1 mm, R(r) = (e^(−r) + e^(−r/3))/(8π r)
    /// → 1/(4π r) as r → 0, so R(1e-9 mm) = 7.957747e7 mm⁻² (by hand:
    /// 1/(4π·1e-9)), a thousand times R(1e-6 mm); r = 0 keeps the
    /// documented value at r_floor_mm = 1e-6 mm, and 1e-310 stays finite.
    #[test]
    fn reflectance_below_the_floor_is_the_closed_form() {
        let b = Burley::from_scattering_distance([1.0; 3], [1.0; 3]).unwrap();
        let r9 = b.reflectance(1e-9)[0];
        assert!((r9 / 7.957747e7 - 1.0).abs() < 1e-6, "{r9}");
        let r6 = b.reflectance(1e-6)[0];
        assert!((r9 / r6 / 1000.0 - 1.0).abs() < 1e-5);
        assert_eq!(b.reflectance(0.0)[0], b.reflectance(b.r_floor_mm())[0]);
        assert!(b.reflectance(1e-310)[0].is_finite());
    }
}
