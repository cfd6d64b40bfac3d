//! `burley` (Golubev 2018, `shaders/sss_burley.wgsl`): one pass over an
//! importance-sampled disk with per-pixel rotation, energy-normalised
//! bilateral weights on the Euclidean distance and a discrete LOD. At a
//! high count (`--samples 2304`) it is the converged screen-space Burley
//! the sample-count studies compare against; the ground truth is
//! `reference` (`sss/reference.rs`), which shares its irradiance (light,
//! shadow map, PCF, maps) but none of its disk, pixel grid or weights.

use super::{Scattered, SssFrame, SssPipelines};
use crate::model::sampling::{AngleSequence, SamplePattern};
use crate::model::{ModelError, RadialProfile, Rgb};
use crate::render::frame::{buf, tex, FrameEncoder};
use crate::render::gpu_types::GpuSample;
use crate::render::gpu_types::{BurleyUniforms, SssUniforms};
use crate::render::pipelines::{
    buffer_entry, fullscreen_pipeline, texture_entry, uniform_entry, Output, Stencil, HDR,
};
use crate::render::profile_gpu::storage;
use crate::render::settings::BurleySampling;
use crate::render::targets::HdrTarget;

/// `burley` in the registry (`sss::Method::sss`).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "burley",
    label: "burley (Golubev 2018 disk)",
    quality: super::Quality::Samples,
    stochastic: super::Stochastic::Always,
    reads: super::Reads {
        separable_kernel: false,
        penner_tables: false,
        gaussians: false,
    },
    penner_in_scene_pass: false,
    ground_truth: false,
    baseline: false,
    variant: "",
    shader: Some((
        "sss_burley",
        include_str!("../../../shaders/sss_burley.wgsl"),
    )),
    colour: [31, 119, 180],
    encode,
};

/// `burley`'s share of the profile on the GPU.
pub(in crate::render) struct Buffers {
    /// The main pattern followed by the LOD's short one.
    samples: wgpu::Buffer,
    /// r·R_N(r) per channel (the weights), then the CDF.
    profile_lut: wgpu::Buffer,
    /// Samples of the main pattern.
    count: u32,
    /// Low-LOD count, filter radius (the widest channel's 0.997-energy
    /// radius, mm) and sampling flags; `lod_on` is set per frame.
    uniforms: BurleyUniforms,
}

impl Buffers {
    pub fn new(device: &wgpu::Device, inputs: &Inputs) -> Self {
        let mut samples = inputs.samples.clone();
        samples.extend_from_slice(&inputs.low_samples);
        Self {
            samples: storage(device, "burley samples", bytemuck::cast_slice(&samples)),
            profile_lut: storage(device, "profile lut", bytemuck::cast_slice(&inputs.lut)),
            count: inputs.samples.len() as u32,
            uniforms: BurleyUniforms {
                low_count: inputs.low_samples.len() as u32,
                filter_radius_mm: inputs.filter_radius_mm,
                lod_on: 0,
                flags: inputs.sampling.shader_flags(),
            },
        }
    }
}

/// `burley`'s layout and pipeline (`fs_burley`, testing the stencil).
pub(in crate::render) struct Pipeline {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl Pipeline {
    pub fn new(device: &wgpu::Device, module: &wgpu::ShaderModule) -> Self {
        let storage = wgpu::BufferBindingType::Storage { read_only: true };
        let frag = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sss burley"),
            entries: &[
                uniform_entry::<SssUniforms>(0, frag),
                texture_entry(1),
                texture_entry(2),
                buffer_entry(3, storage, frag),
                buffer_entry(4, storage, frag),
                buffer_entry(
                    5,
                    wgpu::BufferBindingType::Storage { read_only: false },
                    frag,
                ),
                uniform_entry::<BurleyUniforms>(6, frag),
            ],
        });
        Self {
            pipeline: fullscreen_pipeline(
                device,
                module,
                "fs_burley",
                &layout,
                Output::Replace(HDR),
                Stencil::Test,
            ),
            layout,
        }
    }
}

pub(in crate::render) fn encode(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
) -> Scattered {
    let gpu = &io.profile.methods.burley;
    let (samples, n, label) = (&gpu.samples, gpu.count, "sss burley");
    let u = f.uniform("sss uniforms", bytemuck::bytes_of(&io.uniforms(n)));
    let lod = f.uniform(
        "burley uniforms",
        bytemuck::bytes_of(&BurleyUniforms {
            lod_on: io.lod as u32,
            ..gpu.uniforms
        }),
    );
    let t = io.targets;
    let bg = f.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &p.burley.layout,
        entries: &[
            buf(0, &u),
            tex(1, t.view(HdrTarget::Diffuse)),
            tex(2, &t.linear_depth),
            buf(3, samples),
            buf(4, &gpu.profile_lut),
            buf(5, io.counters),
            buf(6, &lod),
        ],
    });
    f.fullscreen(
        Some(t.view(HdrTarget::Ping)),
        &p.burley.pipeline,
        &bg,
        label,
        (io.sss_pixels, io.sss_pixels * n as u64),
        false,
        true,
    );
    Scattered {
        target: HdrTarget::Ping,
        samples_per_pixel: n,
        counted_pass: Some(label),
    }
}

/// `burley`'s CPU inputs: its sample patterns and the profile table its
/// shader reads (uploaded by [`Buffers`]).
#[derive(Debug, Clone)]
pub struct Inputs {
    pub samples: Vec<GpuSample>,
    /// The short pattern the LOD uses for 1–4 px disks.
    pub low_samples: Vec<GpuSample>,
    /// How it samples (the pattern here, the rest in the shader).
    pub sampling: BurleySampling,
    /// The widest channel's 0.997-energy radius (mm): the LOD's disk size.
    pub filter_radius_mm: f32,
    /// r·R_N(r) per channel, then the CDF ([`profile_lut`]).
    pub lut: Vec<[f32; 4]>,
    /// The radius (mm) the table reaches: the 0.999-energy radius.
    pub lut_radius_mm: f32,
}

/// Entries of each half of `burley`'s profile table.
pub(in crate::render) const LUT_SIZE: usize = 256;

impl Inputs {
    /// The default sampling's patterns of `samples` and the table out to
    /// `r_max` (mm), for a profile of total reflectance `total`.
    pub fn new(
        profile: &dyn RadialProfile,
        samples: usize,
        r_max: f64,
        total: Rgb,
    ) -> Result<Self, ModelError> {
        let sampling = BurleySampling::default();
        let (samples, low_samples) = burley_patterns(profile, samples, sampling)?;
        let filter_radius_mm = profile
            .radius_for_energy(crate::model::DEFAULT_ENERGY_FRACTION)
            .into_iter()
            .fold(0.0, f64::max) as f32;
        Ok(Self {
            samples,
            low_samples,
            sampling,
            filter_radius_mm,
            lut: profile_lut(profile, r_max, total),
            lut_radius_mm: r_max as f32,
        })
    }

    /// Rebuilds the patterns for another count or sampling strategy.
    pub fn set_patterns(
        &mut self,
        profile: &dyn RadialProfile,
        samples: usize,
        sampling: BurleySampling,
    ) -> Result<(), ModelError> {
        (self.samples, self.low_samples) = burley_patterns(profile, samples, sampling)?;
        self.sampling = sampling;
        Ok(())
    }

    /// Feeds everything the GPU receives from these inputs to `h`.
    pub fn fingerprint_into(&self, h: &mut impl std::hash::Hasher) {
        h.write(bytemuck::cast_slice(&self.samples));
        h.write(bytemuck::cast_slice(&self.low_samples));
        h.write(bytemuck::cast_slice(&self.lut));
        let b = self.sampling;
        h.write(&[b.shader_flags() as u8, b.mis as u8, b.antithetic as u8]);
        h.write(bytemuck::cast_slice(&[
            self.filter_radius_mm,
            self.lut_radius_mm,
        ]));
    }
}

/// The full and the short (LOD) `burley` pattern: Golubev 2018's quantiles
/// of the widest channel, in antithetic pairs, or MIS across the channels.
fn burley_patterns(
    profile: &dyn RadialProfile,
    samples: usize,
    sampling: BurleySampling,
) -> Result<(Vec<GpuSample>, Vec<GpuSample>), ModelError> {
    let pattern = |n| {
        if sampling.antithetic {
            SamplePattern::new_antithetic(profile, n, AngleSequence::GoldenAngle)
        } else if sampling.mis {
            SamplePattern::new_mis(profile, n, AngleSequence::GoldenAngle)
        } else {
            SamplePattern::new(profile, n, AngleSequence::GoldenAngle)
        }
    };
    // The shader weighs a sample by R(ρ)/q(r): inv_pdf = 1/q.
    let gpu = |p: SamplePattern| -> Vec<GpuSample> {
        p.samples
            .iter()
            .map(|s| GpuSample {
                radius_mm: s.radius_mm as f32,
                angle: s.angle_rad as f32,
                inv_pdf: if s.density_per_mm2 > 0.0 {
                    (1.0 / s.density_per_mm2) as f32
                } else {
                    0.0
                },
                pad: 0.0,
            })
            .collect()
    };
    Ok((
        gpu(pattern(samples)?),
        gpu(pattern((samples / 3).clamp(5, samples.max(5)))?),
    ))
}

/// r·R(r)/total per channel at r = r_max·t², t = i/(LUT_SIZE − 1), then
/// the CDF at the same radii (Burley's weights and centre weight;
/// `shaders/sss_burley.wgsl` reads both halves).
fn profile_lut(profile: &dyn RadialProfile, r_max: f64, total: Rgb) -> Vec<[f32; 4]> {
    (0..LUT_SIZE)
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
        // Then the CDF at the same radii (Burley's centre weight).
        .chain((0..LUT_SIZE).map(|i| {
            let t = i as f64 / (LUT_SIZE - 1) as f64;
            let c = profile.cdf(r_max * t * t);
            [c[0] as f32, c[1] as f32, c[2] as f32, 0.0]
        }))
        .collect()
}
