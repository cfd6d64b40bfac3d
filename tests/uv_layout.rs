//! The Maps window's flip-V suggestion on real assets: Lee Perry-Smith's
//! scan as three.js ships it (glTF with external colour and normal maps
//! painted with V up, which is why tests/yardstick.rs flips them; without
//! the flip the lips land on the chin) and the same maps mirrored by
//! `image` (another program), which then line up.

#![allow(clippy::unwrap_used)]

use scatterlab::render::mesh::Mesh;
use scatterlab::render::textures::{self, TextureSlot};
use scatterlab::render::uv_layout::{flip_evidence, FlipVerdict};
use std::path::Path;

fn scan() -> (Vec<[f32; 2]>, Vec<u32>) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scan");
    let mesh = Mesh::load(&root.join("LeePerrySmith.glb"), 0.0462).unwrap();
    (mesh.vertices.iter().map(|v| v.uv).collect(), mesh.indices)
}

#[test]
fn the_scans_external_maps_ask_for_flip_v_and_mirrored_ones_do_not() {
    let (uvs, idx) = scan();
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scan");
    for (file, slot) in [
        ("Map-COL.jpg", TextureSlot::Albedo),
        (
            "Infinite-Level_02_Tangent_SmoothUV.jpg",
            TextureSlot::Normal,
        ),
    ] {
        let map = textures::load(&root.join(file), slot).unwrap();
        let e = flip_evidence(&uvs, &idx, &map);
        eprintln!("{file}: {e:?}");
        assert_eq!(e.verdict(), FlipVerdict::Flip, "{file}: {e:?}");
        // Mirrored by another program (image's flipv), as a tool that
        // writes V down would have saved it.
        let mirrored = image::open(root.join(file)).unwrap().flipv().to_rgba8();
        let dir = std::env::temp_dir().join(format!("scatterlab-uv-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(file.replace(".jpg", ".png"));
        mirrored.save(&path).unwrap();
        let map = textures::load(&path, slot).unwrap();
        let e = flip_evidence(&uvs, &idx, &map);
        eprintln!("{file} mirrored: {e:?}");
        assert_eq!(e.verdict(), FlipVerdict::Aligned, "{file} mirrored: {e:?}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

/// The default head's own baked maps (procedural.rs paints them in the
/// mesh's UV space) line up as they are, and ask for a flip once mirrored;
/// its SSS mask, one value everywhere, cannot tell.
#[test]
fn the_default_heads_own_maps_line_up() {
    let mesh = Mesh::default_head().unwrap();
    let uvs: Vec<[f32; 2]> = mesh.vertices.iter().map(|v| v.uv).collect();
    for (name, map) in [
        ("albedo", &mesh.textures.albedo),
        ("normal", &mesh.textures.normal),
    ] {
        assert!(map.width > 1, "{name} is not baked");
        let e = flip_evidence(&uvs, &mesh.indices, map);
        eprintln!("own {name} {}x{}: {e:?}", map.width, map.height);
        assert_eq!(e.verdict(), FlipVerdict::Aligned, "{name}: {e:?}");
        let mut mirrored = map.clone();
        mirrored.flip_v();
        let e = flip_evidence(&uvs, &mesh.indices, &mirrored);
        assert_eq!(e.verdict(), FlipVerdict::Flip, "{name} mirrored: {e:?}");
    }
    let e = flip_evidence(&uvs, &mesh.indices, &mesh.textures.mask);
    assert_eq!(e.verdict(), FlipVerdict::Unclear, "mask: {e:?}");
}
