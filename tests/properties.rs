#![allow(clippy::unwrap_used)]
//! Property tests over each model's documented parameter range, edges
//! included: outputs finite, CDFs monotone in [0, 1], inverse CDFs round
//! trip, transmittance falls with thickness; out-of-range input is an error
//! naming the parameter, never a panic. Fixed seeds.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use scatterlab::model::burley::Burley;
use scatterlab::model::dipole::{Dipole, Medium};
use scatterlab::model::gaussian::GaussianSum;
use scatterlab::model::jimenez::Jimenez2012;
use scatterlab::model::multipole::{Layer, LayeredMultipole, MultipoleSlab};
use scatterlab::model::separable::ArtistTwoGaussian;
use scatterlab::model::RadialProfile;

fn config(cases: u32) -> Config {
    Config {
        cases,
        rng_seed: RngSeed::Fixed(0x5ca7_7e41),
        failure_persistence: None,
        ..Config::default()
    }
}

/// log-uniform in [lo, hi] with the edges themselves drawn often.
fn log_range(lo: f64, hi: f64) -> impl Strategy<Value = f64> + Clone {
    prop_oneof![1 => Just(lo), 1 => Just(hi), 6 => (lo.ln()..hi.ln()).prop_map(f64::exp)]
}

fn unit_with_edges() -> impl Strategy<Value = f64> + Clone {
    prop_oneof![1 => Just(0.0), 1 => Just(1.0), 1 => Just(1e-12), 1 => Just(1.0 - 1e-12), 6 => 0.0..1.0f64]
}

fn rgb(s: impl Strategy<Value = f64> + Clone) -> impl Strategy<Value = [f64; 3]> {
    [s.clone(), s.clone(), s]
}

fn radii() -> Vec<f64> {
    let mut r = vec![0.0, 1e-12, 1e-6];
    r.extend((0..40).map(|i| 1e-4 * 1.6f64.powi(i)));
    r.push(1e9);
    r
}

/// The invariants every profile must satisfy.
fn check_profile(p: &dyn RadialProfile) -> Result<(), TestCaseError> {
    let total = p.total_reflectance();
    prop_assert!(
        total.iter().all(|t| t.is_finite() && *t >= 0.0),
        "total {total:?}"
    );
    let mut last = [0.0f64; 3];
    let mut last_t = [f64::INFINITY; 3];
    for r in radii() {
        let (v, rr, c, t) = (p.reflectance(r), p.r_reflectance(r), p.cdf(r), p.tail(r));
        let tr = p.transmittance(r);
        for ch in 0..3 {
            prop_assert!(v[ch].is_finite() && v[ch] >= 0.0, "R({r}) = {v:?}");
            prop_assert!(rr[ch].is_finite() && rr[ch] >= 0.0, "rR({r}) = {rr:?}");
            prop_assert!((0.0..=1.0).contains(&c[ch]), "cdf({r}) = {c:?}");
            prop_assert!(
                c[ch] >= last[ch] - 1e-9,
                "cdf not monotone at {r}: {c:?} after {last:?}"
            );
            prop_assert!(
                (c[ch] + t[ch] - 1.0).abs() < 1e-9,
                "cdf + tail at {r}: {c:?} {t:?}"
            );
            prop_assert!(
                tr[ch].is_finite() && tr[ch] >= 0.0 && tr[ch] <= last_t[ch] + 1e-12,
                "T({r}) = {tr:?}"
            );
            last[ch] = c[ch];
            last_t[ch] = tr[ch];
        }
    }
    for xi in [0.0, 1e-9, 0.3, 0.5, 0.9, 0.997, 1.0 - 1e-9] {
        let r = p.radius_for_energy(xi);
        for ch in 0..3 {
            prop_assert!(r[ch].is_finite() && r[ch] >= 0.0, "inverse({xi}) = {r:?}");
            if total[ch] > 0.0 && p.dirac_weight()[ch] < total[ch] * xi {
                let back = p.cdf(r[ch])[ch];
                let tol = if xi > 0.5 { 1e-7 } else { 1e-7 * xi.max(1e-3) };
                prop_assert!(
                    (back - xi).abs() <= tol.max(1e-12),
                    "cdf(inverse({xi})) = {back}"
                );
            }
        }
    }
    Ok(())
}

proptest! {
    #![proptest_config(config(256))]

    #[test]
    fn burley(a in rgb(unit_with_edges()), d in rgb(log_range(1e-4, 1e3))) {
        check_profile(&Burley::from_scattering_distance(a, d).unwrap())?;
    }

    #[test]
    fn gaussians(terms in prop::collection::vec((log_range(1e-8, 1e4), rgb(unit_with_edges())), 1..7)) {
        check_profile(&GaussianSum::new(&terms).unwrap())?;
    }

    #[test]
    fn jimenez2012(s in rgb(unit_with_edges()), f in rgb(unit_with_edges())) {
        let j = Jimenez2012::new(s, f).unwrap();
        check_profile(&j)?;
        let k = j.kernel(25).unwrap().sum();
        for c in 0..3 { prop_assert!((k[c] - 1.0).abs() < 1e-12, "kernel sum {k:?}"); }
    }

    #[test]
    fn artist(n in rgb(log_range(1e-6, 1.0)), f in rgb(log_range(1e-6, 1.0)), w in unit_with_edges(), s in log_range(1e-4, 1e3)) {
        check_profile(&ArtistTwoGaussian::new(n, f, w, s).unwrap())?;
    }

    #[test]
    fn dipole(sa in rgb(prop_oneof![Just(0.0), log_range(1e-6, 1e3)]), ss in rgb(prop_oneof![Just(0.0), log_range(1e-6, 1e4)]), eta in prop_oneof![Just(1.0), Just(2.0), 1.0..2.0f64]) {
        prop_assume!((0..3).all(|c| sa[c] + ss[c] > 1e-9));
        check_profile(&Dipole::new(Medium { sigma_a_per_mm: sa, sigma_s_prime_per_mm: ss }, eta).unwrap())?;
    }
}

proptest! {
    #![proptest_config(config(64))]

    #[test]
    fn multipole_slab(sa in rgb(prop_oneof![Just(0.0), log_range(1e-4, 1e2)]), ss in rgb(log_range(1e-2, 1e3)), s in log_range(1e-6, 1e3), n in 0u32..25, eta in 1.0..2.0f64) {
        let slab = MultipoleSlab::new(&Layer { medium: Medium { sigma_a_per_mm: sa, sigma_s_prime_per_mm: ss }, thickness_mm: Some(s), eta }, 1.0, 1.0, n, "").unwrap();
        check_profile(&slab)?;
        for r in radii() {
            prop_assert!(slab.transmittance_profile(r).iter().all(|v| v.is_finite() && *v >= 0.0));
        }
    }
}

proptest! {
    #![proptest_config(config(8))]

    #[test]
    fn layered_stack(sa in rgb(log_range(1e-3, 1.0)), ss in rgb(log_range(0.1, 50.0)), s in log_range(1e-3, 10.0), eta in 1.2..1.6f64) {
        let m = Medium { sigma_a_per_mm: sa, sigma_s_prime_per_mm: ss };
        let base = Medium { sigma_a_per_mm: [0.05; 3], sigma_s_prime_per_mm: [1.0; 3] };
        let p = LayeredMultipole::new(&[Layer { medium: m, thickness_mm: Some(s), eta }, Layer { medium: base, thickness_mm: None, eta: 1.4 }], 1.0, 1.0, 10).unwrap();
        for r in radii() {
            let (v, c) = (p.reflectance(r), p.cdf(r));
            prop_assert!(v.iter().all(|x| x.is_finite() && *x >= 0.0));
            prop_assert!(c.iter().all(|x| (0.0..=1.0).contains(x)));
        }
        prop_assert!(p.radius_for_energy(0.997).iter().all(|r| r.is_finite()));
    }
}

proptest! {
    #![proptest_config(config(256))]

    /// Outside the documented ranges: an error that names the parameter.
    #[test]
    fn out_of_range_is_a_named_error(bad in prop_oneof![Just(f64::NAN), Just(f64::INFINITY), Just(-1.0), 1.0001..1e6f64]) {
        let e = Burley::from_scattering_distance([0.5, bad, 0.5], [1.0; 3]).unwrap_err().to_string();
        prop_assert!(e.contains("albedo.g"), "{}", e);
        let e = Burley::from_scattering_distance([0.5; 3], [1.0, 1.0, if bad > 1.0 { 1e4 * bad } else { bad }]).unwrap_err().to_string();
        prop_assert!(e.contains("scattering_distance_mm.b"), "{}", e);
        let e = Dipole::new(Medium { sigma_a_per_mm: [0.1; 3], sigma_s_prime_per_mm: [1.0; 3] }, if bad > 1.0 { 2.0 + bad } else { bad }).unwrap_err().to_string();
        prop_assert!(e.contains("eta"), "{}", e);
        let e = Jimenez2012::new([0.5; 3], [bad, 0.5, 0.5]).unwrap_err().to_string();
        prop_assert!(e.contains("falloff.r"), "{}", e);
    }
}
