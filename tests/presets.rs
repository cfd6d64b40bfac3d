#![allow(clippy::unwrap_used)]
//! Every shipped preset loads, validates, builds a finite profile, and
//! survives a save/load round trip; hostile files give named errors.

use scatterlab::settings::Preset;
use std::path::Path;

#[test]
fn every_preset_loads_and_round_trips() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("presets");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().and_then(|e| e.to_str()) != Some("ron") {
            continue;
        }
        n += 1;
        let p = Preset::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            !p.source.is_empty(),
            "{}: presets must state their source",
            path.display()
        );
        let profile = p.build_profile().unwrap();
        let t = profile.total_reflectance();
        assert!(
            t.iter()
                .all(|v| v.is_finite() && *v > 0.0 && *v <= 1.0 + 1e-12),
            "{}: {t:?}",
            path.display()
        );
        let tmp =
            std::env::temp_dir().join(format!("scatterlab-preset-{}-{n}.ron", std::process::id()));
        p.save(&tmp).unwrap();
        assert_eq!(Preset::load(&tmp).unwrap(), p);
        std::fs::remove_file(&tmp).unwrap();
    }
    assert!(n >= 6, "found {n} presets");
}

#[test]
fn saving_an_invalid_preset_writes_nothing() {
    let mut p = Preset::default_skin();
    if let scatterlab::settings::ProfileSpec::Burley(b) = &mut p.profile {
        b.albedo = [f64::NAN, 0.5, 0.5];
    }
    let tmp = std::env::temp_dir().join(format!("scatterlab-invalid-{}.ron", std::process::id()));
    let e = p.save(&tmp).unwrap_err().to_string();
    assert!(e.contains("albedo.r"), "{e}");
    assert!(!tmp.exists());
}
