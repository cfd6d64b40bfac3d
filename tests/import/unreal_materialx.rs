//! Unreal's SubsurfaceProfile text and script, and MaterialX documents,
//! read back (issue 24).

use super::*;

/// Export → import through Unreal's struct text and through our .py for
/// every shipped look: the Burley look UE renders comes back (Unreal holds
/// the albedo: the reflectance itself within 1e-3 of the total, and the
/// CDF within 1e-3; the text prints nine decimals), with IOR, the dual
/// lobe and the transmission tint as written (clamped to UE's ranges).
#[test]
fn unreal_round_trip_gives_back_the_look() {
    for (file, _) in library::PRESETS {
        let preset = library::load(file).unwrap();
        let (sent, _) = scatterlab::export::burley_of(&preset.profile).unwrap();
        let out = tmp(&format!("{file}.txt"));
        let written = export(&preset, None, Format::Unreal, &out).unwrap();
        let fields = scatterlab::export::unreal_material_fields(&preset);
        for path in &written {
            let looks = import(path);
            let back = &looks[0].preset;
            let got = burley_of(back);
            same_shape(&sent, &got, 1e-3);
            let (a, b) = (sent.albedo(), got.albedo());
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() < 1e-6, "{file}: albedo {a:?} {b:?}");
            }
            let r = &back.rendering;
            assert!((r.ior - fields.ior).abs() < 1e-6, "{file}");
            assert!(
                (r.specular.lobe_mix - fields.lobe_mix).abs() < 1e-6,
                "{file}"
            );
            assert!(
                (r.specular.lobe0_roughness_multiplier - fields.roughness0).abs() < 1e-6,
                "{file}"
            );
            assert!(
                (r.specular.lobe1_roughness_multiplier - fields.roughness1).abs() < 1e-6,
                "{file}"
            );
        }
    }
}

/// UE's default SubsurfaceProfile, in the details panel's syntax (the
/// struct's defaults, `bEnableMeanFreePath=False`), reads as the look UE
/// 5.1+ upgrades it to, and that is the shipped "Skin (Unreal default)"
/// preset: d and albedo within the text's six decimals.
#[test]
fn unreals_default_profile_is_the_unreal_default_preset() {
    let l = &import(&data("unreal/default_subsurface_profile.txt"))[0];
    assert!(
        l.notes
            .iter()
            .any(|n| n.contains("UpgradeDiffuseMeanFreePathToMeanFreePath")),
        "{:?}",
        l.notes
    );
    let preset = library::load("skin_unreal_default.ron").unwrap();
    let (a, b) = (burley_of(&preset), burley_of(&l.preset));
    let (da, db) = (a.scattering_distance_mm(), b.scattering_distance_mm());
    for c in 0..3 {
        assert!(close(db[c], da[c], 2e-5), "d {da:?} vs {db:?}");
        assert!(close(b.albedo()[c], a.albedo()[c], 1e-5));
    }
    assert_eq!(l.preset.rendering.ior, preset.rendering.ior);
    assert_eq!(l.preset.rendering.specular, preset.rendering.specular);
    assert_eq!(l.preset.rendering.texturing, preset.rendering.texturing);
}

#[test]
fn bad_unreal_text_is_refused_by_field() {
    let good = std::fs::read_to_string(data("unreal/default_subsurface_profile.txt")).unwrap();
    for (name, text, expect) in [
        (
            "open.txt",
            good.replace("LobeMix=0.850000,", "LobeMix=0.850000,(("),
            "malformed struct text",
        ),
        (
            "nan.txt",
            good.replace("MeanFreePathDistance=2.674800", "MeanFreePathDistance=nan"),
            "MeanFreePathDistance: NaN is not a finite number",
        ),
        (
            "huge.txt",
            good.replace("MeanFreePathDistance=2.674800", "MeanFreePathDistance=5000"),
            "MeanFreePathDistance: 5000 cm is outside",
        ),
        (
            "separable.txt",
            good.replace("bEnableBurley=True", "bEnableBurley=False"),
            "bEnableBurley: False: a separable",
        ),
        (
            "albedo.txt",
            good.replace("SurfaceAlbedo=(R=0.910580", "SurfaceAlbedo=(R=1.910580"),
            "SurfaceAlbedo.R: 1.91058 is outside 0–1",
        ),
        (
            "nofield.txt",
            good.replace("MeanFreePathColor=", "MeanFreePathColour="),
            "MeanFreePathColor: missing",
        ),
        (
            "trailing.txt",
            format!("{good} extra"),
            "text after the struct",
        ),
    ] {
        assert_refused(name, &text, expect);
    }
}

/// Christensen & Burley 2015 eq. 5, s(A) = 1.85 − A + 7|A − 0.8|³, typed
/// here: OpenPBR's and Standard Surface's mean free path ℓ is d·s(A).
fn s_perp(a: f64) -> f64 {
    1.85 - a + 7.0 * (a - 0.8).abs().powi(3)
}

/// MaterialX's own OpenPBR ketchup (subsurface_radius left at the
/// nodedef's 1.0, no unit: centimetres, said in a note) and Standard
/// Surface jade (radius and scale at their defaults, 1) read as the
/// OpenPBR/Standard Surface definitions say: albedo = subsurface_color,
/// ℓ = radius × scale, d = ℓ/s(A); the default document has
/// subsurface_weight 0 and says what that means.
#[test]
fn materialxs_own_documents_import() {
    let k = &import(&data("materialx/open_pbr_ketchup.mtlx"))[0];
    assert_eq!(k.preset.name, "Ketchup");
    let b = burley_of(&k.preset);
    let a = [0.164, 0.006, 0.002];
    let l = [0.476, 0.058, 0.039].map(|v| v * 1.0 * 10.0);
    for c in 0..3 {
        assert!(close(b.albedo()[c], a[c], 1e-12));
        assert!(
            close(b.scattering_distance_mm()[c], l[c] / s_perp(a[c]), 1e-9),
            "{c}"
        );
    }
    assert_eq!(k.preset.rendering.ior, 1.3);
    assert!(
        k.notes.iter().any(|n| n.contains("centimetres")),
        "{:?}",
        k.notes
    );

    let j = &import(&data("materialx/standard_surface_jade.mtlx"))[0];
    let b = burley_of(&j.preset);
    let a = [0.0603, 0.4398, 0.1916];
    for c in 0..3 {
        assert!(close(
            b.scattering_distance_mm()[c],
            10.0 / s_perp(a[c]),
            1e-9
        ));
    }
    assert!(
        j.notes.iter().any(|n| n.contains("60 % diffuse")),
        "{:?}",
        j.notes
    );

    let d = &import(&data("materialx/open_pbr_default.mtlx"))[0];
    assert!(d.notes.iter().any(|n| n.contains("is 0")), "{:?}", d.notes);
    // --metres-per-unit sets the scene unit of a document without one.
    let m = import_file(
        &data("materialx/open_pbr_ketchup.mtlx"),
        &ImportOptions {
            metres_per_unit: Some(1.0),
        },
    )
    .unwrap();
    let ratio = burley_of(&m[0].preset).scattering_distance_mm()[0]
        / burley_of(&k.preset).scattering_distance_mm()[0];
    assert!(close(ratio, 100.0, 1e-9), "{ratio}");
}

/// Units and colour spaces as the MaterialX specification defines them:
/// a radius in inches is 25.4 mm each; a colour in srgb_texture (on the
/// input or on an enclosing element) is decoded by sRGB's transfer
/// function, typed here from IEC 61966-2-1.
#[test]
fn materialx_units_and_colour_spaces_are_honoured() {
    let srgb = |v: f64| {
        if v <= 0.04045 {
            v / 12.92
        } else {
            ((v + 0.055) / 1.055).powf(2.4)
        }
    };
    let doc = r#"<?xml version="1.0"?>
<materialx version="1.39" colorspace="lin_rec709">
  <open_pbr_surface name="SR_wax" type="surfaceshader" colorspace="srgb_texture">
    <input name="subsurface_weight" type="float" value="1" />
    <input name="subsurface_color" type="color3" value="0.9, 0.6, 0.5" />
    <input name="subsurface_radius" type="float" value="0.1" unittype="distance" unit="inch" />
    <input name="subsurface_radius_scale" type="color3" value="1, 0.5, 0.25" colorspace="lin_rec709" />
  </open_pbr_surface>
</materialx>
"#;
    let path = tmp("wax.mtlx");
    std::fs::write(&path, doc).unwrap();
    let l = &import(&path)[0];
    let b = burley_of(&l.preset);
    let a = [0.9, 0.6, 0.5].map(srgb);
    let mfp = [1.0, 0.5, 0.25].map(|s| s * 0.1 * 25.4);
    for c in 0..3 {
        assert!(close(b.albedo()[c], a[c], 1e-12), "{:?} {a:?}", b.albedo());
        assert!(close(
            b.scattering_distance_mm()[c],
            mfp[c] / s_perp(a[c]),
            1e-9
        ));
    }
    assert!(!l.notes.iter().any(|n| n.contains("centimetres")));
}

/// Export → import through MaterialX for every shipped look: the Burley
/// look the document describes comes back (CDF within 1e-3, albedo within
/// 1e-9), IOR and base roughness as written.
#[test]
fn materialx_round_trip_gives_back_the_look() {
    for (file, _) in library::PRESETS {
        let preset = library::load(file).unwrap();
        let (sent, _) = scatterlab::export::burley_of(&preset.profile).unwrap();
        let out = tmp(&format!("{file}.mtlx"));
        export(&preset, None, Format::Materialx, &out).unwrap();
        let back = &import(&out)[0].preset;
        let got = burley_of(back);
        same_shape(&sent, &got, 1e-3);
        for c in 0..3 {
            assert!((sent.albedo()[c] - got.albedo()[c]).abs() < 1e-9, "{file}");
        }
        assert_eq!(back.rendering.ior, preset.rendering.ior, "{file}");
        assert_eq!(
            back.rendering.specular.roughness, preset.rendering.specular.roughness,
            "{file}"
        );
    }
}

#[test]
fn bad_materialx_is_refused_by_field() {
    let good = std::fs::read_to_string(data("materialx/open_pbr_ketchup.mtlx")).unwrap();
    for (name, text, expect) in [
        ("broken.mtlx", good.replace("</open_pbr_surface>", ""), "malformed XML"),
        ("unit.mtlx", good.replace(r#"value="0.476, 0.058, 0.039" />"#, r#"value="0.476, 0.058, 0.039" /><input name="subsurface_radius" type="float" value="2" unittype="distance" unit="furlong" />"#), "unit \"furlong\""),
        ("space.mtlx", good.replace(r#"colorspace="lin_rec709""#, r#"colorspace="adobergb""#), "colour space \"adobergb\""),
        ("nan.mtlx", good.replace(r#"name="subsurface_color" type="color3" value="0.164"#, r#"name="subsurface_color" type="color3" value="nan"#), "subsurface_color: NaN is not a finite number"),
        ("two.mtlx", good.replace("0.476, 0.058, 0.039", "0.476, 0.058"), "has 2 values"),
        ("root.mtlx", "<?xml version=\"1.0\"?><svg></svg>".to_owned(), "not a MaterialX document"),
        ("none.mtlx", "<?xml version=\"1.0\"?><materialx version=\"1.39\"></materialx>".to_owned(), "no open_pbr_surface"),
    ] {
        assert_refused(name, &text, expect);
    }
}

/// A Substrate Slab's nodes as the material editor copies them
/// (tests/data/unreal/substrate_slab.t3d): Diffuse Albedo (0.8, 0.45,
/// 0.35), SSS MFP (0.12, 0.06, 0.03) cm at SSS MFP Scale 0.5. Burley's d
/// by UE's SubsurfaceProfile conversion (SubsurfaceProfile.cpp
/// `CreateTexture` with `Dmfp2MfpMagicNumber` 0.6, BurleyNormalizedSSS's
/// S_perp): d = 10 · MFP · scale / (0.6 · S_perp(A)) mm, typed here.
#[test]
fn a_substrate_slabs_copied_nodes_import() {
    let l = &import(&data("unreal/substrate_slab.t3d"))[0];
    assert_eq!(l.preset.name, "M_Skin");
    let a = [0.8, 0.45, 0.35];
    let mfp_cm = [0.12, 0.06, 0.03];
    let d = burley_of(&l.preset).scattering_distance_mm();
    for c in 0..3 {
        let want = 10.0 * mfp_cm[c] * 0.5 / (0.6 * s_perp(a[c]));
        assert!(
            (d[c] / want - 1.0).abs() < 1e-6,
            "channel {c}: {} vs {want}",
            d[c]
        );
    }
    assert_eq!(burley_of(&l.preset).albedo(), a);
    assert_eq!(l.preset.rendering.specular.roughness, 0.5);
    // What the Slab draws from something else is refused by field.
    let text = std::fs::read_to_string(data("unreal/substrate_slab.t3d")).unwrap();
    assert_refused(
        "slab_profile.t3d",
        &text.replace(
            "      MaterialExpressionEditorX=-400\n",
            "      SubsurfaceProfile=\"/Script/Engine.SubsurfaceProfile'/Game/SP_Skin.SP_Skin'\"\n      MaterialExpressionEditorX=-400\n",
        ),
        "MaterialExpressionSubstrateSlabBSDF_0.SubsurfaceProfile: the Slab draws",
    );
    assert_refused(
        "slab_wrap.t3d",
        &text.replace(
            "      MaterialExpressionEditorX=-400\n",
            "      SubSurfaceType=MSS_Wrap\n      MaterialExpressionEditorX=-400\n",
        ),
        "SubSurfaceType: MSS_Wrap is not a diffusion profile",
    );
    assert_refused(
        "slab_no_mfp.t3d",
        &text.replace("      SSSMFP=(Expression=\"/Script/Engine.MaterialExpressionConstant3Vector'MaterialGraphNode_3.MaterialExpressionConstant3Vector_1'\")\n", ""),
        "SSSMFP: not plugged and no SubsurfaceProfile",
    );
    assert_refused(
        "slab_texture.t3d",
        &text.replace(
            "Class=/Script/Engine.MaterialExpressionConstant3Vector Name=\"MaterialExpressionConstant3Vector_1\"",
            "Class=/Script/Engine.MaterialExpressionTextureSample Name=\"MaterialExpressionConstant3Vector_1\"",
        ),
        "SSSMFP: driven by a MaterialExpressionTextureSample node",
    );
    assert_refused(
        "slab_open.t3d",
        &text.replacen("End Object\n", "", 1),
        "no End Object",
    );
}
