//! A look's inputs for every method, on the CPU ([`ProfileInputs`]: what
//! the methods share, `render/inputs.rs`, and each method's own) and on
//! the GPU ([`ProfileGpu`], uploaded once per fingerprint and reused by
//! every later frame).

use super::{Inputs, Knob, Look, MethodOptions};
use crate::model::{ModelError, RadialProfile};
use crate::render::inputs::Shared;
use crate::render::profile_gpu::SharedGpu;
use crate::render::settings::{Method, RenderSettings};
use crate::settings::ProfileSpec;

/// Every method's inputs for one look, and the options they were made
/// with: the GPU uploads each method's share ([`ProfileGpu`]).
#[derive(Debug, Clone)]
pub struct ProfileInputs {
    /// What every method shares: the transmittance table, the surface
    /// colour, whether anything scatters.
    pub shared: Shared,
    /// Each method's own (its file's `Inputs`).
    pub methods: Inputs,
    /// The methods' options (their command-line flags; the defaults in the
    /// editor), read as the inputs are made and by each frame.
    pub options: MethodOptions,
}

impl ProfileInputs {
    /// Everything every method needs for the look `spec` (built as
    /// `profile`): each method's tables, the slow ones ([`super::MethodInfo::slow_bake`],
    /// the Gaussians' fit) only for `method`.
    pub fn for_look(
        spec: &ProfileSpec,
        profile: &dyn RadialProfile,
        method: Method,
        counts: (usize, usize),
        options: &MethodOptions,
    ) -> Result<Self, ModelError> {
        Self::build(Some(spec), profile, counts, options, &|m| {
            m == method || !m.sss().slow_bake
        })
    }

    /// As [`ProfileInputs::for_look`], baking only the tables `method`
    /// reads. The others hold neutral placeholders of the same sizes, so
    /// these inputs must not render another method (the renderer refuses,
    /// [`ProfileInputs::missing_for`]). The editor's live viewport uses it:
    /// a dragged slider rebuilds the inputs every frame.
    pub fn for_method(
        spec: &ProfileSpec,
        profile: &dyn RadialProfile,
        method: Method,
        counts: (usize, usize),
        options: &MethodOptions,
    ) -> Result<Self, ModelError> {
        Self::build(Some(spec), profile, counts, options, &|m| m == method)
    }

    /// Every method's inputs for a bare profile, with `samples` and
    /// `taps` and the default options; the slow tables are left out.
    pub fn new(
        profile: &dyn RadialProfile,
        samples: usize,
        taps: usize,
    ) -> Result<Self, ModelError> {
        Self::build(
            None,
            profile,
            (samples, taps),
            &MethodOptions::default(),
            &|m| !m.sss().slow_bake,
        )
    }

    fn build(
        spec: Option<&ProfileSpec>,
        profile: &dyn RadialProfile,
        counts: (usize, usize),
        options: &MethodOptions,
        bake: &dyn Fn(Method) -> bool,
    ) -> Result<Self, ModelError> {
        let look = Look::new(spec, profile, counts, options);
        Ok(Self {
            shared: Shared::new(spec, profile),
            methods: Inputs::new(&look, bake)?,
            options: options.clone(),
        })
    }

    /// Sets `method`'s inputs to one of its bench configurations (`knob`,
    /// from its [`super::MethodInfo::bench`]) for the look `spec`.
    pub fn bench(
        &mut self,
        spec: &ProfileSpec,
        profile: &dyn RadialProfile,
        method: Method,
        knob: &Knob,
    ) -> Result<(), ModelError> {
        let options = self.options.clone();
        let look = Look::new(Some(spec), profile, (0, 0), &options);
        self.methods.bench(method, &look, knob)
    }

    /// Why these inputs cannot render `method` (the table it reads holds a
    /// placeholder), or `None` when they can: B of a comparison drawn with
    /// A's inputs drew `gaussians` as `none` and said nothing (issue 22).
    pub fn missing_for(&self, method: Method) -> Option<&'static str> {
        self.methods.missing(method)
    }

    /// Whether frames of `s` with these inputs differ only by their random
    /// rotations ([`super::is_stochastic`]).
    pub fn is_stochastic(&self, s: &RenderSettings) -> bool {
        super::is_stochastic(s, &self.options)
    }

    /// A hash of everything the GPU receives from these inputs: the renderer
    /// re-uploads tables, patterns and kernels only when it changes.
    pub fn fingerprint(&self) -> u64 {
        use std::hash::Hasher;
        let mut h = std::collections::hash_map::DefaultHasher::new();
        self.methods.fingerprint_into(&mut h);
        self.shared.fingerprint_into(&mut h);
        h.finish()
    }
}

/// The profile's GPU resources, uploaded once per distinct
/// [`ProfileInputs`]: what the methods share and each method's own.
pub(in crate::render) struct ProfileGpu {
    /// Fingerprint of the inputs these buffers hold.
    pub key: u64,
    pub shared: SharedGpu,
    /// Each method's buffers.
    pub methods: super::Buffers,
}

impl ProfileGpu {
    pub fn new(device: &wgpu::Device, queue: &wgpu::Queue, inputs: &ProfileInputs) -> Self {
        Self {
            key: inputs.fingerprint(),
            shared: SharedGpu::new(device, &inputs.shared),
            methods: super::Buffers::new(device, queue, &inputs.methods),
        }
    }
}
