//! The SSS methods, one file each: `burley`, `separable` and `gaussians`
//! (screen-space passes), `preintegrated` and `none` (lit in the scene
//! pass, `shaders/scene.wgsl`), and the ground truth they are judged
//! against, `reference` (object space, on the CPU). Each file declares its
//! method's [`MethodInfo`]; [`Method::sss`] below is the registry, the one
//! `match` over the methods that every list and property derives from.

pub mod burley;
pub mod gaussians;
pub mod none;
pub mod preintegrated;
pub mod reference;
pub mod separable;

use super::frame::FrameEncoder;
use super::gpu_types::SssUniforms;
use super::profile_gpu::ProfileGpu;
use super::settings::Method;
use super::targets::{HdrTarget, Targets};
use crate::model::{ModelError, RadialProfile, Rgb};

/// The SSS methods' pipelines, built once with the renderer: switching
/// methods or editing the profile never recompiles a shader. Each method's
/// file builds its own (`gaussians` reuses `separable`'s).
pub(super) struct SssPipelines {
    pub burley: burley::Pipeline,
    pub separable: separable::Pipelines,
}

impl SssPipelines {
    pub fn new(device: &wgpu::Device, module: &dyn Fn(&'static str) -> wgpu::ShaderModule) -> Self {
        Self {
            burley: burley::Pipeline::new(device, &module("sss_burley")),
            separable: separable::Pipelines::new(device, &module("sss_separable")),
        }
    }
}

/// Every method's CPU inputs for one profile, each its own file's
/// `Inputs` (`ProfileInputs::methods`).
#[derive(Debug, Clone)]
pub struct Inputs {
    pub burley: burley::Inputs,
    pub separable: separable::Inputs,
    pub gaussians: gaussians::Inputs,
    pub preintegrated: preintegrated::Inputs,
    pub reference: reference::Inputs,
}

impl Inputs {
    /// Each method's inputs for `profile` (of total reflectance `total`,
    /// tables out to `r_max` mm) with `samples` and `taps`; the costly
    /// tables only where `bake` says, neutral placeholders elsewhere.
    pub(super) fn new(
        profile: &dyn RadialProfile,
        (samples, taps): (usize, usize),
        bake: Reads,
        r_max: f64,
        total: Rgb,
    ) -> Result<Self, ModelError> {
        Ok(Self {
            burley: burley::Inputs::new(profile, samples, r_max, total)?,
            separable: if bake.separable_kernel {
                separable::Inputs::importance_sampled(profile, taps)?
            } else {
                separable::Inputs::identity()
            },
            gaussians: gaussians::Inputs::default(),
            preintegrated: preintegrated::Inputs::new(profile, bake.penner_tables)?,
            reference: reference::Inputs::new(profile),
        })
    }

    /// Feeds everything the GPU receives from these inputs to `h`.
    pub(super) fn fingerprint_into(&self, h: &mut impl std::hash::Hasher) {
        self.burley.fingerprint_into(h);
        self.separable.fingerprint_into(h);
        self.gaussians.fingerprint_into(h);
        self.preintegrated.fingerprint_into(h);
        h.write(&self.reference.table.fingerprint().to_le_bytes());
    }
}

/// Every method's share of the profile on the GPU, uploaded from its
/// `Inputs` by its own file (`ProfileGpu::methods`).
pub(super) struct Buffers {
    pub burley: burley::Buffers,
    pub separable: separable::Buffers,
    pub gaussians: gaussians::Buffers,
    /// Read by the scene pass.
    pub preintegrated: preintegrated::Tables,
}

impl Buffers {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, inputs: &Inputs) -> Self {
        Self {
            burley: burley::Buffers::new(device, &inputs.burley),
            separable: separable::Buffers::new(device, &inputs.separable),
            gaussians: gaussians::Buffers::new(device, &inputs.gaussians),
            preintegrated: preintegrated::Tables::new(device, queue, &inputs.preintegrated),
        }
    }
}

/// What the SSS passes of one frame read and write.
pub(super) struct SssFrame<'t> {
    pub targets: &'t Targets,
    pub profile: &'t ProfileGpu,
    /// Pixels whose mask exceeds 1/255 (from the classify pass).
    pub sss_pixels: u64,
    /// Uniforms common to every pass; each pass sets the sample count and
    /// (separable) the direction, follow-surface term and axis rotation.
    pub uniforms: SssUniforms,
    /// GPU counters: samples taken, pixels convolved, pixels skipped by the LOD.
    pub counters: &'t wgpu::Buffer,
    pub lod: bool,
    /// `separable`: stochastic per-pixel axis rotation (Jimenez 2015 §6).
    pub rotate_separable: bool,
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
pub(super) struct Scattered {
    pub target: HdrTarget,
    pub samples_per_pixel: u32,
    /// The pass whose samples the GPU counters measured, if any.
    pub counted_pass: Option<&'static str>,
}

/// Records a method's screen-space passes, if it has any.
pub(super) type Encode = fn(&mut FrameEncoder, &SssPipelines, &SssFrame) -> Scattered;

/// For a method lit in the scene pass (`none`, `preintegrated`): nothing
/// to record, the scattered irradiance is the diffuse target.
pub(super) fn no_pass(_: &mut FrameEncoder, _: &SssPipelines, _: &SssFrame) -> Scattered {
    Scattered {
        target: HdrTarget::Diffuse,
        samples_per_pixel: 0,
        counted_pass: None,
    }
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
    /// Whether frames differ by random rotations (a mean over frames
    /// converges).
    pub stochastic: Stochastic,
    /// The tables it reads that cost time to bake ([`crate::render::ProfileInputs::for_method`]
    /// bakes only these).
    pub reads: Reads,
    /// Whether the scene pass lights it with Penner's D(θ, κ) instead of
    /// saturate(N·L).
    pub penner_in_scene_pass: bool,
    /// Whether it is the ground truth (the profile integrated in object
    /// space on the CPU): drawn on the finest LOD, judged against nothing.
    pub ground_truth: bool,
    /// Whether it is the baseline: no scattering at all.
    pub baseline: bool,
    /// What reports call its one configuration (the CSV's `variant`),
    /// empty for none.
    pub variant: &'static str,
    /// Its colour in the bench's charts (sRGB).
    pub colour: [u8; 3],
    /// Its screen-space pass's WGSL module, (name, source), built after
    /// `fullscreen.wgsl` and `sss_common.wgsl` (`pipelines::shader_sources`);
    /// `None` for a method with no pass or one that reuses another's.
    pub shader: Option<(&'static str, &'static str)>,
    /// Records its passes.
    pub(in crate::render) encode: Encode,
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

/// When a method's frames differ only by random rotations.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stochastic {
    Never,
    Always,
    /// With stochastic axis rotation on (`RenderSettings::separable_rotation`).
    WhenRotated,
}

/// The tables a method reads that cost time to bake.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Reads {
    /// The importance-sampled separable kernel (about 45 ms for the default skin).
    pub separable_kernel: bool,
    /// Penner's pre-integrated and penumbra tables (25 ms).
    pub penner_tables: bool,
    /// The Gaussians (a six-Gaussian fit of any other profile).
    pub gaussians: bool,
}

/// The registry of methods: the one `match` over [`Method`]'s variants.
/// Every list (`Method::all`, the bench's configurations, the editor's
/// menus) and every property comes from here and the enum's declaration.
impl Method {
    pub fn sss(self) -> &'static MethodInfo {
        match self {
            Method::None => &none::METHOD,
            Method::Burley => &burley::METHOD,
            Method::Separable => &separable::METHOD,
            Method::Gaussians => &gaussians::METHOD,
            Method::Preintegrated => &preintegrated::METHOD,
            Method::Reference => &reference::METHOD,
        }
    }

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

    /// The first method whose quality is set by `quality`'s count
    /// (`burley` for samples, `separable` for taps).
    pub fn by_quality(quality: Quality) -> Method {
        Self::the_one(|m| m.quality == quality)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The six methods, each once, in the declaration's order, and each
    /// one's id is the name clap gives its variant (`--method`), which is
    /// what reports and the bench's CSV carry.
    #[test]
    fn method_ids_are_clap_names() {
        let ids: Vec<&str> = Method::all().iter().map(|m| m.id()).collect();
        let listed = [
            "none",
            "burley",
            "separable",
            "gaussians",
            "preintegrated",
            "reference",
        ];
        assert_eq!(ids, listed);
        for &m in Method::all() {
            let name = clap::ValueEnum::to_possible_value(&m).map(|v| v.get_name().to_owned());
            assert_eq!(name.as_deref(), Some(m.id()));
        }
    }

    /// The roles the renderer, the editor and the bench look up are each
    /// held by exactly one method, and each of the three quality counts
    /// by at least one.
    #[test]
    fn each_role_is_held_by_one_method() {
        let count =
            |p: &dyn Fn(&MethodInfo) -> bool| Method::all().iter().filter(|m| p(m.sss())).count();
        assert_eq!(count(&|m| m.ground_truth), 1);
        assert_eq!(count(&|m| m.baseline), 1);
        for q in [Quality::Fixed, Quality::Samples, Quality::Taps] {
            assert!(count(&|m| m.quality == q) >= 1, "{q:?}");
        }
        assert_eq!(Method::ground_truth().id(), "reference");
        assert_eq!(Method::baseline().id(), "none");
        assert_eq!(Method::by_quality(Quality::Samples).id(), "burley");
        assert_eq!(Method::by_quality(Quality::Taps).id(), "separable");
        assert_eq!(Method::ground_truth().preview(), Method::default());
        let ids: Vec<&str> = Method::all().iter().map(|m| m.id()).collect();
        let mut unique = ids.clone();
        unique.sort();
        unique.dedup();
        assert_eq!(unique.len(), ids.len(), "{ids:?}");
    }
}
