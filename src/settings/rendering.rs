//! The rendering part of a look: which real-time method, its quality, and
//! the material settings that engines keep next to the profile (texturing
//! and transmission modes, thickness remap, tint, IOR, world scale and the
//! dual-lobe specular). Unity's DiffusionProfileSettings holds the same
//! fields, which is why the Unity export reads them from here.

use crate::model::{check_range, check_rgb, ModelError, Rgb};
use serde::{Deserialize, Serialize};

/// SSS method: the one definition, used by presets (serde), the command
/// line (`clap::ValueEnum`: `--method burley`) and the renderer
/// (`render::Method` is this type). What each method is, its id, label and
/// properties, is in its own file under `render/sss/`, reached through the
/// registry `Method::sss` (`render/sss/mod.rs`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum,
)]
pub enum MethodId {
    /// Plain diffuse, the baseline.
    None,
    /// Golubev 2018 importance-sampled disk.
    #[default]
    Burley,
    /// Jimenez 2012 two-pass separable blur (Jimenez et al. 2015's
    /// pre-integrated kernel for every profile but Jimenez 2012's own).
    Separable,
    /// The profile as a sum of Gaussians, each blurred in two depth-aware 1D
    /// passes (d'Eon 2007 in screen space, Jimenez 2009): 12 passes for 6.
    Gaussians,
    /// Penner 2011 pre-integrated skin: D(θ, curvature) from a lookup table
    /// in the scene pass, no screen-space pass.
    Preintegrated,
    /// d'Eon & Luebke 2007 texture-space diffusion: the light gathered
    /// over the mesh's UV atlas, where surface the camera cannot see (the
    /// lid margin, the back of the ear) has its texels too.
    TextureSpace,
    /// The ground truth: the profile integrated over the whole SSS surface
    /// in object space on the CPU (`render::ground_truth`); seconds to
    /// minutes a frame.
    Reference,
}

impl MethodId {
    /// Every method, in the editor's and reports' order: clap's list of
    /// the enum (the declaration order), not a list kept by hand.
    pub fn all() -> &'static [MethodId] {
        <MethodId as clap::ValueEnum>::value_variants()
    }
}

/// Where the albedo is applied (Unity's `texturingMode`; d'Eon 2007): the
/// one definition (presets, `--texturing`, `render::TexturingMode`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum,
)]
pub enum TexturingId {
    /// √albedo before and after scattering (Unity 0): softer texture.
    #[default]
    #[value(name = "pre-and-post")]
    PreAndPostScatter,
    /// Albedo after scattering only (Unity 1): keeps scanned detail sharp.
    PostScatter,
}

/// Light through thin parts (Unity's `transmissionMode` plus off): the one
/// definition (presets, `--transmission`, `render::Transmission`).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize, Default, clap::ValueEnum,
)]
pub enum TransmissionId {
    /// No transmitted light.
    Off,
    /// Baked thickness, shadowed with the front face (Unity 1, "Thin
    /// Object"; Jimenez 2010).
    #[default]
    #[value(name = "thin")]
    ThinObject,
    /// max(baked, shadow-map) thickness, unshadowed (Unity 0, "Thick
    /// Object"; Golubev 2018).
    #[value(name = "thick")]
    ThickObject,
}

/// Unreal's dual-lobe GGX specular: two roughnesses, each a multiplier of
/// the material roughness, mixed by `lobe_mix` exactly as Unreal mixes
/// them: D = lerp(D_lobe0, D_lobe1, LobeMix) (ShadingModels.ush line 256,
/// UE 5.1.1), so `lobe_mix` is the weight of lobe 1, the rougher one. HDRP
/// weights its *smoother* lobe by its own `lobeMix` (Lit.hlsl
/// `EvaluateBSDF`), so the Unity export writes 1 − `lobe_mix`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DualLobeSpec {
    /// The material's roughness the multipliers apply to (perceptual, 0–1).
    pub roughness: f64,
    /// Multiplier of the first (sharper) lobe's roughness.
    pub lobe0_roughness_multiplier: f64,
    /// Multiplier of the second (broader) lobe's roughness.
    pub lobe1_roughness_multiplier: f64,
    /// Weight of lobe 1 (the rougher lobe), 0–1; lobe 0 gets 1 − this.
    pub lobe_mix: f64,
}

impl Default for DualLobeSpec {
    fn default() -> Self {
        // Unreal's FSubsurfaceProfileStruct defaults (SubsurfaceProfile.h,
        // UE 5.1.1 lines 95–102 and the constructor: Roughness0 0.75,
        // Roughness1 1.30, LobeMix 0.85, i.e. 85 % on the rougher lobe) on a
        // skin roughness of 0.55.
        Self {
            roughness: 0.55,
            lobe0_roughness_multiplier: 0.75,
            lobe1_roughness_multiplier: 1.30,
            lobe_mix: 0.85,
        }
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RenderingSpec {
    pub method: MethodId,
    /// Burley disk samples per pixel.
    pub samples: usize,
    /// Separable kernel taps (odd).
    pub taps: usize,
    /// Burley's level of detail (skip sub-pixel disks).
    pub lod: bool,
    pub texturing: TexturingId,
    pub transmission: TransmissionId,
    /// Thickness a black and a white texel of a thickness map stand for (mm).
    pub thickness_remap_mm: (f64, f64),
    /// Linear RGB multiplier of transmitted light.
    pub transmission_tint: Rgb,
    /// Index of refraction of the surface (specular F0).
    pub ior: f64,
    /// Metres per scene unit of the meshes this look is used on.
    pub world_scale_m_per_unit: f64,
    pub specular: DualLobeSpec,
    /// The look came from an engine that keeps the albedo in the material
    /// (HDRP: the profile's filter is normalised, its albedo 1), so the
    /// profile's albedo is not the surface's colour: the editor draws and
    /// compares it with a material albedo the artist chooses (look A's,
    /// the head's map, or a typed one) and says which.
    pub albedo_in_material: bool,
}

impl Default for RenderingSpec {
    fn default() -> Self {
        Self {
            method: MethodId::default(),
            samples: 21,
            taps: 17,
            lod: true,
            texturing: TexturingId::PreAndPostScatter,
            transmission: TransmissionId::ThinObject,
            // Unity's default thickness remap.
            thickness_remap_mm: (0.0, 5.0),
            transmission_tint: [1.0; 3],
            ior: 1.4,
            world_scale_m_per_unit: 1.0,
            specular: DualLobeSpec::default(),
            albedo_in_material: false,
        }
    }
}

/// The range each rendering field accepts: `RenderingSpec::validate`
/// checks it and the editor's rows stay inside it.
pub mod limits {
    /// `thickness_remap_mm` (both ends; the second at least the first).
    pub const THICKNESS_REMAP_MM: (f64, f64) = (0.0, 1e4);
    pub const TRANSMISSION_TINT: (f64, f64) = (0.0, 16.0);
    pub const IOR: (f64, f64) = (1.0, 2.0);
    pub const WORLD_SCALE_M_PER_UNIT: (f64, f64) = (1e-3, 1e3);
    /// `specular.roughness` and `specular.lobe_mix`.
    pub const UNIT: (f64, f64) = (0.0, 1.0);
    /// `specular.lobe0_roughness_multiplier` and `lobe1_…`.
    pub const LOBE_MULTIPLIER: (f64, f64) = (0.0, 2.0);
}

/// Burley sample counts the editor and presets accept.
pub const SAMPLES_RANGE: (usize, usize) = (1, 1024);
/// Separable tap counts (odd).
pub const TAPS_RANGE: (usize, usize) = (3, 129);

impl RenderingSpec {
    /// Checks every field; errors name it under `rendering.`.
    pub fn validate(&self) -> Result<(), ModelError> {
        let n = |field: &str, v: usize, (lo, hi): (usize, usize)| {
            check_range(
                &format!("rendering.{field}"),
                v as f64,
                lo as f64,
                hi as f64,
                "",
            )
        };
        n("samples", self.samples, SAMPLES_RANGE)?;
        n("taps", self.taps, TAPS_RANGE)?;
        if self.taps.is_multiple_of(2) {
            return Err(ModelError::invalid(
                "rendering.taps",
                format!("{} is even; the kernel needs a centre tap", self.taps),
            ));
        }
        let range = |field: &str, v: f64, (lo, hi): (f64, f64), unit: &'static str| {
            check_range(&format!("rendering.{field}"), v, lo, hi, unit)
        };
        let (lo, hi) = self.thickness_remap_mm;
        range(
            "thickness_remap_mm.0",
            lo,
            limits::THICKNESS_REMAP_MM,
            " mm",
        )?;
        let upper = (lo, limits::THICKNESS_REMAP_MM.1);
        range("thickness_remap_mm.1", hi, upper, " mm")?;
        let (lo, hi) = limits::TRANSMISSION_TINT;
        check_rgb(
            "rendering.transmission_tint",
            self.transmission_tint,
            lo,
            hi,
            "",
        )?;
        range("ior", self.ior, limits::IOR, "")?;
        let scale = self.world_scale_m_per_unit;
        range(
            "world_scale_m_per_unit",
            scale,
            limits::WORLD_SCALE_M_PER_UNIT,
            " m/unit",
        )?;
        let s = &self.specular;
        range("specular.roughness", s.roughness, limits::UNIT, "")?;
        let lobe0 = s.lobe0_roughness_multiplier;
        range(
            "specular.lobe0_roughness_multiplier",
            lobe0,
            limits::LOBE_MULTIPLIER,
            "",
        )?;
        let lobe1 = s.lobe1_roughness_multiplier;
        range(
            "specular.lobe1_roughness_multiplier",
            lobe1,
            limits::LOBE_MULTIPLIER,
            "",
        )?;
        range("specular.lobe_mix", s.lobe_mix, limits::UNIT, "")?;
        Ok(())
    }

    /// Specular reflectance at normal incidence from the IOR (Fresnel).
    pub fn f0(&self) -> f64 {
        let k = (self.ior - 1.0) / (self.ior + 1.0);
        k * k
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_validate_and_bad_fields_are_named() {
        RenderingSpec::default().validate().unwrap();
        let mut r = RenderingSpec {
            taps: 16,
            ..Default::default()
        };
        assert!(r
            .validate()
            .unwrap_err()
            .to_string()
            .contains("rendering.taps"));
        r.taps = 17;
        r.ior = f64::NAN;
        assert!(r
            .validate()
            .unwrap_err()
            .to_string()
            .contains("rendering.ior"));
        r.ior = 1.4;
        r.thickness_remap_mm = (3.0, 1.0);
        let e = r.validate().unwrap_err().to_string();
        assert!(e.contains("thickness_remap_mm.1"), "{e}");
    }

    /// Skin's IOR 1.4 gives F0 = (0.4/2.4)² = 0.02778 (Fresnel at normal
    /// incidence), the 0.028 the renderer used before the IOR was a field.
    #[test]
    fn f0_from_ior() {
        let r = RenderingSpec::default();
        assert!((r.f0() - 0.027_777_8).abs() < 1e-6);
    }
}
