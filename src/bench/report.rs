//! `results.csv` and the generated `accuracy.md`.

use super::floor::Floor;
use super::scenes::{Config, Scene};
use super::skip::SkipRow;
use super::{Options, Row};
use crate::render::Method;
use anyhow::{Context as _, Result};
use std::fmt::Write as _;
use std::path::Path;

pub const CSV_HEADER: &str = "scene,method,variant,count,width,height,sss_pixels,samples,\
sss_ms,frame_ms,none_frame_ms,sss_time_ratio,frame_time_ratio,rel_rmse,flip_sss,flip_image,timing,\
rel_rmse_interior,edge_error_share";

pub fn write_csv(path: &Path, rows: &[Row]) -> Result<()> {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{:.4},{:.4},{:.4},{:.5},{:.5},{:.6},{:.6},{:.6},{},{:.6},{:.4}",
            r.scene,
            r.config.method().id(),
            r.config.variant(),
            r.config.count(),
            r.width,
            r.height,
            r.sss_pixels,
            r.samples,
            r.sss_ms,
            r.frame_ms,
            r.none_frame_ms,
            r.sss_ratio(),
            r.frame_ratio(),
            r.rel_rmse,
            r.flip_sss,
            r.flip_image,
            r.timing,
            r.rel_rmse_interior,
            r.edge_error_share
        );
    }
    crate::fsutil::write_atomic(path, s.as_bytes())
        .with_context(|| format!("writing {}", path.display()))
}

pub const FLOOR_HEADER: &str = "scene,d_to_zero_rel_rmse,supersampled_rel_rmse,mixed_fraction";

/// `floor.csv`: the ground truth's floor per scene (`bench::floor`).
pub fn write_floor_csv(path: &Path, floors: &[(&'static str, Floor)]) -> Result<()> {
    let mut s = String::from(FLOOR_HEADER);
    s.push('\n');
    for (scene, f) in floors {
        let _ = writeln!(
            s,
            "{scene},{:.6},{:.6},{:.6}",
            f.d_to_zero, f.supersampled, f.mixed_fraction
        );
    }
    crate::fsutil::write_atomic(path, s.as_bytes())
        .with_context(|| format!("writing {}", path.display()))
}

/// Reads a `floor.csv` back (for `--replot`).
pub fn read_floor_csv(path: &Path) -> Result<Vec<(&'static str, Floor)>> {
    let scenes = super::scenes::scenes((1, 1));
    let ids: Vec<&'static str> = scenes.iter().map(|s| s.id).collect();
    super::csv::read(path, FLOOR_HEADER, 4)?
        .iter()
        .map(|r| {
            r.expect_fields(&[4])?;
            Ok((
                r.one_of(0, &ids)?,
                Floor {
                    d_to_zero: r.num(1)?,
                    supersampled: r.num(2)?,
                    mixed_fraction: r.num(3)?,
                },
            ))
        })
        .collect()
}

/// Reads a `results.csv` written by [`write_csv`] back (for `--replot`).
pub fn read_csv(path: &Path) -> Result<Vec<Row>> {
    let scenes = super::scenes::scenes((1, 1));
    let ids: Vec<&'static str> = scenes.iter().map(|s| s.id).collect();
    let mut configs = super::scenes::configs();
    configs.push(Config::reference());
    super::csv::read(path, CSV_HEADER, 19)?
        .iter()
        .map(|r| {
            // Runs before issue 22 have no edge_error_share (column 19).
            r.expect_fields(&[18, 19])?;
            let f = |k: usize| r.text(k);
            let config = *configs
                .iter()
                .find(|c| {
                    c.method().id() == f(1) && c.variant() == f(2) && c.count().to_string() == f(3)
                })
                .with_context(|| {
                    format!("{}: unknown configuration {} {} {}", r.at, f(1), f(2), f(3))
                })?;
            let num = |k: usize| r.num(k);
            Ok(Row {
                scene: r.one_of(0, &ids)?,
                config,
                width: num(4)? as u32,
                height: num(5)? as u32,
                sss_pixels: num(6)? as u64,
                samples: num(7)? as u64,
                sss_ms: num(8)?,
                frame_ms: num(9)?,
                none_frame_ms: num(10)?,
                rel_rmse: num(13)?,
                rel_rmse_interior: num(17)?,
                edge_error_share: if r.fields.len() > 18 {
                    num(18)?
                } else {
                    f64::NAN
                },
                flip_sss: num(14)?,
                flip_image: num(15)?,
                timing: match f(16) {
                    "wall-clock" => "wall-clock",
                    "cpu-wall-clock" => "cpu-wall-clock",
                    _ => "gpu-timestamps",
                },
            })
        })
        .collect()
}

/// Rows of one scene that no other row beats on both frame time and
/// relative RMSE (the reference is the yardstick, not a candidate).
pub fn pareto_front<'a>(rows: &[&'a Row]) -> Vec<&'a Row> {
    let cand: Vec<&Row> = rows
        .iter()
        .copied()
        .filter(|r| !r.config.method.sss().ground_truth)
        .collect();
    let mut front: Vec<&Row> = cand
        .iter()
        .copied()
        .filter(|a| {
            !cand.iter().any(|b| {
                b.frame_ratio() <= a.frame_ratio()
                    && b.rel_rmse <= a.rel_rmse
                    && (b.frame_ratio() < a.frame_ratio() || b.rel_rmse < a.rel_rmse)
            })
        })
        .collect();
    front.sort_by(|a, b| a.frame_ratio().total_cmp(&b.frame_ratio()));
    front
}

/// Whether an artist can pick this configuration (the single-flag Burley
/// variants are measurements, not options).
pub fn shipped(c: Config) -> bool {
    !c.method.sss().ground_truth && c.knob.shipped
}

/// The cheapest shipped configuration (by frame time) with relative RMSE
/// at most `limit`.
pub fn cheapest_within<'a>(rows: &[&'a Row], limit: f64) -> Option<&'a Row> {
    rows.iter()
        .copied()
        .filter(|r| shipped(r.config) && r.rel_rmse <= limit)
        .min_by(|a, b| a.frame_ratio().total_cmp(&b.frame_ratio()))
}

pub fn find<'a>(rows: &'a [Row], scene: &str, config: Config) -> Option<&'a Row> {
    rows.iter().find(|r| r.scene == scene && r.config == config)
}

pub struct Context<'a> {
    pub scenes: &'a [Scene],
    pub rows: &'a [Row],
    pub floors: &'a [(&'static str, Floor)],
    /// The ground truth's other paths (`truth.csv`; none in older runs).
    pub truth: &'a [super::truth::TruthRow],
    pub skip: &'a [SkipRow],
    pub options: Options,
    pub adapter: &'a str,
    pub quick: bool,
}

fn scene_table(s: &mut String, scene: &Scene, rows: &[&Row]) {
    let front = pareto_front(rows);
    let _ = writeln!(
        s,
        "| Method | SSS px | samples / SSS px | SSS passes ÷ none frame | frame ÷ none frame | rel. RMSE | rel. RMSE, interior | error share at edges | FLIP (SSS px) | front |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    for r in rows {
        let per_px = if r.sss_pixels > 0 {
            r.samples as f64 / r.sss_pixels as f64
        } else {
            0.0
        };
        let on = front.iter().any(|f| std::ptr::eq(*f, *r));
        let _ = writeln!(
            s,
            "| {} | {} | {:.1} | {:.3} | {:.2} | {:.4} | {:.4} | {} | {:.4} | {} |",
            r.config.label(),
            r.sss_pixels,
            per_px,
            r.sss_ratio(),
            r.frame_ratio(),
            r.rel_rmse,
            r.rel_rmse_interior,
            // A results.csv from before the column has no edge share.
            if r.edge_error_share.is_finite() {
                format!("{:.2}", r.edge_error_share)
            } else {
                "—".into()
            },
            r.flip_sss,
            if on { "●" } else { "" }
        );
    }
    let _ = writeln!(s, "\n![{}]({}.png)\n", scene.id, scene.id);
}

fn sampling_target(s: &mut String, c: &Context) {
    let b = Config::of;
    let _ = writeln!(
        s,
        "## Beating the published sampling\n\nBaseline: Golubev 2018 as published (`golubev`). Target: `burley` (`improved`) at 21 samples no worse than `golubev` at 55 on the head scenes.\n\n| Scene | golubev 21 | golubev 55 | improved 21 | antithetic 21 | mis 21 | r2 21 | bilinear 21 | centre 21 | improved 55 | met (RMSE) | met (FLIP) |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    // `burley`'s configurations by (sampling, samples): the study of its
    // sampling (`burley::bench`).
    let variants: Vec<Option<Config>> = [
        ("golubev", 21),
        ("golubev", 55),
        ("improved", 21),
        ("antithetic", 21),
        ("mis", 21),
        ("r2", 21),
        ("bilinear", 21),
        ("centre", 21),
        ("improved", 55),
    ]
    .iter()
    .map(|&(v, n)| b(Method::Burley, v, n))
    .collect();
    for scene in c.scenes.iter().filter(|s| s.head_shot) {
        let got: Vec<Option<&Row>> = variants
            .iter()
            .map(|v| v.and_then(|v| find(c.rows, scene.id, v)))
            .collect();
        let cell = |r: &Option<&Row>| match r {
            Some(r) => format!("{:.4} / {:.4}", r.rel_rmse, r.flip_sss),
            None => "—".into(),
        };
        let met = |f: fn(&Row) -> f64| match (got[2], got[1]) {
            (Some(a), Some(b)) => {
                if f(a) <= f(b) {
                    "yes"
                } else {
                    "no"
                }
            }
            _ => "—",
        };
        let cells: Vec<String> = got.iter().map(cell).collect();
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} |",
            scene.id,
            cells.join(" | "),
            met(|r| r.rel_rmse),
            met(|r| r.flip_sss)
        );
    }
    let _ = writeln!(s, "\nCells: relative RMSE / mean FLIP over SSS pixels.\n");
}

/// Scattering changes the head's irradiance by a few per cent RMS, so an
/// absolute error budget says little; the budgets are fractions of the
/// `none` frame's error (how much of the scattering a method captures).
pub const BUDGETS: [f64; 3] = [0.5, 0.25, 0.1];

fn picks(s: &mut String, c: &Context) {
    let _ = writeln!(
        s,
        "## Cheapest configuration within an error budget\n\nBudgets are fractions of the `none` frame's relative RMSE (no scattering at all): ≤ 0.5× captures half of the scattering, ≤ 0.1× nine tenths. Cells: the configuration an artist can pick (no single-flag Burley variants) with the smallest frame time ÷ `none` frame that meets the budget.\n\n| Scene | `none` RMSE | ≤ 0.5× | ≤ 0.25× | ≤ 0.1× |\n| --- | --- | --- | --- | --- |"
    );
    for scene in c.scenes {
        let rows: Vec<&Row> = c.rows.iter().filter(|r| r.scene == scene.id).collect();
        let Some(none) = rows.iter().find(|r| r.config == Config::none()) else {
            continue;
        };
        let cell = |f: f64| match cheapest_within(&rows, f * none.rel_rmse) {
            Some(r) => format!("{} ({:.2}×)", r.config.label(), r.frame_ratio()),
            None => "—".into(),
        };
        let cells: Vec<String> = BUDGETS.iter().map(|f| cell(*f)).collect();
        let _ = writeln!(
            s,
            "| {} | {:.4} | {} |",
            scene.id,
            none.rel_rmse,
            cells.join(" | ")
        );
    }
    let _ = writeln!(s);
}

fn floor_table(s: &mut String, c: &Context) {
    let _ = writeln!(
        s,
        "## The ground truth's floor and cost\n\nHow far the yardstick is from answers it must give exactly (`bench::floor`): with a profile that scatters nothing (d = 1 µm) it must give back the `none` frame, and gathered at 2 × 2 points of each pixel's footprint it must give back its own one-point answer (over the pixels whose footprint is one surface; the others, at silhouettes and creases, are the \"mixed\" column). A difference between two methods smaller than the scene's floor is the yardstick's noise. Its cost: the wall time of its frame (CPU, every core), and that as a multiple of the `none` frame of the same scene and run.\n\n| Scene | d → 0 against `none` | 2 × 2 against 1 | mixed pixels | ground truth (s) | × `none` |\n| --- | --- | --- | --- | --- | --- |"
    );
    for (scene, f) in c.floors {
        let truth = c
            .rows
            .iter()
            .find(|r| r.scene == *scene && r.config == Config::reference());
        let (secs, ratio) = truth.map_or(("—".into(), "—".into()), |r| {
            (
                format!("{:.2}", r.frame_ms / 1e3),
                format!("{:.0}", r.frame_ms / r.none_frame_ms),
            )
        });
        let _ = writeln!(
            s,
            "| {scene} | {:.4} | {:.4} | {:.1} % | {secs} | {ratio} |",
            f.d_to_zero,
            f.supersampled,
            100.0 * f.mixed_fraction
        );
    }
    let _ = writeln!(s);
}

/// The generated report: the floor, tables per scene, the sampling
/// target, the budget picks and the skip study.
pub fn markdown(c: &Context) -> String {
    let mut s = String::new();
    let timing = c
        .rows
        .iter()
        .find(|r| !r.config.method.sss().ground_truth)
        .map(|r| r.timing)
        .unwrap_or("gpu-timestamps");
    let _ = writeln!(
        s,
        "# Bench results ({})\n\nGenerated by `scatterlab bench{}`. Adapter: {}. Frames {}×{}, one warm-up and {} timed frame(s) per configuration (fastest kept). Times: {}; given as ratios to the `none` frame of the same scene and run (on a CPU adapter such as lavapipe the GPU time is CPU time). Error against `reference`, the ground truth (the profile integrated over the whole SSS surface of the mesh in object space on the CPU, `render::ground_truth`; rendered once per scene, its CPU time is in the csv): relative RMSE of the scattered irradiance (linear HDR) over SSS pixels, the same over the interior (SSS pixels at least 3 px from a mask edge or silhouette, where the screen-space methods renormalise over what they see), the share of the squared error in the 3 px band along those edges, and mean FLIP over SSS pixels of the tonemapped images. ● marks the Pareto front of frame time against RMSE.\n",
        if c.quick { "quick" } else { "full" },
        if c.quick { " --quick" } else { "" },
        c.adapter,
        c.options.size.0,
        c.options.size.1,
        c.options.repeats,
        timing
    );
    floor_table(&mut s, c);
    let none_ms = |scene: &str| {
        c.rows
            .iter()
            .find(|r| r.scene == scene)
            .map(|r| r.none_frame_ms)
    };
    super::truth::markdown(&mut s, c.truth, &none_ms);
    for scene in c.scenes {
        let rows: Vec<&Row> = c.rows.iter().filter(|r| r.scene == scene.id).collect();
        let _ = writeln!(s, "## {}\n\n{}.\n", scene.id, scene.description);
        if let Some((_, f)) = c.floors.iter().find(|(id, _)| *id == scene.id) {
            let _ = writeln!(
                s,
                "The ground truth's floor here: {:.4} (d → 0), {:.4} (2 × 2 supersampled); relative RMSE differences smaller than the larger are noise.\n",
                f.d_to_zero, f.supersampled
            );
        }
        scene_table(&mut s, scene, &rows);
    }
    sampling_target(&mut s, c);
    picks(&mut s, c);
    super::skip::markdown(&mut s, c.skip);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(config: Config, frame_ms: f64, rel_rmse: f64) -> Row {
        Row {
            scene: "s",
            config,
            width: 1,
            height: 1,
            sss_pixels: 1,
            samples: 1,
            sss_ms: 0.0,
            frame_ms,
            none_frame_ms: 1.0,
            rel_rmse,
            rel_rmse_interior: rel_rmse,
            edge_error_share: 0.0,
            flip_sss: 0.0,
            flip_image: 0.0,
            timing: "gpu-timestamps",
        }
    }

    #[test]
    fn pareto_front_by_hand() {
        let b = |n| Config::of(Method::Burley, "golubev", n).unwrap();
        let rows = [
            row(Config::none(), 1.0, 0.5),
            row(b(7), 2.0, 0.2),
            row(b(13), 3.0, 0.3), // dominated by b(7)
            row(b(21), 4.0, 0.1),
            row(Config::reference(), 30.0, 0.0), // never a candidate
        ];
        let refs: Vec<&Row> = rows.iter().collect();
        let front: Vec<usize> = pareto_front(&refs)
            .iter()
            .map(|r| r.config.count())
            .collect();
        assert_eq!(front, vec![0, 7, 21]);
        assert_eq!(
            cheapest_within(&refs, 0.25).map(|r| r.config.count()),
            Some(7)
        );
        assert!(cheapest_within(&refs, 0.05).is_none());
    }
}
