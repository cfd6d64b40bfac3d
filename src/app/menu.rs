//! The editor's menu bar, keyboard shortcuts, dropped files and the
//! parameters panel's frame (its rows are `params_ui`; the status bar is
//! `report.rs`).

use super::*;

impl EditorApp {
    pub(super) fn handle_drops(&mut self, ctx: &egui::Context) {
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .filter(|p| !p.as_os_str().is_empty())
                .collect()
        });
        for path in dropped {
            let ext = path
                .extension()
                .and_then(|e| e.to_str())
                .unwrap_or("")
                .to_ascii_lowercase();
            let engines = crate::export::importable_extensions(false);
            let meshes = crate::render::mesh::Mesh::EXTENSIONS;
            match ext.as_str() {
                e if e == crate::settings::PRESET_EXTENSION => self.guarded(Pending::Open(path)),
                // A .gltf is a look when a material has the volume
                // extension (the glTF export), and otherwise a mesh.
                e if engines.contains(&e)
                    && (!meshes.contains(&e) || crate::export::gltf_has_volume(&path)) =>
                {
                    self.import_now(&path)
                }
                e if meshes.contains(&e) => self.load_mesh(Some(path)),
                "hdr" => self.load_environment(path),
                _ => {
                    self.say(format!(
                        "Error: {}: not a preset (.ron), engine file (.{}), mesh (.{}) or environment (.hdr)",
                        path.display(),
                        engines.join(", ."),
                        meshes.join(", ."),
                    )
                )}
            }
        }
    }

    pub(super) fn shortcuts(&mut self, ctx: &egui::Context) {
        use egui::{Key, KeyboardShortcut, Modifiers};
        // A prompt is up (unsaved changes, replace, recover): it asked
        // about the look as it is, so no key may change the look under it.
        if self.modal_prompt_open() {
            return;
        }
        let cmd_shift = Modifiers::COMMAND | Modifiers::SHIFT;
        let (redo, undo, redo_y, save_as, save, open, toggle, image) = ctx.input_mut(|i| {
            (
                i.consume_shortcut(&KeyboardShortcut::new(cmd_shift, Key::Z)),
                i.consume_shortcut(&KeyboardShortcut::new(Modifiers::COMMAND, Key::Z)),
                i.consume_shortcut(&KeyboardShortcut::new(Modifiers::COMMAND, Key::Y)),
                i.consume_shortcut(&KeyboardShortcut::new(cmd_shift, Key::S)),
                i.consume_shortcut(&KeyboardShortcut::new(Modifiers::COMMAND, Key::S)),
                i.consume_shortcut(&KeyboardShortcut::new(Modifiers::COMMAND, Key::O)),
                i.key_pressed(Key::Space),
                i.consume_key(Modifiers::NONE, Key::F12),
            )
        });
        if ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::F1)) {
            self.windows.shortcuts.toggle();
        }
        if image {
            self.open_dialog(DialogKind::SaveImage);
        }
        if redo || redo_y {
            self.doc.redo();
        } else if undo {
            self.doc.undo();
        }
        if save_as {
            self.open_dialog(DialogKind::SaveAs);
        } else if save {
            self.save();
        }
        if open {
            self.open_dialog(DialogKind::Open);
        }
        self.viewport_keys(ctx, toggle);
    }

    /// The View menu's interface scale and theme, set on `ctx` where
    /// changed.
    pub(super) fn apply_interface(&mut self, ctx: &egui::Context) {
        // The interface's scale and theme (View menu), where changed; a
        // zoom by keyboard (egui's Ctrl+plus/minus) is taken as the scale.
        if let Some(applied) = self.view.applied_scale {
            if (ctx.zoom_factor() - applied).abs() > 1e-4 {
                self.ui_state.ui_scale = ctx.zoom_factor();
            }
        }
        let scale = self
            .ui_state
            .ui_scale
            .clamp(*state::UI_SCALE_RANGE.start(), *state::UI_SCALE_RANGE.end());
        if (ctx.zoom_factor() - scale).abs() > 1e-4 {
            ctx.set_zoom_factor(scale);
        }
        self.view.applied_scale = Some(scale);
        let theme = if self.ui_state.light_theme {
            egui::Theme::Light
        } else {
            egui::Theme::Dark
        };
        if ctx.theme() != theme {
            ctx.set_theme(theme);
        }
    }

    pub(super) fn menu_bar_ui(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| self.file_menu_ui(ui));
            ui.menu_button("Edit", |ui| {
                if ui
                    .add_enabled(self.doc.can_undo(), egui::Button::new("Undo  (Ctrl+Z)"))
                    .clicked()
                {
                    self.doc.undo();
                }
                if ui
                    .add_enabled(
                        self.doc.can_redo(),
                        egui::Button::new("Redo  (Ctrl+Shift+Z)"),
                    )
                    .clicked()
                {
                    self.doc.redo();
                }
            });
            ui.menu_button("Export", |ui| self.export_menu_ui(ui));
            ui.menu_button("View", |ui| {
                let items = self.windows.menu_items_ui(ui, windows::Menu::View);
                self.apply(items);
                ui.separator();
                ui.add(
                    egui::Slider::new(&mut self.ui_state.ui_scale, state::UI_SCALE_RANGE)
                        .step_by(0.05)
                        .custom_formatter(|v, _| format!("{:.0} %", v * 100.0))
                        .text("interface scale"),
                )
                .on_hover_text(
                    "The size of text and controls (Ctrl+plus and Ctrl+minus too); remembered.",
                );
                ui.horizontal(|ui| {
                    ui.label("Theme");
                    ui.selectable_value(&mut self.ui_state.light_theme, false, "dark");
                    ui.selectable_value(&mut self.ui_state.light_theme, true, "light");
                })
                .response
                .on_hover_text("The interface's colours; the viewport and plots keep theirs.");
            });
            ui.menu_button("Help", |ui| {
                let items = self.windows.menu_items_ui(ui, windows::Menu::Help);
                self.apply(items);
            });
            ui.separator();
            let dirty = if self.doc.is_dirty() { " *" } else { "" };
            ui.label(format!("{}{}", self.doc.preset.name, dirty))
                .on_hover_text("* = unsaved changes");
        });
    }

    /// The File menu: presets, open, import, save, images, meshes and quit.
    fn file_menu_ui(&mut self, ui: &mut egui::Ui) {
        let items = self.windows.menu_items_ui(ui, windows::Menu::FilePresets);
        self.apply(items);
        ui.menu_button("New from preset", |ui| {
            for (file, _) in library::PRESETS {
                if let Ok(p) = library::load(file) {
                    if ui.button(&p.name).on_hover_text(&p.source).clicked() {
                        self.guarded(Pending::New(Box::new(p)));
                        ui.close();
                    }
                }
            }
        });
        if ui.button("Open…  (Ctrl+O)").clicked() {
            self.open_dialog(DialogKind::Open);
            ui.close();
        }
        if ui
            .button("Import engine file…")
            .on_hover_text("A Unity HDRP diffusion profile, Unreal SubsurfaceProfile text or .py, MaterialX document, Godot material or Blender snippet, as a new look: what that engine draws from it (you can also drop the file on the window)")
            .clicked()
        {
            self.open_dialog(DialogKind::Import);
            ui.close();
        }
        ui.menu_button("Open recent", |ui| {
            if self.ui_state.recent.is_empty() {
                ui.label("(none)");
            }
            for p in self.ui_state.recent.clone() {
                if ui.button(p.display().to_string()).clicked() {
                    self.guarded(Pending::Open(p));
                    ui.close();
                }
            }
        });
        if ui.button("Save  (Ctrl+S)").clicked() {
            self.save();
            ui.close();
        }
        if ui.button("Save as…  (Ctrl+Shift+S)").clicked() {
            self.open_dialog(DialogKind::SaveAs);
            ui.close();
        }
        if ui
            .button("Save image…  (F12)")
            .on_hover_text(
                "The viewport's frame as you see it (both sides of a comparison), as a PNG",
            )
            .clicked()
        {
            self.open_dialog(DialogKind::SaveImage);
            ui.close();
        }
        if ui
            .button("Reference image…")
            .on_hover_text("A photograph beside the render or over it, with an eyedropper that picks its colours into the look's albedo or tint")
            .clicked()
        {
            self.open_dialog(DialogKind::Reference);
            ui.close();
        }
        let items = self.windows.menu_items_ui(ui, windows::Menu::FileImages);
        self.apply(items);
        ui.separator();
        if ui
            .button("Load mesh…")
            .on_hover_text("An OBJ or glTF with UVs, in metres.")
            .clicked()
        {
            self.open_dialog(DialogKind::Mesh);
            ui.close();
        }
        if ui
            .button("Scanned head")
            .on_hover_text("Lee Perry-Smith's head scan (CC BY 3.0) with its colour and normal maps, at 0.0462 m/unit: a person, eyes closed as scanned.")
            .clicked()
        {
            if !self.open_scanned_head() {
                self.say("Error: the head scan is not here (assets/scan/ of the repository): use Load mesh…");
            }
            ui.close();
        }
        if ui
            .button("Procedural head")
            .on_hover_text("scatterlab's own head (CC0, with eyes and teeth): the bench's head.")
            .clicked()
        {
            self.load_mesh(None);
            ui.close();
        }
        ui.checkbox(&mut self.ui_state.start_on_scan, "Start on the scanned head")
            .on_hover_text("Open the editor on the head scan (else the procedural head) when no mesh is asked for.");
        ui.separator();
        if ui.button("Quit").clicked() {
            self.guarded(Pending::Quit);
            ui.close();
        }
    }

    /// The Export menu: every target, its name and what it writes.
    fn export_menu_ui(&mut self, ui: &mut egui::Ui) {
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
                self.open_dialog(DialogKind::Export(f));
                ui.close();
            }
        }
    }

    pub(super) fn params_panel_ui(&mut self, ui: &mut egui::Ui) {
        let p = &mut self.doc.preset;
        ui.heading("Look");
        ui.horizontal(|ui| {
            ui.label("Name");
            ui.text_edit_singleline(&mut p.name).on_hover_text(
                "The look's name, used in exports (Unity m_Name, Unreal asset name).",
            );
        });
        ui.separator();
        params_ui::model_picker_ui(ui, &mut p.profile);
        params_ui::model_params_ui(ui, &mut p.profile);
        self.map_colour_ui(ui);
        let p = &mut self.doc.preset;
        // The model's error, from the last build (never rebuilt per frame:
        // layered stacks take seconds).
        if let Some(Err(e)) = &self.profile.curves {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
        if let Err(e) = p.rendering.validate() {
            ui.colored_label(ui.visuals().error_fg_color, e.to_string());
        }
        ui.separator();
        egui::CollapsingHeader::new("Rendering")
            .default_open(true)
            .show(ui, |ui| params_ui::rendering_ui(ui, &mut p.rendering));
        ui.separator();
        egui::CollapsingHeader::new("Engines (live)")
            .default_open(true)
            .show(ui, |ui| self.engine_readouts_ui(ui));
    }

    pub(super) fn engine_readouts_ui(&mut self, ui: &mut egui::Ui) {
        use crate::model::units::{UnityProfile, UnrealProfile, UNREAL_DEFAULT_WORLD_UNIT_SCALE};
        // The file the look came from, as that engine wrote it (while the
        // look is still the one imported).
        if let Some((path, look)) = &self.profile.imported {
            if look.preset == self.doc.preset {
                let name = path.file_name().map_or_else(
                    || path.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                );
                ui.label(format!("Imported from {name} ({})", look.kind))
                    .on_hover_text(path.display().to_string());
                let width = look
                    .fields
                    .iter()
                    .map(|(k, _)| k.chars().count())
                    .max()
                    .unwrap_or(0);
                let text: String = look
                    .fields
                    .iter()
                    .map(|(k, v)| format!("{k:width$}  {v}\n"))
                    .collect();
                ui.monospace(text.trim_end());
                for n in &look.notes {
                    ui.label(egui::RichText::new(format!("• {n}")).small());
                }
                ui.separator();
            }
        }
        let p = &self.doc.preset;
        let burley = match &p.profile {
            crate::settings::ProfileSpec::Burley(b) => {
                b.build().map(|b| (b, 0.0)).map_err(|e| e.to_string())
            }
            _ => match self
                .profile
                .latest
                .as_ref()
                .filter(|a| a.key.profile == p.profile)
            {
                Some(a) => a.burley_fit.clone().unwrap_or_else(|| Err("no fit".into())),
                None => {
                    ui.horizontal(|ui| {
                        super::report::spinner(ui);
                        ui.label("fitting Burley …");
                    });
                    return;
                }
            },
        };
        let (b, err) = match burley {
            Ok(x) => x,
            Err(e) => {
                ui.colored_label(ui.visuals().error_fg_color, e);
                return;
            }
        };
        if err > 0.0 {
            ui.label(format!(
                "Through a Burley fit (relative L2 error of r·R(r): {:.2} %)",
                100.0 * err
            ));
        }
        let f3 = |v: [f64; 3]| format!("({:.4}, {:.4}, {:.4})", v[0], v[1], v[2]);
        if let Ok(u) = UnityProfile::from_burley(&b, p.rendering.world_scale_m_per_unit) {
            ui.label("Unity HDRP")
                .on_hover_text("DiffusionProfileSettings fields");
            ui.monospace(format!(
                "scatteringDistance  {}\nmultiplier          {:.4}\nworldScale          {:.4} m/unit\nalbedo (material)   {}",
                f3(u.scattering_distance_color),
                u.scattering_distance_multiplier,
                u.world_scale_m_per_unit,
                f3(b.albedo())
            ));
        }
        if let Ok(u) = UnrealProfile::from_burley(&b, UNREAL_DEFAULT_WORLD_UNIT_SCALE) {
            ui.label("Unreal")
                .on_hover_text("SubsurfaceProfile (Burley, mean free path)");
            ui.monospace(format!(
                "SurfaceAlbedo         {}\nMeanFreePathColor     {}\nMeanFreePathDistance  {:.4} cm\nWorldUnitScale        {:.2}",
                f3(u.surface_albedo),
                f3(u.mean_free_path_color),
                u.mean_free_path_distance_cm,
                u.world_unit_scale
            ));
        }
    }
}
