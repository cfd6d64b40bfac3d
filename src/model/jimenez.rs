//! Jimenez 2012 separable SSS as shipped in the Jimenez demo
//! (iryoku/separable-sss, `SeparableSSS::calculateKernel`), Unreal's
//! separable fallback and Godot.
//!
//! The demo's base profile is d'Eon's red channel without its narrowest
//! Gaussian ("directly bounced light, accounted by the strength"), with the
//! radius scaled per channel by 1/(0.001 + falloff). The kernel is
//! S(Δx) = strength·R(Δx/(0.001+falloff)) + (1 − strength)·δ(Δx)
//! (Jimenez 2012), R evaluated on the 1D offset and normalised over the
//! taps: a 1D kernel, which the two passes apply along x and then y.
//!
//! **The one reading of a Jimenez 2012 look** (issue 22), everywhere a look
//! is used (ground truth, tables, T(d), Burley's pattern, fits, exports):
//! the radial profile whose pre-integrated 1D kernel a_p(x) = ∫R(x, y) dy
//! (Jimenez et al. 2015 §4) is the demo's kernel before its cut at ±range.
//! The marginal of a 2D Gaussian of variance σ² per axis is the 1D Gaussian
//! of variance σ², so that profile is the sum of 2D Gaussians with
//! variances v_k(0.001+falloff)² and the weights the demo's 1D kernel
//! gives them: its term w_k·e^(−r²/2v_kf²)/(2πv_k) integrates over the
//! line to w_k·f/√(2πv_k), so weights strength·(w_k/√v_k)/Σ(w/√v), plus a
//! Dirac delta of weight 1 − strength: an energy-conserving blur (total 1).
//! The old reading weighted the terms by w_k/Σw, as a 2D sum, which is not
//! what the demo draws: its variance was 2.4× the demo kernel's at the
//! default skin (falloff 1), and `separable` and every other method drew
//! two different looks (`the_radial_reading_is_the_demos_kernel` checks
//! the marginal against the demo's formula; the demo's cut at ±2 mm, or ±3
//! above 20 taps, is the separable method's own approximation).

use super::gaussian::{GaussianSum, Term, DEON_SKIN};
use super::separable::{SeparableKernel, Tap};
use super::{check_range, check_rgb, rgb_map, ModelError, Rgb};

/// Unreal's and the Jimenez 2012 demo's default Subsurface Color / SSS Strength.
pub const DEFAULT_STRENGTH: Rgb = [0.48, 0.41, 0.28];
/// Unreal's and the Jimenez 2012 demo's default Falloff Color / SSS Falloff.
pub const DEFAULT_FALLOFF: Rgb = [1.0, 0.37, 0.3];

/// Valid strength and falloff per channel (`Jimenez2012::new` checks them;
/// the editor's fields take their range from here).
pub const STRENGTH_RANGE: (f64, f64) = (0.0, 1.0);
pub const FALLOFF_RANGE: (f64, f64) = (0.0, 1.0);

/// Tap counts the renderer supports (odd, so that offset 0 exists).
pub const TAPS_RANGE: (usize, usize) = (3, 127);

/// Jimenez 2012 parameters.
#[derive(Debug, Clone, PartialEq)]
pub struct Jimenez2012 {
    strength: Rgb,
    falloff: Rgb,
    profile: GaussianSum,
}

/// The demo's base profile: d'Eon's red weights without the first Gaussian.
fn base_terms() -> impl Iterator<Item = (f64, f64)> {
    DEON_SKIN.iter().skip(1).map(|(v, w)| (*v, w[0]))
}

/// Each base term's share of the demo's 1D kernel, (w/√v)/Σ(w/√v): the
/// line integral of w·e^(−x²/2vf²)/(2πv) is w·f/√(2πv), and the common
/// f/√(2π) cancels in the normalisation (see the module).
fn kernel_shares() -> impl Iterator<Item = (f64, f64)> {
    let sum: f64 = base_terms().map(|(v, w)| w / v.sqrt()).sum();
    base_terms().map(move |(v, w)| (v, w / v.sqrt() / sum))
}

/// The radial reading's terms for `strength` and falloff × `width_mm`.
fn radial_terms(strength: Rgb, falloff: Rgb, width_mm: f64) -> GaussianSum {
    let channels: [Vec<Term>; 3] = [0, 1, 2].map(|c| {
        let f = (0.001 + falloff[c]) * width_mm;
        kernel_shares()
            .map(|(v, share)| Term {
                weight: strength[c] * share,
                variance_mm2: v * f * f,
            })
            .collect()
    });
    GaussianSum::from_channels(channels, rgb_map(|c| 1.0 - strength[c]))
}

impl Jimenez2012 {
    /// strength and falloff ∈ [0, 1] per channel.
    pub fn new(strength: Rgb, falloff: Rgb) -> Result<Self, ModelError> {
        check_rgb("strength", strength, STRENGTH_RANGE.0, STRENGTH_RANGE.1, "")?;
        check_rgb("falloff", falloff, FALLOFF_RANGE.0, FALLOFF_RANGE.1, "")?;
        let profile = radial_terms(strength, falloff, 1.0);
        Ok(Self {
            strength,
            falloff,
            profile,
        })
    }

    pub fn strength(&self) -> Rgb {
        self.strength
    }

    pub fn falloff(&self) -> Rgb {
        self.falloff
    }

    /// The demo's `profile(r)` for one channel (2D Gaussian formula
    /// evaluated on the 1D offset, red weights, falloff-scaled radius).
    fn demo_profile(&self, channel: usize, r: f64) -> f64 {
        let rr = r / (0.001 + self.falloff[channel]);
        base_terms()
            .map(|(v, w)| w * (-(rr * rr) / (2.0 * v)).exp() / (2.0 * std::f64::consts::PI * v))
            .sum()
    }

    /// The 1D kernel of `calculateKernel`: N taps (odd), offsets
    /// RANGE·sign(o)·|o|^EXPONENT/RANGE^EXPONENT with RANGE = 3 above 20
    /// taps and 2 otherwise, EXPONENT = 2; trapezoid "area" weights;
    /// per-channel normalisation; centre first; then the strength lerp.
    pub fn kernel(&self, taps: usize) -> Result<SeparableKernel, ModelError> {
        check_taps(taps)?;
        const EXPONENT: i32 = 2;
        let range = if taps > 20 { 3.0 } else { 2.0 };
        let step = 2.0 * range / (taps - 1) as f64;
        let offsets: Vec<f64> = (0..taps)
            .map(|i| {
                let o: f64 = -range + i as f64 * step;
                range * o.signum() * o.abs().powi(EXPONENT) / range.powi(EXPONENT)
            })
            .collect();
        let mut k: Vec<(Rgb, f64)> = (0..taps)
            .map(|i| {
                let w0 = if i > 0 {
                    (offsets[i] - offsets[i - 1]).abs()
                } else {
                    0.0
                };
                let w1 = if i + 1 < taps {
                    (offsets[i] - offsets[i + 1]).abs()
                } else {
                    0.0
                };
                let area = 0.5 * (w0 + w1);
                (
                    rgb_map(|c| area * self.demo_profile(c, offsets[i])),
                    offsets[i],
                )
            })
            .collect();
        // Offset 0 first, as the demo orders it.
        let centre = k.remove(taps / 2);
        k.insert(0, centre);
        let sum = rgb_map(|c| k.iter().map(|t| t.0[c]).sum::<f64>());
        let taps_out = k
            .iter()
            .enumerate()
            .map(|(i, (w, o))| {
                let weight = rgb_map(|c| {
                    let n = w[c] / sum[c];
                    if i == 0 {
                        (1.0 - self.strength[c]) + self.strength[c] * n
                    } else {
                        self.strength[c] * n
                    }
                });
                Tap {
                    weight,
                    offset_mm: if i == 0 { 0.0 } else { *o },
                }
            })
            .collect();
        Ok(SeparableKernel { taps: taps_out })
    }
}

impl Jimenez2012 {
    /// The same kernel with every radius multiplied by `width_mm`, the
    /// physical length of one kernel unit (the demo's profile is in mm, so
    /// width 1 is the kernel itself). An engine that ships the demo's fixed
    /// kernel and only exposes its width (Godot 4's `subsurf_scatter_strength`)
    /// renders this profile: variances v_k·((0.001 + falloff)·width)², the
    /// weights and the Dirac delta unchanged.
    pub fn widened(&self, width_mm: f64) -> Result<GaussianSum, ModelError> {
        check_range("width", width_mm, 1e-6, 1e6, "mm")?;
        Ok(radial_terms(self.strength, self.falloff, width_mm))
    }
}

/// Validates a tap count: odd and within [`TAPS_RANGE`].
pub fn check_taps(taps: usize) -> Result<usize, ModelError> {
    check_range(
        "taps",
        taps as f64,
        TAPS_RANGE.0 as f64,
        TAPS_RANGE.1 as f64,
        "",
    )?;
    if taps.is_multiple_of(2) {
        return Err(ModelError::invalid(
            "taps",
            format!("must be odd so that offset 0 is a tap (got {taps})"),
        ));
    }
    Ok(taps)
}

super::delegate_radial_profile!(Jimenez2012, profile);

/// The demo's 11-tap kernel as printed in iryoku/separable-sss
/// `SeparableSSS.h` (its default strength and falloff), (r, g, b, offset),
/// centre first. Godot 4's `subsurface_scattering.glsl` ships the
/// non-negative half of the 11- and 25-tap ones (its `skin_kernel`).
#[cfg(test)]
pub(crate) const PUBLISHED_11: [[f64; 4]; 11] = [
    [0.560479, 0.669086, 0.784728, 0.0],
    [0.00471691, 0.000184771, 5.07566e-005, -2.0],
    [0.0192831, 0.00282018, 0.00084214, -1.28],
    [0.03639, 0.0130999, 0.00643685, -0.72],
    [0.0821904, 0.0358608, 0.0209261, -0.32],
    [0.0771802, 0.113491, 0.0793803, -0.08],
    [0.0771802, 0.113491, 0.0793803, 0.08],
    [0.0821904, 0.0358608, 0.0209261, 0.32],
    [0.03639, 0.0130999, 0.00643685, 0.72],
    [0.0192831, 0.00282018, 0.00084214, 1.28],
    [0.00471691, 0.000184771, 5.07565e-005, 2.0],
];

/// The demo's 17-tap kernel as printed in iryoku/separable-sss
/// `SeparableSSS.h` (its default strength and falloff), (r, g, b, offset),
/// centre first. Godot 4's `subsurface_scattering.glsl` ships the
/// non-negative half of the 11- and 25-tap ones (its `skin_kernel`).
#[cfg(test)]
pub(crate) const PUBLISHED_17: [[f64; 4]; 17] = [
    [0.536343, 0.624624, 0.748867, 0.0],
    [0.00317394, 0.000134823, 3.77269e-005, -2.0],
    [0.0100386, 0.000914679, 0.000275702, -1.53125],
    [0.0144609, 0.00317269, 0.00106399, -1.125],
    [0.0216301, 0.00794618, 0.00376991, -0.78125],
    [0.0347317, 0.0151085, 0.00871983, -0.5],
    [0.0571056, 0.0287432, 0.0172844, -0.28125],
    [0.0582416, 0.0659959, 0.0411329, -0.125],
    [0.0324462, 0.0656718, 0.0532821, -0.03125],
    [0.0324462, 0.0656718, 0.0532821, 0.03125],
    [0.0582416, 0.0659959, 0.0411329, 0.125],
    [0.0571056, 0.0287432, 0.0172844, 0.28125],
    [0.0347317, 0.0151085, 0.00871983, 0.5],
    [0.0216301, 0.00794618, 0.00376991, 0.78125],
    [0.0144609, 0.00317269, 0.00106399, 1.125],
    [0.0100386, 0.000914679, 0.000275702, 1.53125],
    [0.00317394, 0.000134823, 3.77269e-005, 2.0],
];

/// The demo's 25-tap kernel as printed in iryoku/separable-sss
/// `SeparableSSS.h` (its default strength and falloff), (r, g, b, offset),
/// centre first. Godot 4's `subsurface_scattering.glsl` ships the
/// non-negative half of the 11- and 25-tap ones (its `skin_kernel`).
#[cfg(test)]
pub(crate) const PUBLISHED_25: [[f64; 4]; 25] = [
    [0.530605, 0.613514, 0.739601, 0.0],
    [0.000973794, 1.11862e-005, 9.43437e-007, -3.0],
    [0.00333804, 7.85443e-005, 1.2945e-005, -2.52083],
    [0.00500364, 0.00020094, 5.28848e-005, -2.08333],
    [0.00700976, 0.00049366, 0.000151938, -1.6875],
    [0.0094389, 0.00139119, 0.000416598, -1.33333],
    [0.0128496, 0.00356329, 0.00132016, -1.02083],
    [0.017924, 0.00711691, 0.00347194, -0.75],
    [0.0263642, 0.0119715, 0.00684598, -0.520833],
    [0.0410172, 0.0199899, 0.0118481, -0.333333],
    [0.0493588, 0.0367726, 0.0219485, -0.1875],
    [0.0402784, 0.0657244, 0.04631, -0.0833333],
    [0.0211412, 0.0459286, 0.0378196, -0.0208333],
    [0.0211412, 0.0459286, 0.0378196, 0.0208333],
    [0.0402784, 0.0657244, 0.04631, 0.0833333],
    [0.0493588, 0.0367726, 0.0219485, 0.1875],
    [0.0410172, 0.0199899, 0.0118481, 0.333333],
    [0.0263642, 0.0119715, 0.00684598, 0.520833],
    [0.017924, 0.00711691, 0.00347194, 0.75],
    [0.0128496, 0.00356329, 0.00132016, 1.02083],
    [0.0094389, 0.00139119, 0.000416598, 1.33333],
    [0.00700976, 0.00049366, 0.000151938, 1.6875],
    [0.00500364, 0.00020094, 5.28848e-005, 2.08333],
    [0.00333804, 7.85443e-005, 1.2945e-005, 2.52083],
    [0.000973794, 1.11862e-005, 9.43437e-007, 3.0],
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::RadialProfile;

    /// The 11-, 17- and 25-tap kernels printed in iryoku/separable-sss
    /// `SeparableSSS.h` (generated by the demo with its default strength and
    /// falloff), to their printed 6 significant digits.
    #[test]
    fn reproduces_published_kernels() {
        let published: [(usize, &[[f64; 4]]); 3] = [
            (11, &PUBLISHED_11),
            (17, &PUBLISHED_17),
            (25, &PUBLISHED_25),
        ];
        let j = Jimenez2012::new(DEFAULT_STRENGTH, DEFAULT_FALLOFF).unwrap();
        for (n, table) in published {
            let k = j.kernel(n).unwrap();
            assert_eq!(k.taps.len(), n);
            for (tap, row) in k.taps.iter().zip(table) {
                for c in 0..3 {
                    let rel = (tap.weight[c] - row[c]).abs() / row[c];
                    assert!(rel < 2e-5, "n={n} {tap:?} vs {row:?}");
                }
                assert!(
                    (tap.offset_mm - row[3]).abs() < 1e-5,
                    "n={n} {tap:?} vs {row:?}"
                );
            }
        }
    }

    /// Kernels sum to one per channel; strength 0 gives the identity.
    #[test]
    fn kernel_normalisation_and_identity() {
        let j = Jimenez2012::new([0.3, 0.7, 1.0], [0.2, 0.5, 1.0]).unwrap();
        for n in [3, 7, 33, 127] {
            let s = j.kernel(n).unwrap().sum();
            for c in 0..3 {
                assert!((s[c] - 1.0).abs() < 1e-13);
            }
        }
        let id = Jimenez2012::new([0.0; 3], [0.5; 3])
            .unwrap()
            .kernel(11)
            .unwrap();
        assert_eq!(id.taps[0].weight, [1.0; 3]);
        assert!(id.taps[1..].iter().all(|t| t.weight == [0.0; 3]));
        assert!(j.kernel(10).is_err() && j.kernel(1).is_err());
    }

    /// The one reading: the radial profile's pre-integrated kernel is the
    /// demo's. Its strip CDF Φ(x) (the CDF of a_p, by the model's own
    /// quadrature of R: `strip_cdf_numerically`) against the demo's
    /// formula integrated over the line, written out here:
    /// ∫_{−∞}^{x} Σ w_k e^(−(t/f)²/2v_k)/(2πv_k) dt normalised, i.e.
    /// Σ w_k f/√(2πv_k)·½(1 + erf(x/(f√(2v_k)))) / Σ w_k f/√(2πv_k) for
    /// d'Eon's red terms 2–6 (0.100, 0.118, 0.113, 0.358, 0.078 at 0.0484,
    /// 0.187, 0.567, 1.99, 7.41 mm²), times strength, plus the Dirac's step.
    /// The demo's kernel is then a quadrature of this marginal, cut at
    /// ±2 mm up to 20 taps and ±3 mm above (calculateKernel's RANGE): the
    /// cut is the separable method's own truncation, and at falloff 1 it
    /// removes most of red's variance per axis (measured 0.363 mm² for the
    /// profile, 0.164 for the 17-tap kernel, 0.251 for the 25-tap one;
    /// green 0.043, 0.037, 0.041),
    /// where the old 2D-weighted reading was 2.4× wider still.
    #[test]
    fn the_radial_reading_is_the_demos_kernel() {
        let deon = [
            (0.0484, 0.100),
            (0.187, 0.118),
            (0.567, 0.113),
            (1.99, 0.358),
            (7.41, 0.078),
        ];
        let j = Jimenez2012::new(DEFAULT_STRENGTH, DEFAULT_FALLOFF).unwrap();
        for x in [-2.5f64, -0.7, -0.05, 0.03, 0.4, 1.3, 4.0] {
            let phi = crate::model::strip_cdf_numerically(&j, x);
            for c in 0..3 {
                let (s, f) = (DEFAULT_STRENGTH[c], 0.001 + DEFAULT_FALLOFF[c]);
                let mass = |v: f64, w: f64| w * f / (2.0 * std::f64::consts::PI * v).sqrt();
                let total: f64 = deon.iter().map(|(v, w)| mass(*v, *w)).sum();
                let cont: f64 = deon
                    .iter()
                    .map(|(v, w)| {
                        mass(*v, *w) * 0.5 * (1.0 + libm::erf(x / (f * (2.0 * v).sqrt())))
                    })
                    .sum::<f64>()
                    / total;
                let want = s * cont + (1.0 - s) * if x >= 0.0 { 1.0 } else { 0.0 };
                assert!(
                    (phi[c] - want).abs() < 1e-9,
                    "x {x} c {c}: {} vs {want}",
                    phi[c]
                );
            }
        }
        // Variance per axis: the profile's Σ w σ² against the kernels'.
        let (k17, k25) = (j.kernel(17).unwrap(), j.kernel(25).unwrap());
        let var = |k: &SeparableKernel, c: usize| -> f64 {
            k.taps
                .iter()
                .map(|t| t.weight[c] * t.offset_mm.powi(2))
                .sum()
        };
        for c in 0..3 {
            let profile: f64 = j
                .profile
                .channel_terms(c)
                .iter()
                .map(|t| t.weight * t.variance_mm2)
                .sum();
            let (a, b) = (var(&k17, c), var(&k25, c));
            eprintln!("channel {c}: profile {profile:.4} mm², 17 taps {a:.4}, 25 taps {b:.4}");
            // Cut and quadrature only ever narrow it; the wider cut less so.
            assert!(a < b && b <= profile * 1.02, "{c}: {a} {b} vs {profile}");
        }
    }

    /// As a radial profile: total 1, Dirac 1 − strength, CDF(0) = 1 − strength.
    #[test]
    fn radial_profile_energy() {
        let j = Jimenez2012::new(DEFAULT_STRENGTH, DEFAULT_FALLOFF).unwrap();
        let t = j.total_reflectance();
        let c0 = j.cdf(0.0);
        for c in 0..3 {
            assert!((t[c] - 1.0).abs() < 1e-14);
            assert!((c0[c] - (1.0 - DEFAULT_STRENGTH[c])).abs() < 1e-14);
        }
    }
}
