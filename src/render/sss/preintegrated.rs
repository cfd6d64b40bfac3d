//! `preintegrated` (Penner 2011): no screen-space pass. The scene pass
//! (`shaders/scene.wgsl`) looks Penner's D(θ, κ) up from the profile
//! core's ring-integral table with the per-vertex mean curvature
//! (`Mesh::compute_curvature`: signed, a hollow read as flat), instead of
//! saturate(N·L), each channel with its own normal read from a mip of the
//! normal map as FaceWorks reads its blurred normal; this file gives the
//! scene pass its tables and uniforms ([`METHOD`]'s scene hook).

use super::{Look, MethodInputs, ProfileInputs};
use crate::model::lut::{LutLayout, ShadowLayout};
use crate::model::{ModelError, RadialProfile};
use crate::render::gpu_types::SceneUniforms;
use crate::render::profile_gpu::table;

/// `preintegrated` in the registry (`sss::Method::sss`).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "preintegrated",
    label: "preintegrated (Penner 2011)",
    colour: [140, 86, 75],
    scene: Some(super::SceneHook {
        tables: scene_tables,
        uniforms: scene_uniforms,
    }),
    ..super::MethodInfo::BASE
};

/// `preintegrated`'s options (none on the command line).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::Args)]
#[group(skip)]
pub struct Options {
    /// Scatter shadow edges through Penner's penumbra table.
    #[arg(skip = true)]
    pub penumbra: bool,
}

impl Default for Options {
    fn default() -> Self {
        Self { penumbra: true }
    }
}

/// Nothing is kept between frames, and its pass is the scene pass.
pub(in crate::render) type State = ();
pub(in crate::render) type Pipelines = ();

/// Penner's tables on the GPU, filterable, read by the scene pass.
pub(in crate::render) struct Buffers {
    /// D(θ, κ) − saturate(N·L).
    lut: wgpu::TextureView,
    /// The scattered shadow across a penumbra.
    penumbra: wgpu::TextureView,
}

impl super::MethodBuffers<Inputs> for Buffers {
    fn new(device: &wgpu::Device, queue: &wgpu::Queue, inputs: &Inputs) -> Self {
        let (lut, pen) = (&inputs.lut_layout, &inputs.penumbra_layout);
        Self {
            lut: table(
                device,
                queue,
                "pre-integrated lut",
                (lut.width, lut.height),
                &inputs.lut,
            ),
            penumbra: table(
                device,
                queue,
                "penumbra lut",
                (pen.width, pen.height),
                &inputs.penumbra_lut,
            ),
        }
    }
}

/// The scene pass's bindings 3 and 12.
fn scene_tables(buffers: &super::Buffers) -> [&wgpu::TextureView; 2] {
    let b = &buffers.preintegrated;
    [&b.lut, &b.penumbra]
}

/// Its terms of the scene's uniforms: on when `drawn`, the curvature 1/r
/// (1/mm) of the table's first and last rows, each channel's σ for its
/// blurred normal, the penumbra table and its widths.
fn scene_uniforms(inputs: &ProfileInputs, drawn: bool, u: &mut SceneUniforms) {
    let i = &inputs.methods.preintegrated;
    let (layout, pen) = (&i.lut_layout, &i.penumbra_layout);
    u.preintegrated = drawn as u32;
    u.lut_curvature_first = 1.0 / layout.curvature_radius(0) as f32;
    u.lut_curvature_last = 1.0 / layout.curvature_radius(layout.height - 1) as f32;
    let [r, g, b] = i.blur_sigma_mm;
    u.blur_sigma_mm = [r, g, b, 0.0];
    u.penumbra_on = inputs.options.preintegrated.penumbra as u32;
    u.penumbra_inv_width_first = 1.0 / pen.penumbra_max_mm as f32;
    u.penumbra_inv_width_last = 1.0 / pen.penumbra_min_mm as f32;
}

/// `preintegrated`'s CPU inputs: Penner's tables and per-channel normals.
#[derive(Debug, Clone)]
pub struct Inputs {
    /// Penner's table as FaceWorks stores it, D(θ, κ) − saturate(cos θ)
    /// (row-major, 64×64), and its layout. The shader adds saturate(N·L)
    /// back, so clamping to the edge texels (N·L = ±0.984) costs nothing
    /// at N·L = ±1.
    pub lut: Vec<[f32; 4]>,
    pub lut_layout: LutLayout,
    /// Penner's penumbra table (row-major) and its layout.
    pub penumbra_lut: Vec<[f32; 4]>,
    pub penumbra_layout: ShadowLayout,
    /// Per channel, the profile's per-axis σ (mm, `model::axis_sigma_mm`):
    /// each channel's blurred normal is the normal map read at the mip
    /// whose texels are σ wide (FaceWorks' `CalculateMipLevelForBlurredNormal`,
    /// `src/runtime.cpp` lines 158–161 of NVIDIAGameWorks/FaceWorks:
    /// log2(max(normalMapSize·diffusionRadius, averageUVScale) /
    /// averageUVScale), its diffusion radius 2.7 mm for skin being σ of
    /// d'Eon's widest Gaussian), so wide red light ignores pores and the
    /// mid-scale shape stays.
    pub blur_sigma_mm: [f32; 3],
    /// False for the placeholders of inputs made for another method.
    pub baked: bool,
}

impl MethodInputs for Inputs {
    fn new(look: &Look<'_>, bake: bool) -> Result<Self, ModelError> {
        Self::of_profile(look.profile, bake)
    }

    fn missing(&self) -> Option<&'static str> {
        (!self.baked).then_some("Penner's pre-integrated and penumbra tables")
    }

    fn fingerprint_into(&self, h: &mut impl std::hash::Hasher) {
        use std::hash::Hash;
        h.write(bytemuck::cast_slice(&self.lut));
        h.write(bytemuck::cast_slice(&self.penumbra_lut));
        h.write(bytemuck::cast_slice(&self.blur_sigma_mm));
        let (l, p) = (&self.lut_layout, &self.penumbra_layout);
        h.write(bytemuck::cast_slice(&[
            p.penumbra_min_mm,
            p.penumbra_max_mm,
        ]));
        h.write(bytemuck::cast_slice(&[p.width as u64, p.height as u64]));
        (l.width, l.height).hash(h);
        l.curvature_radius_min_mm.to_bits().hash(h);
        l.curvature_radius_max_mm.to_bits().hash(h);
    }
}

impl Inputs {
    /// Penner's tables of `profile`, or neutral placeholders of the same
    /// sizes when `bake` is off (25 ms saved for the other methods).
    pub fn of_profile(profile: &dyn RadialProfile, bake: bool) -> Result<Self, ModelError> {
        let lut_layout = LutLayout {
            width: 64,
            height: 64,
            curvature_radius_min_mm: 2.0,
            curvature_radius_max_mm: 200.0,
        };
        let penumbra_layout = ShadowLayout::default();
        let (lut, penumbra_lut) = penner_tables(profile, bake, lut_layout, penumbra_layout)?;
        let sigma = crate::model::axis_sigma_mm(profile);
        Ok(Self {
            lut,
            lut_layout,
            penumbra_lut,
            penumbra_layout,
            blur_sigma_mm: sigma.map(|s| s as f32),
            baked: bake,
        })
    }
}

/// Rows of RGBA texels, as uploaded.
type RgbaTable = Vec<[f32; 4]>;

/// Penner's D(θ, κ) − saturate(N·L) table and scattered-shadow table, or
/// zeros when `bake` is off (a method that never reads them).
fn penner_tables(
    profile: &dyn RadialProfile,
    bake: bool,
    lut_layout: LutLayout,
    penumbra_layout: ShadowLayout,
) -> Result<(RgbaTable, RgbaTable), ModelError> {
    Ok(if bake {
        let d = crate::model::lut::Lut::bake(profile, lut_layout)?
            .d
            .iter()
            .enumerate()
            .map(|(k, v)| {
                let lit = lut_layout.n_dot_l(k % lut_layout.width).max(0.0);
                [0, 1, 2].map(|c| (v[c] - lit) as f32)
            })
            .map(|d| [d[0], d[1], d[2], 1.0])
            .collect();
        let penumbra = crate::model::lut::bake_shadow(profile, penumbra_layout)?
            .iter()
            .map(|v| [v[0] as f32, v[1] as f32, v[2] as f32, 1.0])
            .collect();
        (d, penumbra)
    } else {
        // Zero: D(θ, κ) − saturate(N·L) of a profile that does not
        // scatter, and an unscattered shadow; never read by the others.
        (
            vec![[0.0, 0.0, 0.0, 1.0]; lut_layout.width * lut_layout.height],
            vec![[0.0, 0.0, 0.0, 1.0]; penumbra_layout.width * penumbra_layout.height],
        )
    })
}
