//! Unit constants and conversions between scatterlab's Burley parameters
//! (albedo A and scattering distance d in physical millimetres) and the
//! parameters of the engines artists ship on. Each conversion goes both
//! ways; round trips are exact to rounding (tests).

use super::burley::{Burley, ScalingFit};
use super::{check_range, check_rgb, rgb_map, ModelError, Rgb};
use std::f64::consts::PI;

pub const MM_PER_CM: f64 = 10.0;
pub const MM_PER_M: f64 = 1000.0;

/// Unity HDRP `DiffusionProfileSettings`: the scattering distance d (mm at
/// world scale 1) is stored as an LDR colour times a multiplier, split the
/// way `HDUtils.ConvertHDRColorToLDR` splits HDR input (the brightest
/// channel maps to 191/255). `world_scale_m_per_unit` tells HDRP how many
/// metres one scene unit is; with it set correctly d stays physical.
/// Unity keeps the albedo in the material, not in the profile.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnityProfile {
    pub scattering_distance_color: Rgb,
    pub scattering_distance_multiplier: f64,
    pub world_scale_m_per_unit: f64,
}

impl UnityProfile {
    pub fn from_burley(b: &Burley, world_scale_m_per_unit: f64) -> Result<Self, ModelError> {
        check_range(
            "world_scale_m_per_unit",
            world_scale_m_per_unit,
            1e-3,
            1e3,
            " m/unit",
        )?;
        let (color, multiplier) = split_hdr(b.scattering_distance_mm());
        Ok(Self {
            scattering_distance_color: color,
            scattering_distance_multiplier: multiplier,
            world_scale_m_per_unit,
        })
    }

    /// Back to Burley; Unity's profile has no albedo, so it is supplied.
    pub fn to_burley(&self, albedo: Rgb) -> Result<Burley, ModelError> {
        check_rgb(
            "scattering_distance_color",
            self.scattering_distance_color,
            0.0,
            1.0,
            "",
        )?;
        check_range(
            "scattering_distance_multiplier",
            self.scattering_distance_multiplier,
            0.0,
            1e6,
            "",
        )?;
        let d =
            rgb_map(|c| self.scattering_distance_color[c] * self.scattering_distance_multiplier);
        Burley::from_scattering_distance(albedo, d)
    }
}

/// HDRP's `ConvertHDRColorToLDR`: ldr = min(191, 191/max·hdr)/255 and
/// intensity = 255·max/191, so ldr·intensity = hdr.
pub fn split_hdr(hdr: Rgb) -> (Rgb, f64) {
    const K: f64 = 191.0;
    let max = hdr.into_iter().fold(0.0, f64::max);
    if max == 0.0 {
        return (hdr, 1.0);
    }
    let scale = K / max;
    (rgb_map(|c| (scale * hdr[c]).min(K) / 255.0), 255.0 / scale)
}

/// Unreal Engine 5 `FSubsurfaceProfileStruct` with Burley and mean free
/// path enabled (UE 5.1+; sources read at 5.1.1). UE turns the mean free
/// path MFP = MeanFreePathColor × MeanFreePathDistance (cm) into
/// DMFP_mm = MFP·10·S_dmfp(A)/S_perp(A)/0.6 (SubsurfaceProfile.cpp line
/// 473, `Dmfp2MfpMagicNumber` line 82), and its shader uses the shape
/// S_dmfp(A)/DMFP; together d = MFP_mm/(0.6·S_perp(A)).
/// A world distance in cm maps to profile millimetres as
/// cm·10·WorldUnitScale/0.1 (BurleyNormalizedSSS.cpp), so the physical d is
/// d_profile·0.1/WorldUnitScale (the default 0.1 is physical).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UnrealProfile {
    pub surface_albedo: Rgb,
    pub mean_free_path_color: Rgb,
    pub mean_free_path_distance_cm: f64,
    pub world_unit_scale: f64,
}

/// UE5's `Dmfp2MfpMagicNumber` (SubsurfaceProfile.cpp line 82, 5.1.1).
pub const UNREAL_DMFP_TO_MFP: f64 = 0.6;
/// UE's default world unit scale (physical profiles).
pub const UNREAL_DEFAULT_WORLD_UNIT_SCALE: f64 = 0.1;
/// `MeanFreePathDistance`'s ClampMin (SubsurfaceProfile.h lines 31–32):
/// shorter paths are folded into the colour, as UE's own upgrade does
/// (SubsurfaceProfile.cpp lines 97–101, "Support mfp < 0.1f").
pub const UNREAL_MIN_MEAN_FREE_PATH_CM: f64 = 0.1;
/// `MeanFreePathColor`'s ClampMin (SubsurfaceProfile.h lines 25–26).
pub const UNREAL_MIN_MEAN_FREE_PATH_COLOR: f64 = 0.001;
/// UE's `SUBSURFACE_KERNEL_SIZE` (SubsurfaceProfile.h line 261), in cm.
const UNREAL_SUBSURFACE_KERNEL_SIZE: f64 = 3.0;

impl UnrealProfile {
    pub fn from_burley(b: &Burley, world_unit_scale: f64) -> Result<Self, ModelError> {
        check_range("world_unit_scale", world_unit_scale, 1e-4, 50.0, "")?;
        let a = b.albedo();
        let d = b.scattering_distance_mm();
        let mfp_mm = rgb_map(|c| {
            d[c] * world_unit_scale / UNREAL_DEFAULT_WORLD_UNIT_SCALE
                * UNREAL_DMFP_TO_MFP
                * ScalingFit::Perpendicular.scale(a[c])
        });
        let max = mfp_mm.into_iter().fold(0.0, f64::max);
        Ok(Self {
            surface_albedo: a,
            mean_free_path_color: rgb_map(|c| mfp_mm[c] / max),
            mean_free_path_distance_cm: max / MM_PER_CM,
            world_unit_scale,
        }
        .fold_short_distance())
    }

    /// UE clamps MeanFreePathDistance to at least 0.1 cm; a shorter path
    /// keeps its product by scaling the colour down (SubsurfaceProfile.cpp
    /// lines 97–101, 5.1.1), which this does too.
    pub fn fold_short_distance(mut self) -> Self {
        let dist = self.mean_free_path_distance_cm;
        if dist < UNREAL_MIN_MEAN_FREE_PATH_CM && dist > 0.0 {
            let k = dist / UNREAL_MIN_MEAN_FREE_PATH_CM;
            self.mean_free_path_color = rgb_map(|c| self.mean_free_path_color[c] * k);
            self.mean_free_path_distance_cm = UNREAL_MIN_MEAN_FREE_PATH_CM;
        }
        self
    }

    /// Colour channels under UE's ClampMin of 0.001, which the editor would
    /// raise (and so lengthen that channel's path): the names of the
    /// channels whose value cannot be held exactly.
    pub fn clamped_channels(&self) -> Vec<&'static str> {
        ["red", "green", "blue"]
            .into_iter()
            .zip(self.mean_free_path_color)
            .filter(|(_, v)| *v < UNREAL_MIN_MEAN_FREE_PATH_COLOR)
            .map(|(n, _)| n)
            .collect()
    }

    /// What UE 5.1+ does to a profile saved before mean free paths
    /// (`UpgradeDiffuseMeanFreePathToMeanFreePath`, SubsurfaceProfile.cpp
    /// lines 84–109, 5.1.1): MeanFreePathColor × Distance was a diffuse
    /// mean free path; it becomes MFP = DMFP·S_perp(A)/S_dmfp(A)·0.6
    /// (`GetMeanFreePathFromDiffuseMeanFreePath`, BurleyNormalizedSSS.cpp
    /// lines 114–117), split again into colour and distance, folded below
    /// 0.1 cm, and WorldUnitScale is divided by SUBSURFACE_KERNEL_SIZE/10
    /// (line 109). UE's default profile (SubsurfaceProfile.h lines 114–134)
    /// reaches 5.1+ this way.
    pub fn upgrade_from_diffuse_mean_free_path(
        surface_albedo: Rgb,
        dmfp_color: Rgb,
        dmfp_distance_cm: f64,
        world_unit_scale: f64,
    ) -> Self {
        let a = surface_albedo;
        let mfp_cm = rgb_map(|c| {
            dmfp_color[c] * dmfp_distance_cm * ScalingFit::Perpendicular.scale(a[c])
                / ScalingFit::DiffuseMeanFreePath.scale(a[c])
                * UNREAL_DMFP_TO_MFP
        });
        let max = mfp_cm.into_iter().fold(0.0, f64::max);
        Self {
            surface_albedo: a,
            mean_free_path_color: rgb_map(|c| mfp_cm[c] / max),
            mean_free_path_distance_cm: max,
            world_unit_scale: world_unit_scale / (UNREAL_SUBSURFACE_KERNEL_SIZE / MM_PER_CM),
        }
        .fold_short_distance()
    }

    pub fn to_burley(&self) -> Result<Burley, ModelError> {
        check_rgb("surface_albedo", self.surface_albedo, 0.0, 1.0, "")?;
        check_rgb(
            "mean_free_path_color",
            self.mean_free_path_color,
            0.0,
            1.0,
            "",
        )?;
        check_range(
            "mean_free_path_distance_cm",
            self.mean_free_path_distance_cm,
            1e-6,
            1e3,
            " cm",
        )?;
        check_range("world_unit_scale", self.world_unit_scale, 1e-4, 50.0, "")?;
        let a = self.surface_albedo;
        let d = rgb_map(|c| {
            let mfp_mm = self.mean_free_path_color[c] * self.mean_free_path_distance_cm * MM_PER_CM;
            mfp_mm / (UNREAL_DMFP_TO_MFP * ScalingFit::Perpendicular.scale(a[c]))
                * UNREAL_DEFAULT_WORLD_UNIT_SCALE
                / self.world_unit_scale
        });
        Burley::from_scattering_distance(a, d)
    }

    /// Copy-paste text for the details panel (struct export syntax).
    pub fn to_struct_text(&self) -> String {
        let c = |v: Rgb| format!("(R={:.9},G={:.9},B={:.9},A=1.000000)", v[0], v[1], v[2]);
        format!(
            "(SurfaceAlbedo={},MeanFreePathColor={},MeanFreePathDistance={:.9},WorldUnitScale={:.6},bEnableBurley=True,bEnableMeanFreePath=True)",
            c(self.surface_albedo),
            c(self.mean_free_path_color),
            self.mean_free_path_distance_cm,
            self.world_unit_scale
        )
    }
}

/// Blender's Principled BSDF with the Christensen–Burley method, as Cycles
/// (Blender 3.0 and later; checked in the Cycles sources of Blender 5.0.0)
/// reads it:
/// - `svm/closure.h` lines 468–470 form radius = max(Subsurface Radius ×
///   Subsurface Scale, 0) in scene units and take the clamped Base Color as
///   the BSSRDF's albedo (its closure weight, lines 462–463);
/// - `closure/bssrdf.h` `bssrdf_setup_radius` (lines 66–88) multiplies that
///   radius by 1/(4π), and `bssrdf_burley_eval` (lines 129–148) uses the
///   result as Burley's d: (e^{−r/d} + e^{−r/3d})/(4d) per unit radius.
///
/// So d = Radius × Scale × metres_per_unit / (4π), with no albedo term: the
/// s(A) fit of Christensen & Burley 2015 (`bssrdf_burley_setup`, still in
/// the file) has had no caller since Cycles X (Blender 3.0). The Cycles
/// render in `tests/real_clients.rs` recovers d from a shadow edge.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlenderSubsurface {
    pub base_color: Rgb,
    pub subsurface_radius: Rgb,
    pub subsurface_scale: f64,
    pub metres_per_unit: f64,
}

/// Cycles' `bssrdf_setup_radius`: Burley's d = radius / (4π).
const CYCLES_RADIUS_PER_D: f64 = 4.0 * PI;

impl BlenderSubsurface {
    pub fn from_burley(b: &Burley, metres_per_unit: f64) -> Result<Self, ModelError> {
        check_range("metres_per_unit", metres_per_unit, 1e-6, 1e3, " m/unit")?;
        let d_mm = b.scattering_distance_mm();
        // Radius × Scale in scene units = 4π d (bssrdf.h lines 68–71).
        let units = rgb_map(|c| d_mm[c] * CYCLES_RADIUS_PER_D / (MM_PER_M * metres_per_unit));
        let scale = units.into_iter().fold(0.0, f64::max);
        Ok(Self {
            base_color: b.albedo(),
            subsurface_radius: rgb_map(|c| if scale > 0.0 { units[c] / scale } else { 0.0 }),
            subsurface_scale: scale,
            metres_per_unit,
        })
    }

    pub fn to_burley(&self) -> Result<Burley, ModelError> {
        check_rgb("base_color", self.base_color, 0.0, 1.0, "")?;
        check_rgb("subsurface_radius", self.subsurface_radius, 0.0, 1e6, "")?;
        check_range(
            "subsurface_scale",
            self.subsurface_scale,
            0.0,
            1e6,
            " units",
        )?;
        check_range(
            "metres_per_unit",
            self.metres_per_unit,
            1e-6,
            1e3,
            " m/unit",
        )?;
        // d = Radius × Scale / (4π) (bssrdf.h lines 68–71), in mm.
        let d = rgb_map(|c| {
            self.subsurface_radius[c] * self.subsurface_scale * self.metres_per_unit * MM_PER_M
                / CYCLES_RADIUS_PER_D
        });
        Burley::from_scattering_distance(self.base_color, d)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn skin() -> Burley {
        Burley::from_scattering_distance([0.91058, 0.338275, 0.2718], [0.7568628, 0.32156864, 0.2])
            .unwrap()
    }

    fn close(a: Rgb, b: Rgb, tol: f64) -> bool {
        (0..3).all(|c| (a[c] - b[c]).abs() <= tol * b[c].abs().max(1e-12))
    }

    #[test]
    fn round_trips_are_exact() {
        let b = skin();
        for ws in [0.01, 1.0] {
            let u = UnityProfile::from_burley(&b, ws).unwrap();
            assert!(close(
                u.to_burley(b.albedo()).unwrap().scattering_distance_mm(),
                b.scattering_distance_mm(),
                1e-12
            ));
        }
        for wus in [0.1, 1.0, 0.02] {
            let u = UnrealProfile::from_burley(&b, wus).unwrap();
            let back = u.to_burley().unwrap();
            assert!(close(
                back.scattering_distance_mm(),
                b.scattering_distance_mm(),
                1e-12
            ));
            assert!(close(back.albedo(), b.albedo(), 1e-15));
        }
        let bl = BlenderSubsurface::from_burley(&b, 1.0).unwrap();
        assert!(close(
            bl.to_burley().unwrap().scattering_distance_mm(),
            b.scattering_distance_mm(),
            1e-12
        ));
        assert_eq!(bl.subsurface_radius[0], 1.0);
    }

    /// HDRP's split puts the brightest channel at 191/255 and keeps ldr·k = hdr.
    #[test]
    fn unity_split_follows_hdrp_rule() {
        let (ldr, k) = split_hdr([2.0, 0.5, 0.25]);
        assert!((ldr[0] - 191.0 / 255.0).abs() < 1e-15);
        assert!((ldr[1] * k - 0.5).abs() < 1e-15 && (k - 2.0 * 255.0 / 191.0).abs() < 1e-12);
    }

    /// UE5's "Skin1" preset stores MeanFreePathColor (1, 0.735, 0.518) ×
    /// 0.1295 cm, i.e. 1/σ′t of Jensen 2001's Skin1 in cm; our cm→mm reading
    /// gives 1/σ′t in mm to the preset's 3 digits.
    #[test]
    fn unreal_mean_free_path_units_match_measured_skin1() {
        let u = UnrealProfile {
            surface_albedo: [0.44, 0.22, 0.13],
            mean_free_path_color: [1.0, 0.735, 0.518],
            mean_free_path_distance_cm: 0.1295,
            world_unit_scale: 0.1,
        };
        let b = u.to_burley().unwrap();
        let mfp = rgb_map(|c| {
            b.scattering_distance_mm()[c]
                * UNREAL_DMFP_TO_MFP
                * ScalingFit::Perpendicular.scale(u.surface_albedo[c])
        });
        let sigma_t = [0.74 + 0.032, 0.88 + 0.17, 1.01 + 0.48];
        for c in 0..3 {
            assert!(
                (mfp[c] - 1.0 / sigma_t[c]).abs() < 2e-3,
                "c={c}: {} vs {}",
                mfp[c],
                1.0 / sigma_t[c]
            );
        }
    }

    /// Cycles uses d = Radius × Scale / (4π) (bssrdf.h `bssrdf_setup_radius`,
    /// Blender 5.0.0 lines 66–88): the default skin's red d = 0.7568628 mm is
    /// Radius 1 × Scale 4π·0.7568628e-3 m = 0.00951102 m, green and blue
    /// 0.32156864/0.7568628 = 0.424870 and 0.2/0.7568628 = 0.264249 of it,
    /// whatever the albedo (hand computation; the Cycles render in
    /// tests/real_clients.rs measures the same d from a shadow edge).
    #[test]
    fn blender_radius_is_four_pi_d_without_albedo() {
        let b = BlenderSubsurface::from_burley(&skin(), 1.0).unwrap();
        assert!((b.subsurface_scale - 0.009_511_02).abs() < 1e-8, "{b:?}");
        assert!((b.subsurface_radius[1] - 0.424_870).abs() < 1e-6, "{b:?}");
        assert!((b.subsurface_radius[2] - 0.264_249).abs() < 1e-6, "{b:?}");
        let white =
            Burley::from_scattering_distance([1.0; 3], skin().scattering_distance_mm()).unwrap();
        let w = BlenderSubsurface::from_burley(&white, 1.0).unwrap();
        assert_eq!(w.subsurface_radius, b.subsurface_radius);
        // Scene in centimetres: the same physical d takes 100× the scale.
        let cm = BlenderSubsurface::from_burley(&skin(), 0.01).unwrap();
        assert!((cm.subsurface_scale / b.subsurface_scale - 100.0).abs() < 1e-9);
    }

    /// UE's default struct (SubsurfaceProfile.h 5.1.1 lines 114–134:
    /// SurfaceAlbedo (0.91058, 0.338275, 0.2718), MeanFreePathColor
    /// (1, 0.1983/2.229, 0.1607/2.229), MeanFreePathDistance 1.2·2.229 cm,
    /// WorldUnitScale 0.1) upgraded as UE 5.1+ does. Figures worked by hand
    /// from UE's formulas: S_perp = 0.948885/2.200757/2.609788, S_dmfp =
    /// 14.862004/3.500000/3.501147, so MFP = (0.102467, 0.089776, 0.086246)
    /// cm, WorldUnitScale 1/3, and d = MFP·10/(0.6·S_perp)·0.1/(1/3) =
    /// (0.539934, 0.203966, 0.165237) mm: about half a millimetre, not the
    /// 47 mm that reading the defaults as a mean free path gives.
    #[test]
    fn unreal_default_profile_upgrades_to_half_a_millimetre() {
        let u = UnrealProfile::upgrade_from_diffuse_mean_free_path(
            [0.91058, 0.338275, 0.2718],
            [1.0, 0.1983 / 2.229, 0.1607 / 2.229],
            1.2 * 2.229,
            0.1,
        );
        assert!(
            (u.mean_free_path_distance_cm - 0.102_467).abs() < 1e-6,
            "{u:?}"
        );
        assert!((u.world_unit_scale - 1.0 / 3.0).abs() < 1e-12);
        let d = u.to_burley().unwrap().scattering_distance_mm();
        for (c, want) in [0.539_934, 0.203_966, 0.165_237].into_iter().enumerate() {
            assert!(
                (d[c] - want).abs() < 2e-6,
                "channel {c}: {} vs {want}",
                d[c]
            );
        }
        // The shipped preset holds exactly this look.
        let p = crate::settings::Preset::from_ron(
            include_str!("../../presets/skin_unreal_default.ron"),
            std::path::Path::new("presets/skin_unreal_default.ron"),
        )
        .unwrap();
        let crate::settings::ProfileSpec::Burley(spec) = &p.profile else {
            panic!("the Unreal default preset is Burley")
        };
        let pd = spec.build().unwrap().scattering_distance_mm();
        assert!(close(pd, d, 1e-5), "{pd:?} vs {d:?}");
    }

    /// UE keeps MeanFreePathDistance ≥ 0.1 cm and folds a shorter path into
    /// the colour (SubsurfaceProfile.cpp lines 97–101): the default skin's
    /// 0.0431 cm path becomes 0.1 cm with a colour 0.431× as large, and the
    /// look is unchanged.
    #[test]
    fn unreal_short_paths_fold_into_the_colour() {
        let u = UnrealProfile::from_burley(&skin(), UNREAL_DEFAULT_WORLD_UNIT_SCALE).unwrap();
        assert_eq!(u.mean_free_path_distance_cm, UNREAL_MIN_MEAN_FREE_PATH_CM);
        // MFP_red = 0.7568628 mm · 0.6 · S_perp(0.91058) = 0.0431 cm (hand).
        assert!(
            (u.mean_free_path_color[0] - 0.430_906).abs() < 1e-5,
            "{u:?}"
        );
        assert!(u.clamped_channels().is_empty());
        let back = u.to_burley().unwrap().scattering_distance_mm();
        assert!(close(back, skin().scattering_distance_mm(), 1e-12));
    }

    #[test]
    fn bad_engine_input_is_named() {
        let e = UnrealProfile {
            surface_albedo: [0.5; 3],
            mean_free_path_color: [1.0; 3],
            mean_free_path_distance_cm: -1.0,
            world_unit_scale: 0.1,
        }
        .to_burley()
        .unwrap_err();
        assert!(e.to_string().contains("mean_free_path_distance_cm"), "{e}");
    }
}
