//! `burley` (Golubev 2018, `shaders/sss_burley.wgsl`): one pass over an
//! importance-sampled disk with per-pixel rotation, energy-normalised
//! bilateral weights on the Euclidean distance and a discrete LOD. At a
//! high count (`--samples 2304`) it is the converged screen-space Burley
//! the sample-count studies compare against; the ground truth is
//! `reference` (`sss/reference.rs`), which shares its irradiance (light,
//! shadow map, PCF, maps) but none of its disk, pixel grid or weights.

use super::{Knob, Look, MethodInputs, Scattered, SssFrame, SssPipelines};
use crate::model::sampling::{AngleSequence, SamplePattern};
use crate::model::{ModelError, RadialProfile, Rgb};
use crate::render::context::GpuError;
use crate::render::frame::{buf, tex, FrameEncoder};
use crate::render::gpu_types::GpuSample;
use crate::render::gpu_types::{BurleyUniforms, SssUniforms};
use crate::render::pipelines::{
    buffer_entry, fullscreen_pipeline, texture_entry, uniform_entry, Output, Stencil, HDR,
};
use crate::render::profile_gpu::storage;
use crate::render::targets::HdrTarget;

/// `burley` in the registry (`sss::Method::sss`).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "burley",
    label: "burley (Golubev 2018 disk)",
    quality: super::Quality::Samples,
    stochastic: |_| true,
    shader: Some((
        "sss_burley",
        include_str!("../../../shaders/sss_burley.wgsl"),
    )),
    colour: [31, 119, 180],
    bench,
    encode,
    ..super::MethodInfo::BASE
};

/// `burley`'s command-line options.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::Args)]
#[group(skip)]
pub struct Options {
    /// `burley` sampling: `improved` (MIS across the channels, R2
    /// rotations, an exact centre weight) or `golubev` (Golubev 2018 as
    /// published); `bench` measures both.
    #[arg(id = "burley_sampling", long = "burley-sampling", value_name = "BURLEY_SAMPLING", default_value = "improved", value_parser = sampling_parser())]
    pub sampling: BurleySampling,
}

/// `--burley-sampling`: one of the named samplings
/// (`BurleySampling::NAMED`).
fn sampling_parser() -> impl clap::builder::TypedValueParser<Value = BurleySampling> {
    let names = BurleySampling::NAMED.map(|(name, _)| name);
    clap::builder::TypedValueParser::map(clap::builder::PossibleValuesParser::new(names), |name| {
        BurleySampling::named(&name).unwrap_or_default()
    })
}

/// Nothing is kept between frames.
pub(in crate::render) type State = ();

/// The sample counts `bench` measures.
pub const BENCH_SAMPLES: [usize; 7] = [7, 13, 21, 34, 55, 89, 144];
/// The single improvements, measured alone at these counts.
pub const ABLATION_SAMPLES: [usize; 2] = [21, 55];

/// `bench`'s configurations: both named samplings at every count, then
/// each single improvement to Golubev 2018 alone (measurements, not
/// options an artist picks).
fn bench() -> Vec<Knob> {
    let knob = |variant, count, series, shipped| Knob {
        variant,
        count,
        series,
        shipped,
    };
    let mut k: Vec<Knob> = BENCH_SAMPLES
        .map(|n| knob("improved", n, (" (improved)", Some([214, 39, 40])), true))
        .into_iter()
        .chain(BENCH_SAMPLES.map(|n| knob("golubev", n, (" (Golubev 2018)", None), true)))
        .collect();
    for flag in ["antithetic", "mis", "r2", "bilinear", "centre"] {
        k.extend(
            ABLATION_SAMPLES
                .map(|n| knob(flag, n, (", one improvement", Some([255, 127, 14])), false)),
        );
    }
    k
}

/// How `burley` places and weighs its samples. [`BurleySampling::GOLUBEV`]
/// is Golubev 2018 as published (radii at the widest channel's quantiles
/// (i + ½)/N, golden-angle angles, a white-noise per-pixel rotation); the
/// other flags are the improvements `bench` measures against it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BurleySampling {
    /// Point-symmetric pairs of samples (antithetic variates): the linear
    /// part of the irradiance cancels in each pair. Takes precedence over
    /// `mis` (the pattern is the widest channel's).
    pub antithetic: bool,
    /// Radii from every channel's CDF in turn, weighted by the mixture
    /// density (multiple importance sampling, balance heuristic).
    pub mis: bool,
    /// Per-pixel rotation from the R2 low-discrepancy sequence (Roberts
    /// 2018) instead of a hash: neighbouring pixels get well-spread angles,
    /// so the noise is blue rather than white.
    pub r2_rotation: bool,
    /// Fetch each sample bilinearly at its exact offset (SSS texels only)
    /// instead of the nearest pixel: four loads instead of one.
    pub bilinear: bool,
    /// The centre pixel carries the energy inside its own footprint,
    /// CDF(r_px), exactly; the samples estimate the rest (as Unreal does).
    pub centre_weight: bool,
}

impl BurleySampling {
    /// Golubev 2018 as published: the baseline.
    pub const GOLUBEV: Self = Self {
        antithetic: false,
        mis: false,
        r2_rotation: false,
        bilinear: false,
        centre_weight: false,
    };
    /// What `burley` uses: the improvements that measured better than the
    /// baseline on the head (`docs/accuracy.md`).
    pub const IMPROVED: Self = Self {
        antithetic: true,
        mis: false,
        r2_rotation: true,
        bilinear: false,
        centre_weight: false,
    };

    /// The shader's `BurleyUniforms::flags`: the `SAMPLING_*` bit of each
    /// option that is on.
    pub fn shader_flags(self) -> u32 {
        use crate::render::gpu_types::{
            SAMPLING_BILINEAR, SAMPLING_CENTRE_WEIGHT, SAMPLING_R2_ROTATION,
        };
        [
            (self.r2_rotation, SAMPLING_R2_ROTATION),
            (self.centre_weight, SAMPLING_CENTRE_WEIGHT),
            (self.bilinear, SAMPLING_BILINEAR),
        ]
        .iter()
        .filter(|(on, _)| *on)
        .fold(0, |bits, (_, bit)| bits | bit)
    }

    /// The samplings with a name, as `--burley-sampling` and the bench
    /// call them.
    pub const NAMED: [(&'static str, Self); 2] =
        [("improved", Self::IMPROVED), ("golubev", Self::GOLUBEV)];

    /// The named sampling `name` (one of [`BurleySampling::NAMED`]).
    pub fn named(name: &str) -> Option<Self> {
        Self::NAMED
            .iter()
            .find(|(n, _)| *n == name)
            .map(|(_, s)| *s)
    }

    /// A short name: `golubev`, `improved`, or the flags that are on.
    pub fn id(self) -> String {
        match Self::NAMED.iter().find(|(_, s)| *s == self) {
            Some((name, _)) => (*name).into(),
            None => [
                (self.antithetic, "antithetic"),
                (self.mis, "mis"),
                (self.r2_rotation, "r2"),
                (self.bilinear, "bilinear"),
                (self.centre_weight, "centre"),
            ]
            .iter()
            .filter(|f| f.0)
            .map(|f| f.1)
            .collect::<Vec<_>>()
            .join("+"),
        }
    }
}

impl BurleySampling {
    /// The sampling [`BurleySampling::id`] names: a named one, or the
    /// flags joined by `+`.
    pub fn from_id(id: &str) -> Option<Self> {
        if let Some(s) = Self::named(id) {
            return Some(s);
        }
        let mut s = Self::GOLUBEV;
        for flag in id.split('+') {
            let on = match flag {
                "antithetic" => &mut s.antithetic,
                "mis" => &mut s.mis,
                "r2" => &mut s.r2_rotation,
                "bilinear" => &mut s.bilinear,
                "centre" => &mut s.centre_weight,
                _ => return None,
            };
            *on = true;
        }
        Some(s)
    }
}

impl Default for BurleySampling {
    fn default() -> Self {
        Self::IMPROVED
    }
}

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
    /// The radius (mm) the profile table reaches.
    lut_radius_mm: f32,
}

/// The importance-sampled disk and the profile table on the GPU, as a
/// gather reads them: burley's own, and the only per-profile data
/// `texture-space` reads (it uploads none of its own, so the two methods
/// gather the same samples through the same table).
pub(in crate::render) struct Disk<'a> {
    /// The main pattern followed by the LOD's short one.
    pub samples: &'a wgpu::Buffer,
    /// r·R_N(r) per channel (the weights), then the CDF.
    pub profile_lut: &'a wgpu::Buffer,
    /// Samples of the main pattern.
    pub count: u32,
    /// The radius (mm) the profile table reaches.
    pub lut_radius_mm: f32,
}

impl Buffers {
    /// The disk and table ([`Disk`]) these buffers hold.
    pub(in crate::render) fn disk(&self) -> Disk<'_> {
        Disk {
            samples: &self.samples,
            profile_lut: &self.profile_lut,
            count: self.count,
            lut_radius_mm: self.lut_radius_mm,
        }
    }
}

impl super::MethodBuffers<Inputs> for Buffers {
    fn new(device: &wgpu::Device, _: &wgpu::Queue, inputs: &Inputs) -> Self {
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
            lut_radius_mm: inputs.lut_radius_mm,
        }
    }
}

/// `burley`'s layout and pipeline (`fs_burley`, testing the stencil).
pub(in crate::render) struct Pipelines {
    layout: wgpu::BindGroupLayout,
    pipeline: wgpu::RenderPipeline,
}

impl super::MethodPipelines for Pipelines {
    fn new(device: &wgpu::Device, module: &dyn Fn(&'static str) -> wgpu::ShaderModule) -> Self {
        let module = &module("sss_burley");
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

fn encode(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
    _: &mut super::State,
) -> Result<Scattered, GpuError> {
    let gpu = &io.profile.methods.burley;
    let disk = gpu.disk();
    let (n, label) = (disk.count, "sss burley");
    let uniforms = SssUniforms {
        lut_radius_mm: disk.lut_radius_mm,
        lut_entries: LUT_SIZE as u32,
        ..io.uniforms(n)
    };
    let u = f.uniform("sss uniforms", bytemuck::bytes_of(&uniforms));
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
            buf(3, disk.samples),
            buf(4, disk.profile_lut),
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
    Ok(Scattered {
        counted_pass: Some(label),
        ..Scattered::in_target(HdrTarget::Ping, n)
    })
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

impl MethodInputs for Inputs {
    /// Always baked (the patterns and the table take about a millisecond).
    fn new(look: &Look<'_>, _bake: bool) -> Result<Self, ModelError> {
        Self::of_profile(
            look.profile,
            look.samples,
            look.options.burley.sampling,
            (look.r_max_mm, look.total),
        )
    }

    /// `variant` is the sampling's id, `count` its samples.
    fn bench(&mut self, look: &Look<'_>, knob: &Knob) -> Result<(), ModelError> {
        let sampling = BurleySampling::from_id(knob.variant).ok_or_else(|| {
            ModelError::invalid("burley bench variant", format!("{:?}", knob.variant))
        })?;
        self.set_patterns(look.profile, knob.count, sampling)
    }

    fn fingerprint_into(&self, h: &mut impl std::hash::Hasher) {
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

impl Inputs {
    /// `sampling`'s patterns of `samples` and the table out to `r_max`
    /// (mm), for a profile of total reflectance `total`.
    pub fn of_profile(
        profile: &dyn RadialProfile,
        samples: usize,
        sampling: BurleySampling,
        (r_max, total): (f64, Rgb),
    ) -> Result<Self, ModelError> {
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
