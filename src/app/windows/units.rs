//! A loaded mesh's units: metres per unit with common choices, a live
//! height readout and a suggestion from the bounds (a head is 18–40 cm
//! tall with or without its neck). Asked when a mesh without remembered
//! units loads; every change applies at once (the mesh reloads and the
//! camera frames it) and is remembered for the file.

use super::{Action, Menu, Window, WindowView};
use crate::app::viewport::MeshInfo;
use crate::app::MeshArg;
use crate::render::mesh::{CRANIUM_M, PLAUSIBLE_CRANIUM_M, PLAUSIBLE_HEIGHT_M};
use std::path::Path;

/// The units prompt, open for the loaded mesh.
#[derive(Default)]
pub struct UnitsWindow {
    open: bool,
}

/// The mesh's height, its choices and the suggestion; `mpu` as the
/// artist left it, and whether OK was clicked.
fn units_ui(ui: &mut egui::Ui, path: &Path, info: MeshInfo, mpu: &mut f32) -> bool {
    let size = info.size;
    let h = size.height_units.max(1e-9);
    let mut done = false;
    let name = path.file_name().map_or_else(
        || path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    ui.label(format!("{name} is {h:.4} units tall."));
    ui.horizontal(|ui| {
        for (label, v) in [
            ("m", 1.0),
            ("dm", 0.1),
            ("cm", 0.01),
            ("mm", 0.001),
            ("inch", 0.0254),
        ] {
            ui.selectable_value(mpu, v, label);
        }
    });
    let speed = (*mpu) * 0.01;
    ui.add(
        egui::DragValue::new(mpu)
            .range(MeshArg::METRES_PER_UNIT)
            .speed(speed)
            .max_decimals(6)
            .suffix(" m/unit"),
    )
    .on_hover_text("Metres per unit of the file (Unity's worldScale convention).");
    let height_cm = h * (*mpu) * 100.0;
    let (lo, hi) = PLAUSIBLE_HEIGHT_M;
    let mut text = format!("Mesh height = {height_cm:.1} cm");
    let mut plausible = (100.0 * lo..=100.0 * hi).contains(&height_cm);
    if let Some(c) = size.cranium_units {
        let across_cm = c * (*mpu) * 100.0;
        let (lo, hi) = PLAUSIBLE_CRANIUM_M;
        text += &format!(", the head {across_cm:.1} cm across");
        plausible = (100.0 * lo..=100.0 * hi).contains(&across_cm);
    }
    let hover = format!(
            "Across: the mean of the head's width (ears included) and depth (nose included) above the neck; an adult's is about {:.0} cm.",
            100.0 * CRANIUM_M
        );
    if plausible {
        ui.label(text).on_hover_text(hover);
    } else {
        ui.colored_label(
            egui::Color32::from_rgb(240, 170, 60),
            format!("{text}: not a head's size"),
        )
        .on_hover_text(hover);
    }
    let suggested = size.suggest_metres_per_unit();
    let label = match size.cranium_units {
        Some(c) => format!(
            "Use {suggested} m/unit ({:.1} cm across, {:.1} cm tall)",
            c * suggested * 100.0,
            h * suggested * 100.0
        ),
        None => format!(
            "Use {suggested} m/unit ({:.1} cm tall)",
            h * suggested * 100.0
        ),
    };
    if ui
            .button(label)
            .on_hover_text(match size.cranium_units {
                Some(_) => "The units that make the head an adult's size (a common unit when one is within 20 %).",
                None => "No head found above a neck: a common unit that makes the mesh 18–40 cm tall, or the exact scale for 25 cm.",
            })
            .clicked()
        {
            *mpu = suggested;
        }
    if ui.button("OK").clicked() {
        done = true;
    }
    done
}

/// A mesh inside out (its faces or normals pointing in: it draws as a
/// dark disc) is named, with the offer to turn it outward; one turned is
/// said so, and can be drawn as the file has it again.
fn facing_ui(ui: &mut egui::Ui, info: MeshInfo, turn: &mut bool) {
    if let Some(what) = info.facing.describe() {
        ui.colored_label(
            egui::Color32::from_rgb(240, 170, 60),
            format!("The file is inside out: {what} point inward, so it draws dark."),
        );
        if ui
            .button("Turn outward")
            .on_hover_text("Reverse the triangles' winding and the normals that point inward, as the file should have them (remembered for this file).")
            .clicked()
        {
            *turn = true;
        }
        ui.separator();
    } else if *turn {
        ui.checkbox(turn, "Turned outward (the file is inside out)")
            .on_hover_text("Untick to draw the mesh as the file has it.");
        ui.separator();
    }
}

impl Window for UnitsWindow {
    fn title(&self) -> &'static str {
        "Mesh units"
    }
    fn menu(&self) -> Option<Menu> {
        Some(Menu::Mesh)
    }
    fn menu_label(&self) -> String {
        "Units…".into()
    }
    fn menu_tooltip(&self) -> &'static str {
        "Metres per unit of this mesh: its size, the camera and the scattering distances in mm depend on it."
    }
    fn is_open(&self) -> bool {
        self.open
    }
    fn set_open(&mut self, open: bool) {
        self.open = open;
    }

    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        if view.mesh.is_none() {
            // The default head has no units to ask for: closed.
            self.open = false;
        }
        let (Some(path), Some(info)) = (view.mesh.filter(|_| self.open), view.mesh_info) else {
            return Vec::new();
        };
        let current = view.meshes.get(path).cloned().unwrap_or_default();
        let (mut mpu, mut turn) = (current.metres_per_unit, current.turn_outward);
        let mut done = false;
        egui::Window::new(self.title())
            .collapsible(false)
            .resizable(false)
            .anchor(egui::Align2::CENTER_CENTER, egui::vec2(0.0, 0.0))
            .open(&mut self.open)
            .show(ctx, |ui| {
                facing_ui(ui, info, &mut turn);
                done = units_ui(ui, path, info, &mut mpu);
            });
        if done {
            self.open = false;
        }
        if mpu != current.metres_per_unit
            || turn != current.turn_outward
            || !view.meshes.contains_key(path)
        {
            let settings = crate::app::state::MeshSettings {
                metres_per_unit: mpu,
                turn_outward: turn,
                ..current
            };
            return vec![Action::SetMeshSettings(path.to_path_buf(), settings)];
        }
        Vec::new()
    }
}
