//! The ground truth's own cost and error on each path and at each bound
//! (issue 38): per scene, the gather on the CPU at the final bound (the
//! yardstick every row is measured against), on the CPU at the loose
//! bound (`TruthBound::Loose`, the same walk with coarser leaves and
//! splits), and, with `bench --reference-gpu`, on the GPU at the final
//! bound. Each against the final CPU truth of the scene, with its own
//! d → 0 floor (the truth of a profile that scatters nothing against the
//! `none` frame), and its gather time as a multiple of the `none` frame of
//! the same scene and run.

use super::{floor, metrics};
use crate::model::RadialProfile;
use crate::render::ground_truth::{ProfileTable, TruthBound};
use crate::render::{FrameStats, Method, ProfileInputs, RenderSettings, Renderer};
use anyhow::{Context, Result};
use std::fmt::Write as _;
use std::path::Path;
use std::sync::Arc;

/// One path of the ground truth on one scene.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthRow {
    pub scene: &'static str,
    /// `cpu-final`, `cpu-loose` or `gpu-final`.
    pub path: &'static str,
    /// The gather's wall time (ms), without building the cells.
    pub gather_ms: f64,
    /// Relative RMSE against the final CPU truth over SSS pixels (0 for
    /// that truth itself).
    pub from_final: f64,
    /// Relative RMSE of its d → 0 frame against `none`.
    pub d_to_zero: f64,
    /// On the GPU: the points it did not finish (gathered on the CPU).
    pub gpu_unfinished: Option<u64>,
}

/// The gather's time of a reference frame: its CPU time less the cells'.
fn gather_ms(stats: &FrameStats) -> f64 {
    stats.reference_cpu_ms.unwrap_or(0.0) - stats.reference_build_ms.unwrap_or(0.0)
}

/// The look's inputs with the ground truth at `bound` and on the GPU or
/// not.
fn path_inputs(
    look: &ProfileInputs,
    profile: &dyn RadialProfile,
    bound: TruthBound,
    gpu: bool,
) -> ProfileInputs {
    let mut i = look.clone();
    i.options.reference.bound = bound;
    i.options.reference.gpu = gpu;
    i.methods.reference.table = Arc::new(ProfileTable::with_bound(profile, bound));
    i
}

/// Measures the loose bound and (with `gpu`) the GPU path on the scene
/// `settings`, given the final CPU truth already rendered (`final_truth`
/// and its `final_stats`) and its floor's d → 0 figure.
pub fn measure(
    renderer: &mut Renderer,
    (look, profile): (&ProfileInputs, &dyn RadialProfile),
    settings: &RenderSettings,
    (final_truth, final_stats, final_d_to_zero): (&[[f32; 4]], &FrameStats, f64),
    gpu: bool,
) -> Result<Vec<TruthRow>> {
    let scene = "";
    let mut rows = vec![TruthRow {
        scene,
        path: "cpu-final",
        gather_ms: gather_ms(final_stats),
        from_final: 0.0,
        d_to_zero: final_d_to_zero,
        gpu_unfinished: None,
    }];
    let mask = metrics::sss_mask(final_truth);
    let none = RenderSettings {
        method: Method::baseline(),
        ..settings.clone()
    };
    let zero_look = floor::d_to_zero_inputs(look)?;
    let (_, unscattered, _) = renderer
        .render_with_diffuse(&zero_look, &none)
        .context("the none frame at d → 0")?;
    let zero_mask = metrics::sss_mask(&unscattered);
    let zero_profile = floor::d_to_zero_profile(look)?;
    let mut paths = vec![("cpu-loose", TruthBound::Loose, false)];
    if gpu {
        paths.push(("gpu-final", TruthBound::Final, true));
    }
    for (path, bound, on_gpu) in paths {
        let inputs = path_inputs(look, profile, bound, on_gpu);
        let (_, truth, stats) = renderer
            .render_with_diffuse(&inputs, settings)
            .with_context(|| format!("the ground truth ({path})"))?;
        let zero = path_inputs(&zero_look, &zero_profile, bound, on_gpu);
        let (_, at_zero, _) = renderer
            .render_with_diffuse(&zero, settings)
            .with_context(|| format!("the ground truth ({path}) at d → 0"))?;
        rows.push(TruthRow {
            scene,
            path,
            gather_ms: gather_ms(&stats),
            from_final: metrics::relative_rmse(&truth, final_truth, &mask),
            d_to_zero: metrics::relative_rmse(&at_zero, &unscattered, &zero_mask),
            gpu_unfinished: stats.reference_gpu_unfinished,
        });
    }
    Ok(rows)
}

pub const HEADER: &str =
    "scene,path,gather_ms,from_final_rel_rmse,d_to_zero_rel_rmse,gpu_unfinished";

/// `truth.csv`: the ground truth's paths per scene.
pub fn write_csv(path: &Path, rows: &[TruthRow]) -> Result<()> {
    let mut s = String::from(HEADER);
    s.push('\n');
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{:.1},{:.6},{:.6},{}",
            r.scene,
            r.path,
            r.gather_ms,
            r.from_final,
            r.d_to_zero,
            r.gpu_unfinished.map_or(String::new(), |n| n.to_string())
        );
    }
    crate::fsutil::write_atomic(path, s.as_bytes())
        .with_context(|| format!("writing {}", path.display()))
}

/// Reads a `truth.csv` back (`--replot`); a run from before it was
/// written has none: no rows.
pub fn read_csv(path: &Path) -> Result<Vec<TruthRow>> {
    if !path.exists() {
        return Ok(Vec::new());
    }
    let scenes = super::scenes::scenes((1, 1));
    let ids: Vec<&'static str> = scenes.iter().map(|s| s.id).collect();
    const PATHS: [&str; 3] = ["cpu-final", "cpu-loose", "gpu-final"];
    super::csv::read(path, HEADER, 6)?
        .iter()
        .map(|r| {
            r.expect_fields(&[6])?;
            Ok(TruthRow {
                scene: r.one_of(0, &ids)?,
                path: r.one_of(1, &PATHS)?,
                gather_ms: r.num(2)?,
                from_final: r.num(3)?,
                d_to_zero: r.num(4)?,
                gpu_unfinished: r.opt_num(5)?.map(|v| v as u64),
            })
        })
        .collect()
}

/// The report's table: each scene's paths, with the `none` frame of the
/// same scene and run (`none_ms`).
pub fn markdown(s: &mut String, rows: &[TruthRow], none_ms: &dyn Fn(&str) -> Option<f64>) {
    if rows.is_empty() {
        return;
    }
    let _ = writeln!(
        s,
        "## The ground truth on each path and at each bound\n\nThe gather of the ground truth (its cells, which depend only on the light and the look, left out) on the CPU at the final bound (the yardstick of every table here), on the CPU at the loose bound (`render --truth-bound loose`: the same walk with the rule's τ four times larger and a near piece's corners allowed 4 % apart) and, with `bench --reference-gpu`, on the GPU (`render --reference-gpu`: the same walk in a compute shader with the scene pass's own shading; the points the GPU did not finish, lavapipe's loop limit, are gathered on the CPU and counted). Each: its distance from the final CPU truth, its own d → 0 floor, and its time as a multiple of the `none` frame of the same scene and run.\n\n| Scene | path | gather (s) | × `none` | from the final CPU truth | d → 0 against `none` | points left to the CPU |\n| --- | --- | --- | --- | --- | --- | --- |"
    );
    for r in rows {
        let ratio = none_ms(r.scene).map_or("—".into(), |n| format!("{:.0}", r.gather_ms / n));
        let _ = writeln!(
            s,
            "| {} | {} | {:.2} | {ratio} | {:.4} | {:.4} | {} |",
            r.scene,
            r.path,
            r.gather_ms / 1e3,
            r.from_final,
            r.d_to_zero,
            r.gpu_unfinished.map_or("—".into(), |n| n.to_string())
        );
    }
    let _ = writeln!(s);
}
