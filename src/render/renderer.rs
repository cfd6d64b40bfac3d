//! The frame, as a table of contents: shadow → scene → classify → the
//! method's SSS passes (one file each under `sss/`) → [accumulate →]
//! composite → readback, all offscreen. Each fixed pass lives in
//! `passes/`, the targets in `targets.rs`, the camera and light in
//! `framing.rs`.

use super::context::{GpuContext, GpuError};
use super::frame::FrameEncoder;
use super::framing::Framing;
use super::gpu_types::SssUniforms;
use super::layers::{read_frame, sss_counts, FrameLayers, Want};
use super::mesh::Mesh;
use super::passes::classify::ClassifyPass;
use super::passes::composite::CompositePass;
use super::passes::scene::{ScenePass, SurfaceMaps};
use super::passes::shadow::ShadowPass;
use super::passes::{counter_buffers, pick_lod, MeshLod};
pub use super::pipelines::shader_sources;
pub use super::readback::{f32_to_half, half_to_f32};
pub use super::settings::{
    FrameStats, IrradiancePattern, Method, RenderSettings, Specular, TexturingMode, Transmission,
};
use super::sss::{self, ProfileGpu, ProfileInputs, SssFrame, SssPipelines};
use super::targets::{HdrTarget, Targets};
use super::textures::MeshTextures;
use super::timing::{sss_gpu_ms, PassTimer};
use glam::Vec3;

/// Per-profile resources and the scene bind group that refers to them.
struct ProfileBinding {
    gpu: ProfileGpu,
    scene_bg: wgpu::BindGroup,
}

/// Everything the scene pass's targets depend on: its uniforms (camera,
/// light, look, method's scene terms), the size, the level of detail and
/// the profile on the GPU.
#[derive(Debug, Clone, PartialEq)]
struct SceneKey {
    uniforms: Vec<u8>,
    size: (u32, u32),
    lod: usize,
    profile: u64,
}

/// Owns the device, the mesh and the passes.
pub struct Renderer {
    ctx: GpuContext,
    /// Levels of detail, finest first.
    lods: Vec<MeshLod>,
    framing: Framing,
    shadow: ShadowPass,
    scene: ScenePass,
    classify: ClassifyPass,
    sss: SssPipelines,
    composite: CompositePass,
    /// An environment map is set to draw behind the head.
    has_background: bool,
    targets: Option<Targets>,
    profile: Option<ProfileBinding>,
    /// What the scene, depth, stencil and classify targets were last drawn
    /// with, and the SSS pixels counted: a progressive frame past the first
    /// with the same key reuses them.
    scene_key: Option<(SceneKey, u64)>,
    /// The finest level of detail on the CPU, with its maps: the surface
    /// the ground truth (`reference`) integrates over.
    mesh: Mesh,
    /// What the methods keep from frame to frame (the ground truth's
    /// cloud, kept while only the view changes).
    sss_state: sss::State,
    /// Set to stop a ground truth under way (the editor's newer request;
    /// [`Renderer::cancel_with`]).
    cancel: std::sync::Arc<std::sync::atomic::AtomicBool>,
    /// Where the last frame's scattered light was left for the composite
    /// (a running mean, or one of the HDR targets), and the frame's size:
    /// [`Renderer::read_last_radiance`] reads it back.
    last_shown: Option<(Shown, (u32, u32))>,
}

/// The texture a frame's composite read its scattered light from.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Shown {
    /// Progressive refinement's running mean of this slot.
    Mean(usize),
    Target(HdrTarget),
}

impl Shown {
    /// A frame's: the running mean where it refines, else its target.
    fn of(progressive: Option<super::Progressive>, target: HdrTarget) -> Self {
        progressive.map_or(Shown::Target(target), |p| Shown::Mean(p.slot))
    }
}

impl Renderer {
    pub fn new(ctx: GpuContext, mesh: &Mesh) -> Result<Self, GpuError> {
        let maps = SurfaceMaps::upload(&ctx, &mesh.textures)?;
        let (shadow, scene, classify, sss, composite) = ctx.checked("pipeline creation", || {
            let device = &ctx.device;
            let sources: std::collections::HashMap<_, _> = shader_sources().into_iter().collect();
            let module = |name: &'static str| {
                device.create_shader_module(wgpu::ShaderModuleDescriptor {
                    label: Some(name),
                    source: wgpu::ShaderSource::Wgsl(sources[name].as_str().into()),
                })
            };
            let scene_module = module("scene");
            let scene = ScenePass::new(&ctx, &scene_module, maps);
            (
                ShadowPass::new(device, &scene_module, &scene.uniforms),
                scene,
                ClassifyPass::new(device, &module("classify")),
                SssPipelines::new(device, &module),
                CompositePass::new(device, &ctx.queue, &module("composite")),
            )
        })?;
        let mut lods = vec![MeshLod::new(&ctx.device, mesh)];
        if let Some(coarse) = &mesh.coarse {
            lods.push(MeshLod::new(&ctx.device, coarse));
        }
        let (lo, hi) = mesh.bounds();
        Ok(Self {
            lods,
            framing: Framing {
                centre: Vec3::from(mesh.focus),
                radius: 0.5 * (hi - lo).length(),
                metres_per_unit: mesh.metres_per_unit,
                eyes: mesh.eyeballs(),
            },
            shadow,
            scene,
            classify,
            sss,
            composite,
            has_background: false,
            targets: None,
            profile: None,
            scene_key: None,
            mesh: Mesh {
                coarse: None,
                ..mesh.clone()
            },
            sss_state: Default::default(),
            cancel: Default::default(),
            last_shown: None,
            ctx,
        })
    }

    pub fn adapter_name(&self) -> String {
        format!(
            "{} ({:?})",
            self.ctx.adapter_info.name, self.ctx.adapter_info.backend
        )
    }

    /// Why the GPU device under this renderer was lost, if it was
    /// ([`GpuContext::lost`]): make a new renderer.
    pub fn device_lost(&self) -> Option<String> {
        self.ctx.lost()
    }

    /// The device this renderer draws with (tests of device loss).
    #[doc(hidden)]
    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    fn ensure_targets(&mut self, w: u32, h: u32) {
        if self.targets.as_ref().is_some_and(|t| t.size == (w, h)) {
            return;
        }
        self.targets = Some(Targets::new(&self.ctx, (w, h)));
        self.scene_key = None;
    }

    /// Shares `flag` as this renderer's cancel: while it is set a ground
    /// truth stops at its next chunk of pixels and its frame fails with
    /// [`GpuError::Cancelled`]. Its owner clears it (the editor's render
    /// thread when it takes the newest request; the viewport sets it with
    /// each request it sends). Clearing it at a frame's start instead lost
    /// the cancel of requests already waiting.
    pub fn cancel_with(&mut self, flag: std::sync::Arc<std::sync::atomic::AtomicBool>) {
        self.cancel = flag;
    }

    /// Draws `map` behind the head where a frame's settings ask for a
    /// background (`None`: none to draw).
    pub fn set_background(&mut self, map: Option<&super::environment::BackgroundMap>) {
        self.composite
            .set_background(&self.ctx.device, &self.ctx.queue, map);
        self.has_background = map.is_some();
    }

    /// Replaces the mesh's surface maps (the editor draws the default head
    /// with neutral maps first and swaps in its baked maps when they are
    /// ready). The next frame rebuilds the scene's bind group.
    pub fn set_surface_maps(&mut self, maps: &MeshTextures) -> Result<(), GpuError> {
        self.scene.maps = SurfaceMaps::upload(&self.ctx, maps)?;
        self.profile = None;
        self.scene_key = None;
        self.mesh.textures = std::sync::Arc::new(maps.clone());
        self.sss_state = Default::default();
        Ok(())
    }

    /// The last frame's scene-linear radiance, before exposure and the
    /// display transform, read back from the targets it left (nothing is
    /// drawn again): [`FrameLayers::radiance`], alpha the coverage. The
    /// editor reads it once a view has settled, for its pixel probe and
    /// histogram. Fails when no frame was drawn, or the targets have been
    /// made anew since.
    pub fn read_last_radiance(&mut self) -> Result<super::layers::SceneLinear, GpuError> {
        let none = || GpuError::Readback("no frame drawn to read the radiance of".into());
        let (shown, size) = self.last_shown.ok_or_else(none)?;
        let t = self
            .targets
            .as_ref()
            .filter(|t| t.size == size)
            .ok_or_else(none)?;
        let texture = match shown {
            Shown::Mean(slot) => &t.accum[slot].as_ref().ok_or_else(none)?.0,
            Shown::Target(target) => t.texture(target),
        };
        let encoder = self
            .ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("read radiance"),
            });
        let (_, layers) = read_frame(&self.ctx, encoder, t, texture, Want::Layers, size)?;
        let layers = layers.ok_or_else(none)?;
        Ok(super::layers::SceneLinear {
            width: size.0,
            height: size.1,
            radiance: layers.radiance(),
            specular: layers.specular,
        })
    }

    /// Uploads the profile's tables, patterns and kernels unless the same
    /// inputs are already on the GPU. Returns whether it uploaded.
    fn ensure_profile(&mut self, inputs: &ProfileInputs) -> bool {
        let key = inputs.fingerprint();
        if self.profile.as_ref().is_some_and(|p| p.gpu.key == key) {
            return false;
        }
        let gpu = ProfileGpu::new(&self.ctx.device, &self.ctx.queue, inputs);
        let scene_bg = self.scene.bind(
            &self.ctx.device,
            &gpu.shared,
            sss::scene_tables(&gpu.methods),
            &self.shadow,
        );
        self.profile = Some(ProfileBinding { gpu, scene_bg });
        true
    }

    /// Renders one frame and reads it back as 8-bit sRGB RGBA.
    pub fn render(
        &mut self,
        inputs: &ProfileInputs,
        s: &RenderSettings,
    ) -> Result<(image::RgbaImage, FrameStats), GpuError> {
        self.render_inner(inputs, s, false)
            .map(|(img, _, st)| (img, st))
    }

    /// As [`Renderer::render`], also reading back the scattered diffuse
    /// irradiance (linear HDR, before albedo and tonemapping), row-major RGBA:
    /// under progressive refinement, the running mean.
    pub fn render_with_diffuse(
        &mut self,
        inputs: &ProfileInputs,
        s: &RenderSettings,
    ) -> Result<(image::RgbaImage, Vec<[f32; 4]>, FrameStats), GpuError> {
        self.render_inner(inputs, s, true)
    }

    /// As [`Renderer::render`], also reading back every linear layer the
    /// composite pass combined ([`FrameLayers`]; `render --out FILE.exr`).
    pub fn render_layers(
        &mut self,
        inputs: &ProfileInputs,
        s: &RenderSettings,
    ) -> Result<(image::RgbaImage, FrameLayers, FrameStats), GpuError> {
        let (image, layers, stats) = self.render_read(inputs, s, Want::Layers)?;
        let layers = layers.ok_or_else(|| GpuError::Readback("the frame's layers".into()))?;
        Ok((image, layers, stats))
    }

    fn render_inner(
        &mut self,
        inputs: &ProfileInputs,
        s: &RenderSettings,
        want_diffuse: bool,
    ) -> Result<(image::RgbaImage, Vec<[f32; 4]>, FrameStats), GpuError> {
        let want = if want_diffuse {
            Want::Diffuse
        } else {
            Want::Image
        };
        let (image, layers, stats) = self.render_read(inputs, s, want)?;
        Ok((
            image,
            layers.map(|l| l.scattered).unwrap_or_default(),
            stats,
        ))
    }

    fn render_read(
        &mut self,
        inputs: &ProfileInputs,
        s: &RenderSettings,
        want: Want,
    ) -> Result<(image::RgbaImage, Option<FrameLayers>, FrameStats), GpuError> {
        if let Some(missing) = inputs.missing_for(s.method) {
            return Err(GpuError::InputsLack {
                method: s.method.id(),
                missing,
            });
        }
        self.ensure_targets(s.width, s.height);
        if let Some(p) = s.progressive {
            if p.slot >= 2 {
                return Err(GpuError::Readback(format!(
                    "progressive slot {} (there are two: A and B)",
                    p.slot
                )));
            }
            if let Some(t) = self.targets.as_mut() {
                t.ensure_accumulator(&self.ctx.device, p.slot);
            }
        }
        // Any validation error in the frame is reported, never panicked on.
        let scope = self
            .ctx
            .device
            .push_error_scope(wgpu::ErrorFilter::Validation);
        let uploaded = self.ensure_profile(inputs);
        let result = self.encode_and_read(inputs, s, want);
        let error = pollster::block_on(scope.pop());
        if error.is_some() || result.is_err() {
            // The shadow map or the profile may be incomplete: redo them.
            self.shadow.invalidate();
            self.scene_key = None;
            self.profile = None;
        }
        match error {
            Some(e) => Err(GpuError::Validation {
                stage: "frame",
                message: e.to_string(),
            }),
            None => result.map(|(img, diffuse, mut stats)| {
                stats.profile_uploaded = uploaded;
                (img, diffuse, stats)
            }),
        }
    }

    /// The SSS pixels counted by the last frame if its scene, depth,
    /// stencil and classification can be reused: a progressive frame past
    /// the first changes only the rotations, and a frame of the ground
    /// truth's tiles only the tiles gathered (the key holds everything the
    /// scene pass depends on).
    fn reusable_scene(&self, key: &SceneKey, s: &RenderSettings) -> Option<u64> {
        let later = s.progressive.is_some_and(|p| p.frame > 0) || s.truth_tiles.is_some();
        match &self.scene_key {
            Some((last, pixels)) if later && last == key => Some(*pixels),
            _ => None,
        }
    }

    /// Which of the mesh's levels of detail a frame draws: the finest for
    /// the ground truth, which integrates the finest surface, or with the
    /// mesh LOD off.
    fn mesh_lod_for(&self, s: &RenderSettings) -> usize {
        if s.method.sss().ground_truth || !s.mesh_lod {
            0
        } else {
            pick_lod(&self.lods, &self.framing, s)
        }
    }

    /// Records and submits the frame's passes, then reads it back.
    fn encode_and_read(
        &mut self,
        inputs: &ProfileInputs,
        s: &RenderSettings,
        want: Want,
    ) -> Result<(image::RgbaImage, Option<FrameLayers>, FrameStats), GpuError> {
        let (Some(t), Some(profile)) = (self.targets.as_ref(), self.profile.as_ref()) else {
            return Err(GpuError::Readback("no targets".into()));
        };
        let ctx = &self.ctx;
        let camera = self.framing.camera_and_light(s);
        let mut scene_u = self
            .scene
            .uniforms(&self.framing, &camera, &inputs.shared, s);
        sss::scene_terms(inputs, s.method, &mut scene_u);
        let lod_index = self.mesh_lod_for(s);
        let lod = &self.lods[lod_index];
        let scene_key = SceneKey {
            uniforms: bytemuck::bytes_of(&scene_u).to_vec(),
            size: (s.width, s.height),
            lod: lod_index,
            profile: profile.gpu.key,
        };
        let reused_pixels = self.reusable_scene(&scene_key, s);
        ctx.queue
            .write_buffer(&self.scene.uniforms, 0, bytemuck::bytes_of(&scene_u));
        let mut f = FrameEncoder::new(&ctx.device, PassTimer::new(ctx));
        let reuse = reused_pixels.is_some();
        self.shadow
            .encode(&mut f, lod, scene_u.light_clip_from_world, lod_index, reuse);
        if !reuse {
            self.scene.encode(&mut f, t, lod, &profile.scene_bg);
        }
        // Classify: count SSS pixels on the GPU; with none on screen, or a
        // profile that does not scatter (strength 0), no SSS pass runs.
        f.stencil = Some(&t.depth_stencil);
        let sss_pixels = match reused_pixels {
            Some(n) => n,
            None => self.classify.count(ctx, &mut f, t)?,
        };
        let method = if sss_pixels > 0 && inputs.shared.scatters {
            s.method
        } else {
            Method::baseline()
        };
        // Samples taken, pixels convolved, pixels skipped by the LOD.
        let (counters, counters_read) = counter_buffers(&ctx.device, "sss counters");
        let io = SssFrame {
            targets: t,
            profile: &profile.gpu,
            inputs,
            sss_pixels,
            uniforms: sss_uniforms(s, self.framing.metres_per_unit),
            counters: &counters,
            lod: s.lod,
            deterministic: s.deterministic,
            ctx,
            mesh: &self.mesh,
            shadow: &self.shadow,
            scene: &scene_u,
            view_from_world: camera.view,
            settings: s,
            cancel: &self.cancel,
            scene_bind: &profile.scene_bg,
            scene_layout: self.scene.layout(),
            drawn: lod,
        };
        let scattered = (method.sss().encode)(&mut f, &self.sss, &io, &mut self.sss_state)?;
        let truth = scattered.truth.clone().unwrap_or_default();
        let reference_cpu_ms = scattered.truth.as_ref().map(|t| t.cpu_ms);
        f.encoder
            .copy_buffer_to_buffer(&counters, 0, &counters_read, 0, 16);
        let (exposure, target) = (s.view.exposure, scattered.target);
        let background = background_terms(s, self.has_background, &camera);
        let shown = self.composite.finish(
            &mut f,
            t,
            s.progressive,
            (exposure, s.tone_map, background),
            target,
        )?;
        let FrameEncoder {
            mut encoder,
            mut timer,
            ..
        } = f;
        timer.resolve(&mut encoder);
        let (image, diffuse) = read_frame(ctx, encoder, t, shown, want, (s.width, s.height))?;
        self.last_shown = Some((Shown::of(s.progressive, target), (s.width, s.height)));
        let (sss_samples, lod_skipped_pixels) =
            sss_counts(ctx, &scattered, &counters_read, sss_pixels, &mut timer);
        let passes = timer.finish(ctx);
        let stats = FrameStats {
            method: s.method.id(),
            sss_gpu_ms: sss_gpu_ms(&passes),
            passes,
            samples_per_sss_pixel: scattered.samples_per_pixel,
            sss_pixels,
            sss_samples,
            lod_skipped_pixels,
            reference_cpu_ms,
            reference_build_ms: truth.build_ms,
            reference_gpu_unfinished: truth.gpu_unfinished,
            truth_tiles: truth.tiles,
            profile_uploaded: false,
            scene_reused: reuse,
            target_bytes: t.bytes,
            triangles: lod.index_count as u64 / 3,
            width: s.width,
            height: s.height,
            camera: self.framing.record(&camera, s),
            adapter: self.adapter_name(),
            driver: super::driver::describe(&self.ctx.adapter_info),
            driver_advice: super::driver::advice(&self.ctx.adapter_info),
        };
        self.scene_key = Some((scene_key, sss_pixels));
        Ok((image, diffuse, stats))
    }
}

/// The uniforms every SSS pass shares; each pass sets its sample count
/// ([`SssFrame::uniforms`]) and its own fields (`burley` its table's
/// reach, `separable` its direction, follow-surface term and axis
/// rotation).
fn sss_uniforms(s: &RenderSettings, metres_per_unit: f32) -> SssUniforms {
    SssUniforms {
        size: [s.width as f32, s.height as f32],
        pixels_per_unit_at_depth_1: s.height as f32 / (2.0 * (0.5 * s.view.fov_y_rad).tan()),
        mm_per_unit: metres_per_unit * 1000.0,
        rotation_offset_turns: s.progressive.map_or(0.0, |p| p.rotation_offset()),
        deterministic: s.deterministic as u32,
        sample_count: 0,
        lut_radius_mm: 0.0,
        lut_entries: 0,
        follow_surface: 0.0,
        direction: [0.0; 2],
        rotate_axis: 0,
        pad0: 0,
        pad1: 0,
        pad2: 0,
        weight: [1.0; 4],
    }
}

/// What the composite draws behind the head: the HDR map where asked and
/// loaded, turned and blurred, seen through the camera's rotation alone.
fn background_terms(
    s: &RenderSettings,
    has_background: bool,
    camera: &super::framing::CameraLight,
) -> super::passes::composite::BackgroundTerms {
    let rotation_only = {
        let mut v = camera.view;
        v.w_axis = glam::Vec4::W;
        v
    };
    super::passes::composite::BackgroundTerms {
        on: s.background.is_some() && has_background,
        blur: s.background.map_or(0.0, |b| b.blur),
        turn_rad: s.background.map_or(0.0, |b| b.turn_rad),
        intensity: s.background.map_or(1.0, |b| b.intensity),
        direction_from_clip: (camera.projection * rotation_only).inverse(),
    }
}
