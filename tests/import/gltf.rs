//! glTF's volume extensions, both ways (issue 40 item 1).

use super::*;
use scatterlab::export::{export_with, ExportOptions, GltfMesh};

fn sphere(scatter: bool) -> ExportOptions {
    ExportOptions {
        gltf_mesh: GltfMesh::Sphere,
        gltf_volume_scatter: scatter,
        ..Default::default()
    }
}

/// Every shipped look, exported to glTF and imported back, with and
/// without the draft volume_scatter (without it the albedo comes back from
/// `baseColorFactor`): the Burley profile the export sent, CDF within
/// 1e-3, and the IOR and transmission tint. The file is also read by the
/// extensions' own definitions, typed here from the Khronos texts and not
/// from our code: σt = −ln(attenuationColor)/attenuationDistance
/// (KHR_materials_volume README line 150) must be 1/ℓ with ℓ = d·s(A),
/// s = 1.85 − A + 7|A − 0.8|³ (Christensen & Burley 2015 eq. 5), and the
/// multi-scatter colour A.
#[test]
fn gltf_round_trip_gives_back_the_look() {
    for (file, _) in library::PRESETS {
        let preset = library::load(file).unwrap();
        let (sent, _) = scatterlab::export::burley_of(&preset.profile).unwrap();
        for scatter in [true, false] {
            let out = tmp(&format!("{file}_{scatter}.gltf"));
            export_with(&preset, None, Format::Gltf, &out, &sphere(scatter)).unwrap();
            let back = &import(&out)[0];
            let worst = same_shape(&sent, &burley_of(&back.preset), 1e-3);
            assert!(worst < 1e-9, "{file}: {worst}");
            assert_eq!(back.preset.rendering.ior, preset.rendering.ior, "{file}");
            assert_eq!(
                back.preset.rendering.transmission_tint,
                preset.rendering.transmission_tint.map(|t| t.min(1.0)),
                "{file}"
            );
            assert_eq!(
                back.notes.iter().any(|n| n.contains("base colour")),
                !scatter,
                "{file}: {:?}",
                back.notes
            );
            // The definitions, on the file's own numbers.
            let doc: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
            let ext = &doc["materials"][0]["extensions"];
            let dist_m = ext["KHR_materials_volume"]["attenuationDistance"]
                .as_f64()
                .unwrap();
            let a = sent.albedo();
            let d = sent.scattering_distance_mm();
            for c in 0..3 {
                let colour = ext["KHR_materials_volume"]["attenuationColor"][c]
                    .as_f64()
                    .unwrap();
                let sigma_t_per_mm = -colour.ln() / (dist_m * 1e3);
                let s = 1.85 - a[c] + 7.0 * (a[c] - 0.8).abs().powi(3);
                let ell = d[c] * s;
                assert!(
                    (sigma_t_per_mm * ell - 1.0).abs() < 1e-9,
                    "{file} channel {c}: σt {sigma_t_per_mm} /mm, ℓ {ell} mm"
                );
                let base = doc["materials"][0]["pbrMetallicRoughness"]["baseColorFactor"][c]
                    .as_f64()
                    .unwrap();
                // serde_json's default parser may miss the last bit.
                assert!((base - a[c]).abs() < 1e-15);
                if scatter {
                    let ms = ext["KHR_materials_volume_scatter"]["multiscatterColorFactor"][c]
                        .as_f64()
                        .unwrap();
                    assert!((ms - a[c]).abs() < 1e-15);
                }
            }
            // The glTF unit is the metre: the widest ℓ in metres.
            let widest = (0..3)
                .map(|c| d[c] * (1.85 - a[c] + 7.0 * (a[c] - 0.8).abs().powi(3)))
                .fold(0.0, f64::max);
            assert!((dist_m - widest * 1e-3).abs() < 1e-15, "{file}");
        }
    }
}

/// A file written in centimetres (distances ×100) is read with
/// `--metres-per-unit 0.01` to the same look, and says so.
#[test]
fn a_gltf_in_centimetres_reads_with_metres_per_unit() {
    let preset = Preset::default_skin();
    let out = tmp("skin_m.gltf");
    export_with(&preset, None, Format::Gltf, &out, &sphere(true)).unwrap();
    let mut doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let v = &mut doc["materials"][0]["extensions"]["KHR_materials_volume"]["attenuationDistance"];
    *v = serde_json::json!(v.as_f64().unwrap() * 100.0);
    let cm = tmp("skin_cm.gltf");
    std::fs::write(&cm, doc.to_string()).unwrap();
    let options = ImportOptions {
        metres_per_unit: Some(0.01),
    };
    let back = &import_file(&cm, &options).unwrap()[0];
    same_shape(&burley_of(&preset), &burley_of(&back.preset), 1e-9);
    assert!(
        back.notes.iter().any(|n| n.contains("0.01 m")),
        "{:?}",
        back.notes
    );
}

/// Broken volumes are refused naming the field; a glTF with no volume is
/// no look (a mesh), refused when named and skipped in a folder.
#[test]
fn bad_gltf_volumes_are_refused_by_field() {
    let material = |ext: &str| {
        format!(
            r#"{{"asset":{{"version":"2.0"}},"materials":[{{"name":"m","extensions":{{{ext}}}}}]}}"#
        )
    };
    assert_refused(
        "no_distance.gltf",
        &material(r#""KHR_materials_volume":{"attenuationColor":[0.5,0.5,0.5]}"#),
        "materials[0].extensions.KHR_materials_volume.attenuationDistance: missing",
    );
    assert_refused(
        "white.gltf",
        &material(
            r#""KHR_materials_volume":{"attenuationDistance":0.001,"attenuationColor":[0.5,1.0,0.5]}"#,
        ),
        "KHR_materials_volume.attenuationColor: 1 in green",
    );
    assert_refused(
        "negative.gltf",
        &material(
            r#""KHR_materials_volume":{"attenuationDistance":-1,"attenuationColor":[0.5,0.5,0.5]}"#,
        ),
        "attenuationDistance: -1 must be over 0",
    );
    assert_refused(
        "albedo.gltf",
        &material(
            r#""KHR_materials_volume":{"attenuationDistance":0.001,"attenuationColor":[0.5,0.5,0.5]},"KHR_materials_volume_scatter":{"multiscatterColorFactor":[0.5,2,0.5]}}"#,
        )
        .replace("}}}]}", "}}]}"),
        "KHR_materials_volume_scatter.multiscatterColorFactor: 2 is outside 0–1",
    );
    assert_refused("not_json.gltf", "{\"asset\": [", "malformed glTF JSON");
    // A mesh's glTF (no volume): named, it is refused; in a folder with a
    // look, it is skipped and counted.
    let mesh = r#"{"asset":{"version":"2.0"},"materials":[{"name":"plain"}]}"#;
    assert_refused("mesh.gltf", mesh, "no material has KHR_materials_volume");
    let dir = tmp("gltf_folder");
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("mesh.gltf"), mesh).unwrap();
    export_with(
        &Preset::default_skin(),
        None,
        Format::Gltf,
        &dir.join("skin.gltf"),
        &sphere(false),
    )
    .unwrap();
    let outdir = tmp("gltf_folder_out");
    let _ = std::fs::remove_dir_all(&outdir);
    let (code, stdout, stderr) = cli(&[
        "convert",
        "--from",
        dir.to_str().unwrap(),
        "--to",
        "ron",
        "--out",
        outdir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{stdout}\n{stderr}");
    assert!(
        stdout.contains("1 skipped") || stdout.contains("skipped 1"),
        "{stdout}"
    );
}
