//! The numerical stress report (`scatterlab stress`): every model swept
//! across its documented parameter range (random points and the edges)
//! against references computed independently of the code under test.
//!
//! - **R(r)**: the model's closed form written out again here from its
//!   paper (Burley 2015; Gaussian sums, d'Eon 2007 / Jimenez 2012 / 2015;
//!   Jensen 2001's dipole; Donner & Jensen 2005's slab multipole as the
//!   reference for a one-layer stack, whose R goes through FFTLog).
//! - **CDF**: adaptive Gauss–Kronrod quadrature of 2πr·R(r) at 10⁻¹²
//!   relative, inside and outside the radius; the smaller of CDF and tail is
//!   compared, so the error is relative where it is small.
//! - **Inverse CDF**: r = inverse_cdf(ξ), then cdf(r) (or tail(r) above ½)
//!   against ξ (or 1 − ξ), relative.
//! - **Kernels**: Jimenez 2015 importance-sampled separable taps (7, 17,
//!   33) and the Jimenez 2012 kernel sum to 1 per channel.
//! - **NaN / Inf**: every value computed, including radii 0, 10⁻³⁰⁰,
//!   10³⁰⁰ and ∞ and ξ at 0 and 1 − 2⁻⁵³.

use super::burley::Burley;
use super::dipole::{boundary_a, Dipole, Medium};
use super::gaussian::{GaussianSum, DEON_SKIN};
use super::jimenez::Jimenez2012;
use super::multipole::{Layer, LayeredMultipole, MultipoleSlab};
use super::quad::{integrate_to_infinity, integrate_with_breaks};
use super::separable::{ArtistTwoGaussian, SeparableKernel};
use super::{measured, ModelError, RadialProfile, Rgb};
use serde::Serialize;
use std::f64::consts::PI;

/// CDF and tail errors are measured where the reference exceeds this; the
/// quadrature's absolute tolerance is 10⁻¹⁶ of the channel's energy, so the
/// reference itself is good to 10⁻⁷ relative there.
pub const CDF_FLOOR: f64 = 1e-9;

/// One model's worst figures over the sweep.
#[derive(Debug, Clone, Serialize)]
pub struct ModelStress {
    pub model: &'static str,
    /// Parameter sets tried (random and edges).
    pub cases: usize,
    /// Values computed (every channel counts).
    pub evaluations: u64,
    pub non_finite: u64,
    /// Where the first NaN / Inf came from.
    pub non_finite_at: String,
    /// Worst |R − R_ref|/R_ref, and the parameters and radius where.
    pub worst_r_rel: f64,
    pub worst_r_at: String,
    /// What R was compared against.
    pub r_reference: &'static str,
    pub worst_cdf_rel: f64,
    pub worst_cdf_at: String,
    pub worst_inverse_rel: f64,
    pub worst_inverse_at: String,
    /// Worst |Σ taps − 1| over the separable kernels.
    pub worst_kernel_norm: f64,
    pub worst_kernel_at: String,
    /// CPU time of the model's cases (s), summed over the threads.
    pub seconds: f64,
}

/// The whole report.
#[derive(Debug, Clone, Serialize)]
pub struct StressReport {
    pub seed: u64,
    pub random_cases_per_model: usize,
    pub cdf_floor: f64,
    pub models: Vec<ModelStress>,
}

impl StressReport {
    pub fn total_non_finite(&self) -> u64 {
        self.models.iter().map(|m| m.non_finite).sum()
    }
}

/// SplitMix64: a tiny deterministic generator (fixed seeds, no dependency),
/// also what the hostile-input tests mutate presets with.
pub struct Rng(pub u64);

impl Rng {
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1), 53 bits.
    pub fn unit(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in 0..n (n > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next_u64() % n as u64) as usize
    }
    fn log_range(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + self.unit() * (hi.ln() - lo.ln())).exp()
    }
    /// A value in [lo, hi] that is an edge one time in five.
    fn edged(&mut self, lo: f64, hi: f64, log: bool) -> f64 {
        match self.next_u64() % 10 {
            0 => lo,
            1 => hi,
            _ if log => self.log_range(lo, hi),
            _ => lo + self.unit() * (hi - lo),
        }
    }
    fn rgb(&mut self, lo: f64, hi: f64, log: bool) -> Rgb {
        [0, 1, 2].map(|_| self.edged(lo, hi, log))
    }
}

/// A parameter set under test: the profile, its reference r·R(r) per
/// channel (mm⁻¹), and a description for the report.
struct Case {
    profile: Box<dyn RadialProfile>,
    reference_rr: Option<Box<dyn Fn(f64) -> Rgb>>,
    /// Compare R only within the channel's [0.001, 0.999] energy radii
    /// (tabulated profiles; closed forms are compared everywhere).
    bulk_only: bool,
    label: String,
}

/// The running worst figures of one model.
struct Tally {
    stress: ModelStress,
}

impl Tally {
    fn new(model: &'static str, r_reference: &'static str) -> Self {
        Self {
            stress: ModelStress {
                model,
                cases: 0,
                evaluations: 0,
                non_finite: 0,
                non_finite_at: String::new(),
                worst_r_rel: 0.0,
                worst_r_at: String::new(),
                r_reference,
                worst_cdf_rel: 0.0,
                worst_cdf_at: String::new(),
                worst_inverse_rel: 0.0,
                worst_inverse_at: String::new(),
                worst_kernel_norm: 0.0,
                worst_kernel_at: String::new(),
                seconds: 0.0,
            },
        }
    }
    fn values(&mut self, v: &[f64], what: impl FnOnce() -> String) {
        self.stress.evaluations += v.len() as u64;
        let bad = v.iter().filter(|x| !x.is_finite()).count() as u64;
        if bad > 0 && self.stress.non_finite == 0 {
            self.stress.non_finite_at = what();
        }
        self.stress.non_finite += bad;
    }
    fn worst(slot: &mut f64, at: &mut String, err: f64, label: impl FnOnce() -> String) {
        // A NaN error is the worst of all.
        if err.is_nan() || err > *slot {
            *slot = if err.is_nan() { f64::INFINITY } else { err };
            *at = label();
        }
    }
}

fn rel(a: f64, b: f64) -> f64 {
    if a == b {
        0.0
    } else {
        (a - b).abs() / b.abs()
    }
}

/// Radii (mm) on which a case is checked: ten decades around its length
/// scale plus each channel's 0.001 / 0.5 / 0.999 energy radii.
fn radii(p: &dyn RadialProfile) -> Vec<f64> {
    let l = p.length_scale_mm().max(1e-300);
    let mut r: Vec<f64> = (-6..=4).map(|k| l * 10f64.powi(k)).collect();
    for f in [0.001, 0.5, 0.999] {
        r.extend(p.radius_for_energy(f));
    }
    r.retain(|x| x.is_finite() && *x > 0.0);
    r
}

/// Every output at extreme arguments, for the NaN / Inf count only.
fn extremes(case: &Case, t: &mut Tally) {
    let p = &*case.profile;
    for r in [0.0, 1e-300, 1e-12, 1e12, 1e300, f64::INFINITY] {
        for (name, v) in [
            ("R", p.reflectance(r)),
            ("r·R", p.r_reflectance(r)),
            ("cdf", p.cdf(r)),
            ("tail", p.tail(r)),
            ("T", p.transmittance(r)),
        ] {
            t.values(&v, || format!("{name}({r:e}) = {v:?}, {}", case.label));
        }
    }
    for xi in [0.0, 1e-300, 0.5, 1.0 - f64::EPSILON] {
        let r = [0, 1, 2].map(|c| p.inverse_cdf(c, xi));
        t.values(&r, || {
            format!("inverse_cdf({xi:e}) = {r:?}, {}", case.label)
        });
    }
    let total = p.total_reflectance();
    t.values(&total, || format!("total = {total:?}, {}", case.label));
    let phi = p.strip_cdf(p.length_scale_mm());
    t.values(&phi, || format!("strip_cdf = {phi:?}, {}", case.label));
}

fn check_r(case: &Case, t: &mut Tally) {
    let Some(reference) = &case.reference_rr else {
        return;
    };
    let p = &*case.profile;
    let lo = p.radius_for_energy(0.001);
    let hi = p.radius_for_energy(0.999);
    for r in radii(p) {
        let (got, want) = (p.r_reflectance(r), reference(r));
        t.values(&got, || format!("r·R({r:e}) = {got:?}, {}", case.label));
        for c in 0..3 {
            if case.bulk_only && !(r >= lo[c] && r <= hi[c]) {
                continue;
            }
            // Below 1e-290 the reference itself underflows.
            if want[c].abs() < 1e-290 && got[c].abs() < 1e-290 {
                continue;
            }
            let s = &mut t.stress;
            Tally::worst(
                &mut s.worst_r_rel,
                &mut s.worst_r_at,
                rel(got[c], want[c]),
                || format!("{}, channel {c}, r = {r:.3e} mm", case.label),
            );
        }
    }
}

/// Energy of one channel inside and outside r by quadrature (reference),
/// to 10⁻¹² relative or 10⁻¹⁶ of `energy` absolute. Both sides are split
/// geometrically so that no feature can fall between the nodes of one
/// panel: inside at r·4⁻ᵏ (k = 1…30), outside at r·2ᵏ up to 10⁷ mm (a
/// 1 km-wide Gaussian is the widest documented; a stopping rule on quiet
/// panels would end in the gap between two far-apart terms).
fn energies(p: &dyn RadialProfile, c: usize, r: f64, energy: f64) -> (f64, f64) {
    const FAR_MM: f64 = 1e7;
    let f = |x: f64| 2.0 * PI * p.r_reflectance(x)[c];
    let abs = 1e-16 * energy;
    let mut inner: Vec<f64> = (0..=30).rev().map(|k| r * 0.25f64.powi(k)).collect();
    inner.insert(0, 0.0);
    let inside = integrate_with_breaks(&f, &inner, abs, 1e-12);
    let mut outer = vec![r];
    let mut a = r.max(1e-12);
    while a < FAR_MM {
        a *= 2.0;
        outer.push(a);
    }
    let outside =
        integrate_with_breaks(&f, &outer, abs, 1e-12) + integrate_to_infinity(&f, a, a, abs, 1e-12);
    (inside, outside)
}

fn check_cdf(case: &Case, t: &mut Tally) {
    let p = &*case.profile;
    let (total, dirac) = (p.total_reflectance(), p.dirac_weight());
    for r in radii(p) {
        let (cdf, tail) = (p.cdf(r), p.tail(r));
        t.values(&cdf, || format!("cdf({r:e}) = {cdf:?}, {}", case.label));
        t.values(&tail, || format!("tail({r:e}) = {tail:?}, {}", case.label));
        for c in 0..3 {
            if total[c] <= 0.0 {
                continue;
            }
            let (inside, outside) = energies(p, c, r, total[c] - dirac[c]);
            let sum = dirac[c] + inside + outside;
            let (ref_cdf, ref_tail) = ((dirac[c] + inside) / sum, outside / sum);
            let err = if ref_cdf <= 0.5 {
                (ref_cdf >= CDF_FLOOR).then(|| rel(cdf[c], ref_cdf))
            } else {
                (ref_tail >= CDF_FLOOR).then(|| rel(tail[c], ref_tail))
            };
            if let Some(err) = err {
                let s = &mut t.stress;
                Tally::worst(&mut s.worst_cdf_rel, &mut s.worst_cdf_at, err, || {
                    format!("{}, channel {c}, r = {r:.3e} mm", case.label)
                });
            }
        }
    }
}

fn check_inverse(case: &Case, t: &mut Tally, rng: &mut Rng) {
    let p = &*case.profile;
    let (total, dirac) = (p.total_reflectance(), p.dirac_weight());
    let mut xis = vec![1e-12, 1e-6, 1e-3, 0.1, 0.5, 0.9, 0.997, 1.0 - 1e-9];
    xis.extend((0..4).map(|_| rng.unit()));
    for xi in xis {
        for c in 0..3 {
            // Below the Dirac's share every ξ maps to r = 0.
            if total[c] <= 0.0 || xi <= dirac[c] / total[c] {
                continue;
            }
            let r = p.inverse_cdf(c, xi);
            t.values(&[r], || {
                format!("inverse_cdf({c}, {xi:e}) = {r}, {}", case.label)
            });
            let err = if xi <= 0.5 {
                rel(p.cdf(r)[c], xi)
            } else {
                rel(p.tail(r)[c], 1.0 - xi)
            };
            let s = &mut t.stress;
            Tally::worst(
                &mut s.worst_inverse_rel,
                &mut s.worst_inverse_at,
                err,
                || format!("{}, channel {c}, ξ = {xi:.6e}", case.label),
            );
        }
    }
}

/// Kernels sum to 1 in every channel with energy and to 0 in a channel
/// without (the convention of `SeparableKernel::importance_sampled`).
fn check_kernels(case: &Case, t: &mut Tally) {
    let total = case.profile.total_reflectance();
    for taps in [7, 17, 33] {
        let Ok(k) = SeparableKernel::importance_sampled(&*case.profile, taps) else {
            t.values(&[f64::NAN], || {
                format!("no {taps}-tap kernel, {}", case.label)
            });
            continue;
        };
        let sum = k.sum();
        t.values(&sum, || {
            format!("{taps}-tap kernel sum {sum:?}, {}", case.label)
        });
        for (c, v) in sum.iter().enumerate() {
            let want = if total[c] > 0.0 { 1.0 } else { 0.0 };
            let s = &mut t.stress;
            Tally::worst(
                &mut s.worst_kernel_norm,
                &mut s.worst_kernel_at,
                (v - want).abs(),
                || format!("{}, {taps} taps, channel {c}", case.label),
            );
        }
    }
}

fn fmt3(v: Rgb) -> String {
    format!("({:.4e}, {:.4e}, {:.4e})", v[0], v[1], v[2])
}

/// Burley 2015: r·R(r) = A·s·(e^(−sr) + e^(−sr/3))/(8π).
fn burley_case(rng: &mut Rng) -> Result<Case, ModelError> {
    let a = rng.rgb(0.0, 1.0, false);
    let d = rng.rgb(1e-4, 1e3, true);
    let label = format!("A = {}, d = {} mm", fmt3(a), fmt3(d));
    Ok(Case {
        profile: Box::new(Burley::from_scattering_distance(a, d)?),
        reference_rr: Some(Box::new(move |r| {
            [0, 1, 2].map(|c| {
                let s = 1.0 / d[c];
                a[c] * s * ((-s * r).exp() + (-s * r / 3.0).exp()) / (8.0 * PI)
            })
        })),
        bulk_only: false,
        label,
    })
}

/// Σ w·e^(−r²/2v)/(2πv) times r, for terms per channel.
fn gaussian_rr(terms: [Vec<(f64, f64)>; 3]) -> Box<dyn Fn(f64) -> Rgb> {
    Box::new(move |r| {
        [0, 1, 2].map(|c| {
            terms[c]
                .iter()
                .map(|(v, w)| r * w * (-(r * r) / (2.0 * v)).exp() / (2.0 * PI * v))
                .sum()
        })
    })
}

fn gaussians_case(rng: &mut Rng) -> Result<Case, ModelError> {
    let n = 1 + (rng.next_u64() % 6) as usize;
    let terms: Vec<(f64, Rgb)> = (0..n)
        .map(|_| (rng.edged(1e-10, 1e6, true), rng.rgb(0.0, 1.0, false)))
        .collect();
    let label = format!(
        "{n} terms, variances {:?} mm²",
        terms.iter().map(|t| t.0).collect::<Vec<_>>()
    );
    let per_channel = [0, 1, 2].map(|c| terms.iter().map(|(v, w)| (*v, w[c])).collect());
    Ok(Case {
        profile: Box::new(GaussianSum::new(&terms)?),
        reference_rr: Some(gaussian_rr(per_channel)),
        bulk_only: false,
        label,
    })
}

/// Jimenez 2012: d'Eon's red terms 2–6 with variances × (0.001 + falloff)²
/// and the weights of the demo's 1D kernel, strength·(w/√v)/Σ(w/√v) (the
/// radial profile whose pre-integrated kernel is the demo's; Jimenez 2012,
/// Jimenez et al. 2015 §4).
fn jimenez_case(rng: &mut Rng) -> Result<Case, ModelError> {
    let (s, f) = (rng.rgb(0.0, 1.0, false), rng.rgb(0.0, 1.0, false));
    let sum: f64 = DEON_SKIN[1..].iter().map(|t| t.1[0] / t.0.sqrt()).sum();
    let per_channel = [0, 1, 2].map(|c| {
        let k = (0.001 + f[c]).powi(2);
        DEON_SKIN[1..]
            .iter()
            .map(|(v, w)| (v * k, s[c] * w[0] / v.sqrt() / sum))
            .collect()
    });
    Ok(Case {
        profile: Box::new(Jimenez2012::new(s, f)?),
        reference_rr: Some(gaussian_rr(per_channel)),
        bulk_only: false,
        label: format!("strength = {}, falloff = {}", fmt3(s), fmt3(f)),
    })
}

/// Jimenez 2015 §5: w·G(σn·s) + (1 − w)·G(σf·s).
fn artist_case(rng: &mut Rng) -> Result<Case, ModelError> {
    let (n, f) = (rng.rgb(1e-6, 1.0, true), rng.rgb(1e-6, 1.0, true));
    let (w, s) = (rng.edged(0.0, 1.0, false), rng.edged(1e-4, 1e3, true));
    let per_channel =
        [0, 1, 2].map(|c| vec![((n[c] * s).powi(2), w), ((f[c] * s).powi(2), 1.0 - w)]);
    Ok(Case {
        profile: Box::new(ArtistTwoGaussian::new(n, f, w, s)?),
        reference_rr: Some(gaussian_rr(per_channel)),
        bulk_only: false,
        label: format!(
            "σn = {}, σf = {}, w = {w:.4}, s = {s:.4e} mm",
            fmt3(n),
            fmt3(f)
        ),
    })
}

/// Jensen 2001 eq. 4 with z_r = 1/σ′t, z_v = z_r + 4AD.
fn dipole_rr(m: Medium, eta: f64) -> Box<dyn Fn(f64) -> Rgb> {
    let a = boundary_a(eta);
    Box::new(move |r| {
        [0, 1, 2].map(|c| {
            let (sa, ssp) = (m.sigma_a_per_mm[c], m.sigma_s_prime_per_mm[c]);
            let st = sa + ssp;
            let (alpha, str_) = (ssp / st, (3.0 * sa * st).sqrt());
            let zr = 1.0 / st;
            let zv = zr + 4.0 * a / (3.0 * st);
            let term = |z: f64| {
                let d = (r * r + z * z).sqrt();
                z * (1.0 + str_ * d) * (-str_ * d).exp() / (d * d * d)
            };
            r * alpha / (4.0 * PI) * (term(zr) + term(zv))
        })
    })
}

fn medium(rng: &mut Rng) -> Medium {
    loop {
        let m = Medium {
            sigma_a_per_mm: [0, 1, 2].map(|_| {
                if rng.next_u64().is_multiple_of(8) {
                    0.0
                } else {
                    rng.edged(1e-6, 1e3, true)
                }
            }),
            sigma_s_prime_per_mm: [0, 1, 2].map(|_| {
                if rng.next_u64().is_multiple_of(8) {
                    0.0
                } else {
                    rng.edged(1e-6, 1e4, true)
                }
            }),
        };
        if (0..3).all(|c| m.sigma_a_per_mm[c] + m.sigma_s_prime_per_mm[c] > 1e-9) {
            return m;
        }
    }
}

fn dipole_case(rng: &mut Rng) -> Result<Case, ModelError> {
    let (m, eta) = (medium(rng), rng.edged(1.0, 2.0, false));
    Ok(Case {
        profile: Box::new(Dipole::new(m, eta)?),
        reference_rr: Some(dipole_rr(m, eta)),
        bulk_only: false,
        label: format!(
            "σa = {}, σ′s = {} 1/mm, η = {eta:.4}",
            fmt3(m.sigma_a_per_mm),
            fmt3(m.sigma_s_prime_per_mm)
        ),
    })
}

/// Every measured material at η = 1.0, 1.3 and 2.0, in turn.
fn measured_case(index: usize) -> Result<Case, ModelError> {
    let all = measured::all();
    let mat = &all[index % all.len()];
    let eta = [1.3, 1.0, 2.0][(index / all.len()) % 3];
    Ok(Case {
        profile: Box::new(Dipole::new(mat.medium(), eta)?),
        reference_rr: Some(dipole_rr(mat.medium(), eta)),
        bulk_only: false,
        label: format!("{} at η = {eta}", mat.name),
    })
}

fn slab_layer(rng: &mut Rng) -> Layer {
    Layer {
        medium: Medium {
            sigma_a_per_mm: rng.rgb(1e-4, 1e2, true),
            sigma_s_prime_per_mm: rng.rgb(1e-2, 1e3, true),
        },
        thickness_mm: Some(rng.edged(1e-6, 1e3, true)),
        eta: rng.edged(1.0, 2.0, false),
    }
}

fn slab_label(l: &Layer, n: u32) -> String {
    format!(
        "σa = {}, σ′s = {} 1/mm, s = {:.3e} mm, η = {:.3}, {n} pairs",
        fmt3(l.medium.sigma_a_per_mm),
        fmt3(l.medium.sigma_s_prime_per_mm),
        l.thickness_mm.unwrap_or(f64::INFINITY),
        l.eta
    )
}

/// The slab's R is its own closed form; CDF, inverse and kernels are
/// checked, and the slab is the reference of the one-layer stack below.
fn slab_case(rng: &mut Rng) -> Result<Case, ModelError> {
    let layer = slab_layer(rng);
    let n = (rng.next_u64() % 26) as u32;
    Ok(Case {
        profile: Box::new(MultipoleSlab::new(&layer, 1.0, 1.0, n, "")?),
        reference_rr: None,
        bulk_only: false,
        label: slab_label(&layer, n),
    })
}

/// A one-layer stack (frequency space + FFTLog) against the slab's
/// real-space dipole sum. Parameters stay where the stack is documented
/// (optical thickness 10⁻³–10³ mean free paths).
fn stack_case(rng: &mut Rng) -> Result<Case, ModelError> {
    let medium = Medium {
        sigma_a_per_mm: rng.rgb(1e-3, 1.0, true),
        sigma_s_prime_per_mm: rng.rgb(0.1, 50.0, true),
    };
    let layer = Layer {
        medium,
        thickness_mm: Some(rng.edged(1e-2, 10.0, true)),
        eta: rng.edged(1.2, 1.6, false),
    };
    let n = 10;
    let slab = MultipoleSlab::new(&layer, 1.0, 1.0, n, "")?;
    let stack = LayeredMultipole::new(&[layer], 1.0, 1.0, n)?;
    Ok(Case {
        profile: Box::new(stack),
        reference_rr: Some(Box::new(move |r| slab.r_reflectance(r))),
        bulk_only: true,
        label: slab_label(&layer, n),
    })
}

/// A random case of a model (`usize`: the case's index); an error when
/// the generator left the model's documented ranges.
type Generator = fn(&mut Rng, usize) -> Result<Case, ModelError>;

/// One model of the sweep.
struct ModelSweep {
    name: &'static str,
    /// What R is compared with.
    reference: &'static str,
    generate: Generator,
    /// The model gets random_cases / cost cases.
    cost: usize,
    /// Kernels are built on every n-th case (1: all). Models without a
    /// closed-form strip CDF build each tap by nested quadrature.
    kernel_every: usize,
}

const MODELS: [ModelSweep; 8] = [
    ModelSweep {
        name: "burley",
        reference: "closed form (Burley 2015)",
        generate: |r, _| burley_case(r),
        cost: 1,
        kernel_every: 1,
    },
    ModelSweep {
        name: "gaussians",
        reference: "closed form (sum of 2D Gaussians)",
        generate: |r, _| gaussians_case(r),
        cost: 1,
        kernel_every: 1,
    },
    ModelSweep {
        name: "jimenez2012",
        reference: "closed form (d'Eon terms scaled, Jimenez 2012)",
        generate: |r, _| jimenez_case(r),
        cost: 1,
        kernel_every: 1,
    },
    ModelSweep {
        name: "artist",
        reference: "closed form (Jimenez 2015 §5)",
        generate: |r, _| artist_case(r),
        cost: 1,
        kernel_every: 1,
    },
    ModelSweep {
        name: "dipole",
        reference: "closed form (Jensen 2001 eq. 4)",
        generate: |r, _| dipole_case(r),
        cost: 1,
        kernel_every: 8,
    },
    ModelSweep {
        name: "measured",
        reference: "closed form (dipole of each table row)",
        generate: |_, i| measured_case(i),
        cost: 1,
        kernel_every: 8,
    },
    ModelSweep {
        name: "multipole-slab",
        reference: "(is the closed form)",
        generate: |r, _| slab_case(r),
        cost: 6,
        kernel_every: 8,
    },
    ModelSweep {
        name: "multipole-stack",
        reference: "one-slab real-space dipole sum (bulk: 0.001–0.999 energy)",
        generate: |r, _| stack_case(r),
        cost: 24,
        kernel_every: 4,
    },
];

/// Names of the models the sweep covers.
pub fn model_names() -> Vec<&'static str> {
    MODELS.iter().map(|m| m.name).collect()
}

/// The default `random_cases`: about two minutes on 2 cores in release
/// (the multipole slab takes about 14 s a case, the stack about 10).
pub const DEFAULT_CASES: usize = 48;

/// `scatterlab stress --long`: the full sweep (about 20 CPU-minutes).
pub const LONG_CASES: usize = 400;

/// Runs the sweep: `random_cases` parameter sets per model (fewer for the
/// costly stacks), deterministic for a seed whatever the thread count;
/// `only` restricts it to one model by name. Cases run in parallel
/// (rayon); `progress` is called after each with (done, total).
pub fn run(random_cases: usize, seed: u64, only: Option<&str>) -> StressReport {
    run_with_progress(random_cases, seed, only, |_, _| {})
}

/// As [`run`], reporting progress.
pub fn run_with_progress(
    random_cases: usize,
    seed: u64,
    only: Option<&str>,
    progress: impl Fn(usize, usize) + Sync,
) -> StressReport {
    use rayon::prelude::*;
    let chosen: Vec<(usize, &ModelSweep)> = MODELS
        .iter()
        .enumerate()
        .filter(|(_, m)| only.is_none_or(|o| o == m.name))
        .collect();
    // Every (model, case) pair, costliest models first so that their long
    // cases start early and the cores finish together.
    let mut jobs: Vec<(usize, usize)> = chosen
        .iter()
        .enumerate()
        .flat_map(|(j, (_, m))| (0..(random_cases / m.cost).max(2)).map(move |i| (j, i)))
        .collect();
    jobs.sort_by_key(|&(j, i)| (std::cmp::Reverse(chosen[j].1.cost), j, i));
    let total = jobs.len();
    let done = std::sync::atomic::AtomicUsize::new(0);
    let mut tallies: Vec<(usize, usize, ModelStress)> = jobs
        .par_iter()
        // One case a job: cases run from 1 ms to 14 s, and only single
        // jobs can be stolen by an idle core.
        .with_max_len(1)
        .map(|&(j, i)| {
            let (k, m) = chosen[j];
            // Each case its own stream: the same cases whatever the order.
            let mut rng = Rng(seed
                ^ (k as u64).wrapping_mul(0xA076_1D64_78BD_642F)
                ^ (i as u64).wrapping_mul(0xE703_7ED1_A0B4_28DB));
            rng.next_u64();
            let mut t = Tally::new(m.name, m.reference);
            let start = std::time::Instant::now();
            t.stress.cases = 1;
            match (m.generate)(&mut rng, i) {
                Ok(case) => {
                    extremes(&case, &mut t);
                    check_r(&case, &mut t);
                    check_cdf(&case, &mut t);
                    check_inverse(&case, &mut t, &mut rng);
                    if i % m.kernel_every == 0 {
                        check_kernels(&case, &mut t);
                    }
                }
                Err(e) => {
                    // The sweep's own parameters were refused: as bad as
                    // a wrong answer, and said where.
                    t.stress.worst_r_rel = f64::INFINITY;
                    t.stress.worst_r_at =
                        format!("case {i}: the generator left the model's range: {e}");
                }
            }
            t.stress.seconds = start.elapsed().as_secs_f64();
            let n = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            progress(n, total);
            (j, i, t.stress)
        })
        .collect();
    // Merged in case order: the report does not depend on the schedule.
    tallies.sort_by_key(|&(j, i, _)| (j, i));
    let mut models: Vec<ModelStress> = chosen
        .iter()
        .map(|(_, m)| Tally::new(m.name, m.reference).stress)
        .collect();
    for (j, _, t) in tallies {
        models[j].absorb(t);
    }
    StressReport {
        seed,
        random_cases_per_model: random_cases,
        cdf_floor: CDF_FLOOR,
        models,
    }
}

impl ModelStress {
    /// Adds a later case's tally: counts add, each worst keeps the larger
    /// (the earlier on a tie) with where it happened, the first NaN's
    /// place stays the first.
    fn absorb(&mut self, o: ModelStress) {
        self.cases += o.cases;
        self.evaluations += o.evaluations;
        if self.non_finite == 0 && o.non_finite > 0 {
            self.non_finite_at = o.non_finite_at;
        }
        self.non_finite += o.non_finite;
        let keep = |slot: &mut f64, at: &mut String, v: f64, v_at: String| {
            if v > *slot {
                *slot = v;
                *at = v_at;
            }
        };
        keep(
            &mut self.worst_r_rel,
            &mut self.worst_r_at,
            o.worst_r_rel,
            o.worst_r_at,
        );
        keep(
            &mut self.worst_cdf_rel,
            &mut self.worst_cdf_at,
            o.worst_cdf_rel,
            o.worst_cdf_at,
        );
        keep(
            &mut self.worst_inverse_rel,
            &mut self.worst_inverse_at,
            o.worst_inverse_rel,
            o.worst_inverse_at,
        );
        keep(
            &mut self.worst_kernel_norm,
            &mut self.worst_kernel_at,
            o.worst_kernel_norm,
            o.worst_kernel_at,
        );
        self.seconds += o.seconds;
    }
}

#[cfg(test)]
mod tests;
