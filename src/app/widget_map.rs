//! `SCATTERLAB_WIDGET_MAP=FILE`: the editor's controls as AccessKit sees
//! them, with where they are on screen, for tools that drive the real
//! window with a pointer (`tools/measure_live.sh`). A tool finds a control
//! by what it is (its role and label), never by window coordinates, so a
//! panel that moves does not send its drag to nothing.
//!
//! An egui plugin: on a frame at most every [`EVERY_S`] seconds it turns
//! egui's AccessKit tree on for that frame alone (the tree is built only
//! then, so the UI frames in between cost what they cost without it), and
//! writes the tree's nodes that have a label or a value, one a line:
//!
//! ```text
//! # scatterlab widget map: role, label, value, x0 y0 x1 y1 (window pixels)
//! SpinButton<TAB>R: mm<TAB>R: 0.757 mm<TAB>126 150 192 168
//! ```
//!
//! Rectangles are in physical pixels from the window's top left (the root
//! node's transform is egui's pixels per point). The file is replaced
//! whole (written beside it, then renamed), so a reader never sees half
//! of it.

use std::path::PathBuf;
use std::time::{Duration, Instant};

/// How often the map is written at most (s): each write builds the tree.
pub const EVERY_S: f64 = 0.25;

/// The plugin; [`install`] adds it where the variable is set.
pub struct WidgetMap {
    path: PathBuf,
    last: Option<Instant>,
    /// This frame builds the tree (chosen in the input hook).
    sampling: bool,
    written: String,
}

/// Adds the plugin to `ctx` when `SCATTERLAB_WIDGET_MAP` names a file.
pub fn install(ctx: &egui::Context) {
    if let Some(path) = std::env::var_os("SCATTERLAB_WIDGET_MAP") {
        ctx.add_plugin(WidgetMap {
            path: path.into(),
            last: None,
            sampling: false,
            written: String::new(),
        });
    }
}

impl egui::Plugin for WidgetMap {
    fn debug_name(&self) -> &'static str {
        "scatterlab widget map"
    }

    fn input_hook(&mut self, ctx: &egui::Context, _input: &mut egui::RawInput) {
        let due = self
            .last
            .is_none_or(|t| t.elapsed() >= Duration::from_secs_f64(EVERY_S));
        self.sampling = due;
        if due {
            ctx.enable_accesskit();
        }
    }

    fn output_hook(&mut self, ctx: &egui::Context, output: &mut egui::FullOutput) {
        if !self.sampling {
            return;
        }
        self.sampling = false;
        ctx.disable_accesskit();
        // The window has no AccessKit adapter (eframe is built without
        // one): the update is this plugin's alone.
        let Some(update) = output.platform_output.accesskit_update.take() else {
            return;
        };
        self.last = Some(Instant::now());
        let text = render(&update, ctx.pixels_per_point());
        if text != self.written {
            let tmp = self.path.with_extension("tmp");
            if std::fs::write(&tmp, &text)
                .and_then(|()| std::fs::rename(&tmp, &self.path))
                .is_ok()
            {
                self.written = text;
            }
        }
    }
}

/// One line a node that has a label or a value (tabs and line breaks in
/// them become spaces), in the update's order.
pub fn render(update: &egui::accesskit::TreeUpdate, pixels_per_point: f32) -> String {
    let clean = |s: &str| s.replace(['\t', '\n', '\r'], " ");
    let mut out =
        String::from("# scatterlab widget map: role, label, value, x0 y0 x1 y1 (window pixels)\n");
    // A control labelled by another node (egui's `labelled_by`) takes
    // that node's text as its label.
    let texts: std::collections::HashMap<_, &str> = update
        .nodes
        .iter()
        .filter_map(|(id, n)| Some((*id, n.label().or(n.value())?)))
        .collect();
    for (_, node) in &update.nodes {
        let label = node
            .label()
            .or_else(|| {
                node.labelled_by()
                    .iter()
                    .find_map(|id| texts.get(id).copied())
            })
            .unwrap_or("");
        // A text's value, or a number's (a drag value, a slider), or
        // whether a checkbox, radio button or selectable is on.
        let value = match (node.value(), node.numeric_value(), node.toggled()) {
            (Some(v), _, _) => v.to_owned(),
            (None, Some(n), _) => format!("{n}"),
            (None, None, Some(egui::accesskit::Toggled::True)) => "checked".into(),
            (None, None, Some(_)) => "unchecked".into(),
            (None, None, None) => String::new(),
        };
        let Some(b) = node.bounds() else { continue };
        if label.is_empty() && value.is_empty() {
            continue;
        }
        let s = f64::from(pixels_per_point);
        out += &format!(
            "{:?}\t{}\t{}\t{:.0} {:.0} {:.0} {:.0}\n",
            node.role(),
            clean(label),
            clean(&value),
            b.x0 * s,
            b.y0 * s,
            b.x1 * s,
            b.y1 * s
        );
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A drag value drawn in a real egui pass, read back from the map: its
    /// role and label are AccessKit's, and its rectangle is the one egui
    /// laid it out in, scaled by the pixels per point.
    #[test]
    fn a_drag_value_is_found_by_its_label_where_egui_drew_it() {
        let ctx = egui::Context::default();
        ctx.enable_accesskit();
        ctx.set_pixels_per_point(2.0);
        let mut value = 1.25_f64;
        let mut rect = egui::Rect::NOTHING;
        let mut out = ctx.run_ui(egui::RawInput::default(), |ui| {
            egui::CentralPanel::default().show(ui, |ui| {
                rect = ui
                    .add(egui::DragValue::new(&mut value).prefix("R: ").suffix(" mm"))
                    .rect;
            });
        });
        // Nothing paints here: the fonts' texture is not wanted.
        out.textures_delta.clear();
        let text = render(out.platform_output.accesskit_update.as_ref().unwrap(), 2.0);
        let line = text
            .lines()
            .find(|l| l.starts_with("SpinButton\tR: mm\tR: 1.25 mm\t"))
            .unwrap_or_else(|| panic!("no drag value in\n{text}"));
        let numbers: Vec<f32> = line
            .rsplit('\t')
            .next()
            .unwrap()
            .split(' ')
            .map(|n| n.parse().unwrap())
            .collect();
        let want = [rect.min.x, rect.min.y, rect.max.x, rect.max.y].map(|v| (v * 2.0).round());
        assert_eq!(numbers, want, "{line}");
    }

    /// A checkbox's state is its value, and a text field labelled by a
    /// label (egui's `labelled_by`) carries that label's text.
    #[test]
    fn a_checkbox_says_its_state_and_a_field_its_labels_text() {
        let ctx = egui::Context::default();
        ctx.enable_accesskit();
        let (mut on, mut off, mut typed) = (true, false, String::new());
        let mut out = ctx.run_ui(egui::RawInput::default(), |ui| {
            egui::CentralPanel::default().show(ui, |ui| {
                ui.checkbox(&mut on, "flip V");
                ui.checkbox(&mut off, "mask");
                let label = ui.label("Your folders:");
                ui.text_edit_singleline(&mut typed).labelled_by(label.id);
            });
        });
        out.textures_delta.clear();
        let text = render(out.platform_output.accesskit_update.as_ref().unwrap(), 1.0);
        for want in [
            "CheckBox\tflip V\tchecked\t",
            "CheckBox\tmask\tunchecked\t",
            "TextInput\tYour folders:\t\t",
        ] {
            assert!(
                text.lines().any(|l| l.starts_with(want)),
                "no {want:?} in\n{text}"
            );
        }
    }
}
