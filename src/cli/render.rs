//! `scatterlab render`: the head (or any mesh) rendered offscreen with the
//! look's SSS method, written as a PNG; optionally beside a second method
//! or as the difference from one.

use super::args::ModelArgs;
use super::built;
use super::view::{LookArgs, ViewArgs};
use crate::render::{GpuContext, ProfileInputs, RenderSettings, Renderer};
use crate::settings::rendering::MethodId;
use crate::settings::{Preset, RenderingSpec};
use anyhow::{Context, Result};
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[command(flatten)]
    pub look: LookArgs,
    /// Pixels (16–8192).
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub width: u32,
    /// Pixels (16–8192).
    #[arg(long, default_value_t = 512, value_parser = clap::value_parser!(u32).range(16..=8192))]
    pub height: u32,
    /// Turn off the per-pixel random rotation (reproducible images).
    #[arg(long)]
    pub deterministic: bool,
    #[arg(long, value_name = "FILE.png")]
    pub out: PathBuf,
    /// Also write per-frame statistics as JSON.
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    #[command(flatten)]
    pub view: ViewArgs,
    /// Render a second method and show both, split at --split.
    #[arg(long, value_enum)]
    pub compare: Option<MethodId>,
    /// Divider position for --compare (0–1 of the width).
    #[arg(long, default_value_t = 0.5)]
    pub split: f32,
    /// With --compare: write the |A − B| heat map instead of the split
    /// (against `reference` when no --compare is given).
    #[arg(long)]
    pub diff: bool,
    /// With --diff: the |ΔL*| (CIE lightness, 0–100) at the top of the
    /// colour bar, so that several heat maps share one scale; default: the
    /// frame's largest difference.
    #[arg(long, value_name = "ΔL*")]
    pub diff_scale: Option<f32>,
}

impl RenderArgs {
    pub fn run(self) -> Result<()> {
        let rendering = self.rendering()?;
        let inputs = self.profile_inputs(&rendering, rendering.method)?;
        // What the editor's render thread uses for a map (`app/viewport.rs`).
        let thickness_range_mm = rendering.thickness_remap_mm.1 as f32;
        let mesh = self.view.load_mesh(thickness_range_mm)?;
        let environment_sh = self.environment_sh()?;
        let orbit = self.view.orbit(|fov| mesh.framing_distance_m(fov))?;
        let settings = RenderSettings {
            deterministic: self.deterministic,
            mesh_lod: !self.look.no_lod,
            ..RenderSettings::for_look(&rendering, orbit, environment_sh, (self.width, self.height))
        };
        let mut renderer = Renderer::new(GpuContext::new_headless()?, &mesh)?;
        let (mut image, mut stats) = renderer.render(&inputs, &settings)?;
        for _ in 1..self.view.frames {
            (image, stats) = renderer.render(&inputs, &settings)?;
        }
        let diff_scale = self.compared(&mut renderer, &rendering, &settings, &mut image)?;
        self.write(&image, &stats)?;
        if let Some(scale) = diff_scale {
            println!(
                "difference heat map: top of the colour bar = |ΔL| {scale:.5} (linear luminance)"
            );
        }
        Ok(())
    }

    /// The look's rendering settings (the preset's, with the flags applied).
    fn rendering(&self) -> Result<RenderingSpec> {
        let base = match &self.model.preset {
            Some(path) => Preset::load(path)?.rendering,
            None => RenderingSpec::default(),
        };
        self.look.apply(base)
    }

    /// The profile's inputs for `method` (A's, or B's of a comparison: each
    /// side reads its own tables).
    fn profile_inputs(&self, rendering: &RenderingSpec, method: MethodId) -> Result<ProfileInputs> {
        // The shared model flags name the volume albedo `--albedo`; here that
        // flag is `--volume-albedo` (`--albedo` is the albedo map).
        let (spec, p) = built(&self.model).map_err(|e| {
            anyhow::anyhow!(format!("{e:#}").replace("--albedo", "--volume-albedo"))
        })?;
        let counts = (rendering.samples, rendering.taps);
        Ok(ProfileInputs::for_look(
            &spec,
            p.as_ref(),
            method,
            counts,
            &self.view.methods,
        )?)
    }

    /// The environment's irradiance SH, scaled by --environment-intensity.
    fn environment_sh(&self) -> Result<[[f32; 3]; 9]> {
        let intensity = self.view.environment_intensity;
        crate::model::check_range("environment_intensity", intensity as f64, 0.0, 1e4, "")?;
        let environment = match &self.view.environment {
            Some(path) => crate::render::environment::Environment::load(path)?,
            None => Default::default(),
        };
        Ok(environment
            .irradiance_sh()
            .map(|c| c.map(|v| v * intensity)))
    }

    /// With --compare or --diff: renders B and replaces `image` with the
    /// split or the heat map; returns the heat map's scale.
    fn compared(
        &self,
        renderer: &mut Renderer,
        rendering: &RenderingSpec,
        settings: &RenderSettings,
        image: &mut image::RgbaImage,
    ) -> Result<Option<f32>> {
        let other = match (self.compare, self.diff) {
            (Some(m), _) => m,
            (None, true) => MethodId::ground_truth(),
            (None, false) => return Ok(None),
        };
        crate::model::check_range("split", self.split as f64, 0.0, 1.0, "")?;
        let b_settings = RenderSettings {
            method: other,
            ..settings.clone()
        };
        let (b, _) = renderer.render(&self.profile_inputs(rendering, other)?, &b_settings)?;
        if !self.diff {
            *image = crate::render::compare::split_view(image, &b, self.split);
            return Ok(None);
        }
        if let Some(v) = self.diff_scale {
            crate::model::check_range("diff_scale", v as f64, 1e-6, 1e6, "")?;
        }
        let (d, scale) = crate::render::compare::difference_view(image, &b, self.diff_scale);
        *image = d;
        Ok(Some(scale))
    }

    /// Writes the PNG (and --stats) atomically and says what it wrote.
    fn write(&self, image: &image::RgbaImage, stats: &crate::render::FrameStats) -> Result<()> {
        let out = &self.out;
        let mut bytes = Vec::new();
        image.write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )?;
        crate::fsutil::write_atomic(out, &bytes)
            .with_context(|| format!("{}: cannot write", out.display()))?;
        if let Some(path) = &self.stats {
            crate::fsutil::write_atomic(path, serde_json::to_string_pretty(stats)?.as_bytes())
                .with_context(|| format!("{}: cannot write", path.display()))?;
        }
        let passes: Vec<_> = stats.passes.iter().map(|p| p.name).collect();
        println!(
            "wrote {} ({}×{}, {}, passes: {})",
            out.display(),
            self.width,
            self.height,
            stats.adapter,
            passes.join(", ")
        );
        Ok(())
    }
}
