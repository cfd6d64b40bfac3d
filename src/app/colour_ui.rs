//! A colour field's picker and its entry row: hex, sRGB bytes, HSV of the
//! displayed sRGB (as paint programs give it) and the session's recent
//! colours. Fields past 1 keep their multiplier (HDRP's inspector).

use crate::model::colour::{hex_of, hsv_of, parse_hex, rgb_of_hsv};
use crate::model::{Rgb, CHANNEL_NAMES};
use egui::{DragValue, Ui};

/// A colour field's colour (linear, 0–1) and multiplier: the field itself
/// where its range ends at 1, else v / max(v) and max(v) (see
/// [`colour_picker_ui`]).
pub(super) fn colour_parts(v: &Rgb, range: &std::ops::RangeInclusive<f64>) -> ([f64; 3], f64) {
    let m = v.iter().cloned().fold(0.0, f64::max);
    let multiplier = if *range.end() > 1.0 && m > 0.0 {
        m
    } else {
        1.0
    };
    (v.map(|x| (x / multiplier).clamp(0.0, 1.0)), multiplier)
}

/// Whether a colour field's entry row is open (its "#" toggle).
pub(super) fn colour_entry_id(label: &str) -> egui::Id {
    egui::Id::unique(("colour_entry_open", label))
}

/// The colour entry under a colour field, behind its "#" toggle: hex,
/// sRGB 0–255, HSV (on the displayed sRGB, as paint programs give it) and
/// the session's recent colours. A field past 1 keeps its multiplier.
/// Returns whether it changed `v`.
pub(super) fn colour_entry_ui(
    ui: &mut Ui,
    label: &str,
    v: &mut Rgb,
    range: &std::ops::RangeInclusive<f64>,
) -> bool {
    let recent_id = egui::Id::unique("colour_entry_recent");
    if !ui.data(|d| d.get_temp::<bool>(colour_entry_id(label)).unwrap_or(false)) {
        return false;
    }
    let (colour, multiplier) = colour_parts(v, range);
    let mut picked: Option<[f64; 3]> = None;
    ui.horizontal_wrapped(|ui| {
        ui.add_space(12.0);
        picked = hex_entry_ui(ui, label, colour)
            .or(bytes_entry_ui(ui, colour))
            .or(hsv_entry_ui(ui, colour))
            .or(recent_colours_ui(ui, recent_id));
    });
    let Some(p) = picked else {
        return false;
    };
    let (lo, hi) = (*range.start(), *range.end());
    let new: Rgb = std::array::from_fn(|c| (p[c] * multiplier).clamp(lo, hi));
    if new == *v {
        return false;
    }
    // The colour left behind joins the recent ones (at most 8, newest first).
    ui.data_mut(|d| {
        let list: &mut Vec<[f64; 3]> = d.get_temp_mut_or_default(recent_id);
        list.retain(|c| *c != colour);
        list.insert(0, colour);
        list.truncate(8);
    });
    *v = new;
    true
}

/// The colour (linear, 0–1) as sRGB hex, applied when the field loses
/// focus; the colour typed, if one was.
fn hex_entry_ui(ui: &mut Ui, label: &str, colour: [f64; 3]) -> Option<[f64; 3]> {
    use crate::export::import::srgb_decode;
    let srgb = colour.map(super::analysis::linear_to_srgb8);
    let hex_id = egui::Id::unique(("colour_entry_hex", label));
    let mut hex = ui
        .data(|d| d.get_temp::<String>(hex_id))
        .unwrap_or_else(|| hex_of(srgb));
    let r = ui
        .add(egui::TextEdit::singleline(&mut hex).desired_width(64.0))
        .on_hover_text("sRGB hex, #rrggbb; Enter applies");
    let mut picked = None;
    if r.lost_focus() {
        picked = parse_hex(&hex).map(|b| b.map(|x| srgb_decode(x as f64 / 255.0)));
        ui.data_mut(|d| d.remove::<String>(hex_id));
    } else if r.has_focus() {
        ui.data_mut(|d| d.insert_temp(hex_id, hex));
    }
    picked
}

/// The colour as sRGB bytes, each a drag value; the colour dragged to,
/// where only the channel moved changes (the others keep their exact
/// value, not its nearest byte).
fn bytes_entry_ui(ui: &mut Ui, colour: [f64; 3]) -> Option<[f64; 3]> {
    use crate::export::import::srgb_decode;
    let mut bytes = colour.map(|x| f64::from(super::analysis::linear_to_srgb8(x)));
    let mut moved = [false; 3];
    for (c, x) in bytes.iter_mut().enumerate() {
        moved[c] = ui
            .add(
                DragValue::new(x)
                    .range(0.0..=255.0)
                    .speed(1.0)
                    .max_decimals(0)
                    .prefix(format!("{} ", CHANNEL_NAMES[c].to_uppercase()))
                    .suffix("/255"),
            )
            .changed();
    }
    moved.iter().any(|m| *m).then(|| {
        std::array::from_fn(|c| {
            if moved[c] {
                srgb_decode(bytes[c].round() / 255.0)
            } else {
                colour[c]
            }
        })
    })
}

/// The colour as HSV of its displayed sRGB (hue in degrees, saturation
/// and value in %), each a drag value; the colour dragged to.
fn hsv_entry_ui(ui: &mut Ui, colour: [f64; 3]) -> Option<[f64; 3]> {
    use crate::export::import::srgb_decode;
    let enc = colour.map(|x| super::analysis::linear_to_srgb8(x) as f64 / 255.0);
    let [h, s, val] = hsv_of(enc);
    let mut hsv = [h, s * 100.0, val * 100.0];
    let mut changed = false;
    for (x, (prefix, suffix, max, speed)) in hsv.iter_mut().zip([
        ("H ", "°", 360.0, 1.0),
        ("S ", " %", 100.0, 0.5),
        ("V ", " %", 100.0, 0.5),
    ]) {
        changed |= ui
            .add(
                DragValue::new(x)
                    .range(0.0..=max)
                    .speed(speed)
                    .max_decimals(1)
                    .prefix(prefix)
                    .suffix(suffix),
            )
            .changed();
    }
    changed.then(|| rgb_of_hsv([hsv[0], hsv[1] / 100.0, hsv[2] / 100.0]).map(srgb_decode))
}

/// The session's recent colours as swatches; the one clicked.
fn recent_colours_ui(ui: &mut Ui, recent_id: egui::Id) -> Option<[f64; 3]> {
    let recent: Vec<[f64; 3]> = ui.data(|d| d.get_temp(recent_id).unwrap_or_default());
    let mut picked = None;
    for (i, r) in recent.iter().enumerate() {
        let c = r.map(super::analysis::linear_to_srgb8);
        let (rect, resp) = ui.allocate_exact_size(egui::vec2(16.0, 16.0), egui::Sense::click());
        ui.painter()
            .rect_filled(rect, 2.0, egui::Color32::from_rgb(c[0], c[1], c[2]));
        let name = format!("recent colour {}", i + 1);
        resp.widget_info(|| egui::WidgetInfo::labeled(egui::accesskit::Role::Button, true, &name));
        if resp.on_hover_text(hex_of(c)).clicked() {
            picked = Some(*r);
        }
    }
    picked
}

/// The swatch of an RGB field, a button that opens egui's colour picker
/// (its numbers linear, as the fields are: `EditorApp::show` sets the
/// numeric colour space). A field whose range ends at 1 (albedo, tint) is
/// the colour itself; one that reaches past 1 (distances in mm) is colour
/// × multiplier, as HDRP's inspector splits its scattering distance
/// (`DiffusionProfileSettings.cs`: `scatteringDistance` colour and
/// `scatteringDistanceMultiplier`): the picker edits v / max(v) and the
/// multiplier max(v) stays. Returns whether it changed `v`.
pub(super) fn colour_picker_ui(
    ui: &mut Ui,
    label: &str,
    v: &mut Rgb,
    range: &std::ops::RangeInclusive<f64>,
) -> bool {
    let multiplier = if *range.end() > 1.0 {
        let m = v.iter().cloned().fold(0.0, f64::max);
        if m > 0.0 {
            m
        } else {
            1.0
        }
    } else {
        1.0
    };
    let mut colour = v.map(|x| (x / multiplier).clamp(0.0, 1.0) as f32);
    let response = egui::color_picker::color_edit_button_rgb(ui, &mut colour);
    let srgb = colour.map(|x| super::analysis::linear_to_srgb8(x as f64));
    let name = format!("{label} colour");
    response.widget_info(|| {
        let mut info = egui::WidgetInfo::labeled(egui::accesskit::Role::ColorWell, true, &name);
        info.current_text_value = Some(hex_of(srgb));
        info
    });
    let tip = if multiplier == 1.0 && *range.end() <= 1.0 {
        format!(
            "{label}: click to pick the colour. Linear {:.4} / {:.4} / {:.4}; shown as sRGB #{:02x}{:02x}{:02x}.",
            v[0], v[1], v[2], srgb[0], srgb[1], srgb[2]
        )
    } else {
        format!(
            "{label}: click to pick its colour; the largest channel stays at {multiplier:.4} (colour × multiplier, as HDRP's inspector). Colour, linear: {:.4} / {:.4} / {:.4}; shown as sRGB #{:02x}{:02x}{:02x}.",
            colour[0], colour[1], colour[2], srgb[0], srgb[1], srgb[2]
        )
    };
    let response = response.on_hover_text(tip);
    if !response.changed() {
        return false;
    }
    let (lo, hi) = (*range.start(), *range.end());
    let picked: Rgb = std::array::from_fn(|c| (colour[c] as f64 * multiplier).clamp(lo, hi));
    // Opening the picker converts the colour through f32 and HSV and back:
    // only a move beyond that rounding is an edit (else merely opening it
    // marked the look as changed).
    let tolerance = 1e-5 * multiplier.max(1.0);
    let moved: Vec<usize> = (0..3)
        .filter(|&c| (picked[c] - v[c]).abs() > tolerance)
        .collect();
    if moved.is_empty() {
        return false;
    }
    // Channels the artist did not move keep their exact value.
    for c in moved {
        v[c] = picked[c];
    }
    true
}
