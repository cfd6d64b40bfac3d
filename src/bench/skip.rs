//! Measured proof that unused work is skipped: SSS cost against screen
//! coverage, strength 0, transmission off, and the LOD on the far shot.

use super::scenes::{plane_settings, scenes, Config, Stage};
use super::{measure, renderer_for, Options, Prepared};
use crate::model::jimenez::{Jimenez2012, DEFAULT_FALLOFF};
use crate::render::textures::{MeshTextures, TextureImage};
use crate::render::{
    FrameStats, GpuContext, IrradiancePattern, Mesh, Method, ProfileInputs, RenderSettings,
    Renderer, Transmission,
};
use anyhow::{Context as _, Result};
use std::fmt::Write as _;
use std::path::Path;

/// One measured frame of the skip study.
#[derive(Debug, Clone)]
pub struct SkipRow {
    pub study: &'static str,
    pub case: String,
    pub method: &'static str,
    pub pixels: u64,
    pub sss_pixels: u64,
    pub sss_samples: u64,
    pub lod_skipped_pixels: u64,
    pub sss_passes: usize,
    pub scene_ms: f64,
    pub sss_ms: f64,
    pub frame_ms: f64,
    /// The `none` frame of the same case.
    pub none_frame_ms: f64,
    /// Every pass as name:pixels:samples:ms.
    pub passes: String,
}

fn row(study: &'static str, case: String, m: &super::Measured, none_frame_ms: f64) -> SkipRow {
    let s: &FrameStats = &m.fastest;
    let pass_ms = |name: &str| {
        s.passes
            .iter()
            .filter(|p| p.name == name)
            .filter_map(|p| p.gpu_ms)
            .sum::<f64>()
    };
    SkipRow {
        study,
        case,
        method: s.method,
        pixels: s.width as u64 * s.height as u64,
        sss_pixels: m.stats.sss_pixels,
        sss_samples: m.stats.sss_samples,
        lod_skipped_pixels: m.stats.lod_skipped_pixels,
        sss_passes: s
            .passes
            .iter()
            .filter(|p| p.name.starts_with("sss"))
            .count(),
        scene_ms: pass_ms("scene"),
        sss_ms: m.sss_ms,
        frame_ms: m.frame_ms,
        none_frame_ms,
        passes: s
            .passes
            .iter()
            .map(|p| {
                format!(
                    "{}:{}:{}:{:.3}",
                    p.name,
                    p.pixels,
                    p.samples,
                    p.gpu_ms.unwrap_or(f64::NAN)
                )
            })
            .collect::<Vec<_>>()
            .join(" "),
    }
}

/// A plane whose SSS mask covers the left `fraction` of the visible width.
fn masked_plane(fraction: f32, settings: &RenderSettings) -> Mesh {
    const TEXELS: usize = 2048;
    let mut plane = Mesh::plane(200.0, 0.001);
    // Visible half-width on the plane (mm) → the u range on screen.
    let aspect = settings.width as f32 / settings.height as f32;
    let half_w_mm =
        settings.view.camera_distance_m * 1000.0 * (0.5 * settings.view.fov_y_rad).tan() * aspect;
    let (u0, u1) = (0.5 - half_w_mm / 200.0, 0.5 + half_w_mm / 200.0);
    // 0 % and 100 % are the whole plane (the mask is filtered, so a cut at
    // the screen's edge would bleed a column).
    let cut = match fraction {
        f if f <= 0.0 => -1.0,
        f if f >= 1.0 => 2.0,
        f => u0 + f * (u1 - u0),
    };
    let texels = (0..TEXELS)
        .map(|i| {
            let u = (i as f32 + 0.5) / TEXELS as f32;
            if u < cut {
                255
            } else {
                0
            }
        })
        .collect();
    plane.textures = std::sync::Arc::new(MeshTextures {
        mask: TextureImage {
            width: TEXELS as u32,
            height: 1,
            channels: 1,
            texels,
        },
        ..Default::default()
    });
    plane
}

/// `burley` at its default sampling and 21 samples: the method whose
/// skipped work (coverage, strength 0, LOD) these studies measure.
fn b21() -> Result<Config> {
    Config::of(Method::Burley, "improved", 21).context("burley's bench configurations")
}

fn burley(prepared: &Prepared) -> Result<ProfileInputs> {
    prepared.inputs(b21()?)
}

/// SSS cost at 0, 10, 50 and 100 % coverage of a lit plane.
fn coverage(prepared: &Prepared, options: Options) -> Result<Vec<SkipRow>> {
    let base = plane_settings(options.size, IrradiancePattern::Lit);
    let inputs = burley(prepared)?;
    let none_inputs = prepared.inputs(Config::none())?;
    let mut rows = Vec::new();
    for pct in [0u32, 10, 50, 100] {
        let mesh = masked_plane(pct as f32 / 100.0, &base);
        let mut r = Renderer::new(GpuContext::new_headless()?, &mesh)?;
        let none = measure(
            &mut r,
            &none_inputs,
            &with(&base, Config::none()),
            options.repeats,
        )?;
        for (c, i) in [(b21()?, &inputs), (Config::none(), &none_inputs)] {
            let m = measure(&mut r, i, &with(&base, c), options.repeats)?;
            rows.push(row("coverage", format!("{pct}%"), &m, none.frame_ms));
        }
    }
    Ok(rows)
}

fn with(s: &RenderSettings, c: Config) -> RenderSettings {
    RenderSettings {
        method: c.method(),
        ..s.clone()
    }
}

/// Strength 0 (Jimenez 2012: nothing scatters), transmission off / thin /
/// thick on the back-lit ear, and the LOD on / off on the far shot.
fn head_studies(prepared: &Prepared, options: Options, r: &mut Renderer) -> Result<Vec<SkipRow>> {
    let shots = scenes(options.size);
    let shot = |id: &str| -> Result<RenderSettings> {
        shots
            .iter()
            .find(|s| s.id == id)
            .map(|s| s.settings.clone())
            .context("a bench scene is missing")
    };
    let b21 = b21()?;
    let inputs = burley(prepared)?;
    let none_inputs = prepared.inputs(Config::none())?;
    let mut rows = Vec::new();
    let front = shot("head_front")?;
    let none = measure(
        r,
        &none_inputs,
        &with(&front, Config::none()),
        options.repeats,
    )?;
    let zero = Jimenez2012::new([0.0; 3], DEFAULT_FALLOFF)?;
    let zero_inputs = ProfileInputs::new(&zero, 21, 17)?;
    let m = measure(r, &zero_inputs, &with(&front, b21), options.repeats)?;
    rows.push(row(
        "strength",
        "jimenez strength 0".into(),
        &m,
        none.frame_ms,
    ));
    let m = measure(r, &inputs, &with(&front, b21), options.repeats)?;
    rows.push(row("strength", "default skin".into(), &m, none.frame_ms));
    let ear = shot("head_backlit_ear")?;
    let none = measure(
        r,
        &none_inputs,
        &with(&ear, Config::none()),
        options.repeats,
    )?;
    for (name, t) in [
        ("off", Transmission::Off),
        ("thin", Transmission::ThinObject),
        ("thick", Transmission::ThickObject),
    ] {
        let s = RenderSettings {
            transmission: t,
            ..with(&ear, b21)
        };
        let m = measure(r, &inputs, &s, options.repeats)?;
        rows.push(row(
            "transmission",
            format!("transmission {name}"),
            &m,
            none.frame_ms,
        ));
    }
    let far = shot("head_far")?;
    let none = measure(
        r,
        &none_inputs,
        &with(&far, Config::none()),
        options.repeats,
    )?;
    for lod in [true, false] {
        let s = RenderSettings {
            lod,
            ..with(&far, b21)
        };
        let m = measure(r, &inputs, &s, options.repeats)?;
        let case = if lod {
            "far shot LOD on"
        } else {
            "far shot LOD off"
        };
        rows.push(row("lod", case.into(), &m, none.frame_ms));
    }
    Ok(rows)
}

pub fn run(
    prepared: &Prepared,
    options: Options,
    head: Option<&mut Renderer>,
) -> Result<Vec<SkipRow>> {
    let mut rows = coverage(prepared, options)?;
    let mut own;
    let r = match head {
        Some(r) => r,
        None => {
            own = renderer_for(Stage::Head)?;
            &mut own
        }
    };
    rows.extend(head_studies(prepared, options, r)?);
    Ok(rows)
}

pub const CSV_HEADER: &str = "study,case,method,pixels,sss_pixels,sss_samples,lod_skipped_pixels,\
sss_passes,scene_ms,sss_ms,frame_ms,none_frame_ms,frame_time_ratio,passes";

pub fn write_csv(path: &Path, rows: &[SkipRow]) -> Result<()> {
    let mut s = String::from(CSV_HEADER);
    s.push('\n');
    for r in rows {
        // Plain CSV: no field but the last (passes) may hold a comma.
        anyhow::ensure!(!r.case.contains(','), "skip case `{}` has a comma", r.case);
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.4},{}",
            r.study,
            r.case,
            r.method,
            r.pixels,
            r.sss_pixels,
            r.sss_samples,
            r.lod_skipped_pixels,
            r.sss_passes,
            r.scene_ms,
            r.sss_ms,
            r.frame_ms,
            r.none_frame_ms,
            r.frame_ms / r.none_frame_ms,
            r.passes
        );
    }
    crate::fsutil::write_atomic(path, s.as_bytes())
        .with_context(|| format!("writing {}", path.display()))
}

/// Reads a `skip.csv` written by [`write_csv`] back (for `--replot`).
pub fn read_csv(path: &Path) -> Result<Vec<SkipRow>> {
    const STUDIES: [&str; 4] = ["coverage", "strength", "transmission", "lod"];
    let methods: Vec<&'static str> = crate::settings::rendering::MethodId::all()
        .iter()
        .map(|m| m.id())
        .collect();
    super::csv::read(path, CSV_HEADER, 14)?
        .iter()
        .map(|r| {
            r.expect_fields(&[14])?;
            let num = |k: usize| r.num(k);
            Ok(SkipRow {
                study: r.one_of(0, &STUDIES)?,
                case: r.text(1).to_string(),
                method: r.one_of(2, &methods)?,
                pixels: num(3)? as u64,
                sss_pixels: num(4)? as u64,
                sss_samples: num(5)? as u64,
                lod_skipped_pixels: num(6)? as u64,
                sss_passes: num(7)? as usize,
                scene_ms: num(8)?,
                sss_ms: num(9)?,
                frame_ms: num(10)?,
                none_frame_ms: num(11)?,
                passes: r.text(13).to_string(),
            })
        })
        .collect()
}

pub fn markdown(s: &mut String, rows: &[SkipRow]) {
    let _ = writeln!(
        s,
        "## Skipped work\n\n| Study | Case | Method | SSS px (of all) | samples | LOD-skipped px | SSS passes | scene pass ms | SSS ms | frame ÷ none frame |\n| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |"
    );
    for r in rows {
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} ({:.1} %) | {} | {} | {} | {:.2} | {:.2} | {:.3} |",
            r.study,
            r.case,
            r.method,
            r.sss_pixels,
            100.0 * r.sss_pixels as f64 / r.pixels.max(1) as f64,
            r.sss_samples,
            r.lod_skipped_pixels,
            r.sss_passes,
            r.scene_ms,
            r.sss_ms,
            r.frame_ms / r.none_frame_ms
        );
    }
    let _ = writeln!(s);
}
