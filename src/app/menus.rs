//! The menu bar as a type (issue 51): built from what its menus show,
//! each menu a short function and most items rows of a table ([`item`]:
//! label, tooltip, what it asks for), returning [`Action`]s that
//! `EditorApp::apply` performs. The windows' items come from the one list
//! of windows ([`super::windows::Windows::items`]).

use super::windows::{items_ui, Action, MenuItem};
use super::DialogKind;
use crate::export::Format;
use crate::settings::library;
use std::path::PathBuf;

/// An item of a menu.
fn item(label: &str, tooltip: &str, action: Action) -> MenuItem {
    MenuItem {
        label: label.into(),
        tooltip: tooltip.into(),
        action,
    }
}

/// The menu bar: File, Edit, Export, View, Help and the look's name.
pub struct MenuBar {
    /// The look's name, and whether it has unsaved changes.
    pub name: String,
    pub dirty: bool,
    pub can_undo: bool,
    pub can_redo: bool,
    /// Files opened lately, newest first.
    pub recent: Vec<PathBuf>,
    /// The windows' items: the File menu's first ones (the presets), its
    /// images', the View menu's and the Help menu's.
    pub presets_items: Vec<MenuItem>,
    pub images_items: Vec<MenuItem>,
    pub view_items: Vec<MenuItem>,
    pub help_items: Vec<MenuItem>,
    /// The interface's scale and theme (light: true).
    pub ui_scale: f32,
    pub light_theme: bool,
    /// Open on the head scan when no mesh is asked for.
    pub start_on_scan: bool,
}

impl MenuBar {
    /// Draws the bar; what the artist asked for.
    pub fn ui(mut self, ui: &mut egui::Ui) -> Vec<Action> {
        let mut actions = Vec::new();
        let (scale, theme, scan) = (self.ui_scale, self.light_theme, self.start_on_scan);
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| actions.extend(self.file_ui(ui)));
            ui.menu_button("Edit", |ui| actions.extend(self.edit_ui(ui)));
            ui.menu_button("Export", |ui| actions.extend(export_ui(ui)));
            ui.menu_button("View", |ui| actions.extend(self.view_ui(ui)));
            ui.menu_button("Help", |ui| actions.extend(items_ui(ui, &self.help_items)));
            ui.separator();
            let dirty = if self.dirty { " *" } else { "" };
            ui.label(format!("{}{dirty}", self.name))
                .on_hover_text("* = unsaved changes");
        });
        if (self.ui_scale, self.light_theme) != (scale, theme) {
            actions.push(Action::SetInterface {
                scale: self.ui_scale,
                light_theme: self.light_theme,
            });
        }
        if self.start_on_scan != scan {
            actions.push(Action::SetStartOnScan(self.start_on_scan));
        }
        actions
    }

    /// The File menu: presets, open, import, save, images, meshes and quit.
    fn file_ui(&mut self, ui: &mut egui::Ui) -> Vec<Action> {
        let mut actions = items_ui(ui, &self.presets_items);
        actions.extend(self.open_ui(ui));
        actions.extend(items_ui(ui, &file_items()));
        actions.extend(items_ui(ui, &self.images_items));
        ui.separator();
        actions.extend(items_ui(ui, &mesh_items()));
        ui.checkbox(&mut self.start_on_scan, "Start on the scanned head")
            .on_hover_text("Open the editor on the head scan (else the procedural head) when no mesh is asked for.");
        ui.separator();
        actions.extend(items_ui(ui, &[item("Quit", "", Action::Quit)]));
        actions
    }

    /// New from a shipped preset, Open…, Import engine file… and Open
    /// recent.
    fn open_ui(&self, ui: &mut egui::Ui) -> Vec<Action> {
        let mut actions = Vec::new();
        ui.menu_button("New from preset", |ui| {
            let presets: Vec<MenuItem> = library::PRESETS
                .iter()
                .filter_map(|(file, _)| library::load(file).ok())
                .map(|p| {
                    item(
                        &p.name.clone(),
                        &p.source.clone(),
                        Action::NewLook(Box::new(p)),
                    )
                })
                .collect();
            actions.extend(items_ui(ui, &presets));
        });
        actions.extend(items_ui(ui, &[
            item("Open…  (Ctrl+O)", "", Action::OpenDialog(DialogKind::Open)),
            item("Import engine file…", "A Unity HDRP diffusion profile, Unreal SubsurfaceProfile text or .py, MaterialX document, Godot material or Blender snippet, as a new look: what that engine draws from it (you can also drop the file on the window)", Action::OpenDialog(DialogKind::Import)),
        ]));
        ui.menu_button("Open recent", |ui| {
            if self.recent.is_empty() {
                ui.label("(none)");
            }
            let recent: Vec<MenuItem> = self
                .recent
                .iter()
                .map(|p| item(&p.display().to_string(), "", Action::OpenPreset(p.clone())))
                .collect();
            actions.extend(items_ui(ui, &recent));
        });
        actions
    }

    /// Undo and redo.
    fn edit_ui(&self, ui: &mut egui::Ui) -> Vec<Action> {
        let mut actions = Vec::new();
        if ui
            .add_enabled(self.can_undo, egui::Button::new("Undo  (Ctrl+Z)"))
            .clicked()
        {
            actions.push(Action::Undo);
        }
        if ui
            .add_enabled(self.can_redo, egui::Button::new("Redo  (Ctrl+Shift+Z)"))
            .clicked()
        {
            actions.push(Action::Redo);
        }
        actions
    }

    /// The View menu's windows, the interface's scale and theme.
    fn view_ui(&mut self, ui: &mut egui::Ui) -> Vec<Action> {
        let actions = items_ui(ui, &self.view_items);
        ui.separator();
        // Applied when the drag ends, not on the way: the menu rescales
        // with the interface, so the slider would move under the pointer
        // (aiming at 130 % gave 95 %). The value dragged to waits in egui's
        // memory meanwhile; a click or the keyboard applies at once.
        let pending = ui.make_persistent_id("interface scale being dragged");
        let mut scale = ui
            .data(|d| d.get_temp::<f32>(pending))
            .unwrap_or(self.ui_scale);
        let slider = ui
            .add(
                egui::Slider::new(&mut scale, super::state::UI_SCALE_RANGE)
                    .step_by(0.05)
                    .custom_formatter(|v, _| format!("{:.0} %", v * 100.0))
                    .text("interface scale"),
            )
            .on_hover_text("The size of text and controls (Ctrl+plus and Ctrl+minus too), applied when you let go; remembered.");
        if slider.dragged() {
            ui.data_mut(|d| d.insert_temp(pending, scale));
        } else {
            // A drag that ended here applies; one left behind when the menu
            // closed mid-drag does not (the menu opened again shows it once
            // and forgets it); a click or a key applies at once.
            let left = ui.data_mut(|d| d.remove_temp::<f32>(pending));
            if slider.drag_stopped() || left.is_none() {
                self.ui_scale = scale;
            }
        }
        ui.horizontal(|ui| {
            ui.label("Theme");
            ui.selectable_value(&mut self.light_theme, false, "dark");
            ui.selectable_value(&mut self.light_theme, true, "light");
        })
        .response
        .on_hover_text("The interface's colours; the viewport and plots keep theirs.");
        actions
    }
}

/// Save, Save as, Save image and Reference image.
fn file_items() -> [MenuItem; 4] {
    [
        item("Save  (Ctrl+S)", "", Action::Save),
        item("Save as…  (Ctrl+Shift+S)", "", Action::OpenDialog(DialogKind::SaveAs)),
        item("Save image…  (F12)", "The viewport's frame as you see it (both sides of a comparison), as a PNG", Action::OpenDialog(DialogKind::SaveImage)),
        item("Reference image…", "A photograph beside the render or over it, with an eyedropper that picks its colours into the look's albedo or tint", Action::OpenDialog(DialogKind::Reference)),
    ]
}

/// A mesh from a file, the head scan or the procedural head.
fn mesh_items() -> [MenuItem; 3] {
    [
        item("Load mesh…", "An OBJ or glTF with UVs, in metres.", Action::OpenDialog(DialogKind::Mesh)),
        item("Scanned head", "Lee Perry-Smith's head scan (CC BY 3.0) with its colour and normal maps, at 0.0462 m/unit: a person, eyes closed as scanned.", Action::ScannedHead),
        item("Procedural head", "scatterlab's own head (CC0, with eyes and teeth): the bench's head.", Action::ProceduralHead),
    ]
}

/// The Export menu: every target, its name and what it writes.
fn export_ui(ui: &mut egui::Ui) -> Vec<Action> {
    let mut actions = Vec::new();
    for &f in Format::all() {
        // The name, and what it writes on a second, dimmer line.
        let mut text = egui::text::LayoutJob::default();
        let style = ui.style();
        text.append(
            f.name(),
            0.0,
            egui::TextFormat::simple(
                egui::TextStyle::Button.resolve(style),
                style.visuals.text_color(),
            ),
        );
        text.append(
            &format!("\n{}", f.description()),
            0.0,
            egui::TextFormat::simple(
                egui::TextStyle::Small.resolve(style),
                style.visuals.weak_text_color(),
            ),
        );
        if ui
            .button(text)
            .on_hover_text(format!(
                "{}: {} (command line: --format {})",
                f.name(),
                f.description(),
                f.id()
            ))
            .clicked()
        {
            actions.push(Action::OpenDialog(DialogKind::Export(f)));
            ui.close();
        }
    }
    actions
}
