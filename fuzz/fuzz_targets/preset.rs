//! Preset files: any text either loads into a preset whose profile is
//! finite everywhere we sample it, or is refused with an error naming the
//! file. A panic, or a NaN from an accepted preset, is a crash.
#![no_main]

use libfuzzer_sys::fuzz_target;
use scatterlab::settings::Preset;
use std::path::Path;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match Preset::from_ron(text, Path::new("fuzz.ron")) {
        Ok(preset) => {
            let profile = preset
                .build_profile()
                .expect("a validated preset builds its profile");
            let finite = |v: [f64; 3]| v.iter().all(|x| x.is_finite());
            assert!(finite(profile.total_reflectance()));
            for r in [0.0, 0.01, 1.0, 100.0] {
                assert!(finite(profile.reflectance(r)), "R({r})");
                assert!(finite(profile.cdf(r)), "cdf({r})");
            }
            assert!(finite(profile.radius_for_energy(0.997)));
            // What the editor writes back must load again.
            let again = Preset::from_ron(&preset.to_ron(), Path::new("again.ron"))
                .expect("a saved preset loads");
            assert_eq!(again.profile, preset.profile);
        }
        Err(e) => assert!(e.to_string().contains("fuzz.ron")),
    }
});
