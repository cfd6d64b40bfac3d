//! `separable` (Jimenez 2012, `shaders/sss_separable.wgsl`): the profile
//! core's kernel in two depth-aware 1D passes, sssWidth from world scale
//! and projection, and the follow-surface term. The same 1D pass serves
//! each Gaussian of `gaussians`.

use super::{Knob, Look, MethodInputs, Scattered, SssFrame, SssPipelines};
use crate::model::jimenez::Jimenez2012;
use crate::model::separable::SeparableKernel;
use crate::model::{ModelError, RadialProfile};
use crate::render::context::GpuError;
use crate::render::frame::{buf, tex, FrameEncoder};
use crate::render::gpu_types::GpuTap;
use crate::render::gpu_types::SssUniforms;
use crate::render::pipelines::{
    buffer_entry, fullscreen_pipeline, texture_entry, uniform_entry, Output, Stencil, HDR,
};
use crate::render::profile_gpu::storage;
use crate::render::targets::HdrTarget;
use crate::settings::ProfileSpec;

/// `separable` in the registry (`sss::Method::sss`).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "separable",
    label: "separable (Jimenez 2015)",
    quality: super::Quality::Taps,
    stochastic: |o| o.separable.rotation,
    compare_partner: true,
    shader: Some((
        "sss_separable",
        include_str!("../../../shaders/sss_separable.wgsl"),
    )),
    colour: [44, 160, 44],
    bench,
    encode,
    ..super::MethodInfo::BASE
};

/// `separable`'s command-line options.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::Args)]
#[group(skip)]
pub struct Options {
    /// `separable`: rotate the blur axes per pixel (Jimenez 2015 §6).
    #[arg(id = "separable_rotation", long = "separable-rotation")]
    pub rotation: bool,
}

/// Nothing is kept between frames.
pub(in crate::render) type State = ();

/// The tap counts `bench` measures.
pub const BENCH_TAPS: [usize; 5] = [7, 11, 17, 25, 33];

/// `bench`'s configurations: Jimenez 2012's kernel fitted to the profile
/// (`2012`) and Jimenez 2015's importance-sampled pre-integrated kernel
/// (`2015`) at every tap count.
fn bench() -> Vec<Knob> {
    let knob = |variant, count, series| Knob {
        variant,
        count,
        series,
        shipped: true,
    };
    BENCH_TAPS
        .map(|n| knob("2012", n, (", 2012 kernel", None)))
        .into_iter()
        .chain(BENCH_TAPS.map(|n| knob("2015", n, (", 2015 kernel", Some([23, 190, 207])))))
        .collect()
}

/// `separable`'s share of the profile on the GPU: the kernel's taps.
pub(in crate::render) struct Buffers {
    taps: wgpu::Buffer,
    count: u32,
    /// The depth weight's σ (mm), 0 for the Jimenez 2012 lerp.
    depth_sigma_mm: f32,
}

impl super::MethodBuffers<Inputs> for Buffers {
    fn new(device: &wgpu::Device, _: &wgpu::Queue, inputs: &Inputs) -> Self {
        Self {
            taps: storage(device, "separable taps", bytemuck::cast_slice(&inputs.taps)),
            count: inputs.taps.len() as u32,
            depth_sigma_mm: inputs.depth_sigma_mm,
        }
    }
}

/// The 1D pass's layout and its two pipelines (`fs_separable`, testing the
/// stencil): one replacing its target, one adding weight × result into it
/// (`gaussians`).
pub(in crate::render) struct Pipelines {
    layout: wgpu::BindGroupLayout,
    replace: wgpu::RenderPipeline,
    add: wgpu::RenderPipeline,
}

impl super::MethodPipelines for Pipelines {
    fn new(device: &wgpu::Device, module: &dyn Fn(&'static str) -> wgpu::ShaderModule) -> Self {
        let module = &module("sss_separable");
        let frag = wgpu::ShaderStages::FRAGMENT;
        let layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("sss separable"),
            entries: &[
                uniform_entry::<SssUniforms>(0, frag),
                texture_entry(1),
                texture_entry(2),
                buffer_entry(
                    3,
                    wgpu::BufferBindingType::Storage { read_only: true },
                    frag,
                ),
            ],
        });
        let pass = |output| {
            fullscreen_pipeline(
                device,
                module,
                "fs_separable",
                &layout,
                output,
                Stencil::Test,
            )
        };
        Self {
            replace: pass(Output::Replace(HDR)),
            add: pass(Output::Add(HDR)),
            layout,
        }
    }
}

/// Follow-surface strength of the Jimenez 2012 demo kernel: a lerp towards
/// the centre of this much per mm of depth difference, the form of the
/// demo's SSSS_FOLLOW_SURFACE term. The value is ours: the demo's,
/// saturate(300 · distanceToProjectionWindow · sssWidth · Δdepth), is in its
/// own scene units and depends on its camera and sssWidth slider, so it has
/// no fixed per-mm value to copy. Every other kernel uses Jimenez 2015
/// eq. 7's weight e^(−Δz²/2σ²) with its own σ (see [`follow_surface`]).
const FOLLOW_SURFACE: f32 = 0.5;

/// `SssUniforms::follow_surface` for a kernel of depth σ (mm): the 2012
/// lerp strength (positive) for σ = 0, else −1/(2σ²), which the shader
/// turns into a lerp towards the centre by 1 − e^(−Δz²/2σ²), so the weight
/// a tap loses across a depth step stays at the centre (energy is kept).
fn follow_surface(depth_sigma_mm: f32) -> f32 {
    if depth_sigma_mm > 0.0 {
        -0.5 / (depth_sigma_mm * depth_sigma_mm)
    } else {
        FOLLOW_SURFACE
    }
}

/// How the vertical pass writes its target.
pub(in crate::render) enum Into {
    /// Replace the target's contents.
    Replace,
    /// Add `weight` × result: clear the target first when `first`.
    Add { weight: [f32; 3], first: bool },
}

/// Blurs the scene's diffuse along x into ping, then along y into pong,
/// with `taps` (buffer, count).
pub(in crate::render) fn blur_xy(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
    taps: (&wgpu::Buffer, u32),
    depth_sigma_mm: f32,
    into: Into,
    labels: [&'static str; 2],
) {
    let t = io.targets;
    let (weight, y_pipeline, y_load) = match into {
        Into::Replace => ([1.0; 3], &p.separable.replace, false),
        Into::Add { weight, first } => (weight, &p.separable.add, !first),
    };
    let passes = [
        (
            [1.0, 0.0],
            HdrTarget::Diffuse,
            HdrTarget::Ping,
            labels[0],
            [1.0; 3],
            &p.separable.replace,
            false,
        ),
        (
            [0.0, 1.0],
            HdrTarget::Ping,
            HdrTarget::Pong,
            labels[1],
            weight,
            y_pipeline,
            y_load,
        ),
    ];
    for (dir, from, to, label, weight, pipeline, load) in passes {
        let u = SssUniforms {
            direction: dir,
            follow_surface: follow_surface(depth_sigma_mm),
            rotate_axis: (io.inputs.options.separable.rotation && !io.deterministic) as u32,
            weight: [weight[0], weight[1], weight[2], 1.0],
            ..io.uniforms(taps.1)
        };
        let u = f.uniform("sss uniforms", bytemuck::bytes_of(&u));
        let bg = f.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout: &p.separable.layout,
            entries: &[
                buf(0, &u),
                tex(1, t.view(from)),
                tex(2, &t.linear_depth),
                buf(3, taps.0),
            ],
        });
        f.fullscreen(
            Some(t.view(to)),
            pipeline,
            &bg,
            label,
            (io.sss_pixels, io.sss_pixels * taps.1 as u64),
            load,
            true,
        );
    }
}

fn encode(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
    _: &mut super::State,
) -> Result<Scattered, GpuError> {
    let gpu = &io.profile.methods.separable;
    blur_xy(
        f,
        p,
        io,
        (&gpu.taps, gpu.count),
        gpu.depth_sigma_mm,
        Into::Replace,
        ["sss separable x", "sss separable y"],
    );
    Ok(Scattered::in_target(HdrTarget::Pong, 2 * gpu.count))
}

/// `separable`'s CPU inputs: the kernel's taps and how the passes follow
/// the surface across depth.
#[derive(Debug, Clone)]
pub struct Inputs {
    pub taps: Vec<GpuTap>,
    /// σ (mm) of Jimenez 2015 eq. 7's depth weight e^(−Δz²/2σ²) for the
    /// pre-integrated kernel (its widest channel's RMS width), or 0 for the
    /// Jimenez 2012 demo kernel's lerp towards the centre.
    pub depth_sigma_mm: f32,
    /// False for the placeholder of inputs made for another method.
    pub baked: bool,
}

impl MethodInputs for Inputs {
    /// A Jimenez 2012 look keeps the demo's kernel (with its own taps);
    /// any other profile uses the importance-sampled pre-integrated kernel
    /// (Jimenez 2015 §4, §7). Without `bake`, the identity placeholder.
    fn new(look: &Look<'_>, bake: bool) -> Result<Self, ModelError> {
        if !bake {
            return Ok(Self::identity());
        }
        match look.spec {
            Some(ProfileSpec::Jimenez2012(j)) => Ok(Self::of_kernel(
                &Jimenez2012::new(j.strength, j.falloff)?.kernel(look.taps)?,
                true,
            )),
            _ => Self::importance_sampled(look.profile, look.taps),
        }
    }

    fn missing(&self) -> Option<&'static str> {
        (!self.baked).then_some("the separable kernel's taps")
    }

    /// `2012`: Jimenez 2012's kernel, the look's own for a Jimenez 2012
    /// look, else fitted to the profile (`model::fit::fit_jimenez`);
    /// `2015`: the importance-sampled pre-integrated kernel; `count` taps.
    fn bench(&mut self, look: &Look<'_>, knob: &Knob) -> Result<(), ModelError> {
        *self = match knob.variant {
            "2012" => {
                let jimenez = match look.spec {
                    Some(ProfileSpec::Jimenez2012(j)) => Jimenez2012::new(j.strength, j.falloff)?,
                    _ => crate::model::fit::fit_jimenez(look.profile)?.model,
                };
                Self::of_kernel(&jimenez.kernel(knob.count)?, true)
            }
            "2015" => Self::importance_sampled(look.profile, knob.count)?,
            v => {
                return Err(ModelError::invalid(
                    "separable bench variant",
                    format!("{v:?}"),
                ))
            }
        };
        Ok(())
    }

    fn fingerprint_into(&self, h: &mut impl std::hash::Hasher) {
        h.write(bytemuck::cast_slice(&self.taps));
        h.write(bytemuck::bytes_of(&self.depth_sigma_mm));
    }
}

impl Inputs {
    /// The importance-sampled pre-integrated kernel of `profile` with
    /// `taps` taps (Jimenez 2015 §4, §7).
    pub fn importance_sampled(
        profile: &dyn RadialProfile,
        taps: usize,
    ) -> Result<Self, ModelError> {
        Ok(Self::of_kernel(
            &SeparableKernel::importance_sampled(profile, taps)?,
            false,
        ))
    }

    /// One tap of weight 1 at the centre: the identity blur, the
    /// placeholder of inputs made for another method.
    pub fn identity() -> Self {
        Self {
            taps: vec![GpuTap {
                weight_offset: [1.0, 1.0, 1.0, 0.0],
            }],
            depth_sigma_mm: 0.0,
            baked: false,
        }
    }

    /// A kernel's taps: `demo_2012` keeps the Jimenez 2012 demo's
    /// follow-surface lerp, otherwise the depth weight's σ is the kernel's
    /// RMS width.
    pub fn of_kernel(kernel: &SeparableKernel, demo_2012: bool) -> Self {
        Self {
            taps: gpu_taps(kernel),
            depth_sigma_mm: if demo_2012 { 0.0 } else { rms_width_mm(kernel) },
            baked: true,
        }
    }
}

/// The RMS width √(Σ w x² / Σ w) (mm) of a 1D kernel's widest channel:
/// the σ of Jimenez 2015 eq. 7's depth weight (σ_max, the widest Gaussian
/// of their two-Gaussian kernel; for any other kernel, its spread).
fn rms_width_mm(kernel: &SeparableKernel) -> f32 {
    (0..3)
        .map(|c| {
            let (m2, w) = kernel.taps.iter().fold((0.0f64, 0.0f64), |(m2, w), t| {
                (
                    m2 + t.weight[c] * t.offset_mm * t.offset_mm,
                    w + t.weight[c],
                )
            });
            if w > 0.0 {
                (m2 / w).sqrt()
            } else {
                0.0
            }
        })
        .fold(0.0f64, f64::max) as f32
}

/// A separable kernel's taps as the GPU reads them: rgb weight, offset (mm).
fn gpu_taps(kernel: &SeparableKernel) -> Vec<GpuTap> {
    kernel
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
        .collect()
}
