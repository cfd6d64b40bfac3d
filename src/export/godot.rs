//! Godot 4 `StandardMaterial3D` (`.tres`), Forward+ renderer.
//!
//! Godot's screen-space SSS cannot hold a profile: its kernel is baked into
//! the shader and a material only scales its width. What Godot renders, read
//! from its source (line numbers from Godot 4.2.2-stable; the text is the
//! same in 4.3–4.5):
//!
//! - The blur (`servers/rendering/renderer_rd/shaders/effects/
//!   subsurface_scattering.glsl`) uses the Jimenez demo's default kernels:
//!   `skin_kernel` is `SeparableSSS::calculateKernel` with strength
//!   (0.48, 0.41, 0.28) and falloff (1, 0.37, 0.3), and the plain `kernel`
//!   is its red channel for all three (checked tap by tap in
//!   `tests::godot_tables_are_the_demo_kernel`). As a radial profile that is
//!   [`Jimenez2012::widened`]: 1 − strength stays at the entry point.
//!   Low quality has 11 taps, Medium 17 (both reach 2 kernel units), High
//!   25 (3 units) (`effects/ss_effects.cpp` lines 348–350, 1654–1655).
//! - One kernel unit spans `step = scale·strength/3` in UV, with
//!   `scale = mix(subsurface_scattering_scale, unit_size/depth,
//!   subsurface_scattering_depth_scale)` (the shader's `main`) and
//!   `unit_size = P[0][0]` (`ss_effects.cpp`, `sub_surface_scattering`:
//!   the point (1, 0, −1) projected). The shader treats that NDC length as
//!   UV, so with depth scale 1 a kernel unit is 2·strength/3 scene units at
//!   any distance: world-space and independent of the camera. The project
//!   setting `rendering/environment/subsurface_scattering/
//!   subsurface_scattering_depth_scale` defaults to 0.01
//!   (`servers/rendering_server.cpp` line 3539), which makes the blur a
//!   fixed fraction of the screen. The export asks for depth scale
//!   [`GODOT_DEPTH_SCALE`] = 0.1 with `subsurface_scattering_scale` at its
//!   minimum [`GODOT_SCALE`] = 0.001 (range 0.001–1, line 3538): a kernel
//!   unit is then 2·0.1·strength/3 scene units plus a screen-space
//!   0.0009·strength/3 of the view width (0.3 % of the world term for a
//!   face 0.5 m from a 60° camera). Depth scale 1 would be exactly
//!   world-space, but then skin's widths (0.1–0.5 mm a unit) need
//!   strengths under Godot's 0.001 floor (next point).
//! - A neighbour whose strength is below 0.001 ends the blur (`do_filter`:
//!   `if (abs(color.a) < 0.001) break;`), so a width under
//!   [`GODOT_MIN_STRENGTH`] renders nothing: the export clamps to it.
//! - Transmittance (`scene_forward_lights_inc.glsl`, `light_compute`) adds
//!   exp(−(8.25·z/depth)²)·color.rgb·color.a·light·clamp(boost − N·L, 0, 1)/π
//!   with z the shadow-map thickness in scene units; skin mode replaces
//!   exp(…)·color.rgb by a fixed six-Gaussian curve. `color.a` has been
//!   multiplied by the SSS strength (`scene_forward_clustered.glsl`:
//!   `transmittance_color.a *= sss_strength`), so at a physical width
//!   Godot's transmitted light is `strength` times ours; a colour holds
//!   0–1, so nothing in the material can undo that, and the notes say so.
//!   With boost 0 the angular term is ours (`shaders/scene.wgsl`:
//!   light·max(−N·L, 0)·T(d)·tint/π).
//! - Neither the Mobile nor the Compatibility renderer runs the blur
//!   (Godot docs, "Renderers", StandardMaterial features).
//!
//! Property names and ranges: `scene/resources/material.cpp` lines
//! 2820–2831 (`subsurf_scatter_strength` 0–1, `_transmittance_depth`
//! 0.001–8, `_transmittance_boost` 0–1); `;` starts a comment in a text
//! resource (`core/variant/variant_parser.cpp` lines 1628–1639).

use super::Provenance;
use crate::model::fit::{fit_jimenez_width, Fit, WidenedJimenez};
use crate::model::jimenez::{Jimenez2012, DEFAULT_FALLOFF, DEFAULT_STRENGTH};
use crate::model::{quad, ModelError, RadialProfile, Rgb};
use crate::settings::rendering::TransmissionId;
use crate::settings::Preset;

/// The project settings the export asks for (module docs).
pub const GODOT_DEPTH_SCALE: f64 = 0.1;
pub const GODOT_SCALE: f64 = 0.001;
/// Below this per-pixel strength Godot's blur stops (see module docs).
pub const GODOT_MIN_STRENGTH: f64 = 0.001;
/// Scene units per metre Godot assumes (its convention: 1 unit = 1 m).
const GODOT_UNITS_PER_M: f64 = 1.0;
/// Godot's transmittance depth range (material.cpp line 2830).
const DEPTH_RANGE_M: (f64, f64) = (0.001, 8.0);

/// The skin-mode transmittance curve (`scene_forward_lights_inc.glsl`,
/// `light_compute`, SSS_MODE_SKIN), dd = −(8.25·z/depth)²: Godot's shader
/// hard-codes d'Eon's six Gaussians (variances and weights), the same
/// numbers as `DEON_SKIN`.
const SKIN_TRANSMITTANCE: [(f64, Rgb); 6] = crate::model::gaussian::DEON_SKIN;

/// What a Godot material can carry of a look.
#[derive(Debug, Clone)]
pub struct GodotSubsurface {
    /// `subsurf_scatter_skin_mode`: the per-channel kernel.
    pub skin_mode: bool,
    /// Physical length of one kernel unit, mm (after the strength clamp).
    pub width_mm: f64,
    /// `subsurf_scatter_strength`.
    pub strength: f64,
    /// Whether the fitted width fell below what Godot renders.
    pub clamped: bool,
    /// Relative L2 error of r·R(r) per channel, energy-normalised.
    pub error: Rgb,
    /// Fraction of the light Godot leaves at the entry point.
    pub unscattered: Rgb,
    pub transmittance: Option<GodotTransmittance>,
}

#[derive(Debug, Clone, Copy)]
pub struct GodotTransmittance {
    /// `subsurf_scatter_transmittance_depth`, scene units (m).
    pub depth_m: f64,
    /// rgb of `subsurf_scatter_transmittance_color` (ignored in skin mode).
    pub color: Rgb,
    /// Relative L2 error of the transmitted light over thickness.
    pub error: Rgb,
}

/// Kernel units → scene units: 2·strength·depth scale/3 (the screen term
/// left out).
fn strength_for_width(width_mm: f64) -> f64 {
    1.5 * width_mm * 1e-3 * GODOT_UNITS_PER_M / GODOT_DEPTH_SCALE
}

pub(super) fn width_for_strength(strength: f64) -> f64 {
    strength / (1.5 * 1e-3 * GODOT_UNITS_PER_M / GODOT_DEPTH_SCALE)
}

/// Best width for one kernel among those Godot renders, and whether the
/// unconstrained best lies outside them.
fn fit_mode(
    target: &dyn RadialProfile,
    kernel: &Jimenez2012,
) -> Result<(Fit<WidenedJimenez>, bool), ModelError> {
    let range = (
        width_for_strength(GODOT_MIN_STRENGTH),
        width_for_strength(1.0),
    );
    let fit = fit_jimenez_width(target, kernel, range)?;
    let w = fit.model.width_mm;
    let at_bound = w <= range.0 * (1.0 + 1e-6) || w >= range.1 * (1.0 - 1e-6);
    Ok((fit, at_bound))
}

/// Godot's transmitted light for one mode at thickness z (m), per channel,
/// before the colour.
fn godot_transmittance_shape(skin: bool, depth_m: f64, z_m: f64) -> Rgb {
    let d = 8.25 * z_m / depth_m;
    let dd = -d * d;
    if skin {
        let mut out = [0.0; 3];
        for (v, w) in SKIN_TRANSMITTANCE {
            let e = (dd / v).exp();
            for c in 0..3 {
                out[c] += w[c] * e;
            }
        }
        out
    } else {
        [dd.exp(); 3]
    }
}

/// Fits depth (and in plain mode the colour) to tint·T(d)/T(0) per channel.
fn fit_transmittance(
    preset: &Preset,
    target: &dyn RadialProfile,
    skin: bool,
) -> GodotTransmittance {
    let tint = preset.rendering.transmission_tint;
    let total = target.total_reflectance();
    // Thickness range: until every channel's T has fallen to 1e-3 of T(0).
    let mut t_max_mm = target.length_scale_mm().max(1e-3);
    for _ in 0..60 {
        let t = target.transmittance(t_max_mm);
        if (0..3).all(|c| t[c] <= 1e-3 * total[c]) {
            break;
        }
        t_max_mm *= 1.5;
    }
    const N: usize = 256;
    let zs: Vec<f64> = (0..N)
        .map(|i| t_max_mm * i as f64 / (N - 1) as f64)
        .collect();
    let ours: Vec<Rgb> = zs
        .iter()
        .map(|&z| {
            let t = target.transmittance(z);
            std::array::from_fn(|c| {
                if total[c] > 0.0 {
                    tint[c] * t[c] / total[c]
                } else {
                    0.0
                }
            })
        })
        .collect();
    let norm2: Rgb = std::array::from_fn(|c| ours.iter().map(|o| o[c] * o[c]).sum());
    // For a depth: the best colour per channel (plain mode) and the error.
    let eval = |depth_m: f64| -> (Rgb, Rgb) {
        let g: Vec<Rgb> = zs
            .iter()
            .map(|&z| godot_transmittance_shape(skin, depth_m, z * 1e-3 * GODOT_UNITS_PER_M))
            .collect();
        let color: Rgb = std::array::from_fn(|c| {
            if skin {
                return 1.0;
            }
            let gt: f64 = (0..N).map(|i| g[i][c] * ours[i][c]).sum();
            let gg: f64 = (0..N).map(|i| g[i][c] * g[i][c]).sum();
            if gg > 0.0 {
                (gt / gg).clamp(0.0, 1.0)
            } else {
                0.0
            }
        });
        let err: Rgb = std::array::from_fn(|c| {
            let num: f64 = (0..N)
                .map(|i| (color[c] * g[i][c] - ours[i][c]).powi(2))
                .sum();
            crate::model::relative_l2(num, norm2[c])
        });
        (color, err)
    };
    let obj = |ln_d: f64| eval(ln_d.exp()).1.iter().map(|e| e * e).sum::<f64>();
    let (lo, hi) = (DEPTH_RANGE_M.0.ln(), DEPTH_RANGE_M.1.ln());
    let steps = 90;
    let best = (0..=steps)
        .map(|i| lo + (hi - lo) * i as f64 / steps as f64)
        .min_by(|a, b| obj(*a).total_cmp(&obj(*b)))
        .unwrap_or(lo);
    let cell = (hi - lo) / steps as f64;
    let (ln_d, _) = quad::minimize_scalar(obj, (best - cell).max(lo), (best + cell).min(hi), 1e-10);
    let depth_m = ln_d.exp();
    let (color, error) = eval(depth_m);
    GodotTransmittance {
        depth_m,
        color,
        error,
    }
}

/// The Godot material of a look: both kernels fitted, the better kept.
pub fn godot_subsurface(preset: &Preset) -> Result<GodotSubsurface, ModelError> {
    let target = preset.profile.build()?;
    let plain = Jimenez2012::new([DEFAULT_STRENGTH[0]; 3], [DEFAULT_FALLOFF[0]; 3])?;
    let skin = Jimenez2012::new(DEFAULT_STRENGTH, DEFAULT_FALLOFF)?;
    let (fp, cp) = fit_mode(target.as_ref(), &plain)?;
    let (fs, cs) = fit_mode(target.as_ref(), &skin)?;
    let skin_mode = fs.max_error() < fp.max_error();
    let (fit, clamped, kernel) = if skin_mode {
        (fs, cs, &skin)
    } else {
        (fp, cp, &plain)
    };
    let transmittance = (preset.rendering.transmission != TransmissionId::Off)
        .then(|| fit_transmittance(preset, target.as_ref(), skin_mode));
    Ok(GodotSubsurface {
        skin_mode,
        width_mm: fit.model.width_mm,
        strength: strength_for_width(fit.model.width_mm),
        clamped,
        error: fit.relative_l2_error,
        unscattered: kernel.strength().map(|s| 1.0 - s),
        transmittance,
    })
}

/// What the Godot material will not hold, one sentence each (the export
/// dialog and the file's comments).
pub fn godot_notes(preset: &Preset) -> Result<Vec<String>, ModelError> {
    let g = godot_subsurface(preset)?;
    Ok(notes_of(&g))
}

fn notes_of(g: &GodotSubsurface) -> Vec<String> {
    let e = g.error.into_iter().fold(0.0, f64::max);
    let mut n = vec![
        format!(
            "Godot's SSS kernel is fixed (Jimenez's demo skin kernel{}); only its width is set: relative L2 error of r·R(r) {e:.4} (R {:.4}, G {:.4}, B {:.4}).",
            if g.skin_mode { ", skin mode" } else { ", red channel" },
            g.error[0],
            g.error[1],
            g.error[2]
        ),
        format!(
            "Godot leaves {:.0}% / {:.0}% / {:.0}% of the light unblurred at the entry point.",
            100.0 * g.unscattered[0],
            100.0 * g.unscattered[1],
            100.0 * g.unscattered[2]
        ),
        format!("In Project Settings > Rendering > Environment > Subsurface Scattering set Subsurface Scattering Scale to {GODOT_SCALE} and Depth Scale to {GODOT_DEPTH_SCALE} (the defaults 0.05 and 0.01 size the blur by the screen, not the object), and use the Forward+ renderer (Mobile and Compatibility have no SSS blur)."),
    ];
    if g.clamped {
        n.push(format!(
            "The best width is below what Godot renders (strength < {GODOT_MIN_STRENGTH}): written at strength {:.4}, one kernel unit = {:.3} mm.",
            g.strength, g.width_mm
        ));
    }
    if let Some(t) = &g.transmittance {
        let e = t.error.into_iter().fold(0.0, f64::max);
        n.push(format!(
            "Transmittance: Godot's Gaussian-of-thickness curve, relative L2 error {e:.4}. Godot multiplies transmitted light by the SSS strength, so it is {:.4}× as bright as in scatterlab; no material field can undo that.",
            g.strength
        ));
    }
    n.push("Godot assumes 1 scene unit = 1 m; scale the strength with your scene unit.".into());
    n
}

/// A `.tres` float: Godot's parser reads plain decimal and exponent forms.
fn f(v: f64) -> String {
    format!("{v:.9}")
        .trim_end_matches('0')
        .trim_end_matches('.')
        .to_owned()
}

/// A line safe inside a `;` comment.
fn comment(s: &str) -> String {
    s.replace(['\n', '\r'], " ")
}

pub fn godot_material(preset: &Preset, prov: &Provenance) -> Result<String, ModelError> {
    let g = godot_subsurface(preset)?;
    let (burley, _) = super::burley_of(&preset.profile)?;
    let a = burley.albedo();
    let r = &preset.rendering;
    let color =
        |v: Rgb, alpha: f64| format!("Color({}, {}, {}, {})", f(v[0]), f(v[1]), f(v[2]), f(alpha));
    let mut out = String::new();
    out.push_str("[gd_resource type=\"StandardMaterial3D\" format=3]\n\n");
    out.push_str(&format!(
        "; Godot 4 StandardMaterial3D for \"{}\": {}.\n",
        comment(&preset.name),
        comment(&prov.line())
    ));
    out.push_str("; Checked against Godot 4.2-4.5 source (material.cpp, subsurface_scattering.glsl, scene_forward_lights_inc.glsl).\n");
    for note in notes_of(&g) {
        out.push_str(&format!("; {}\n", comment(&note)));
    }
    out.push_str(&format!(
        "; Width: one kernel unit = {} mm; strength = 1.5 x width (m) / depth scale, as Godot's blur spans 2 x strength x depth scale / 3 scene units per kernel unit.\n",
        f(g.width_mm)
    ));
    out.push_str(
        "; Albedo: albedo_color is the look's Burley albedo A (linear in scatterlab; Godot reads this Color as sRGB-encoded, so it is converted).\n\n",
    );
    out.push_str("[resource]\n");
    out.push_str(&format!(
        "resource_name = \"{}\"\n",
        preset.name.replace(['"', '\\'], "_")
    ));
    out.push_str(&format!(
        "albedo_color = {}\n",
        color(a.map(linear_to_srgb), 1.0)
    ));
    out.push_str(&format!("roughness = {}\n", f(r.specular.roughness)));
    out.push_str("subsurf_scatter_enabled = true\n");
    out.push_str(&format!("subsurf_scatter_strength = {}\n", f(g.strength)));
    out.push_str(&format!("subsurf_scatter_skin_mode = {}\n", g.skin_mode));
    if let Some(t) = &g.transmittance {
        out.push_str("subsurf_scatter_transmittance_enabled = true\n");
        out.push_str(&format!(
            "subsurf_scatter_transmittance_color = {}\n",
            color(t.color.map(linear_to_srgb), 1.0)
        ));
        out.push_str(&format!(
            "subsurf_scatter_transmittance_depth = {}\n",
            f(t.depth_m)
        ));
        out.push_str("subsurf_scatter_transmittance_boost = 0.0\n");
    }
    Ok(out)
}

/// sRGB transfer function (IEC 61966-2-1), for Godot's `source_color`
/// colours, which the editor stores encoded and the renderer linearises.
fn linear_to_srgb(v: f64) -> f64 {
    crate::model::colour::linear_to_srgb_f64(v.clamp(0.0, 1.0))
}

mod read;
pub use read::read;

/// Godot 4's StandardMaterial3D as an export target.
pub(super) const TARGET: super::Target = super::Target {
    id: "godot",
    name: "Godot 4 material",
    description: "a StandardMaterial3D .tres; its fixed kernel's error is stated",
    extension: "tres",
    companion: None,
    slow: false,
    write: |preset, prov, out, _, _| super::write(out, godot_material(preset, prov)?.as_bytes()),
    notes: godot_notes,
    fidelity: |preset| {
        godot_subsurface(preset)
            .ok()
            .map(|g| g.error.into_iter().fold(0.0, f64::max))
    },
    params: None,
    reader: Some(super::Reader {
        extensions: &["tres"],
        claims: |ext, text| ext == "tres" || text.trim_start().starts_with("[gd_resource"),
        read: |text, path, _| read(text, path),
    }),
};

#[cfg(test)]
mod tests {
    use super::*;

    /// Godot's kernel tables (`subsurface_scattering.glsl`, Godot 4.x:
    /// `skin_kernel` as (r, g, b, offset), centre first, positive offsets
    /// only) are the Jimenez demo's default kernel; the plain `kernel` is its
    /// red channel. Numbers copied from Godot's shader.
    #[test]
    fn godot_tables_are_the_demo_kernel() {
        // Godot's tables are the demo's non-negative offsets (compared
        // by hand with the shader; `PUBLISHED_*` holds them once).
        use crate::model::jimenez::{PUBLISHED_11, PUBLISHED_25};
        let half = |t: &[[f64; 4]]| -> Vec<[f64; 4]> {
            t.iter().copied().filter(|r| r[3] >= 0.0).collect()
        };
        let (godot_25, godot_11) = (half(&PUBLISHED_25), half(&PUBLISHED_11));
        assert_eq!((godot_25.len(), godot_11.len()), (13, 6));
        let demo = Jimenez2012::new(DEFAULT_STRENGTH, DEFAULT_FALLOFF).unwrap();
        for (taps, table) in [(25, &godot_25[..]), (11, &godot_11[..])] {
            let k = demo.kernel(taps).unwrap();
            for row in table {
                let tap = k
                    .taps
                    .iter()
                    .find(|t| (t.offset_mm - row[3]).abs() < 1e-5)
                    .unwrap_or_else(|| panic!("no tap at {}", row[3]));
                for c in 0..3 {
                    let rel = (tap.weight[c] - row[c]).abs() / row[c];
                    assert!(
                        rel < 2e-5,
                        "{taps} taps, offset {}, channel {c}: {} vs {}",
                        row[3],
                        tap.weight[c],
                        row[c]
                    );
                }
            }
        }
    }

    /// A look that is Godot's own skin kernel at width 1 mm goes across
    /// exactly: skin mode, strength 0.015 (hand: 1.5 × 1 mm × 1e-3 m/mm
    /// / depth scale 0.1).
    #[test]
    fn godots_own_kernel_round_trips() {
        let mut p = Preset::default_skin();
        p.profile =
            crate::settings::ProfileSpec::Jimenez2012(crate::settings::profile::Jimenez2012Spec {
                strength: DEFAULT_STRENGTH,
                falloff: DEFAULT_FALLOFF,
            });
        let g = godot_subsurface(&p).unwrap();
        assert!(g.skin_mode);
        assert!((g.strength - 0.015).abs() < 1e-8, "{}", g.strength);
        assert!(g.error.iter().all(|e| *e < 1e-5), "{:?}", g.error);
        assert!(!g.clamped);
    }

    /// The default skin (Burley) cannot be held: the error is stated, and it
    /// is large because Godot keeps 52 % of red at the entry point.
    #[test]
    fn burley_skin_reports_its_error() {
        let g = godot_subsurface(&Preset::default_skin()).unwrap();
        eprintln!("{g:?}");
        assert!(
            g.error.iter().all(|e| e.is_finite() && *e > 0.05),
            "{:?}",
            g.error
        );
        assert!(g.strength >= GODOT_MIN_STRENGTH && g.strength <= 1.0);
    }

    /// sRGB encoding: 0.5 linear is 0.735357 (IEC 61966-2-1 worked value).
    #[test]
    fn srgb_encoding() {
        assert!((linear_to_srgb(0.5) - 0.735_356_6).abs() < 1e-6);
        assert_eq!(linear_to_srgb(0.0), 0.0);
    }
}
