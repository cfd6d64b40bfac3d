//! The parameter panel: model choice and every model's parameters, the
//! rendering settings, each field with its unit and a tooltip that says
//! what it does physically.

use super::colour_ui::{colour_entry_id, colour_entry_ui, colour_picker_ui};
use crate::model::multipole::{DIPOLES_RANGE, THICKNESS_RANGE_MM};
use crate::model::{burley, dipole, gaussian, jimenez, measured, separable, Rgb, CHANNEL_NAMES};
use crate::settings::profile::*;
use crate::settings::rendering::{limits, DualLobeSpec, MethodId, TexturingId, TransmissionId};
use crate::settings::{ProfileSpec, RenderingSpec};
use egui::{DragValue, Ui};

/// A number with its unit; returns whether it changed.
fn scalar_ui(
    ui: &mut Ui,
    label: &str,
    unit: &str,
    tip: &str,
    v: &mut f64,
    range: std::ops::RangeInclusive<f64>,
    speed: f64,
) -> bool {
    ui.horizontal(|ui| {
        ui.label(label).on_hover_text(tip);
        ui.add(
            DragValue::new(v)
                .range(range)
                .speed(speed)
                .max_decimals(5)
                .suffix(unit),
        )
        .on_hover_text(tip)
        .changed()
    })
    .inner
}

/// The size of a drag value showing `text` (the button's padding around
/// the body font's width of it).
fn field_size(ui: &Ui, text: &str) -> egui::Vec2 {
    let font = egui::TextStyle::Button.resolve(ui.style());
    let width = ui.fonts_mut(|f| {
        f.layout_no_wrap(text.to_owned(), font, egui::Color32::WHITE)
            .size()
            .x
    });
    let pad = ui.spacing().button_padding;
    egui::vec2(width + 2.0 * pad.x, ui.spacing().interact_size.y)
}

/// Three numbers (R, G, B) with a unit and a swatch when they are a colour.
#[allow(clippy::too_many_arguments)]
fn rgb_ui(
    ui: &mut Ui,
    label: &str,
    unit: &str,
    tip: &str,
    v: &mut Rgb,
    range: std::ops::RangeInclusive<f64>,
    speed: f64,
    swatch: bool,
) -> bool {
    // Wraps in a narrow panel rather than widening it. Each field is as
    // wide as its widest value (5 decimals, the range's whole digits), so
    // that typing a value does not reflow the row and move the swatch (and
    // its open picker) to another line.
    // At most three whole digits: a field whose range runs to 1e6 mm (a
    // mean free path) holds values near 1 and would wrap its row.
    let whole = ((range.end().abs().clamp(1.0, 999.0).log10().floor() as usize) + 1).min(3);
    let widest = format!("R: {}.88888{unit}", "8".repeat(whole));
    let field = field_size(ui, &widest);
    let changed = ui
        .horizontal_wrapped(|ui| {
            ui.label(label).on_hover_text(tip);
            let mut changed = false;
            for (c, x) in v.iter_mut().enumerate() {
                changed |= ui
                    .add_sized(
                        field,
                        DragValue::new(x)
                            .range(range.clone())
                            .speed(speed)
                            .max_decimals(5)
                            .prefix(format!("{}: ", CHANNEL_NAMES[c].to_uppercase()))
                            .suffix(unit),
                    )
                    .on_hover_text(tip)
                    .changed();
            }
            if swatch {
                changed |= colour_picker_ui(ui, label, v, &range);
                let id = colour_entry_id(label);
                let open = ui.data(|d| d.get_temp::<bool>(id).unwrap_or(false));
                if ui
                    .selectable_label(open, "#")
                    .on_hover_text(format!(
                        "{label}: type the colour as hex, sRGB 0–255 or HSV, or pick a recent one"
                    ))
                    .clicked()
                {
                    ui.data_mut(|d| d.insert_temp(id, !open));
                }
            }
            changed
        })
        .inner;
    if swatch {
        changed | colour_entry_ui(ui, label, v, &range)
    } else {
        changed
    }
}

fn count_ui(
    ui: &mut Ui,
    label: &str,
    tip: &str,
    v: &mut usize,
    range: (usize, usize),
    step: usize,
) {
    ui.horizontal(|ui| {
        ui.label(label).on_hover_text(tip);
        let mut x = *v as u32;
        if ui
            .add(
                DragValue::new(&mut x)
                    .range(range.0 as u32..=range.1 as u32)
                    .speed(0.2),
            )
            .on_hover_text(tip)
            .changed()
        {
            // Keep odd counts odd (kernels need a centre tap).
            let mut n = x as usize;
            if step == 2 && n.is_multiple_of(2) {
                n = if n > *v {
                    n + 1
                } else {
                    n.saturating_sub(1).max(range.0)
                };
            }
            *v = n;
        }
    });
}

/// A field's range from the model's own validation limits (one source of
/// truth: the field cannot take a value `validate` refuses).
fn span((lo, hi): (f64, f64)) -> std::ops::RangeInclusive<f64> {
    lo..=hi
}

/// The model picker; switching model starts from that model's defaults.
pub fn model_picker_ui(ui: &mut Ui, spec: &mut ProfileSpec) {
    let models = ProfileSpec::models().map(|m| {
        let (name, tip) = m.describe();
        (name, m, tip)
    });
    let current = models
        .iter()
        .find(|(_, m, _)| m.model_name() == spec.model_name())
        .map(|(n, _, _)| *n)
        .unwrap_or("?");
    egui::ComboBox::from_label("Model")
        .selected_text(current)
        .show_ui(ui, |ui| {
            for (name, default, tip) in models {
                let selected = default.model_name() == spec.model_name();
                if ui.selectable_label(selected, name).on_hover_text(tip).clicked() && !selected {
                    *spec = default;
                }
            }
        })
        .response
        .on_hover_text("The diffusion profile model. Switching starts from the model's defaults (undo restores).");
}

/// The parameters of the current model.
pub fn model_params_ui(ui: &mut Ui, spec: &mut ProfileSpec) {
    match spec {
        ProfileSpec::Burley(b) => burley_ui(ui, b),
        ProfileSpec::Jimenez2012(Jimenez2012Spec { strength, falloff }) => {
            rgb_ui(ui, "Strength", "", "Per channel, the fraction of light that scatters (Jimenez 2012 'SSS strength'); the rest stays where it entered.", strength, span(jimenez::STRENGTH_RANGE), 0.005, false);
            rgb_ui(ui, "Falloff", "", "Per channel, how far the scattered light spreads relative to red (Jimenez 2012 'falloff').", falloff, span(jimenez::FALLOFF_RANGE), 0.005, false);
        }
        ProfileSpec::Artist(a) => artist_ui(ui, a),
        ProfileSpec::Gaussians(g) => gaussians_ui(ui, g),
        ProfileSpec::Dipole(d) => dipole_ui(ui, d),
        ProfileSpec::Measured(m) => measured_ui(ui, m),
        ProfileSpec::Multipole(m) => multipole_ui(ui, m),
    }
}

/// The artist model's two Gaussians: widths, weight and scale.
fn artist_ui(
    ui: &mut Ui,
    ArtistSpec {
        sigma_near,
        sigma_far,
        weight,
        scale_mm,
    }: &mut ArtistSpec,
) {
    rgb_ui(
        ui,
        "σn (near)",
        "",
        "Width of the near Gaussian per channel, relative to the scale s: short-range softening.",
        sigma_near,
        span(separable::ARTIST_SIGMA_RANGE),
        0.002,
        false,
    );
    rgb_ui(
        ui,
        "σf (far)",
        "",
        "Width of the far Gaussian per channel, relative to s: the long red tail.",
        sigma_far,
        span(separable::ARTIST_SIGMA_RANGE),
        0.005,
        false,
    );
    scalar_ui(
        ui,
        "w (near weight)",
        "",
        "Share of the energy in the near Gaussian; 1 − w goes to the far one.",
        weight,
        span(separable::ARTIST_WEIGHT_RANGE),
        0.005,
    );
    scalar_ui(
        ui,
        "s (scale)",
        " mm",
        "Global width of both Gaussians in millimetres: how far light travels.",
        scale_mm,
        span(separable::ARTIST_SCALE_RANGE_MM),
        0.05,
    );
}

/// The dipole's σa, σs' and η, with a measured material to fill them from.
fn dipole_ui(
    ui: &mut Ui,
    DipoleSpec {
        sigma_a_per_mm,
        sigma_s_prime_per_mm,
        eta,
    }: &mut DipoleSpec,
) {
    ui.horizontal(|ui| {
        egui::ComboBox::from_label("Fill from measured")
            .selected_text("…")
            .show_ui(ui, |ui| {
                for m in measured::all() {
                    if ui.button(&m.name).clicked() {
                        *sigma_a_per_mm = m.sigma_a_per_mm;
                        *sigma_s_prime_per_mm = m.sigma_s_prime_per_mm;
                    }
                }
            })
            .response
            .on_hover_text(
                "Copy σa and σs' of a measured material (Jensen 2001, Narasimhan 2006).",
            );
    });
    rgb_ui(ui, "σa", " /mm", "Absorption coefficient per channel: larger absorbs sooner, shortening and tinting the scatter.", sigma_a_per_mm, span(dipole::SIGMA_A_RANGE), 0.001, false);
    rgb_ui(ui, "σs'", " /mm", "Reduced scattering coefficient per channel: larger scatters sooner, shortening the profile and raising its albedo.", sigma_s_prime_per_mm, span(dipole::SIGMA_S_PRIME_RANGE), 0.005, false);
    scalar_ui(ui, "η", "", "Relative index of refraction of the surface: more internal reflection keeps light in longer.", eta, span(dipole::ETA_RANGE), 0.005);
}

/// A measured material through the dipole, and its η.
fn measured_ui(ui: &mut Ui, MeasuredSpec { name, eta }: &mut MeasuredSpec) {
    egui::ComboBox::from_label("Material")
        .selected_text(name.clone())
        .show_ui(ui, |ui| {
            for mat in measured::all() {
                let tip = format!(
                    "σs' = {:?} /mm, σa = {:?} /mm",
                    mat.sigma_s_prime_per_mm, mat.sigma_a_per_mm
                );
                ui.selectable_value(name, mat.name.clone(), &mat.name)
                    .on_hover_text(tip);
            }
        })
        .response
        .on_hover_text(
            "Measured σs' and σa (Jensen et al. 2001; Narasimhan et al. 2006), through the dipole.",
        );
    scalar_ui(
        ui,
        "η",
        "",
        "Relative index of refraction of the surface.",
        eta,
        span(dipole::ETA_RANGE),
        0.005,
    );
    if let Ok(mat) = measured::find(name) {
        ui.label(format!(
            "σs' = {:.3?} /mm\nσa = {:.4?} /mm",
            mat.sigma_s_prime_per_mm, mat.sigma_a_per_mm
        ));
    }
}

fn burley_ui(ui: &mut Ui, b: &mut BurleySpec) {
    let BurleySpec { albedo, shape } = b;
    rgb_ui(ui, "Albedo", "", "Total diffuse reflectance A per channel (Burley's volume albedo): how much light comes back out; it also sets the profile's shape through s(A).", albedo, span(burley::ALBEDO_RANGE), 0.003, true);
    let mut is_sd = matches!(shape, BurleyShape::ScatteringDistance { .. });
    ui.horizontal_wrapped(|ui| {
        ui.label("Shape from");
        let sd = ui
            .radio_value(&mut is_sd, true, "scattering distance")
            .on_hover_text("Unity's parameter: d per channel, the profile's length scale.");
        let mfp = ui
            .radio_value(&mut is_sd, false, "mean free path")
            .on_hover_text("A mean free path through one of Christensen & Burley's scaling fits.");
        if sd.changed() || mfp.changed() {
            let built = BurleySpec {
                albedo: *albedo,
                shape: shape.clone(),
            }
            .build()
            .ok();
            *shape = match (is_sd, built) {
                (true, Some(p)) => BurleyShape::ScatteringDistance {
                    mm: p.scattering_distance_mm(),
                    multiplier: 1.0,
                },
                (true, None) => BurleySpec::default().shape,
                (false, _) => BurleyShape::MeanFreePath {
                    mm: [1.0, 0.5, 0.25],
                    fit: ScalingFit::DiffuseMeanFreePath,
                },
            };
        }
    });
    match shape {
        BurleyShape::ScatteringDistance { mm, multiplier } => {
            rgb_ui(ui, "Scattering distance", " mm", "d per channel: how far light travels under the skin before it comes back out (Unity's 'Scattering Distance').", mm, span(burley::DISTANCE_RANGE_MM), 0.005, true);
            scalar_ui(
                ui,
                "Multiplier",
                "×",
                "Scales all three distances together (Unity's 'Multiplier').",
                multiplier,
                span(MULTIPLIER_RANGE),
                0.005,
            );
        }
        BurleyShape::MeanFreePath { mm, fit } => {
            rgb_ui(
                ui,
                "Mean free path",
                " mm",
                "Per channel, the (diffuse) mean free path ℓ; d = ℓ / s(A).",
                mm,
                span(burley::MEAN_FREE_PATH_RANGE_MM),
                0.005,
                true,
            );
            egui::ComboBox::from_label("Scaling fit")
                .selected_text(format!("{fit:?}"))
                .show_ui(ui, |ui| {
                    ui.selectable_value(fit, ScalingFit::Perpendicular, "Perpendicular (eq. 5)");
                    ui.selectable_value(fit, ScalingFit::DiffuseSurface, "Diffuse surface (eq. 6)");
                    ui.selectable_value(
                        fit,
                        ScalingFit::DiffuseMeanFreePath,
                        "Diffuse mean free path (eq. 8)",
                    );
                })
                .response
                .on_hover_text(
                    "Christensen & Burley 2015's fit s(A) for the light's entry geometry.",
                );
        }
    }
}

fn gaussians_ui(ui: &mut Ui, g: &mut GaussiansSpec) {
    let GaussiansSpec { gaussians, dirac } = g;
    let mut remove = None;
    egui::Grid::new("gaussians").striped(true).show(ui, |ui| {
        ui.label("#");
        ui.label("variance")
            .on_hover_text("v of exp(−r²/2v)/(2πv), mm²: the Gaussian's width squared.");
        ui.label("weight R");
        ui.label("G");
        ui.label("B");
        ui.label("");
        ui.end_row();
        for (i, t) in gaussians.iter_mut().enumerate() {
            ui.label(format!("{}", i + 1));
            ui.add(
                DragValue::new(&mut t.variance_mm2)
                    .range(span(gaussian::VARIANCE_RANGE_MM2))
                    .speed(0.002)
                    .max_decimals(5)
                    .suffix(" mm²"),
            )
            .on_hover_text("Variance of this Gaussian (mm²).");
            for c in 0..3 {
                ui.add(
                    DragValue::new(&mut t.weights[c])
                        .range(span(gaussian::WEIGHT_RANGE))
                        .speed(0.002)
                        .max_decimals(4),
                )
                .on_hover_text("Share of the channel's reflectance in this Gaussian.");
            }
            if ui
                .small_button("x")
                .on_hover_text("Remove this Gaussian")
                .clicked()
            {
                remove = Some(i);
            }
            ui.end_row();
        }
    });
    if let Some(i) = remove {
        if gaussians.len() > 1 {
            gaussians.remove(i);
        }
    }
    if ui
        .button("+ Add Gaussian")
        .on_hover_text("Append a Gaussian (variance 1 mm², weight 0)")
        .clicked()
    {
        gaussians.push(GaussianTerm {
            variance_mm2: 1.0,
            weights: [0.0; 3],
        });
    }
    // The unblurred share (a Godot import's), shown, not edited: it comes
    // from the engine's file and `convert` keeps it.
    if dirac.iter().any(|d| *d > 0.0) {
        ui.label(format!(
            "Unblurred share (Dirac): R {:.3}, G {:.3}, B {:.3}",
            dirac[0], dirac[1], dirac[2]
        ))
        .on_hover_text("Light that leaves where it entered (from the imported file's kernel); the Gaussians hold the rest.");
    }
}

fn multipole_ui(ui: &mut Ui, m: &mut MultipoleSpec) {
    let MultipoleSpec {
        layers,
        eta_above,
        eta_below,
        dipoles,
    } = m;
    scalar_ui(
        ui,
        "η above",
        "",
        "Index of the medium light arrives from (air = 1).",
        eta_above,
        span(dipole::ETA_RANGE),
        0.005,
    );
    scalar_ui(
        ui,
        "η below",
        "",
        "Index of the medium under a finite last layer.",
        eta_below,
        span(dipole::ETA_RANGE),
        0.005,
    );
    let mut d = *dipoles as usize;
    count_ui(
        ui,
        "Dipole pairs",
        "Mirrored dipole pairs n per slab (2n + 1 dipoles): more is more accurate and slower.",
        &mut d,
        (DIPOLES_RANGE.0 as usize, DIPOLES_RANGE.1 as usize),
        1,
    );
    *dipoles = d as u32;
    let n = layers.len();
    let mut remove = None;
    for (i, l) in layers.iter_mut().enumerate() {
        egui::CollapsingHeader::new(format!(
            "Layer {} {}",
            i + 1,
            if i == 0 { "(top)" } else { "" }
        ))
        .default_open(true)
        .show(ui, |ui| {
            layer_ui(ui, l, i + 1 == n);
            if n > 1 && ui.small_button("Remove layer").clicked() {
                remove = Some(i);
            }
        });
    }
    if let Some(i) = remove {
        layers.remove(i);
    }
    if ui
        .button("+ Add layer on top")
        .on_hover_text("A 0.1 mm layer above the stack (an oil or epidermis film)")
        .clicked()
    {
        layers.insert(
            0,
            LayerSpec {
                thickness_mm: Some(0.1),
                ..Default::default()
            },
        );
    }
    // Only the last layer may be semi-infinite.
    let len = layers.len();
    for l in layers.iter_mut().take(len.saturating_sub(1)) {
        l.thickness_mm.get_or_insert(1.0);
    }
}

/// One layer's rows: σa, σs', η and its thickness (the last layer may be
/// semi-infinite, a base).
fn layer_ui(ui: &mut Ui, l: &mut LayerSpec, last: bool) {
    rgb_ui(
        ui,
        "σa",
        " /mm",
        "Absorption coefficient of this layer.",
        &mut l.sigma_a_per_mm,
        span(dipole::SIGMA_A_RANGE),
        0.001,
        false,
    );
    rgb_ui(
        ui,
        "σs'",
        " /mm",
        "Reduced scattering coefficient of this layer.",
        &mut l.sigma_s_prime_per_mm,
        span(dipole::SIGMA_S_PRIME_RANGE),
        0.005,
        false,
    );
    scalar_ui(
        ui,
        "η",
        "",
        "Index of refraction of this layer.",
        &mut l.eta,
        span(dipole::ETA_RANGE),
        0.005,
    );
    let mut infinite = l.thickness_mm.is_none();
    if last {
        ui.checkbox(&mut infinite, "semi-infinite")
            .on_hover_text("The last layer may extend without bound (a base).");
    } else {
        infinite = false;
    }
    if infinite {
        l.thickness_mm = None;
    } else {
        let mut t = l.thickness_mm.unwrap_or(1.0);
        scalar_ui(
            ui,
            "Thickness",
            " mm",
            "Depth of this layer.",
            &mut t,
            span(THICKNESS_RANGE_MM),
            0.01,
        );
        l.thickness_mm = Some(t);
    }
}

/// Rendering and engine-side material settings. Unpacked field by field,
/// as `RenderSettings::for_look` does: a new field does not compile until
/// it has a row here.
pub fn rendering_ui(ui: &mut Ui, r: &mut RenderingSpec) {
    let RenderingSpec {
        method,
        samples,
        taps,
        lod,
        texturing,
        transmission,
        thickness_remap_mm,
        transmission_tint,
        ior,
        world_scale_m_per_unit,
        specular,
        albedo_in_material,
    } = r;
    if *albedo_in_material {
        ui.label("Albedo: the material's")
            .on_hover_text("This look's engine keeps the albedo in the material (HDRP), so its file has none: the Albedo above is the material albedo it is drawn with, chosen when it was opened.");
    }
    method_ui(ui, method, (samples, taps), lod);
    texturing_ui(ui, texturing);
    transmission_ui(ui, transmission, thickness_remap_mm, transmission_tint);
    specular_ui(ui, ior, world_scale_m_per_unit, specular);
}

/// The SSS method, its sample and tap counts and the LOD.
fn method_ui(
    ui: &mut Ui,
    method: &mut MethodId,
    (samples, taps): (&mut usize, &mut usize),
    lod: &mut bool,
) {
    egui::ComboBox::from_label("Method")
        .selected_text(method.label())
        .show_ui(ui, |ui| {
            for &m in MethodId::all() {
                ui.selectable_value(method, m, m.label());
            }
        })
        .response
        .on_hover_text("The real-time SSS method the viewport renders with.");
    count_ui(
        ui,
        "Burley samples",
        "Disk samples per pixel of the burley method (Golubev 2018): more is smoother and slower.",
        samples,
        crate::settings::rendering::SAMPLES_RANGE,
        1,
    );
    count_ui(
        ui,
        "Separable taps",
        "Taps of each 1D pass of the separable method (odd).",
        taps,
        crate::settings::rendering::TAPS_RANGE,
        2,
    );
    ui.checkbox(lod, "Level of detail").on_hover_text(
        "Skip scattering where the disk is under a pixel, and use fewer samples under four pixels.",
    );
}

/// When the albedo texture is applied relative to the scattering.
fn texturing_ui(ui: &mut Ui, texturing: &mut TexturingId) {
    egui::ComboBox::from_label("Texturing")
        .selected_text(match texturing {
            TexturingId::PreAndPostScatter => "pre- and post-scatter",
            TexturingId::PostScatter => "post-scatter",
        })
        .show_ui(ui, |ui| {
            ui.selectable_value(
                texturing,
                TexturingId::PreAndPostScatter,
                "pre- and post-scatter",
            )
            .on_hover_text("√albedo before and after the blur: softer texture detail.");
            ui.selectable_value(texturing, TexturingId::PostScatter, "post-scatter")
                .on_hover_text("Albedo after the blur only: keeps scanned texture sharp.");
        })
        .response
        .on_hover_text("When the albedo texture is applied relative to the scattering.");
}

/// Transmission: the mode, a thickness map's remap and the tint.
fn transmission_ui(
    ui: &mut Ui,
    transmission: &mut TransmissionId,
    (lo, hi): &mut (f64, f64),
    tint: &mut Rgb,
) {
    egui::ComboBox::from_label("Transmission")
        .selected_text(match transmission {
            TransmissionId::Off => "off",
            TransmissionId::ThinObject => "thin object",
            TransmissionId::ThickObject => "thick object",
        })
        .show_ui(ui, |ui| {
            ui.selectable_value(transmission, TransmissionId::Off, "off");
            ui.selectable_value(transmission, TransmissionId::ThinObject, "thin object")
                .on_hover_text("Baked thickness, shadowed like the front face (ears, nostrils).");
            ui.selectable_value(transmission, TransmissionId::ThickObject, "thick object")
                .on_hover_text("Thickness from the shadow map, unshadowed.");
        })
        .response
        .on_hover_text("Light passing through thin parts from behind.");
    ui.horizontal_wrapped(|ui| {
        let tip = "Thickness that black and white texels of a thickness map stand for (mm).";
        ui.label("Thickness remap").on_hover_text(tip);
        let range = span(limits::THICKNESS_REMAP_MM);
        let mm = |v| {
            DragValue::new(v)
                .range(range.clone())
                .speed(0.05)
                .suffix(" mm")
        };
        ui.add(mm(lo)).on_hover_text(tip);
        ui.label("to");
        ui.add(mm(hi)).on_hover_text(tip);
        if *hi < *lo {
            *hi = *lo;
        }
    });
    rgb_ui(
        ui,
        "Transmission tint",
        "",
        "Multiplies light transmitted through thin parts.",
        tint,
        span(limits::TRANSMISSION_TINT),
        0.005,
        true,
    );
}

/// The surface's specular: IOR, the export world scale and Unreal's dual
/// GGX lobes.
fn specular_ui(ui: &mut Ui, ior: &mut f64, world_scale: &mut f64, s: &mut DualLobeSpec) {
    scalar_ui(
        ui,
        "IOR",
        "",
        "Index of refraction of the surface: sets the specular reflectance F0 = ((n−1)/(n+1))².",
        ior,
        span(limits::IOR),
        0.005,
    );
    scalar_ui(
        ui,
        "World scale",
        " m/unit",
        "Metres per scene unit of the meshes this look is used on (Unity's worldScale).",
        world_scale,
        span(limits::WORLD_SCALE_M_PER_UNIT),
        0.001,
    );
    ui.label("Dual-lobe specular").on_hover_text("Unreal's two GGX lobes mixed by lobe mix; Unity's smoothness multipliers are derived on export.");
    let DualLobeSpec {
        roughness,
        lobe0_roughness_multiplier,
        lobe1_roughness_multiplier,
        lobe_mix,
    } = s;
    let rows = [
        (
            "  Roughness",
            "Perceptual roughness the lobe multipliers apply to.",
            roughness,
            limits::UNIT,
        ),
        (
            "  Lobe 0 ×",
            "Roughness multiplier of the sharper lobe (Unreal Roughness0).",
            lobe0_roughness_multiplier,
            limits::LOBE_MULTIPLIER,
        ),
        (
            "  Lobe 1 ×",
            "Roughness multiplier of the broader lobe (Unreal Roughness1).",
            lobe1_roughness_multiplier,
            limits::LOBE_MULTIPLIER,
        ),
        (
            "  Lobe mix",
            "Weight of lobe 1 (Unreal LobeMix).",
            lobe_mix,
            limits::UNIT,
        ),
    ];
    for (label, tip, v, range) in rows {
        scalar_ui(ui, label, "", tip, v, span(range), 0.005);
    }
}
