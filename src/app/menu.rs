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

    /// The menu bar ([`menus::MenuBar`]).
    pub(super) fn menu_bar_ui(&mut self, ui: &mut egui::Ui) {
        use windows::Menu;
        let bar = menus::MenuBar {
            name: self.doc.preset.name.clone(),
            dirty: self.doc.is_dirty(),
            can_undo: self.doc.can_undo(),
            can_redo: self.doc.can_redo(),
            recent: self.ui_state.recent.clone(),
            presets_items: self.windows.items(Menu::FilePresets),
            images_items: self.windows.items(Menu::FileImages),
            view_items: self.windows.items(Menu::View),
            help_items: self.windows.items(Menu::Help),
            ui_scale: self.ui_state.ui_scale,
            light_theme: self.ui_state.light_theme,
            start_on_scan: self.ui_state.start_on_scan,
        };
        let actions = bar.ui(ui);
        self.apply(actions);
    }
}
