use super::*;

#[test]
fn catches_a_wrong_reference() {
    // A deliberately wrong reference (2× Burley) must show up as a
    // relative R error of 0.5, so the sweep can fail.
    let mut rng = Rng(7);
    let mut case = burley_case(&mut rng);
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

#[test]
fn generators_stay_in_the_documented_ranges() {
    let mut rng = Rng(1);
    for _ in 0..200 {
        for m in MODELS.iter().take(7) {
            let _ = (m.generate)(&mut rng, 3);
        }
    }
}
