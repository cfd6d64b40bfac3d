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
/// path enabled. UE5 (SubsurfaceProfile.cpp) turns the mean free path
/// MFP = MeanFreePathColor × MeanFreePathDistance (cm) into
/// DMFP_mm = MFP·10·S_dmfp(A)/S_perp(A)/0.6 (`Dmfp2MfpMagicNumber`), and
/// its shader uses the shape S_dmfp(A)/DMFP; together d = MFP_mm/(0.6·S_perp(A)).
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

/// UE5's `Dmfp2MfpMagicNumber`.
pub const UNREAL_DMFP_TO_MFP: f64 = 0.6;
/// UE's default world unit scale (physical profiles).
pub const UNREAL_DEFAULT_WORLD_UNIT_SCALE: f64 = 0.1;

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
        })
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

/// Blender's Principled BSDF with the Christensen–Burley method: Cycles
/// (`bssrdf_burley_setup`) scales Subsurface Radius × Subsurface Scale (scene
/// units) by 1/(4π) to a mean free path ℓ and uses d = ℓ/s(A) with the
/// diffuse-surface fit s(A) = 1.9 − A + 3.5(A − 0.8)² (C&B eq. 6), A = base colour.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlenderSubsurface {
    pub base_color: Rgb,
    pub subsurface_radius: Rgb,
    pub subsurface_scale: f64,
    pub metres_per_unit: f64,
}

impl BlenderSubsurface {
    pub fn from_burley(b: &Burley, metres_per_unit: f64) -> Result<Self, ModelError> {
        check_range("metres_per_unit", metres_per_unit, 1e-6, 1e3, " m/unit")?;
        let a = b.albedo();
        let d = b.scattering_distance_mm();
        let units = rgb_map(|c| {
            d[c] * 4.0 * PI * ScalingFit::DiffuseSurface.scale(a[c]) / (MM_PER_M * metres_per_unit)
        });
        let scale = units.into_iter().fold(0.0, f64::max);
        Ok(Self {
            base_color: a,
            subsurface_radius: rgb_map(|c| units[c] / scale),
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
        let a = self.base_color;
        let d = rgb_map(|c| {
            self.subsurface_radius[c] * self.subsurface_scale * self.metres_per_unit * MM_PER_M
                / (4.0 * PI * ScalingFit::DiffuseSurface.scale(a[c]))
        });
        Burley::from_scattering_distance(a, d)
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
