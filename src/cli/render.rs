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
    /// The image: a PNG (tone-mapped sRGB), or with `.exr` the frame's
    /// linear float layers (the scattered and unscattered diffuse
    /// irradiance, albedo, specular and, as R, G, B, A, the radiance
    /// before exposure and tone mapping).
    #[arg(long, value_name = "FILE.png|FILE.exr")]
    pub out: PathBuf,
    /// Also write per-frame statistics as JSON (with the camera and key
    /// light in metres, `camera`).
    #[arg(long, value_name = "FILE.json")]
    pub stats: Option<PathBuf>,
    /// Also write the mesh as drawn, in metres in the renderer's world
    /// frame (y up), as an OBJ with its normals and groups skin, eyes and
    /// teeth: with --stats's `camera`, what another renderer needs to draw
    /// the same shot (tests/clients/blender_head.py). Needs --no-lod, and a
    /// mesh without colour, normal or mask maps (the OBJ carries neither).
    #[arg(long, value_name = "FILE.obj")]
    pub scene_obj: Option<PathBuf>,
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
            map_colour: self.view.map_colour,
            tone_map: self.view.tone_map,
            ..RenderSettings::for_look(&rendering, orbit, environment_sh, (self.width, self.height))
        };
        let exr = self.writes_exr()?;
        let n = self.view.methods.reference.supersample;
        if n > 1 && rendering.method != MethodId::ground_truth() {
            anyhow::bail!(
                "--supersample {n}: only the ground truth gathers sub-points of a pixel (use --method reference)"
            );
        }
        self.check_scene_obj(&mesh, &settings)?;
        let mut renderer = Renderer::new(GpuContext::new_headless()?, &mesh)?;
        for _ in 1..self.view.frames {
            renderer.render(&inputs, &settings)?;
        }
        // The last frame, with what it reads back: the layers for an EXR,
        // the scattered diffuse for the N × N check.
        let (mut image, layers, stats) = if exr || n > 1 {
            let (image, layers, stats) = renderer.render_layers(&inputs, &settings)?;
            (image, Some(layers), stats)
        } else {
            let (image, stats) = renderer.render(&inputs, &settings)?;
            (image, None, stats)
        };
        if let Some(path) = &self.scene_obj {
            crate::fsutil::write_atomic(path, mesh.to_obj_metres().as_bytes())
                .with_context(|| format!("{}: cannot write the mesh", path.display()))?;
        }
        if let (true, Some(layers)) = (exr, &layers) {
            let bytes = exr_layers(layers, settings.view.exposure, stats.method)
                .with_context(|| format!("{}: cannot encode the layers", self.out.display()))?;
            self.write_bytes(&bytes, "linear layers", &stats)?;
        }
        if let (true, Some(layers)) = (n > 1, &layers) {
            self.supersample_check(&mut renderer, &inputs, &settings, &layers.scattered)?;
        }
        if exr {
            return Ok(());
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

    /// `--scene-obj` writes the full mesh without its maps: refuse a frame
    /// that would draw something else (a coarser level of detail, a colour,
    /// normal or mask map), so that another renderer's shot is the same.
    fn check_scene_obj(&self, mesh: &crate::render::Mesh, settings: &RenderSettings) -> Result<()> {
        let Some(path) = &self.scene_obj else {
            return Ok(());
        };
        if settings.mesh_lod && mesh.coarse.is_some() {
            anyhow::bail!(
                "--scene-obj {}: the frame may draw the mesh's coarser level of detail, which the OBJ does not hold: add --no-lod",
                path.display()
            );
        }
        let (t, plain) = (
            &mesh.textures,
            crate::render::textures::MeshTextures::default(),
        );
        let maps: Vec<&str> = [
            (
                "colour",
                t.albedo != plain.albedo || t.albedo_mode != plain.albedo_mode,
            ),
            ("normal", t.normal != plain.normal),
            ("mask", t.mask != plain.mask),
        ]
        .into_iter()
        .filter_map(|(name, on)| on.then_some(name))
        .collect();
        if let Some((last, rest)) = maps.split_last() {
            let named = if rest.is_empty() {
                format!("a {last} map")
            } else {
                format!("{} and {last} maps", rest.join(", "))
            };
            anyhow::bail!(
                "--scene-obj {}: the mesh has {named}, which the OBJ does not carry: drop --albedo, --normal and --mask, and for the default head use --mesh assets/head/head.obj --metres-per-unit 0.1 (the same head without its maps)",
                path.display()
            );
        }
        Ok(())
    }

    /// The look's rendering settings (the preset's, with the flags applied).
    fn rendering(&self) -> Result<RenderingSpec> {
        let base = match &self.model.preset {
            Some(path) => {
                let r = Preset::load(path)?.rendering;
                if r.albedo_in_material && self.model.albedo.is_none() {
                    eprintln!(
                        "warning: {}: the look's engine keeps the albedo in the material (HDRP), so its albedo is 1 and the head draws white; give the material's with --volume-albedo R,G,B",
                        path.display()
                    );
                }
                r
            }
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

    /// The ground truth's N × N check on this view, as the bench's floor
    /// takes it (`bench::floor::measure`): the truth at one point a pixel
    /// against the N × N one just rendered (`fine`, each sub-point with its
    /// own footprint), over the SSS pixels whose footprint is one surface.
    fn supersample_check(
        &self,
        renderer: &mut Renderer,
        inputs: &ProfileInputs,
        settings: &RenderSettings,
        fine: &[[f32; 4]],
    ) -> Result<()> {
        use crate::bench::metrics;
        let n = inputs.options.reference.supersample;
        let mut plain_inputs = inputs.clone();
        plain_inputs.options.reference.supersample = 1;
        let (_, plain, _) = renderer
            .render_with_diffuse(&plain_inputs, settings)
            .context("the ground truth at one point a pixel")?;
        let sss = metrics::sss_mask(&plain);
        let one_surface: Vec<bool> = sss
            .iter()
            .zip(fine)
            .map(|(m, f)| *m && f[..3].iter().all(|v| v.is_finite()))
            .collect();
        let count = |m: &[bool]| m.iter().filter(|v| **v).count();
        let (n_sss, n_one) = (count(&sss), count(&one_surface));
        if n_one == 0 {
            anyhow::bail!(
                "--supersample {n}: no SSS pixel on this view has one surface under it ({n_sss} SSS pixels)"
            );
        }
        println!(
            "{n}×{n} check: the ground truth at one point a pixel is {:.5} (relative RMSE) from {n}×{n} points a pixel, over {n_one} SSS pixels; {:.2} % of the {n_sss} SSS pixels are not one surface under the pixel and are left out",
            metrics::relative_rmse(fine, &plain, &one_surface),
            100.0 * (1.0 - n_one as f64 / n_sss as f64)
        );
        Ok(())
    }

    /// Whether `--out` names an OpenEXR file: its layers are one method's,
    /// so `--compare` and `--diff` (pictures of two) write PNGs only.
    fn writes_exr(&self) -> Result<bool> {
        let exr = self
            .out
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
        if exr && (self.compare.is_some() || self.diff) {
            anyhow::bail!(
                "--out {}: an EXR holds one method's linear layers; --compare and --diff write a PNG (render each method to its own .exr to compare them)",
                self.out.display()
            );
        }
        Ok(exr)
    }

    /// Writes the PNG (and --stats) atomically and says what it wrote.
    fn write(&self, image: &image::RgbaImage, stats: &crate::render::FrameStats) -> Result<()> {
        let mut bytes = Vec::new();
        image.write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )?;
        self.write_bytes(&bytes, "", stats)
    }

    /// Writes `bytes` to --out (and --stats) atomically and says what it
    /// wrote.
    fn write_bytes(
        &self,
        bytes: &[u8],
        what: &str,
        stats: &crate::render::FrameStats,
    ) -> Result<()> {
        let out = &self.out;
        crate::fsutil::write_atomic(out, bytes)
            .with_context(|| format!("{}: cannot write", out.display()))?;
        if let Some(path) = &self.stats {
            crate::fsutil::write_atomic(path, serde_json::to_string_pretty(stats)?.as_bytes())
                .with_context(|| format!("{}: cannot write", path.display()))?;
        }
        let passes: Vec<_> = stats.passes.iter().map(|p| p.name).collect();
        let what = if what.is_empty() {
            String::new()
        } else {
            format!("{what}, ")
        };
        println!(
            "wrote {} ({}×{}, {what}{}, {}, passes: {})",
            out.display(),
            self.width,
            self.height,
            stats.adapter,
            stats.driver,
            passes.join(", ")
        );
        if let Some(advice) = &stats.driver_advice {
            eprintln!("note: {advice}");
        }
        Ok(())
    }
}

/// The frame's layers as one OpenEXR part of 32-bit float channels, named
/// as compositors name layers (`scattered.R` …), row-major with y down:
/// - `R`, `G`, `B`, `A`: the radiance the composite pass tone-maps
///   ([`FrameLayers::radiance`]), alpha the coverage. The PNG of the same
///   frame is sRGB(ACES(exposure × RGB)) with Narkowicz's 2015 fit of the
///   ACES curve (`composite.wgsl`); the background, 0 here, is grey there;
/// - `scattered.*`: the scattered diffuse irradiance (what the bench
///   compares), alpha the SSS mask;
/// - `unscattered.*`: the scene's diffuse irradiance × albedo^pre, before
///   any SSS pass (for `preintegrated`, lit in the scene pass, its
///   scattered light), alpha the SSS mask;
/// - `albedo.*`: albedo^post, alpha the coverage;
/// - `specular.*`: the specular radiance.
///
/// The header holds the exposure (`exposure`, a float) and the method.
fn exr_layers(layers: &crate::render::FrameLayers, exposure: f32, method: &str) -> Result<Vec<u8>> {
    use exr::prelude::*;
    let (w, h) = (layers.width as usize, layers.height as usize);
    let radiance = layers.radiance();
    let mut channels: Vec<AnyChannel<FlatSamples>> = Vec::new();
    let mut add = |prefix: &str, names: &[&str], get: &dyn Fn(usize, usize) -> f32| {
        for (k, n) in names.iter().enumerate() {
            let name = if prefix.is_empty() {
                n.to_string()
            } else {
                format!("{prefix}.{n}")
            };
            let samples = (0..w * h).map(|i| get(i, k)).collect();
            channels.push(AnyChannel::new(name.as_str(), FlatSamples::F32(samples)));
        }
    };
    let rgba = ["R", "G", "B", "A"];
    add("", &rgba, &|i, k| radiance[i][k]);
    add("scattered", &rgba, &|i, k| layers.scattered[i][k]);
    add("unscattered", &rgba, &|i, k| layers.unscattered[i][k]);
    add("albedo", &rgba, &|i, k| layers.albedo[i][k]);
    add("specular", &rgba[..3], &|i, k| layers.specular[i][k]);
    let mut attributes = LayerAttributes::named("");
    attributes.comments = Some(Text::from(
        "scatterlab render: linear layers before exposure and tone mapping; the PNG is sRGB(ACES(exposure * RGB)) (Narkowicz 2015) on the mesh",
    ));
    attributes.software_name = Some(Text::from(
        format!("scatterlab {}", env!("CARGO_PKG_VERSION")).as_str(),
    ));
    attributes
        .other
        .insert(Text::from("exposure"), AttributeValue::F32(exposure));
    attributes.other.insert(
        Text::from("method"),
        AttributeValue::Text(Text::from(method)),
    );
    let layer = Layer::new(
        (w, h),
        attributes,
        Encoding::FAST_LOSSLESS,
        AnyChannels::sort(channels.into()),
    );
    let mut cursor = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer).write().to_buffered(&mut cursor)?;
    Ok(cursor.into_inner())
}
