#![allow(clippy::unwrap_used)]
#![allow(clippy::needless_range_loop)]
//! Every export format: parsed back, or checked against the target's
//! documented layout, with values round-tripped where the format allows.
//! References: Burley's closed forms (Christensen & Burley 2015 eq. 2–3),
//! HDRP's DiffusionProfileSettings fields, Unreal's struct export syntax,
//! naga for WGSL, the png/exr decoders.

use scatterlab::export::{export, Format, LUT_LAYOUT, PROFILE_TEXELS};
use scatterlab::model::lut::preintegrated_d;
use scatterlab::model::units::UnrealProfile;
use scatterlab::settings::profile::{BurleyShape, BurleySpec};
use scatterlab::settings::{Preset, ProfileSpec};
use std::path::{Path, PathBuf};

fn tmp(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("scatterlab-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn skin() -> Preset {
    Preset::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/skin_default.ron")).unwrap()
}

/// The default skin's d = mm × multiplier, read from the preset itself.
fn skin_d_and_albedo(p: &Preset) -> ([f64; 3], [f64; 3]) {
    match &p.profile {
        ProfileSpec::Burley(BurleySpec {
            albedo,
            shape: BurleyShape::ScatteringDistance { mm, multiplier },
        }) => (mm.map(|v| v * multiplier), *albedo),
        other => panic!("{other:?}"),
    }
}

fn numbers_after(text: &str, key: &str) -> Vec<f64> {
    let start = text
        .find(key)
        .unwrap_or_else(|| panic!("{key} missing in\n{text}"))
        + key.len();
    let rest = &text[start..];
    let end = rest.find('\n').unwrap_or(rest.len());
    rest[..end]
        .split(|c: char| !(c.is_ascii_digit() || c == '.' || c == '-' || c == 'e'))
        .filter_map(|s| s.parse().ok())
        .collect()
}

#[test]
fn ron_round_trips() {
    let p = skin();
    let out = tmp("skin.ron");
    export(&p, None, Format::Ron, &out).unwrap();
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains(&format!("scatterlab {}", env!("CARGO_PKG_VERSION"))));
    assert_eq!(Preset::from_ron(&text, &out).unwrap(), p);
}

/// HDRP layout: script GUID, m_Version 2, the LDR colour ≤ 191/255 with
/// its multiplier giving back d, and every documented field.
#[test]
fn unity_asset_has_hdrp_layout_and_round_trips_d() {
    let mut p = skin();
    p.rendering.thickness_remap_mm = (0.5, 7.0);
    p.rendering.ior = 1.35;
    let out = tmp("skin.asset");
    export(
        &p,
        Some(Path::new("presets/skin_default.ron")),
        Format::Unity,
        &out,
    )
    .unwrap();
    let t = std::fs::read_to_string(&out).unwrap();
    assert!(t.starts_with("%YAML 1.1\n%TAG !u! tag:unity3d.com,2011:\n"));
    assert!(t.contains("--- !u!114 &11400000\nMonoBehaviour:\n"));
    assert!(
        t.contains("m_Script: {fileID: 11500000, guid: b2686e09ec7aef44bad2843e4416f057, type: 3}")
    );
    assert!(t.contains("\n  m_Version: 2\n"));
    assert!(t.contains("presets/skin_default.ron"));
    for field in [
        "scatteringDistance:",
        "scatteringDistanceMultiplier:",
        "transmissionTint:",
        "texturingMode: 0",
        "smoothnessMultipliers:",
        "lobeMix:",
        "diffuseShadingPower:",
        "transmissionMode: 1",
        "thicknessRemap: {x: 0.5, y: 7}",
        "worldScale: 1",
        "ior: 1.35",
        "hash:",
    ] {
        assert!(t.contains(field), "{field} missing:\n{t}");
    }
    let color = numbers_after(&t, "    scatteringDistance: ");
    let mult = numbers_after(&t, "scatteringDistanceMultiplier: ")[0];
    let (d, _) = skin_d_and_albedo(&p);
    let max = color[..3].iter().cloned().fold(0.0, f64::max);
    assert!((max - 191.0 / 255.0).abs() < 1e-9, "{color:?}");
    for c in 0..3 {
        assert!(
            (color[c] * mult - d[c]).abs() < 1e-9 * d[c].max(1.0),
            "{c}: {color:?} × {mult} vs {d:?}"
        );
    }
}

/// Unreal's struct text parses back through UnrealProfile to the same d.
#[test]
fn unreal_struct_round_trips_and_python_sets_the_struct() {
    let p = skin();
    let out = tmp("skin_unreal.txt");
    let written = export(&p, None, Format::Unreal, &out).unwrap();
    assert_eq!(written.len(), 2);
    let t = std::fs::read_to_string(&out).unwrap();
    assert!(t.starts_with("(SurfaceAlbedo=(R="), "{t}");
    assert!(t.trim_end().ends_with(')'));
    // Struct export syntax: Key=(R=..,G=..,B=..,A=..) and Key=value.
    let color = |key: &str| -> [f64; 3] {
        let at = t.find(&format!("{key}=(")).unwrap() + key.len() + 2;
        let body = &t[at..at + t[at..].find(')').unwrap()];
        let v: Vec<f64> = body
            .split(',')
            .map(|kv| kv.split('=').nth(1).unwrap().parse().unwrap())
            .collect();
        [v[0], v[1], v[2]]
    };
    let scalar = |key: &str| -> f64 {
        let at = t.find(&format!(",{key}=")).unwrap() + key.len() + 2;
        let end = t[at..].find([',', ')']).unwrap();
        t[at..at + end].parse().unwrap()
    };
    let (albedo, mfp) = (color("SurfaceAlbedo"), color("MeanFreePathColor"));
    let (dist, wus) = (scalar("MeanFreePathDistance"), scalar("WorldUnitScale"));
    let u = UnrealProfile {
        surface_albedo: albedo,
        mean_free_path_color: mfp,
        mean_free_path_distance_cm: dist,
        world_unit_scale: wus,
    };
    let back = u.to_burley().unwrap();
    let (d, a) = skin_d_and_albedo(&p);
    for c in 0..3 {
        assert!(
            (back.scattering_distance_mm()[c] / d[c] - 1.0).abs() < 1e-5,
            "{:?} vs {d:?}",
            back.scattering_distance_mm()
        );
        assert!((back.albedo()[c] - a[c]).abs() < 1e-6);
    }
    let py = std::fs::read_to_string(&written[1]).unwrap();
    assert!(py.contains("unreal.SubsurfaceProfileStruct()"));
    assert!(py.contains("set_editor_property(\"mean_free_path_distance\", "));
    assert!(py.contains(&format!("scatterlab {}", env!("CARGO_PKG_VERSION"))));
}

/// The WGSL export is a valid module (naga) and the kernel's weights sum
/// to 1 per channel; HLSL and GLSL hold the same number of taps.
#[test]
fn shader_arrays_parse_and_are_normalised() {
    let p = skin();
    let out = tmp("kernel.wgsl");
    export(&p, None, Format::Wgsl, &out).unwrap();
    let wgsl = std::fs::read_to_string(&out).unwrap();
    let module = naga::front::wgsl::parse_str(&wgsl)
        .unwrap_or_else(|e| panic!("{}\n{wgsl}", e.emit_to_string(&wgsl)));
    assert!(module.constants.iter().count() >= 3);
    let taps: Vec<Vec<f64>> = wgsl
        .lines()
        .skip_while(|l| !l.starts_with("const kernel"))
        .skip(1)
        .take_while(|l| l.trim_start().starts_with("vec4"))
        .map(|l| numbers_after(l, "vec4<f32>("))
        .collect();
    assert_eq!(taps.len(), p.rendering.taps);
    for c in 0..3 {
        let sum: f64 = taps.iter().map(|t| t[c]).sum();
        assert!((sum - 1.0).abs() < 1e-5, "channel {c}: {sum}");
    }
    assert_eq!(taps[0][3], 0.0, "centre tap first");
    for (fmt, ext, ty) in [
        (Format::Hlsl, "hlsl", "float4("),
        (Format::Glsl, "glsl", "vec4("),
    ] {
        let out = tmp(&format!("kernel.{ext}"));
        export(&p, None, fmt, &out).unwrap();
        let t = std::fs::read_to_string(&out).unwrap();
        let n = p.rendering.taps;
        assert!(
            t.contains(&format!("kernel[{n}]")) || t.contains(&format!("vec4[{n}]")),
            "{t}"
        );
        let rows = t.lines().filter(|l| l.trim_start().starts_with(ty)).count();
        assert_eq!(rows, n + 2 * p.rendering.samples, "{ext}");
    }
}

/// Burley's total reflectance is the albedo A (C&B 2015 eq. 3 integrates
/// to A); the dominant channel's weights sum to it exactly.
#[test]
fn samples_json_weights_estimate_the_albedo() {
    let p = skin();
    let out = tmp("samples.json");
    export(&p, None, Format::SamplesJson, &out).unwrap();
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let samples = v["samples"].as_array().unwrap();
    assert_eq!(samples.len(), p.rendering.samples);
    let (_, albedo) = skin_d_and_albedo(&p);
    let dom = ["r", "g", "b"]
        .iter()
        .position(|c| v["sampled_channel"] == *c)
        .unwrap();
    let sum: f64 = samples
        .iter()
        .map(|s| s["weight"][dom].as_f64().unwrap())
        .sum();
    assert!((sum - albedo[dom]).abs() < 1e-9, "{sum} vs {}", albedo[dom]);
    assert!(samples
        .iter()
        .all(|s| s["radius_mm"].as_f64().unwrap() > 0.0));
}

fn png_text(path: &Path) -> (png::OutputInfo, Vec<u8>, String) {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let text = reader
        .info()
        .uncompressed_latin1_text
        .iter()
        .map(|t| format!("{}: {}", t.keyword, t.text))
        .collect::<Vec<_>>()
        .join("\n");
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    (info, buf, text)
}

/// Decoded LUT texels match D computed directly by quadrature
/// (`preintegrated_d`, the reference the fast row bake is tested against).
#[test]
fn lut_png_and_exr_decode_to_the_direct_integral() {
    let p = skin();
    let profile = p.build_profile().unwrap();
    let out = tmp("lut.png");
    let written = export(&p, None, Format::LutPng, &out).unwrap();
    let (info, buf, text) = png_text(&out);
    assert_eq!(
        (info.width as usize, info.height as usize),
        (LUT_LAYOUT.width, LUT_LAYOUT.height)
    );
    assert!(
        text.contains("delta-encoded") && text.contains("scatterlab"),
        "{text}"
    );
    let (i, j) = (200, 40);
    let ndl = LUT_LAYOUT.n_dot_l(i);
    let c = LUT_LAYOUT.curvature_radius(j);
    let d = preintegrated_d(profile.as_ref(), ndl.acos(), c);
    for ch in 0..3 {
        let v = buf[(j * LUT_LAYOUT.width + i) * 3 + ch] as f64 / 255.0;
        let decoded = (v - 0.5) * 0.5 + ndl.max(0.0);
        assert!(
            (decoded - d[ch]).abs() < 1.5 / 255.0,
            "ch {ch}: {decoded} vs {}",
            d[ch]
        );
    }
    let (_, _, shadow_text) = png_text(&written[1]);
    assert!(shadow_text.contains("Penumbra"), "{shadow_text}");

    let out = tmp("lut.exr");
    export(&p, None, Format::LutExr, &out).unwrap();
    let image = exr::prelude::read_first_rgba_layer_from_file(
        &out,
        |res, _| vec![vec![[0f32; 3]; res.width()]; res.height()],
        |px, pos, (r, g, b, _a): (f32, f32, f32, f32)| px[pos.y()][pos.x()] = [r, g, b],
    )
    .unwrap();
    let px = image.layer_data.channel_data.pixels[j][i];
    for ch in 0..3 {
        assert!(
            (px[ch] as f64 - d[ch]).abs() < 2e-4,
            "ch {ch}: {} vs {}",
            px[ch],
            d[ch]
        );
    }
}

/// r·R(r) texels against Burley's closed form
/// r·R(r) = A·(e^(−r/d) + e^(−r/3d))/(8π d) (C&B 2015 eq. 2).
#[test]
fn profile_exr_and_png_hold_r_times_r() {
    let p = skin();
    let (d, a) = skin_d_and_albedo(&p);
    let profile = p.build_profile().unwrap();
    let r_max = profile
        .radius_for_energy(0.997)
        .into_iter()
        .fold(0.0, f64::max);
    let closed = |c: usize, r: f64| {
        a[c] * ((-r / d[c]).exp() + (-r / (3.0 * d[c])).exp()) / (8.0 * std::f64::consts::PI * d[c])
    };
    let out = tmp("profile.exr");
    let written = export(&p, None, Format::ProfileExr, &out).unwrap();
    let image = exr::prelude::read_first_rgba_layer_from_file(
        &out,
        |res, _| vec![[0f32; 3]; res.width()],
        |px, pos, (r, g, b, _a): (f32, f32, f32, f32)| px[pos.x()] = [r, g, b],
    )
    .unwrap();
    let row = &image.layer_data.channel_data.pixels;
    assert_eq!(row.len(), PROFILE_TEXELS);
    for i in [0, 10, 100, 255] {
        let r = (i as f64 + 0.5) / PROFILE_TEXELS as f64 * r_max;
        for c in 0..3 {
            let want = closed(c, r);
            assert!(
                (row[i][c] as f64 / want - 1.0).abs() < 1e-5,
                "i {i} c {c}: {} vs {want}",
                row[i][c]
            );
        }
    }
    assert!(written[1].to_string_lossy().contains("_transmittance"));
    let out = tmp("profile.png");
    export(&p, None, Format::ProfilePng, &out).unwrap();
    let (info, buf, text) = png_text(&out);
    assert_eq!(info.bit_depth, png::BitDepth::Sixteen);
    assert!(text.contains("divided by its maximum"), "{text}");
    let max = buf
        .chunks(2)
        .map(|b| u16::from_be_bytes([b[0], b[1]]))
        .max()
        .unwrap();
    assert_eq!(max, 65535);
}

/// The snippet's radius and scale give the look's d through Cycles' own
/// rule, typed here from `bssrdf_setup_radius` (Blender 5.0.0
/// kernel/closure/bssrdf.h lines 66–88): d = Radius × Scale / (4π), with no
/// albedo term; Base Color is the albedo; `use_nodes` (deprecated in 5.0)
/// is only set before 5.0. tests/real_clients.rs renders it in Cycles.
#[test]
fn blender_snippet_follows_cycles_radius_rule() {
    let p = skin();
    let out = tmp("skin.py");
    export(&p, None, Format::Blender, &out).unwrap();
    let t = std::fs::read_to_string(&out).unwrap();
    assert!(t.contains("import bpy") && t.contains("Subsurface Radius"));
    let radius = numbers_after(&t, "\nSUBSURFACE_RADIUS = ");
    let scale_m = numbers_after(&t, "\nSUBSURFACE_SCALE_M = ")[0];
    let base = numbers_after(&t, "\nBASE_COLOR = ");
    let (d, a) = skin_d_and_albedo(&p);
    for c in 0..3 {
        let cycles_d_mm = radius[c] * scale_m * 1000.0 / (4.0 * std::f64::consts::PI);
        assert!(
            (cycles_d_mm / d[c] - 1.0).abs() < 1e-9,
            "{c}: {cycles_d_mm} vs {}",
            d[c]
        );
        assert!((base[c] - a[c]).abs() < 1e-12);
    }
    assert!(t.contains("if bpy.app.version < (5, 0, 0):\n    mat.use_nodes = True"));
}

/// A non-Burley look is converted through a fit, and the file says so.
#[test]
fn non_burley_looks_say_they_were_fitted() {
    let p =
        Preset::load(&Path::new(env!("CARGO_MANIFEST_DIR")).join("presets/ketchup_jensen2001.ron"))
            .unwrap();
    let out = tmp("ketchup.asset");
    export(&p, None, Format::Unity, &out).unwrap();
    let t = std::fs::read_to_string(&out).unwrap();
    assert!(t.contains("converted through a Burley fit"), "{t}");
}

/// Bad input: a NaN names its field; an unwritable path names the path and
/// leaves nothing behind.
#[test]
fn bad_input_gives_named_errors_and_writes_nothing() {
    let mut p = skin();
    p.rendering.ior = f64::NAN;
    let out = tmp("nan.asset");
    let e = export(&p, None, Format::Unity, &out)
        .unwrap_err()
        .to_string();
    assert!(e.contains("rendering.ior"), "{e}");
    assert!(!out.exists());
    let bad = Path::new("/definitely/not/a/dir/x.asset");
    let e = export(&skin(), None, Format::Unity, bad)
        .unwrap_err()
        .to_string();
    assert!(e.contains("/definitely/not/a/dir/x.asset"), "{e}");
}
