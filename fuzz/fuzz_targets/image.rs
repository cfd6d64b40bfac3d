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
    // Images the header says are over 4 megapixels are not decoded: their
    // cost is linear in pixels and well-formed (the long run's one
    // "timeout" was a 307-byte JPEG claiming 14856 × 4104, which decodes
    // in 0.16 s and 185 MB in a release build; docs/robustness.md), so
    // the fuzzer would spend its time in decode loops, not in new paths.
    // The loaders' own limits (64 MP, 16384 a side, 512 MiB an
    // allocation) have their own tests.
    let claimed = image::ImageReader::open(&path)
        .and_then(|r| r.with_guessed_format())
        .ok()
        .and_then(|r| r.into_dimensions().ok());
    if claimed.is_some_and(|(w, h)| u64::from(w) * u64::from(h) > 4 << 20) {
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
