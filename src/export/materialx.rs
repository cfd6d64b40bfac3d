//! MaterialX with an OpenPBR Surface (`open_pbr_surface`, MaterialX 1.39+,
//! OpenPBR 1.1) for USD/MaterialX pipelines: Houdini, Maya/Arnold,
//! Omniverse.
//!
//! OpenPBR defines `subsurface_radius × subsurface_radius_scale` as the mean
//! free path ℓ = 1/σt of the volume per channel (OpenPBR specification,
//! "Subsurface", index.html line 712) and `subsurface_color` as the observed
//! multiple-scattering albedo (line 713), which is Burley's A. Burley's d
//! and the volume's ℓ are tied by Christensen & Burley 2015's fit for the
//! searchlight configuration with the mean free path, d = ℓ/s(A), s(A) =
//! 1.85 − A + 7|A − 0.8|³ (their eq. 5; Unreal's `GetPerpendicularScalingFactor`
//! uses the same). So ℓ = d·s(A). Distances are written in millimetres with
//! `unittype="distance" unit="millimeter"`, so a MaterialX unit system
//! converts them to the scene's unit; a renderer that ignores units must
//! read them as millimetres (the document's comment says so).

use super::{burley_of, Provenance};
use crate::model::burley::ScalingFit;
use crate::model::{ModelError, Rgb};
use crate::settings::Preset;

/// The OpenPBR subsurface of a look: mean free path per channel in mm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OpenPbrSubsurface {
    pub color: Rgb,
    /// `subsurface_radius`: the largest channel's mean free path, mm.
    pub radius_mm: f64,
    /// `subsurface_radius_scale`: each channel's path over the largest.
    pub radius_scale: Rgb,
}

pub fn open_pbr_subsurface(preset: &Preset) -> Result<(OpenPbrSubsurface, f64), ModelError> {
    let (burley, fit_error) = burley_of(&preset.profile)?;
    let a = burley.albedo();
    let d = burley.scattering_distance_mm();
    // ℓ = d·s(A), Christensen & Burley 2015 eq. 5.
    let mfp_mm: Rgb = std::array::from_fn(|c| d[c] * ScalingFit::Perpendicular.scale(a[c]));
    let max = mfp_mm.into_iter().fold(0.0, f64::max);
    let scale = std::array::from_fn(|c| if max > 0.0 { mfp_mm[c] / max } else { 0.0 });
    Ok((
        OpenPbrSubsurface {
            color: a,
            radius_mm: max,
            radius_scale: scale,
        },
        fit_error,
    ))
}

/// Text safe inside an XML comment (no "--").
fn comment_text(s: &str) -> String {
    s.replace("--", "- -").replace(['\n', '\r'], " ")
}

/// An XML name: letters, digits and '_', not starting with a digit.
fn xml_name(s: &str) -> String {
    let n: String = s
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    let n = n.trim_matches('_').to_owned();
    if n.is_empty() {
        "look".into()
    } else {
        n
    }
}

pub fn materialx_document(preset: &Preset, prov: &Provenance) -> Result<String, ModelError> {
    let (s, fit_error) = open_pbr_subsurface(preset)?;
    let r = &preset.rendering;
    let name = xml_name(&preset.name);
    let c3 = |v: Rgb| format!("{}, {}, {}", v[0], v[1], v[2]);
    let fit = if fit_error > 0.0 {
        format!("converted through a Burley fit (relative L2 error of r*R(r): {fit_error:.4})")
    } else {
        "exact Burley parameters".into()
    };
    Ok(format!(
        r#"<?xml version="1.0"?>
<!-- OpenPBR Surface for "{title}": {line}.
     {fit}. subsurface_radius x subsurface_radius_scale is the mean free path
     l = d s(A) per channel, in millimetres (unit attribute), with Burley's d
     and s(A) = 1.85 - A + 7|A - 0.8|^3 (Christensen and Burley 2015 eq. 5);
     subsurface_color is the albedo A. A renderer without MaterialX units must
     convert millimetres to its scene unit. The dual-lobe specular is not
     representable: specular_roughness is the base roughness. -->
<materialx version="1.39" colorspace="lin_rec709">
  <open_pbr_surface name="SR_{name}" type="surfaceshader">
    <input name="base_color" type="color3" value="{color}" />
    <input name="specular_ior" type="float" value="{ior}" />
    <input name="specular_roughness" type="float" value="{rough}" />
    <input name="subsurface_weight" type="float" value="1" />
    <input name="subsurface_color" type="color3" value="{color}" />
    <input name="subsurface_radius" type="float" value="{radius}" unittype="distance" unit="millimeter" />
    <input name="subsurface_radius_scale" type="color3" value="{scale}" />
  </open_pbr_surface>
  <surfacematerial name="M_{name}" type="material">
    <input name="surfaceshader" type="surfaceshader" nodename="SR_{name}" />
  </surfacematerial>
</materialx>
"#,
        title = comment_text(&preset.name),
        line = comment_text(&prov.line()),
        color = c3(s.color),
        ior = r.ior,
        rough = r.specular.roughness,
        radius = s.radius_mm,
        scale = c3(s.radius_scale),
    ))
}

mod read;
pub use read::read;
pub(super) use read::scattering_distance;

/// MaterialX OpenPBR as an export target.
pub(super) const TARGET: super::Target = super::Target {
    id: "materialx",
    name: "MaterialX OpenPBR",
    description: "an .mtlx document with an open_pbr_surface",
    extension: "mtlx",
    companion: None,
    slow: false,
    write: |preset, prov, out, _, _| {
        super::write(out, materialx_document(preset, prov)?.as_bytes())
    },
    notes: |preset| {
        Ok(vec![
            super::burley_note(preset)?,
            "The dual-lobe specular is not representable in OpenPBR: the base roughness is written.".into(),
        ])
    },
    fidelity: super::burley_fidelity,
    params: None,
    reader: Some(super::Reader {
        extensions: &["mtlx"],
        claims: |ext, text| {
            let head = text.trim_start();
            ext == "mtlx" || head.starts_with("<?xml") || head.starts_with("<materialx")
        },
        read,
    }),
};

#[cfg(test)]
mod tests {
    use super::*;

    /// The default skin: d = 0.7568628 mm at A = 0.91058 gives
    /// ℓ = 0.7568628 × (1.85 − 0.91058 + 7·0.11058³) = 0.7568628 × 0.948885
    /// = 0.718176 mm (hand computation of C&B eq. 5).
    #[test]
    fn mean_free_path_is_d_times_s() {
        let (s, e) = open_pbr_subsurface(&Preset::default_skin()).unwrap();
        assert_eq!(e, 0.0);
        assert!((s.radius_mm - 0.718_176).abs() < 1e-6, "{s:?}");
        assert_eq!(s.radius_scale[0], 1.0);
    }

    #[test]
    fn names_and_comments_are_xml_safe() {
        assert_eq!(xml_name("Skin (default)"), "Skin__default");
        assert_eq!(comment_text("a--b"), "a- -b");
    }
}
