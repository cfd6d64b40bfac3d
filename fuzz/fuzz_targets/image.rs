//! Surface maps and environment maps (PNG, JPEG, Radiance .hdr): the
//! loaders behind `--albedo`, `--normal`, `--mask`… and `--environment`.
//! Any bytes give an image or a named error, never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use scatterlab::render::environment::Environment;
use scatterlab::render::textures::{load, TextureSlot};

fuzz_target!(|data: &[u8]| {
    // One file per process, so parallel fuzzers (-jobs) do not race.
    let path =
        std::env::temp_dir().join(format!("scatterlab-fuzz-image-{}.img", std::process::id()));
    if std::fs::write(&path, data).is_err() {
        return;
    }
    for slot in [TextureSlot::Albedo, TextureSlot::Mask] {
        match load(&path, slot) {
            Ok(img) => assert_eq!(
                img.texels.len(),
                (img.width * img.height * img.channels) as usize
            ),
            Err(e) => assert!(e.to_string().contains("scatterlab-fuzz-")),
        }
    }
    if let Ok(env) = Environment::load(&path) {
        let sh = env.irradiance_sh();
        assert!(sh.iter().flatten().all(|v| v.is_finite()));
    }
});
