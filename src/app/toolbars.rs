//! The viewport's two toolbars as types (issue 51): each is built from
//! what it shows, draws its rows (each a short function) on a copy of the
//! settings it edits, and returns [`Action`]s, which
//! `EditorApp::apply` performs. Neither writes the editor's state.

use super::compare::CompareSettings;
use super::state::{self, CompareB, CompareMode, EnvironmentChoice, ViewState};
use super::windows::{Action, MenuItem};
use super::AbView;
use crate::settings::albedo::MaterialAlbedo;
use crate::settings::rendering::MethodId;
use std::path::Path;

/// How far B's file is from A, beside B.
pub struct BReadout {
    /// Relative L2 difference of r·R(r) per channel.
    pub difference: [f64; 3],
    /// "drawn with A's albedo", when B's engine keeps it in the material.
    pub albedo_note: Option<String>,
    /// B's engine fields that differ from A's: name, and both values.
    pub others: Vec<(&'static str, String)>,
}

/// Compare mode, B, the split and A/B alone: rows that wrap.
pub struct CompareBar {
    pub settings: CompareSettings,
    /// A's method and B's method or file name.
    pub names: (String, String),
    /// There is an edit to show the look before.
    pub has_before: bool,
    /// B is a file whose engine keeps the albedo in the material.
    pub b_albedo_in_material: bool,
    /// The head has a colour map of its own.
    pub has_map: bool,
    pub readout: Option<BReadout>,
}

impl CompareBar {
    /// Draws the rows; what the artist asked for.
    pub fn ui(mut self, ui: &mut egui::Ui) -> Vec<Action> {
        let before = self.settings.clone();
        let mut actions = Vec::new();
        if !self.has_before {
            self.settings.show_before = false;
        }
        // Wraps onto more rows where the viewport is narrow, so the
        // viewport below never grows past its panel.
        ui.horizontal_wrapped(|ui| {
            self.modes_ui(ui);
            if self.settings.mode != CompareMode::Off {
                // B and its controls on a row of their own: a widget that
                // overflows a row widens everything under it.
                ui.end_row();
                actions.extend(self.b_ui(ui));
                self.readout_ui(ui);
                self.scale_ui(ui);
                self.alone_ui(ui);
            }
        });
        if self.settings != before {
            actions.insert(0, Action::SetCompare(self.settings));
        }
        actions
    }

    /// The modes, "before" and "SSS only".
    fn modes_ui(&mut self, ui: &mut egui::Ui) {
        let s = &mut self.settings;
        ui.label("Compare").on_hover_text(
            "A is the current look; B another method or preset. Space flips between A alone and B alone; Escape, or the mode again, shows both.",
        );
        for (m, name) in [
            (CompareMode::Off, "off"),
            (CompareMode::Split, "split"),
            (CompareMode::SideBySide, "side by side"),
            (CompareMode::Difference, "difference"),
        ] {
            if ui
                .selectable_label(s.mode == m && s.ab == AbView::Both, name)
                .clicked()
            {
                s.mode = m;
                s.ab = AbView::Both;
            }
        }
        // A widget of the row, not a nested ui: squeezed at the row's end
        // (1280×720 at 130 %), a nested ui wrapped "before" a letter a line
        // and made the toolbar as tall as the viewport.
        if ui
            .add_enabled(
                self.has_before,
                egui::Button::selectable(s.show_before, "before"),
            )
            .on_hover_text("Flicker: show the look as it was before the last edit (F toggles), to see what the edit changed.")
            .on_disabled_hover_text("No edit yet to compare with.")
            .clicked()
        {
            s.show_before = !s.show_before;
        }
        let none = CompareB::Method(MethodId::baseline());
        let sss_only = s.mode == CompareMode::Difference && s.b == none && s.ab == AbView::Both;
        if ui
            .selectable_label(sss_only, "SSS only")
            .on_hover_text("What scattering adds: the difference view of this look against the same look without SSS (method none), |ΔL*| on the fixed scale at the right edge. Click again to go back.")
            .clicked()
        {
            if sss_only {
                s.mode = CompareMode::Off;
            } else {
                s.mode = CompareMode::Difference;
                s.b = none;
                s.ab = AbView::Both;
            }
        }
    }

    /// B's menu (a method, or a file) and, for a file whose engine keeps
    /// the albedo in the material, the albedo it is drawn with.
    fn b_ui(&mut self, ui: &mut egui::Ui) -> Vec<Action> {
        let mut actions = Vec::new();
        let s = &mut self.settings;
        // A long file name is cut in the middle (whole on hover): the row
        // stays one line at 1280×720.
        let name = &self.names.1;
        let short = match name.chars().count() {
            n if n > 18 => {
                let head: String = name.chars().take(9).collect();
                let tail: String = name.chars().skip(n - 7).collect();
                format!("{head}…{tail}")
            }
            _ => name.clone(),
        };
        ui.menu_button(format!("B: {short}"), |ui| {
            for &m in MethodId::all() {
                if ui.button(m.label()).clicked() {
                    s.b = CompareB::Method(m);
                    ui.close();
                }
            }
            if ui
                .button("a preset or engine file…")
                .on_hover_text("B is the look in a preset, or what an engine draws from its file (Unity .asset, Unreal text, MaterialX, Godot .tres, Blender .py), with how far its r·R(r) is from A")
                .clicked()
            {
                actions.push(Action::OpenDialog(super::DialogKind::CompareB));
                ui.close();
            }
        });
        if !(matches!(s.b, CompareB::Preset(_)) && self.b_albedo_in_material) {
            return actions;
        }
        let current = s.b_albedo;
        egui::ComboBox::from_id_salt("b_material_albedo")
            .selected_text(format!("B's albedo: {}", current.label()))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut s.b_albedo, MaterialAlbedo::LookA, "A's");
                ui.add_enabled_ui(self.has_map, |ui| {
                    ui.selectable_value(&mut s.b_albedo, MaterialAlbedo::Map, "the head's map")
                        .on_disabled_hover_text("The head has no colour map of its own.");
                });
                if ui
                    .selectable_label(matches!(current, MaterialAlbedo::Typed(_)), "a colour…")
                    .clicked()
                {
                    actions.push(Action::AskBAlbedoColour);
                }
            })
            .response
            .on_hover_text("B's engine keeps the albedo in the material (HDRP), so its file has none: B is drawn and compared with this albedo.");
        actions
    }

    /// How far a file's look is from A: what the round trip costs.
    fn readout_ui(&self, ui: &mut egui::Ui) {
        let Some(r) = &self.readout else { return };
        let d = r.difference;
        // Short, so the row stays one line at 1280×720: the albedo B is
        // drawn with is the combo box's beside it, and the fields that also
        // differ are counted here and named on hover.
        ui.label(format!(
            "B − A {:.1}/{:.1}/{:.1} %",
            100.0 * d[0],
            100.0 * d[1],
            100.0 * d[2],
        ))
        .on_hover_text(format!("Relative L2 difference of r·R(r) between B's look and A's, per channel (to A's 99.7 % radius): for a file exported from A, the round-trip error of that engine.{}", match &r.albedo_note {
            Some(a) => format!(" B's engine keeps the albedo in the material, so B is {a}: what differs is the profile's shape and B's other fields (its world scale and transmission mode in the Engines panel)."),
            None => String::new(),
        }));
        if !r.others.is_empty() {
            let names: Vec<&str> = r.others.iter().map(|(n, _)| *n).collect();
            let details: Vec<&str> = r.others.iter().map(|(_, d)| d.as_str()).collect();
            let n = names.len();
            ui.label(format!("+{n} field{}", if n == 1 { "" } else { "s" }))
                .on_hover_text(format!("Also differs: {}. B's engine-side fields that differ from A's, which the r·R(r) difference does not show:\n{}", names.join(", "), details.join("\n")));
        }
    }

    /// The difference view's scale, or the split's place.
    fn scale_ui(&mut self, ui: &mut egui::Ui) {
        let s = &mut self.settings;
        if s.mode == CompareMode::Difference {
            ui.add_enabled(
                !s.difference_auto,
                egui::DragValue::new(&mut s.difference_scale)
                    .range(0.1..=100.0)
                    .speed(0.05)
                    .max_decimals(1)
                    .prefix("white = ")
                    .suffix(" ΔL*"),
            )
            .on_hover_text("The difference that shows white: |A − B| of CIE lightness L* (0 black, 100 white; about 1 is just noticeable side by side). Fixed, so compares read on one scale.");
            ui.checkbox(&mut s.difference_auto, "auto")
                .on_hover_text("Scale each difference view to its own largest difference instead (the scale then changes with every pair).");
        }
        if s.mode == CompareMode::Split {
            ui.spacing_mut().slider_width = 90.0;
            ui.add(egui::Slider::new(&mut s.split, 0.0..=1.0).text("split"))
                .on_hover_text("Where the split line sits: A left of it, B right.");
        }
    }

    /// A alone, B alone.
    fn alone_ui(&mut self, ui: &mut egui::Ui) {
        let (a_name, b_name) = &self.names;
        for (side, name) in [(AbView::A, "A alone"), (AbView::B, "B alone")] {
            if ui
                .selectable_label(self.settings.ab == side, name)
                .on_hover_text(format!(
                    "Space flips between A alone and B alone (A: {a_name}, B: {b_name})."
                ))
                .clicked()
            {
                self.settings.ab = if self.settings.ab == side {
                    AbView::Both
                } else {
                    side
                };
            }
        }
    }
}

/// Environment, light rigs (and Light & display…), Reset view, the ground
/// truth and a loaded mesh's menu: one row at 1280×720 (the environment
/// and the light are menus; their fields are in Light & display). It
/// wraps only where the viewport is narrower still.
pub struct ViewBar<'a> {
    pub view: ViewState,
    /// The HDR map loaded last, if any.
    pub environment_file: Option<&'a Path>,
    pub refine_to_truth: bool,
    /// The camera distance that frames the mesh (m): Reset view's.
    pub framing: f32,
    /// The Mesh menu's items, with a mesh loaded.
    pub mesh_items: Vec<MenuItem>,
}

impl ViewBar<'_> {
    /// Draws the row; what the artist asked for.
    pub fn ui(mut self, ui: &mut egui::Ui) -> Vec<Action> {
        let (view, refine) = (self.view, self.refine_to_truth);
        let mut actions = Vec::new();
        ui.horizontal_wrapped(|ui| {
            actions.extend(self.environment_ui(ui));
            actions.extend(light_menu_ui(ui, &self.view));
            self.reset_and_truth_ui(ui);
            if !self.mesh_items.is_empty() {
                // One menu, so a loaded mesh keeps the row at 1280×720.
                ui.menu_button("Mesh", |ui| {
                    actions.extend(super::windows::items_ui(ui, &self.mesh_items))
                })
                .response
                .on_hover_text("The loaded mesh's units and maps.");
            }
        });
        if self.view != view {
            actions.insert(0, Action::SetView(self.view));
        }
        if self.refine_to_truth != refine {
            actions.push(Action::SetRefineToTruth(self.refine_to_truth));
        }
        actions
    }

    /// The environment's combo box: the studio sky, black, the loaded
    /// map, another map or a shipped one, and the window with its turn.
    fn environment_ui(&mut self, ui: &mut egui::Ui) -> Vec<Action> {
        let mut actions = Vec::new();
        let v = &mut self.view;
        let map_name = self
            .environment_file
            .and_then(|p| p.file_name())
            .map_or("HDR map".into(), |n| n.to_string_lossy().into_owned());
        let current = match v.environment {
            EnvironmentChoice::Studio => "studio sky".to_owned(),
            EnvironmentChoice::Black => "black".to_owned(),
            EnvironmentChoice::Map => map_name.clone(),
        };
        let env = egui::ComboBox::from_id_salt("environment")
            .selected_text(current.clone())
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut v.environment, EnvironmentChoice::Studio, "studio sky")
                    .on_hover_text("The procedural studio sky.");
                ui.selectable_value(&mut v.environment, EnvironmentChoice::Black, "black")
                    .on_hover_text("No environment light: the rig's lights alone.");
                if v.environment_map_sh.is_some() {
                    let tip =
                        self.environment_file
                            .map_or("The last HDR map loaded.".into(), |p| {
                                format!(
                                    "{} (its irradiance, as order-2 spherical harmonics)",
                                    p.display()
                                )
                            });
                    ui.selectable_value(&mut v.environment, EnvironmentChoice::Map, map_name)
                        .on_hover_text(tip);
                }
                actions.extend(maps_ui(ui));
            })
            .response;
        env.widget_info(|| {
            let mut info =
                egui::WidgetInfo::labeled(egui::accesskit::Role::ComboBox, true, "Environment");
            info.current_text_value = Some(current.clone());
            info
        });
        env.on_hover_text(
            "Environment: what lights the head besides the key, fill and rim lights.",
        );
        actions
    }

    /// Reset view and "to truth".
    fn reset_and_truth_ui(&mut self, ui: &mut egui::Ui) {
        if ui
            .button("Reset view")
            .on_hover_text(
                "Camera, lights and exposure back to their defaults (a white key light, the fill and rim off); the environment stays.",
            )
            .clicked()
        {
            self.view.orbit = crate::settings::OrbitView {
                camera_distance_m: self.framing,
                ..Default::default()
            };
        }
        ui.checkbox(&mut self.refine_to_truth, "to truth").on_hover_text(
            "Refine to the truth: once the method's frame has converged, go on to the ground truth (reference) of the same view and keep it as the converged state: a coarse one first, then the full frame, with progress and the time left. A alone; while comparing, the two sides stay as they are.",
        );
    }
}

/// The environment list's maps: another one from a file, the shipped
/// ones, and the window with the map's turn, blur and background.
fn maps_ui(ui: &mut egui::Ui) -> Vec<Action> {
    let mut actions = Vec::new();
    if ui
        .button("HDR map…")
        .on_hover_text("Light the head with an equirectangular Radiance .hdr map (or drop one onto the window).")
        .clicked()
    {
        actions.push(Action::ChooseEnvironmentFile);
        ui.close();
    }
    for path in state::shipped_hdr_maps() {
        let name = path
            .file_stem()
            .map(|n| n.to_string_lossy().replace('_', " "))
            .unwrap_or_default();
        if ui
            .button(format!("shipped: {name}"))
            .on_hover_text(format!(
                "{} (CC0, made by tools/make_hdri.py)",
                path.display()
            ))
            .clicked()
        {
            actions.push(Action::LoadEnvironment(path));
            ui.close();
        }
    }
    ui.separator();
    let title = super::windows::light::TITLE;
    if ui
        .button(format!("Turn, blur, background: {title}…"))
        .on_hover_text("The HDR map's turn and blur and whether it is drawn behind the head, in a window that stays open.")
        .clicked()
    {
        actions.push(Action::OpenWindow(title));
        ui.close();
    }
    actions
}

/// The light rigs, one click each, and the Light & display window (each
/// light's intensity and colour, the exposure, the display transform: fields and
/// a combo box that a menu cannot hold, tests/pointer.rs).
fn light_menu_ui(ui: &mut egui::Ui, v: &ViewState) -> Vec<Action> {
    let title = super::windows::light::TITLE;
    let mut actions = Vec::new();
    let current = state::LightRig::current(v);
    let rig_label = current.map_or("Light: custom".to_owned(), |r| {
        format!("Light: {}", r.label())
    });
    ui.menu_button(rig_label, |ui| {
        for rig in state::LightRig::ALL {
            if ui
                .selectable_label(current == Some(rig), rig.label())
                .on_hover_text(rig.tip())
                .clicked()
            {
                actions.push(Action::ApplyRig(rig));
                ui.close();
            }
        }
        ui.separator();
        if ui
            .button(format!("{title}…"))
            .on_hover_text("The key, fill and rim lights' intensity, colour and direction, the exposure, the camera's focal length, the display transform (ACES, AgX, PBR Neutral) and the environment, in a window that stays open.")
            .clicked()
        {
            actions.push(Action::OpenWindow(title));
            ui.close();
        }
    })
    .response
    .on_hover_text("Lighting set-ups that show scattering, each one click: the key light's direction is relative to the camera. Right-drag the view or drag the light gizmo (bottom right) to move the light. Intensity, exposure and the display transform: Light & display….");
    actions
}
