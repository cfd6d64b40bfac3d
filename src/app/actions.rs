//! `EditorApp::apply`: every [`Action`] a window, toolbar or menu returns
//! is performed here, in one place (issue 51), so that no window writes
//! the document or another window's state.

use super::windows::reference::PickInto;
use super::windows::Action;
use super::windows::Window;
use super::*;

impl EditorApp {
    /// Performs `actions` in order.
    pub(super) fn apply(&mut self, actions: Vec<Action>) {
        for action in actions {
            match action {
                Action::SetView(v) => self.ui_state.view = v,
                Action::ApplyRig(rig) => {
                    if !rig.apply(&mut self.ui_state.view) {
                        // The HDR rig with no map loaded: ask for one; the
                        // map lights the head once it has loaded.
                        self.view.hdr_rig_pending = true;
                        self.open_dialog(DialogKind::Environment);
                    }
                }
                Action::ChooseEnvironmentFile => self.open_dialog(DialogKind::Environment),
                Action::LoadEnvironment(path) => self.load_environment(path),
                Action::OpenWindow(title) => {
                    self.windows.open(title);
                }
                Action::Say(line) => self.say(line),
                Action::AnswerUnsaved(p, answer) => self.answer_unsaved(p, answer),
                Action::AnswerRecovery(found, restore) => {
                    self.answer_recovery(None, *found, restore)
                }
                Action::AnswerOverwrite(o, replace) => self.answer_overwrite(o, replace),
                Action::AnswerAlbedo(p, true) => self.answer_albedo_prompt(p),
                Action::AnswerAlbedo(p, false) => self.decline_albedo_prompt(p),
                Action::Undo => self.doc.undo(),
                Action::Redo => self.doc.redo(),
                Action::Save => self.save(),
                Action::ScannedHead => {
                    if !self.open_scanned_head() {
                        self.say("Error: the head scan is not here (assets/scan/ of the repository): use Load mesh…");
                    }
                }
                Action::ProceduralHead => self.load_mesh(None),
                Action::Quit => self.guarded(Pending::Quit),
                Action::SetInterface { scale, light_theme } => {
                    (self.ui_state.ui_scale, self.ui_state.light_theme) = (scale, light_theme);
                }
                Action::SetStartOnScan(on) => self.ui_state.start_on_scan = on,
                Action::SetCompare(c) => self.set_compare(c),
                Action::AskBAlbedoColour => self.ask_b_albedo_colour(),
                Action::SetRefineToTruth(on) => self.ui_state.refine_to_truth = on,
                Action::OpenDialog(kind) => self.open_dialog(kind),
                Action::SetStill(s) => self.ui_state.still = s,
                Action::SetTurntable(s) => self.ui_state.turntable = s,
                Action::BrowsePresets => {
                    let wake = self.waker.as_fn();
                    self.windows
                        .browser
                        .open(&self.ui_state.preset_folders, wake);
                }
                Action::SetPresetFolders(folders) => {
                    self.ui_state.preset_folders = folders;
                    let wake = self.waker.as_fn();
                    self.windows
                        .browser
                        .relist(&self.ui_state.preset_folders, wake);
                }
                Action::OpenPreset(path) => self.guarded(Pending::Open(path)),
                Action::NewLook(p) => self.guarded(Pending::New(p)),
                Action::SetMeshSettings(mesh, settings) => {
                    self.ui_state.meshes.insert(mesh, settings);
                }
                Action::SetLook(p) => self.doc.replace(*p),
                Action::EditLook(p) => self.doc.preset = *p,
                Action::ComparePair([a, b]) => {
                    self.guarded(Pending::Open(a));
                    self.ui_state.compare_b = state::CompareB::Preset(b);
                    self.ui_state.compare = state::CompareMode::SideBySide;
                }
                Action::PickColour(rgb, into) => {
                    let said = match self.pick_colour(rgb, into) {
                        Ok(s) => {
                            self.windows.reference.set_picked(rgb);
                            s
                        }
                        Err(e) => format!("Error: eyedropper: {e}"),
                    };
                    self.say(said);
                }
            }
        }
    }

    /// Draws the windows of [`windows::Windows`] and applies what they ask.
    pub(super) fn windows_ui(&mut self, ctx: &egui::Context) {
        let view = windows::WindowView {
            view: &self.ui_state.view,
            environment_file: self.ui_state.environment_file.as_deref(),
            still: &self.ui_state.still,
            turntable: &self.ui_state.turntable,
            preset_folders: &self.ui_state.preset_folders,
            doc_path: self.doc.path.as_deref(),
            mesh: self.meshes.mesh.as_deref(),
            mesh_info: self.meshes.mesh_info,
            meshes: &self.ui_state.meshes,
            waker: &self.waker,
            look_name: &self.doc.preset.name,
            colour_map_mean: self.meshes.colour_map_mean(),
            viewport_rect: self.layout.viewport_rect,
        };
        let actions = self.windows.show(ctx, &view);
        self.apply(actions);
    }

    /// Starts the still to `out` from the viewport's current request.
    pub(super) fn start_still(&mut self, out: PathBuf) {
        match self.viewport().request() {
            Some(base) => {
                self.windows
                    .still
                    .start(base, self.ui_state.still, out, self.waker.as_fn())
            }
            None => self.say(format!(
                "Error: {}: no viewport view to render (wait for the head to appear)",
                out.display()
            )),
        }
    }

    /// Starts a turntable to `gif` from the viewport's current request
    /// (its window polls it while it runs).
    pub(super) fn start_turntable(&mut self, gif: PathBuf) {
        match self.viewport().request() {
            Some(base) => {
                self.windows
                    .turntable
                    .start(base, self.ui_state.turntable, gif, self.waker.as_fn())
            }
            None => self.say(format!(
                "Error: {}: no viewport to turn (wait for the head to appear)",
                gif.display()
            )),
        }
    }

    /// Whether a still is rendering (UI tests).
    pub fn still_running(&self) -> bool {
        self.windows.still.running()
    }

    /// Frames done and in all of the turntable rendering (UI tests).
    pub fn turntable_progress(&self) -> Option<(u32, u32)> {
        self.windows.turntable.progress()
    }

    /// Writes `rgb` (linear) into the field `into`, as an undoable edit.
    /// Returns what it did, for the status bar.
    pub fn pick_colour(&mut self, rgb: [f64; 3], into: PickInto) -> Result<String, String> {
        let p = &mut self.doc.preset;
        match into {
            PickInto::Albedo => {
                if !crate::settings::albedo::set_albedo(p, rgb) {
                    return Err(
                        "this model has no albedo field (Burley's has): pick into the transmission tint, or switch the model".into(),
                    );
                }
            }
            PickInto::TransmissionTint => p.rendering.transmission_tint = rgb,
        }
        self.doc.commit();
        Ok(format!(
            "{} picked: {:.4} / {:.4} / {:.4} (linear, the reference's 5×5 mean)",
            into.label(),
            rgb[0],
            rgb[1],
            rgb[2]
        ))
    }

    /// Loads `path` as the reference image.
    pub(super) fn load_reference(&mut self, path: PathBuf) {
        let said = self.windows.reference.load(path);
        self.say(said);
    }

    /// The reference image's path (UI tests).
    pub fn reference_path(&self) -> Option<&Path> {
        self.windows.reference.path()
    }

    /// Test hook: keep the preset browser's thumbnails in `dir` instead.
    pub fn set_thumbnail_dir(&mut self, dir: PathBuf) {
        self.windows.browser.thumbnail_dir = Some(dir);
    }

    /// The open preset browser (UI tests).
    pub fn preset_browser(&self) -> Option<&super::windows::browser::PresetBrowser> {
        self.windows.browser.browser()
    }

    /// Opens a budget report's merges in their window.
    pub fn open_budget(&mut self, pairs: super::windows::budget::BudgetPairs) {
        let said = self.windows.budget.load(pairs);
        self.say(said);
    }

    /// The compare toolbar's settings: the mode, B, what is shown and the
    /// difference view's scale (remembered), A/B alone and "before".
    fn set_compare(&mut self, c: compare::CompareSettings) {
        let u = &mut self.ui_state;
        (u.compare, u.compare_b, u.split) = (c.mode, c.b, c.split);
        (u.difference_scale, u.difference_auto) = (c.difference_scale, c.difference_auto);
        if c.b_albedo != u.b_material_albedo {
            u.b_material_albedo = c.b_albedo;
            u.b_material_albedo_asked = true;
        }
        (self.view.ab, self.view.show_before) = (c.ab, c.show_before);
    }

    /// The mesh the viewport is asked to show (`None`: the default head).
    pub fn mesh_path(&self) -> Option<&Path> {
        self.meshes.mesh.as_deref()
    }

    /// The loaded mesh's size and framing, once the viewport has it.
    pub fn mesh_info(&self) -> Option<viewport::MeshInfo> {
        self.meshes.mesh_info
    }

    /// The mesh whose units prompt is open.
    pub fn units_prompt_for(&self) -> Option<&Path> {
        self.mesh_path().filter(|_| self.windows.units.is_open())
    }

    /// Whether the Maps window's previews are computed (UI tests).
    pub fn maps_preview_ready(&self) -> bool {
        self.windows.maps.preview_ready()
    }

    /// Opens the shipped head scan (Lee Perry-Smith, CC BY 3.0:
    /// assets/scan/ATTRIBUTION.md) at 0.0462 m/unit with its colour and
    /// normal maps, flipped as they are made (V up), in the map's own
    /// colour (the Look panel offers it tinted by the look's albedo, for
    /// looks to differ on it); units and maps the artist has set for it
    /// before are kept. False where the files are missing (a copy of the
    /// binary without the repository).
    pub fn open_scanned_head(&mut self) -> bool {
        let Some((path, settings)) = state::scanned_head() else {
            return false;
        };
        self.ui_state.meshes.entry(path.clone()).or_insert(settings);
        self.load_mesh(Some(path));
        true
    }

    /// Shows the mesh at `path` in the viewport, or the default head.
    pub(super) fn load_mesh(&mut self, path: Option<PathBuf>) {
        match &path {
            Some(p) => self.say(format!("Loading mesh {} …", p.display())),
            None if self.meshes.mesh.is_some() => self.say("Loading the default head …"),
            None => {}
        }
        self.meshes.mesh = path;
    }

    /// Shows `mesh` in the viewport (`edit --mesh`), with its units if
    /// given: they are remembered for the file as the units prompt would.
    pub fn open_mesh(&mut self, mesh: MeshArg) {
        if let Some(m) = mesh.metres_per_unit {
            self.ui_state
                .meshes
                .entry(mesh.path.clone())
                .or_default()
                .metres_per_unit = m;
        }
        self.load_mesh(Some(mesh.path));
    }
}
