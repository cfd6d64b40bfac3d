//! A look's albedo: the colour a profile gives the surface, how a look
//! whose engine keeps the albedo in the material (HDRP: the profile's file
//! has none, `RenderingSpec::albedo_in_material`) is drawn, and how a
//! colour map and the look's albedo combine. The editor, the renderer and
//! the preset browser resolve it here, and the compare row lists the
//! engine fields two looks differ in ([`differing_fields`]).

use super::{Preset, ProfileSpec};
use crate::model::{RadialProfile, Rgb};

/// Base colour for kernels without a colour (see [`look_colour`]): the
/// default skin's albedo A (presets/skin_default.ron, Unreal's default
/// SurfaceAlbedo).
pub const KERNEL_SURFACE_ALBEDO: [f32; 3] = [0.91058, 0.338275, 0.2718];

/// Where the surface colour comes from when a mesh has a colour map of
/// its own ([`AlbedoMode::Absolute`]); a modulating map (the default
/// head's) always multiplies the look's colour. An engine's material
/// takes its base colour from the map, and the profile spreads light
/// without changing its colour (HDRP, Unreal, Cycles), so the map alone
/// draws every look in the scan's colour: `Tinted` and `Look` are how a
/// look's own albedo A is seen on a scan.
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Default,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
pub enum MapColour {
    /// The map is the albedo, as the engines draw it.
    #[default]
    Map,
    /// The map's detail scaled so that its mean is the look's albedo:
    /// albedo(uv) = A · map(uv) / mean(map), per channel.
    Tinted,
    /// The look's albedo everywhere; the map's colour is not used.
    Look,
}

impl MapColour {
    pub const ALL: [MapColour; 3] = [MapColour::Map, MapColour::Tinted, MapColour::Look];

    pub fn label(self) -> &'static str {
        match self {
            MapColour::Map => "the map's colour",
            MapColour::Tinted => "the map tinted by the look's albedo",
            MapColour::Look => "the look's albedo",
        }
    }
}

/// The albedo a look is drawn and compared with when its engine keeps the
/// albedo in the material (`RenderingSpec::albedo_in_material`: an HDRP
/// profile, whose file has none).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, Default)]
pub enum MaterialAlbedo {
    /// Look A's albedo: the question "how far is my look from this
    /// engine's profile?" with the colour held equal.
    #[default]
    LookA,
    /// The head's colour map as the engine's material would use it (the
    /// map's mean colour stands for it in the plots).
    Map,
    /// The default skin's albedo ([`KERNEL_SURFACE_ALBEDO`], Unreal's
    /// default SurfaceAlbedo): a skin colour whatever look was open.
    DefaultSkin,
    /// A colour the artist typed (linear RGB).
    Typed([f64; 3]),
}

impl MaterialAlbedo {
    /// Short, for the compare row ("B's albedo: …").
    pub fn label(self) -> String {
        match self {
            MaterialAlbedo::LookA => "A's".into(),
            MaterialAlbedo::Map => "the head's map".into(),
            MaterialAlbedo::DefaultSkin => "the default skin's".into(),
            MaterialAlbedo::Typed(c) => format!("typed {:.3}/{:.3}/{:.3}", c[0], c[1], c[2]),
        }
    }
}

/// The colour a look gives the surface (`render::inputs::Shared::surface_albedo`):
/// its profile's total reflectance, clamped to [0, 1]; kernels without a
/// colour of their own (energy-conserving blurs, total 1: Jimenez 2012,
/// the artist model) leave it to the surface, as in the engines, and the
/// default skin's albedo stands in for a colour map.
pub fn look_colour(spec: &ProfileSpec, profile: &dyn RadialProfile) -> [f32; 3] {
    if matches!(spec, ProfileSpec::Jimenez2012(_) | ProfileSpec::Artist(_)) {
        return KERNEL_SURFACE_ALBEDO;
    }
    profile
        .total_reflectance()
        .map(|t| t.clamp(0.0, 1.0) as f32)
}

/// The colour `p` gives the surface: Burley's A, else the profile's total
/// reflectance, clamped to [0, 1] ([`look_colour`], which
/// also gives kernels without a colour the default skin's).
pub fn look_albedo(p: &Preset) -> Rgb {
    if let ProfileSpec::Burley(b) = &p.profile {
        return b.albedo;
    }
    match p.profile.build() {
        Ok(profile) => look_colour(&p.profile, profile.as_ref()).map(|c| c as f64),
        Err(_) => KERNEL_SURFACE_ALBEDO.map(|c| c as f64),
    }
}

/// `p` with its albedo set to `rgb` (clamped to Burley's range), where its
/// model has one (HDRP's profiles are Burley's). Returns whether it did.
pub fn set_albedo(p: &mut Preset, rgb: Rgb) -> bool {
    let (lo, hi) = crate::model::burley::ALBEDO_RANGE;
    match &mut p.profile {
        ProfileSpec::Burley(b) => {
            b.albedo = rgb.map(|c| c.clamp(lo, hi));
            true
        }
        _ => false,
    }
}

/// The colour a material-albedo choice stands for: A's, the map's mean
/// (A's without a colour map), the default skin's, or the typed one.
pub fn resolve(choice: MaterialAlbedo, a_albedo: Rgb, map_mean: Option<[f32; 3]>) -> Rgb {
    match choice {
        MaterialAlbedo::LookA => a_albedo,
        MaterialAlbedo::Map => map_mean.map_or(a_albedo, |m| m.map(|c| c as f64)),
        // The preset's own numbers (f64), not KERNEL_SURFACE_ALBEDO's f32.
        MaterialAlbedo::DefaultSkin => look_albedo(&Preset::default_skin()),
        MaterialAlbedo::Typed(c) => c,
    }
}

/// B as the editor draws and compares it: a look whose engine keeps the
/// albedo in the material gets `choice`'s colour, and on a colour map it
/// is drawn in the map's colour when the choice is the map. Returns the
/// look, its surface colour on a colour map, and the choice's label where
/// one was applied.
pub fn b_as_drawn(
    mut b: Preset,
    a_albedo: Rgb,
    choice: MaterialAlbedo,
    map_colour: MapColour,
    map_mean: Option<[f32; 3]>,
) -> (Preset, MapColour, Option<String>) {
    if !b.rendering.albedo_in_material {
        return (b, map_colour, None);
    }
    let rgb = resolve(choice, a_albedo, map_mean);
    if !set_albedo(&mut b, rgb) {
        return (b, map_colour, None);
    }
    let (colour, label) = match (choice, map_mean) {
        (MaterialAlbedo::Map, Some(_)) => (MapColour::Map, choice.label()),
        (MaterialAlbedo::Map, None) => (map_colour, "A's (no colour map)".into()),
        _ => (map_colour, choice.label()),
    };
    (b, colour, Some(label))
}

/// The engine-side fields in which B's look differs from A's, named with
/// both values (the compare row lists them beside B − A: what a profile's
/// shape error does not show).
pub fn differing_fields(a: &Preset, b: &Preset) -> Vec<(&'static str, String)> {
    let (ra, rb) = (&a.rendering, &b.rendering);
    let mut out = Vec::new();
    let mut diff = |name: &'static str, x: String, y: String| {
        if x != y {
            out.push((name, format!("{name}: B {y}, A {x}")));
        }
    };
    diff(
        "texturing",
        format!("{:?}", ra.texturing),
        format!("{:?}", rb.texturing),
    );
    diff(
        "transmission",
        format!("{:?}", ra.transmission),
        format!("{:?}", rb.transmission),
    );
    diff(
        "world scale",
        format!("{} m/unit", ra.world_scale_m_per_unit),
        format!("{} m/unit", rb.world_scale_m_per_unit),
    );
    diff(
        "thickness remap",
        format!("{:?} mm", ra.thickness_remap_mm),
        format!("{:?} mm", rb.thickness_remap_mm),
    );
    diff(
        "transmission tint",
        format!("{:.3?}", ra.transmission_tint),
        format!("{:.3?}", rb.transmission_tint),
    );
    diff("IOR", format!("{:.3}", ra.ior), format!("{:.3}", rb.ior));
    diff(
        "specular",
        format!("{:.3?}", ra.specular),
        format!("{:.3?}", rb.specular),
    );
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An HDRP import (albedo 1, in the material) compared as B takes A's
    /// albedo by default, the typed one when chosen, and the map's mean
    /// drawn as the map when there is one; a look with its own albedo is
    /// left alone.
    #[test]
    fn b_takes_the_chosen_material_albedo() {
        let a = Preset::default_skin();
        let mut hdrp = Preset::default();
        hdrp.rendering.albedo_in_material = true;
        let (b, mc, label) = b_as_drawn(
            hdrp.clone(),
            look_albedo(&a),
            MaterialAlbedo::LookA,
            MapColour::Tinted,
            None,
        );
        assert_eq!(look_albedo(&b), look_albedo(&a));
        assert_eq!((mc, label.as_deref()), (MapColour::Tinted, Some("A's")));
        let typed = [0.2, 0.5, 0.1];
        let (b, ..) = b_as_drawn(
            hdrp.clone(),
            look_albedo(&a),
            MaterialAlbedo::Typed(typed),
            MapColour::Map,
            None,
        );
        assert_eq!(look_albedo(&b), typed);
        let mean = [0.5f32, 0.25, 0.125];
        let (b, mc, _) = b_as_drawn(
            hdrp.clone(),
            look_albedo(&a),
            MaterialAlbedo::Map,
            MapColour::Look,
            Some(mean),
        );
        assert_eq!(look_albedo(&b), [0.5, 0.25, 0.125]);
        assert_eq!(mc, MapColour::Map);
        // Without a colour map the map choice falls back to A's, and says so.
        let (b, _, label) = b_as_drawn(
            hdrp,
            look_albedo(&a),
            MaterialAlbedo::Map,
            MapColour::Map,
            None,
        );
        assert_eq!(look_albedo(&b), look_albedo(&a));
        assert!(label.unwrap().contains("no colour map"));
        let own = Preset::default_skin();
        let (b, _, label) = b_as_drawn(
            own.clone(),
            look_albedo(&a),
            MaterialAlbedo::Typed(typed),
            MapColour::Map,
            None,
        );
        assert_eq!((b, label), (own, None));
    }
}
