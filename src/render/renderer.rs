//! The frame: shadow → scene → classify → the method's SSS passes (one
//! file each under `sss/`) → composite, all offscreen.

use super::context::{GpuContext, GpuError};
use super::frame::{buf, color_attachment, tex, FrameEncoder};
use super::gpu_types::{CompositeUniforms, SceneUniforms, SssUniforms};
use super::inputs::LUT_SIZE;
pub use super::inputs::{gaussian_taps, gaussian_terms, ProfileInputs};
use super::mesh::Mesh;
pub use super::pipelines::shader_sources;
use super::pipelines::{
    buffer_entry, fullscreen_pipeline, scene_pipeline, shadow_pipeline, texture_entry, Output,
    Stencil, ALBEDO, DEPTH_STENCIL, HDR, OUTPUT,
};
use super::profile_gpu::ProfileGpu;
pub use super::readback::{f32_to_half, half_to_f32};
use super::readback::{read_u32x4, readback};
pub use super::settings::{
    BurleySampling, FrameStats, IrradiancePattern, Method, RenderSettings, Specular, TexturingMode,
    Transmission,
};
use super::sss::{self, SssFrame, SssPipelines};
use super::textures::{self, AlbedoMode, MeshTextures, RoughnessMode, TextureImage};
use super::timing::PassTimer;
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

const SHADOW_SIZE: u32 = 1024;

/// The HDR targets a method reads from and writes to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum HdrTarget {
    /// The scene's diffuse irradiance and SSS mask.
    Diffuse,
    Ping,
    /// `separable`'s second pass; the sum of the Gaussians for `gaussians`.
    Pong,
}

pub(super) struct Targets {
    pub size: (u32, u32),
    /// Diffuse, ping, pong (indexed by [`HdrTarget`]).
    hdr: [(wgpu::Texture, wgpu::TextureView); 3],
    pub specular: wgpu::TextureView,
    /// albedo^post and coverage.
    pub albedo: wgpu::TextureView,
    pub linear_depth: wgpu::TextureView,
    linear_depth_texture: wgpu::Texture,
    /// Depth buffer; its stencil marks the SSS pixels.
    depth_stencil: wgpu::TextureView,
    output: wgpu::Texture,
    /// Progressive refinement's running means (A and B), made on first use.
    accum: [Option<(wgpu::Texture, wgpu::TextureView)>; 2],
    /// Bytes of GPU memory these targets take.
    pub bytes: u64,
}

impl Targets {
    pub fn view(&self, t: HdrTarget) -> &wgpu::TextureView {
        &self.hdr[t as usize].1
    }

    fn texture(&self, t: HdrTarget) -> &wgpu::Texture {
        &self.hdr[t as usize].0
    }
}

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

/// Owns the device, the mesh and the pipelines.
pub struct Renderer {
    ctx: GpuContext,
    /// Levels of detail, finest first.
    lods: Vec<MeshLod>,
    mesh_centre: Vec3,
    metres_per_unit: f32,
    mesh_radius: f32,
    /// The eyeballs ([`Mesh::eyeballs`]).
    eyes: [[f32; 4]; 2],
    scene_layout: wgpu::BindGroupLayout,
    scene_pipeline: wgpu::RenderPipeline,
    scene_uniforms: wgpu::Buffer,
    shadow_pipeline: wgpu::RenderPipeline,
    shadow_bg: wgpu::BindGroup,
    shadow_map: wgpu::TextureView,
    /// The shadow map's texture (read back by `reference`).
    shadow_texture: wgpu::Texture,
    shadow_sampler: wgpu::Sampler,
    lut_sampler: wgpu::Sampler,
    surface_sampler: wgpu::Sampler,
    /// Albedo, normal, roughness, mask and thickness maps of the mesh.
    surface_maps: [wgpu::TextureView; 5],
    /// `SceneUniforms::surface` for these maps (detail strength in w).
    surface_modes: [f32; 4],
    sss: SssPipelines,
    composite_layout: wgpu::BindGroupLayout,
    composite_pipeline: wgpu::RenderPipeline,
    /// Progressive refinement: a method's output into a running mean.
    accumulate_layout: wgpu::BindGroupLayout,
    accumulate_pipeline: wgpu::RenderPipeline,
    classify_layout: wgpu::BindGroupLayout,
    classify_pipeline: wgpu::RenderPipeline,
    targets: Option<Targets>,
    profile: Option<ProfileBinding>,
    /// The light transform the shadow map was last drawn with: the map
    /// depends only on it and the mesh, so an unchanged light skips the pass.
    shadow_key: Option<([[f32; 4]; 4], usize)>,
    /// What the scene, depth, stencil and classify targets were last drawn
    /// with, and the SSS pixels counted: a progressive frame past the first
    /// with the same key reuses them.
    scene_key: Option<(SceneKey, u64)>,
    /// The finest level of detail on the CPU, with its maps: the surface
    /// the ground truth (`reference`) integrates over.
    mesh: Mesh,
    /// The ground truth's cloud, kept while only the view changes.
    reference_cache: Option<sss::reference::Cache>,
}

impl Renderer {
    pub fn new(ctx: GpuContext, mesh: &Mesh) -> Result<Self, GpuError> {
        let device = &ctx.device;
        let sources: std::collections::HashMap<_, _> = shader_sources().into_iter().collect();
        let module = |name: &'static str| {
            device.create_shader_module(wgpu::ShaderModuleDescriptor {
                label: Some(name),
                source: wgpu::ShaderSource::Wgsl(sources[name].as_str().into()),
            })
        };
        let frag = wgpu::ShaderStages::FRAGMENT;
        let uniform = wgpu::BufferBindingType::Uniform;
        let storage = wgpu::BufferBindingType::Storage { read_only: true };
        let texture = |binding, sample_type| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: frag,
            ty: wgpu::BindingType::Texture {
                sample_type,
                view_dimension: wgpu::TextureViewDimension::D2,
                multisampled: false,
            },
            count: None,
        };
        let sampler = |binding, ty| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: frag,
            ty: wgpu::BindingType::Sampler(ty),
            count: None,
        };
        let filterable = wgpu::TextureSampleType::Float { filterable: true };
        let built = ctx.checked("pipeline creation", || {
            let uniform0 = buffer_entry(0, uniform, wgpu::ShaderStages::VERTEX_FRAGMENT);
            let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("scene"),
                entries: &[
                    uniform0,
                    texture(1, wgpu::TextureSampleType::Depth),
                    sampler(2, wgpu::SamplerBindingType::Comparison),
                    texture(3, filterable),
                    sampler(4, wgpu::SamplerBindingType::Filtering),
                    buffer_entry(5, storage, frag),
                    texture(6, filterable),
                    texture(7, filterable),
                    texture(8, filterable),
                    texture(9, filterable),
                    texture(10, filterable),
                    sampler(11, wgpu::SamplerBindingType::Filtering),
                    texture(12, filterable),
                    // The same shadow map read raw (the thick-object
                    // thickness): GLSL cannot textureLoad a depth texture
                    // bound for comparison, and WebGPU allows a depth view
                    // as an unfilterable float texture.
                    texture(13, wgpu::TextureSampleType::Float { filterable: false }),
                ],
            });
            let shadow_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("shadow"),
                entries: &[uniform0],
            });
            let composite_layout =
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("composite"),
                    entries: &[
                        buffer_entry(0, uniform, frag),
                        texture_entry(1),
                        texture_entry(2),
                        texture_entry(3),
                        texture_entry(4),
                    ],
                });
            let accumulate_layout =
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("accumulate"),
                    entries: &[texture_entry(1)],
                });
            let classify_layout =
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("classify"),
                    entries: &[
                        texture_entry(0),
                        buffer_entry(
                            1,
                            wgpu::BufferBindingType::Storage { read_only: false },
                            frag,
                        ),
                    ],
                });
            let classify_pipeline = fullscreen_pipeline(
                device,
                &module("classify"),
                "fs_classify",
                &classify_layout,
                Output::Nothing,
                Stencil::Mark,
            );
            let scene_module = module("scene");
            Pipelines {
                scene_pipeline: scene_pipeline(
                    device,
                    &scene_module,
                    &scene_layout,
                    ctx.specular_format,
                    ctx.linear_depth_format,
                ),
                shadow_pipeline: shadow_pipeline(device, &scene_module, &shadow_layout),
                composite_pipeline: fullscreen_pipeline(
                    device,
                    &module("composite"),
                    "fs_composite",
                    &composite_layout,
                    Output::Replace(OUTPUT),
                    Stencil::None,
                ),
                accumulate_pipeline: fullscreen_pipeline(
                    device,
                    &module("composite"),
                    "fs_accumulate",
                    &accumulate_layout,
                    Output::Mean(HDR),
                    Stencil::None,
                ),
                accumulate_layout,
                sss: SssPipelines::new(device, &module),
                scene_layout,
                shadow_layout,
                composite_layout,
                classify_layout,
                classify_pipeline,
            }
        })?;
        let shadow_texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("shadow map"),
            size: wgpu::Extent3d {
                width: SHADOW_SIZE,
                height: SHADOW_SIZE,
                depth_or_array_layers: 1,
            },
            mip_level_count: 1,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::Depth32Float,
            usage: wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
            view_formats: &[],
        });
        let shadow_map = shadow_texture.create_view(&Default::default());
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow pcf"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let lut_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("lut"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            ..Default::default()
        });
        // Surface maps: trilinear and repeating. No anisotropy: on llvmpipe
        // 4× anisotropic filtering cost ~25 ms of a 640×360 scene pass.
        let surface_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("surface maps"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            anisotropy_clamp: 1,
            ..Default::default()
        });
        let (surface_maps, surface_modes) = upload_surface_maps(&ctx, &mesh.textures)?;
        let scene_uniforms = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("scene uniforms"),
            size: std::mem::size_of::<SceneUniforms>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let shadow_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow"),
            layout: &built.shadow_layout,
            entries: &[buf(0, &scene_uniforms)],
        });
        let mut lods = vec![MeshLod::new(device, mesh)];
        if let Some(coarse) = &mesh.coarse {
            lods.push(MeshLod::new(device, coarse));
        }
        let (lo, hi) = mesh.bounds();
        Ok(Self {
            lods,
            mesh_centre: Vec3::from(mesh.focus),
            mesh_radius: 0.5 * (hi - lo).length(),
            eyes: mesh.eyeballs(),
            metres_per_unit: mesh.metres_per_unit,
            scene_layout: built.scene_layout,
            scene_pipeline: built.scene_pipeline,
            scene_uniforms,
            shadow_pipeline: built.shadow_pipeline,
            shadow_bg,
            shadow_map,
            shadow_texture,
            shadow_sampler,
            lut_sampler,
            surface_sampler,
            surface_maps,
            surface_modes,
            sss: built.sss,
            composite_layout: built.composite_layout,
            composite_pipeline: built.composite_pipeline,
            accumulate_layout: built.accumulate_layout,
            accumulate_pipeline: built.accumulate_pipeline,
            classify_layout: built.classify_layout,
            classify_pipeline: built.classify_pipeline,
            targets: None,
            profile: None,
            shadow_key: None,
            scene_key: None,
            mesh: Mesh {
                coarse: None,
                ..mesh.clone()
            },
            reference_cache: None,
            ctx,
        })
    }

    pub fn adapter_name(&self) -> String {
        format!(
            "{} ({:?})",
            self.ctx.adapter_info.name, self.ctx.adapter_info.backend
        )
    }

    fn ensure_targets(&mut self, w: u32, h: u32) {
        if self.targets.as_ref().is_some_and(|t| t.size == (w, h)) {
            return;
        }
        let device = &self.ctx.device;
        let make = |label, format, usage| target_texture(device, label, (w, h), format, usage);
        let rt = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let mut bytes = 0u64;
        let mut make = |label, format: wgpu::TextureFormat, usage| {
            // Depth24PlusStencil8 has no copy size; count 4 bytes.
            bytes += format.block_copy_size(None).unwrap_or(4) as u64 * w as u64 * h as u64;
            make(label, format, usage)
        };
        let view = |t: &wgpu::Texture| t.create_view(&Default::default());
        let mut hdr = |label| {
            // Copied out for readback and the reference; written by it.
            let t = make(
                label,
                HDR,
                rt | wgpu::TextureUsages::COPY_SRC | wgpu::TextureUsages::COPY_DST,
            );
            let v = view(&t);
            (t, v)
        };
        let hdr = [hdr("diffuse"), hdr("sss ping"), hdr("sss pong")];
        let specular = view(&make("specular", self.ctx.specular_format, rt));
        let albedo = view(&make("albedo", ALBEDO, rt));
        let linear_depth_texture = make(
            "linear depth",
            self.ctx.linear_depth_format,
            rt | wgpu::TextureUsages::COPY_SRC,
        );
        let linear_depth = view(&linear_depth_texture);
        let depth_stencil = view(&make(
            "depth stencil",
            DEPTH_STENCIL,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        ));
        let output = make(
            "output",
            OUTPUT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        self.targets = Some(Targets {
            size: (w, h),
            hdr,
            specular,
            albedo,
            linear_depth,
            linear_depth_texture,
            depth_stencil,
            output,
            accum: [None, None],
            bytes,
        });
        self.scene_key = None;
    }

    /// The running-mean target `slot` of progressive refinement, made on
    /// first use (a frame rendered alone never allocates it).
    fn ensure_accumulator(&mut self, slot: usize) {
        let device = &self.ctx.device;
        let Some(t) = self.targets.as_mut() else {
            return;
        };
        if t.accum[slot].is_some() {
            return;
        }
        let (w, h) = t.size;
        let texture = target_texture(
            device,
            "progressive mean",
            (w, h),
            HDR,
            wgpu::TextureUsages::RENDER_ATTACHMENT
                | wgpu::TextureUsages::TEXTURE_BINDING
                | wgpu::TextureUsages::COPY_SRC,
        );
        t.bytes += HDR.block_copy_size(None).unwrap_or(8) as u64 * w as u64 * h as u64;
        let view = texture.create_view(&Default::default());
        t.accum[slot] = Some((texture, view));
    }

    /// Replaces the mesh's surface maps (the editor draws the default head
    /// with neutral maps first and swaps in its baked maps when they are
    /// ready). The next frame rebuilds the scene's bind group.
    pub fn set_surface_maps(&mut self, maps: &MeshTextures) -> Result<(), GpuError> {
        let (views, modes) = upload_surface_maps(&self.ctx, maps)?;
        self.surface_maps = views;
        self.surface_modes = modes;
        self.profile = None;
        self.scene_key = None;
        self.mesh.textures = std::sync::Arc::new(maps.clone());
        self.reference_cache = None;
        Ok(())
    }

    /// Uploads the profile's tables, patterns and kernels unless the same
    /// inputs are already on the GPU. Returns whether it uploaded.
    fn ensure_profile(&mut self, inputs: &ProfileInputs) -> bool {
        let key = inputs.fingerprint();
        if self.profile.as_ref().is_some_and(|p| p.gpu.key == key) {
            return false;
        }
        let gpu = ProfileGpu::new(&self.ctx.device, &self.ctx.queue, inputs);
        let scene_bg = self
            .ctx
            .device
            .create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some("scene"),
                layout: &self.scene_layout,
                entries: &[
                    buf(0, &self.scene_uniforms),
                    tex(1, &self.shadow_map),
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::Sampler(&self.shadow_sampler),
                    },
                    tex(3, &gpu.preintegrated_lut),
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: wgpu::BindingResource::Sampler(&self.lut_sampler),
                    },
                    buf(5, &gpu.transmittance),
                    tex(6, &self.surface_maps[0]),
                    tex(7, &self.surface_maps[1]),
                    tex(8, &self.surface_maps[2]),
                    tex(9, &self.surface_maps[3]),
                    tex(10, &self.surface_maps[4]),
                    wgpu::BindGroupEntry {
                        binding: 11,
                        resource: wgpu::BindingResource::Sampler(&self.surface_sampler),
                    },
                    tex(12, &gpu.penumbra_lut),
                    tex(13, &self.shadow_map),
                ],
            });
        self.profile = Some(ProfileBinding { gpu, scene_bg });
        true
    }

    /// Runs the classification compute pass after the recorded work,
    /// submits, and reads the SSS pixel count back.
    fn count_sss_pixels(&self, f: &mut FrameEncoder, t: &Targets) -> Result<u64, GpuError> {
        let device = &self.ctx.device;
        let (counts, read) = counter_buffers(device, "sss counts");
        let bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("classify"),
            layout: &self.classify_layout,
            entries: &[tex(0, t.view(HdrTarget::Diffuse)), buf(1, &counts)],
        });
        let (w, h) = t.size;
        f.fullscreen(
            None,
            &self.classify_pipeline,
            &bg,
            "classify",
            (w as u64 * h as u64, 0),
            false,
            true,
        );
        f.encoder.copy_buffer_to_buffer(&counts, 0, &read, 0, 16);
        self.ctx.queue.submit([f.take().finish()]);
        read_u32x4(&self.ctx, &read)
            .map(|c| c[0] as u64)
            .ok_or_else(|| GpuError::Readback("sss pixel count".into()))
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

    fn render_inner(
        &mut self,
        inputs: &ProfileInputs,
        s: &RenderSettings,
        want_diffuse: bool,
    ) -> Result<(image::RgbaImage, Vec<[f32; 4]>, FrameStats), GpuError> {
        self.ensure_targets(s.width, s.height);
        if let Some(p) = s.progressive {
            if p.slot >= 2 {
                return Err(GpuError::Readback(format!(
                    "progressive slot {} (there are two: A and B)",
                    p.slot
                )));
            }
            self.ensure_accumulator(p.slot);
        }
        // Any validation error in the frame is reported, never panicked on.
        let scope = self
            .ctx
            .device
            .push_error_scope(wgpu::ErrorFilter::Validation);
        let uploaded = self.ensure_profile(inputs);
        let result = self.encode_and_read(inputs, s, want_diffuse);
        let error = pollster::block_on(scope.pop());
        if error.is_some() || result.is_err() {
            // The shadow map or the profile may be incomplete: redo them.
            self.shadow_key = None;
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

    /// The camera (eye, view, projection) and the light's direction and
    /// orthographic clip transform around the mesh's bounding sphere.
    fn camera_and_light(&self, s: &RenderSettings) -> (Vec3, Mat4, Mat4, Vec3, Mat4) {
        let aspect = s.width as f32 / s.height as f32;
        let dist = s.camera_distance_m / self.metres_per_unit;
        let dir = orbit_direction(s.camera_yaw, s.camera_pitch);
        let right = Vec3::Y.cross(dir).normalize_or_zero();
        let up = dir.cross(right);
        let target = self.mesh_centre
            + (right * s.camera_pan_m[0] + up * s.camera_pan_m[1]) / self.metres_per_unit;
        let eye = target + dist * dir;
        let view = Mat4::look_at_rh(eye, target, Vec3::Y);
        let proj = Mat4::perspective_rh(s.fov_y, aspect, 0.05 * dist, 10.0 * dist);
        let light = orbit_direction(s.light_azimuth, s.light_elevation);
        let rad = self.mesh_radius;
        let up = if light.y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let light_clip = match self.point_light(s) {
            // A perspective map from the light, just wide enough for the
            // bounding sphere.
            Some((pos, dist, near, far)) => {
                let half = (rad / dist).clamp(1e-4, 0.99).asin() * 1.05;
                Mat4::perspective_rh(2.0 * half, 1.0, near, far)
                    * Mat4::look_at_rh(pos, self.mesh_centre, up)
            }
            None => {
                let light_view =
                    Mat4::look_at_rh(self.mesh_centre + light * 2.0 * rad, self.mesh_centre, up);
                Mat4::orthographic_rh(-rad, rad, -rad, rad, 0.01 * rad, 4.0 * rad) * light_view
            }
        };
        (eye, view, proj, light, light_clip)
    }

    /// The coarsest level of detail whose mean edge spans at most
    /// `LOD_EDGE_PX` pixels at the mesh's distance, else the finest.
    fn pick_lod(&self, s: &RenderSettings) -> usize {
        let dist = s.camera_distance_m / self.metres_per_unit;
        let px_per_unit = s.height as f32 / (2.0 * (0.5 * s.fov_y).tan() * dist);
        (0..self.lods.len())
            .rev()
            .find(|&k| k == 0 || self.lods[k].mean_edge * px_per_unit <= LOD_EDGE_PX)
            .unwrap_or(0)
    }

    /// A point light's position, distance from the centre and shadow
    /// near/far planes (world units), or `None` for a directional light.
    fn point_light(&self, s: &RenderSettings) -> Option<(Vec3, f32, f32, f32)> {
        let metres = s.point_light_distance_m?;
        let rad = self.mesh_radius;
        // At least just outside the bounding sphere.
        let dist = (metres / self.metres_per_unit).max(1.05 * rad);
        let dir = orbit_direction(s.light_azimuth, s.light_elevation);
        Some((
            self.mesh_centre + dir * dist,
            dist,
            (dist - rad).max(0.01 * rad),
            dist + rad,
        ))
    }

    fn scene_uniforms(&self, inputs: &ProfileInputs, s: &RenderSettings) -> SceneUniforms {
        let (eye, view, proj, light, light_clip) = self.camera_and_light(s);
        let rad = self.mesh_radius;
        let pre = match s.texturing {
            TexturingMode::PostScatter => 0.0,
            TexturingMode::PreAndPostScatter => 0.5,
        };
        SceneUniforms {
            clip_from_world: (proj * view).to_cols_array_2d(),
            view_from_world: view.to_cols_array_2d(),
            camera_position: eye.extend(1.0).into(),
            light_direction: match self.point_light(s) {
                Some((pos, ..)) => pos.extend(1.0).into(),
                None => light.extend(0.0).into(),
            },
            light_range: match self.point_light(s) {
                Some((_, dist, near, far)) => [near, far, dist, 0.0],
                None => [0.0; 4],
            },
            light_radiance: [s.light_intensity; 4],
            surface_albedo: [
                inputs.surface_albedo[0],
                inputs.surface_albedo[1],
                inputs.surface_albedo[2],
                0.0,
            ],
            params: match s.specular {
                Specular::DualGgx {
                    roughness0,
                    roughness1,
                    ..
                } => [pre, roughness0, s.specular_f0, roughness1],
                Specular::Kelemen { roughness } => [pre, roughness, s.specular_f0, roughness],
            },
            specular: match s.specular {
                Specular::DualGgx { lobe_mix, .. } => [lobe_mix, 0.0, 0.0, 0.0],
                Specular::Kelemen { .. } => [0.0, 1.0, 0.0, 0.0],
            },
            light_clip_from_world: light_clip.to_cols_array_2d(),
            // Bias: a texel of depth slope; normal offset: one shadow texel in world units.
            shadow: [
                1.0 / SHADOW_SIZE as f32,
                2.0 / SHADOW_SIZE as f32,
                2.0 * rad / SHADOW_SIZE as f32,
                // Depth range of the orthographic light projection (world units).
                4.0 * rad - 0.01 * rad,
            ],
            transmission: [
                match s.transmission {
                    Transmission::Off => 0.0,
                    Transmission::ThinObject => 1.0,
                    Transmission::ThickObject => 2.0,
                },
                inputs.transmittance_range_mm,
                inputs.transmittance.len() as f32,
                1000.0 * self.metres_per_unit,
            ],
            transmission_tint: [
                s.transmission_tint[0],
                s.transmission_tint[1],
                s.transmission_tint[2],
                0.0,
            ],
            preintegrated: sss::preintegrated::uniforms(s.method, &inputs.lut_layout),
            preintegrated_normals: [
                inputs.normal_blend[0],
                inputs.normal_blend[1],
                inputs.normal_blend[2],
                if s.penumbra { 1.0 } else { 0.0 },
            ],
            surface: [
                self.surface_modes[0],
                self.surface_modes[1],
                self.surface_modes[2],
                s.detail_normal_strength,
            ],
            environment_sh: s.environment_sh.map(|c| [c[0], c[1], c[2], 0.0]),
            eyes: self.eyes,
            penumbra: [
                1.0 / inputs.penumbra_layout.penumbra_max_mm as f32,
                1.0 / inputs.penumbra_layout.penumbra_min_mm as f32,
                // The PCF's 4-texel footprint, in mm.
                4.0 * 2.0 * rad / SHADOW_SIZE as f32 * 1000.0 * self.metres_per_unit,
                0.0,
            ],
            pattern: match s.pattern {
                IrradiancePattern::Lit => [0.0; 4],
                IrradiancePattern::Step => [1.0, 0.0, 0.0, 0.0],
                IrradiancePattern::Checkerboard { period_mm } => {
                    [2.0, period_mm / (1000.0 * self.metres_per_unit), 0.0, 0.0]
                }
            },
        }
    }

    fn encode_and_read(
        &mut self,
        inputs: &ProfileInputs,
        s: &RenderSettings,
        want_diffuse: bool,
    ) -> Result<(image::RgbaImage, Vec<[f32; 4]>, FrameStats), GpuError> {
        let (Some(t), Some(profile)) = (self.targets.as_ref(), self.profile.as_ref()) else {
            return Err(GpuError::Readback("no targets".into()));
        };
        let ctx = &self.ctx;
        let device = &ctx.device;
        let scene_u = self.scene_uniforms(inputs, s);
        let light_clip = scene_u.light_clip_from_world;
        // The ground truth integrates the finest surface: draw that one.
        let lod_index = if s.method == Method::Reference || !s.mesh_lod {
            0
        } else {
            self.pick_lod(s)
        };
        let lod = &self.lods[lod_index];
        let scene_key = SceneKey {
            uniforms: bytemuck::bytes_of(&scene_u).to_vec(),
            size: (s.width, s.height),
            lod: lod_index,
            profile: profile.gpu.key,
        };
        // A progressive frame past the first changes only the rotations:
        // the scene's targets and stencil from the frame before still hold.
        let reused_pixels = match (&self.scene_key, s.progressive) {
            (Some((key, pixels)), Some(p)) if p.frame > 0 && *key == scene_key => Some(*pixels),
            _ => None,
        };
        let shadow_cached =
            reused_pixels.is_some() || self.shadow_key == Some((light_clip, lod_index));
        ctx.queue
            .write_buffer(&self.scene_uniforms, 0, bytemuck::bytes_of(&scene_u));
        let (w, h) = (s.width as u64, s.height as u64);
        let mut f = FrameEncoder::new(device, PassTimer::new(ctx));
        let mesh_pass = |pass: &mut wgpu::RenderPass, pipeline, bg| {
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bg, &[]);
            pass.set_vertex_buffer(0, lod.vertices.slice(..));
            pass.set_index_buffer(lod.indices.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..lod.index_count, 0, 0..1);
        };
        let depth_attachment = |view, stencil: bool| {
            Some(wgpu::RenderPassDepthStencilAttachment {
                view,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: stencil.then_some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(0),
                    store: wgpu::StoreOp::Store,
                }),
            })
        };
        if !shadow_cached {
            let mut pass = f.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow"),
                color_attachments: &[],
                depth_stencil_attachment: depth_attachment(&self.shadow_map, false),
                timestamp_writes: f
                    .timer
                    .render("shadow", (SHADOW_SIZE * SHADOW_SIZE) as u64, 0),
                ..Default::default()
            });
            mesh_pass(&mut pass, &self.shadow_pipeline, &self.shadow_bg);
        }
        if reused_pixels.is_none() {
            let mut pass = f.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("scene"),
                color_attachments: &[
                    Some(color_attachment(t.view(HdrTarget::Diffuse), false)),
                    Some(color_attachment(&t.specular, false)),
                    Some(color_attachment(&t.albedo, false)),
                    Some(color_attachment(&t.linear_depth, false)),
                ],
                depth_stencil_attachment: depth_attachment(&t.depth_stencil, true),
                timestamp_writes: f.timer.render("scene", w * h, 0),
                ..Default::default()
            });
            mesh_pass(&mut pass, &self.scene_pipeline, &profile.scene_bg);
        }
        // Classify: count SSS pixels on the GPU; with none on screen, or a
        // profile that does not scatter (strength 0), no SSS pass runs.
        f.stencil = Some(&t.depth_stencil);
        let sss_pixels = match reused_pixels {
            Some(n) => n,
            None => self.count_sss_pixels(&mut f, t)?,
        };
        let method = if sss_pixels > 0 && inputs.scatters {
            s.method
        } else {
            Method::None
        };
        // Samples taken, pixels convolved, pixels skipped by the LOD.
        let (counters, counters_read) = counter_buffers(device, "sss counters");
        let io = SssFrame {
            targets: t,
            profile: &profile.gpu,
            sss_pixels,
            uniforms: SssUniforms {
                size: [
                    s.width as f32,
                    s.height as f32,
                    1.0 / s.width as f32,
                    1.0 / s.height as f32,
                ],
                projection: [
                    s.height as f32 / (2.0 * (0.5 * s.fov_y).tan()),
                    self.metres_per_unit * 1000.0,
                    s.progressive.map_or(0.0, |p| p.rotation_offset()),
                    0.0,
                ],
                params: [
                    0.0,
                    if s.deterministic { 1.0 } else { 0.0 },
                    inputs.lut_radius_mm,
                    LUT_SIZE as f32,
                ],
                direction: [0.0; 4],
                weight: [1.0; 4],
            },
            counters: &counters,
            lod: s.lod,
            rotate_separable: s.separable_rotation && !s.deterministic,
        };
        let mut reference_cpu_ms = None;
        if method == Method::Reference {
            let (_, view, ..) = self.camera_and_light(s);
            let io = sss::reference::Io {
                diffuse: t.texture(HdrTarget::Diffuse),
                linear_depth: &t.linear_depth_texture,
                linear_depth_format: ctx.linear_depth_format,
                shadow_map: &self.shadow_texture,
                shadow_size: SHADOW_SIZE,
                ping: t.texture(HdrTarget::Ping),
            };
            // The scene pass must be on the GPU before it is read back.
            ctx.queue.submit([f.take().finish()]);
            let timing = sss::reference::scatter(
                ctx,
                &self.mesh,
                &io,
                &scene_u,
                view,
                s,
                inputs,
                &mut self.reference_cache,
            )?;
            reference_cpu_ms = Some(timing.build_ms.unwrap_or(0.0) + timing.gather_ms);
        }
        let scattered = sss::encode(method, &mut f, &self.sss, &io);
        f.encoder
            .copy_buffer_to_buffer(&counters, 0, &counters_read, 0, 16);
        let cu = f.uniform(
            "composite uniforms",
            bytemuck::bytes_of(&CompositeUniforms {
                exposure: [s.exposure, 0.0, 0.0, 0.0],
            }),
        );
        // Progressive: this frame's output joins the running mean (weight
        // 1/(n+1) for sample n), and the mean is what composite shows.
        let shown = match (s.progressive, &t.accum) {
            (Some(p), accum) => {
                let Some((mean_texture, mean)) = accum[p.slot].as_ref() else {
                    return Err(GpuError::Readback("no progressive target".into()));
                };
                let bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("accumulate"),
                    layout: &self.accumulate_layout,
                    entries: &[tex(1, t.view(scattered.target))],
                });
                let mut pass = f.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("accumulate"),
                    color_attachments: &[Some(color_attachment(mean, p.frame > 0))],
                    timestamp_writes: f.timer.render("accumulate", w * h, 0),
                    ..Default::default()
                });
                pass.set_pipeline(&self.accumulate_pipeline);
                pass.set_bind_group(0, &bg, &[]);
                let c = 1.0 / (p.frame as f64 + 1.0);
                pass.set_blend_constant(wgpu::Color {
                    r: c,
                    g: c,
                    b: c,
                    a: c,
                });
                pass.draw(0..3, 0..1);
                (mean_texture, mean)
            }
            (None, _) => (t.texture(scattered.target), t.view(scattered.target)),
        };
        let output_view = t.output.create_view(&Default::default());
        let cbg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("composite"),
            layout: &self.composite_layout,
            entries: &[
                buf(0, &cu),
                tex(1, shown.1),
                tex(2, &t.specular),
                tex(3, &t.albedo),
                tex(4, t.view(HdrTarget::Diffuse)),
            ],
        });
        f.fullscreen(
            Some(&output_view),
            &self.composite_pipeline,
            &cbg,
            "composite",
            (w * h, 0),
            false,
            false,
        );
        let FrameEncoder {
            mut encoder,
            mut timer,
            ..
        } = f;
        timer.resolve(&mut encoder);
        let mut wanted: Vec<(&wgpu::Texture, u32)> = vec![(&t.output, 4)];
        if want_diffuse {
            wanted.push((t.texture(HdrTarget::Diffuse), 8));
            wanted.push((shown.0, 8));
        }
        let mut bytes = ctx.checked("frame", || {
            readback(ctx, encoder, &wanted, s.width, s.height)
        })??;
        let diffuse = if want_diffuse {
            let halves = |b: Vec<u8>| -> Vec<[f32; 4]> {
                b.chunks_exact(8)
                    .map(|px| {
                        [0, 1, 2, 3]
                            .map(|k| half_to_f32(u16::from_le_bytes([px[2 * k], px[2 * k + 1]])))
                    })
                    .collect()
            };
            let out = halves(bytes.pop().unwrap_or_default());
            let unscattered = halves(bytes.pop().unwrap_or_default());
            // What composite shows: the method's output on SSS pixels, the
            // scene's diffuse elsewhere.
            out.into_iter()
                .zip(unscattered)
                .map(|(o, d)| if o[3] > 1.0 / 255.0 { o } else { d })
                .collect()
        } else {
            Vec::new()
        };
        let image = image::RgbaImage::from_raw(s.width, s.height, bytes.swap_remove(0))
            .ok_or_else(|| GpuError::Readback("size mismatch".into()))?;
        let measured = scattered
            .counted_pass
            .and_then(|_| read_u32x4(&self.ctx, &counters_read));
        let spp = scattered.samples_per_pixel;
        let (sss_samples, lod_skipped_pixels) = match measured {
            Some(c) => (c[0] as u64, c[2] as u64),
            None => (sss_pixels * spp as u64, 0),
        };
        if let Some(label) = scattered.counted_pass {
            timer.set_samples(label, sss_samples);
        }
        let passes = timer.finish(ctx);
        // Sum over the SSS passes, where every one was timed.
        let sss: Vec<_> = passes
            .iter()
            .filter(|p| p.name.starts_with("sss"))
            .collect();
        let sss_gpu_ms = (!sss.is_empty())
            .then(|| sss.iter().map(|p| p.gpu_ms).sum::<Option<f64>>())
            .flatten();
        let stats = FrameStats {
            method: s.method.id(),
            passes,
            samples_per_sss_pixel: spp,
            sss_pixels,
            sss_samples,
            lod_skipped_pixels,
            sss_gpu_ms,
            reference_cpu_ms,
            profile_uploaded: false,
            scene_reused: reused_pixels.is_some(),
            target_bytes: t.bytes,
            triangles: lod.index_count as u64 / 3,
            width: s.width,
            height: s.height,
            adapter: self.adapter_name(),
        };
        self.shadow_key = Some((light_clip, lod_index));
        self.scene_key = Some((scene_key, sss_pixels));
        Ok((image, diffuse, stats))
    }
}

/// A 2D, single-sample, single-mip render target of `size`.
fn target_texture(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// Uploads a mesh's five surface maps (albedo, normal, roughness, mask,
/// thickness) and their `SceneUniforms::surface` modes, refusing maps the
/// adapter cannot hold, naming the slot, before any upload (an oversized
/// texture is a device error otherwise).
fn upload_surface_maps(
    ctx: &GpuContext,
    maps: &MeshTextures,
) -> Result<([wgpu::TextureView; 5], [f32; 4]), GpuError> {
    let device = &ctx.device;
    let upload = |img, format, label| textures::upload(device, &ctx.queue, img, format, label);
    let no_thickness = TextureImage::solid(&[0]);
    let max = device.limits().max_texture_dimension_2d;
    let (srgb, rgba, grey) = (
        wgpu::TextureFormat::Rgba8UnormSrgb,
        wgpu::TextureFormat::Rgba8Unorm,
        wgpu::TextureFormat::R8Unorm,
    );
    let slots = [
        ("albedo map", &maps.albedo, srgb),
        ("normal map", &maps.normal, rgba),
        ("roughness map", &maps.roughness, grey),
        ("mask map", &maps.mask, grey),
        (
            "thickness map",
            maps.thickness.as_ref().map_or(&no_thickness, |t| &t.0),
            grey,
        ),
    ];
    if let Some((slot, img, _)) = slots
        .iter()
        .find(|(_, i, _)| i.width > max || i.height > max)
    {
        return Err(GpuError::Validation {
            stage: "surface maps",
            message: format!(
                "the {slot} is {}×{}; this adapter holds at most {max}×{max}",
                img.width, img.height
            ),
        });
    }
    let views = ctx.checked("surface maps", || {
        slots.map(|(label, img, format)| upload(img, format, label))
    })?;
    let modes = [
        if maps.albedo_mode == AlbedoMode::Absolute {
            1.0
        } else {
            0.0
        },
        if maps.roughness_mode == RoughnessMode::Absolute {
            1.0
        } else {
            0.0
        },
        maps.thickness.as_ref().map_or(0.0, |t| t.1),
        1.0,
    ];
    Ok((views, modes))
}

/// Draw the coarse level of detail while its mean edge is at most this
/// many pixels: at that size the subdivided triangles (a quarter the area)
/// cost lavapipe ~25 ms more scene pass at 640×360 (measured) for
/// silhouettes no one can see; closer shots get the smooth mesh.
const LOD_EDGE_PX: f32 = 10.0;

/// Four zeroed u32 GPU counters and the buffer they are read back through.
fn counter_buffers(device: &wgpu::Device, label: &'static str) -> (wgpu::Buffer, wgpu::Buffer) {
    let counters = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: bytemuck::cast_slice(&[0u32; 4]),
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    });
    let read = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: 16,
        usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
        mapped_at_creation: false,
    });
    (counters, read)
}

/// Unit vector for an azimuth about +y (0 = +z) and an elevation (radians).
fn orbit_direction(azimuth: f32, elevation: f32) -> Vec3 {
    Vec3::new(
        azimuth.sin() * elevation.cos(),
        elevation.sin(),
        azimuth.cos() * elevation.cos(),
    )
}

/// One level of detail on the GPU.
struct MeshLod {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
    /// Mean edge length (mesh units).
    mean_edge: f32,
}

impl MeshLod {
    fn new(device: &wgpu::Device, mesh: &Mesh) -> Self {
        Self {
            vertices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("vertices"),
                contents: bytemuck::cast_slice(&mesh.vertices),
                usage: wgpu::BufferUsages::VERTEX,
            }),
            indices: device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some("indices"),
                contents: bytemuck::cast_slice(&mesh.indices),
                usage: wgpu::BufferUsages::INDEX,
            }),
            index_count: mesh.indices.len() as u32,
            mean_edge: mesh.mean_edge(),
        }
    }
}

/// Everything [`Renderer::new`] builds inside one validation scope.
struct Pipelines {
    scene_layout: wgpu::BindGroupLayout,
    scene_pipeline: wgpu::RenderPipeline,
    shadow_layout: wgpu::BindGroupLayout,
    shadow_pipeline: wgpu::RenderPipeline,
    composite_layout: wgpu::BindGroupLayout,
    composite_pipeline: wgpu::RenderPipeline,
    accumulate_layout: wgpu::BindGroupLayout,
    accumulate_pipeline: wgpu::RenderPipeline,
    classify_layout: wgpu::BindGroupLayout,
    classify_pipeline: wgpu::RenderPipeline,
    sss: SssPipelines,
}
