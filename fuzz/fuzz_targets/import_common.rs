//! What every importer target checks (issue 24): any text read as an
//! engine file with extension `ext` either gives looks that validate,
//! build finite profiles and save and load again, or is refused with one
//! line naming the file. A panic, a NaN from an accepted look or an error
//! without the file is a crash.

use scatterlab::export::{import_text, ImportOptions};
use scatterlab::settings::Preset;
use std::path::PathBuf;

pub fn check(data: &[u8], ext: &str) {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    // A folder that does not exist: a Unity list's GUIDs resolve to nothing.
    let path = PathBuf::from(format!("/nonexistent-scatterlab-fuzz/fuzz.{ext}"));
    match import_text(text, &path, &ImportOptions::default()) {
        Ok(looks) => {
            for look in looks {
                look.preset.validate().expect("an imported look validates");
                let profile = look.preset.build_profile().expect("an imported look builds");
                let finite = |v: [f64; 3]| v.iter().all(|x| x.is_finite());
                assert!(finite(profile.total_reflectance()));
                for r in [0.0, 0.01, 1.0, 100.0] {
                    assert!(finite(profile.reflectance(r)), "R({r})");
                    assert!(finite(profile.cdf(r)), "cdf({r})");
                }
                let again = Preset::from_ron(&look.preset.to_ron(), std::path::Path::new("again.ron"))
                    .expect("an imported look saves and loads");
                assert_eq!(again.profile, look.preset.profile);
            }
        }
        Err(e) => {
            let m = e.to_string();
            assert!(m.contains(&format!("fuzz.{ext}")), "{m}");
            assert_eq!(m.lines().count(), 1, "{m}");
        }
    }
}
