#![allow(clippy::unwrap_used)]
//! What scatterlab refuses, and how it says so: an unknown field at any
//! level of a preset, an empty, short or wrong-kind file, a full disk. Each
//! error names the file and what is wrong; nothing half-written is left.
//! Older presets, as shipped in the project's history, still load.

use scatterlab::export::Format;
use scatterlab::render::mesh::Mesh;
use scatterlab::render::textures::{self, TextureSlot};
use scatterlab::settings::Preset;
use std::path::{Path, PathBuf};

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scatterlab-refusals-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A look with every level a preset has: the preset, a Burley spec, its
/// shape's variant, the rendering section and its specular.
const BURLEY: &str = r#"(
    format_version: 2,
    name: "levels",
    profile: Burley((
        albedo: (0.8, 0.5, 0.3),
        shape: ScatteringDistance(mm: (1.0, 0.5, 0.25), multiplier: 1.0),
    )),
    rendering: (
        method: Burley,
        specular: (roughness: 0.5),
    ),
)"#;

/// Gaussian terms and multipole layers: the levels inside lists.
const GAUSSIANS: &str = r#"(
    profile: Gaussians((gaussians: [(variance_mm2: 0.1, weights: (1.0, 1.0, 1.0))])),
)"#;
const MULTIPOLE: &str = r#"(
    profile: Multipole((
        layers: [(sigma_a_per_mm: (0.1, 0.1, 0.1), sigma_s_prime_per_mm: (1.0, 1.0, 1.0), eta: 1.4, thickness_mm: None)],
    )),
)"#;

/// Issue 27: `ScatteringDistance(…, extra: 3)` loaded silently. An
/// unknown field is an error at every level, naming the field and the
/// file; the same texts without it load (so the insertion is the cause).
#[test]
fn an_unknown_field_is_refused_at_every_level() {
    let dir = scratch("unknown");
    let cases = [
        ("the preset", BURLEY, "name: \"levels\","),
        ("the Burley spec", BURLEY, "albedo: (0.8, 0.5, 0.3),"),
        ("the shape's variant", BURLEY, "multiplier: 1.0"),
        ("the rendering section", BURLEY, "method: Burley,"),
        ("the specular", BURLEY, "roughness: 0.5"),
        ("a Gaussian term", GAUSSIANS, "variance_mm2: 0.1,"),
        ("a multipole layer", MULTIPOLE, "eta: 1.4,"),
    ];
    for (level, text, after) in cases {
        let clean = dir.join("clean.ron");
        std::fs::write(&clean, text).unwrap();
        Preset::load(&clean).unwrap_or_else(|e| panic!("{level}: the clean text fails: {e}"));
        let sep = if after.ends_with(',') { " " } else { ", " };
        let edited = text.replacen(after, &format!("{after}{sep}extra: 3,"), 1);
        assert_ne!(edited, text, "{level}: nothing inserted");
        let path = dir.join("extra.ron");
        std::fs::write(&path, &edited).unwrap();
        let e = Preset::load(&path).expect_err(level).to_string();
        assert!(e.contains("extra"), "{level}: {e}");
        assert!(e.contains(&path.display().to_string()), "{level}: {e}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Every preset the project ships, and every earlier version of one
/// (`tests/data/presets_history/`, taken from the history with `git show`;
/// format 1 has no `rendering`), still loads and validates.
#[test]
fn every_shipped_preset_and_its_earlier_versions_load() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut formats = std::collections::BTreeMap::<u32, usize>::new();
    let mut count = 0;
    for dir in ["presets", "tests/data/presets_history"] {
        for e in std::fs::read_dir(root.join(dir)).unwrap() {
            let p = e.unwrap().path();
            if p.extension().is_none_or(|x| x != "ron") {
                continue;
            }
            let text = std::fs::read_to_string(&p).unwrap();
            let version: u32 = text
                .split("format_version:")
                .nth(1)
                .and_then(|t| t.trim_start().split(',').next())
                .and_then(|v| v.trim().parse().ok())
                .unwrap_or(1);
            Preset::load(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            *formats.entry(version).or_default() += 1;
            count += 1;
        }
    }
    assert!(count >= 19, "{count} presets");
    assert!(formats.get(&1).copied().unwrap_or(0) >= 1, "{formats:?}");
    assert!(formats.get(&2).copied().unwrap_or(0) >= 1, "{formats:?}");
}

/// Empty, short and wrong-kind files say what is wrong with them ("0
/// bytes", "not a binary glTF"), naming the file; none panics.
#[test]
fn empty_short_and_wrong_kind_files_say_what_is_wrong() {
    let dir = scratch("short");
    let png = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/head_burley_160.png"),
    )
    .unwrap_or_else(|_| b"\x89PNG\r\n\x1a\n0000".to_vec());
    let file = |name: &str, bytes: &[u8]| {
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        p
    };
    let mesh = |p: &Path| Mesh::load(p, 1.0).err().unwrap().to_string();
    for (path, want) in [
        (file("empty.glb", b""), "0 bytes: the file is empty"),
        (
            file("short.glb", b"glTF\x02"),
            "5 bytes: too short for a binary glTF header",
        ),
        (file("picture.glb", &png), "not a binary glTF"),
        (file("empty.gltf", b""), "0 bytes"),
        (
            file("text.gltf", b"solid cube\nfacet normal"),
            "not a glTF document",
        ),
        (file("empty.obj", b""), "0 bytes: the file is empty"),
    ] {
        let e = mesh(&path);
        assert!(e.contains(want), "{}: {e}", path.display());
        assert!(e.contains(&path.display().to_string()), "{e}");
    }
    let empty_ron = file("empty.ron", b"");
    let e = Preset::load(&empty_ron).unwrap_err().to_string();
    assert!(e.contains("0 bytes") && e.contains("empty.ron"), "{e}");
    let blank_ron = file("blank.ron", b"  \n\n");
    let e = Preset::load(&blank_ron).unwrap_err().to_string();
    assert!(e.contains("no preset in it"), "{e}");
    for (name, bytes, want) in [
        ("empty.png", &b""[..], "0 bytes"),
        (
            "short.png",
            &b"\x89PN"[..],
            "3 bytes: too short for an image",
        ),
    ] {
        let p = file(name, bytes);
        let e = textures::load(&p, TextureSlot::Albedo)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains(want) && e.contains(name), "{e}");
    }
    let empty_asset = file("empty.asset", b"");
    let e = scatterlab::export::import_file(&empty_asset, &Default::default())
        .err()
        .unwrap()
        .to_string();
    assert!(e.contains("0 bytes") && e.contains("empty.asset"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An image whose header claims more than the loaders take is refused
/// from its header, before any pixel is decoded: 16384 × 16384 is over the
/// 64-megapixel limit, 20000 × 10 over 16384 a side. The PNG headers were
/// written with Python's zlib.crc32 for the chunk CRCs (PNG spec 5.3), so
/// they are well-formed (one IDAT of a single zero byte) and only the
/// size is wrong.
#[test]
fn images_over_the_size_limits_are_refused_from_their_header() {
    let dir = scratch("huge");
    for (name, hex, want) in [
        (
            "square.png",
            "89504e470d0a1a0a0000000d494844520000400000004000080200000026aa87d30000000949444154789c630000000100015eff7df90000000049454e44ae426082",
            "16384×16384 is over the 64-megapixel limit",
        ),
        (
            "wide.png",
            "89504e470d0a1a0a0000000d4948445200004e200000000a0802000000de11f91a0000000949444154789c630000000100015eff7df90000000049454e44ae426082",
            "20000×10 is over the limit of 16384 pixels a side",
        ),
    ] {
        let bytes: Vec<u8> = (0..hex.len() / 2)
            .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).unwrap())
            .collect();
        let p = dir.join(name);
        std::fs::write(&p, bytes).unwrap();
        let e = textures::load(&p, TextureSlot::Albedo)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains(want) && e.contains(name), "{e}");
        let e = scatterlab::render::environment::Environment::load(&p)
            .err()
            .unwrap()
            .to_string();
        assert!(e.contains(want) && e.contains(name), "{e}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A full disk while saving a preset or exporting (the write fails part
/// way, as ENOSPC does, injected on this thread): the file already there
/// stays as it was, nothing temporary is left, and the error names the
/// file, the cause and that nothing changed.
#[test]
fn a_full_disk_leaves_the_old_file_and_says_so() {
    let dir = scratch("full");
    let preset = Preset::default_skin();
    let path = dir.join("look.ron");
    preset.save(&path).unwrap();
    let before = std::fs::read(&path).unwrap();
    let renamed = Preset {
        name: "A longer name, so the new file differs".into(),
        ..preset.clone()
    };
    scatterlab::fsutil::inject_full_disk(Some(40));
    let e = renamed.save(&path).unwrap_err().to_string();
    let out = dir.join("look.asset");
    let exported = scatterlab::export::export(&preset, None, Format::Unity, &out);
    scatterlab::fsutil::inject_full_disk(None);
    assert_eq!(
        std::fs::read(&path).unwrap(),
        before,
        "the saved preset changed"
    );
    for e in [e, exported.unwrap_err().to_string()] {
        assert!(e.contains("No space left on device"), "{e}");
        assert!(e.contains("unchanged"), "{e}");
        assert!(e.contains(dir.to_str().unwrap()), "{e}");
    }
    assert!(!out.exists(), "a partial export was left");
    let leftovers: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    // And without the fault the same save goes through.
    renamed.save(&path).unwrap();
    assert_eq!(Preset::load(&path).unwrap().name, renamed.name);
    std::fs::remove_dir_all(&dir).unwrap();
}
