//! The file dialog (`egui_file`), what its OK does, the answers of the
//! unsaved-changes and overwrite prompts (the prompts themselves are
//! windows: `windows/unsaved.rs`, `windows/overwrite.rs`), the keyboard
//! (Escape's topmost window, then `keys.rs`'s shortcuts), the viewport's
//! frame saved as an image, and an HDR map chosen (or remembered, or
//! dropped) loaded on its thread and taken in when it arrives.

use super::windows::unsaved::Unsaved;
use super::windows::Window;
use super::*;

impl EditorApp {
    /// Whether the unsaved-changes prompt is waiting for an answer.
    pub fn prompt_open(&self) -> bool {
        self.windows.unsaved.is_open()
    }

    /// Whether a modal prompt is up: unsaved changes, replace existing
    /// files, or recover an earlier editor's work.
    pub fn modal_prompt_open(&self) -> bool {
        self.windows.modal_open() || self.autosave.as_ref().is_some_and(|a| a.found.is_some())
    }

    /// Whether a file dialog or a modal prompt is up.
    pub(super) fn dialog_up(&self) -> bool {
        self.dialogs.dialog.is_some() || self.modal_prompt_open()
    }

    /// The titles of the open windows Escape can close.
    fn open_windows(&self) -> Vec<&'static str> {
        self.windows.open_titles()
    }

    pub(super) fn dialogs_ui(&mut self, ctx: &egui::Context) {
        // A window opened (again) since the last frame comes to the front
        // (egui keeps a reopened window where it was in the stack), so
        // that Escape closes what the artist opened last.
        let open = self.open_windows();
        self.dialogs.bring_new_to_front(ctx, open);
        self.file_dialog_ui(ctx);
    }

    /// Closes the open window that is drawn on top (those of
    /// `windows::Windows`, the preset browser, Mesh maps, Save turntable,
    /// Save image at size, Reference, Budget merges); whether
    /// one was open. egui keeps its windows' layers in
    /// drawing order, each named by the window's title.
    pub(super) fn close_topmost_window(&mut self, ctx: &egui::Context) -> bool {
        let open = self.open_windows();
        if open.is_empty() {
            return false;
        }
        let order: Vec<egui::LayerId> = ctx.memory(|m| m.layer_ids().collect());
        let top = order
            .iter()
            .rev()
            .find_map(|l| open.iter().find(|t| l.id == window_id(t)).copied())
            .unwrap_or(open[open.len() - 1]);
        self.windows.close(top)
    }

    /// Writes the viewport's frame, as shown (a comparison with both sides,
    /// the tonemapped 8-bit pixels), to `path` as a PNG, atomically.
    pub fn save_image(&mut self, path: &Path) {
        let Some((frame, _)) = &self.view.last_frame else {
            self.say(format!(
                "Error: {}: no viewport frame to save yet (wait for the head to appear)",
                path.display()
            ));
            return;
        };
        let mut png = Vec::new();
        let written = frame
            .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
            .map_err(|e| e.to_string())
            .and_then(|()| crate::fsutil::write_atomic(path, &png).map_err(|e| e.to_string()));
        self.say(match written {
            Ok(()) => {
                let state = match self.view.quality {
                    Some(viewport::Quality::Converged { .. }) => "converged",
                    _ => "not converged yet: a preview",
                };
                format!(
                    "Saved image {} ({}×{}, {}, {state})",
                    path.display(),
                    frame.width(),
                    frame.height(),
                    self.view.frame_info.split(" · ").next().unwrap_or("")
                )
            }
            Err(e) => format!("Error: {}: {e}", path.display()),
        });
    }

    /// An HDR map has loaded: the HDR light rig that asked for it, if one
    /// did, lights the head now.
    pub(super) fn environment_loaded(&mut self) {
        if std::mem::take(&mut self.view.hdr_rig_pending) {
            state::LightRig::Hdr.apply(&mut self.ui_state.view);
        }
    }

    /// No HDR map came (the dialog cancelled, the map refused): the HDR
    /// light rig that asked for one is off.
    pub(super) fn environment_not_loaded(&mut self) {
        self.view.hdr_rig_pending = false;
    }

    /// The keyboard ([`keys::shortcuts`]), none while a modal prompt is
    /// up: it asked about the look as it is, so no key may change the look
    /// under it. Escape in a field being typed into or in an open list is
    /// theirs (it cancels the edit, closes the list); otherwise it closes
    /// the topmost window, and only with none open goes back to the
    /// compare mode's view.
    pub(super) fn keys(&mut self, ctx: &egui::Context) {
        use egui::{Key, Modifiers};
        if self.modal_prompt_open() {
            return;
        }
        let free = ctx.memory(|m| m.focused().is_none());
        let escape_taken = ctx.input(|i| i.key_pressed(Key::Escape))
            && free
            && !egui::Popup::is_any_open(ctx)
            && self.close_topmost_window(ctx);
        if escape_taken {
            ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::Escape));
        }
        let view = keys::KeysView {
            has_before: self.doc.before_last_edit().is_some(),
            comparing: self.ui_state.compare != CompareMode::Off,
            ab: self.view.ab,
            escape_taken,
        };
        let actions = keys::shortcuts(ctx, &view);
        self.apply(actions);
    }

    /// The unsaved-changes prompt's answer for `pending`: Save (Save As
    /// first for a look without a file, then carry on), Discard or Cancel.
    pub(super) fn answer_unsaved(&mut self, pending: Pending, answer: Unsaved) {
        match answer {
            Unsaved::Save if self.doc.path.is_none() => {
                self.dialogs.after_save = Some(pending);
                self.open_dialog(DialogKind::SaveAs);
            }
            Unsaved::Save => {
                self.save();
                if !self.doc.is_dirty() {
                    self.run_pending(pending);
                }
            }
            Unsaved::Discard => self.run_pending(pending),
            Unsaved::Cancel => {}
        }
    }

    /// The open file dialog (`egui_file`): folders first, then the files
    /// of this kind; an export's notes in a window above it.
    pub(super) fn file_dialog_ui(&mut self, ctx: &egui::Context) {
        let Some(mut dialog) = self.dialogs.dialog.take() else {
            return;
        };
        if let Some(notes) = self
            .dialogs
            .export_notes
            .as_ref()
            .and_then(|rx| rx.try_recv().ok())
        {
            dialog.notes = Some(notes);
            self.dialogs.export_notes = None;
        }
        if let DialogKind::Export(f) = dialog.kind {
            // Beside the dialog (shifted left for it), not under it.
            egui::Window::new("Export notes")
                .id(egui::Id::unique("scatterlab_export_notes"))
                .anchor(egui::Align2::RIGHT_CENTER, [-8.0, 0.0])
                .default_width(330.0)
                .max_width(330.0)
                .collapsible(false)
                .resizable(false)
                .show(ctx, |ui| {
                    ui.strong(f.name());
                    ui.label(f.description());
                    ui.separator();
                    match &dialog.notes {
                        Some(notes) => {
                            for n in notes {
                                ui.label(n);
                            }
                        }
                        None => {
                            ui.horizontal(|ui| {
                                super::report::spinner(ui);
                                ui.label("Estimating how closely the target holds this look …");
                            });
                        }
                    }
                });
        }
        let state = dialog.picker.show(ctx).state();
        let mut close = false;
        match state {
            egui_file::State::Selected => {
                close = true;
                if let Some(path) = dialog.picker.path().map(Path::to_path_buf) {
                    self.accept_dialog(&mut dialog, path, &mut close);
                }
            }
            egui_file::State::Open => {}
            egui_file::State::Cancelled | egui_file::State::Closed => {
                close = true;
                if dialog.kind == DialogKind::SaveAs {
                    // Cancelled: nothing saved, so nothing to carry on with.
                    self.dialogs.after_save = None;
                }
                if dialog.kind == DialogKind::Environment {
                    // No map chosen: the HDR light rig that asked for it is off.
                    self.environment_not_loaded();
                }
            }
        }
        if !close && self.dialogs.dialog.is_none() {
            self.dialogs.dialog = Some(dialog);
        }
    }

    /// Open, Save or Export in a file dialog: remember its folder, then
    /// write, open or load — or first ask, where a Save As or export would
    /// replace files. A folder given as the file to write is opened
    /// instead (never offered for replacing).
    pub(super) fn accept_dialog(
        &mut self,
        dialog: &mut FileDialog,
        mut path: PathBuf,
        close: &mut bool,
    ) {
        if dialog.kind == DialogKind::PresetFolder {
            self.add_preset_folder(path);
            return;
        }
        if path.is_dir() {
            dialog.picker.set_path(&path);
            dialog.picker.open();
            *close = false;
            return;
        }
        if dialog.kind.writes() && path.extension().is_none() {
            // "skin" in the Save dialog means skin.ron.
            if let Some(x) = dialog.kind.extensions().first() {
                path.set_extension(x);
            }
        }
        if let Some(dir) = path.parent().filter(|d| d.is_dir()) {
            self.ui_state
                .folders
                .insert(dialog.kind.folder_key().into(), dir.to_path_buf());
        }
        let existing: Vec<PathBuf> = match &dialog.kind {
            DialogKind::SaveAs | DialogKind::SaveImage => vec![path.clone()],
            DialogKind::SaveStill => {
                super::windows::still::planned_paths(&path, &self.ui_state.still)
            }
            DialogKind::SaveTurntable => {
                super::windows::turntable::planned_paths(&path, &self.ui_state.turntable)
            }
            DialogKind::Export(f) => crate::export::planned_paths(*f, &path),
            _ => Vec::new(),
        }
        .into_iter()
        .filter(|p| p.exists())
        .collect();
        if dialog.kind.writes() && !existing.is_empty() {
            self.windows.overwrite.write = Some(Overwrite {
                kind: dialog.kind.clone(),
                path,
                existing,
                notes: dialog.notes.clone(),
            });
        } else {
            self.write_or_open(dialog.kind.clone(), path.clone(), close);
            if !*close {
                // Kept open (a B that does not load): back to browsing.
                dialog.picker.open();
            }
        }
    }

    /// A folder chosen in the folder dialog, listed in the preset browser
    /// (once) and remembered.
    fn add_preset_folder(&mut self, dir: PathBuf) {
        if !dir.is_dir() {
            self.say(format!(
                "Error: {} is not a folder: choose a folder of .ron presets",
                dir.display()
            ));
            return;
        }
        if let Some(parent) = dir.parent().filter(|d| d.is_dir()) {
            self.ui_state
                .folders
                .insert(DialogKind::PresetFolder.folder_key().into(), parent.into());
        }
        if self.ui_state.preset_folders.contains(&dir) {
            self.say(format!("{} is already listed", dir.display()));
            return;
        }
        let folders = [self.ui_state.preset_folders.clone(), vec![dir]].concat();
        self.apply(vec![super::windows::Action::SetPresetFolders(folders)]);
    }

    /// The overwrite prompt's answer: write, or back to the dialog.
    pub(super) fn answer_overwrite(&mut self, o: Overwrite, replace: bool) {
        if replace {
            let mut close = true;
            self.write_or_open(o.kind, o.path, &mut close);
            return;
        }
        let dir = o.path.parent().map(Path::to_path_buf).unwrap_or_default();
        let name = o
            .path
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_default();
        self.show_dialog(o.kind, &dir, &name);
        if let Some(d) = self.dialogs.dialog.as_mut() {
            d.notes = o.notes;
        }
    }

    /// What a file dialog's OK does with `path`; `close` false keeps the
    /// dialog open (a preset B that does not load).
    pub(super) fn write_or_open(&mut self, kind: DialogKind, path: PathBuf, close: &mut bool) {
        {
            match kind {
                DialogKind::Open => self.guarded(Pending::Open(path)),
                DialogKind::Import => self.import_now(&path),
                DialogKind::SaveAs => self.save_as(&path),
                DialogKind::Export(f) => self.export(f, path),
                DialogKind::CompareB => match super::viewport::load_look(&path) {
                    Ok(b) => {
                        self.ui_state.compare_b = CompareB::Preset(path);
                        self.ask_b_albedo(&b);
                    }
                    Err(e) => {
                        self.say(format!("Error: {e}"));
                        *close = false;
                    }
                },
                DialogKind::Mesh => self.load_mesh(Some(path)),
                DialogKind::SaveImage => self.save_image(&path),
                DialogKind::SaveTurntable => self.start_turntable(path),
                DialogKind::SaveStill => self.start_still(path),
                DialogKind::Environment => self.load_environment(path),
                DialogKind::Reference => self.load_reference(path),
                DialogKind::PresetFolder => self.add_preset_folder(path),
                DialogKind::Map(k) => {
                    if let Some(mesh) = self.mesh_path().map(Path::to_path_buf) {
                        self.ui_state.meshes.entry(mesh).or_default().maps[k].path = Some(path);
                    }
                }
            }
        }
    }

    /// The HDR map remembered from the last run, for its background: its
    /// lighting is remembered (SH), its picture is read again, quietly.
    pub(super) fn reload_background(&mut self) {
        if self.view.background_map.is_some() || self.jobs.loading_environment() {
            return;
        }
        if let Some(p) = self
            .ui_state
            .environment_file
            .clone()
            .filter(|p| p.is_file())
        {
            // Loading makes the map the environment: keep the choice.
            let keep = Some(self.ui_state.view.environment);
            self.jobs.load_environment(p, keep, &self.waker);
        }
    }

    /// Loads an equirectangular HDR map on its own thread and lights the
    /// head with it once it arrives.
    pub fn load_environment(&mut self, path: PathBuf) {
        self.say(format!("Loading environment {} …", path.display()));
        self.jobs.load_environment(path, None, &self.waker);
    }

    /// Takes in an environment map that finished loading: the background
    /// and the lighting, or the error.
    pub(super) fn poll_environment(&mut self) {
        let Some(loaded) = self.jobs.finished_environment() else {
            return;
        };
        match loaded.result {
            Ok((path, sh, bg)) => {
                self.view.background_map = bg.map(|m| viewport::SharedMap(std::sync::Arc::new(m)));
                let v = &mut self.ui_state.view;
                v.environment_map_sh = Some(sh);
                match loaded.keep {
                    // The remembered map read again at start-up: the
                    // artist's choice stays, and nothing is said.
                    Some(env) => v.environment = env,
                    None => {
                        v.environment = state::EnvironmentChoice::Map;
                        self.say(format!("Environment {}", path.display()));
                    }
                }
                self.ui_state.environment_file = Some(path);
                self.environment_loaded();
            }
            Err(e) => {
                self.say(format!("Error: {e}"));
                // The HDR rig that asked for this map is off.
                self.environment_not_loaded();
            }
        }
    }
}

/// The id egui gives a window of this title (`Window::new`:
/// `Id::unique(title.text())`, the title's text as an `Option<Cow<str>>`).
pub(super) fn window_id(title: &str) -> egui::Id {
    egui::Id::unique(Some(std::borrow::Cow::Borrowed(title)))
}
