#![allow(clippy::unwrap_used)]
//! The numerical stress sweep (`scatterlab stress`) on a few random
//! parameter sets per model plus the range edges: no NaN or Inf anywhere,
//! and every model within the accuracy docs/accuracy.md states. The
//! references are independent of the code under test (closed forms written
//! out again from the papers, adaptive quadrature at 10⁻¹²); the full sweep
//! is `scatterlab stress --long` in release.

use scatterlab::model::stress::{model_names, run};

#[test]
fn closed_form_models_are_finite_and_exact() {
    // (model, R, CDF, inverse round trip) bounds, relative.
    for (model, r, cdf, inv) in [
        ("burley", 1e-13, 1e-12, 1e-12),
        ("gaussians", 1e-13, 1e-10, 1e-10),
        ("jimenez2012", 1e-12, 1e-10, 1e-10),
        ("artist", 1e-13, 1e-10, 1e-10),
        ("dipole", 1e-12, 1e-6, 1e-9),
        ("measured", 1e-12, 1e-6, 1e-9),
    ] {
        let report = run(24, 11, Some(model));
        let m = &report.models[0];
        assert_eq!(m.model, model);
        assert!(m.cases >= 24 && m.evaluations > 1000, "{m:?}");
        assert_eq!(m.non_finite, 0, "{model}: {}", m.non_finite_at);
        assert!(
            m.worst_r_rel <= r,
            "{model} R: {} at {}",
            m.worst_r_rel,
            m.worst_r_at
        );
        assert!(
            m.worst_cdf_rel <= cdf,
            "{model} CDF: {} at {}",
            m.worst_cdf_rel,
            m.worst_cdf_at
        );
        assert!(
            m.worst_inverse_rel <= inv,
            "{model} inverse: {} at {}",
            m.worst_inverse_rel,
            m.worst_inverse_at
        );
        assert!(
            m.worst_kernel_norm <= 1e-12,
            "{model} kernel: {} at {}",
            m.worst_kernel_norm,
            m.worst_kernel_at
        );
    }
}

#[test]
fn multipole_slab_is_finite_and_its_cdf_exact() {
    let report = run(4, 5, Some("multipole-slab"));
    let m = &report.models[0];
    assert_eq!(m.non_finite, 0, "{}", m.non_finite_at);
    assert!(
        m.worst_cdf_rel <= 1e-6,
        "{} at {}",
        m.worst_cdf_rel,
        m.worst_cdf_at
    );
    assert!(
        m.worst_inverse_rel <= 1e-8,
        "{} at {}",
        m.worst_inverse_rel,
        m.worst_inverse_at
    );
    assert!(m.worst_kernel_norm <= 1e-12);
}

#[test]
fn every_model_is_swept() {
    assert_eq!(
        model_names(),
        [
            "burley",
            "gaussians",
            "jimenez2012",
            "artist",
            "dipole",
            "measured",
            "multipole-slab",
            "multipole-stack"
        ]
    );
}
