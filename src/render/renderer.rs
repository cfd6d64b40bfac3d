//! The frame: scene pass → SSS pass(es) → composite, all offscreen.

use super::context::{GpuContext, GpuError};
use super::gpu_types::{CompositeUniforms, SceneUniforms, SssUniforms};
use super::inputs::LUT_SIZE;
pub use super::inputs::{gaussian_taps, ProfileInputs};
use super::mesh::Mesh;
pub use super::pipelines::shader_sources;
use super::pipelines::{
    accumulate_pipeline, buffer_entry, fullscreen_pipeline, scene_pipeline, shadow_pipeline,
    texture_entry, DEPTH_CHANNEL, HDR, OUTPUT,
};
pub use super::readback::{f32_to_half, half_to_f32};
use super::readback::{read_u32x4, readback};
pub use super::settings::{
    FrameStats, IrradiancePattern, Method, RenderSettings, Specular, TexturingMode, Transmission,
};
use super::timing::PassTimer;
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

const SHADOW_SIZE: u32 = 1024;

struct Targets {
    size: (u32, u32),
    diffuse: wgpu::TextureView,
    specular: wgpu::TextureView,
    albedo_depth: wgpu::TextureView,
    depth: wgpu::TextureView,
    ping: wgpu::TextureView,
    pong: wgpu::TextureView,
    accum: wgpu::TextureView,
    output: wgpu::Texture,
    /// The textures behind `diffuse`, `ping` and `pong` (for HDR readback).
    diffuse_tex: wgpu::Texture,
    ping_tex: wgpu::Texture,
    pong_tex: wgpu::Texture,
    accum_tex: wgpu::Texture,
}

/// Owns the device, the mesh and the pipelines.
pub struct Renderer {
    ctx: GpuContext,
    vertex_buffer: wgpu::Buffer,
    index_buffer: wgpu::Buffer,
    index_count: u32,
    mesh_centre: Vec3,
    metres_per_unit: f32,
    scene_layout: wgpu::BindGroupLayout,
    scene_pipeline: wgpu::RenderPipeline,
    shadow_layout: wgpu::BindGroupLayout,
    shadow_pipeline: wgpu::RenderPipeline,
    shadow_map: wgpu::TextureView,
    shadow_sampler: wgpu::Sampler,
    mesh_radius: f32,
    burley_layout: wgpu::BindGroupLayout,
    burley_pipeline: wgpu::RenderPipeline,
    separable_layout: wgpu::BindGroupLayout,
    separable_pipeline: wgpu::RenderPipeline,
    composite_layout: wgpu::BindGroupLayout,
    composite_pipeline: wgpu::RenderPipeline,
    accumulate_pipeline: wgpu::RenderPipeline,
    classify_layout: wgpu::BindGroupLayout,
    classify_pipeline: wgpu::ComputePipeline,
    targets: Option<Targets>,
    /// The light transform the shadow map was last drawn with: the map
    /// depends only on it and the mesh, so an unchanged light skips the pass.
    shadow_key: Option<[[f32; 4]; 4]>,
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
        let built = ctx.checked("pipeline creation", || {
            let uniform0 = buffer_entry(
                0,
                wgpu::BufferBindingType::Uniform,
                wgpu::ShaderStages::VERTEX_FRAGMENT,
            );
            let scene_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("scene"),
                entries: &[
                    uniform0,
                    wgpu::BindGroupLayoutEntry {
                        binding: 1,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Texture {
                            sample_type: wgpu::TextureSampleType::Depth,
                            view_dimension: wgpu::TextureViewDimension::D2,
                            multisampled: false,
                        },
                        count: None,
                    },
                    wgpu::BindGroupLayoutEntry {
                        binding: 2,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                        count: None,
                    },
                    wgpu::BindGroupLayoutEntry {
                        binding: 3,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Texture {
                            sample_type: wgpu::TextureSampleType::Float { filterable: true },
                            view_dimension: wgpu::TextureViewDimension::D2,
                            multisampled: false,
                        },
                        count: None,
                    },
                    wgpu::BindGroupLayoutEntry {
                        binding: 4,
                        visibility: wgpu::ShaderStages::FRAGMENT,
                        ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                        count: None,
                    },
                    buffer_entry(
                        5,
                        wgpu::BufferBindingType::Storage { read_only: true },
                        wgpu::ShaderStages::FRAGMENT,
                    ),
                ],
            });
            let shadow_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("shadow"),
                entries: &[uniform0],
            });
            let storage = wgpu::BufferBindingType::Storage { read_only: true };
            let frag = wgpu::ShaderStages::FRAGMENT;
            let burley_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("sss burley"),
                entries: &[
                    buffer_entry(0, wgpu::BufferBindingType::Uniform, frag),
                    texture_entry(1),
                    texture_entry(2),
                    buffer_entry(3, storage, frag),
                    buffer_entry(4, storage, frag),
                    buffer_entry(
                        5,
                        wgpu::BufferBindingType::Storage { read_only: false },
                        frag,
                    ),
                    buffer_entry(6, wgpu::BufferBindingType::Uniform, frag),
                ],
            });
            let separable_layout =
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("sss separable"),
                    entries: &[
                        buffer_entry(0, wgpu::BufferBindingType::Uniform, frag),
                        texture_entry(1),
                        texture_entry(2),
                        buffer_entry(3, storage, frag),
                    ],
                });
            let composite_layout =
                device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                    label: Some("composite"),
                    entries: &[
                        buffer_entry(0, wgpu::BufferBindingType::Uniform, frag),
                        texture_entry(1),
                        texture_entry(2),
                        texture_entry(3),
                    ],
                });
            let scene_module = module("scene");
            let scene_pipeline = scene_pipeline(device, &scene_module, &scene_layout);
            let shadow_pipeline = shadow_pipeline(device, &scene_module, &shadow_layout);
            let burley_pipeline = fullscreen_pipeline(
                device,
                &module("sss_burley"),
                "fs_burley",
                &burley_layout,
                HDR,
            );
            let separable_pipeline = fullscreen_pipeline(
                device,
                &module("sss_separable"),
                "fs_separable",
                &separable_layout,
                HDR,
            );
            let composite_pipeline = fullscreen_pipeline(
                device,
                &module("composite"),
                "fs_composite",
                &composite_layout,
                OUTPUT,
            );
            let accumulate_pipeline =
                accumulate_pipeline(device, &module("sss_separable"), &separable_layout);
            let pipelines = (
                scene_pipeline,
                shadow_pipeline,
                burley_pipeline,
                separable_pipeline,
                composite_pipeline,
                accumulate_pipeline,
            );
            (
                scene_layout,
                shadow_layout,
                burley_layout,
                separable_layout,
                composite_layout,
                pipelines,
            )
        })?;
        let (
            scene_layout,
            shadow_layout,
            burley_layout,
            separable_layout,
            composite_layout,
            pipelines,
        ) = built;
        let (
            scene_pipeline,
            shadow_pipeline,
            burley_pipeline,
            separable_pipeline,
            composite_pipeline,
            accumulate_pipeline,
        ) = pipelines;
        let shadow_map = device
            .create_texture(&wgpu::TextureDescriptor {
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
                    | wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            })
            .create_view(&Default::default());
        let shadow_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("shadow pcf"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            compare: Some(wgpu::CompareFunction::LessEqual),
            ..Default::default()
        });
        let (classify_layout, classify_pipeline) = ctx.checked("classify pipeline", || {
            let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some("classify"),
                entries: &[
                    wgpu::BindGroupLayoutEntry {
                        binding: 0,
                        visibility: wgpu::ShaderStages::COMPUTE,
                        ty: wgpu::BindingType::Texture {
                            sample_type: wgpu::TextureSampleType::Float { filterable: false },
                            view_dimension: wgpu::TextureViewDimension::D2,
                            multisampled: false,
                        },
                        count: None,
                    },
                    buffer_entry(
                        1,
                        wgpu::BufferBindingType::Storage { read_only: false },
                        wgpu::ShaderStages::COMPUTE,
                    ),
                ],
            });
            let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("classify"),
                bind_group_layouts: &[Some(&layout)],
                ..Default::default()
            });
            let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some("classify"),
                layout: Some(&pl),
                module: &module("classify"),
                entry_point: Some("cs_classify"),
                compilation_options: Default::default(),
                cache: None,
            });
            (layout, pipeline)
        })?;
        let vertex_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("vertices"),
            contents: bytemuck::cast_slice(&mesh.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
        let index_buffer = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("indices"),
            contents: bytemuck::cast_slice(&mesh.indices),
            usage: wgpu::BufferUsages::INDEX,
        });
        let (lo, hi) = mesh.bounds();
        Ok(Self {
            vertex_buffer,
            index_buffer,
            index_count: mesh.indices.len() as u32,
            mesh_centre: Vec3::from(mesh.focus),
            mesh_radius: 0.5 * (hi - lo).length(),
            shadow_layout,
            shadow_pipeline,
            shadow_map,
            shadow_sampler,
            metres_per_unit: mesh.metres_per_unit,
            scene_layout,
            scene_pipeline,
            burley_layout,
            burley_pipeline,
            separable_layout,
            separable_pipeline,
            composite_layout,
            composite_pipeline,
            accumulate_pipeline,
            classify_layout,
            classify_pipeline,
            targets: None,
            shadow_key: None,
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
        let make = |label, format, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let rt = wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING;
        let view = |t: wgpu::Texture| t.create_view(&Default::default());
        let hdr_rt = rt | wgpu::TextureUsages::COPY_SRC;
        let diffuse_tex = make("diffuse", HDR, hdr_rt);
        let ping_tex = make("sss ping", HDR, hdr_rt);
        let pong_tex = make("sss pong", HDR, hdr_rt);
        let accum_tex = make("sss accumulation", HDR, hdr_rt);
        let output = make(
            "output",
            OUTPUT,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        self.targets = Some(Targets {
            size: (w, h),
            diffuse: diffuse_tex.create_view(&Default::default()),
            specular: view(make("specular", HDR, rt)),
            albedo_depth: view(make("albedo+depth", DEPTH_CHANNEL, rt)),
            depth: view(make(
                "depth",
                wgpu::TextureFormat::Depth32Float,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )),
            ping: ping_tex.create_view(&Default::default()),
            pong: pong_tex.create_view(&Default::default()),
            accum: accum_tex.create_view(&Default::default()),
            output,
            diffuse_tex,
            ping_tex,
            pong_tex,
            accum_tex,
        });
    }

    /// Runs the classification compute pass after the work in `encoder`,
    /// submits, and reads the SSS pixel count back.
    fn count_sss_pixels(
        &self,
        mut encoder: wgpu::CommandEncoder,
        diffuse: &wgpu::TextureView,
        timer: &mut PassTimer,
    ) -> Result<u64, GpuError> {
        let device = &self.ctx.device;
        let counts = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sss counts"),
            contents: bytemuck::cast_slice(&[0u32; 4]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let read = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sss counts readback"),
            size: 16,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        let bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("classify"),
            layout: &self.classify_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: wgpu::BindingResource::TextureView(diffuse),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: counts.as_entire_binding(),
                },
            ],
        });
        let (w, h) = self.targets.as_ref().map_or((0, 0), |t| t.size);
        {
            let mut pass = encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("classify"),
                timestamp_writes: timer.compute("classify", w as u64 * h as u64, 0),
            });
            pass.set_pipeline(&self.classify_pipeline);
            pass.set_bind_group(0, &bg, &[]);
            pass.dispatch_workgroups(w.div_ceil(8), h.div_ceil(8), 1);
        }
        encoder.copy_buffer_to_buffer(&counts, 0, &read, 0, 16);
        self.ctx.queue.submit([encoder.finish()]);
        let (tx, rx) = std::sync::mpsc::channel();
        read.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
        let err = |e: String| GpuError::Readback(e);
        device
            .poll(wgpu::PollType::wait_indefinitely())
            .map_err(|e| err(e.to_string()))?;
        rx.recv()
            .map_err(|e| err(e.to_string()))?
            .map_err(|e| err(e.to_string()))?;
        let data = read
            .slice(..)
            .get_mapped_range()
            .map_err(|e| err(e.to_string()))?;
        let n = u32::from_le_bytes([data[0], data[1], data[2], data[3]]) as u64;
        drop(data);
        read.unmap();
        Ok(n)
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
    /// irradiance (linear HDR, before albedo and tonemapping), row-major RGBA.
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
        // Any validation error in the frame is reported, never panicked on.
        let scope = self
            .ctx
            .device
            .push_error_scope(wgpu::ErrorFilter::Validation);
        let result = self.encode_and_read(inputs, s, want_diffuse);
        let error = pollster::block_on(scope.pop());
        if error.is_some() || result.is_err() {
            // The shadow map may not have been drawn: draw it next time.
            self.shadow_key = None;
        }
        match error {
            Some(e) => Err(GpuError::Validation {
                stage: "frame",
                message: e.to_string(),
            }),
            None => result,
        }
    }

    fn encode_and_read(
        &mut self,
        inputs: &ProfileInputs,
        s: &RenderSettings,
        want_diffuse: bool,
    ) -> Result<(image::RgbaImage, Vec<[f32; 4]>, FrameStats), GpuError> {
        let Some(t) = self.targets.as_ref() else {
            return Err(GpuError::Readback("no targets".into()));
        };
        let ctx = &self.ctx;
        let device = &ctx.device;
        let aspect = s.width as f32 / s.height as f32;
        let dist = s.camera_distance_m / self.metres_per_unit;
        let eye = self.mesh_centre
            + dist
                * Vec3::new(
                    s.camera_yaw.sin() * s.camera_pitch.cos(),
                    s.camera_pitch.sin(),
                    s.camera_yaw.cos() * s.camera_pitch.cos(),
                );
        let view = Mat4::look_at_rh(eye, self.mesh_centre, Vec3::Y);
        let proj = Mat4::perspective_rh(s.fov_y, aspect, 0.05 * dist, 10.0 * dist);
        let light = Vec3::new(
            s.light_azimuth.sin() * s.light_elevation.cos(),
            s.light_elevation.sin(),
            s.light_azimuth.cos() * s.light_elevation.cos(),
        );
        // Orthographic light view around the mesh's bounding sphere.
        let rad = self.mesh_radius;
        let light_view = Mat4::look_at_rh(
            self.mesh_centre + light * 2.0 * rad,
            self.mesh_centre,
            if light.y.abs() > 0.99 {
                Vec3::Z
            } else {
                Vec3::Y
            },
        );
        let light_proj = Mat4::orthographic_rh(-rad, rad, -rad, rad, 0.01 * rad, 4.0 * rad);
        let light_clip = (light_proj * light_view).to_cols_array_2d();
        let shadow_cached = self.shadow_key == Some(light_clip);
        let pre = match s.texturing {
            TexturingMode::PostScatter => 0.0,
            TexturingMode::PreAndPostScatter => 0.5,
        };
        let scene_u = SceneUniforms {
            clip_from_world: (proj * view).to_cols_array_2d(),
            view_from_world: view.to_cols_array_2d(),
            camera_position: eye.extend(1.0).into(),
            light_direction: light.extend(0.0).into(),
            light_radiance: [s.light_intensity; 4],
            sky_radiance: [0.045, 0.05, 0.06, 0.0],
            ground_radiance: [0.02, 0.018, 0.016, 0.0],
            skin_albedo: [s.skin_albedo[0], s.skin_albedo[1], s.skin_albedo[2], 0.0],
            params: match s.specular {
                Specular::DualGgx {
                    roughness0,
                    roughness1,
                    ..
                } => [pre, roughness0, 0.028, roughness1],
                Specular::Kelemen { roughness } => [pre, roughness, 0.028, roughness],
            },
            specular: match s.specular {
                Specular::DualGgx { lobe_mix, .. } => [lobe_mix, 0.0, 0.0, 0.0],
                Specular::Kelemen { .. } => [0.0, 1.0, 0.0, 0.0],
            },
            light_clip_from_world: light_clip,
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
            preintegrated: [
                if s.method == Method::Preintegrated {
                    1.0
                } else {
                    0.0
                },
                1.0 / inputs.lut_layout.curvature_radius(0) as f32,
                1.0 / inputs
                    .lut_layout
                    .curvature_radius(inputs.lut_layout.height - 1) as f32,
                0.0,
            ],
            pattern: match s.pattern {
                IrradiancePattern::Lit => [0.0; 4],
                IrradiancePattern::Step => [1.0, 0.0, 0.0, 0.0],
                IrradiancePattern::Checkerboard { period_mm } => {
                    [2.0, period_mm / (1000.0 * self.metres_per_unit), 0.0, 0.0]
                }
            },
        };
        let uniform = |label, bytes: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::UNIFORM,
            })
        };
        let storage = |label, bytes: &[u8]| {
            device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
                label: Some(label),
                contents: bytes,
                usage: wgpu::BufferUsages::STORAGE,
            })
        };
        let scene_buf = uniform("scene uniforms", bytemuck::bytes_of(&scene_u));
        // Penner's table as a small filterable texture (rebuilt with the profile).
        let lut_tex = device.create_texture_with_data(
            &ctx.queue,
            &wgpu::TextureDescriptor {
                label: Some("pre-integrated lut"),
                size: wgpu::Extent3d {
                    width: inputs.lut_layout.width as u32,
                    height: inputs.lut_layout.height as u32,
                    depth_or_array_layers: 1,
                },
                mip_level_count: 1,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format: wgpu::TextureFormat::Rgba16Float,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            bytemuck::cast_slice(
                &inputs
                    .preintegrated_lut
                    .iter()
                    .flat_map(|v| v.map(f32_to_half))
                    .collect::<Vec<u16>>(),
            ),
        );
        let lut_view = lut_tex.create_view(&Default::default());
        // Rgba16Float: filterable on every adapter (Rgba32Float is not).
        let lut_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("lut"),
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            address_mode_u: wgpu::AddressMode::ClampToEdge,
            address_mode_v: wgpu::AddressMode::ClampToEdge,
            ..Default::default()
        });
        let transmittance_buf = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("transmittance"),
            contents: bytemuck::cast_slice(&inputs.transmittance),
            usage: wgpu::BufferUsages::STORAGE,
        });
        let scene_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("scene"),
            layout: &self.scene_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: scene_buf.as_entire_binding(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: wgpu::BindingResource::TextureView(&self.shadow_map),
                },
                wgpu::BindGroupEntry {
                    binding: 2,
                    resource: wgpu::BindingResource::Sampler(&self.shadow_sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 3,
                    resource: wgpu::BindingResource::TextureView(&lut_view),
                },
                wgpu::BindGroupEntry {
                    binding: 4,
                    resource: wgpu::BindingResource::Sampler(&lut_sampler),
                },
                wgpu::BindGroupEntry {
                    binding: 5,
                    resource: transmittance_buf.as_entire_binding(),
                },
            ],
        });
        let shadow_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("shadow"),
            layout: &self.shadow_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: scene_buf.as_entire_binding(),
            }],
        });
        let sss_u = |n: f32, dir: [f32; 2]| SssUniforms {
            size: [
                s.width as f32,
                s.height as f32,
                1.0 / s.width as f32,
                1.0 / s.height as f32,
            ],
            projection: [
                s.height as f32 / (2.0 * (0.5 * s.fov_y).tan()),
                self.metres_per_unit * 1000.0,
                0.0,
                0.0,
            ],
            params: [
                n,
                if s.deterministic { 1.0 } else { 0.0 },
                inputs.lut_radius_mm,
                LUT_SIZE as f32,
            ],
            direction: [dir[0], dir[1], 0.5, 0.0],
        };
        let (w, h) = (s.width as u64, s.height as u64);
        let mut timer = PassTimer::new(ctx);
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame"),
        });
        if !shadow_cached {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("shadow"),
                color_attachments: &[],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.shadow_map,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.render("shadow", (SHADOW_SIZE * SHADOW_SIZE) as u64, 0),
                ..Default::default()
            });
            pass.set_pipeline(&self.shadow_pipeline);
            pass.set_bind_group(0, &shadow_bg, &[]);
            pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
            pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
        }
        {
            fn color(view: &wgpu::TextureView) -> Option<wgpu::RenderPassColorAttachment<'_>> {
                Some(wgpu::RenderPassColorAttachment {
                    view,
                    resolve_target: None,
                    depth_slice: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })
            }
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("scene"),
                color_attachments: &[
                    color(&t.diffuse),
                    color(&t.specular),
                    color(&t.albedo_depth),
                ],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &t.depth,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Clear(1.0),
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: timer.render("scene", w * h, 0),
                ..Default::default()
            });
            pass.set_pipeline(&self.scene_pipeline);
            pass.set_bind_group(0, &scene_bg, &[]);
            pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
            pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
            pass.draw_indexed(0..self.index_count, 0, 0..1);
        }
        // Classify: count SSS pixels on the GPU; with none on screen, or a
        // profile that does not scatter (strength 0), no SSS pass runs.
        let sss_pixels = self.count_sss_pixels(encoder, &t.diffuse, &mut timer)?;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame sss"),
        });
        let method = if sss_pixels > 0 && inputs.scatters {
            s.method
        } else {
            Method::None
        };
        fn tex(binding: u32, view: &wgpu::TextureView) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(view),
            }
        }
        let mut scattered = &t.diffuse;
        let mut scattered_tex = &t.diffuse_tex;
        let mut samples_per_pixel = 0;
        // One fullscreen triangle into `target`, timed and counted as
        // (pixels, samples).
        let fullscreen = |encoder: &mut wgpu::CommandEncoder,
                          timer: &mut PassTimer,
                          target: &wgpu::TextureView,
                          pipeline: &wgpu::RenderPipeline,
                          bg: &wgpu::BindGroup,
                          label,
                          (pixels, samples): (u64, u64)| {
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some(label),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view: target,
                    resolve_target: None,
                    depth_slice: None,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                timestamp_writes: timer.render(label, pixels, samples),
                ..Default::default()
            });
            pass.set_pipeline(pipeline);
            pass.set_bind_group(0, bg, &[]);
            pass.draw(0..3, 0..1);
        };
        // Buffers must outlive the encoder's submission.
        let mut keep = Vec::new();
        // Samples taken, pixels convolved, pixels skipped by the LOD.
        let counters = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("sss counters"),
            contents: bytemuck::cast_slice(&[0u32; 4]),
            usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        });
        let counters_read = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("sss counters readback"),
            size: 16,
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        // Bind group of one depth-aware 1D pass (separable and gaussians).
        let separable_bg =
            |u: &wgpu::Buffer, src: &wgpu::TextureView, taps: &wgpu::Buffer, label| {
                device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some(label),
                    layout: &self.separable_layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: u.as_entire_binding(),
                        },
                        tex(1, src),
                        tex(2, &t.albedo_depth),
                        wgpu::BindGroupEntry {
                            binding: 3,
                            resource: taps.as_entire_binding(),
                        },
                    ],
                })
            };
        let mut counted = false;
        let mut burley_label = None;
        match method {
            Method::None | Method::Preintegrated => {}
            Method::Burley | Method::Reference => {
                let (list, label) = if method == Method::Burley {
                    (&inputs.samples, "sss burley")
                } else {
                    (&inputs.reference_samples, "sss reference")
                };
                let u = uniform(
                    "sss uniforms",
                    bytemuck::bytes_of(&sss_u(list.len() as f32, [0.0, 0.0])),
                );
                // Main pattern followed by the short LOD pattern.
                let mut all = list.clone();
                let use_lod = s.lod && method == Method::Burley;
                if use_lod {
                    all.extend_from_slice(&inputs.low_samples);
                }
                let smp = storage("samples", bytemuck::cast_slice(&all));
                let lod_u = uniform(
                    "lod",
                    bytemuck::cast_slice(&[
                        inputs.low_samples.len() as f32,
                        inputs.filter_radius_mm,
                        if use_lod { 1.0 } else { 0.0 },
                        0.0,
                    ]),
                );
                let lut = storage("profile lut", bytemuck::cast_slice(&inputs.lut));
                let bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
                    label: Some("burley"),
                    layout: &self.burley_layout,
                    entries: &[
                        wgpu::BindGroupEntry {
                            binding: 0,
                            resource: u.as_entire_binding(),
                        },
                        tex(1, &t.diffuse),
                        tex(2, &t.albedo_depth),
                        wgpu::BindGroupEntry {
                            binding: 3,
                            resource: smp.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 4,
                            resource: lut.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 5,
                            resource: counters.as_entire_binding(),
                        },
                        wgpu::BindGroupEntry {
                            binding: 6,
                            resource: lod_u.as_entire_binding(),
                        },
                    ],
                });
                fullscreen(
                    &mut encoder,
                    &mut timer,
                    &t.ping,
                    &self.burley_pipeline,
                    &bg,
                    label,
                    (sss_pixels, sss_pixels * list.len() as u64),
                );
                burley_label = Some(label);
                keep.extend([u, smp, lut, lod_u]);
                counted = true;
                scattered = &t.ping;
                scattered_tex = &t.ping_tex;
                samples_per_pixel = list.len() as u32;
            }
            Method::Separable => {
                let taps = storage("taps", bytemuck::cast_slice(&inputs.taps));
                let n = inputs.taps.len() as f32;
                for (dir, src, dst, label) in [
                    ([1.0, 0.0], &t.diffuse, &t.ping, "sss separable x"),
                    ([0.0, 1.0], &t.ping, &t.pong, "sss separable y"),
                ] {
                    let u = uniform("sss uniforms", bytemuck::bytes_of(&sss_u(n, dir)));
                    let bg = separable_bg(&u, src, &taps, label);
                    fullscreen(
                        &mut encoder,
                        &mut timer,
                        dst,
                        &self.separable_pipeline,
                        &bg,
                        label,
                        (sss_pixels, sss_pixels * inputs.taps.len() as u64),
                    );
                    keep.push(u);
                }
                keep.push(taps);
                scattered = &t.pong;
                scattered_tex = &t.pong_tex;
                samples_per_pixel = 2 * inputs.taps.len() as u32;
            }
            Method::Gaussians => {
                // Clear the accumulation target once, then per Gaussian:
                // horizontal, vertical, and add weight × result.
                encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                    label: Some("sss gaussians clear"),
                    color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                        view: &t.accum,
                        resolve_target: None,
                        depth_slice: None,
                        ops: wgpu::Operations {
                            load: wgpu::LoadOp::Clear(wgpu::Color::TRANSPARENT),
                            store: wgpu::StoreOp::Store,
                        },
                    })],
                    timestamp_writes: timer.render("sss gaussians clear", w * h, 0),
                    ..Default::default()
                });
                for (sigma, weight) in inputs.gaussians.iter() {
                    let taps = storage(
                        "gaussian taps",
                        bytemuck::cast_slice(&gaussian_taps(*sigma)),
                    );
                    let bind = |u: &wgpu::Buffer, src: &wgpu::TextureView, label| {
                        separable_bg(u, src, &taps, label)
                    };
                    for (dir, src, dst, label) in [
                        ([1.0, 0.0], &t.diffuse, &t.ping, "sss gaussian x"),
                        ([0.0, 1.0], &t.ping, &t.pong, "sss gaussian y"),
                    ] {
                        let u = uniform("sss uniforms", bytemuck::bytes_of(&sss_u(13.0, dir)));
                        fullscreen(
                            &mut encoder,
                            &mut timer,
                            dst,
                            &self.separable_pipeline,
                            &bind(&u, src, label),
                            label,
                            (sss_pixels, sss_pixels * 13),
                        );
                        keep.push(u);
                    }
                    let mut acc_u = sss_u(13.0, [0.0, 0.0]);
                    acc_u.direction = [weight[0], weight[1], weight[2], 0.0];
                    let u = uniform("accumulate uniforms", bytemuck::bytes_of(&acc_u));
                    let bg = bind(&u, &t.pong, "sss gaussian accumulate");
                    {
                        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                            label: Some("sss gaussian accumulate"),
                            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                                view: &t.accum,
                                resolve_target: None,
                                depth_slice: None,
                                ops: wgpu::Operations {
                                    load: wgpu::LoadOp::Load,
                                    store: wgpu::StoreOp::Store,
                                },
                            })],
                            // One load per pixel, over the whole target.
                            timestamp_writes: timer.render("sss gaussian accumulate", w * h, w * h),
                            ..Default::default()
                        });
                        pass.set_pipeline(&self.accumulate_pipeline);
                        pass.set_bind_group(0, &bg, &[]);
                        pass.draw(0..3, 0..1);
                    }
                    keep.extend([u, taps]);
                }
                scattered = &t.accum;
                scattered_tex = &t.accum_tex;
                samples_per_pixel = 2 * 13 * inputs.gaussians.len() as u32;
            }
        }
        encoder.copy_buffer_to_buffer(&counters, 0, &counters_read, 0, 16);
        let cu = uniform(
            "composite uniforms",
            bytemuck::bytes_of(&CompositeUniforms {
                exposure: [s.exposure, 0.0, 0.0, 0.0],
            }),
        );
        let output_view = t.output.create_view(&Default::default());
        let cbg = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("composite"),
            layout: &self.composite_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: cu.as_entire_binding(),
                },
                tex(1, scattered),
                tex(2, &t.specular),
                tex(3, &t.albedo_depth),
            ],
        });
        fullscreen(
            &mut encoder,
            &mut timer,
            &output_view,
            &self.composite_pipeline,
            &cbg,
            "composite",
            (w * h, 0),
        );
        timer.resolve(&mut encoder);
        let mut wanted: Vec<(&wgpu::Texture, u32)> = vec![(&t.output, 4)];
        if want_diffuse {
            wanted.push((scattered_tex, 8));
        }
        let mut bytes = ctx.checked("frame", || {
            readback(ctx, encoder, &wanted, s.width, s.height)
        })??;
        let diffuse = if want_diffuse {
            bytes
                .pop()
                .unwrap_or_default()
                .chunks_exact(8)
                .map(|px| {
                    [0, 1, 2, 3]
                        .map(|k| half_to_f32(u16::from_le_bytes([px[2 * k], px[2 * k + 1]])))
                })
                .collect()
        } else {
            Vec::new()
        };
        let image = image::RgbaImage::from_raw(s.width, s.height, bytes.swap_remove(0))
            .ok_or_else(|| GpuError::Readback("size mismatch".into()))?;
        drop(keep);
        let measured = if counted {
            read_u32x4(&self.ctx, &counters_read)
        } else {
            None
        };
        let (sss_samples, lod_skipped_pixels) = match measured {
            Some(c) => (c[0] as u64, c[2] as u64),
            None => (sss_pixels * samples_per_pixel as u64, 0),
        };
        if let Some(label) = burley_label {
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
            samples_per_sss_pixel: samples_per_pixel,
            sss_pixels,
            sss_samples,
            lod_skipped_pixels,
            sss_gpu_ms,
            width: s.width,
            height: s.height,
            adapter: self.adapter_name(),
        };
        self.shadow_key = Some(light_clip);
        Ok((image, diffuse, stats))
    }
}
