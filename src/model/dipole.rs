//! The dipole diffusion model in its corrected form (Mikkelsen 2009 §2.6,
//! eq. 30, as in Donner & Jensen 2005; Mikkelsen 2009).
//!
//! σ′t = σa + σ′s, α′ = σ′s/σ′t, σtr = √(3σa σ′t), D = 1/(3σ′t),
//! z_r = 1/σ′t, z_v = z_r + 4AD, A = (1 + F_dr)/(1 − F_dr),
//! d_r = √(r² + z_r²), d_v = √(r² + z_v²),
//! R(r) = α′/(4π)·[(σtr d_r + 1) z_r e^(−σtr d_r)/d_r³ + (σtr d_v + 1) z_v e^(−σtr d_v)/d_v³].
//!
//! Each source term integrates over the plane in closed form,
//! ∫_ρ^∞ 2πr·z(1 + σd)e^(−σd)/(4πd³) dr = ½·z·e^(−σ d(ρ))/d(ρ),
//! which gives the total (Jensen 2001's R_d) and the CDF (Mikkelsen eq. 40).

use super::measured::Material;
use super::{check_range, check_rgb, rgb_map, ModelError, RadialProfile, Rgb};
use std::f64::consts::PI;

/// Documented parameter ranges.
pub const SIGMA_A_RANGE: (f64, f64) = (0.0, 1e3);
pub const SIGMA_S_PRIME_RANGE: (f64, f64) = (0.0, 1e4);
pub const ETA_RANGE: (f64, f64) = (1.0, 2.0);

/// Unpolarised Fresnel reflectance for light going from index n_i to n_t,
/// `eta_t_over_i` = n_t/n_i, at incidence cosine `cos_i`.
pub fn fresnel_dielectric(eta_t_over_i: f64, cos_i: f64) -> f64 {
    let ci = cos_i.clamp(0.0, 1.0);
    let sin_t2 = (1.0 - ci * ci) / (eta_t_over_i * eta_t_over_i);
    if sin_t2 >= 1.0 {
        return 1.0;
    }
    let ct = (1.0 - sin_t2).sqrt();
    let n = eta_t_over_i;
    let rs = (ci - n * ct) / (ci + n * ct);
    let rp = (n * ci - ct) / (n * ci + ct);
    0.5 * (rs * rs + rp * rp)
}

/// Internal diffuse Fresnel reflectance by quadrature, Mikkelsen 2009 eq. 21
/// (with its 1/π): light inside a medium of relative index η = n_in/n_out
/// reflected back at the boundary, F_dr = 2∫₀¹ F_r(μ) μ dμ.
pub fn fdr_exact(eta: f64) -> f64 {
    let inv = 1.0 / eta;
    let f = |mu: f64| 2.0 * fresnel_dielectric(inv, mu) * mu;
    let mut breaks = vec![0.0];
    if eta > 1.0 {
        breaks.push((1.0 - inv * inv).sqrt()); // critical angle: TIR below it
    }
    breaks.push(1.0);
    super::quad::integrate_with_breaks(&f, &breaks, 1e-14, 1e-13)
}

/// Jensen et al. 2001's fit F_dr = −1.440/η² + 0.710/η + 0.668 + 0.0636η,
/// valid for η ≥ 1 (within 2e-3 of [`fdr_exact`] on [1, 2]).
pub fn fdr_jensen_fit(eta: f64) -> f64 {
    -1.440 / (eta * eta) + 0.710 / eta + 0.668 + 0.0636 * eta
}

/// The F_dr used by the models: Jensen's published fit for η ≥ 1 (as in the
/// papers whose numbers we reproduce), the exact integral below 1 (internal
/// interfaces of layered media), where the fit is not valid.
pub fn fdr(eta: f64) -> f64 {
    if eta >= 1.0 {
        fdr_jensen_fit(eta).max(0.0)
    } else {
        fdr_exact(eta)
    }
}

/// Boundary mismatch A = (1 + F_dr)/(1 − F_dr) (Mikkelsen 2009 eq. 23).
pub fn boundary_a(eta: f64) -> f64 {
    let f = fdr(eta);
    (1.0 + f) / (1.0 - f)
}

/// Optical properties of one homogeneous medium, per channel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Medium {
    pub sigma_a_per_mm: Rgb,
    pub sigma_s_prime_per_mm: Rgb,
}

impl Medium {
    pub fn validate(&self, prefix: &str) -> Result<(), ModelError> {
        check_rgb(
            &format!("{prefix}sigma_a_per_mm"),
            self.sigma_a_per_mm,
            SIGMA_A_RANGE.0,
            SIGMA_A_RANGE.1,
            " 1/mm",
        )?;
        check_rgb(
            &format!("{prefix}sigma_s_prime_per_mm"),
            self.sigma_s_prime_per_mm,
            SIGMA_S_PRIME_RANGE.0,
            SIGMA_S_PRIME_RANGE.1,
            " 1/mm",
        )?;
        for c in 0..3 {
            if self.sigma_a_per_mm[c] + self.sigma_s_prime_per_mm[c] < 1e-9 {
                return Err(ModelError::invalid(
                    format!(
                        "{prefix}sigma_a_per_mm.{} + sigma_s_prime_per_mm.{}",
                        super::CHANNEL_NAMES[c],
                        super::CHANNEL_NAMES[c]
                    ),
                    "σa + σ′s must be positive (a medium with no extinction has no profile)",
                ));
            }
        }
        Ok(())
    }

    /// Per-channel derived coefficients.
    pub fn channel(&self, c: usize) -> ChannelCoefficients {
        let sa = self.sigma_a_per_mm[c];
        let ssp = self.sigma_s_prime_per_mm[c];
        let st = sa + ssp;
        ChannelCoefficients {
            sigma_t_prime: st,
            reduced_albedo: ssp / st,
            sigma_tr: (3.0 * sa * st).sqrt(),
            diffusion: 1.0 / (3.0 * st),
            mean_free_path: 1.0 / st,
        }
    }
}

/// σ′t, α′, σtr, D and ℓ = 1/σ′t of one channel (mm⁻¹ / mm).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChannelCoefficients {
    pub sigma_t_prime: f64,
    pub reduced_albedo: f64,
    pub sigma_tr: f64,
    pub diffusion: f64,
    pub mean_free_path: f64,
}

/// z·(1 + σd)·e^(−σd)/d³ for one point source at signed height z.
#[inline]
pub(crate) fn source_term(z: f64, sigma: f64, r: f64) -> f64 {
    // hypot: r² overflows for r > 1e154 and made R(1e300) NaN (stress).
    let d = r.hypot(z);
    if d == f64::INFINITY {
        return 0.0; // (1 + σd)·e^(−σd) would be ∞·0
    }
    z * (1.0 + sigma * d) * (-sigma * d).exp() / (d * d * d)
}

/// ∫_ρ^∞ 2πr·source_term dr / (2π) = z·e^(−σ d(ρ))/d(ρ): the energy of one
/// source beyond radius ρ (×½ α′ gives reflectance units).
#[inline]
pub(crate) fn source_tail(z: f64, sigma: f64, rho: f64) -> f64 {
    let d = rho.hypot(z);
    if d == f64::INFINITY {
        return 0.0; // σ·d would be 0·∞ when σ = 0
    }
    z * (-sigma * d).exp() / d
}

/// source_tail(z, σ, 0) − source_tail(z, σ, ρ): the energy of one source
/// within radius ρ, without the cancellation of the difference (which
/// left the dipole's CDF at ξ = 10⁻¹² only 6·10⁻⁴ accurate; found by
/// `scatterlab stress`). With δ = d − |z| = ρ²/(d + |z|):
/// sign(z)·e^(−σ|z|)·(1 − e^(−ln(1 + δ/|z|) − σδ)).
#[inline]
pub(crate) fn source_head(z: f64, sigma: f64, rho: f64) -> f64 {
    let a = z.abs();
    if a == 0.0 {
        return 0.0;
    }
    let d = rho.hypot(z);
    let delta = rho * rho / (d + a);
    let delta = if delta.is_finite() { delta } else { d - a };
    // σ = 0 (no absorption) with δ = ∞ would give 0·∞.
    let x = (delta / a).ln_1p() + if sigma > 0.0 { sigma * delta } else { 0.0 };
    z.signum() * (-sigma * a).exp() * -(-x).exp_m1()
}

/// The semi-infinite dipole.
#[derive(Debug, Clone, PartialEq)]
pub struct Dipole {
    medium: Medium,
    eta: f64,
    z_r: Rgb,
    z_v: Rgb,
    coef: [ChannelCoefficients; 3],
}

impl Dipole {
    /// σa, σ′s in mm⁻¹ and the relative index η ∈ [1, 2].
    pub fn new(medium: Medium, eta: f64) -> Result<Self, ModelError> {
        check_range("eta", eta, ETA_RANGE.0, ETA_RANGE.1, "")?;
        Self::with_relative_index(medium, eta)
    }

    /// As [`Dipole::new`] with a relative index that may be below 1 (the
    /// base of a layer stack under a denser layer); η ∈ [0.5, 2].
    pub fn with_relative_index(medium: Medium, eta: f64) -> Result<Self, ModelError> {
        medium.validate("")?;
        check_range("eta (relative)", eta, 0.5, ETA_RANGE.1, "")?;
        let a = boundary_a(eta);
        let coef = [0, 1, 2].map(|c| medium.channel(c));
        let z_r = rgb_map(|c| coef[c].mean_free_path);
        let z_v = rgb_map(|c| z_r[c] + 4.0 * a * coef[c].diffusion);
        Ok(Self {
            medium,
            eta,
            z_r,
            z_v,
            coef,
        })
    }

    /// A named measured material (Jensen 2001, Narasimhan 2006).
    pub fn measured(material: &Material, eta: f64) -> Result<Self, ModelError> {
        Self::new(material.medium(), eta)
    }

    pub fn medium(&self) -> Medium {
        self.medium
    }
    pub fn eta(&self) -> f64 {
        self.eta
    }
    /// Depths of the real and virtual sources (mm).
    pub fn source_depths_mm(&self) -> (Rgb, Rgb) {
        (self.z_r, self.z_v)
    }
    pub fn coefficients(&self, c: usize) -> ChannelCoefficients {
        self.coef[c]
    }
}

impl RadialProfile for Dipole {
    fn reflectance(&self, radius_mm: f64) -> Rgb {
        rgb_map(|c| {
            let k = &self.coef[c];
            k.reduced_albedo / (4.0 * PI)
                * (source_term(self.z_r[c], k.sigma_tr, radius_mm)
                    + source_term(self.z_v[c], k.sigma_tr, radius_mm))
        })
    }

    /// Jensen 2001: R_d = α′/2·(1 + e^(−4/3·A·√(3(1−α′))))·e^(−√(3(1−α′))),
    /// here as ½α′(e^(−σtr z_r) + e^(−σtr z_v)), the same expression.
    fn total_reflectance(&self) -> Rgb {
        rgb_map(|c| {
            let k = &self.coef[c];
            0.5 * k.reduced_albedo
                * ((-k.sigma_tr * self.z_r[c]).exp() + (-k.sigma_tr * self.z_v[c]).exp())
        })
    }

    fn cdf(&self, radius_mm: f64) -> Rgb {
        rgb_map(|c| {
            let s = self.coef[c].sigma_tr;
            let (zr, zv) = (self.z_r[c], self.z_v[c]);
            let num = source_head(zr, s, radius_mm) + source_head(zv, s, radius_mm);
            let den = (-s * zr).exp() + (-s * zv).exp();
            if den > 0.0 {
                (num / den).clamp(0.0, 1.0)
            } else {
                1.0
            }
        })
    }

    /// Mikkelsen 2009 eq. 40: ε(ρ) = [z_r e^(−σ d_r)/d_r + z_v e^(−σ d_v)/d_v] / [e^(−σ z_r) + e^(−σ z_v)].
    fn tail(&self, radius_mm: f64) -> Rgb {
        rgb_map(|c| {
            let s = self.coef[c].sigma_tr;
            let (zr, zv) = (self.z_r[c], self.z_v[c]);
            let num = source_tail(zr, s, radius_mm) + source_tail(zv, s, radius_mm);
            let den = (-s * zr).exp() + (-s * zv).exp();
            if den > 0.0 {
                (num / den).clamp(0.0, 1.0)
            } else {
                0.0
            }
        })
    }

    fn length_scale_mm(&self) -> f64 {
        (0..3)
            .map(|c| {
                let k = &self.coef[c];
                if k.sigma_tr > 0.0 {
                    (1.0 / k.sigma_tr).min(1e3 * self.z_v[c])
                } else {
                    10.0 * self.z_v[c]
                }
            })
            .fold(1e-9, f64::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::measured;
    use crate::model::quad;

    /// Jensen 2001's closed form for the total diffuse reflectance.
    fn jensen_rd(alpha: f64, eta: f64) -> f64 {
        let a = boundary_a(eta);
        let s = (3.0 * (1.0 - alpha)).sqrt();
        0.5 * alpha * (1.0 + (-4.0 / 3.0 * a * s).exp()) * (-s).exp()
    }

    #[test]
    fn fdr_fit_tracks_exact_integral() {
        for i in 0..=20 {
            let eta = 1.0 + i as f64 * 0.05;
            let (a, b) = (fdr_exact(eta), fdr_jensen_fit(eta));
            assert!((a - b).abs() < 2e-3, "eta={eta}: exact {a} fit {b}");
        }
        assert!(fdr_exact(1.0).abs() < 1e-12);
        // Below 1 (denser neighbour) the boundary reflects little.
        assert!(fdr_exact(0.95) < 0.02 && fdr_exact(0.95) > 0.0);
    }

    #[test]
    fn total_matches_jensen_closed_form_and_quadrature() {
        let m = measured::find("Skin1").unwrap();
        let d = Dipole::measured(&m, 1.3).unwrap();
        let t = d.total_reflectance();
        for c in 0..3 {
            let k = d.coefficients(c);
            assert!((t[c] - jensen_rd(k.reduced_albedo, 1.3)).abs() < 1e-14);
            let q = quad::integrate_to_infinity(
                &|r: f64| 2.0 * PI * r * d.reflectance(r)[c],
                0.0,
                0.5,
                1e-14,
                1e-12,
            );
            assert!((q - t[c]).abs() < 1e-9, "c={c}: {q} vs {}", t[c]);
        }
    }

    /// Jensen et al. 2001 fitted σa, σ′s with the dipole at η = 1.3 using
    /// the measured total diffuse reflectance as a constraint; those
    /// measured R_d (two decimals) are what Unreal Engine 5's subsurface
    /// presets store as SurfaceAlbedo (AssetDefinition_SubsurfaceProfile.cpp).
    /// The dipole must land on them within the fit's residual: every
    /// material within 0.01 except Marble, the outlier, within 0.06.
    #[test]
    fn reproduces_measured_total_reflectance() {
        let published = [
            ("Skin1", [0.44, 0.22, 0.13]),
            ("Skin2", [0.63, 0.44, 0.34]),
            ("Marble", [0.83, 0.79, 0.75]),
            ("Ketchup", [0.16, 0.01, 0.00]),
            ("Wholemilk", [0.91, 0.88, 0.76]),
            ("Apple", [0.85, 0.84, 0.53]),
        ];
        for (name, albedo) in published {
            let d = Dipole::measured(&measured::find(name).unwrap(), 1.3).unwrap();
            let t = d.total_reflectance();
            for c in 0..3 {
                let bound = if name == "Marble" { 0.06 } else { 0.01 };
                assert!(
                    (t[c] - albedo[c]).abs() <= bound,
                    "{name} c={c}: {} vs {}",
                    t[c],
                    albedo[c]
                );
            }
        }
    }

    #[test]
    fn cdf_matches_quadrature() {
        let d = Dipole::new(
            Medium {
                sigma_a_per_mm: [0.032, 0.17, 0.48],
                sigma_s_prime_per_mm: [0.74, 0.88, 1.01],
            },
            1.3,
        )
        .unwrap();
        let tot = d.total_reflectance();
        for &rho in &[0.1, 1.0, 5.0] {
            for c in 0..3 {
                let q = quad::integrate(
                    &|r: f64| 2.0 * PI * r * d.reflectance(r)[c],
                    0.0,
                    rho,
                    1e-15,
                    1e-13,
                );
                assert!((q / tot[c] - d.cdf(rho)[c]).abs() < 1e-10);
            }
        }
    }

    #[test]
    fn edges_stay_finite() {
        for (sa, ss) in [(0.0, 1.0), (1.0, 0.0), (1e3, 1e-6), (1e-9, 1e4)] {
            for eta in [1.0, 2.0] {
                let d = Dipole::new(
                    Medium {
                        sigma_a_per_mm: [sa; 3],
                        sigma_s_prime_per_mm: [ss; 3],
                    },
                    eta,
                )
                .unwrap();
                for r in [0.0, 1e-9, 1.0, 1e6] {
                    for v in d
                        .reflectance(r)
                        .into_iter()
                        .chain(d.cdf(r))
                        .chain(d.tail(r))
                    {
                        assert!(v.is_finite() && v >= 0.0, "sa={sa} ss={ss} r={r}: {v}");
                    }
                }
                assert!(d.radius_for_energy(0.997).iter().all(|r| r.is_finite()));
            }
        }
        let e = Dipole::new(
            Medium {
                sigma_a_per_mm: [0.0; 3],
                sigma_s_prime_per_mm: [0.0; 3],
            },
            1.3,
        )
        .unwrap_err();
        assert!(e.to_string().contains("sigma_a_per_mm.r"), "{e}");
        assert!(Dipole::new(
            Medium {
                sigma_a_per_mm: [0.1; 3],
                sigma_s_prime_per_mm: [1.0; 3]
            },
            2.5
        )
        .unwrap_err()
        .to_string()
        .contains("eta"));
    }
}
