//! Pure math: diffusion profiles, kernels, sampling, lookup tables, fits and
//! unit conversions. Nothing here knows about wgpu or egui.
//!
//! Every model is a [`RadialProfile`]: a radially symmetric diffuse
//! reflectance profile R(r) per RGB channel, in mm⁻², with its total diffuse
//! reflectance ∫2πr R(r) dr, its radial CDF and inverse CDF, and the
//! thin-slab transmittance T(d) = ∫2πr R(√(r²+d²)) dr (Christensen & Burley 2015; Golubev 2018).

/// Implements [`RadialProfile`] for a wrapper by forwarding every method
/// to the inner profile in `$field`.
macro_rules! delegate_radial_profile {
    ($ty:ty, $field:ident) => {
        impl $crate::model::RadialProfile for $ty {
            fn reflectance(&self, radius_mm: f64) -> $crate::model::Rgb {
                self.$field.reflectance(radius_mm)
            }
            fn r_reflectance(&self, radius_mm: f64) -> $crate::model::Rgb {
                self.$field.r_reflectance(radius_mm)
            }
            fn total_reflectance(&self) -> $crate::model::Rgb {
                self.$field.total_reflectance()
            }
            fn dirac_weight(&self) -> $crate::model::Rgb {
                self.$field.dirac_weight()
            }
            fn cdf(&self, radius_mm: f64) -> $crate::model::Rgb {
                self.$field.cdf(radius_mm)
            }
            fn tail(&self, radius_mm: f64) -> $crate::model::Rgb {
                self.$field.tail(radius_mm)
            }
            fn inverse_cdf(&self, channel: usize, xi: f64) -> f64 {
                self.$field.inverse_cdf(channel, xi)
            }
            fn length_scale_mm(&self) -> f64 {
                self.$field.length_scale_mm()
            }
            fn r_floor_mm(&self) -> f64 {
                self.$field.r_floor_mm()
            }
            fn strip_cdf(&self, x_mm: f64) -> $crate::model::Rgb {
                self.$field.strip_cdf(x_mm)
            }
            fn transmittance(&self, thickness_mm: f64) -> $crate::model::Rgb {
                self.$field.transmittance(thickness_mm)
            }
        }
    };
}
pub(crate) use delegate_radial_profile;

pub mod burley;
pub mod colour;
pub mod dipole;
pub mod fit;
pub mod gaussian;
pub mod hankel;
pub mod jimenez;
pub mod lut;
pub mod measured;
pub mod multipole;
pub mod quad;
pub mod sampling;
pub mod separable;
pub mod stress;
pub mod tabulated;
pub mod units;

use std::f64::consts::PI;

/// One value per colour channel, in linear RGB order.
pub type Rgb = [f64; 3];

/// Default energy fraction for the "effective radius" (Unity HDRP's 0.997,
/// the three-sigma analogue; Golubev 2018).
pub const DEFAULT_ENERGY_FRACTION: f64 = 0.997;

/// Errors from building or querying a model. Each names the offending field.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ModelError {
    #[error("{field} = {value} is outside its range {}{unit}", range_text(*min, *max))]
    OutOfRange {
        field: String,
        value: f64,
        min: f64,
        max: f64,
        unit: &'static str,
    },
    #[error("{field} is not a finite number (got {value})")]
    NotFinite { field: String, value: f64 },
    #[error("{field}: {reason}")]
    Invalid { field: String, reason: String },
}

fn range_text(min: f64, max: f64) -> String {
    if max.is_infinite() || max >= f64::MAX {
        format!("[{min}, ∞)")
    } else {
        format!("[{min}, {max}]")
    }
}

impl ModelError {
    pub fn invalid(field: impl Into<String>, reason: impl Into<String>) -> Self {
        Self::Invalid {
            field: field.into(),
            reason: reason.into(),
        }
    }
}

/// Checks that `value` is finite and inside `[min, max]`; the error names `field`.
pub fn check_range(
    field: &str,
    value: f64,
    min: f64,
    max: f64,
    unit: &'static str,
) -> Result<f64, ModelError> {
    if !value.is_finite() {
        return Err(ModelError::NotFinite {
            field: field.to_owned(),
            value,
        });
    }
    if value < min || value > max || (max.is_infinite() && value.is_infinite()) {
        return Err(ModelError::OutOfRange {
            field: field.to_owned(),
            value,
            min,
            max,
            unit,
        });
    }
    Ok(value)
}

/// [`check_range`] for each channel; fields are named `field.r`, `field.g`, `field.b`.
pub fn check_rgb(
    field: &str,
    value: Rgb,
    min: f64,
    max: f64,
    unit: &'static str,
) -> Result<Rgb, ModelError> {
    for (c, v) in value.iter().enumerate() {
        check_range(&format!("{field}.{}", CHANNEL_NAMES[c]), *v, min, max, unit)?;
    }
    Ok(value)
}

/// Channel suffixes used in error messages and JSON.
pub const CHANNEL_NAMES: [&str; 3] = ["r", "g", "b"];

/// Checks a radius: finite and non-negative.
pub fn check_radius(field: &str, radius_mm: f64) -> Result<f64, ModelError> {
    check_range(field, radius_mm, 0.0, f64::INFINITY, " mm")
}

/// Checks a CDF value ξ ∈ [0, 1).
pub fn check_xi(field: &str, xi: f64) -> Result<f64, ModelError> {
    if !xi.is_finite() {
        return Err(ModelError::NotFinite {
            field: field.to_owned(),
            value: xi,
        });
    }
    if !(0.0..1.0).contains(&xi) {
        return Err(ModelError::OutOfRange {
            field: field.to_owned(),
            value: xi,
            min: 0.0,
            max: 1.0,
            unit: " (1 itself is excluded: it maps to an infinite radius)",
        });
    }
    Ok(xi)
}

/// Applies `f` to each channel.
#[inline]
pub fn rgb_map(f: impl Fn(usize) -> f64) -> Rgb {
    [f(0), f(1), f(2)]
}

/// A radially symmetric diffusion profile, one value per RGB channel.
///
/// Conventions, used by every model:
/// - `reflectance(r)` is the continuous part of R(r) in mm⁻². It is finite
///   for every finite r ≥ 0: where R has an integrable singularity at r = 0
///   (Burley's 1/r), r = 0 is evaluated at `r_floor_mm()`.
/// - `dirac_weight()` is energy concentrated at r = 0 (the Jimenez 2012
///   strength lerp puts 1 − strength there). It is part of the total and of
///   the CDF, which therefore starts at `dirac/total` for r = 0.
/// - `cdf(r)` is P(radius ≤ r) for the distribution 2πr R(r)/total and
///   `tail(r)` = 1 − cdf(r), each computed without cancellation. A channel
///   with zero total has cdf ≡ 1 (all of its nothing sits at r = 0).
pub trait RadialProfile: Send + Sync + std::fmt::Debug {
    /// R(r) per channel, mm⁻² (continuous part).
    fn reflectance(&self, radius_mm: f64) -> Rgb;

    /// r·R(r) per channel, mm⁻¹; finite at r = 0 (the limit).
    fn r_reflectance(&self, radius_mm: f64) -> Rgb {
        let r = radius_mm;
        // The limit at r = ∞ is 0 for any profile with finite energy; the
        // product would be ∞·0 = NaN (found by `scatterlab stress`).
        if r == f64::INFINITY {
            return [0.0; 3];
        }
        let v = self.reflectance(r);
        rgb_map(|c| r * v[c])
    }

    /// Total diffuse reflectance ∫2πr R(r) dr plus the Dirac weight (dimensionless).
    fn total_reflectance(&self) -> Rgb;

    /// Energy at r = 0 carried by a Dirac delta (dimensionless).
    fn dirac_weight(&self) -> Rgb {
        [0.0; 3]
    }

    /// Radial CDF P(R ≤ r) per channel.
    fn cdf(&self, radius_mm: f64) -> Rgb;

    /// 1 − CDF per channel, accurate where the CDF is close to 1.
    fn tail(&self, radius_mm: f64) -> Rgb;

    /// Radius (mm) below which the channel holds the fraction `xi` ∈ [0, 1)
    /// of its energy. The default solves cdf(r) = ξ by a safeguarded Newton
    /// iteration to ~1e-12 relative.
    fn inverse_cdf(&self, channel: usize, xi: f64) -> f64 {
        invert_cdf_numerically(self, channel, xi)
    }

    /// A length (mm) typical of the profile, used to seed numerics.
    fn length_scale_mm(&self) -> f64;

    /// Smallest radius at which `reflectance` is evaluated (see trait docs).
    fn r_floor_mm(&self) -> f64 {
        0.0
    }

    /// Radius per channel holding `fraction` of the energy (default 0.997).
    fn radius_for_energy(&self, fraction: f64) -> Rgb {
        rgb_map(|c| self.inverse_cdf(c, fraction))
    }

    /// Φ(x): the fraction of the energy whose x-coordinate is ≤ x, i.e. the
    /// CDF of the normalised pre-integrated 1D kernel a_p (Jimenez 2015 §4).
    /// Default: Φ(X) = 1 − ∫_X^∞ p(r)·acos(X/r)/π dr for X ≥ 0, where
    /// p = 2πrR/total, and Φ(−X) = 1 − Φ(X) apart from the Dirac jump.
    fn strip_cdf(&self, x_mm: f64) -> Rgb {
        strip_cdf_numerically(self, x_mm)
    }

    /// Thin-slab transmittance T(d) = ∫₀^∞ 2πr R(√(r²+d²)) dr per channel
    /// (Christensen & Burley 2015; Golubev 2018). With ρ = √(r²+d²) this is ∫_d^∞ 2πρ R(ρ) dρ, i.e.
    /// total × tail(d) (the Dirac part only counts at d = 0).
    fn transmittance(&self, thickness_mm: f64) -> Rgb {
        let total = self.total_reflectance();
        let dirac = self.dirac_weight();
        let tail = self.tail(thickness_mm);
        rgb_map(|c| {
            if thickness_mm <= 0.0 {
                total[c]
            } else {
                // tail already excludes the Dirac (it sits at r = 0 < d).
                (total[c] * tail[c]).min(total[c] - dirac[c]).max(0.0)
            }
        })
    }
}

/// Relative tolerance used by the generic inverse CDF.
const INVERSE_RTOL: f64 = 1e-13;

/// Solves cdf(r) = ξ for one channel: bracket by doubling, then Newton steps
/// on the CDF (or on the tail when ξ > 0.5, to keep precision), falling back
/// to bisection whenever a step leaves the bracket.
pub fn invert_cdf_numerically<P: RadialProfile + ?Sized>(p: &P, channel: usize, xi: f64) -> f64 {
    let c = channel;
    let total = p.total_reflectance()[c];
    if !(xi > 0.0) || total <= 0.0 {
        return 0.0;
    }
    if p.cdf(0.0)[c] >= xi {
        return 0.0; // the Dirac already holds this much
    }
    let use_tail = xi > 0.5;
    let target = if use_tail { 1.0 - xi } else { xi };
    // g(r) increases with r and has root where the CDF equals ξ.
    let g = |r: f64| {
        if use_tail {
            target - p.tail(r)[c]
        } else {
            p.cdf(r)[c] - target
        }
    };
    let mut hi = p.length_scale_mm().max(1e-12);
    let mut guard = 0;
    while g(hi) < 0.0 && guard < 2000 {
        hi *= 2.0;
        guard += 1;
    }
    let mut lo = 0.0_f64;
    let mut r = 0.5 * hi;
    for _ in 0..200 {
        let gr = g(r);
        if gr == 0.0 {
            return r;
        }
        if gr < 0.0 {
            lo = r;
        } else {
            hi = r;
        }
        // dP/dr = 2πr R(r)/total (continuous part).
        let pdf = 2.0 * PI * p.r_reflectance(r)[c] / total;
        let mut next = if pdf > 0.0 && pdf.is_finite() {
            r - gr / pdf
        } else {
            f64::NAN
        };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - r).abs() <= INVERSE_RTOL * next.abs() || hi - lo <= INVERSE_RTOL * hi {
            return next;
        }
        r = next;
    }
    r
}

/// See [`RadialProfile::strip_cdf`].
pub fn strip_cdf_numerically<P: RadialProfile + ?Sized>(p: &P, x_mm: f64) -> Rgb {
    let total = p.total_reflectance();
    let x = x_mm.abs();
    let scale = p.length_scale_mm();
    rgb_map(|c| {
        if total[c] <= 0.0 {
            return if x_mm >= 0.0 { 1.0 } else { 0.0 };
        }
        let f = |r: f64| {
            if r <= x {
                return 0.0;
            }
            2.0 * PI * p.r_reflectance(r)[c] / total[c] * (x / r).min(1.0).acos() / PI
        };
        let beyond = quad::integrate_to_infinity(&f, x, scale, 1e-14, 1e-12);
        // The Dirac at 0 is inside for every x ≥ 0 and outside below.
        if x_mm >= 0.0 {
            (1.0 - beyond).clamp(0.0, 1.0)
        } else {
            beyond.clamp(0.0, 1.0)
        }
    })
}

/// Direct quadrature of T(d) = ∫₀^∞ 2πr R(√(r²+d²)) dr, independent of the
/// tail identity used by [`RadialProfile::transmittance`]; used to check it.
/// The profile's per-axis standard deviation σ (mm) per channel: its
/// light's spread along one direction of the surface, σ² = ⟨r²⟩/2 for a
/// radially symmetric spread. ⟨r²⟩ = ∫₀^∞ 2r·tail(r) dr (integration by
/// parts of ∫ r² dP; the Dirac part sits at r = 0 and adds nothing),
/// integrated in ln r, where r²·tail(r) is smooth, by adaptive
/// quadrature. For a Gaussian of variance v it is √v; for Burley's
/// profile √7·d (`axis_sigma_matches_burley_and_deon`). FaceWorks'
/// "diffusion radius" of skin, 2.7 mm, is the σ of d'Eon's widest
/// Gaussian (7.41 mm²); `preintegrated` picks its blurred normal's mip
/// from it.
pub fn axis_sigma_mm<P: RadialProfile + ?Sized>(p: &P) -> Rgb {
    rgb_map(|c| {
        if p.tail(0.0)[c] <= 0.0 {
            return 0.0;
        }
        let scale = p.length_scale_mm().max(1e-9);
        // r²·tail(r) in ln r: 2r·tail(r) dr = 2r²·tail(r) d(ln r).
        let f = |u: f64| {
            let r = u.exp();
            2.0 * r * r * p.tail(r)[c]
        };
        let lo = (1e-9 * scale).ln();
        let hi = p.inverse_cdf(c, 1.0 - 1e-12).max(scale).ln() + 2.0;
        let mean_r2 = quad::integrate(&f, lo, hi, 1e-14 * scale * scale, 1e-10);
        (0.5 * mean_r2).max(0.0).sqrt()
    })
}

pub fn transmittance_by_quadrature<P: RadialProfile + ?Sized>(p: &P, thickness_mm: f64) -> Rgb {
    let d = thickness_mm;
    let scale = p.length_scale_mm().max(d);
    rgb_map(|c| {
        let f = |r: f64| {
            let rho = (r * r + d * d).sqrt();
            if rho <= 0.0 {
                return 0.0;
            }
            // 2πr R(ρ) = 2π (r/ρ) · ρR(ρ), finite at ρ → 0.
            2.0 * PI * (r / rho) * p.r_reflectance(rho)[c]
        };
        quad::integrate_to_infinity(&f, 0.0, scale, 1e-12, 1e-10)
    })
}

/// Relative L2 distance of r·R(r) between two profiles on [0, r_max] per
/// channel (used by fits and tests).
pub fn relative_l2_rr<A, B>(target: &A, model: &B, r_max: Rgb) -> Rgb
where
    A: RadialProfile + ?Sized,
    B: RadialProfile + ?Sized,
{
    rgb_map(|c| {
        let (num, den) = quad::gauss_legendre_panels(0.0, r_max[c], 64, |r| {
            let t = target.r_reflectance(r)[c];
            let m = model.r_reflectance(r)[c];
            ((m - t) * (m - t), t * t)
        });
        relative_l2(num, den)
    })
}

/// √(num/den) for squared norms, with 0/0 = 0 and x/0 = ∞.
pub(crate) fn relative_l2(num: f64, den: f64) -> f64 {
    if den > 0.0 {
        (num / den).sqrt()
    } else if num > 0.0 {
        f64::INFINITY
    } else {
        0.0
    }
}
