//! `EditorApp::apply`: every [`Action`] a window, toolbar, panel or key
//! returns is performed here, in one place (issue 51), so that no window
//! writes the document or another window's state; and what the menu bar,
//! the toolbars, the viewport panel and the windows are lent to draw, with
//! what they return applied (a loaded mesh framed, B as it is drawn).

use super::windows::reference::PickInto;
use super::windows::Action;
use super::windows::Window;
use super::*;

impl EditorApp {
    /// Performs `actions` in order.
    pub(super) fn apply(&mut self, actions: Vec<Action>) {
        for action in actions {
            match action {
                a @ (Action::SetView(_)
                | Action::ApplyRig(_)
                | Action::FrameMesh
                | Action::ToggleBefore
                | Action::SetAb(_)
                | Action::Log(_)
                | Action::MeshLoaded(..)
                | Action::MeshFailed { .. }) => self.apply_to_view(a),
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
                    self.windows.browser.head = self.thumbnail_head();
                    let wake = self.waker.as_fn();
                    self.windows
                        .browser
                        .open(&self.ui_state.preset_folders, wake);
                }
                Action::SetPresetFolders(folders) => {
                    self.ui_state.preset_folders = folders;
                    self.windows.browser.head = self.thumbnail_head();
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
                Action::Import(path) => self.import_now(&path),
                Action::LoadMesh(path) => self.load_mesh(Some(path)),
                Action::ToggleWindow(title) => {
                    if !self.windows.close(title) {
                        self.windows.open(title);
                    }
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

    /// The actions on what the viewport shows: the camera and light, the
    /// environment, A/B and "before", the frame log, a mesh loaded or not.
    fn apply_to_view(&mut self, action: Action) {
        match action {
            Action::SetView(v) => {
                let before = self.ui_state.view.environment;
                self.ui_state.view = v;
                self.environment_switched(before);
            }
            Action::ApplyRig(rig) => {
                let before = self.ui_state.view.environment;
                let applied = rig.apply(&mut self.ui_state.view);
                self.environment_switched(before);
                if !applied {
                    // The HDR rig with no map loaded: ask for one; the
                    // map lights the head once it has loaded.
                    self.view.hdr_rig_pending = true;
                    self.open_dialog(DialogKind::Environment);
                }
            }
            Action::FrameMesh => self.frame_mesh(),
            Action::ToggleBefore => self.view.show_before = !self.view.show_before,
            Action::SetAb(ab) => self.view.ab = ab,
            Action::Log(line) => self.log_line(format_args!("{line}")),
            Action::MeshLoaded(p, info) => self.mesh_loaded(p, info),
            Action::MeshFailed {
                asked,
                error,
                kept,
                kept_settings,
            } => self.mesh_failed(asked, error, kept, kept_settings),
            // `apply` routes only the arms above here.
            other => unreachable!("not a view action: {other:?}"),
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

    /// The viewport's panel: its two toolbars, then the viewport
    /// ([`viewport_ui::ViewportPanel`]); what each asks is applied before
    /// the next is drawn, as a click in a toolbar changes what the
    /// viewport asks of the render thread in the same frame.
    pub(super) fn viewport_panel_ui(&mut self, ui: &mut egui::Ui) {
        self.compare_toolbar_ui(ui);
        self.view_toolbar_ui(ui);
        let dialog_up = self.dialog_up();
        let panel = viewport_ui::ViewportPanel {
            camera: self.ui_state.view,
            a_albedo: self.a_albedo(),
            valid: self.doc.preset.rendering.validate().is_ok() && !self.curves_failed(),
            status: self.status().to_owned(),
            names: self.side_names(),
            view: &mut self.view,
            ui_state: &self.ui_state,
            doc: &self.doc,
            meshes: &self.meshes,
            layout: &mut self.layout,
            reference: &self.windows.reference,
            dialog_up,
            actions: Vec::new(),
        };
        let actions = panel.show(ui);
        self.apply(actions);
    }

    /// The render thread's replies that have arrived, handled before the
    /// panels are drawn so that the status bar shows them in the same UI
    /// frame. Polled only in the viewport's panel, after the status bar,
    /// each reply changed what the bar had drawn and the frame was drawn
    /// again: two UI frames a viewport frame, each costing lavapipe
    /// 10–20 ms of CPU beside the render thread's.
    pub(super) fn poll_viewport(&mut self, ctx: &egui::Context) {
        let replies = self.view.viewport.as_mut().map(|vp| vp.poll());
        for reply in replies.unwrap_or_default() {
            let actions = self.view.receive(ctx, reply);
            self.apply(actions);
        }
    }

    /// The compare toolbar ([`toolbars::CompareBar`]).
    pub(super) fn compare_toolbar_ui(&mut self, ui: &mut egui::Ui) {
        let b_file = match &self.view.b_look {
            Some((_, _, Ok(b))) if matches!(self.ui_state.compare_b, CompareB::Preset(_)) => {
                Some(b)
            }
            _ => None,
        };
        let readout = match (&self.ui_state.compare_b, self.b_difference()) {
            (CompareB::Preset(_), Some(d)) => Some(toolbars::BReadout {
                difference: d,
                albedo_note: self.b_albedo_note(),
                others: b_file.map_or_else(Vec::new, |b| {
                    crate::settings::albedo::differing_fields(&self.doc.preset, b)
                }),
            }),
            _ => None,
        };
        let u = &self.ui_state;
        let bar = toolbars::CompareBar {
            settings: compare::CompareSettings {
                mode: u.compare,
                b: u.compare_b.clone(),
                ab: self.view.ab,
                show_before: self.view.show_before,
                difference_scale: u.difference_scale,
                difference_auto: u.difference_auto,
                split: u.split,
                b_albedo: u.b_material_albedo,
            },
            names: self.side_names(),
            has_before: self.doc.before_last_edit().is_some(),
            b_albedo_in_material: b_file.is_some_and(|b| b.rendering.albedo_in_material),
            has_map: self.meshes.colour_map_mean().is_some(),
            readout,
        };
        let actions = bar.ui(ui);
        self.apply(actions);
    }

    /// The view toolbar ([`toolbars::ViewBar`]).
    pub(super) fn view_toolbar_ui(&mut self, ui: &mut egui::Ui) {
        let bar = toolbars::ViewBar {
            view: self.ui_state.view,
            environment_file: self.ui_state.environment_file.as_deref(),
            refine_to_truth: self.ui_state.refine_to_truth,
            framing: self.meshes.framing_distance_m(),
            mesh_items: if self.meshes.mesh.is_some() {
                self.windows.items(windows::Menu::Mesh)
            } else {
                Vec::new()
            },
        };
        let actions = bar.ui(ui);
        self.apply(actions);
    }

    /// What the status bar shows of the viewport and the work under way.
    pub(super) fn status_bar_view(&self) -> report::StatusBarView<'_> {
        report::StatusBarView {
            busy: self.busy(),
            frame_info: self.viewport().frame_info(),
            adapter: &self.view.adapter,
        }
    }

    /// A restored look's mesh (the default head if none), framed as it
    /// was: the restored view is kept, not reframed.
    pub(super) fn restore_mesh(&mut self, mesh: Option<(PathBuf, state::MeshSettings)>) {
        match mesh {
            Some((path, settings)) => {
                self.view.framed_for = Some((Some(path.clone()), settings.metres_per_unit));
                self.ui_state.meshes.insert(path.clone(), settings);
                self.meshes.mesh = Some(path);
            }
            None => self.meshes.mesh = None,
        }
    }

    /// The viewport: its frames, how far they got, what it shows.
    pub fn viewport(&self) -> &ViewportState {
        &self.view
    }

    /// Where the viewport was last drawn.
    pub(super) fn viewport_rect(&self) -> Option<egui::Rect> {
        self.layout.viewport_rect
    }

    /// The viewport's rect, the compare labels drawn on it (text, rect),
    /// and the left and right panels' rects, as last drawn.
    pub fn viewport_layout(&self) -> ViewportLayout {
        self.layout.viewport_layout()
    }

    /// The Histogram window's counts, as last counted (UI tests).
    pub fn histogram(&self) -> Option<&crate::render::StopsHistogram> {
        self.windows.histogram.counted()
    }

    /// The probe's text as last drawn (UI tests).
    pub fn probe_text(&self) -> Option<&str> {
        self.layout.probe.as_deref()
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
            profile_panel_rect: self.layout.panel_rects[1],
            radiance: self.view.radiance.as_ref(),
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

/// B as it is drawn, and the material albedos asked of it.
impl EditorApp {
    /// The loaded mesh's colour map's mean colour, if it has one.
    pub(super) fn colour_map_mean(&self) -> Option<[f32; 3]> {
        self.meshes.colour_map_mean()
    }

    /// B as drawn ([`crate::settings::albedo::b_as_drawn`]) with the editor's choices.
    pub(super) fn b_drawn(
        &self,
        b: Preset,
    ) -> (Preset, crate::settings::albedo::MapColour, Option<String>) {
        crate::settings::albedo::b_as_drawn(
            b,
            self.a_albedo(),
            self.ui_state.b_material_albedo,
            self.ui_state.map_colour,
            self.meshes.colour_map_mean(),
        )
    }

    /// "drawn with A's albedo" when B's engine keeps the albedo in the
    /// material (the compare row and the difference readout say it).
    pub(super) fn b_albedo_note(&self) -> Option<String> {
        match &self.view.b_look {
            Some((_, _, Ok(b))) if b.rendering.albedo_in_material => self
                .b_drawn(b.clone())
                .2
                .map(|label| format!("drawn with {label} albedo")),
            _ => None,
        }
    }

    /// Asks, the first time, which material albedo B is drawn with when
    /// B's engine keeps it in the material.
    pub(super) fn ask_b_albedo(&mut self, b: &Preset) {
        if self.ui_state.b_material_albedo_asked {
            return;
        }
        let a_albedo = self.a_albedo();
        (self.windows.albedo).ask_b(b, self.ui_state.b_material_albedo, a_albedo);
    }

    /// The material-albedo prompt for B, on a typed colour ("a colour…"
    /// beside B).
    pub(super) fn ask_b_albedo_colour(&mut self) {
        let b = match &self.view.b_look {
            Some((_, _, Ok(b))) if b.rendering.albedo_in_material => b.clone(),
            _ => return,
        };
        self.ui_state.b_material_albedo_asked = false;
        self.ask_b_albedo(&b);
        if let Some(p) = self.windows.albedo.prompt.as_mut() {
            p.choice = crate::settings::albedo::MaterialAlbedo::Typed(p.typed.map(|c| c as f64));
        }
    }

    /// The status line no longer names an HDR map that stopped lighting
    /// the head: once the environment is switched away from the map, it
    /// says what lights it now.
    fn environment_switched(&mut self, before: state::EnvironmentChoice) {
        use state::EnvironmentChoice as E;
        let now = self.ui_state.view.environment;
        if before == E::Map && now != E::Map && self.status().starts_with("Environment ") {
            self.say(match now {
                E::Studio => "Environment: the studio sky (the HDR map is off)",
                _ => "Environment: black, the rig's lights alone (the HDR map is off)",
            });
        }
    }

    /// The head the preset browser draws its thumbnails on: the mesh on
    /// screen with its units and maps (the scan, or the artist's), or the
    /// procedural head (`None`).
    fn thumbnail_head(&self) -> Option<windows::browser::ThumbnailHead> {
        let mesh = self.meshes.mesh.clone()?;
        Some(windows::browser::ThumbnailHead {
            settings: self.ui_state.meshes.get(&mesh).cloned().unwrap_or_default(),
            framing_m: self.meshes.framing_distance_m(),
            mesh,
        })
    }

    /// F: the whole mesh in view from where the camera is, whatever its
    /// shape ([`crate::settings::OrbitView::framing_whole`]: the sphere
    /// that holds it fits the viewport's narrower side). Side by side, it
    /// fits a half: the render thread steps each half's camera back by
    /// [`super::viewport::side_by_side_zoom_out`], so the distance is
    /// taken back by as much here.
    fn frame_mesh(&mut self) {
        let side_by_side = self
            .view
            .viewport
            .as_ref()
            .and_then(|vp| vp.last_request())
            .is_some_and(|r| {
                !r.show_b && matches!(r.b, Some((_, state::CompareMode::SideBySide, _)))
            });
        let o = &mut self.ui_state.view.orbit;
        match (self.meshes.mesh_info, self.layout.viewport_rect) {
            (Some(info), Some(rect)) => {
                let w = if side_by_side { 0.5 } else { 1.0 } * rect.width();
                let h = rect.height().max(1.0);
                *o = o.framing_whole(info.bounds_centre_m, info.bounds_radius_m, w / h);
                if side_by_side {
                    o.camera_distance_m /=
                        super::viewport::side_by_side_zoom_out((w as u32, h as u32));
                }
            }
            _ => {
                o.camera_distance_m = self.meshes.framing_distance_m();
                o.camera_pan_m = crate::settings::OrbitView::default().camera_pan_m;
            }
        }
        self.say("Framed the mesh (F)");
    }

    /// A mesh or its maps failed to load: the mesh on screen stays, with
    /// the settings it was loaded with (so the next request does not ask
    /// for the failed one again), and the error is said once, naming what
    /// is still shown.
    fn mesh_failed(
        &mut self,
        asked: Option<PathBuf>,
        error: String,
        kept: Option<PathBuf>,
        kept_settings: state::MeshSettings,
    ) {
        // A request sent while the file was loading fails again, and the
        // artist may have asked for another mesh since: only the failure of
        // the mesh asked for now is said and undone.
        if self.meshes.mesh != asked {
            return;
        }
        let shown = kept
            .as_ref()
            .map_or("the procedural head".to_string(), |p| {
                p.file_name()
                    .map_or_else(|| p.display().to_string(), |n| n.to_string_lossy().into())
            });
        self.say(format!("Error: {error} (kept {shown} on screen)"));
        if let Some(p) = &kept {
            self.ui_state.meshes.insert(p.clone(), kept_settings);
        }
        self.meshes.mesh = kept;
    }

    /// The render thread loaded a mesh (`None`: the default head): frame
    /// it (a mesh the artist loads, or new units of it; the procedural head
    /// at start-up keeps a remembered view of it), ask its units if new or
    /// inside out, say it.
    fn mesh_loaded(&mut self, p: Option<PathBuf>, info: viewport::MeshInfo) {
        self.log_line(format_args!(
            "mesh {} metres_per_unit={}",
            p.as_ref()
                .map_or("default head".into(), |p| p.display().to_string()),
            info.metres_per_unit
        ));
        // The default head the render thread sets up at start,
        // arriving after a mesh was asked for (`edit --mesh`, a
        // restored look, a file dropped at once): that mesh
        // follows, so there is nothing to frame, size or say. (A
        // mesh that failed to load before any renderer existed is
        // replaced by the head after an error, which the arms below
        // handle; later failures keep the mesh: `mesh_failed`.)
        if p.is_none() && self.meshes.mesh.is_some() && !self.status().starts_with("Error") {
            return;
        }
        self.meshes.mesh_info = Some(info);
        // Frame a mesh the artist loads, or new units of it; the procedural
        // head at start-up keeps the remembered view of it.
        let key = (p.clone(), info.metres_per_unit);
        // The remembered view is kept for the procedural head at start-up,
        // and only if it was of it (a view of a small mesh would crop the
        // head; states that do not say were of it). A file loaded at start
        // is framed: the render thread draws its first frame framed.
        let first_head = self.view.framed_for.is_none()
            && p.is_none()
            && self
                .ui_state
                .view_framed_for
                .as_ref()
                .is_none_or(Option::is_none);
        if self.view.framed_for.as_ref() != Some(&key) && !first_head {
            self.ui_state.view.orbit.camera_distance_m = info.framing_distance_m;
            self.ui_state.view.orbit.camera_pan_m = [0.0; 2];
        } else if first_head {
            // A remembered view that shows under a fifth of the
            // head (an extreme close-up, panned away) is no way to
            // start: frame the head, keep the angles and the light.
            let seen = self
                .ui_state
                .view
                .orbit
                .visible_fraction(info.framing_distance_m);
            if seen < 0.2 {
                let o = &mut self.ui_state.view.orbit;
                o.camera_distance_m = info.framing_distance_m;
                o.camera_pan_m = [0.0; 2];
                self.say(format!(
                    "The remembered view showed about {:.0} % of the head: framed the whole head (Reset view does the same)",
                    100.0 * seen
                ));
            }
        }
        self.view.framed_for = Some(key);
        self.ui_state.view_framed_for = Some(p.clone());
        if let Some(p) = &p {
            if !self.ui_state.meshes.contains_key(p) || info.facing.inside_out() {
                self.windows.units.set_open(true);
            }
        }
        match &p {
            Some(p) if info.facing.inside_out() => self.say(format!(
                "Warning: {}: the file is inside out ({} point inward), so it draws dark: Turn outward in the Mesh menu's Units…",
                p.display(),
                info.facing.describe().unwrap_or("its faces")
            )),
            Some(p) => self.say(format!("Mesh {}", p.display())),
            // The first load of the default head is not news.
            // After a failed load the error stays readable.
            None if self.status().starts_with("Error") => {
                let said = format!("{} (showing the default head)", self.status());
                self.say(said);
                self.meshes.mesh = None;
            }
            None if self.status().starts_with("Loading") => {
                self.say("Procedural head");
            }
            None => {}
        }
    }
}
