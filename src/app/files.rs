//! The look's files: open, save, save as, import, export, the
//! unsaved-changes guard, where each file dialog starts and what it shows,
//! the results of the background jobs (analysis, environment loads,
//! exports) as they come in, the material-albedo prompt's answers for a
//! look opened or imported, and the autosave and its recovery
//! (`autosave.rs` writes and finds the files).

use super::*;

impl EditorApp {
    /// Imports the engine file at `path` as a new, unsaved look (the first
    /// of several, with a note), keeping the file's own fields for the
    /// Engines readout.
    pub fn import_now(&mut self, path: &Path) {
        match crate::export::import_file(path, &crate::export::ImportOptions::default()) {
            Ok(mut looks) if !looks.is_empty() => {
                let more = looks.len() - 1;
                let first = looks.remove(0);
                self.guarded(Pending::New(Box::new(first.preset.clone())));
                self.say(if more > 0 {
                    format!(
                        "Imported \"{}\" from {} ({more} more profile(s) in the file: `scatterlab import FILE --out DIR` writes them all)",
                        first.preset.name,
                        path.display()
                    )
                } else {
                    format!(
                        "Imported \"{}\" from {} ({})",
                        first.preset.name,
                        path.display(),
                        first.kind
                    )
                });
                self.profile.imported = Some((path.to_owned(), first));
            }
            Ok(_) => self.say(format!("Error: {}: no look in the file", path.display())),
            Err(e) => self.say(format!("Error: {e}")),
        }
    }

    /// Opens `path` now (the caller has dealt with unsaved changes).
    pub fn open_now(&mut self, path: &Path) {
        match Preset::load(path) {
            Ok(p) => {
                let before = self.a_albedo();
                self.doc = Document::new(p, Some(path.to_owned()));
                self.ui_state.add_recent(path);
                self.say(format!("Opened {}", path.display()));
                let map_mean = self.colour_map_mean();
                self.windows
                    .albedo
                    .ask_look(&self.doc.preset, before, map_mean);
            }
            Err(e) => self.say(format!("Error: {e}")),
        }
    }

    /// Saves to the document's file (or asks where).
    pub fn save(&mut self) {
        match self.doc.path.clone() {
            Some(p) => self.save_as(&p),
            None => self.open_dialog(DialogKind::SaveAs),
        }
    }

    pub fn save_as(&mut self, path: &Path) {
        match self.doc.save_as(path) {
            Ok(()) => {
                self.ui_state.add_recent(path);
                self.say(format!("Saved {}", path.display()));
                // Save, then what the unsaved-changes prompt was for.
                if let Some(action) = self.dialogs.after_save.take() {
                    self.run_pending(action);
                }
            }
            Err(e) => {
                // Not saved: the quit (or open) it was for does not happen,
                // now or after some later save.
                self.dialogs.after_save = None;
                self.say(format!("Error: {e}"));
            }
        }
    }

    /// Whether the editor may close now (Quit answered).
    pub fn close_allowed(&self) -> bool {
        self.allow_close
    }

    /// Runs `action` now, or asks first if there are unsaved changes.
    pub(super) fn guarded(&mut self, action: Pending) {
        if self.doc.is_dirty() {
            self.windows.unsaved.pending = Some(action);
        } else {
            self.run_pending(action);
        }
    }

    pub(super) fn run_pending(&mut self, action: Pending) {
        match action {
            Pending::Open(p) => self.open_now(&p),
            Pending::New(p) => {
                self.say(format!("New look from \"{}\"", p.name));
                let before = self.a_albedo();
                self.doc = Document::new(*p, None);
                let map_mean = self.colour_map_mean();
                self.windows
                    .albedo
                    .ask_look(&self.doc.preset, before, map_mean);
            }
            Pending::Quit => self.allow_close = true,
        }
    }

    /// The folder a dialog of `kind` starts in: the folder of the current
    /// file of that kind (the look for presets, the mesh, the environment
    /// map, the slot's map, B), else where this kind was last used, else
    /// the look's folder, else the artist's documents folder, never the
    /// process's working directory. A dialog that writes never starts in
    /// the shipped presets' folder (a look opened from there is saved
    /// elsewhere).
    pub(super) fn dialog_folder(&self, kind: &DialogKind) -> PathBuf {
        let writes = kind.writes();
        let current: Option<PathBuf> = match kind {
            DialogKind::Open | DialogKind::SaveAs | DialogKind::PresetFolder => {
                self.doc.path.clone()
            }
            DialogKind::CompareB => match &self.ui_state.compare_b {
                CompareB::Preset(p) => Some(p.clone()),
                _ => self.doc.path.clone(),
            },
            DialogKind::Mesh => self.mesh_path().map(Path::to_path_buf),
            DialogKind::Environment => self.ui_state.environment_file.clone(),
            DialogKind::Reference => self.reference_path().map(Path::to_path_buf),
            DialogKind::Map(k) => self.mesh_path().map(|m| {
                self.ui_state
                    .meshes
                    .get(m)
                    .and_then(|s| s.maps[*k].path.clone())
                    .unwrap_or_else(|| m.to_path_buf())
            }),
            DialogKind::Import
            | DialogKind::Export(_)
            | DialogKind::SaveImage
            | DialogKind::SaveTurntable
            | DialogKind::SaveStill => None,
        };
        let usable = |d: &Path| !(writes && library::is_shipped_presets(d));
        let folder_of = |p: &Path| {
            p.parent()
                .filter(|d| !d.as_os_str().is_empty() && d.is_dir() && usable(d))
                .map(Path::to_path_buf)
        };
        current
            .as_deref()
            .and_then(folder_of)
            .or_else(|| {
                self.ui_state
                    .folders
                    .get(kind.folder_key())
                    .filter(|d| d.is_dir() && usable(d))
                    .cloned()
            })
            .or_else(|| self.doc.path.as_deref().and_then(folder_of))
            .or_else(documents_folder)
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_default()
    }

    pub(super) fn open_dialog(&mut self, kind: DialogKind) {
        let dir = self.dialog_folder(&kind);
        let name = match &kind {
            // The look's own file name where it has one (a look opened
            // from Skin1's file saves as that name, not a second spelling).
            DialogKind::SaveAs => self
                .doc
                .path
                .as_deref()
                .and_then(Path::file_name)
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_else(|| {
                    format!(
                        "{}.{}",
                        file_stem(&self.doc.preset.name),
                        crate::settings::PRESET_EXTENSION
                    )
                }),
            DialogKind::Export(f) => {
                crate::export::export_file_name(&file_stem(&self.doc.preset.name), *f)
            }
            DialogKind::SaveImage => format!(
                "{}_{}.png",
                file_stem(&self.doc.preset.name),
                self.doc.preset.rendering.method.id()
            ),
            DialogKind::SaveStill => format!(
                "{}_{}_{}x{}.png",
                file_stem(&self.doc.preset.name),
                self.doc.preset.rendering.method.id(),
                self.ui_state.still.width,
                self.ui_state.still.height
            ),
            DialogKind::SaveTurntable => format!(
                "{}_{}_turntable.gif",
                file_stem(&self.doc.preset.name),
                self.doc.preset.rendering.method.id()
            ),
            _ => String::new(),
        };
        let format = match kind {
            DialogKind::Export(format) => Some(format),
            _ => None,
        };
        let mesh = self.mesh_path().map(Path::to_path_buf);
        self.dialogs
            .work_out_export_notes(&self.doc.preset, format, mesh.as_deref(), &self.waker);
        self.show_dialog(kind, &dir, &name);
    }

    /// Opens the file dialog for `kind` in `dir` with `name` in its file
    /// field.
    pub(super) fn show_dialog(&mut self, kind: DialogKind, dir: &Path, name: &str) {
        let exts = kind.extensions();
        let picker = if kind == DialogKind::PresetFolder {
            egui_file::FileDialog::select_folder()
        } else if kind.writes() {
            egui_file::FileDialog::save_file()
        } else {
            egui_file::FileDialog::open_file()
        };
        let mut picker = picker
            .id(egui::Id::unique("scatterlab_file_dialog"))
            .title(&kind.title())
            .initial_path(dir)
            .default_filename(name)
            .anchor(
                egui::Align2::CENTER_CENTER,
                // An export's notes stand to the right.
                [
                    if matches!(kind, DialogKind::Export(_)) {
                        -180.0
                    } else {
                        0.0
                    },
                    0.0,
                ],
            )
            .default_size([620.0, 400.0])
            .keep_on_top(true)
            .show_rename(false)
            .show_new_folder(kind.writes())
            .open_button_text(
                if kind == DialogKind::PresetFolder {
                    "Add this folder"
                } else {
                    "Open"
                }
                .into(),
            )
            .file_label_text("File name:".into())
            .show_files_filter(Box::new(move |p: &Path| {
                p.extension()
                    .and_then(|x| x.to_str())
                    .is_some_and(|x| exts.contains(&x.to_ascii_lowercase().as_str()))
            }));
        picker.open();
        self.dialogs.dialog = Some(FileDialog {
            kind,
            picker,
            notes: None,
        });
    }

    /// Test hook: points the open file dialog at `path` as an artist would
    /// by typing its folder into the folder field and its name into the
    /// file-name field (AccessKit cannot commit egui_file's folder field,
    /// which acts on losing focus). Returns false without an open dialog.
    pub fn dialog_goto(&mut self, path: &Path) -> bool {
        let Some(d) = self.dialogs.dialog.take() else {
            return false;
        };
        let (dir, name) = if path.is_dir() {
            (path.to_path_buf(), String::new())
        } else {
            (
                path.parent().map(Path::to_path_buf).unwrap_or_default(),
                path.file_name()
                    .map(|n| n.to_string_lossy().into_owned())
                    .unwrap_or_default(),
            )
        };
        let notes = d.notes;
        self.show_dialog(d.kind, &dir, &name);
        if let Some(d) = self.dialogs.dialog.as_mut() {
            d.notes = notes;
        }
        true
    }

    /// The open file dialog's folder (UI tests).
    pub fn dialog_folder_shown(&self) -> Option<PathBuf> {
        self.dialogs
            .dialog
            .as_ref()
            .map(|d| d.picker.directory().to_path_buf())
    }

    /// Whether background work is under way (the status bar's spinner):
    /// exports, an environment map, the analysis.
    pub(super) fn busy(&self) -> bool {
        self.jobs.busy() || self.analysis_busy()
    }

    /// Starts an export on its own thread (table bakes take seconds).
    pub fn export(&mut self, format: Format, out: PathBuf) {
        let look = (self.doc.preset.clone(), self.doc.path.clone());
        let on_mesh = self.mesh_path().map(|p| {
            let settings = self.ui_state.meshes.get(p).cloned().unwrap_or_default();
            (p.to_path_buf(), settings, self.ui_state.map_colour)
        });
        self.jobs.export(look, format, out, on_mesh, &self.waker);
        self.say(format!("Exporting {} …", format.id()));
    }

    /// Takes in the analysis thread's result (fits, tables, a slow
    /// model's curves).
    pub(super) fn poll_analysis(&mut self) {
        let Some(taken) = self.profile.take_analysis(&self.doc.preset.profile) else {
            return;
        };
        self.log_line(format_args!("analysis result"));
        // A panic the thread survived (`Background`): said as a notice as
        // well as in the plot.
        if let Err(e) = taken {
            eprintln!("warning: {e}");
            self.say(format!("Warning: {e}"));
        }
    }

    /// Takes in what the background threads finished: the analysis (fits,
    /// tables, a slow model's curves), an environment map, exports.
    pub(super) fn poll_workers(&mut self) {
        self.poll_analysis();
        self.poll_environment();
        for r in self.jobs.finished_exports() {
            self.say(match r {
                Ok(paths) => format!(
                    "Exported {}",
                    paths
                        .iter()
                        .map(|p| p.display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                Err(e) => format!("Error: {e}"),
            });
        }
    }
}

/// The material-albedo prompt's answers ([`windows::albedo`]).
impl EditorApp {
    /// The prompt's other button: "Use A's for now" for B (A's, asked),
    /// "Keep albedo 1" for a document (said).
    pub(super) fn decline_albedo_prompt(&mut self, p: windows::albedo::AlbedoPrompt) {
        if p.target == windows::albedo::PromptFor::CompareB {
            self.ui_state.b_material_albedo = crate::settings::albedo::MaterialAlbedo::LookA;
            self.ui_state.b_material_albedo_asked = true;
        } else {
            self.say(format!(
                "\"{}\" keeps its file's albedo 1 (a white head): set Albedo to the material's",
                p.name
            ));
        }
    }

    /// Applies the prompt's answer.
    pub(super) fn answer_albedo_prompt(&mut self, p: windows::albedo::AlbedoPrompt) {
        let map_mean = self.colour_map_mean();
        match p.target {
            windows::albedo::PromptFor::CompareB => {
                self.ui_state.b_material_albedo = p.choice;
                self.ui_state.b_material_albedo_asked = true;
                self.say(format!(
                    "B \"{}\" is drawn with {} albedo (its engine keeps the albedo in the material); change it beside B",
                    p.name,
                    p.choice.label()
                ));
            }
            windows::albedo::PromptFor::Look => {
                let rgb = crate::settings::albedo::resolve(p.choice, p.a_albedo, map_mean);
                let as_read = self.doc.preset.clone();
                let preset = &mut self.doc.preset;
                if !crate::settings::albedo::set_albedo(preset, rgb) {
                    return;
                }
                preset.rendering.albedo_in_material = false;
                let what = match (p.choice, map_mean) {
                    (crate::settings::albedo::MaterialAlbedo::DefaultSkin, _) => {
                        "the default skin's, Unreal's default SurfaceAlbedo".to_string()
                    }
                    (crate::settings::albedo::MaterialAlbedo::LookA, _) => {
                        "the look open before it".to_string()
                    }
                    (crate::settings::albedo::MaterialAlbedo::Map, Some(_)) => {
                        "the head's colour map's mean".to_string()
                    }
                    (crate::settings::albedo::MaterialAlbedo::Map, None) => {
                        "the look open before it (no colour map)".to_string()
                    }
                    (crate::settings::albedo::MaterialAlbedo::Typed(_), _) => {
                        "typed at import".to_string()
                    }
                };
                preset.description = format!(
                    "{} Albedo {:.4}/{:.4}/{:.4} from the material ({what}): its engine keeps the albedo in the material, and the file has none.",
                    preset.description, rgb[0], rgb[1], rgb[2]
                )
                .trim()
                .to_owned();
                if p.choice == crate::settings::albedo::MaterialAlbedo::Map && map_mean.is_some() {
                    self.ui_state.map_colour = crate::settings::albedo::MapColour::Map;
                }
                // An import (no file yet) starts as what was chosen; a
                // preset file that says "albedo in the material" keeps its
                // own as the undo step and shows as changed.
                let undo = if self.doc.path.is_none() {
                    self.doc = Document::new(self.doc.preset.clone(), None);
                    "Keep albedo 1 in the prompt draws the file's white"
                } else {
                    self.doc.commit();
                    "undo gives back the file's albedo 1"
                };
                // The Engines panel's readout of the file stays: this is
                // the look imported, with its material's albedo.
                if let Some((_, look)) = &mut self.profile.imported {
                    if look.preset == as_read {
                        look.preset = self.doc.preset.clone();
                    }
                }
                self.say(format!(
                    "\"{}\" drawn with albedo {:.3}/{:.3}/{:.3} ({what}); {undo}",
                    p.name, rgb[0], rgb[1], rgb[2]
                ));
            }
        }
    }
}

/// Autosave and recovery ([`autosave`]).
impl EditorApp {
    /// Autosaves the look into `data_dir` from now on, and offers back
    /// what an editor killed or crashed there left.
    pub fn with_autosave(mut self, data_dir: &Path) -> Self {
        let autosave = autosave::Autosave::new(data_dir);
        if let Some(first) = autosave.unreadable.first() {
            self.say(format!(
                "Warning: {} recovery file(s) an earlier editor left cannot be read and were left in place (open them in a text editor; the look is the preset inside): {first}",
                autosave.unreadable.len()
            ));
        }
        let mut autosave = autosave;
        self.windows.recovery.found = autosave.found.take();
        self.autosave = Some(autosave);
        self
    }

    /// This editor's autosave file, if autosave is on.
    pub fn autosave_file(&self) -> Option<PathBuf> {
        self.autosave.as_ref().map(|a| a.file().to_owned())
    }

    /// Writes the autosave now if anything unsaved changed (tests; the
    /// editor itself calls it every frame and writes at most every
    /// [`autosave::AUTOSAVE_SECONDS`]).
    pub fn autosave_now(&mut self) {
        self.autosave_tick(None, true);
    }

    /// The frame's autosave check; with `ctx`, a frame is asked for at the
    /// next deadline while something is left to write, so the write does
    /// not wait for input.
    pub(super) fn autosave_tick(&mut self, ctx: Option<&egui::Context>, force: bool) {
        let mesh = self.mesh_path().map(Path::to_path_buf);
        let Some(a) = self.autosave.as_mut() else {
            return;
        };
        let now = autosave::Snapshot {
            doc: &self.doc,
            ui: &self.ui_state,
            mesh: mesh.as_deref(),
        };
        let ticked = a.tick(now, force);
        if let Some(message) = ticked.message {
            self.say(message);
        }
        if let (Some(ctx), Some(after)) = (ctx, ticked.wake_in) {
            ctx.request_repaint_after(after);
        }
    }

    /// A clean quit: nothing to recover.
    pub(super) fn autosave_clear(&mut self) {
        if let Some(a) = self.autosave.as_mut() {
            a.clear();
        }
    }

    /// Puts a recovered look back: the document as it was with its undo
    /// history (what it differs from is what was saved, so it shows as
    /// unsaved), the mesh with its units and maps, and the view and
    /// compare state.
    fn restore(&mut self, r: autosave::Recovery) {
        let mut history = r.history;
        if history.undo.is_empty() && history.saved.is_none() {
            // An older recovery file: one step back to the preset file
            // (or the default), as those restored.
            history.undo.push(
                r.path
                    .as_deref()
                    .and_then(|p| Preset::load(p).ok())
                    .unwrap_or_default(),
            );
        }
        self.doc = Document::restored(r.preset, r.path, history);
        self.restore_mesh(r.mesh.map(|m| (m.path, m.settings)));
        self.ui_state.view = r.view;
        self.ui_state.compare = r.compare;
        self.ui_state.compare_b = r.compare_b;
        self.ui_state.split = r.split;
        self.say(format!(
            "Restored \"{}\" as it was when the editor stopped; save it to keep it",
            self.doc.preset.name
        ));
    }

    /// The recovery prompt's answer: restore the look an earlier editor
    /// left (and write it under this editor's name before the old file
    /// goes: a crash in between loses nothing), or discard its file.
    pub(super) fn answer_recovery(
        &mut self,
        ctx: Option<&egui::Context>,
        found: autosave::Found,
        restore: bool,
    ) {
        if restore {
            self.restore(found.recovery);
            self.autosave_tick(ctx, true);
        }
        let _ = std::fs::remove_file(&found.file);
    }
}

/// The artist's documents folder: `XDG_DOCUMENTS_DIR` (the environment,
/// else `user-dirs.dirs` in the XDG config folder, as xdg-user-dirs writes
/// it), else `~/Documents`, else the home folder; `None` without a home.
pub(super) fn documents_folder() -> Option<PathBuf> {
    let home = std::env::var_os("HOME")
        .or_else(|| std::env::var_os("USERPROFILE"))
        .map(PathBuf::from)?;
    let expand = |v: &str| -> PathBuf {
        let v = v.trim().trim_matches('"');
        match v.strip_prefix("$HOME") {
            Some(rest) => home.join(rest.trim_start_matches('/')),
            None => PathBuf::from(v),
        }
    };
    let from_env = std::env::var("XDG_DOCUMENTS_DIR").ok().map(|v| expand(&v));
    let from_file = || {
        let config = std::env::var_os("XDG_CONFIG_HOME")
            .map(PathBuf::from)
            .unwrap_or_else(|| home.join(".config"));
        std::fs::read_to_string(config.join("user-dirs.dirs"))
            .ok()?
            .lines()
            .find_map(|l| l.trim().strip_prefix("XDG_DOCUMENTS_DIR=").map(&expand))
    };
    from_env
        .or_else(from_file)
        .filter(|d| d.is_dir())
        .or_else(|| Some(home.join("Documents")).filter(|d| d.is_dir()))
        .or(Some(home))
}
