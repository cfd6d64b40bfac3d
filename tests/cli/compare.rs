//! `scatterlab render --compare`: B is drawn with B's own inputs.

use super::*;
use clap::Parser;

/// Every pair of methods: the B side of `render --method A --compare B`
/// (split at 0, so all but the divider column is B) must be the image of
/// `render --method B` alone, pixel for pixel (deterministic frames). B's
/// tables were baked for A's method, so `--method burley --compare
/// gaussians` drew B as `none` and said nothing (issue 22). Run in process
/// (`scatterlab::cli::run`) to spare 36 process starts.
#[test]
fn compare_draws_b_with_bs_own_inputs() {
    let dir = std::env::temp_dir().join(format!("scatterlab-compare-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Every method of the registry, so a new one joins the matrix.
    let methods: Vec<&str> = scatterlab::render::Method::all()
        .iter()
        .map(|m| m.id())
        .collect();
    let render = |out: &PathBuf, extra: &[&str]| -> image::RgbaImage {
        let mut args = vec![
            "scatterlab",
            "render",
            "--width",
            "40",
            "--height",
            "40",
            "--deterministic",
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        let cli = scatterlab::cli::Cli::try_parse_from(&args).unwrap();
        scatterlab::cli::run(cli).unwrap_or_else(|e| panic!("{args:?}: {e:#}"));
        image::open(out).unwrap().to_rgba8()
    };
    let alone: Vec<image::RgbaImage> = methods
        .iter()
        .map(|m| render(&dir.join(format!("{m}.png")), &["--method", m]))
        .collect();
    // The methods differ on this view (else the test could not fail):
    // every one but the baseline from it.
    let none = scatterlab::render::Method::baseline().id();
    let base = methods.iter().position(|m| *m == none).unwrap();
    for (m, image) in methods.iter().zip(&alone) {
        if *m != none {
            assert_ne!(*image, alone[base], "{none} and {m} render alike");
        }
    }
    for (a, name_a) in methods.iter().enumerate() {
        for (b, name_b) in methods.iter().enumerate() {
            if a == b {
                continue;
            }
            let out = dir.join(format!("{name_a}-vs-{name_b}.png"));
            let split = render(
                &out,
                &["--method", name_a, "--compare", name_b, "--split", "0"],
            );
            for (x, y, p) in split.enumerate_pixels().filter(|(x, _, _)| *x > 0) {
                assert_eq!(
                    p,
                    alone[b].get_pixel(x, y),
                    "{name_a} --compare {name_b}: B differs from {name_b} alone at ({x}, {y})"
                );
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
}
