//! `scatterlab bench`: run time against error for every SSS method and
//! count on fixed scenes, each against the ground truth (`reference`: the
//! profile integrated over the mesh in object space, `render::ground_truth`),
//! plus the proof that unused work is skipped.
//!
//! Times are GPU timestamps of the SSS passes (wall-clock of the frame
//! where the adapter has no timestamp queries), always reported as a ratio
//! to the `none` frame measured in the same run. On lavapipe the "GPU" is
//! the CPU, so the ratios, not the milliseconds, are what carries over.

pub mod chart;
pub mod csv;
pub mod floor;
pub mod metrics;
pub mod report;
pub mod scenes;
pub mod skip;
pub mod truth;

use crate::model::RadialProfile;
use crate::render::{FrameStats, GpuContext, Mesh, ProfileInputs, RenderSettings, Renderer};
use crate::settings::{Preset, ProfileSpec};
use anyhow::{Context, Result};
use image::RgbaImage;
use scenes::{Config, Scene, Stage};
use std::path::Path;
use std::time::Instant;

/// One row of `results.csv`.
#[derive(Debug, Clone)]
pub struct Row {
    pub scene: &'static str,
    pub config: Config,
    pub width: u32,
    pub height: u32,
    pub sss_pixels: u64,
    /// Profile samples (burley, reference) or taps × pixels × passes.
    pub samples: u64,
    /// GPU time of the SSS passes (ms); 0 when none ran.
    pub sss_ms: f64,
    /// GPU time of the whole frame (ms), shadow map excluded (cached).
    pub frame_ms: f64,
    /// The `none` frame of the same scene in the same run (ms).
    pub none_frame_ms: f64,
    pub rel_rmse: f64,
    /// Relative RMSE over the SSS pixels at least [`INTERIOR_MARGIN_PX`]
    /// from a mask edge or silhouette (`metrics::interior`).
    pub rel_rmse_interior: f64,
    /// The share of the squared error (over SSS pixels) that lies within
    /// [`INTERIOR_MARGIN_PX`] of a mask edge or silhouette: 1 − SSE(interior)
    /// / SSE(all) (`metrics::squared_error`).
    pub edge_error_share: f64,
    /// Mean FLIP over SSS pixels and over the whole image.
    pub flip_sss: f64,
    pub flip_image: f64,
    /// "gpu-timestamps" or "wall-clock"; "cpu-wall-clock" for `reference`.
    pub timing: &'static str,
}

impl Row {
    pub fn sss_ratio(&self) -> f64 {
        self.sss_ms / self.none_frame_ms
    }
    pub fn frame_ratio(&self) -> f64 {
        self.frame_ms / self.none_frame_ms
    }
}

/// Margin (px) of the interior error.
pub const INTERIOR_MARGIN_PX: usize = 3;

/// Frame sizes and repeats of a run.
#[derive(Debug, Clone, Copy)]
pub struct Options {
    pub size: (u32, u32),
    /// Timed frames per configuration after one warm-up (the minimum is kept).
    pub repeats: u32,
    /// Also gather the ground truth on the GPU (`truth.csv`'s `gpu-final`).
    pub gpu_truth: bool,
}

impl Options {
    pub fn new(quick: bool) -> Self {
        if quick {
            Self {
                size: (320, 180),
                repeats: 1,
                gpu_truth: false,
            }
        } else {
            Self {
                size: (640, 360),
                repeats: 3,
                gpu_truth: false,
            }
        }
    }
}

/// The profile and the inputs of each configuration, each made once per
/// run (the Gaussians' and Jimenez 2012's fits take a while).
pub struct Prepared {
    pub profile: Box<dyn RadialProfile>,
    pub spec: ProfileSpec,
    /// Every method's inputs at the look's defaults (21 samples, 17 taps).
    pub base: ProfileInputs,
    made: std::sync::Mutex<Vec<(Config, ProfileInputs)>>,
}

impl Prepared {
    pub fn new(preset: &Preset) -> Result<Self> {
        let profile = preset.build_profile()?;
        Ok(Self {
            base: ProfileInputs::new(profile.as_ref(), 21, 17)?,
            spec: preset.profile.clone(),
            profile,
            made: Default::default(),
        })
    }

    /// The inputs of one configuration: the base with the method's own
    /// set to it (the method's `MethodInputs::bench`).
    pub fn inputs(&self, config: Config) -> Result<ProfileInputs> {
        let made = |m: &Vec<(Config, ProfileInputs)>| {
            m.iter().find(|(c, _)| *c == config).map(|(_, i)| i.clone())
        };
        if let Some(i) = self.made.lock().ok().as_deref().and_then(made) {
            return Ok(i);
        }
        let mut i = self.base.clone();
        i.bench(
            &self.spec,
            self.profile.as_ref(),
            config.method,
            &config.knob,
        )?;
        if let Ok(mut m) = self.made.lock() {
            m.push((config, i.clone()));
        }
        Ok(i)
    }
}

/// A frame's image, scattered irradiance and best times.
pub struct Measured {
    pub image: RgbaImage,
    pub diffuse: Vec<[f32; 4]>,
    /// The warm-up frame's stats (pixels and samples).
    pub stats: FrameStats,
    /// The fastest timed frame's stats (per-pass times).
    pub fastest: FrameStats,
    pub sss_ms: f64,
    pub frame_ms: f64,
    pub timing: &'static str,
}

fn frame_gpu_ms(stats: &FrameStats) -> Option<f64> {
    stats.passes.iter().map(|p| p.gpu_ms).sum()
}

/// Renders one warm-up frame (read back with its irradiance) and
/// `repeats` timed frames, keeping the fastest time.
pub fn measure(
    renderer: &mut Renderer,
    inputs: &ProfileInputs,
    settings: &RenderSettings,
    repeats: u32,
) -> Result<Measured> {
    let (image, diffuse, stats) = renderer.render_with_diffuse(inputs, settings)?;
    let (mut sss_ms, mut frame_ms) = (f64::INFINITY, f64::INFINITY);
    let mut timing = "gpu-timestamps";
    let mut fastest = stats.clone();
    for _ in 0..repeats.max(1) {
        let start = Instant::now();
        let (_, s) = renderer.render(inputs, settings)?;
        let wall = start.elapsed().as_secs_f64() * 1e3;
        let f = frame_gpu_ms(&s).unwrap_or_else(|| {
            timing = "wall-clock";
            wall
        });
        if f < frame_ms {
            frame_ms = f;
            fastest = s.clone();
        }
        sss_ms = sss_ms.min(s.sss_gpu_ms.unwrap_or(0.0));
    }
    Ok(Measured {
        image,
        diffuse,
        stats,
        fastest,
        sss_ms,
        frame_ms,
        timing,
    })
}

/// A renderer for a scene's stage, on its own headless device.
pub fn renderer_for(stage: Stage) -> Result<Renderer> {
    let mesh = match stage {
        Stage::Head => Mesh::default_head()?,
        Stage::Scan => scenes::scan_mesh()?,
        Stage::Plane => Mesh::plane(200.0, 0.001),
    };
    Ok(Renderer::new(GpuContext::new_headless()?, &mesh)?)
}

/// Every configuration on one scene, and the ground truth's floor and
/// its other paths there.
pub fn bench_scene(
    renderer: &mut Renderer,
    prepared: &Prepared,
    scene: &Scene,
    options: Options,
) -> Result<(Vec<Row>, floor::Floor, Vec<truth::TruthRow>)> {
    let settings = |c: Config| RenderSettings {
        method: c.method(),
        ..scene.settings.clone()
    };
    let run = |r: &mut Renderer, c: Config| -> Result<Measured> {
        measure(r, &prepared.inputs(c)?, &settings(c), options.repeats)
            .with_context(|| format!("{}: {}", scene.id, c.label()))
    };
    // The ground truth is the yardstick, rendered once: its time is CPU
    // wall time (its gather runs on the CPU), not a point on the charts.
    let reference = {
        let start = Instant::now();
        let (image, diffuse, stats) = renderer
            .render_with_diffuse(
                &prepared.inputs(Config::reference())?,
                &settings(Config::reference()),
            )
            .with_context(|| format!("{}: reference", scene.id))?;
        let wall = start.elapsed().as_secs_f64() * 1e3;
        Measured {
            image,
            diffuse,
            sss_ms: stats.reference_cpu_ms.unwrap_or(wall),
            fastest: stats.clone(),
            stats,
            frame_ms: wall,
            timing: "cpu-wall-clock",
        }
    };
    let floor = floor::measure(
        renderer,
        &prepared.inputs(Config::reference())?,
        &settings(Config::reference()),
        &reference.diffuse,
    )
    .with_context(|| format!("{}: the ground truth's floor", scene.id))?;
    let mut truth_rows = truth::measure(
        renderer,
        (
            &prepared.inputs(Config::reference())?,
            prepared.profile.as_ref(),
        ),
        &settings(Config::reference()),
        (&reference.diffuse, &reference.stats, floor.d_to_zero),
        options.gpu_truth,
    )
    .with_context(|| format!("{}: the ground truth's paths", scene.id))?;
    for t in &mut truth_rows {
        t.scene = scene.id;
    }
    let mask = metrics::sss_mask(&reference.diffuse);
    let inner = metrics::interior(&mask, scene.settings.width as usize, INTERIOR_MARGIN_PX);
    let row = |c: Config, m: &Measured| {
        let flip = metrics::flip_map(&reference.image, &m.image);
        Row {
            scene: scene.id,
            config: c,
            width: scene.settings.width,
            height: scene.settings.height,
            sss_pixels: m.stats.sss_pixels,
            samples: m.stats.sss_samples,
            sss_ms: m.sss_ms,
            frame_ms: m.frame_ms,
            none_frame_ms: 0.0,
            rel_rmse: metrics::relative_rmse(&m.diffuse, &reference.diffuse, &mask),
            rel_rmse_interior: metrics::relative_rmse(&m.diffuse, &reference.diffuse, &inner),
            edge_error_share: metrics::edge_share(&m.diffuse, &reference.diffuse, &mask, &inner),
            flip_sss: metrics::masked_mean(&flip, &mask),
            flip_image: metrics::masked_mean(&flip, &vec![true; flip.len()]),
            timing: m.timing,
        }
    };
    let mut rows = vec![row(Config::reference(), &reference)];
    for c in scenes::configs() {
        rows.push(row(c, &run(renderer, c)?));
    }
    // `none` again at the end: the smaller of the two brackets drift.
    let none_again = run(renderer, Config::none())?.frame_ms;
    let none_frame_ms = rows
        .iter()
        .filter(|r| r.config == Config::none())
        .map(|r| r.frame_ms)
        .fold(none_again, f64::min);
    for r in &mut rows {
        r.none_frame_ms = none_frame_ms;
    }
    Ok((rows, floor, truth_rows))
}

/// Redraws the charts and the report of an earlier run from its
/// `results.csv` and `skip.csv` (`bench --replot DIR`), without rendering.
pub fn replot(dir: &Path, quick: bool) -> Result<()> {
    let options = Options::new(quick);
    let rows = report::read_csv(&dir.join("results.csv"))?;
    let floors = report::read_floor_csv(&dir.join("floor.csv"))?;
    let truths = truth::read_csv(&dir.join("truth.csv"))?;
    let skip_rows = skip::read_csv(&dir.join("skip.csv"))?;
    let first = rows.first().context("results.csv has no rows")?;
    let scenes = scenes::scenes((first.width, first.height));
    for scene in &scenes {
        chart::write(&dir.join(format!("{}.png", scene.id)), scene, &rows)?;
    }
    let md = report::markdown(&report::Context {
        scenes: &scenes,
        rows: &rows,
        floors: &floors,
        truth: &truths,
        skip: &skip_rows,
        options: Options {
            size: (first.width, first.height),
            ..options
        },
        adapter: "(as recorded in the run)",
        quick,
    });
    crate::fsutil::write_atomic(&dir.join("accuracy.md"), md.as_bytes())
        .with_context(|| format!("writing {}", dir.join("accuracy.md").display()))
}

/// `scatterlab bench --out DIR [--quick] [--preset FILE]`.
pub fn run_cli(out: &Path, quick: bool, preset: Option<&Path>, gpu_truth: bool) -> Result<()> {
    let options = Options {
        gpu_truth,
        ..Options::new(quick)
    };
    let preset = match preset {
        Some(p) => Preset::load(p)?,
        None => Preset::default_skin(),
    };
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let start = Instant::now();
    let prepared = Prepared::new(&preset)?;
    eprintln!(
        "prepared the profile's patterns, kernels and fits in {:.1} s",
        start.elapsed().as_secs_f64()
    );
    let scenes = scenes::scenes(options.size);
    let mut head: Option<Renderer> = None;
    let mut plane: Option<Renderer> = None;
    // The scan's files are read first: a binary run away from its
    // checkout fails here, not minutes in.
    let mut scan: Option<Renderer> = None;
    if scenes.iter().any(|s| s.stage == Stage::Scan) {
        scan = Some(renderer_for(Stage::Scan).context(
            "bench needs the head scan of the checkout it was built from (assets/scan); run it from there",
        )?);
    }
    let mut rows = Vec::new();
    let mut floors = Vec::new();
    let mut truths = Vec::new();
    for (k, scene) in scenes.iter().enumerate() {
        let t = Instant::now();
        let slot = match scene.stage {
            Stage::Head => &mut head,
            Stage::Scan => &mut scan,
            Stage::Plane => &mut plane,
        };
        let renderer = match slot {
            Some(r) => r,
            None => slot.insert(renderer_for(scene.stage)?),
        };
        let (scene_rows, floor, truth_rows) = bench_scene(renderer, &prepared, scene, options)?;
        rows.extend(scene_rows);
        floors.push((scene.id, floor));
        truths.extend(truth_rows);
        eprintln!(
            "[{}/{}] {}: {:.1} s",
            k + 1,
            scenes.len(),
            scene.id,
            t.elapsed().as_secs_f64()
        );
    }
    report::write_csv(&out.join("results.csv"), &rows)?;
    report::write_floor_csv(&out.join("floor.csv"), &floors)?;
    truth::write_csv(&out.join("truth.csv"), &truths)?;
    for scene in &scenes {
        chart::write(&out.join(format!("{}.png", scene.id)), scene, &rows)?;
    }
    let skip_rows = skip::run(&prepared, options, head.as_mut())?;
    skip::write_csv(&out.join("skip.csv"), &skip_rows)?;
    let adapter = head
        .as_ref()
        .or(plane.as_ref())
        .map(|r| r.adapter_name())
        .unwrap_or_default();
    let md = report::markdown(&report::Context {
        scenes: &scenes,
        rows: &rows,
        floors: &floors,
        truth: &truths,
        skip: &skip_rows,
        options,
        adapter: &adapter,
        quick,
    });
    crate::fsutil::write_atomic(&out.join("accuracy.md"), md.as_bytes())
        .with_context(|| format!("writing {}", out.join("accuracy.md").display()))?;
    eprintln!(
        "bench: {} rows in {:.1} s → {}",
        rows.len(),
        start.elapsed().as_secs_f64(),
        out.display()
    );
    Ok(())
}
