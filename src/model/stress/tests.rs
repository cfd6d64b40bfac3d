use super::*;

#[test]
fn catches_a_wrong_reference() {
    // A deliberately wrong reference (2× Burley) must show up as a
    // relative R error of 0.5, so the sweep can fail.
    let mut rng = Rng(7);
    let mut case = burley_case(&mut rng).expect("burley's generator stays in range");
    let good = case.reference_rr.take().expect("reference");
    case.reference_rr = Some(Box::new(move |r| good(r).map(|v| 2.0 * v)));
    let mut t = Tally::new("burley", "");
    check_r(&case, &mut t);
    assert!(
        (t.stress.worst_r_rel - 0.5).abs() < 1e-9,
        "{}",
        t.stress.worst_r_rel
    );
}

/// Every model's generator, over many cases (fewer for the costly
/// stacks), builds its model without an error (the constructors refuse
/// anything outside the documented ranges), and a profile with a finite,
/// non-negative total reflectance (an albedo of 0 is in range; a sum of
/// Gaussians may exceed 1) and a finite median radius.
#[test]
fn generators_stay_in_the_documented_ranges() {
    let mut rng = Rng(1);
    for m in MODELS.iter() {
        for i in 0..(200 / m.cost).max(4) {
            let case = (m.generate)(&mut rng, i)
                .unwrap_or_else(|e| panic!("{} case {i} left its range: {e}", m.name));
            let total = case.profile.total_reflectance();
            let median = case.profile.radius_for_energy(0.5);
            for c in 0..3 {
                assert!(
                    total[c].is_finite() && total[c] >= 0.0,
                    "{} {}: total {total:?}",
                    m.name,
                    case.label
                );
                assert!(
                    median[c].is_finite() && median[c] >= 0.0,
                    "{} {}: median radius {median:?}",
                    m.name,
                    case.label
                );
            }
        }
    }
}
