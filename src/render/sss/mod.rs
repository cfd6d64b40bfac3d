//! The SSS methods, one file each: `burley`, `separable` and `gaussians`
//! (screen-space passes), `preintegrated` and `none` (lit in the scene
//! pass, `shaders/scene.wgsl`), and the ground truth they are judged
//! against, `reference` (object space, on the CPU). Each file declares its
//! method's [`MethodInfo`] and the types the registry below gathers: its
//! CPU `Inputs`, GPU `Buffers`, `Pipelines`, command-line `Options` and
//! frame-to-frame `State`. The registry ([`methods!`] below) is the one
//! list of them: it declares the modules, the `match` of [`Method::sss`]
//! and a field per method in [`Inputs`], [`Buffers`], [`SssPipelines`],
//! [`MethodOptions`] and [`State`]. Everything else asks the registry.

mod profile;

pub(in crate::render) use profile::ProfileGpu;
pub use profile::ProfileInputs;

use super::context::{GpuContext, GpuError};
use super::frame::FrameEncoder;
use super::gpu_types::{SceneUniforms, SssUniforms};
use super::mesh::Mesh;
use super::passes::shadow::ShadowPass;
use super::passes::MeshLod;
use super::settings::{Method, RenderSettings};
use super::targets::{HdrTarget, Targets};
use crate::model::{ModelError, RadialProfile, Rgb};
use crate::settings::ProfileSpec;

/// The registry: each line is a method's `MethodId` variant and its file.
/// From it come the modules, [`Method::sss`] (the one `match` over the
/// methods) and the structs with a field per method.
macro_rules! methods {
    ($($variant:ident => $m:ident),* $(,)?) => {
        $(pub mod $m;)*

        impl Method {
            /// The method's [`MethodInfo`], declared in its file.
            pub fn sss(self) -> &'static MethodInfo {
                match self {
                    $(Method::$variant => &$m::METHOD,)*
                }
            }
        }

        /// Every method's CPU inputs for one profile, each its file's
        /// `Inputs` ([`ProfileInputs::methods`]).
        #[derive(Debug, Clone)]
        pub struct Inputs {
            $(pub $m: $m::Inputs,)*
        }

        impl Inputs {
            /// Each method's inputs for `look`; the tables of the methods
            /// `bake` names, neutral placeholders of the same sizes for
            /// the others.
            fn new(look: &Look<'_>, bake: &dyn Fn(Method) -> bool) -> Result<Self, ModelError> {
                Ok(Self {
                    $($m: MethodInputs::new(look, bake(Method::$variant))?,)*
                })
            }

            /// Why these inputs cannot render `method`, if they cannot.
            fn missing(&self, method: Method) -> Option<&'static str> {
                match method {
                    $(Method::$variant => self.$m.missing(),)*
                }
            }

            /// Sets `method`'s inputs to its bench configuration `knob`.
            fn bench(&mut self, method: Method, look: &Look<'_>, knob: &Knob) -> Result<(), ModelError> {
                match method {
                    $(Method::$variant => self.$m.bench(look, knob),)*
                }
            }

            /// Feeds everything the GPU receives from these inputs to `h`.
            fn fingerprint_into(&self, h: &mut impl std::hash::Hasher) {
                $(self.$m.fingerprint_into(h);)*
            }
        }

        /// Every method's share of the profile on the GPU, uploaded from
        /// its `Inputs` by its own file ([`ProfileGpu::methods`]). (A
        /// method with nothing there has a `()`, never read.)
        #[allow(dead_code)]
        pub(in crate::render) struct Buffers {
            $(pub $m: $m::Buffers,)*
        }

        impl Buffers {
            pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, inputs: &Inputs) -> Self {
                Self {
                    $($m: MethodBuffers::new(device, queue, &inputs.$m),)*
                }
            }
        }

        /// The methods' pipelines, built once with the renderer: switching
        /// methods or editing the profile never recompiles a shader.
        #[allow(dead_code)]
        pub(in crate::render) struct SssPipelines {
            $(pub $m: $m::Pipelines,)*
        }

        impl SssPipelines {
            pub fn new(
                device: &wgpu::Device,
                module: &dyn Fn(&'static str) -> wgpu::ShaderModule,
            ) -> Self {
                Self {
                    $($m: MethodPipelines::new(device, module),)*
                }
            }
        }

        /// Every method's options: its command-line flags (flattened into
        /// `render`'s) and their defaults, which the editor uses.
        #[derive(Debug, Clone, Default, PartialEq, clap::Args)]
        #[group(skip)]
        pub struct MethodOptions {
            $(#[command(flatten)] pub $m: $m::Options,)*
        }

        /// What each method keeps from frame to frame (the ground truth's
        /// cells), owned by the renderer.
        #[derive(Default)]
        #[allow(dead_code)]
        pub(in crate::render) struct State {
            $(pub $m: $m::State,)*
        }
    };
}

methods! {
    None => none,
    Burley => burley,
    Separable => separable,
    Gaussians => gaussians,
    Preintegrated => preintegrated,
    TextureSpace => texture_space,
    Reference => reference,
}

/// What a method builds its inputs from.
pub struct Look<'a> {
    /// The look's model, when there is one ([`ProfileInputs::new`] builds
    /// from a profile alone).
    pub spec: Option<&'a ProfileSpec>,
    pub profile: &'a dyn RadialProfile,
    /// The look's sample and tap counts (`rendering.samples`, `.taps`).
    pub samples: usize,
    pub taps: usize,
    /// The widest channel's 0.999-energy radius (mm): how far the tables
    /// reach.
    pub r_max_mm: f64,
    /// The profile's total reflectance per channel.
    pub total: Rgb,
    pub options: &'a MethodOptions,
}

impl<'a> Look<'a> {
    pub fn new(
        spec: Option<&'a ProfileSpec>,
        profile: &'a dyn RadialProfile,
        (samples, taps): (usize, usize),
        options: &'a MethodOptions,
    ) -> Self {
        Self {
            spec,
            profile,
            samples,
            taps,
            r_max_mm: super::inputs::table_radius_mm(profile),
            total: profile.total_reflectance(),
            options,
        }
    }
}

/// A method's CPU inputs for one profile (its file's `Inputs`).
pub trait MethodInputs: Sized {
    /// The inputs for `look`: the costly tables only with `bake`, neutral
    /// placeholders of the same sizes otherwise (the method is not drawn
    /// with them; [`MethodInputs::missing`] says so).
    fn new(look: &Look<'_>, bake: bool) -> Result<Self, ModelError>;
    /// Why these inputs cannot draw the method (a table left as a
    /// placeholder), or `None`.
    fn missing(&self) -> Option<&'static str> {
        None
    }
    /// Sets these inputs to one of the method's bench configurations
    /// ([`MethodInfo::bench`]); the base inputs are those of
    /// [`ProfileInputs::new`].
    fn bench(&mut self, look: &Look<'_>, knob: &Knob) -> Result<(), ModelError> {
        let _ = (look, knob);
        Ok(())
    }
    /// Feeds everything the GPU receives from these inputs to `h`.
    fn fingerprint_into(&self, h: &mut impl std::hash::Hasher);
}

/// A method's share of the profile on the GPU, uploaded from its inputs.
pub(in crate::render) trait MethodBuffers<I> {
    fn new(device: &wgpu::Device, queue: &wgpu::Queue, inputs: &I) -> Self;
}

/// A method's pipelines, built once from the shader modules by name.
pub(in crate::render) trait MethodPipelines {
    fn new(device: &wgpu::Device, module: &dyn Fn(&'static str) -> wgpu::ShaderModule) -> Self;
}

/// A method with no inputs of its own (`none`).
impl MethodInputs for () {
    fn new(_: &Look<'_>, _: bool) -> Result<Self, ModelError> {
        Ok(())
    }
    fn fingerprint_into(&self, _: &mut impl std::hash::Hasher) {}
}

/// A method with nothing on the GPU of its own.
impl<I> MethodBuffers<I> for () {
    fn new(_: &wgpu::Device, _: &wgpu::Queue, _: &I) -> Self {}
}

/// A method with no pipeline of its own (lit in the scene pass, on the
/// CPU, or reusing another's).
impl MethodPipelines for () {
    fn new(_: &wgpu::Device, _: &dyn Fn(&'static str) -> wgpu::ShaderModule) -> Self {}
}

/// The options of a method that has none.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, clap::Args)]
#[group(skip)]
pub struct NoOptions {}

/// What the SSS passes of one frame read and write.
pub(in crate::render) struct SssFrame<'t> {
    pub targets: &'t Targets,
    pub profile: &'t ProfileGpu,
    pub inputs: &'t ProfileInputs,
    /// Pixels whose mask exceeds 1/255 (from the classify pass).
    pub sss_pixels: u64,
    /// Uniforms common to every pass; each pass sets the sample count and
    /// its own fields.
    pub uniforms: SssUniforms,
    /// GPU counters: samples taken, pixels convolved, pixels skipped by the LOD.
    pub counters: &'t wgpu::Buffer,
    pub lod: bool,
    /// Per-pixel random rotations are off (tests, the bench).
    pub deterministic: bool,
    /// What a method computed on the CPU needs (`reference`): the device,
    /// the finest mesh, the shadow pass, the scene's uniforms, the camera,
    /// the frame's settings, and the cancel flag.
    pub ctx: &'t GpuContext,
    pub mesh: &'t Mesh,
    pub shadow: &'t ShadowPass,
    pub scene: &'t SceneUniforms,
    pub view_from_world: glam::Mat4,
    pub settings: &'t RenderSettings,
    pub cancel: &'t std::sync::atomic::AtomicBool,
    /// The scene pass's bind group and its layout (the GPU ground truth
    /// evaluates the scene's `shade` with them).
    pub scene_bind: &'t wgpu::BindGroup,
    pub scene_layout: &'t wgpu::BindGroupLayout,
    /// The level of detail the scene pass drew (`texture-space` draws it
    /// again: into its atlas, and with the scene's depth).
    pub drawn: &'t MeshLod,
}

impl SssFrame<'_> {
    /// The shared uniforms with `count` samples or taps.
    pub fn uniforms(&self, count: u32) -> SssUniforms {
        SssUniforms {
            sample_count: count,
            ..self.uniforms
        }
    }
}

/// Where a method left the scattered irradiance, and what it sampled.
pub(in crate::render) struct Scattered {
    pub target: HdrTarget,
    pub samples_per_pixel: u32,
    /// The pass whose samples the GPU counters measured, if any.
    pub counted_pass: Option<&'static str>,
    /// The ground truth's figures, for the one method that gathers it.
    pub truth: Option<TruthFigures>,
}

/// What a ground-truth frame (`reference`) measured.
#[derive(Debug, Clone, Default)]
pub(in crate::render) struct TruthFigures {
    /// Its CPU time (ms).
    pub cpu_ms: f64,
    /// The part of `cpu_ms` that built the cells, where this frame built
    /// them.
    pub build_ms: Option<f64>,
    /// On the GPU: the points whose walk the GPU did not finish, gathered
    /// on the CPU instead.
    pub gpu_unfinished: Option<u64>,
    /// In tiles: how far the view has got.
    pub tiles: Option<crate::render::settings::TruthProgress>,
}

impl Scattered {
    /// A method's passes left the irradiance in `target`, `samples` a
    /// pixel.
    pub fn in_target(target: HdrTarget, samples_per_pixel: u32) -> Self {
        Self {
            target,
            samples_per_pixel,
            counted_pass: None,
            truth: None,
        }
    }
}

/// Records a method's passes (or computes it, `reference`).
pub(in crate::render) type Encode =
    fn(&mut FrameEncoder, &SssPipelines, &SssFrame, &mut State) -> Result<Scattered, GpuError>;

/// For a method lit in the scene pass (`none`, `preintegrated`): nothing
/// to record, the scattered irradiance is the diffuse target.
pub(in crate::render) fn no_pass(
    _: &mut FrameEncoder,
    _: &SssPipelines,
    _: &SssFrame,
    _: &mut State,
) -> Result<Scattered, GpuError> {
    Ok(Scattered::in_target(HdrTarget::Diffuse, 0))
}

/// What a method lit in the scene pass gives it (`shaders/scene.wgsl`).
pub(in crate::render) struct SceneHook {
    /// Its two tables, bound at `scene.wgsl`'s bindings 3 (the lighting
    /// table) and 12 (the penumbra table).
    pub tables: fn(&Buffers) -> [&wgpu::TextureView; 2],
    /// Sets its fields of the scene's uniforms; `drawn`: this frame draws
    /// the method (otherwise its lighting is off).
    pub uniforms: fn(&ProfileInputs, drawn: bool, &mut SceneUniforms),
}

/// Everything that tells one method from another outside its own file,
/// declared there as its `METHOD` and reached through [`Method::sss`].
pub struct MethodInfo {
    /// The `--method` value, the presets' and reports' name (clap's name
    /// of the variant: `method_ids_are_clap_names` checks).
    pub id: &'static str,
    /// The editor's menu text: the name and its source.
    pub label: &'static str,
    /// The number its quality is set by.
    pub quality: Quality,
    /// Whether frames differ by random rotations, under these options (a
    /// mean over frames converges).
    pub stochastic: fn(&MethodOptions) -> bool,
    /// Its tables take long to bake (a fit): they are built only when it
    /// is the method asked for, not with every other method's tables.
    pub slow_bake: bool,
    /// Whether it is the ground truth (the profile integrated in object
    /// space on the CPU): drawn on the finest LOD, judged against nothing.
    pub ground_truth: bool,
    /// Whether it is the baseline: no scattering at all.
    pub baseline: bool,
    /// Whether it is what a look is compared with by default (compare's
    /// B in the editor).
    pub compare_partner: bool,
    /// Its colour in the bench's charts (sRGB).
    pub colour: [u8; 3],
    /// Its screen-space pass's WGSL module, (name, source), built after
    /// `fullscreen.wgsl` and `sss_common.wgsl` (`pipelines::shader_sources`);
    /// `None` for a method with no pass or one that reuses another's.
    pub shader: Option<(&'static str, &'static str)>,
    /// The configurations `bench` measures it at.
    pub bench: fn() -> Vec<Knob>,
    /// For a method lit in the scene pass: its tables and uniforms there.
    pub(in crate::render) scene: Option<SceneHook>,
    /// Records its passes.
    pub(in crate::render) encode: Encode,
}

impl MethodInfo {
    /// What a method's `METHOD` does not set: a fixed quality, no random
    /// rotations, quick tables, no role, no shader, no scene-pass terms,
    /// one bench configuration and no pass.
    pub(in crate::render) const BASE: MethodInfo = MethodInfo {
        id: "",
        label: "",
        quality: Quality::Fixed,
        stochastic: |_| false,
        slow_bake: false,
        ground_truth: false,
        baseline: false,
        compare_partner: false,
        colour: [0, 0, 0],
        shader: None,
        bench: || vec![Knob::FIXED],
        scene: None,
        encode: no_pass,
    };
}

/// The count a method's quality is set by.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quality {
    /// None: one configuration.
    Fixed,
    /// Samples per pixel (`--samples`).
    Samples,
    /// Taps of a separable kernel (`--taps`).
    Taps,
}

/// One configuration `bench` measures a method at ([`MethodInfo::bench`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Knob {
    /// The CSV's `variant` column ("" for a method's one configuration);
    /// the method's [`MethodInputs::bench`] reads it back.
    pub variant: &'static str,
    /// Samples or taps (the CSV's `count`); 0 for a fixed quality.
    pub count: usize,
    /// Its chart series: the text after the method's id, and its colour
    /// (`None`: the method's own).
    pub series: (&'static str, Option<[u8; 3]>),
    /// Whether an artist can pick it (single-flag ablations are
    /// measurements, not options).
    pub shipped: bool,
}

impl Knob {
    /// A method's one configuration.
    pub const FIXED: Knob = Knob {
        variant: "",
        count: 0,
        series: ("", None),
        shipped: true,
    };
}

impl Method {
    /// The name the command line, presets' reports and the bench use.
    pub fn id(self) -> &'static str {
        self.sss().id
    }

    /// The editor's menu text.
    pub fn label(self) -> &'static str {
        self.sss().label
    }

    /// The ground truth (`reference`).
    pub fn ground_truth() -> Method {
        Self::the_one(|m| m.ground_truth)
    }

    /// The baseline that scatters nothing (`none`).
    pub fn baseline() -> Method {
        Self::the_one(|m| m.baseline)
    }

    /// What a look is compared with by default (`separable`).
    pub fn compare_partner() -> Method {
        Self::the_one(|m| m.compare_partner)
    }

    /// What stands in for this method while the artist works: the default
    /// method for the ground truth, which takes seconds a frame.
    pub fn preview(self) -> Method {
        if self.sss().ground_truth {
            Method::default()
        } else {
            self
        }
    }

    /// The first method with `property` (the registry test checks there
    /// is one); the default method if none has it.
    fn the_one(property: impl Fn(&MethodInfo) -> bool) -> Method {
        Method::all()
            .iter()
            .copied()
            .find(|m| property(m.sss()))
            .unwrap_or_default()
    }
}

/// Whether frames of `s` differ only by their random rotations, so that a
/// mean over frames converges (`burley`'s rotated disks, `separable` with
/// stochastic axis rotation).
pub fn is_stochastic(s: &RenderSettings, options: &MethodOptions) -> bool {
    !s.deterministic && (s.method.sss().stochastic)(options)
}

/// The method lit in the scene pass (`preintegrated`): its tables for the
/// scene's bind group.
pub(in crate::render) fn scene_tables(buffers: &Buffers) -> [&wgpu::TextureView; 2] {
    let hook = Method::all()
        .iter()
        .find_map(|m| m.sss().scene.as_ref())
        .expect("one method is lit in the scene pass (each_role_is_held_by_one_method)");
    (hook.tables)(buffers)
}

/// Sets the scene uniforms' terms of the method lit in the scene pass,
/// on when `method` is it.
pub(in crate::render) fn scene_terms(
    inputs: &ProfileInputs,
    method: Method,
    u: &mut SceneUniforms,
) {
    for &m in Method::all() {
        if let Some(hook) = &m.sss().scene {
            (hook.uniforms)(inputs, m == method, u);
        }
    }
}

#[cfg(test)]
mod tests;
