//! The scene pass: the mesh lit by the light (shadowed), the environment
//! and, for `preintegrated`, Penner's tables, into the G-buffer the SSS
//! passes read (`shaders/scene.wgsl`, `fs_scene`). Its uniforms gather the
//! camera, the light and the look ([`SceneUniforms`]).

use super::super::context::{GpuContext, GpuError};
use super::super::frame::{buf, color_attachment, tex, FrameEncoder};
use super::super::framing::{CameraLight, Framing};
use super::super::gpu_types::SceneUniforms;
use super::super::inputs::ProfileInputs;
use super::super::pipelines::{buffer_entry, scene_pipeline, uniform_entry};
use super::super::profile_gpu::ProfileGpu;
use super::super::settings::{IrradiancePattern, RenderSettings, Specular, TexturingMode,
    Transmission,
};
use super::super::sss;
use super::super::targets::{HdrTarget, Targets};
use super::super::textures::{self, AlbedoMode, MeshTextures, RoughnessMode, TextureImage};
use super::shadow::{ShadowPass, SHADOW_SIZE};
use super::{depth_attachment, MeshLod};

/// A mesh's five surface maps on the GPU and their `SceneUniforms::surface`
/// modes.
pub(in crate::render) struct SurfaceMaps {
    /// Albedo, normal, roughness, mask and thickness.
    views: [wgpu::TextureView; 5],
    modes: [f32; 4],
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
        let flag = |on: bool| if on { 1.0 } else { 0.0 };
        let modes = [
            flag(maps.albedo_mode == AlbedoMode::Absolute),
            flag(maps.roughness_mode == RoughnessMode::Absolute),
            maps.thickness.as_ref().map_or(0.0, |t| t.1),
            1.0,
        ];
        Ok(Self { views, modes })
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
        let frag = wgpu::ShaderStages::FRAGMENT;
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
                uniform_entry::<SceneUniforms>(0, wgpu::ShaderStages::VERTEX_FRAGMENT),
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

    /// The scene's bind group for a profile's tables and the shadow map.
    pub fn bind(
        &self,
        device: &wgpu::Device,
        gpu: &ProfileGpu,
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
                tex(3, &gpu.preintegrated_lut),
                sampler(4, &self.lut_sampler),
                buf(5, &gpu.transmittance),
                tex(6, &maps[0]),
                tex(7, &maps[1]),
                tex(8, &maps[2]),
                tex(9, &maps[3]),
                tex(10, &maps[4]),
                sampler(11, &self.surface_sampler),
                tex(12, &gpu.penumbra_lut),
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
                Some(color_attachment(t.view(HdrTarget::Diffuse), false)),
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
    /// look from `inputs` and `s`.
    pub fn uniforms(
        &self,
        framing: &Framing,
        cl: &CameraLight,
        inputs: &ProfileInputs,
        s: &RenderSettings,
    ) -> SceneUniforms {
        let rad = framing.radius;
        let mm_per_unit = 1000.0 * framing.metres_per_unit;
        let point = framing.point_light(s);
        let pre = match s.texturing {
            TexturingMode::PostScatter => 0.0,
            TexturingMode::PreAndPostScatter => 0.5,
        };
        let [ar, ag, ab] = inputs.surface_albedo;
        let [tr, tg, tb] = s.transmission_tint;
        let [nr, ng, nb] = inputs.normal_blend;
        let modes = self.maps.modes;
        SceneUniforms {
            clip_from_world: (cl.projection * cl.view).to_cols_array_2d(),
            view_from_world: cl.view.to_cols_array_2d(),
            camera_position: cl.eye.extend(1.0).into(),
            light_direction: match &point {
                Some(p) => p.position.extend(1.0).into(),
                None => cl.light.extend(0.0).into(),
            },
            light_range: match &point {
                Some(p) => [p.near, p.far, p.distance, 0.0],
                None => [0.0; 4],
            },
            light_radiance: [s.light_intensity; 4],
            surface_albedo: [ar, ag, ab, 0.0],
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
            light_clip_from_world: cl.light_clip.to_cols_array_2d(),
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
                mm_per_unit,
            ],
            transmission_tint: [tr, tg, tb, 0.0],
            preintegrated: sss::preintegrated::uniforms(s.method, &inputs.lut_layout),
            preintegrated_normals: [nr, ng, nb, if s.penumbra { 1.0 } else { 0.0 }],
            surface: [modes[0], modes[1], modes[2], s.detail_normal_strength],
            environment_sh: s.environment_sh.map(|c| [c[0], c[1], c[2], 0.0]),
            eyes: framing.eyes,
            penumbra: [
                1.0 / inputs.penumbra_layout.penumbra_max_mm as f32,
                1.0 / inputs.penumbra_layout.penumbra_min_mm as f32,
                // The PCF's 4-texel footprint, in mm.
                4.0 * 2.0 * rad / SHADOW_SIZE as f32 * 1000.0 * framing.metres_per_unit,
                0.0,
            ],
            pattern: match s.pattern {
                IrradiancePattern::Lit => [0.0; 4],
                IrradiancePattern::Step => [1.0, 0.0, 0.0, 0.0],
                IrradiancePattern::Checkerboard { period_mm } => {
                    [2.0, period_mm / mm_per_unit, 0.0, 0.0]
                }
            },
        }
    }
}
