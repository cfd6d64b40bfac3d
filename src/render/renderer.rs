//! The frame: scene pass → SSS pass(es) → composite, all offscreen.

use super::context::{GpuContext, GpuError};
use super::gpu_types::{CompositeUniforms, GpuSample, GpuTap, SceneUniforms, SssUniforms};
use super::mesh::Mesh;
use crate::model::sampling::{AngleSequence, SamplePattern};
use crate::model::separable::SeparableKernel;
use crate::model::{ModelError, RadialProfile};
use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

/// Screen-space SSS methods implemented so far.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Plain diffuse, the baseline.
    None,
    /// Golubev 2018 importance-sampled disk.
    Burley,
    /// Jimenez 2012 two-pass separable blur.
    Separable,
    /// The profile as a sum of Gaussians, each blurred in two depth-aware 1D
    /// passes (d'Eon 2007 in screen space, Jimenez 2009): 12 passes for 6.
    Gaussians,
    /// Penner 2011 pre-integrated skin: D(θ, curvature) from a lookup table
    /// in the scene pass, no screen-space pass.
    Preintegrated,
    /// Brute-force convolution with the exact profile on a dense polar grid
    /// (48 rings at the dominant channel's quantiles × 48 angles): ground truth.
    Reference,
}

impl Method {
    pub fn id(self) -> &'static str {
        match self {
            Method::None => "none",
            Method::Burley => "burley",
            Method::Separable => "separable",
            Method::Reference => "reference",
            Method::Gaussians => "gaussians",
            Method::Preintegrated => "preintegrated",
        }
    }
}

/// Where the albedo is applied (d'Eon 2007; seed 000 §2).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TexturingMode {
    PostScatter,
    PreAndPostScatter,
}

/// What one frame looks like.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    pub width: u32,
    pub height: u32,
    pub method: Method,
    pub texturing: TexturingMode,
    /// Camera orbit around the head: yaw and pitch (radians), distance (m).
    pub camera_yaw: f32,
    pub camera_pitch: f32,
    pub camera_distance_m: f32,
    pub fov_y: f32,
    /// Direction towards the light: azimuth and elevation (radians).
    pub light_azimuth: f32,
    pub light_elevation: f32,
    pub light_intensity: f32,
    pub skin_albedo: [f32; 3],
    pub exposure: f32,
    /// Turns off per-pixel random rotation (for tests).
    pub deterministic: bool,
    /// Lighting, or a flat irradiance test pattern.
    pub pattern: IrradiancePattern,
    pub transmission: Transmission,
    pub transmission_tint: [f32; 3],
    /// Burley's discrete LOD (no convolution under 1 px, short pattern under 4 px).
    pub lod: bool,
    pub specular: Specular,
}

/// The specular model (its own buffer; never blurred).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Specular {
    /// Unreal's dual GGX: two roughnesses mixed by `lobe_mix`.
    DualGgx {
        roughness0: f32,
        roughness1: f32,
        lobe_mix: f32,
    },
    /// Kelemen/Szirmay-Kalos with a Beckmann lobe (d'Eon 2007).
    Kelemen { roughness: f32 },
}

/// Light transmitted through thin parts (ears, nostrils).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Transmission {
    Off,
    /// Baked thickness, shadowing shared with the front face (Jimenez 2010).
    ThinObject,
    /// max(baked, shadow-map) thickness, unshadowed (Golubev 2018).
    ThickObject,
}

/// Irradiance for test scenes: lit normally, a step at world x = 0, or a
/// checkerboard, each of irradiance light_intensity (flat, unshaded).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum IrradiancePattern {
    Lit,
    Step,
    Checkerboard { period_mm: f32 },
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            width: 512,
            height: 512,
            method: Method::Burley,
            texturing: TexturingMode::PreAndPostScatter,
            camera_yaw: 0.35,
            camera_pitch: 0.05,
            camera_distance_m: 0.55,
            fov_y: 30f32.to_radians(),
            light_azimuth: 1.25,
            light_elevation: 0.35,
            light_intensity: 3.2,
            skin_albedo: [0.56, 0.33, 0.25],
            exposure: 1.0,
            deterministic: false,
            pattern: IrradiancePattern::Lit,
            transmission: Transmission::ThinObject,
            transmission_tint: [1.0, 1.0, 1.0],
            lod: true,
            // Unreal's SubsurfaceProfile defaults: Roughness0 0.75 and
            // Roughness1 1.30 as multipliers of a material roughness of
            // 0.55, LobeMix 0.15.
            specular: Specular::DualGgx {
                roughness0: 0.41,
                roughness1: 0.72,
                lobe_mix: 0.15,
            },
        }
    }
}

/// Per-profile GPU inputs, computed on the CPU and rebuilt only when the
/// profile or the counts change.
#[derive(Debug, Clone)]
pub struct ProfileInputs {
    pub samples: Vec<GpuSample>,
    /// The dense stratified pattern of the `reference` method.
    pub reference_samples: Vec<GpuSample>,
    /// The short pattern the Burley LOD uses for 1–4 px disks.
    pub low_samples: Vec<GpuSample>,
    /// The widest channel's 0.997-energy radius (mm): the LOD's disk size.
    pub filter_radius_mm: f32,
    /// False when no channel scatters (e.g. Jimenez strength 0): SSS passes are skipped.
    pub scatters: bool,
    /// Normalised thin-slab transmittance T(d)/total at d = range·i/63.
    pub transmittance: Vec<[f32; 4]>,
    pub transmittance_range_mm: f32,
    /// Penner's D(θ, κ) table (row-major, 64×64) and its layout.
    pub preintegrated_lut: Vec<[f32; 4]>,
    pub lut_layout: crate::model::lut::LutLayout,
    /// (σ mm, normalised RGB weight) of each Gaussian for the `gaussians`
    /// method; empty until [`ProfileInputs::set_gaussians`].
    pub gaussians: Vec<(f32, [f32; 3])>,
    pub lut: Vec<[f32; 4]>,
    pub lut_radius_mm: f32,
    pub taps: Vec<GpuTap>,
}

const LUT_SIZE: usize = 256;

impl ProfileInputs {
    /// Burley disk samples, the r·R_N(r) table and separable taps for `profile`.
    pub fn new(
        profile: &dyn RadialProfile,
        samples: usize,
        taps: usize,
    ) -> Result<Self, ModelError> {
        let pattern = SamplePattern::new(profile, samples, AngleSequence::GoldenAngle)?;
        let total = profile.total_reflectance();
        let dom = pattern.sampled_channel;
        // w = R(ρ)/pdf with the planar area density pdf = R_dom(r)/A_dom.
        let gpu_sample = |radius: f64, angle: f64| {
            let rr = profile.r_reflectance(radius)[dom];
            let inv_pdf = if rr > 0.0 {
                total[dom] * radius / rr
            } else {
                0.0
            };
            GpuSample {
                radius_mm: radius as f32,
                angle: angle as f32,
                inv_pdf: inv_pdf as f32,
                pad: 0.0,
            }
        };
        let gpu_samples = pattern
            .samples
            .iter()
            .map(|s| gpu_sample(s.radius_mm, s.angle_rad))
            .collect();
        let low = SamplePattern::new(
            profile,
            (samples / 3).clamp(5, samples.max(5)),
            AngleSequence::GoldenAngle,
        )?;
        let low_samples = low
            .samples
            .iter()
            .map(|s| gpu_sample(s.radius_mm, s.angle_rad))
            .collect();
        let filter_radius_mm = profile
            .radius_for_energy(crate::model::DEFAULT_ENERGY_FRACTION)
            .into_iter()
            .fold(0.0, f64::max) as f32;
        // Reference: rings at the quantiles (i + ½)/48, angles (j + ½·(i mod 2))/48.
        const RINGS: usize = 48;
        let reference_samples = (0..RINGS)
            .flat_map(|i| {
                let r = profile.inverse_cdf(dom, (i as f64 + 0.5) / RINGS as f64);
                (0..RINGS).map(move |j| {
                    (
                        r,
                        std::f64::consts::TAU * (j as f64 + 0.5 * (i % 2) as f64) / RINGS as f64,
                    )
                })
            })
            .map(|(r, a)| gpu_sample(r, a))
            .collect();
        let r_max = profile
            .radius_for_energy(0.999)
            .into_iter()
            .fold(1e-6, f64::max);
        let lut = (0..LUT_SIZE)
            .map(|i| {
                let t = i as f64 / (LUT_SIZE - 1) as f64;
                let rr = profile.r_reflectance(r_max * t * t);
                let n = |c: usize| {
                    if total[c] > 0.0 {
                        (rr[c] / total[c]) as f32
                    } else {
                        0.0
                    }
                };
                [n(0), n(1), n(2), 0.0]
            })
            .collect();
        let kernel = SeparableKernel::importance_sampled(profile, taps)?;
        let taps = kernel
            .taps
            .iter()
            .map(|t| GpuTap {
                weight_offset: [
                    t.weight[0] as f32,
                    t.weight[1] as f32,
                    t.weight[2] as f32,
                    t.offset_mm as f32,
                ],
            })
            .collect();
        let lut_layout = crate::model::lut::LutLayout {
            width: 64,
            height: 64,
            curvature_radius_min_mm: 2.0,
            curvature_radius_max_mm: 200.0,
        };
        let preintegrated_lut = crate::model::lut::Lut::bake(profile, lut_layout)?
            .d
            .iter()
            .map(|v| [v[0] as f32, v[1] as f32, v[2] as f32, 1.0])
            .collect();
        let transmittance_range_mm = r_max as f32;
        let transmittance = (0..64)
            .map(|i| {
                let t = profile.transmittance(r_max * i as f64 / 63.0);
                let n = |c: usize| {
                    if total[c] > 0.0 {
                        (t[c] / total[c]) as f32
                    } else {
                        0.0
                    }
                };
                [n(0), n(1), n(2), 0.0]
            })
            .collect();
        let dirac = profile.dirac_weight();
        let scatters = (0..3).any(|c| total[c] - dirac[c] > 1e-9 * total[c].max(1e-300));
        Ok(Self {
            low_samples,
            filter_radius_mm,
            scatters,
            samples: gpu_samples,
            reference_samples,
            transmittance,
            transmittance_range_mm,
            preintegrated_lut,
            lut_layout,
            gaussians: Vec::new(),
            lut,
            lut_radius_mm: r_max as f32,
            taps,
        })
    }
}

impl ProfileInputs {
    /// Replaces the separable taps (e.g. with the Jimenez 2012 demo kernel
    /// of a Jimenez 2012 profile instead of the pre-integrated one).
    pub fn set_separable_kernel(&mut self, kernel: &SeparableKernel) {
        self.taps = kernel
            .taps
            .iter()
            .map(|t| GpuTap {
                weight_offset: [
                    t.weight[0] as f32,
                    t.weight[1] as f32,
                    t.weight[2] as f32,
                    t.offset_mm as f32,
                ],
            })
            .collect();
    }

    /// Sets the Gaussians of the `gaussians` method from (variance mm²,
    /// RGB weight) terms; weights are normalised per channel (the albedo is
    /// applied separately).
    pub fn set_gaussians(&mut self, terms: &[(f64, [f64; 3])]) {
        let sum = [0, 1, 2].map(|c| terms.iter().map(|t| t.1[c]).sum::<f64>());
        self.gaussians = terms
            .iter()
            .map(|(v, w)| {
                (
                    v.sqrt() as f32,
                    [0, 1, 2].map(|c| {
                        if sum[c] > 0.0 {
                            (w[c] / sum[c]) as f32
                        } else {
                            0.0
                        }
                    }),
                )
            })
            .collect();
    }
}

/// Taps of a normalised 1D Gaussian of standard deviation σ (mm): 13
/// offsets over ±3σ, weights ∝ e^(−x²/2σ²) summing to one, centre first.
pub fn gaussian_taps(sigma_mm: f32) -> Vec<GpuTap> {
    let n = 13;
    let offsets: Vec<f32> = (0..n)
        .map(|j| (j as f32 - 6.0) / 6.0 * 3.0 * sigma_mm)
        .collect();
    let w: Vec<f32> = offsets
        .iter()
        .map(|o| (-o * o / (2.0 * sigma_mm * sigma_mm)).exp())
        .collect();
    let sum: f32 = w.iter().sum();
    let mut taps: Vec<GpuTap> = offsets
        .iter()
        .zip(&w)
        .map(|(o, w)| GpuTap {
            weight_offset: [w / sum, w / sum, w / sum, *o],
        })
        .collect();
    let centre = taps.remove(6);
    taps.insert(0, centre);
    taps
}

/// What a frame did (proof of skipped work comes with later passes).
#[derive(Debug, Clone, PartialEq)]
pub struct FrameStats {
    pub method: &'static str,
    pub passes: Vec<&'static str>,
    pub samples_per_sss_pixel: u32,
    /// Pixels whose SSS mask exceeds 1/255, counted on the GPU.
    pub sss_pixels: u64,
    /// Samples the SSS passes took: counted on the GPU for burley and
    /// reference, sss_pixels × taps for the separable methods.
    pub sss_samples: u64,
    /// Pixels the Burley LOD left unconvolved (disk under one pixel).
    pub lod_skipped_pixels: u64,
    /// GPU time of the SSS passes (ms) from timestamp queries, where the
    /// adapter has them (on lavapipe the "GPU" is the CPU).
    pub sss_gpu_ms: Option<f64>,
    pub width: u32,
    pub height: u32,
    pub adapter: String,
}

const SHADOW_SIZE: u32 = 1024;
const HDR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;
const DEPTH_CHANNEL: wgpu::TextureFormat = wgpu::TextureFormat::Rgba32Float;
const OUTPUT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

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
}

fn texture_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

fn buffer_entry(
    binding: u32,
    ty: wgpu::BufferBindingType,
    stages: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: stages,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    }
}

const FULLSCREEN: &str = include_str!("../../shaders/fullscreen.wgsl");
const SSS_COMMON: &str = include_str!("../../shaders/sss_common.wgsl");

/// Every WGSL module the renderer builds, as (name, full source) pairs;
/// the tests validate each with naga.
pub fn shader_sources() -> Vec<(&'static str, String)> {
    vec![
        ("scene", include_str!("../../shaders/scene.wgsl").to_owned()),
        (
            "classify",
            include_str!("../../shaders/classify.wgsl").to_owned(),
        ),
        (
            "sss_burley",
            format!(
                "{FULLSCREEN}\n{SSS_COMMON}\n{}",
                include_str!("../../shaders/sss_burley.wgsl")
            ),
        ),
        (
            "sss_separable",
            format!(
                "{FULLSCREEN}\n{SSS_COMMON}\n{}",
                include_str!("../../shaders/sss_separable.wgsl")
            ),
        ),
        (
            "composite",
            format!(
                "{FULLSCREEN}\n{}",
                include_str!("../../shaders/composite.wgsl")
            ),
        ),
    ]
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
                timestamp_writes: None,
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
        match pollster::block_on(scope.pop()) {
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
            light_clip_from_world: (light_proj * light_view).to_cols_array_2d(),
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
        let mut passes = vec!["shadow", "scene"];
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame"),
        });
        {
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
        let sss_pixels = self.count_sss_pixels(encoder, &t.diffuse)?;
        let mut encoder = device.create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("frame sss"),
        });
        passes.push("classify");
        let method = if sss_pixels > 0 && inputs.scatters {
            s.method
        } else {
            Method::None
        };
        // Timestamps around the SSS passes: two empty compute passes mark them.
        let timer = self.ctx.timestamps.then(|| {
            let set = device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("sss time"),
                ty: wgpu::QueryType::Timestamp,
                count: 2,
            });
            let resolve = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sss time resolve"),
                size: 16,
                usage: wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
                mapped_at_creation: false,
            });
            let read = device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("sss time readback"),
                size: 16,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            (set, resolve, read)
        });
        let mark = |encoder: &mut wgpu::CommandEncoder, index: u32| {
            if let Some((set, _, _)) = &timer {
                encoder.begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some("sss timestamp"),
                    timestamp_writes: Some(wgpu::ComputePassTimestampWrites {
                        query_set: set,
                        beginning_of_pass_write_index: Some(index),
                        end_of_pass_write_index: None,
                    }),
                });
            }
        };
        mark(&mut encoder, 0);
        fn tex(binding: u32, view: &wgpu::TextureView) -> wgpu::BindGroupEntry<'_> {
            wgpu::BindGroupEntry {
                binding,
                resource: wgpu::BindingResource::TextureView(view),
            }
        }
        let mut scattered = &t.diffuse;
        let mut scattered_tex = &t.diffuse_tex;
        let mut samples_per_pixel = 0;
        let fullscreen = |encoder: &mut wgpu::CommandEncoder,
                          target: &wgpu::TextureView,
                          pipeline: &wgpu::RenderPipeline,
                          bg: &wgpu::BindGroup,
                          label| {
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
        let mut counted = false;
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
                fullscreen(&mut encoder, &t.ping, &self.burley_pipeline, &bg, label);
                keep.extend([u, smp, lut, lod_u]);
                counted = true;
                scattered = &t.ping;
                scattered_tex = &t.ping_tex;
                samples_per_pixel = list.len() as u32;
                passes.push(label);
            }
            Method::Separable => {
                let taps = storage("taps", bytemuck::cast_slice(&inputs.taps));
                let n = inputs.taps.len() as f32;
                for (dir, src, dst, label) in [
                    ([1.0, 0.0], &t.diffuse, &t.ping, "sss separable x"),
                    ([0.0, 1.0], &t.ping, &t.pong, "sss separable y"),
                ] {
                    let u = uniform("sss uniforms", bytemuck::bytes_of(&sss_u(n, dir)));
                    let bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
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
                    });
                    fullscreen(&mut encoder, dst, &self.separable_pipeline, &bg, label);
                    keep.push(u);
                    passes.push(label);
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
                    ..Default::default()
                });
                for (k, (sigma, weight)) in inputs.gaussians.iter().enumerate() {
                    let taps = storage(
                        "gaussian taps",
                        bytemuck::cast_slice(&gaussian_taps(*sigma)),
                    );
                    let bind = |u: &wgpu::Buffer, src: &wgpu::TextureView, label| {
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
                    for (dir, src, dst, label) in [
                        ([1.0, 0.0], &t.diffuse, &t.ping, "sss gaussian x"),
                        ([0.0, 1.0], &t.ping, &t.pong, "sss gaussian y"),
                    ] {
                        let u = uniform("sss uniforms", bytemuck::bytes_of(&sss_u(13.0, dir)));
                        fullscreen(
                            &mut encoder,
                            dst,
                            &self.separable_pipeline,
                            &bind(&u, src, label),
                            label,
                        );
                        keep.push(u);
                        passes.push(label);
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
                            ..Default::default()
                        });
                        pass.set_pipeline(&self.accumulate_pipeline);
                        pass.set_bind_group(0, &bg, &[]);
                        pass.draw(0..3, 0..1);
                    }
                    let _ = k;
                    keep.extend([u, taps]);
                }
                scattered = &t.accum;
                scattered_tex = &t.accum_tex;
                samples_per_pixel = 2 * 13 * inputs.gaussians.len() as u32;
            }
        }
        mark(&mut encoder, 1);
        encoder.copy_buffer_to_buffer(&counters, 0, &counters_read, 0, 16);
        if let Some((set, resolve, read)) = &timer {
            encoder.resolve_query_set(set, 0..2, resolve, 0);
            encoder.copy_buffer_to_buffer(resolve, 0, read, 0, 16);
        }
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
            &output_view,
            &self.composite_pipeline,
            &cbg,
            "composite",
        );
        passes.push("composite");
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
        let sss_gpu_ms = match &timer {
            Some((_, _, read)) if samples_per_pixel > 0 => {
                read_timestamps(&self.ctx, read).map(|(a, b)| {
                    b.saturating_sub(a) as f64 * self.ctx.queue.get_timestamp_period() as f64 * 1e-6
                })
            }
            _ => None,
        };
        let measured = if counted {
            read_u32x4(&self.ctx, &counters_read)
        } else {
            None
        };
        let (sss_samples, lod_skipped_pixels) = match measured {
            Some(c) => (c[0] as u64, c[2] as u64),
            None => (sss_pixels * samples_per_pixel as u64, 0),
        };
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
        Ok((image, diffuse, stats))
    }
}

/// Maps a 4 × u32 buffer (already copied and submitted).
fn read_u32x4(ctx: &GpuContext, read: &wgpu::Buffer) -> Option<[u32; 4]> {
    let (tx, rx) = std::sync::mpsc::channel();
    read.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.device.poll(wgpu::PollType::wait_indefinitely()).ok()?;
    rx.recv().ok()?.ok()?;
    let data = read.slice(..).get_mapped_range().ok()?;
    let v: &[u32] = bytemuck::cast_slice(&data);
    let out = [v[0], v[1], v[2], v[3]];
    drop(data);
    read.unmap();
    Some(out)
}

/// Maps a resolved 2-timestamp buffer (already copied and submitted).
fn read_timestamps(ctx: &GpuContext, read: &wgpu::Buffer) -> Option<(u64, u64)> {
    let (tx, rx) = std::sync::mpsc::channel();
    read.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.device.poll(wgpu::PollType::wait_indefinitely()).ok()?;
    rx.recv().ok()?.ok()?;
    let data = read.slice(..).get_mapped_range().ok()?;
    let v: &[u64] = bytemuck::cast_slice(&data);
    let out = (v[0], v[1]);
    drop(data);
    read.unmap();
    Some(out)
}

/// f32 → IEEE 754 binary16, round to nearest (for Rgba16Float uploads of
/// values well inside the half range; tiny values flush to zero).
pub fn f32_to_half(x: f32) -> u16 {
    let bits = x.to_bits();
    let sign = ((bits >> 16) & 0x8000) as u16;
    let exp = ((bits >> 23) & 0xff) as i32 - 127 + 15;
    let mant = bits & 0x7f_ffff;
    if x.is_nan() {
        return 0x7e00;
    }
    if exp >= 31 {
        return sign | 0x7c00;
    }
    if exp <= 0 {
        return sign;
    }
    let half = sign as u32 | ((exp as u32) << 10) | (mant >> 13);
    // Round to nearest on the dropped bits.
    (half + ((mant >> 12) & 1)) as u16
}

/// IEEE 754 binary16 → f32 (the HDR targets are Rgba16Float).
pub fn half_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let frac = (h & 0x3ff) as f32;
    sign * match exp {
        0 => frac * 2f32.powi(-24),
        31 => {
            if frac == 0.0 {
                f32::INFINITY
            } else {
                f32::NAN
            }
        }
        e => (1.0 + frac / 1024.0) * 2f32.powi(e - 15),
    }
}

/// Copies each texture (with its bytes per pixel) into a buffer, submits
/// the frame, waits, and returns tightly packed rows for each.
fn readback(
    ctx: &GpuContext,
    mut encoder: wgpu::CommandEncoder,
    textures: &[(&wgpu::Texture, u32)],
    w: u32,
    h: u32,
) -> Result<Vec<Vec<u8>>, GpuError> {
    let err = |e: String| GpuError::Readback(e);
    let buffers: Vec<(wgpu::Buffer, u32, u32)> = textures
        .iter()
        .map(|&(texture, bpp)| {
            let row = (bpp * w).div_ceil(256) * 256;
            let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: (row * h) as u64,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(h),
                    },
                },
                wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
            );
            (buffer, row, bpp)
        })
        .collect();
    ctx.queue.submit([encoder.finish()]);
    let (tx, rx) = std::sync::mpsc::channel();
    for (buffer, _, _) in &buffers {
        let tx = tx.clone();
        buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
    }
    ctx.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| err(e.to_string()))?;
    for _ in &buffers {
        rx.recv()
            .map_err(|e| err(e.to_string()))?
            .map_err(|e| err(e.to_string()))?;
    }
    let mut out = Vec::new();
    for (buffer, row, bpp) in &buffers {
        let data = buffer
            .slice(..)
            .get_mapped_range()
            .map_err(|e| err(e.to_string()))?;
        let mut pixels = Vec::with_capacity((bpp * w * h) as usize);
        for y in 0..h as usize {
            let start = y * *row as usize;
            pixels.extend_from_slice(&data[start..start + (bpp * w) as usize]);
        }
        drop(data);
        buffer.unmap();
        out.push(pixels);
    }
    Ok(out)
}

fn scene_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("scene"),
        bind_group_layouts: &[Some(layout)],
        ..Default::default()
    });
    let target = |format| {
        Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("scene"),
        layout: Some(&pl),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<super::gpu_types::Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32, 4 => Float32, 5 => Float32],
            })],
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[target(HDR), target(HDR), target(DEPTH_CHANNEL)],
        }),
        primitive: wgpu::PrimitiveState { cull_mode: None, ..Default::default() },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth32Float,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    })
}

fn accumulate_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("accumulate"),
        bind_group_layouts: &[Some(layout)],
        ..Default::default()
    });
    let add = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("accumulate"),
        layout: Some(&pl),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_fullscreen"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_accumulate"),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format: HDR,
                blend: Some(wgpu::BlendState {
                    color: add,
                    alpha: add,
                }),
                write_mask: wgpu::ColorWrites::COLOR,
            })],
        }),
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    })
}

fn shadow_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("shadow"),
        bind_group_layouts: &[Some(layout)],
        ..Default::default()
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("shadow"),
        layout: Some(&pl),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_shadow"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<super::gpu_types::Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
            })],
        },
        fragment: None,
        primitive: wgpu::PrimitiveState {
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth32Float,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: wgpu::DepthBiasState {
                constant: 2,
                slope_scale: 2.0,
                clamp: 0.0,
            },
        }),
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    })
}

fn fullscreen_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    entry: &'static str,
    layout: &wgpu::BindGroupLayout,
    format: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(entry),
        bind_group_layouts: &[Some(layout)],
        ..Default::default()
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(entry),
        layout: Some(&pl),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_fullscreen"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: None,
                write_mask: wgpu::ColorWrites::ALL,
            })],
        }),
        primitive: Default::default(),
        depth_stencil: None,
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    })
}
