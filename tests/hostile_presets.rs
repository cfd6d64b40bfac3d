#![allow(clippy::unwrap_used)]
//! Every shipped preset with random numbers replaced by valid, invalid and
//! hostile values (NaN, ±∞, negatives, 0, huge, tiny): loading never panics,
//! a refused file names itself in the error, and an accepted one builds a
//! profile whose every output is finite.

use scatterlab::model::stress::Rng;
use scatterlab::model::RadialProfile;
use scatterlab::settings::library::PRESETS;
use scatterlab::settings::Preset;
use std::path::Path;

/// Byte ranges of the numeric literals in RON text (outside comments).
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let b = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'/' && b.get(i + 1) == Some(&b'/') {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
            continue;
        }
        if b[i] == b'"' {
            i += 1;
            while i < b.len() && b[i] != b'"' {
                i += 1;
            }
            i += 1;
            continue;
        }
        let starts = b[i].is_ascii_digit()
            || (b[i] == b'-' && b.get(i + 1).is_some_and(|c| c.is_ascii_digit()));
        let in_word = i > 0 && (b[i - 1].is_ascii_alphanumeric() || b[i - 1] == b'_');
        if starts && !in_word {
            let s = i;
            i += 1;
            while i < b.len()
                && (b[i].is_ascii_digit()
                    || b[i] == b'.'
                    || b[i] == b'e'
                    || b[i] == b'E'
                    || ((b[i] == b'-' || b[i] == b'+') && matches!(b[i - 1], b'e' | b'E')))
            {
                i += 1;
            }
            out.push((s, i));
        } else {
            i += 1;
        }
    }
    out
}

/// A replacement literal: valid-looking, invalid, or hostile.
fn value(rng: &mut Rng) -> String {
    match rng.below(12) {
        0 => "NaN".into(),
        1 => "inf".into(),
        2 => "-inf".into(),
        3 => "-1.0".into(),
        4 => "0.0".into(),
        5 => "1e300".into(),
        6 => "1e-300".into(),
        7 => "-0.0".into(),
        8 => format!("{}", rng.below(2000)),
        9 => format!("{:e}", 10f64.powf(-4.0 + 8.0 * rng.unit())),
        _ => format!("{}", rng.unit() * 2.0),
    }
}

fn check_outputs(p: &dyn RadialProfile, origin: &str) {
    let finite = |what: &str, v: &[f64]| {
        assert!(v.iter().all(|x| x.is_finite()), "{origin}: {what} = {v:?}");
    };
    finite("total", &p.total_reflectance());
    for r in [0.0, 1e-3, 0.1, 1.0, 10.0, 1e3] {
        finite("R", &p.reflectance(r));
        finite("r·R", &p.r_reflectance(r));
        finite("cdf", &p.cdf(r));
        finite("tail", &p.tail(r));
        finite("T", &p.transmittance(r));
    }
    for xi in [0.0, 0.5, 0.997] {
        finite("inverse cdf", &p.radius_for_energy(xi));
    }
}

#[test]
fn random_edits_never_panic_or_produce_nan() {
    // A fixed seed: the same mutations on every run.
    let mut rng = Rng(0x5ca7_7e12);
    let (mut accepted, mut refused) = (0, 0);
    for (file, text) in PRESETS {
        let spans = numbers(text);
        assert!(!spans.is_empty(), "{file}: no numbers found");
        for round in 0..30 {
            let mut edited = text.to_string();
            // One to three numbers, replaced from the back so spans hold.
            let mut picks: Vec<(usize, usize)> = (0..1 + rng.below(3))
                .map(|_| spans[rng.below(spans.len())])
                .collect();
            picks.sort();
            picks.dedup();
            for (s, e) in picks.into_iter().rev() {
                edited.replace_range(s..e, &value(&mut rng));
            }
            let origin = format!("{file}#{round}");
            match Preset::from_ron(&edited, Path::new(&origin)) {
                Ok(p) => {
                    accepted += 1;
                    let profile = p.build_profile().unwrap_or_else(|e| {
                        panic!("{origin}: validated but did not build: {e}\n{edited}")
                    });
                    check_outputs(profile.as_ref(), &origin);
                    assert!(p.rendering.f0().is_finite(), "{origin}: f0");
                }
                Err(e) => {
                    refused += 1;
                    let msg = e.to_string();
                    assert!(
                        msg.contains(&origin),
                        "{origin}: error does not name the file: {msg}"
                    );
                }
            }
        }
    }
    // Both branches were exercised.
    assert!(
        accepted > 20 && refused > 20,
        "accepted {accepted}, refused {refused}"
    );
}

#[test]
fn number_scanner_by_hand() {
    let t = "// 1.0 in a comment\n(a: 1.5, b: -2e-3, name: \"x9\", c: [3, 4e5], d_2: 7)";
    let found: Vec<&str> = numbers(t).iter().map(|&(s, e)| &t[s..e]).collect();
    assert_eq!(found, vec!["1.5", "-2e-3", "3", "4e5", "7"]);
}
