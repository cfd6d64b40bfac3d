#![allow(clippy::unwrap_used)]
//! CLI contracts: `--json` keys, values against independent references
//! (closed forms typed from the papers, published tables, the seeds'
//! numbers), and one-line errors with a non-zero exit for bad input.

use serde_json::Value;
use std::f64::consts::PI;
use std::path::PathBuf;
use std::process::Command;

#[path = "../common/mod.rs"]
mod common;
mod compare;
mod render;
use common::{quad_gltf, quad_gltf_with};

/// The line `render` adds on a lavapipe older than Mesa 25 (issue 50);
/// the tests of other warnings count lines without it, so that they pass
/// on an old lavapipe too (`render_writes_image_and_stats` checks it).
const OLD_DRIVER_NOTE: &str = "note: this is lavapipe from Mesa ";

/// Runs the CLI: its exit code, stdout and stderr (without the old
/// driver's note).
fn run(args: &[&str]) -> (i32, String, String) {
    let (code, out, err) = run_raw(args);
    let err = err
        .lines()
        .filter(|l| !l.starts_with(OLD_DRIVER_NOTE))
        .map(|l| format!("{l}\n"))
        .collect();
    (code, out, err)
}

/// Runs the CLI: its exit code, stdout and stderr as it printed them.
fn run_raw(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_scatterlab"))
        .args(args)
        .output()
        .expect("binary runs");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

fn json(args: &[&str]) -> Value {
    let (code, out, err) = run(args);
    assert_eq!(code, 0, "{args:?} failed: {err}");
    serde_json::from_str(&out).unwrap_or_else(|e| panic!("{args:?}: {e}: {out}"))
}

fn keys(v: &Value) -> Vec<String> {
    v.as_object().unwrap().keys().cloned().collect()
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

/// Burley R(r) = A s (e^(−sr) + e^(−sr/3))/(8πr) and P(r) = 1 − e^(−sr)/4 − 3e^(−sr/3)/4
/// (Christensen & Burley 2015; Golubev 2018): CLI to 1e-5 relative.
#[test]
fn profile_burley_matches_closed_form() {
    let v = json(&[
        "profile",
        "--model",
        "burley",
        "--albedo",
        "0.8,0.5,0.3",
        "--distance",
        "1,0.5,0.25",
        "--radii",
        "0.1,0.5,2",
        "--json",
    ]);
    assert_eq!(
        keys(&v),
        [
            "radii_mm",
            "R",
            "rR",
            "cdf",
            "total_reflectance",
            "radius_997_mm"
        ]
    );
    let a = [0.8, 0.5, 0.3];
    let d = [1.0, 0.5, 0.25];
    for (i, r) in [0.1f64, 0.5, 2.0].iter().enumerate() {
        for c in 0..3 {
            let s = 1.0 / d[c];
            let big_r = a[c] * s * ((-s * r).exp() + (-s * r / 3.0).exp()) / (8.0 * PI * r);
            let p = 1.0 - 0.25 * (-s * r).exp() - 0.75 * (-s * r / 3.0).exp();
            assert!(rel(f(&v["R"][i][c]), big_r) < 1e-5);
            assert!(rel(f(&v["rR"][i][c]), r * big_r) < 1e-5);
            assert!(rel(f(&v["cdf"][i][c]), p) < 1e-5);
        }
    }
    for c in 0..3 {
        assert!(rel(f(&v["total_reflectance"][c]), a[c]) < 1e-12);
        // The 0.997 radius satisfies P(r) = 0.997.
        let (s, r) = (1.0 / d[c], f(&v["radius_997_mm"][c]));
        assert!((1.0 - 0.25 * (-s * r).exp() - 0.75 * (-s * r / 3.0).exp() - 0.997).abs() < 1e-9);
    }
}

/// d'Eon's six Gaussians (GPU Gems 3 table) summed by hand.
#[test]
fn profile_gaussians_defaults_to_deon_skin() {
    let table = [
        (0.0064, [0.233, 0.455, 0.649]),
        (0.0484, [0.100, 0.336, 0.344]),
        (0.187, [0.118, 0.198, 0.0]),
        (0.567, [0.113, 0.007, 0.007]),
        (1.99, [0.358, 0.004, 0.0]),
        (7.41, [0.078, 0.0, 0.0]),
    ];
    let v = json(&[
        "profile",
        "--model",
        "gaussians",
        "--radii",
        "0,0.3,1.5",
        "--json",
    ]);
    for (i, r) in [0.0f64, 0.3, 1.5].iter().enumerate() {
        for c in 0..3 {
            let e: f64 = table
                .iter()
                .map(|(var, w)| w[c] * (-r * r / (2.0 * var)).exp() / (2.0 * PI * var))
                .sum();
            assert!(rel(f(&v["R"][i][c]), e) < 1e-5, "{} vs {e}", v["R"][i][c]);
        }
    }
    let v = json(&[
        "profile",
        "--model",
        "gaussians",
        "--variances",
        "0.5",
        "--weights",
        "1,0.5,0.25",
        "--radii",
        "1",
        "--json",
    ]);
    assert!(rel(f(&v["R"][0][1]), 0.5 * (-1.0f64).exp() / PI) < 1e-12);
}

/// The corrected dipole (Mikkelsen 2009 eq. 30) typed out, for Skin1 at η = 1.3.
#[test]
fn profile_dipole_matches_equation_30() {
    let v = json(&[
        "profile",
        "--model",
        "dipole",
        "--measured",
        "Skin1",
        "--radii",
        "0,0.5,3",
        "--json",
    ]);
    let w = json(&[
        "profile",
        "--model",
        "dipole",
        "--sigma-a",
        "0.032,0.17,0.48",
        "--sigma-s-prime",
        "0.74,0.88,1.01",
        "--eta",
        "1.3",
        "--radii",
        "0,0.5,3",
        "--json",
    ]);
    assert_eq!(v, w);
    let (sa, ss): ([f64; 3], [f64; 3]) = ([0.032, 0.17, 0.48], [0.74, 0.88, 1.01]);
    let eta: f64 = 1.3;
    let fdr = -1.44 / (eta * eta) + 0.71 / eta + 0.668 + 0.0636 * eta;
    let a = (1.0 + fdr) / (1.0 - fdr);
    for (i, r) in [0.0f64, 0.5, 3.0].iter().enumerate() {
        for c in 0..3 {
            let st = sa[c] + ss[c];
            let alpha = ss[c] / st;
            let str_ = (3.0 * sa[c] * st).sqrt();
            let zr = 1.0 / st;
            let zv = zr + 4.0 * a / (3.0 * st);
            let (dr, dv) = ((r * r + zr * zr).sqrt(), (r * r + zv * zv).sqrt());
            let e = alpha / (4.0 * PI)
                * ((str_ * dr + 1.0) * zr * (-str_ * dr).exp() / dr.powi(3)
                    + (str_ * dv + 1.0) * zv * (-str_ * dv).exp() / dv.powi(3));
            assert!(rel(f(&v["R"][i][c]), e) < 1e-5);
        }
    }
}

/// A one-layer semi-infinite "stack" is the dipole; a two-layer stack from a file builds.
#[test]
fn profile_multipole_from_layers_file() {
    let dir = std::env::temp_dir();
    let one = dir.join(format!("scatterlab-one-{}.ron", std::process::id()));
    std::fs::write(&one, "(layers: [(sigma_a_per_mm: (0.032, 0.17, 0.48), sigma_s_prime_per_mm: (0.74, 0.88, 1.01), eta: 1.3)])").unwrap();
    let v = json(&[
        "profile",
        "--model",
        "multipole",
        "--layers",
        one.to_str().unwrap(),
        "--radii",
        "0.5,2",
        "--json",
    ]);
    let d = json(&[
        "profile",
        "--model",
        "dipole",
        "--measured",
        "Skin1",
        "--radii",
        "0.5,2",
        "--json",
    ]);
    assert_eq!(v["R"], d["R"]);
    let two = dir.join(format!("scatterlab-two-{}.ron", std::process::id()));
    std::fs::write(&two, "(layers: [(sigma_a_per_mm: (0.005, 0.005, 0.005), sigma_s_prime_per_mm: (1.3, 1.3, 1.3), eta: 1.4, thickness_mm: 6.0), (sigma_a_per_mm: (0.01, 0.01, 0.01), sigma_s_prime_per_mm: (1.0, 1.0, 1.0), eta: 1.4)])").unwrap();
    let v = json(&[
        "profile",
        "--model",
        "multipole",
        "--layers",
        two.to_str().unwrap(),
        "--radii",
        "0.5,2",
        "--json",
    ]);
    assert!(f(&v["total_reflectance"][0]) > 0.0 && f(&v["cdf"][1][0]) > f(&v["cdf"][0][0]));
    std::fs::write(&two, "(layers: [(eta: 7.0)])").unwrap();
    let (code, _, err) = run(&[
        "profile",
        "--model",
        "multipole",
        "--layers",
        two.to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("layers[0].eta") && err.lines().count() == 1,
        "{err}"
    );
    std::fs::remove_file(&one).unwrap();
    std::fs::remove_file(&two).unwrap();
}

/// Inverse CDF: P(r(ξ)) = ξ with the CDF typed from Golubev 2018; Halley agrees.
#[test]
fn sample_burley_inverts_the_cdf() {
    let xi = [0.0, 1e-9, 0.25, 0.5, 0.997, 0.999999];
    let arg = xi.map(|x| x.to_string()).join(",");
    let v = json(&["sample", "burley", "--shape", "1.3", "--xi", &arg, "--json"]);
    assert_eq!(keys(&v), ["xi", "radius_mm"]);
    let h = json(&[
        "sample", "burley", "--shape", "1.3", "--xi", &arg, "--method", "halley", "--json",
    ]);
    for (i, x) in xi.iter().enumerate() {
        let r = f(&v["radius_mm"][i]);
        let p = 1.0 - 0.25 * (-1.3 * r).exp() - 0.75 * (-1.3 * r / 3.0).exp();
        assert!((p - x).abs() <= 1e-12 + 1e-9 * x, "xi={x}: {p}");
        assert!((f(&h["radius_mm"][i]) - r).abs() <= 1e-6 * r);
    }
}

/// The 11-tap kernel printed in iryoku/separable-sss `SeparableSSS.h`.
#[test]
fn kernel_jimenez_matches_published_taps() {
    let v = json(&[
        "kernel",
        "jimenez",
        "--strength",
        "0.48,0.41,0.28",
        "--falloff",
        "1,0.37,0.3",
        "--taps",
        "11",
        "--json",
    ]);
    assert_eq!(keys(&v), ["kernel"]);
    let first = [0.560479, 0.669086, 0.784728, 0.0];
    let second = [0.00471691, 0.000184771, 5.07566e-005, -2.0];
    for k in 0..3 {
        assert!(rel(f(&v["kernel"][0][k]), first[k]) < 2e-5);
        assert!(rel(f(&v["kernel"][1][k]), second[k]) < 2e-5);
    }
    assert_eq!(f(&v["kernel"][1][3]), -2.0);
    let (code, _, err) = run(&["kernel", "jimenez", "--taps", "10"]);
    assert_ne!(code, 0);
    assert!(err.contains("taps"), "{err}");
}

/// Penner's D at θ = 45° on a 3 mm sphere for S = 1/0.7568628 (the
/// survey's Octave case): the sphere's average, mpmath.
#[test]
fn lut_preintegrated_is_the_spheres_average() {
    let v = json(&[
        "lut",
        "preintegrated",
        "--model",
        "burley",
        "--albedo",
        "1,1,1",
        "--distance",
        "0.7568628,0.7568628,0.7568628",
        "--theta",
        "0.7853981633974483,0",
        "--curvature-radius",
        "3,1000",
        "--json",
    ]);
    assert_eq!(keys(&v), ["D"]);
    // The sphere's exact ring mean (mpmath at 20 digits: 0.576285275), not
    // the survey's two-point mean, whose Octave numbers 0.563473/0.946522
    // the library test reproduces to show what it computed.
    assert!(rel(f(&v["D"][0][0][0]), 0.576_285_275) < 1e-5);
    // θ = 0 on a nearly flat surface: D → cos 0 = 1.
    assert!((f(&v["D"][1][1][2]) - 1.0).abs() < 1e-3);
    let png = std::env::temp_dir().join(format!("scatterlab-lut-{}.png", std::process::id()));
    let (code, _, err) = run(&[
        "lut",
        "preintegrated",
        "--out",
        png.to_str().unwrap(),
        "--size",
        "32",
    ]);
    assert_eq!(code, 0, "{err}");
    let img = image::open(&png).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), (32, 32));
    // Top row (flattest): N·L = −1 is black, N·L = 1 bright.
    assert!(img.get_pixel(0, 0)[0] < 5 && img.get_pixel(31, 0)[0] > 200);
    // Most curved row, at the terminator: red wraps further than blue (Penner 2011).
    let p = img.get_pixel(16, 31);
    assert!(p[0] > p[2] + 10, "{p:?}");
    std::fs::remove_file(&png).unwrap();
}

/// Burley transmittance A/4·(e^(−sd) + 3e^(−sd/3)) (Golubev 2018).
#[test]
fn transmittance_matches_closed_form() {
    let v = json(&[
        "transmittance",
        "--model",
        "burley",
        "--albedo",
        "0.9,0.6,0.3",
        "--distance",
        "1,0.5,0.2",
        "--thickness",
        "0,0.4,3",
        "--json",
    ]);
    assert_eq!(keys(&v), ["thickness_mm", "T"]);
    for (i, t) in [0.0f64, 0.4, 3.0].iter().enumerate() {
        for (c, (a, d)) in [(0.9f64, 1.0f64), (0.6, 0.5), (0.3, 0.2)]
            .iter()
            .enumerate()
        {
            let s = 1.0 / d;
            let e = a / 4.0 * ((-s * t).exp() + 3.0 * (-s * t / 3.0).exp());
            assert!(rel(f(&v["T"][i][c]), e) < 1e-5);
        }
    }
}

/// Fitting Burley to a Burley profile returns it with ~0 error.
#[test]
fn fit_recovers_known_parameters() {
    let v = json(&[
        "fit",
        "--model",
        "burley",
        "--albedo",
        "0.8,0.5,0.3",
        "--distance",
        "1,0.5,0.25",
        "--to",
        "burley",
        "--json",
    ]);
    assert_eq!(keys(&v), ["params", "relative_l2_error"]);
    assert!(f(&v["relative_l2_error"]) < 1e-6);
    for (c, d) in [1.0, 0.5, 0.25].iter().enumerate() {
        assert!(rel(f(&v["params"]["scattering_distance_mm"][c]), *d) < 1e-5);
    }
    let g = json(&[
        "fit",
        "--model",
        "gaussians",
        "--to",
        "gaussians:6",
        "--json",
    ]);
    assert!(f(&g["relative_l2_error"]) < 0.01);
    assert_eq!(g["params"]["gaussians"].as_array().unwrap().len(), 6);
    let (code, _, err) = run(&["fit", "--to", "spline"]);
    assert_ne!(code, 0);
    assert!(err.contains("--to"), "{err}");
}

#[test]
fn bad_input_is_one_line_and_non_zero() {
    let cases: [&[&str]; 11] = [
        &["profile", "--radii", "-1"],
        &["profile", "--model", "measured"],
        &["render", "--burley-sampling", "nope"],
        &["profile", "--radii", "nan"],
        &["profile", "--radii", "1,x"],
        &["profile", "--model", "burley", "--distance", "1,1"],
        &["profile", "--model", "burley", "--albedo", "1.5,0.5,0.5"],
        &["profile", "--model", "dipole", "--measured", "nope"],
        &["profile", "--preset", "/nonexistent/file.ron"],
        &["sample", "burley", "--shape", "1", "--xi", "1"],
        &["transmittance", "--thickness", "-0.5"],
    ];
    for args in cases {
        let (code, out, err) = run(args);
        assert_ne!(code, 0, "{args:?} succeeded: {out}");
        assert_eq!(err.trim_end().lines().count(), 1, "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    let (_, _, err) = run(&["profile", "--model", "burley", "--albedo", "1.5,0.5,0.5"]);
    assert!(err.contains("albedo.r"), "{err}");
    let (_, _, err) = run(&["profile", "--model", "measured"]);
    assert!(err.contains("--measured NAME"), "{err}");
}

/// `--model` takes every model's name from the look's own list (and
/// `jimenez` for Jimenez 2012), and the engines' parameter sets.
#[test]
fn every_model_name_is_a_model_flag() {
    for (args, model) in [
        (&["--model", "jimenez"][..], "jimenez2012"),
        (&["--model", "jimenez2012"], "jimenez2012"),
        (&["--model", "artist"], "artist"),
        (&["--model", "multipole"], "multipole"),
        (&["--model", "measured", "--measured", "Skin1"], "measured"),
        (
            &["--model", "unity", "--scattering-color", "1,0.5,0.25"],
            "burley",
        ),
    ] {
        let (code, out, err) = run(&[&["profile"][..], args].concat());
        assert_eq!(code, 0, "{args:?}: {err}");
        assert!(
            out.starts_with(&format!("model: {model}\n")),
            "{args:?}: {out}"
        );
    }
}

#[test]
fn convert_round_trips_through_unity_numbers() {
    let v = json(&[
        "convert",
        "--model",
        "burley",
        "--albedo",
        "0.9,0.4,0.3",
        "--distance",
        "2,0.5,0.25",
        "--to",
        "unity",
        "--json",
    ]);
    let p = &v["params"];
    // HDRP: brightest channel at 191/255, colour × multiplier = d.
    assert!((f(&p["scattering_distance_color"][0]) - 191.0 / 255.0).abs() < 1e-12);
    assert!(
        rel(
            f(&p["scattering_distance_color"][1]) * f(&p["scattering_distance_multiplier"]),
            0.5
        ) < 1e-12
    );
}

/// Engine parameters in, engine parameters out: Unreal → Unity → Unreal
/// returns the input (the conversions are exact inverses).
#[test]
fn converts_between_engines_both_ways() {
    let v = json(&[
        "convert",
        "--model",
        "unreal",
        "--albedo",
        "0.44,0.22,0.13",
        "--mfp-color",
        "1,0.735,0.518",
        "--mfp-distance-cm",
        "0.1295",
        "--to",
        "unity",
        "--json",
    ]);
    let p = &v["params"];
    let (color, mult) = (
        &p["scattering_distance_color"],
        f(&p["scattering_distance_multiplier"]),
    );
    let c = format!("{},{},{}", f(&color[0]), f(&color[1]), f(&color[2]));
    let back = json(&[
        "convert",
        "--model",
        "unity",
        "--albedo",
        "0.44,0.22,0.13",
        "--scattering-color",
        &c,
        "--multiplier",
        &mult.to_string(),
        "--to",
        "unreal",
        "--json",
    ]);
    let q = &back["params"];
    assert!(rel(f(&q["mean_free_path_distance_cm"]), 0.1295) < 1e-9);
    for (k, e) in [1.0, 0.735, 0.518].iter().enumerate() {
        assert!(rel(f(&q["mean_free_path_color"][k]), *e) < 1e-9);
    }
    let (code, _, err) = run(&[
        "convert",
        "--model",
        "unreal",
        "--albedo",
        "0.5,0.5,0.5",
        "--to",
        "unity",
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("--mfp-color"), "{err}");
}

/// `export` writes the file atomically and prints every path it wrote;
/// bad input exits non-zero with one line naming the problem.
#[test]
fn export_writes_files_and_refuses_bad_input() {
    let dir = std::env::temp_dir().join(format!("scatterlab-cli-export-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let preset = concat!(env!("CARGO_MANIFEST_DIR"), "/presets/skin_default.ron");
    let out = dir.join("skin.asset");
    let (code, stdout, err) = run(&[
        "export",
        "--preset",
        preset,
        "--format",
        "unity",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(stdout.trim(), out.display().to_string());
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("guid: b2686e09ec7aef44bad2843e4416f057")
            && text.contains("skin_default.ron")
    );
    // Unreal writes the struct and a Python companion.
    let out = dir.join("skin.txt");
    let (code, stdout, err) = run(&[
        "export",
        "--preset",
        preset,
        "--format",
        "unreal",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(stdout.lines().count(), 2, "{stdout}");
    assert!(dir.join("skin.py").exists());
    // glTF on the sphere with the draft extension; its flags are refused
    // beside another format.
    let out = dir.join("skin.gltf");
    let (code, _, err) = run(&[
        "export",
        "--preset",
        preset,
        "--format",
        "gltf",
        "--gltf-mesh",
        "sphere",
        "--gltf-volume-scatter",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let doc: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&out).unwrap()).unwrap();
    assert_eq!(doc["nodes"][0]["name"], "sphere");
    assert!(doc["extensionsUsed"]
        .as_array()
        .unwrap()
        .contains(&serde_json::json!("KHR_materials_volume_scatter")));
    let (code, _, err) = run(&[
        "export",
        "--preset",
        preset,
        "--format",
        "unity",
        "--gltf-mesh",
        "sphere",
        "--out",
        dir.join("x.asset").to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("--gltf-mesh") && err.contains("unity"),
        "{err}"
    );
    // An unknown format and a broken preset: one line, non-zero.
    let (code, _, err) = run(&[
        "export", "--preset", preset, "--format", "fbx", "--out", "x",
    ]);
    assert_ne!(code, 0);
    assert_eq!(err.trim().lines().count(), 1, "{err}");
    let bad = dir.join("bad.ron");
    std::fs::write(&bad, "(profile: Burley((albedo: (0.5, NaN, 0.5))))").unwrap();
    let (code, _, err) = run(&[
        "export",
        "--preset",
        bad.to_str().unwrap(),
        "--format",
        "ron",
        "--out",
        dir.join("o.ron").to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("bad.ron") && err.contains("albedo.g"), "{err}");
    assert!(!dir.join("o.ron").exists());
    // A profile from --model and its flags, as every other command takes
    // it (issue 40, item 5): the written preset holds those numbers.
    let out = dir.join("flags.ron");
    let (code, _, err) = run(&[
        "export",
        "--model",
        "burley",
        "--distance",
        "1.5,0.6,0.25",
        "--albedo",
        "0.8,0.5,0.3",
        "--format",
        "ron",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let p = scatterlab::settings::Preset::load(&out).unwrap();
    match &p.profile {
        scatterlab::settings::ProfileSpec::Burley(b) => {
            let d = b.build().unwrap().scattering_distance_mm();
            for (got, want) in d.iter().zip([1.5, 0.6, 0.25]) {
                assert!((got - want).abs() < 1e-12, "{d:?}");
            }
        }
        other => panic!("not Burley: {other:?}"),
    }
    // --preset with a model flag is refused, naming the flag.
    let (code, _, err) = run(&[
        "export",
        "--preset",
        preset,
        "--distance",
        "1,1,1",
        "--format",
        "ron",
        "--out",
        dir.join("o2.ron").to_str().unwrap(),
    ]);
    assert_ne!(code, 0);
    assert!(err.contains("--distance"), "{err}");
    std::fs::remove_dir_all(&dir).unwrap();
}
