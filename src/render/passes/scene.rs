//! The scene pass: the mesh lit by the light (shadowed), the environment
//! and, for the method lit here, its tables, into the G-buffer the SSS
//! passes read (`shaders/scene.wgsl`, `fs_main`). Its uniforms gather the
//! camera, the light and the look ([`SceneUniforms`]); that method's terms
//! are its own file's to set (`sss::scene_terms`).

use super::super::context::{GpuContext, GpuError};
use super::super::frame::{buf, color_attachment, color_attachment_clearing, tex, FrameEncoder};
use super::super::framing::{CameraLight, Framing};
use super::super::gpu_types::{
    SceneUniforms, DIFFUSE_ALPHA_BACKGROUND, MAP_ABSOLUTE, MAP_LOOK, MAP_MODULATES,
    PATTERN_CHECKERBOARD, PATTERN_LIT, PATTERN_STEP, SPECULAR_DUAL_GGX, SPECULAR_KELEMEN,
    TRANSMISSION_OFF, TRANSMISSION_THICK, TRANSMISSION_THIN,
};
use super::super::inputs::Shared;
use super::super::pipelines::{buffer_entry, scene_pipeline, uniform_entry};
use super::super::profile_gpu::SharedGpu;
use super::super::settings::{
    IrradiancePattern, RenderSettings, Specular, TexturingMode, Transmission,
};
use super::super::targets::{HdrTarget, Targets};
use super::super::textures::{
    self, AlbedoMode, MapColour, MeshTextures, RoughnessMode, TextureImage,
};
use super::shadow::{ShadowPass, SHADOW_SIZE};
use super::{depth_attachment, MeshLod};

/// A mesh's five surface maps on the GPU and how the scene reads them.
pub(in crate::render) struct SurfaceMaps {
    /// Albedo, normal, roughness, mask and thickness.
    views: [wgpu::TextureView; 5],
    /// `MAP_*`: [`SceneUniforms::albedo_map_mode`].
    albedo_mode: u32,
    /// `MAP_*`: [`SceneUniforms::roughness_map_mode`].
    roughness_mode: u32,
    /// The thickness map's range (mm); 0: none (the per-vertex bake).
    thickness_range_mm: f32,
    /// A colour map's mean linear colour ([`textures::albedo_map_mean`]),
    /// which [`MapColour::Tinted`] scales to the look's albedo.
    albedo_mean: Option<[f32; 3]>,
}

impl SurfaceMaps {
    /// The scene's `albedo_map_mode` and `surface_albedo` for a look of
    /// colour `look` (linear A) shown as `colour` says.
    fn albedo_terms(&self, look: [f32; 3], colour: MapColour) -> (u32, [f32; 3]) {
        if self.albedo_mode != MAP_ABSOLUTE {
            // A modulating map always multiplies the look's colour.
            return (self.albedo_mode, look);
        }
        match (colour, self.albedo_mean) {
            (MapColour::Map, _) => (MAP_ABSOLUTE, look),
            (MapColour::Look, _) | (MapColour::Tinted, None) => (MAP_LOOK, look),
            // The modulating formula A'·2·map with A' = A / (2·mean):
            // albedo = A · map / mean, whose mean over the map is A.
            (MapColour::Tinted, Some(mean)) => (
                MAP_MODULATES,
                std::array::from_fn(|c| look[c] / (2.0 * mean[c].max(1e-3))),
            ),
        }
    }
}

impl SurfaceMaps {
    /// Uploads a mesh's maps, refusing maps the adapter cannot hold, naming
    /// the slot, before any upload (an oversized texture is a device error
    /// otherwise).
    pub fn upload(ctx: &GpuContext, maps: &MeshTextures) -> Result<Self, GpuError> {
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
        let mode = |absolute: bool| {
            if absolute {
                MAP_ABSOLUTE
            } else {
                MAP_MODULATES
            }
        };
        Ok(Self {
            views,
            albedo_mode: mode(maps.albedo_mode == AlbedoMode::Absolute),
            roughness_mode: mode(maps.roughness_mode == RoughnessMode::Absolute),
            thickness_range_mm: maps.thickness.as_ref().map_or(0.0, |t| t.1),
            albedo_mean: textures::albedo_map_mean(&maps.albedo),
        })
    }
}

pub(in crate::render) struct ScenePass {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
    /// [`SceneUniforms`], written each frame (the shadow pass reads it too).
    pub uniforms: wgpu::Buffer,
    lut_sampler: wgpu::Sampler,
    surface_sampler: wgpu::Sampler,
    pub maps: SurfaceMaps,
}

impl ScenePass {
    pub fn new(ctx: &GpuContext, module: &wgpu::ShaderModule, maps: SurfaceMaps) -> Self {
        let device = &ctx.device;
        // The GPU ground truth calls the scene pass's `shade` from a
        // compute shader with this same bind group (ground_truth/gpu.rs).
        let frag = wgpu::ShaderStages::FRAGMENT | wgpu::ShaderStages::COMPUTE;
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
        let storage = wgpu::BufferBindingType::Storage { read_only: true };
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("scene"),
            entries: &[
                uniform_entry::<SceneUniforms>(
                    0,
                    wgpu::ShaderStages::VERTEX_FRAGMENT | wgpu::ShaderStages::COMPUTE,
                ),
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
        Self {
            pipeline: scene_pipeline(
                device,
                module,
                &layout,
                ctx.specular_format,
                ctx.linear_depth_format,
            ),
            layout,
            uniforms: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("scene uniforms"),
                size: std::mem::size_of::<SceneUniforms>() as u64,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            lut_sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("lut"),
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                address_mode_u: wgpu::AddressMode::ClampToEdge,
                address_mode_v: wgpu::AddressMode::ClampToEdge,
                ..Default::default()
            }),
            // Surface maps: trilinear and repeating. No anisotropy: on
            // llvmpipe 4× anisotropic filtering cost ~25 ms of a 640×360
            // scene pass.
            surface_sampler: device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some("surface maps"),
                address_mode_u: wgpu::AddressMode::Repeat,
                address_mode_v: wgpu::AddressMode::Repeat,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                mipmap_filter: wgpu::MipmapFilterMode::Linear,
                anisotropy_clamp: 1,
                ..Default::default()
            }),
            maps,
        }
    }

    /// The layout of [`ScenePass::bind`]'s groups.
    pub fn layout(&self) -> &wgpu::BindGroupLayout {
        &self.layout
    }

    /// The scene's bind group for a profile's tables and the shadow map.
    /// The scene's bind group: the shared profile tables, the scene-lit
    /// method's two `tables` (its lighting and penumbra tables), the
    /// maps and the shadow map.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        shared: &SharedGpu,
        tables: [&wgpu::TextureView; 2],
        shadow: &ShadowPass,
    ) -> wgpu::BindGroup {
        let sampler = |binding, s| wgpu::BindGroupEntry {
            binding,
            resource: wgpu::BindingResource::Sampler(s),
        };
        let maps = &self.maps.views;
        device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout: &self.layout,
            entries: &[
                buf(0, &self.uniforms),
                tex(1, &shadow.view),
                sampler(2, &shadow.sampler),
                tex(3, tables[0]),
                sampler(4, &self.lut_sampler),
                buf(5, &shared.transmittance),
                tex(6, &maps[0]),
                tex(7, &maps[1]),
                tex(8, &maps[2]),
                tex(9, &maps[3]),
                tex(10, &maps[4]),
                sampler(11, &self.surface_sampler),
                tex(12, tables[1]),
                tex(13, &shadow.view),
            ],
        })
    }

    /// Draws the mesh into the targets (clearing them, depth and stencil).
    pub fn encode(
        &self,
        f: &mut FrameEncoder,
        t: &Targets,
        lod: &MeshLod,
        bind_group: &wgpu::BindGroup,
    ) {
        let (w, h) = t.size;
        let mut pass = f.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[
                // The background's alpha marks it for the SSS passes.
                Some(color_attachment_clearing(
                    t.view(HdrTarget::Diffuse),
                    Some(wgpu::Color {
                        a: DIFFUSE_ALPHA_BACKGROUND as f64,
                        ..wgpu::Color::TRANSPARENT
                    }),
                )),
                Some(color_attachment(&t.specular, false)),
                Some(color_attachment(&t.albedo, false)),
                Some(color_attachment(&t.linear_depth, false)),
            ],
            depth_stencil_attachment: depth_attachment(&t.depth_stencil, true),
            timestamp_writes: f.timer.render("scene", w as u64 * h as u64, 0),
            ..Default::default()
        });
        lod.draw(&mut pass, &self.pipeline, bind_group);
    }

    /// The scene's uniforms for a frame: camera and light from `cl`, the
    /// look from `shared` and `s`. The scene-lit method's terms are off
    /// here (`preintegrated`, `lut_*`, `blur_sigma_mm`, `penumbra_*`): its
    /// file sets them (`sss::scene_terms`).
    pub fn uniforms(
        &self,
        framing: &Framing,
        cl: &CameraLight,
        shared: &Shared,
        s: &RenderSettings,
    ) -> SceneUniforms {
        let rad = framing.radius;
        let mm_per_unit = 1000.0 * framing.metres_per_unit;
        let point = framing.point_light(s);
        let rgb0 = |[r, g, b]: [f32; 3]| [r, g, b, 0.0];
        let (roughness0, roughness1, lobe_mix, specular_model) = match s.specular {
            Specular::DualGgx {
                roughness0,
                roughness1,
                lobe_mix,
            } => (roughness0, roughness1, lobe_mix, SPECULAR_DUAL_GGX),
            Specular::Kelemen { roughness } => (roughness, roughness, 0.0, SPECULAR_KELEMEN),
        };
        let (pattern, pattern_period) = match s.pattern {
            IrradiancePattern::Lit => (PATTERN_LIT, 0.0),
            IrradiancePattern::Step => (PATTERN_STEP, 0.0),
            IrradiancePattern::Checkerboard { period_mm } => {
                (PATTERN_CHECKERBOARD, period_mm / mm_per_unit)
            }
        };
        let maps = &self.maps;
        let (albedo_map_mode, surface_albedo) =
            maps.albedo_terms(shared.surface_albedo, s.map_colour);
        SceneUniforms {
            clip_from_world: (cl.projection * cl.view).to_cols_array_2d(),
            view_from_world: cl.view.to_cols_array_2d(),
            light_clip_from_world: cl.light_clip.to_cols_array_2d(),
            camera_position: cl.eye.extend(1.0).into(),
            light_direction: match &point {
                Some(p) => p.position.extend(1.0).into(),
                None => cl.light.extend(0.0).into(),
            },
            light_radiance: rgb0(s.view.light_colour.map(|c| c * s.view.light_intensity)),
            rig_direction: [s.view.fill, s.view.rim].map(|l| rgb0(l.direction())),
            rig_radiance: [s.view.fill, s.view.rim].map(|l| rgb0(l.radiance())),
            surface_albedo: rgb0(surface_albedo),
            transmission_tint: rgb0(s.transmission_tint),
            blur_sigma_mm: [0.0; 4],
            environment_sh: s.environment_sh.map(rgb0),
            eyes: framing.eyes,
            pre_scatter_exponent: match s.texturing {
                TexturingMode::PostScatter => 0.0,
                TexturingMode::PreAndPostScatter => 0.5,
            },
            roughness0,
            specular_f0: s.specular_f0,
            roughness1,
            lobe_mix,
            specular_model,
            pattern,
            pattern_period,
            // Bias: a texel of depth slope; normal offset: one shadow
            // texel in world units.
            shadow_texel: 1.0 / SHADOW_SIZE as f32,
            shadow_depth_bias: 2.0 / SHADOW_SIZE as f32,
            shadow_normal_offset: 2.0 * rad / SHADOW_SIZE as f32,
            shadow_depth_range: 4.0 * rad - 0.01 * rad,
            light_near: point.as_ref().map_or(0.0, |p| p.near),
            light_far: point.as_ref().map_or(0.0, |p| p.far),
            light_reference_distance: point.as_ref().map_or(0.0, |p| p.distance),
            pad0: 0.0,
            transmission_mode: match s.transmission {
                Transmission::Off => TRANSMISSION_OFF,
                Transmission::ThinObject => TRANSMISSION_THIN,
                Transmission::ThickObject => TRANSMISSION_THICK,
            },
            transmittance_range_mm: shared.transmittance_range_mm,
            transmittance_entries: shared.transmittance.len() as u32,
            mm_per_unit,
            preintegrated: 0,
            lut_curvature_first: 0.0,
            lut_curvature_last: 0.0,
            penumbra_on: 0,
            albedo_map_mode,
            roughness_map_mode: maps.roughness_mode,
            thickness_map_range_mm: maps.thickness_range_mm,
            detail_normal_strength: s.detail_normal_strength,
            penumbra_inv_width_first: 0.0,
            penumbra_inv_width_last: 0.0,
            // The PCF's 4-texel footprint, in mm.
            pcf_footprint_mm: 4.0 * 2.0 * rad / SHADOW_SIZE as f32
                * 1000.0
                * framing.metres_per_unit,
            pad1: 0.0,
        }
    }
}
