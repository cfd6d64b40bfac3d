#![allow(clippy::unwrap_used)]
//! `scatterlab bench --quick` end to end (what CI runs): every scene ×
//! method × count has its row in results.csv with finite figures, each
//! scene has its chart, and the skip study shows the work that must not
//! happen did not: no SSS pass at 0 % coverage or strength 0, all pixels at
//! 100 %, fewer samples with the LOD on the far shot.

use std::collections::HashMap;
use std::path::Path;

const SCENES: [&str; 9] = [
    "head_front",
    "head_backlit_ear",
    "head_backlit_ear_thick",
    "head_closeup",
    "scan_front",
    "scan_backlit_ear",
    "head_far",
    "plane_edge",
    "plane_checker",
];

fn csv(path: &Path) -> Vec<HashMap<String, String>> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    lines
        .map(|l| {
            let cells: Vec<&str> = l.splitn(header.len(), ',').collect();
            assert_eq!(cells.len(), header.len(), "{l}");
            header
                .iter()
                .zip(cells)
                .map(|(h, c)| (h.to_string(), c.to_string()))
                .collect()
        })
        .collect()
}

fn num(row: &HashMap<String, String>, key: &str) -> f64 {
    let v: f64 = row[key]
        .parse()
        .unwrap_or_else(|_| panic!("{key} = {}", row[key]));
    assert!(v.is_finite(), "{key} = {v} in {row:?}");
    v
}

/// Every row the registry declares (each method's `MethodInfo::bench`,
/// and the ground truth), as (method, variant, count).
fn expected_configs() -> Vec<(String, String, u32)> {
    let mut c = vec![(
        scatterlab::render::Method::ground_truth().id().to_string(),
        String::new(),
        0,
    )];
    c.extend(scatterlab::bench::scenes::configs().iter().map(|c| {
        (
            c.method.id().to_string(),
            c.variant().to_string(),
            c.count() as u32,
        )
    }));
    c
}

/// The rows the issues asked for, typed here, as (method, variant, count):
/// the registry must declare each of them.
fn asked_for() -> Vec<(String, String, u32)> {
    let mut c: Vec<(String, String, u32)> = vec![
        ("reference".into(), String::new(), 0),
        ("none".into(), String::new(), 0),
        ("preintegrated".into(), String::new(), 0),
        ("gaussians".into(), "6x2-passes".into(), 0),
    ];
    for v in ["2012", "2015"] {
        for t in [7, 11, 17, 25, 33] {
            c.push(("separable".into(), v.into(), t));
        }
    }
    for v in ["improved", "golubev"] {
        for n in [7, 13, 21, 34, 55, 89, 144] {
            c.push(("burley".into(), v.into(), n));
        }
    }
    for v in ["antithetic", "mis", "r2", "bilinear", "centre"] {
        for n in [21, 55] {
            c.push(("burley".into(), v.into(), n));
        }
    }
    c
}

#[test]
fn quick_bench_writes_every_row_chart_and_skip_figure() {
    let out = std::env::temp_dir().join(format!("scatterlab-bench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_scatterlab"))
        .args(["bench", "--quick", "--out", out.to_str().unwrap()])
        .status()
        .unwrap();
    assert!(status.success());

    let rows = csv(&out.join("results.csv"));
    let expected = expected_configs();
    for row in asked_for() {
        assert!(
            expected.contains(&row),
            "the registry does not bench {row:?}"
        );
    }
    assert_eq!(rows.len(), SCENES.len() * expected.len());
    for scene in SCENES {
        for (m, v, n) in &expected {
            let hits: Vec<_> = rows
                .iter()
                .filter(|r| {
                    r["scene"] == scene
                        && r["method"] == *m
                        && r["variant"] == *v
                        && r["count"] == n.to_string()
                })
                .collect();
            assert_eq!(hits.len(), 1, "{scene} {m} {v} {n}");
            let r = hits[0];
            for key in ["sss_ms", "frame_ms", "rel_rmse", "flip_sss", "flip_image"] {
                assert!(num(r, key) >= 0.0, "{key} in {r:?}");
            }
            assert!(num(r, "none_frame_ms") > 0.0, "{r:?}");
            assert!(num(r, "sss_time_ratio") >= 0.0 && num(r, "frame_time_ratio") > 0.0);
            let share = num(r, "edge_error_share");
            assert!((0.0..=1.0).contains(&share), "edge_error_share in {r:?}");
            if m == "reference" {
                assert_eq!(num(r, "rel_rmse"), 0.0);
            }
        }
        // Scattering matters on every scene: `none` is off the reference,
        // and 144 Burley samples are closer to it than none.
        let get = |m: &str, v: &str, n: u32| {
            rows.iter()
                .find(|r| {
                    r["scene"] == scene
                        && r["method"] == m
                        && r["variant"] == v
                        && r["count"] == n.to_string()
                })
                .unwrap()
        };
        let none = num(get("none", "", 0), "rel_rmse");
        let b144 = num(get("burley", "improved", 144), "rel_rmse");
        assert!(
            none > 0.0 && b144 < none,
            "{scene}: none {none}, burley 144 {b144}"
        );
        // No method at its default configuration is further from the
        // ground truth than the unscattered frame (issue 39; on the planes
        // `preintegrated` is `none`, flat skin having nothing to wrap).
        for (m, v, n) in [
            ("preintegrated", "", 0),
            ("burley", "improved", 21),
            ("separable", "2015", 17),
            ("gaussians", "6x2-passes", 0),
        ] {
            let e = num(get(m, v, n), "rel_rmse");
            assert!(e <= none, "{scene}: {m} {v} {n} at {e}, none at {none}");
        }
        let chart = image::open(out.join(format!("{scene}.png"))).unwrap();
        assert_eq!((chart.width(), chart.height()), (1400, 620));
    }

    // The ground truth's floor (issue 22), at the quick run's 320×180
    // (pixels of 1.8 mm on the head, twice the full run's): a profile that
    // scatters nothing gives back the none frame within 0.5 % everywhere
    // (measured 0.02–0.45 %) but on the scan's back-lit ear (issue 53:
    // 0.63 %); 2 × 2 points a pixel change the plain ground
    // truth by under 0.6 % on the near scenes (0.04–0.51 %; the full run's
    // 0.9 mm pixels are what the 0.3 % target is judged on, docs/accuracy.md)
    // and by under 5 % on the far shot, where the profile fits inside a
    // 9 mm pixel and a point per pixel samples shadow edges (2.7 %).
    let floors = csv(&out.join("floor.csv"));
    assert_eq!(floors.len(), SCENES.len());
    for f in &floors {
        let scene = f["scene"].as_str();
        // The scan back-lit through the ear (issue 53): 0.63 % at this
        // size (the front-lit scan 0.31 %). The residue docs/accuracy.md
        // finds on the procedural head's back-lit ear in the full run
        // (0.60 % there): speckle along the back of the head's outline, lit
        // at grazing angles from behind and seen edge-on, where N·L, the
        // PCF and the normal map's mip level move by per cents between
        // neighbouring pixels.
        let floor = if scene == "scan_backlit_ear" {
            0.008
        } else {
            0.005
        };
        assert!(num(f, "d_to_zero_rel_rmse") < floor, "{f:?}");
        let bound = if scene == "head_far" { 0.05 } else { 0.006 };
        assert!(num(f, "supersampled_rel_rmse") < bound, "{f:?}");
        assert!(num(f, "mixed_fraction") < 0.25, "{f:?}");
    }
    // The ground truth's other paths (issue 38): each scene has the final
    // CPU truth (0 from itself, its floor as in floor.csv) and the loose
    // bound, within 1 % of the final truth (measured here 0.08–0.25 % on
    // the heads and the edge, 0.82 % on the checker, whose edges its
    // leaves, up to twice as wide, straddle) with its own d → 0 floor
    // under 0.5 % (the same as the final's: a profile that scatters
    // nothing has no leaves for τ to widen). No GPU row without
    // --reference-gpu. Times are not asserted.
    let truth = csv(&out.join("truth.csv"));
    assert_eq!(truth.len(), 2 * SCENES.len(), "{truth:?}");
    for scene in SCENES {
        let row = |path: &str| {
            truth
                .iter()
                .find(|r| r["scene"] == scene && r["path"] == path)
                .unwrap_or_else(|| panic!("{scene}: no {path} row"))
        };
        let (fin, loose) = (row("cpu-final"), row("cpu-loose"));
        assert_eq!(num(fin, "from_final_rel_rmse"), 0.0);
        let floor = floors.iter().find(|f| f["scene"] == scene).unwrap();
        assert_eq!(fin["d_to_zero_rel_rmse"], floor["d_to_zero_rel_rmse"]);
        assert!(num(loose, "from_final_rel_rmse") < 0.01, "{loose:?}");
        // The scan's back-lit ear's floor, as above.
        let floor = if scene == "scan_backlit_ear" {
            0.008
        } else {
            0.005
        };
        assert!(num(loose, "d_to_zero_rel_rmse") < floor, "{loose:?}");
        assert!(num(loose, "gather_ms") > 0.0 && num(fin, "gather_ms") > 0.0);
        assert!(loose["gpu_unfinished"].is_empty());
    }
    let skip = csv(&out.join("skip.csv"));
    let case = |study: &str, case: &str, method: &str| {
        skip.iter()
            .find(|r| r["study"] == study && r["case"] == case && r["method"] == method)
            .unwrap_or_else(|| panic!("{study} / {case} / {method}"))
    };
    let zero = case("coverage", "0%", "burley");
    assert_eq!(num(zero, "sss_pixels"), 0.0);
    assert_eq!(num(zero, "sss_passes"), 0.0);
    let full = case("coverage", "100%", "burley");
    assert_eq!(num(full, "sss_pixels"), num(full, "pixels"));
    let ten = num(case("coverage", "10%", "burley"), "sss_pixels") / num(full, "pixels");
    let half = num(case("coverage", "50%", "burley"), "sss_pixels") / num(full, "pixels");
    assert!(
        (ten - 0.1).abs() < 0.02 && (half - 0.5).abs() < 0.02,
        "{ten} {half}"
    );
    assert!(num(full, "sss_samples") > num(case("coverage", "50%", "burley"), "sss_samples"));
    let s0 = case("strength", "jimenez strength 0", "burley");
    assert_eq!(num(s0, "sss_passes"), 0.0);
    assert!(num(s0, "sss_pixels") > 0.0);
    let on = case("lod", "far shot LOD on", "burley");
    let off = case("lod", "far shot LOD off", "burley");
    assert!(
        num(on, "sss_samples") < num(off, "sss_samples"),
        "{on:?} {off:?}"
    );
    assert!(num(on, "lod_skipped_pixels") + num(on, "sss_samples") > 0.0);

    let md = std::fs::read_to_string(out.join("accuracy.md")).unwrap();
    for needle in [
        "## head_front",
        "## Beating the published sampling",
        "## Skipped work",
    ] {
        assert!(md.contains(needle), "accuracy.md lacks {needle}");
    }
    // --replot redraws the charts and the report from the CSVs alone.
    std::fs::remove_file(out.join("head_far.png")).unwrap();
    std::fs::remove_file(out.join("accuracy.md")).unwrap();
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_scatterlab"))
        .args([
            "bench",
            "--replot",
            "--quick",
            "--out",
            out.to_str().unwrap(),
        ])
        .status()
        .unwrap();
    assert!(status.success());
    assert!(image::open(out.join("head_far.png")).is_ok());
    assert_eq!(
        std::fs::read_to_string(out.join("accuracy.md"))
            .unwrap()
            .lines()
            .count(),
        md.lines().count()
    );
    std::fs::remove_dir_all(&out).unwrap();
}
