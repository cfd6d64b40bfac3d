//! Per-profile inputs of every method, computed on the CPU from the
//! profile core and rebuilt only when the profile or the counts change.
//! Each method's share is its own `Inputs`, declared in its file under
//! `sss/` beside the buffers that upload it; what is here is what they
//! share (the transmittance table, the surface colour, whether anything
//! scatters) and which of the costly tables were baked.

use super::sss::{self, separable, Reads};
use crate::model::separable::SeparableKernel;
use crate::model::{ModelError, RadialProfile, Rgb};

pub use super::settings::BurleySampling;
pub use super::sss::gaussians::{gaussian_taps, gaussian_terms, DIRAC_VARIANCE_MM2, GAUSSIAN_TAPS};

/// Base colour for kernels without a colour (see [`look_colour`]): the
/// default skin's albedo A (presets/skin_default.ron, Unreal's default
/// SurfaceAlbedo).
pub const KERNEL_SURFACE_ALBEDO: [f32; 3] = [0.91058, 0.338275, 0.2718];

/// Every method's inputs for one profile: the GPU uploads each method's
/// share (`profile_gpu.rs`).
#[derive(Debug, Clone)]
pub struct ProfileInputs {
    /// Each method's own (`sss::Inputs`).
    pub methods: sss::Inputs,
    /// False when no channel scatters (e.g. Jimenez strength 0): SSS passes are skipped.
    pub scatters: bool,
    /// Normalised thin-slab transmittance T(d)/total at d = range·i/63
    /// (the scene pass's, for every method).
    pub transmittance: Vec<[f32; 4]>,
    pub transmittance_range_mm: f32,
    /// The look's colour: its total diffuse reflectance ∫2πr R(r) dr per
    /// channel (Burley's A), clamped to [0, 1]. The scattering kernels are
    /// energy-normalised, as in the engines, so this is where the look's
    /// colour enters: the base colour of a surface whose map only
    /// modulates (the default head), while a colour map of the artist's
    /// own is the albedo (HDRP, Unreal, Cycles: the material's base colour,
    /// the profile normalised).
    pub surface_albedo: [f32; 3],
    /// Which of the method-specific tables hold the profile (the others
    /// are neutral placeholders of the same sizes; the Gaussians are set
    /// afterwards, [`ProfileInputs::set_gaussians`]).
    baked: Reads,
}

impl ProfileInputs {
    /// Everything every method needs for the look `spec` (built as
    /// `profile`): a Jimenez 2012 look keeps the demo's kernel for
    /// `separable`, any other profile uses the importance-sampled
    /// pre-integrated kernel (Jimenez 2015 §4, §7); the Gaussians are set
    /// when `method` reads them: a Gaussian-sum look's own, six fitted to
    /// any other.
    pub fn for_look(
        spec: &crate::settings::ProfileSpec,
        profile: &dyn RadialProfile,
        method: super::Method,
        (samples, taps): (usize, usize),
        gaussian_taps: usize,
    ) -> Result<Self, ModelError> {
        let mut inputs = Self::new(profile, samples, taps)?;
        inputs.finish_look(spec, profile, method, taps, gaussian_taps)?;
        Ok(inputs)
    }

    /// What a look adds to a profile's inputs: the surface colour of
    /// colourless kernels, Jimenez 2012's own kernel, the Gaussians.
    fn finish_look(
        &mut self,
        spec: &crate::settings::ProfileSpec,
        profile: &dyn RadialProfile,
        method: super::Method,
        taps: usize,
        gaussian_taps: usize,
    ) -> Result<(), ModelError> {
        use crate::settings::ProfileSpec;
        self.surface_albedo = look_colour(spec, profile);
        if let ProfileSpec::Jimenez2012(j) = spec {
            self.set_separable_kernel(
                &crate::model::jimenez::Jimenez2012::new(j.strength, j.falloff)?.kernel(taps)?,
                true,
            );
        }
        if method.sss().reads.gaussians {
            self.set_gaussians(&gaussian_terms(spec, profile)?);
            self.methods.gaussians.taps = gaussian_taps;
        }
        Ok(())
    }

    /// As [`ProfileInputs::for_look`], baking only the tables `method`
    /// reads (its [`Reads`]). The others hold neutral placeholders of the
    /// same sizes, so these inputs must not render another method. The
    /// editor's live viewport uses it: a dragged slider rebuilds the inputs
    /// every frame.
    pub fn for_method(
        spec: &crate::settings::ProfileSpec,
        profile: &dyn RadialProfile,
        method: super::Method,
        (samples, taps): (usize, usize),
        gaussian_taps: usize,
    ) -> Result<Self, ModelError> {
        let mut inputs = Self::with_tables(profile, samples, taps, method.sss().reads)?;
        inputs.finish_look(spec, profile, method, taps, gaussian_taps)?;
        Ok(inputs)
    }

    /// Burley disk samples, the r·R_N(r) table, separable taps and
    /// Penner's tables for `profile`.
    pub fn new(
        profile: &dyn RadialProfile,
        samples: usize,
        taps: usize,
    ) -> Result<Self, ModelError> {
        let every_table = Reads {
            separable_kernel: true,
            penner_tables: true,
            gaussians: false,
        };
        Self::with_tables(profile, samples, taps, every_table)
    }

    fn with_tables(
        profile: &dyn RadialProfile,
        samples: usize,
        taps: usize,
        tables: Reads,
    ) -> Result<Self, ModelError> {
        let total = profile.total_reflectance();
        let r_max = profile
            .radius_for_energy(0.999)
            .into_iter()
            .fold(1e-6, f64::max);
        let dirac = profile.dirac_weight();
        Ok(Self {
            methods: sss::Inputs::new(profile, (samples, taps), tables, r_max, total)?,
            scatters: (0..3).any(|c| total[c] - dirac[c] > 1e-9 * total[c].max(1e-300)),
            transmittance: transmittance_table(profile, r_max, total),
            transmittance_range_mm: r_max as f32,
            surface_albedo: total.map(|t| t.clamp(0.0, 1.0) as f32),
            baked: Reads {
                gaussians: false,
                ..tables
            },
        })
    }

    /// Why these inputs cannot render `method` (the table it reads holds a
    /// placeholder), or `None` when they can: B of a comparison drawn with
    /// A's inputs drew `gaussians` as `none` and said nothing (issue 22).
    pub fn missing_for(&self, method: super::Method) -> Option<&'static str> {
        let reads = method.sss().reads;
        if reads.separable_kernel && !self.baked.separable_kernel {
            Some("the separable kernel's taps")
        } else if reads.penner_tables && !self.baked.penner_tables {
            Some("Penner's pre-integrated and penumbra tables")
        } else if reads.gaussians && self.methods.gaussians.gaussians.is_empty() {
            Some("the Gaussians")
        } else {
            None
        }
    }

    /// Rebuilds the `burley` patterns for another count or sampling strategy.
    pub fn set_burley(
        &mut self,
        profile: &dyn RadialProfile,
        samples: usize,
        sampling: BurleySampling,
    ) -> Result<(), ModelError> {
        self.methods.burley.set_patterns(profile, samples, sampling)
    }

    /// Replaces the separable taps (e.g. with the Jimenez 2012 demo kernel
    /// of a Jimenez 2012 profile instead of the pre-integrated one):
    /// `demo_2012` keeps the demo's follow-surface lerp, otherwise the depth
    /// weight's σ is the kernel's RMS width.
    pub fn set_separable_kernel(&mut self, kernel: &SeparableKernel, demo_2012: bool) {
        self.baked.separable_kernel = true;
        self.methods.separable = separable::Inputs::of_kernel(kernel, demo_2012);
    }

    /// Sets the Gaussians of the `gaussians` method from (variance mm²,
    /// RGB weight) terms; weights are normalised per channel (the albedo is
    /// applied separately).
    pub fn set_gaussians(&mut self, terms: &[(f64, [f64; 3])]) {
        self.methods.gaussians.set(terms);
    }

    /// A hash of everything the GPU receives from these inputs: the renderer
    /// re-uploads tables, patterns and kernels only when it changes.
    pub fn fingerprint(&self) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        self.methods.fingerprint_into(&mut h);
        h.write(bytemuck::cast_slice(&self.transmittance));
        h.write(bytemuck::cast_slice(&[self.transmittance_range_mm]));
        self.scatters.hash(&mut h);
        h.finish()
    }
}

/// The colour a look gives the surface (`ProfileInputs::surface_albedo`):
/// its profile's total reflectance, clamped to [0, 1]; kernels without a
/// colour of their own (energy-conserving blurs, total 1: Jimenez 2012,
/// the artist model) leave it to the surface, as in the engines, and the
/// default skin's albedo stands in for a colour map.
pub fn look_colour(spec: &crate::settings::ProfileSpec, profile: &dyn RadialProfile) -> [f32; 3] {
    use crate::settings::ProfileSpec;
    if matches!(spec, ProfileSpec::Jimenez2012(_) | ProfileSpec::Artist(_)) {
        return KERNEL_SURFACE_ALBEDO;
    }
    profile
        .total_reflectance()
        .map(|t| t.clamp(0.0, 1.0) as f32)
}

/// The thin-slab transmittance T(d)/total per channel at 64 thicknesses
/// d = r_max·i/63 (`shaders/scene.wgsl` `transmittance_at`).
fn transmittance_table(profile: &dyn RadialProfile, r_max: f64, total: Rgb) -> Vec<[f32; 4]> {
    (0..64)
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
        .collect()
}
