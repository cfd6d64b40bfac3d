#![allow(clippy::unwrap_used)]
#![allow(clippy::needless_range_loop)]
//! Exports checked by the programs that read them, not by our own code:
//! Blender 5.0.1's Cycles renders the Blender snippet and the scattering
//! distance is measured back from a shadow edge; HDRP's conventions read
//! the Unity asset through a YAML parser; a stand-in `unreal` module that
//! accepts only Unreal's documented property names runs the Unreal script;
//! the OpenEXR bindings open every EXR export; Khronos' glTF validator and
//! Babylon.js's loader read the glTF export. The Python side lives in
//! tests/clients/ (each script cites its sources); `tools/python-env.sh`
//! (the README's test command runs it) installs the programs into `.venv/`,
//! and `tools/node-env.sh` the node ones into tests/clients/node/.

use scatterlab::export::{burley_of, export, Format};
use scatterlab::settings::Preset;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// The virtual environment's Python; never skipped: without it the test
/// fails and says how to make it.
fn python() -> PathBuf {
    venv_python("SCATTERLAB_PYTHON", ".venv")
}

/// Blender 4.5 LTS's Python (a second venv: one Python holds one bpy).
fn python_blender4() -> PathBuf {
    venv_python("SCATTERLAB_PYTHON_BLENDER4", ".venv-blender4")
}

fn venv_python(var: &str, venv: &str) -> PathBuf {
    if let Some(p) = std::env::var_os(var) {
        return PathBuf::from(p);
    }
    let p = root().join(venv).join("bin/python");
    assert!(
        p.exists(),
        "{} is missing: run tools/python-env.sh (the README's test command does) to install Blender's bpy, OpenEXR, MaterialX, PyYAML and godot-parser",
        p.display()
    );
    p
}

fn tmp_dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scatterlab-clients-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Runs a script from tests/clients and returns its last stdout line as JSON.
fn run_client(script: &str, args: &[&str], env: &[(&str, &str)]) -> Value {
    run_client_in(&python(), script, args, env)
}

fn run_client_in(python: &Path, script: &str, args: &[&str], env: &[(&str, &str)]) -> Value {
    let mut cmd = Command::new(python);
    cmd.arg(root().join("tests/clients").join(script))
        .args(args);
    for (k, v) in env {
        cmd.env(k, v);
    }
    let out = cmd.output().expect("run the client Python");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "{script} {args:?} failed ({}):\n{stdout}\n{stderr}",
        out.status
    );
    let last = stdout
        .lines()
        .rev()
        .find(|l| l.starts_with('{'))
        .unwrap_or_else(|| {
            panic!("{script} printed no JSON:\n{stdout}\n{stderr}");
        });
    serde_json::from_str(last).unwrap()
}

fn preset(file: &str) -> Preset {
    Preset::load(&root().join("presets").join(file)).unwrap()
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect()
}

/// The sun of tests/clients/blender_edge.py: 3 W/m² straight down.
const SUN_IRRADIANCE: f64 = 3.0;

/// Renders the Blender export of `p` in Cycles and returns (d wanted,
/// d measured, albedo, measured lit radiance) per channel.
fn cycles_edge(p: &Preset, tag: &str, extra: &[&str]) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    cycles_edge_in(&python(), p, tag, extra)
}

fn cycles_edge_in(
    python: &Path,
    p: &Preset,
    tag: &str,
    extra: &[&str],
) -> (Vec<f64>, Vec<f64>, Vec<f64>, Vec<f64>) {
    let (burley, _) = burley_of(&p.profile).unwrap();
    let d = burley.scattering_distance_mm().to_vec();
    let (d_min, d_max) = (
        d.iter().cloned().fold(f64::INFINITY, f64::min),
        d.iter().cloned().fold(0.0, f64::max),
    );
    // Ten of the widest d across, pixels at most a quarter of the narrowest.
    let width_mm = (10.0 * d_max).clamp(4.0, 80.0);
    let pixels = ((width_mm / (d_min / 4.0)).ceil() as usize).clamp(160, 480);
    let dir = tmp_dir(tag);
    let snippet = dir.join("snippet.py");
    export(p, None, Format::Blender, &snippet).unwrap();
    let (w, n) = (format!("{width_mm}"), format!("{pixels}"));
    let mut args = vec![
        snippet.to_str().unwrap(),
        dir.to_str().unwrap(),
        "--width-mm",
        &w,
        "--pixels",
        &n,
    ];
    args.extend_from_slice(extra);
    let v = run_client_in(python, "blender_edge.py", &args, &[]);
    let inputs = &v["inputs"];
    assert_eq!(inputs["subsurface_method"], "BURLEY", "{tag}: {v}");
    assert_eq!(inputs["linked_to_output"], true, "{tag}: {v}");
    assert_eq!(
        inputs["subsurface_weight"].as_f64(),
        Some(1.0),
        "{tag}: {v}"
    );
    (
        d,
        floats(&v["d_mm"]),
        burley.albedo().to_vec(),
        floats(&v["amplitude"]),
    )
}

/// Cycles scatters the distance the preset asks for: each channel's d,
/// fitted to the rendered shadow edge with Burley's edge-spread function
/// (tests/clients/blender_edge.py derives it independently), is within
/// 10 % of the look's d, and the lit side's radiance is Base Color × E/π
/// within 5 %. Presets: the default skin (Burley), Jensen 2001's measured
/// Skin1 and the wax dipole (both through their Burley fit, whose d is
/// what the export carries). With the s(A) division Cycles dropped in
/// Blender 3.0, the skin's green and blue came out 2.3× and 2.6× too wide.
#[test]
fn blender_export_scatters_the_look_distance_in_cycles() {
    let mut report = String::new();
    let mut worst = 0.0f64;
    for file in ["skin_default.ron", "skin1_jensen2001.ron", "wax.ron"] {
        let p = preset(file);
        let (want, got, albedo, amp) = cycles_edge(&p, file, &[]);
        for c in 0..3 {
            let rel = got[c] / want[c] - 1.0;
            worst = worst.max(rel.abs());
            report += &format!(
                "{file} ch{c}: d {:.4} mm, Cycles {:.4} mm ({:+.1} %); lit {:.4}, A·E/π {:.4}\n",
                want[c],
                got[c],
                100.0 * rel,
                amp[c],
                albedo[c] * SUN_IRRADIANCE / std::f64::consts::PI
            );
        }
        for c in 0..3 {
            assert!(
                (got[c] / want[c] - 1.0).abs() < 0.10,
                "{file} channel {c}: Cycles scatters d = {} mm, the look has {} mm\n{report}",
                got[c],
                want[c]
            );
            let lit = albedo[c] * SUN_IRRADIANCE / std::f64::consts::PI;
            assert!(
                (amp[c] / lit - 1.0).abs() < 0.05,
                "{file} channel {c}: lit radiance {} vs Base Color × E/π = {lit}\n{report}",
                amp[c]
            );
        }
    }
    eprintln!("{report}worst |Δd|/d = {:.1} %", 100.0 * worst);
}

/// Renders `view` of a head with `scatterlab render` (`none` and
/// `reference`, linear EXR, the key light alone: --ior 1, no environment,
/// transmission off) and the same shot in Cycles from the recorded camera
/// and mesh (tests/clients/blender_head.py); returns its figures.
fn cycles_head(
    tag: &str,
    mesh: &[&str],
    view: (&str, &str, &str),
    size: u32,
    samples: u32,
) -> Value {
    let dir = tmp_dir(tag);
    let snippet = dir.join("snippet.py");
    export(&Preset::default_skin(), None, Format::Blender, &snippet).unwrap();
    let size = size.to_string();
    let (yaw, az, el) = view;
    for method in ["none", "reference"] {
        let out = Command::new(env!("CARGO_BIN_EXE_scatterlab"))
            .current_dir(root())
            .arg("render")
            .args(mesh)
            .args([
                "--camera-yaw",
                yaw,
                "--light-azimuth",
                az,
                "--light-elevation",
                el,
            ])
            .args(["--no-lod", "--ior", "1", "--transmission", "off"])
            .args(["--environment-intensity", "0", "--deterministic"])
            .args(["--width", &size, "--height", &size, "--method", method])
            .arg("--out")
            .arg(dir.join(format!("{method}.exr")))
            .arg("--stats")
            .arg(dir.join(format!("{method}.json")))
            .arg("--scene-obj")
            .arg(dir.join("mesh.obj"))
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{tag} {method}: {}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let p = |f: &str| dir.join(f).to_str().unwrap().to_owned();
    let samples = samples.to_string();
    run_client(
        "blender_head.py",
        &[
            &p("snippet.py"),
            &p("none.json"),
            &p("mesh.obj"),
            &p("none.exr"),
            &p("reference.exr"),
            &p("."),
            "--samples",
            &samples,
            "--seeds",
            "1,2",
        ],
        &[],
    )
}

/// Cycles scatters the light on a whole head as the ground truth does
/// (issue 53, item 3): the scan and the procedural head lit from the side
/// (camera yaw 20°, sun at azimuth 100°, elevation 10°), 96², 256 samples
/// and two seeds of Cycles' Christensen-Burley against `reference`, each
/// minus its own unscattered frame (Cycles with Subsurface Weight 0,
/// scatterlab's `none`). Figures are shares of the lit level A·E/π.
/// - The shot is the same: the skin masks overlap by 99.9 % (IoU ≥ 0.995)
///   and the unscattered frames differ by 1.0-1.3 % RMS (< 3 %; a camera a
///   pixel off, or the mesh in other units, is far beyond).
/// - Over the skin, the ground truth's scattering effect leaves 0.52-0.54
///   of Cycles' (RMS of the difference over RMS of Cycles' effect; < 0.8):
///   a frame that does not scatter leaves 1.0 (measured: `none` given as
///   the ground truth fails all three). In the shadowed skin, where light
///   scattered in is the whole signal, 0.35-0.36 (< 0.6), and its mean
///   there is 0.75-0.88 of Cycles' (0.6-1.3). Cycles' seeds' noise there
///   is 0.05 % against an RMS effect of 0.4-1.0 %.
///
/// What is left is Cycles' noise (the two seeds), Cycles' gain on curved
/// surfaces (+3 % in red on a 10 mm sphere against a quadrature that the
/// ground truth matches within 0.3 %; docs/accuracy.md) and the shadow
/// map's light in creases.
#[test]
fn cycles_scatters_a_whole_head_as_the_ground_truth_does() {
    let mut report = String::new();
    let mut failures = Vec::new();
    let heads: [(&str, &[&str]); 2] = [
        (
            "scan",
            &[
                "--mesh",
                "assets/scan/LeePerrySmith.glb",
                "--metres-per-unit",
                "0.0462",
                "--camera-distance",
                "0.6",
            ],
        ),
        (
            "head",
            &[
                "--mesh",
                "assets/head/head.obj",
                "--metres-per-unit",
                "0.1",
                "--camera-distance",
                "0.55",
            ],
        ),
    ];
    for (tag, mesh) in heads {
        let v = cycles_head(&format!("head-{tag}"), mesh, ("20", "100", "10"), 96, 256);
        let iou = v["pixels"]["mask_iou"].as_f64().unwrap();
        let unscattered = v["unscattered"]["rms_none_vs_no_sss"].as_f64().unwrap();
        let r = &v["regions"];
        let f = |region: &str, key: &str| r[region][key].as_f64().unwrap();
        let skill =
            |region: &str| f(region, "rms_reference_minus_cycles") / f(region, "rms_cycles");
        let mean_ratio = f("shadow", "effect_reference") / f("shadow", "effect_cycles");
        report += &format!(
            "{tag}: IoU {iou:.4}, unscattered RMS {:.2} %, left over skin {:.2}, in shadow {:.2}, shadow mean {:.2} (noise {:.2} % of RMS {:.2} %)\n",
            100.0 * unscattered,
            skill("skin"),
            skill("shadow"),
            mean_ratio,
            100.0 * f("shadow", "noise"),
            100.0 * f("shadow", "rms_cycles"),
        );
        for (ok, what) in [
            (iou >= 0.995, "skin masks"),
            (unscattered < 0.03, "unscattered frames"),
            (skill("skin") < 0.8, "effect over the skin"),
            (skill("shadow") < 0.6, "effect in shadow"),
            ((0.6..1.3).contains(&mean_ratio), "mean effect in shadow"),
        ] {
            if !ok {
                failures.push(format!("{tag}: {what}"));
            }
        }
    }
    eprint!("{report}");
    assert!(failures.is_empty(), "{failures:?}\n{report}");
}

/// A frame that Cycles' script cannot match is refused with the field and
/// the fix, before any render: the default render settings light the head
/// with the studio environment, specular and thin transmission too, which
/// the record names in `camera.unrecorded`.
#[test]
fn cycles_head_script_refuses_a_frame_it_cannot_match() {
    let dir = tmp_dir("head-unmatched");
    let p = |f: &str| dir.join(f).to_str().unwrap().to_owned();
    export(
        &Preset::default_skin(),
        None,
        Format::Blender,
        &dir.join("snippet.py"),
    )
    .unwrap();
    for method in ["none", "reference"] {
        let out = Command::new(env!("CARGO_BIN_EXE_scatterlab"))
            .current_dir(root())
            .args([
                "render",
                "--mesh",
                "assets/head/head.obj",
                "--metres-per-unit",
                "0.1",
            ])
            .args([
                "--no-lod", "--width", "32", "--height", "32", "--method", method,
            ])
            .args([
                "--out",
                &p(&format!("{method}.exr")),
                "--stats",
                &p("none.json"),
            ])
            .args(["--scene-obj", &p("mesh.obj")])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    let out = Command::new(python())
        .arg(root().join("tests/clients/blender_head.py"))
        .args([
            p("snippet.py"),
            p("none.json"),
            p("mesh.obj"),
            p("none.exr"),
            p("reference.exr"),
            p("."),
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!out.status.success(), "{err}");
    assert!(
        err.contains("camera.unrecorded")
            && err.contains("environment")
            && err.contains("--ior 1 --transmission off --environment-intensity 0"),
        "{err}"
    );
    assert!(
        !dir.join("cycles_no_sss.exr").exists(),
        "it rendered before refusing"
    );
}

/// On an artist's object that already has a Principled BSDF (Random Walk,
/// other colours), in a scene modelled in centimetres (Unit Scale 0.01),
/// the snippet replaces the values and Cycles still scatters the look's
/// physical millimetres; on a material with only a Diffuse BSDF it adds a
/// Principled BSDF and connects it to the output.
#[test]
fn blender_export_on_an_existing_material_and_a_centimetre_scene() {
    let p = Preset::default_skin();
    let (want, got, _, _) = cycles_edge(
        &p,
        "existing-cm",
        &["--existing-material", "principled", "--unit-scale", "0.01"],
    );
    for c in 0..3 {
        assert!(
            (got[c] / want[c] - 1.0).abs() < 0.10,
            "channel {c}: Cycles scatters d = {} mm in a cm scene, the look has {} mm",
            got[c],
            want[c]
        );
    }
    let dir = tmp_dir("diffuse-only");
    let snippet = dir.join("snippet.py");
    export(&p, None, Format::Blender, &snippet).unwrap();
    let v = run_client(
        "blender_edge.py",
        &[
            snippet.to_str().unwrap(),
            dir.to_str().unwrap(),
            "--existing-material",
            "diffuse",
            "--no-render",
        ],
        &[],
    );
    let inputs = &v["inputs"];
    assert_eq!(inputs["material"], "ArtistSkin", "{v}");
    assert_eq!(inputs["materials_on_object"], 1, "{v}");
    assert_eq!(inputs["linked_to_output"], true, "{v}");
    assert_eq!(inputs["subsurface_method"], "BURLEY", "{v}");
}

/// The same snippet in Blender 4.5 LTS (PyPI `bpy` 4.5.15), where a
/// material's `use_nodes` is still needed and the 5.0 guards must not
/// trip: the default skin on a fresh plane, and on an artist's Principled
/// material in a centimetre scene, scatters the look's d within 10 %.
#[test]
fn blender_export_works_in_blender_4_5() {
    let p = Preset::default_skin();
    let py = python_blender4();
    for (tag, extra) in [
        ("b45-fresh", &[][..]),
        (
            "b45-existing-cm",
            &["--existing-material", "principled", "--unit-scale", "0.01"][..],
        ),
    ] {
        let (want, got, _, _) = cycles_edge_in(&py, &p, tag, extra);
        for c in 0..3 {
            assert!(
                (got[c] / want[c] - 1.0).abs() < 0.10,
                "{tag}: channel {c}: Blender 4.5's Cycles scatters d = {} mm, the look has {} mm",
                got[c],
                want[c]
            );
        }
    }
}

/// The Unity asset read as HDRP reads it (tests/clients/unity_yaml.py
/// writes HDRP's conventions down with their source lines): field order,
/// GUID, m_Name = the file's name, d from colour × multiplier, and the dual
/// lobe: each of HDRP's two lobes has the roughness and weight of the
/// viewport's lobe (before the fix HDRP put 0.15 on the smoother lobe where
/// the viewport puts 0.85), for every shipped preset.
#[test]
fn unity_asset_reads_as_hdrp_reads_it() {
    let dir = tmp_dir("unity");
    let mut n = 0;
    for entry in std::fs::read_dir(root().join("presets")).unwrap() {
        let path = entry.unwrap().path();
        let p = Preset::load(&path).unwrap();
        let stem = format!("SSS {}", path.file_stem().unwrap().to_string_lossy());
        let out = dir.join(format!("{stem}.asset"));
        export(&p, Some(&path), Format::Unity, &out).unwrap();
        let (burley, _) = burley_of(&p.profile).unwrap();
        let s = &p.rendering.specular;
        let expect = serde_json::json!({
            "file_stem": stem,
            "d_mm": burley.scattering_distance_mm(),
            "world_scale_m_per_unit": p.rendering.world_scale_m_per_unit,
            "roughness": s.roughness,
            "m0": s.lobe0_roughness_multiplier,
            "m1": s.lobe1_roughness_multiplier,
            "lobe_mix": s.lobe_mix,
        });
        let expect_path = dir.join(format!("{stem}.json"));
        std::fs::write(&expect_path, expect.to_string()).unwrap();
        run_client(
            "unity_yaml.py",
            &[out.to_str().unwrap(), expect_path.to_str().unwrap()],
            &[],
        );
        n += 1;
    }
    assert!(n >= 17, "{n} presets");
}

/// The Unreal script runs against a stand-in `unreal` module that knows
/// only the documented SubsurfaceProfileStruct properties of UE 5.1+ and
/// their clamps; what it sets, converted back with UE's own formulas
/// (tests/clients/unreal_check.py), is the look's d, and the struct text
/// agrees. The Substrate material it builds (UE 5.7's Python API, typed
/// into the stub) holds one Slab of type Diffusion with the profile on the
/// Slab and the material, or with `--substrate-diffusion` an SSS MFP that
/// reads back as the look's d. Under UE 5.0's API (no
/// enable_mean_free_path) it stops with a message instead of setting a
/// different look.
#[test]
fn unreal_script_runs_against_the_documented_api() {
    let dir = tmp_dir("unreal");
    for file in [
        "skin_default.ron",
        "skin_unreal_default.ron",
        "jade.ron",
        "skin1_jensen2001.ron",
    ] {
        let p = preset(file);
        let out = dir.join(format!("{file}.txt"));
        let written = export(&p, None, Format::Unreal, &out).unwrap();
        let v = run_client(
            "unreal_check.py",
            &[written[1].to_str().unwrap(), out.to_str().unwrap()],
            &[],
        );
        let (burley, _) = burley_of(&p.profile).unwrap();
        let want = burley.scattering_distance_mm();
        let got = floats(&v["d_mm"]);
        for c in 0..3 {
            assert!(
                (got[c] / want[c] - 1.0).abs() < 1e-5,
                "{file} channel {c}: UE reads d = {} mm, the look has {} mm",
                got[c],
                want[c]
            );
        }
        assert!(
            v["mean_free_path_distance_cm"].as_f64().unwrap() >= 0.1,
            "{v}"
        );
        // UE's LobeMix is the weight of lobe 1, as ours (clamped to 0.1–0.9).
        let mix = v["lobe_mix"].as_f64().unwrap();
        assert!(
            (mix - p.rendering.specular.lobe_mix.clamp(0.1, 0.9)).abs() < 1e-9,
            "{v}"
        );
        // The Substrate material: one Slab of type Diffusion on the Front
        // Material, the profile on the Slab and on the material, the
        // look's albedo as Diffuse Albedo.
        let sub = &v["substrate"];
        assert_eq!(sub["uses_profile"], true, "{file}: {sub}");
        let a = floats(&sub["albedo"]);
        for c in 0..3 {
            assert!((a[c] - burley.albedo()[c]).abs() < 1e-12, "{file}: {sub}");
        }
        // --substrate-diffusion: the Slab's own SSS MFP (cm), read back to
        // d by Christensen & Burley's eq. 5 in the check script.
        let out = dir.join(format!("{file}_diffusion.txt"));
        let options = scatterlab::export::ExportOptions {
            unreal_substrate_diffusion: true,
            ..Default::default()
        };
        let written =
            scatterlab::export::export_with(&p, None, Format::Unreal, &out, &options).unwrap();
        let v = run_client(
            "unreal_check.py",
            &[written[1].to_str().unwrap(), out.to_str().unwrap()],
            &[],
        );
        let sub = &v["substrate"];
        assert_eq!(sub["uses_profile"], false, "{file}: {sub}");
        let got = floats(&sub["d_mm"]);
        for c in 0..3 {
            assert!(
                (got[c] / want[c] - 1.0).abs() < 1e-9,
                "{file} channel {c}: the Slab's SSS MFP reads as d = {} mm, the look has {} mm",
                got[c],
                want[c]
            );
        }
    }
    // An engine without Substrate: the profile is set, the script warns
    // and makes no material.
    let out = dir.join("no_substrate.txt");
    let written = export(&Preset::default_skin(), None, Format::Unreal, &out).unwrap();
    let v = run_client(
        "unreal_check.py",
        &[written[1].to_str().unwrap(), out.to_str().unwrap()],
        &[("SCATTERLAB_UNREAL_STUB_SUBSTRATE", "0")],
    );
    assert!(v["substrate"].is_null(), "{v}");
    // UE 5.0: a clear stop, naming the version.
    let p = Preset::default_skin();
    let out = dir.join("ue50.txt");
    let written = export(&p, None, Format::Unreal, &out).unwrap();
    let o = Command::new(python())
        .arg(root().join("tests/clients/unreal_check.py"))
        .args([written[1].to_str().unwrap(), out.to_str().unwrap()])
        .env("SCATTERLAB_UNREAL_STUB_VERSION", "5.0")
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "the script ran on UE 5.0's API");
    assert!(err.contains("Unreal Engine 5.1 or later"), "{err}");
}

/// Every EXR export opens in the OpenEXR bindings with the layout its
/// header states, and holds Burley's closed forms (r·R(r), T(d)) and the
/// flat-skin limits of the two tables (tests/clients/exr_check.py).
#[test]
fn exr_exports_open_in_openexr() {
    let dir = tmp_dir("exr");
    let p = Preset::default_skin();
    let profile = dir.join("profile.exr");
    let lut = dir.join("lut.exr");
    let pw = export(&p, None, Format::ProfileExr, &profile).unwrap();
    let lw = export(&p, None, Format::LutExr, &lut).unwrap();
    let (burley, _) = burley_of(&p.profile).unwrap();
    let expect = serde_json::json!({
        "profile": pw[0], "transmittance": pw[1], "lut": lw[0], "shadow": lw[1],
        "albedo": burley.albedo(), "d_mm": burley.scattering_distance_mm(),
        "thickness_max_mm": p.rendering.thickness_remap_mm.1,
    });
    let e = dir.join("expect.json");
    std::fs::write(&e, expect.to_string()).unwrap();
    let v = run_client("exr_check.py", &[e.to_str().unwrap()], &[]);
    eprintln!("EXR worst errors: {v}");
}

/// The MaterialX export validates against MaterialX's standard libraries
/// (tests/clients/materialx_check.py), for every shipped preset, and its
/// OpenPBR mean free path, converted with Christensen & Burley's eq. 5
/// typed in the checker, gives back the look's d.
#[test]
fn materialx_export_validates_and_holds_the_look() {
    let dir = tmp_dir("materialx");
    for entry in std::fs::read_dir(root().join("presets")).unwrap() {
        let path = entry.unwrap().path();
        let p = Preset::load(&path).unwrap();
        let out = dir.join(format!(
            "{}.mtlx",
            path.file_stem().unwrap().to_string_lossy()
        ));
        export(&p, Some(&path), Format::Materialx, &out).unwrap();
        let v = run_client("materialx_check.py", &[out.to_str().unwrap()], &[]);
        let (burley, _) = burley_of(&p.profile).unwrap();
        let want = burley.scattering_distance_mm();
        let got = floats(&v["d_mm"]);
        for c in 0..3 {
            assert!(
                (got[c] / want[c] - 1.0).abs() < 1e-6,
                "{}: channel {c}: {} vs {} mm",
                path.display(),
                got[c],
                want[c]
            );
        }
    }
}

/// Godot 4: the `.tres` parses with godot-parser, its properties are
/// BaseMaterial3D's within their ranges, and the error of r·R(r) the file
/// states is what Godot's own kernel (its shader table, rebuilt and checked
/// in godot_check.py) gives at the written strength against the profile
/// EXR, and no nearby width does better. The Jimenez demo preset is Godot's
/// own kernel: it must go across with almost no error.
#[test]
fn godot_material_states_what_godot_renders() {
    let dir = tmp_dir("godot");
    for (file, total) in [
        ("skin_default.ron", None),
        ("skin_unreal_default.ron", None),
        ("wax.ron", None),
        ("skin1_jensen2001.ron", None),
        // An energy-conserving blur (Jimenez 2012: strength·profile plus a
        // 1 − strength Dirac) reflects all the light.
        ("skin_jimenez2012_demo.ron", Some([1.0; 3])),
    ] {
        let path = root().join("presets").join(file);
        let p = Preset::load(&path).unwrap();
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        let tres = dir.join(format!("{stem}.tres"));
        let exr = dir.join(format!("{stem}_profile.exr"));
        export(&p, Some(&path), Format::Godot, &tres).unwrap();
        export(&p, Some(&path), Format::ProfileExr, &exr).unwrap();
        let mut expect = serde_json::json!({
            "tres": tres,
            "profile_exr": exr,
            "total": total,
        });
        // The albedo the material must carry: the preset's own A where the
        // look is Burley's (otherwise it comes from a fit, not checked here).
        if let scatterlab::settings::ProfileSpec::Burley(_) = &p.profile {
            let (b, _) = burley_of(&p.profile).unwrap();
            expect["albedo"] = serde_json::json!(b.albedo());
        }
        let json = dir.join(format!("{stem}.json"));
        std::fs::write(&json, expect.to_string()).unwrap();
        let v = run_client("godot_check.py", &[json.to_str().unwrap()], &[]);
        assert!(
            v["fails"].as_array().unwrap().is_empty(),
            "{file}: {}",
            v["fails"]
        );
        if total.is_some() {
            let e = floats(&v["errors"]);
            assert!(e.iter().all(|e| *e < 0.02), "{file}: {e:?}");
            assert_eq!(v["skin"], true, "{file}");
        }
    }
}

/// Tangents are MikkTSpace's, as Blender (and the bakers that make normal
/// maps) compute them: the default head written as a triangulated OBJ,
/// imported by Blender 5.0, `Mesh.calc_tangents` (Blender's MikkTSpace on
/// the same corner normals and UVs); at least 98 % of its corners' tangents
/// lie within 1° of ours and 99 % share the bitangent sign. (The rest are
/// vertices that MikkTSpace splits at mirror seams but the index buffer
/// welds.) Our own Lengyel-style tangents before this gave seams with
/// baked maps (issue 12).
#[test]
fn tangents_match_blenders_mikktspace() {
    use std::fmt::Write;
    let head = scatterlab::render::Mesh::default_head().unwrap();
    let dir = tmp_dir("tangents");
    let mut obj = String::from("o head\n");
    for v in &head.vertices {
        let [x, y, z] = v.position;
        writeln!(obj, "v {x} {y} {z}").unwrap();
    }
    for v in &head.vertices {
        // OBJ's V runs up; ours has a top-left origin.
        writeln!(obj, "vt {} {}", v.uv[0], 1.0 - v.uv[1]).unwrap();
    }
    for v in &head.vertices {
        let [x, y, z] = v.normal;
        writeln!(obj, "vn {x} {y} {z}").unwrap();
    }
    for t in head.indices.chunks_exact(3) {
        let [a, b, c] = [t[0] + 1, t[1] + 1, t[2] + 1];
        writeln!(obj, "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}").unwrap();
    }
    let obj_path = dir.join("head.obj");
    std::fs::write(&obj_path, obj).unwrap();
    let ours: Vec<[f32; 4]> = head.vertices.iter().map(|v| v.tangent).collect();
    let ours_path = dir.join("ours.json");
    std::fs::write(&ours_path, serde_json::to_string(&ours).unwrap()).unwrap();
    let v = run_client(
        "blender_tangents.py",
        &[obj_path.to_str().unwrap(), ours_path.to_str().unwrap()],
        &[],
    );
    assert!(v.get("error").is_none(), "{v}");
    eprintln!("tangents against Blender: {v}");
    let within = v["within_1deg"].as_f64().unwrap();
    let sign = v["same_sign"].as_f64().unwrap();
    assert!(within > 0.98 && sign > 0.99, "{v}");
}

/// A head written by another tool: Blender 5.0's glTF exporter writes the
/// default head in centimetres with an external colour map (a two-colour
/// checker, red on the image's top half). `render --mesh` at 0.01 m/unit
/// loads it without a scale warning, frames it, and renders what the OBJ
/// in decimetres with the same map as `--albedo` renders: RMSE under 0.03
/// of full scale (measured 0.018; the eyes differ, as the exported file has
/// one material and its eyeballs are skin, and the rest differs by a level
/// here and there). A map upside down swaps red and blue over half the
/// head (measured 0.24); the head at the wrong size fills or misses the frame.
#[test]
fn a_gltf_written_by_blender_renders_like_the_obj() {
    let dir = tmp_dir("blender-gltf");
    let map = dir.join("map.png");
    image::RgbImage::from_fn(64, 64, |x, y| {
        let c: [u8; 3] = if y < 32 { [220, 40, 30] } else { [30, 60, 220] };
        let k = if (x / 8 + y / 8) % 2 == 1 { 0.6 } else { 1.0 };
        image::Rgb(c.map(|v| (v as f32 * k) as u8))
    })
    .save(&map)
    .unwrap();
    let obj = root().join("assets/head/head.obj");
    let v = run_client(
        "blender_gltf.py",
        &[
            obj.to_str().unwrap(),
            map.to_str().unwrap(),
            dir.to_str().unwrap(),
        ],
        &[],
    );
    let gltf = v["gltf"].as_str().unwrap().to_owned();
    let render = |args: &[&str], out: &Path| -> String {
        let o = Command::new(env!("CARGO_BIN_EXE_scatterlab"))
            .args([
                "render",
                "--camera-yaw",
                "0",
                "--deterministic",
                "--width",
                "192",
                "--height",
                "192",
            ])
            .args(args)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&o.stderr).into_owned();
        assert!(o.status.success(), "{args:?}: {err}");
        err
    };
    let a = dir.join("gltf.png");
    let b = dir.join("obj.png");
    let warn = render(&["--mesh", &gltf, "--metres-per-unit", "0.01"], &a);
    assert!(!warn.contains("warning"), "{warn}");
    render(
        &[
            "--mesh",
            obj.to_str().unwrap(),
            "--metres-per-unit",
            "0.1",
            "--albedo",
            map.to_str().unwrap(),
        ],
        &b,
    );
    let (a, b) = (
        image::open(&a).unwrap().to_rgb8(),
        image::open(&b).unwrap().to_rgb8(),
    );
    let mut sum = 0.0f64;
    for (p, q) in a.pixels().zip(b.pixels()) {
        for c in 0..3 {
            let d = (p[c] as f64 - q[c] as f64) / 255.0;
            sum += d * d;
        }
    }
    let rmse = (sum / (3 * a.width() * a.height()) as f64).sqrt();
    eprintln!("Blender glTF vs OBJ: RMSE {rmse:.4}");
    assert!(
        rmse < 0.03,
        "RMSE {rmse} between the Blender glTF and the OBJ"
    );
}

/// The Blender add-on (tools/blender/scatterlab_looks) in Blender 5.0 and
/// 4.5 LTS: a Principled BSDF in a centimetre scene is written as a look
/// whose d is Cycles' Radius × Scale × unit scale / (4π) (bssrdf.h
/// `bssrdf_setup_radius`, typed here), which scatterlab loads; applied to
/// a new material in a metre scene it sets Radius × Scale back to 4π d
/// (so Cycles scatters the same millimetres); a shipped Burley preset
/// applies with its own d and albedo; a Gaussians look, which Cycles
/// cannot draw exactly, is refused.
#[test]
fn blender_addon_round_trips_in_blender_5_and_4_5() {
    let d_of = |v: &Value| -> Vec<f64> {
        let r = floats(&v["radius"]);
        let s = v["scale"].as_f64().unwrap();
        let u = v["unit_scale"].as_f64().unwrap();
        r.iter()
            .map(|r| r * s * u * 1000.0 / (4.0 * std::f64::consts::PI))
            .collect()
    };
    for (tag, py) in [("b50", python()), ("b45", python_blender4())] {
        let dir = tmp_dir(&format!("addon-{tag}"));
        let v = run_client_in(
            &py,
            "blender_addon.py",
            &[
                dir.to_str().unwrap(),
                root().join("presets").to_str().unwrap(),
            ],
            &[],
        );
        assert_eq!(v["export"][0], "FINISHED", "{tag}: {v}");
        let want = d_of(&v["source"]);
        let look = Preset::load(Path::new(v["written"].as_str().unwrap())).unwrap();
        let b = match &look.profile {
            scatterlab::settings::ProfileSpec::Burley(b) => b.build().unwrap(),
            other => panic!("{other:?}"),
        };
        let (d, a) = (b.scattering_distance_mm(), b.albedo());
        for c in 0..3 {
            assert!(
                (d[c] / want[c] - 1.0).abs() < 1e-9,
                "{tag}: d {d:?} vs {want:?}"
            );
            let base = floats(&v["source"]["base_color"])[c];
            assert!((a[c] - base).abs() < 1e-9, "{tag}: albedo");
        }
        assert!((look.rendering.ior - v["source"]["ior"].as_f64().unwrap()).abs() < 1e-9);
        // Applied in a metre scene: the same millimetres.
        let back = d_of(&v["round_trip"]);
        assert_eq!(v["round_trip"]["method"], "BURLEY", "{tag}");
        for c in 0..3 {
            assert!(
                (back[c] / want[c] - 1.0).abs() < 1e-6,
                "{tag}: round trip {back:?} vs {want:?}"
            );
        }
        // A shipped preset.
        let skin = preset("skin_default.ron");
        let sd = match &skin.profile {
            scatterlab::settings::ProfileSpec::Burley(b) => b.build().unwrap(),
            other => panic!("{other:?}"),
        };
        let applied = d_of(&v["skin"]);
        for c in 0..3 {
            assert!(
                (applied[c] / sd.scattering_distance_mm()[c] - 1.0).abs() < 1e-6,
                "{tag}: skin"
            );
            assert!((floats(&v["skin"]["base_color"])[c] - sd.albedo()[c]).abs() < 1e-6);
        }
        let refused = v["gaussians"][0].as_str().unwrap_or("");
        assert!(refused.contains("no exact Cycles form"), "{tag}: {v}");
    }
}

/// `render --out FILE.exr` opens in the OpenEXR bindings with its layers,
/// and holds what the PNG of the same frame shows: the PNG is
/// sRGB(ACES(exposure × RGB)) of its radiance (Narkowicz 2015's curve,
/// typed in the checker) to 8-bit rounding, the radiance is scattered ×
/// albedo + specular, `none`'s scattered layer is its unscattered one bit
/// for bit, and burley's smooths (tests/clients/render_exr_check.py).
/// With `--compare` an EXR is refused, naming the flag and the file.
#[test]
fn render_exr_layers_make_the_png_in_openexr() {
    let dir = tmp_dir("render-exr");
    let render = |method: &str, out: &Path, extra: &[&str]| -> std::process::Output {
        Command::new(env!("CARGO_BIN_EXE_scatterlab"))
            .args(["render", "--method", method, "--deterministic", "--no-lod"])
            .args([
                "--width",
                "256",
                "--height",
                "256",
                "--camera-distance",
                "0.3",
            ])
            .args(["--exposure", "1.7"])
            .args(extra)
            .arg("--out")
            .arg(out)
            .output()
            .unwrap()
    };
    let (exr, png, none) = (
        dir.join("burley.exr"),
        dir.join("burley.png"),
        dir.join("none.exr"),
    );
    for (method, out) in [("burley", &exr), ("burley", &png), ("none", &none)] {
        let o = render(method, out, &[]);
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    }
    let v = run_client(
        "render_exr_check.py",
        &[
            exr.to_str().unwrap(),
            png.to_str().unwrap(),
            none.to_str().unwrap(),
        ],
        &[],
    );
    eprintln!("render EXR: {v}");
    assert!(v["png_max_255"].as_f64().unwrap() <= 1.0, "{v}");
    let refused = dir.join("compare.exr");
    let o = render("burley", &refused, &["--compare", "none"]);
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success() && !refused.exists(), "{err}");
    assert!(
        err.contains("--out") && err.contains("compare.exr") && err.contains("--compare"),
        "{err}"
    );
}

/// Runs tests/clients/node/gltf_check.mjs (Khronos' validator and
/// Babylon.js's loader, installed by tools/node-env.sh) on a `.gltf`.
fn gltf_check(file: &Path) -> Value {
    let dir = root().join("tests/clients/node");
    assert!(
        dir.join("node_modules/gltf-validator").exists(),
        "{} is missing: run tools/node-env.sh (the README's test command does) to install gltf-validator and Babylon.js",
        dir.join("node_modules").display()
    );
    let out = Command::new("node")
        .arg(dir.join("gltf_check.mjs"))
        .arg(file)
        .current_dir(&dir)
        .output()
        .expect("run node (tools/setup-debian.sh installs it)");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "gltf_check.mjs {}:\n{stdout}\n{stderr}",
        file.display()
    );
    let last = stdout.lines().rev().find(|l| l.starts_with('{'));
    serde_json::from_str(last.unwrap_or_else(|| panic!("no JSON:\n{stdout}\n{stderr}"))).unwrap()
}

/// `got` within 1e-3 of `want`, relative to the larger magnitude (the
/// fields run from 1e-4 m to 1), each number of an array alike.
fn within_1e3(what: &str, got: &Value, want: &Value) {
    let (g, w) = match (got.as_array(), want.as_array()) {
        (Some(g), Some(w)) => (
            floats(&Value::Array(g.clone())),
            floats(&Value::Array(w.clone())),
        ),
        _ => match (got.as_f64(), want.as_f64()) {
            (Some(g), Some(w)) => (vec![g], vec![w]),
            _ => {
                assert_eq!(got, want, "{what}");
                return;
            }
        },
    };
    assert_eq!(g.len(), w.len(), "{what}: {got} vs {want}");
    for (a, b) in g.iter().zip(&w) {
        let scale = a.abs().max(b.abs()).max(1e-300);
        assert!(
            (a - b).abs() <= 1e-3 * scale,
            "{what}: Babylon reads {got}, the notes say {want}"
        );
    }
}

/// Every shipped look exported to glTF (the sphere, with the draft
/// volume_scatter; the head once, with and without it): Khronos' validator
/// (gltf-validator 2.0.0-dev.3.10) finds 0 errors and 0 warnings, its only
/// messages being information that it cannot check the Release Candidate
/// and draft extensions; Babylon.js 9.37.1's loader under NullEngine
/// gives the material the subsurface fields the file's `extras` state for
/// Babylon, within 1e-3 — as PBRMaterial (translucency, tint,
/// diffusionDistance, thickness, IOR) and as OpenPBRMaterial (the mean
/// free path as radius × scale, the multi-scatter colour). The same of
/// the head scan exported as the editor shows it, with its maps.
#[test]
fn gltf_export_validates_and_babylon_reads_what_the_notes_state() {
    use scatterlab::export::{export_with, ExportOptions, GltfMesh};
    let dir = tmp_dir("gltf");
    let mut runs: Vec<(String, Preset, ExportOptions)> = scatterlab::settings::library::PRESETS
        .iter()
        .map(|(file, _)| {
            (
                file.to_string(),
                preset(file),
                ExportOptions {
                    gltf_mesh: GltfMesh::Sphere,
                    gltf_volume_scatter: true,
                    ..Default::default()
                },
            )
        })
        .collect();
    for scatter in [true, false] {
        runs.push((
            format!("head_{scatter}"),
            Preset::default_skin(),
            ExportOptions {
                gltf_mesh: GltfMesh::Head,
                gltf_volume_scatter: scatter,
                ..Default::default()
            },
        ));
    }
    // Issue 52: the mesh on the editor's screen, the head scan with its
    // colour and normal maps as textures and its tangents (the validator
    // checks the images, UVs and tangents too).
    let (scan, settings) = scatterlab::app::state::scanned_head().expect("assets/scan");
    let mesh = scatterlab::app::viewport::load_mesh(&scan, &settings, 5.0).unwrap();
    runs.push((
        "scan_on_screen".into(),
        preset("skin_default.ron"),
        ExportOptions {
            gltf_on_mesh: Some(scatterlab::export::GltfOnMesh {
                mesh: std::sync::Arc::new(mesh),
                name: "LeePerrySmith".into(),
                map_colour: Default::default(),
            }),
            ..Default::default()
        },
    ));
    for (tag, p, options) in runs {
        let out = dir.join(format!("{tag}.gltf"));
        export_with(&p, None, Format::Gltf, &out, &options).unwrap();
        let file: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
        let r = gltf_check(&out);
        let v = &r["validator"];
        assert_eq!(
            (v["numErrors"].as_u64(), v["numWarnings"].as_u64()),
            (Some(0), Some(0)),
            "{tag}: {v}"
        );
        for m in v["messages"].as_array().unwrap() {
            let text = m["message"].as_str().unwrap();
            assert!(
                m["severity"] == 2
                    && m["code"] == "UNSUPPORTED_EXTENSION"
                    && (text.contains("KHR_materials_diffuse_transmission")
                        || text.contains("KHR_materials_volume_scatter")),
                "{tag}: {m}"
            );
        }
        let readings = file["materials"][0]["extras"]["scatterlab"]["readings"]
            .as_array()
            .unwrap()
            .clone();
        let stated = |reader: &str| {
            readings
                .iter()
                .find(|x| x["reader"].as_str().unwrap().starts_with(reader))
                .map(|x| x["fields"].clone())
        };
        let pbr_notes = stated("Babylon.js PBRMaterial").expect("a PBRMaterial reading");
        let pbr = &r["babylon"]["pbr"];
        assert_eq!(pbr["className"], "PBRMaterial");
        for (babylon, noted) in [
            ("isTranslucencyEnabled", "subSurface.isTranslucencyEnabled"),
            ("translucencyIntensity", "subSurface.translucencyIntensity"),
            ("tintColor", "subSurface.tintColor"),
            ("diffusionDistance", "subSurface.diffusionDistance"),
            ("maximumThickness", "subSurface.maximumThickness"),
            (
                "volumeIndexOfRefraction",
                "subSurface.volumeIndexOfRefraction",
            ),
            ("isScatteringEnabled", "subSurface.isScatteringEnabled"),
        ] {
            within_1e3(
                &format!("{tag}: PBR {babylon}"),
                &pbr[babylon],
                &pbr_notes[noted],
            );
        }
        let open = &r["babylon"]["openpbr"];
        match stated("Babylon.js OpenPBRMaterial") {
            Some(notes) => {
                assert!(options.gltf_volume_scatter);
                assert_eq!(open["className"], "OpenPBRMaterial");
                for f in [
                    "subsurfaceRadius",
                    "subsurfaceRadiusScale",
                    "subsurfaceColor",
                ] {
                    within_1e3(&format!("{tag}: OpenPBR {f}"), &open[f], &notes[f]);
                }
            }
            // Without the draft nothing carries the albedo: Babylon keeps
            // OpenPBR's default subsurface colour, 0.8 (the export notes
            // say readers get no albedo for the volume).
            None => {
                assert!(!options.gltf_volume_scatter);
                within_1e3(
                    &format!("{tag}: OpenPBR default"),
                    &open["subsurfaceColor"],
                    &serde_json::json!([0.8, 0.8, 0.8]),
                );
            }
        }
    }
}

/// Blender 5.0.1's own glTF importer on the sphere export (the default
/// skin, with the draft): it makes the volume a Volume Absorption node
/// whose colour and density are what the file's extras state for it
/// (attenuationColor, 1/attenuationDistance), within 1e-3, and a Principled
/// BSDF with the look's albedo and no subsurface, as the extras say.
#[test]
fn blender_imports_the_gltf_as_the_extras_state() {
    use scatterlab::export::{export_with, ExportOptions, GltfMesh};
    let dir = tmp_dir("gltf-blender");
    let out = dir.join("skin.gltf");
    let p = Preset::default_skin();
    let options = ExportOptions {
        gltf_mesh: GltfMesh::Sphere,
        gltf_volume_scatter: true,
        ..Default::default()
    };
    export_with(&p, None, Format::Gltf, &out, &options).unwrap();
    let file: Value = serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    let stated = file["materials"][0]["extras"]["scatterlab"]["readings"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["reader"].as_str().unwrap().starts_with("Blender"))
        .expect("a Blender reading")["fields"]
        .clone();
    let v = run_client(
        "blender_gltf_volume.py",
        &[out.to_str().unwrap(), &p.name],
        &[],
    );
    within_1e3(
        "Volume Absorption colour",
        &v["absorption_color"],
        &stated["Volume Absorption.Color"],
    );
    within_1e3(
        "Volume Absorption density",
        &v["absorption_density"],
        &stated["Volume Absorption.Density"],
    );
    assert_eq!(
        v["subsurface_weight"].as_f64(),
        stated["Principled BSDF.Subsurface Weight"].as_f64()
    );
    let (burley, _) = burley_of(&p.profile).unwrap();
    within_1e3(
        "base colour",
        &v["base_color"],
        &serde_json::json!(burley.albedo()),
    );
}
