//! The editor: egui on eframe. Parameters on the left, the live head in
//! the middle (render thread, `viewport.rs`), plots on the right; presets,
//! undo, compare and export from the menu bar.

pub mod analysis;
mod params_ui;
mod plots;
pub mod state;
pub mod viewport;

use crate::export::Format;
use crate::render::mesh::{CRANIUM_M, PLAUSIBLE_CRANIUM_M, PLAUSIBLE_HEIGHT_M};
use crate::settings::{library, Preset};
use analysis::{Analysis, AnalysisKey, Background, Curves};
use state::{CompareB, CompareMode, Document, UiState};
use std::path::{Path, PathBuf};

const STORAGE_KEY: &str = "scatterlab_ui";

/// What a file dialog is for.
#[derive(Debug, Clone, PartialEq)]
pub enum DialogKind {
    Open,
    SaveAs,
    Export(Format),
    CompareB,
    Mesh,
    Environment,
    /// A map file for slot k of the loaded mesh (`textures::SLOTS`).
    Map(usize),
}

impl DialogKind {
    /// The folder memory this dialog shares (`UiState::folders`).
    fn folder_key(&self) -> &'static str {
        match self {
            DialogKind::Open | DialogKind::SaveAs | DialogKind::CompareB => "preset",
            DialogKind::Export(_) => "export",
            DialogKind::Mesh => "mesh",
            DialogKind::Environment => "environment",
            DialogKind::Map(_) => "map",
        }
    }

    /// Whether the dialog writes files (and must ask before replacing).
    fn writes(&self) -> bool {
        matches!(self, DialogKind::SaveAs | DialogKind::Export(_))
    }
}

#[derive(Debug, Clone)]
struct FileDialog {
    kind: DialogKind,
    path: String,
    /// Export only: what the target will not hold exactly
    /// (`export::export_notes`, computed on a thread: fits take a while).
    notes: Option<Vec<String>>,
}

/// A write that would replace files, waiting for the artist.
#[derive(Debug, Clone)]
struct Overwrite {
    kind: DialogKind,
    path: PathBuf,
    existing: Vec<PathBuf>,
}

/// What the viewport shows while comparing.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AbView {
    /// Both, as the compare mode shows them (split, side by side, |A − B|).
    Both,
    A,
    B,
}

/// Where the editor drew the viewport and its neighbours (UI tests).
#[derive(Debug, Clone)]
pub struct ViewportLayout {
    pub viewport: Option<egui::Rect>,
    /// Compare labels: text and plate.
    pub labels: Vec<(String, egui::Rect)>,
    pub params: Option<egui::Rect>,
    pub plots: Option<egui::Rect>,
}

/// An action waiting for the unsaved-changes prompt.
#[derive(Debug, Clone)]
enum Pending {
    Open(PathBuf),
    New(Box<Preset>),
    Quit,
}

/// A compared preset's file and the plot range its curves were taken on.
type BCurvesKey = (PathBuf, Option<u64>);
/// Its name and curves, or why it cannot be overlaid.
type BCurves = Result<(String, Curves), String>;

/// A finished export, reported by its thread.
type ExportResult = Result<Vec<PathBuf>, String>;

/// A loaded HDR environment: its file and irradiance SH, or why not.
type EnvironmentResult = Result<(PathBuf, [[f32; 3]; 9]), String>;

pub struct EditorApp {
    pub doc: Document,
    pub ui_state: UiState,
    analysis: Background<AnalysisKey, Result<Analysis, String>>,
    pub latest: Option<Analysis>,
    /// Curves of the current look (computed in the frame of the edit).
    pub curves: Option<Result<Curves, String>>,
    curves_for: Option<crate::settings::ProfileSpec>,
    viewport: Option<viewport::Viewport>,
    texture: Option<egui::TextureHandle>,
    frame_info: String,
    status: String,
    dialog: Option<FileDialog>,
    pending: Option<Pending>,
    /// Run after the Save As dialog saves (Save in the unsaved-changes
    /// prompt of a look that has no file yet).
    after_save: Option<Pending>,
    /// Files a Save As or export would replace, waiting for a yes.
    overwrite: Option<Overwrite>,
    exports: Vec<std::sync::mpsc::Receiver<ExportResult>>,
    /// The open export dialog's notes, while they are being computed.
    export_notes: Option<std::sync::mpsc::Receiver<Vec<String>>>,
    /// An HDR environment map loading on its own thread.
    environment_load: Option<std::sync::mpsc::Receiver<EnvironmentResult>>,
    /// While comparing: both as the mode shows them, or one side alone.
    pub ab: AbView,
    mesh: Option<PathBuf>,
    /// The loaded mesh's size and framing (from the render thread).
    mesh_info: Option<viewport::MeshInfo>,
    /// The mesh and units the camera was last framed for.
    framed_for: Option<(Option<PathBuf>, f32)>,
    /// The units prompt, open for this mesh.
    units_prompt: Option<PathBuf>,
    /// The map slots window, open for this mesh.
    maps_window: Option<PathBuf>,
    /// Where the viewport was drawn, and the compare labels on it.
    viewport_rect: Option<egui::Rect>,
    compare_labels: Vec<(String, egui::Rect)>,
    /// The side panels' rects (the viewport must stay between them).
    panel_rects: [Option<egui::Rect>; 2],
    /// The last viewport frame, and how many have arrived.
    last_frame: Option<(image::RgbaImage, u64)>,
    /// How far the last frame had got (preview, refining, converged).
    quality: Option<viewport::Quality>,
    /// When the mouse wheel last zoomed (zooming is live input too).
    last_wheel: Option<std::time::Instant>,
    /// SCATTERLAB_FRAME_LOG: a line per viewport frame and UI frame
    /// (`tools/measure_live.sh` reads it).
    frame_log: Option<std::io::LineWriter<std::fs::File>>,
    allow_close: bool,
    /// Curves of a compared preset (B), keyed by its file and the plot range.
    b_curves: Option<(BCurvesKey, BCurves)>,
    /// The table preview and transmittance strip, with the analysis they show.
    preview_textures: Option<(
        AnalysisKey,
        Option<egui::TextureHandle>,
        egui::TextureHandle,
    )>,
    /// Where the profile plot was drawn (its legend goes under it).
    pub plot_rect: Option<egui::Rect>,
    /// UI time of the last frame outside the viewport (ms).
    pub ui_ms: f64,
    /// When the editor was created, and whether the first UI frame and the
    /// first viewport frame were reported (SCATTERLAB_TIMINGS=1 prints them).
    started: std::time::Instant,
    reported: (bool, bool),
    last_title: String,
}

impl EditorApp {
    /// The editor on `preset` (or the embedded default skin). `viewport`
    /// false leaves out the render thread (UI tests of the panels).
    pub fn new(
        ctx: Option<&egui::Context>,
        ui_state: UiState,
        preset: Option<(Preset, Option<PathBuf>)>,
        viewport: bool,
    ) -> Self {
        let (preset, path) = preset.unwrap_or_else(|| (Preset::default_skin(), None));
        // Background threads wake the UI when they finish (tests step by hand).
        let waker = |ctx: Option<&egui::Context>| {
            let ctx = ctx.cloned();
            move || {
                if let Some(c) = &ctx {
                    c.request_repaint();
                }
            }
        };
        let (c1, c2) = (waker(ctx), waker(ctx));
        let mut app = Self {
            doc: Document::new(preset, path),
            ui_state,
            analysis: Background::start("scatterlab-analysis", analysis::analyse, c1),
            latest: None,
            curves: None,
            curves_for: None,
            viewport: viewport.then(|| viewport::Viewport::start(c2)),
            texture: None,
            frame_info: String::new(),
            status:
                "Ready. Drag a preset (.ron), mesh (.obj/.gltf/.glb) or environment (.hdr) onto the window to open it."
                    .into(),
            dialog: None,
            pending: None,
            after_save: None,
            overwrite: None,
            exports: Vec::new(),
            export_notes: None,
            environment_load: None,
            ab: AbView::Both,
            mesh: None,
            mesh_info: None,
            framed_for: None,
            units_prompt: None,
            maps_window: None,
            last_frame: None,
            viewport_rect: None,
            plot_rect: None,
            compare_labels: Vec::new(),
            panel_rects: [None, None],
            quality: None,
            last_wheel: None,
            frame_log: std::env::var_os("SCATTERLAB_FRAME_LOG").and_then(|p| {
                std::fs::File::create(&p)
                    .map_err(|e| {
                        eprintln!(
                            "warning: SCATTERLAB_FRAME_LOG {}: {e}",
                            PathBuf::from(&p).display()
                        )
                    })
                    .ok()
                    .map(std::io::LineWriter::new)
            }),
            allow_close: false,
            preview_textures: None,
            b_curves: None,
            ui_ms: 0.0,
            started: std::time::Instant::now(),
            reported: (false, false),
            last_title: String::new(),
        };
        app.refresh_curves();
        app
    }

    /// What the main plot draws now, per channel (for tests).
    pub fn plot_series(&self) -> Option<[Vec<[f64; 2]>; 3]> {
        match &self.curves {
            Some(Ok(c)) => Some(plots::series(
                c,
                self.ui_state.plot_quantity,
                self.ui_state.log_y,
            )),
            _ => None,
        }
    }

    /// The status bar's viewport readout (method, size, time, adapter).
    pub fn frame_info(&self) -> &str {
        &self.frame_info
    }

    /// Whether the viewport has shown a rendered frame.
    pub fn has_viewport_frame(&self) -> bool {
        self.texture.is_some()
    }

    /// The last viewport frame and the number of frames received so far.
    pub fn viewport_frame(&self) -> Option<(&image::RgbaImage, u64)> {
        self.last_frame.as_ref().map(|(i, n)| (i, *n))
    }

    /// Whether the viewport has rendered everything asked of it.
    /// The viewport's rect, the compare labels drawn on it (text, rect),
    /// and the left and right panels' rects, as last drawn.
    pub fn viewport_layout(&self) -> ViewportLayout {
        ViewportLayout {
            viewport: self.viewport_rect,
            labels: self.compare_labels.clone(),
            params: self.panel_rects[0],
            plots: self.panel_rects[1],
        }
    }

    /// The names of A (the look's method) and B (a method or a preset).
    fn side_names(&self) -> (String, String) {
        let a = self.doc.preset.rendering.method.label().to_string();
        let b = match &self.ui_state.compare_b {
            CompareB::Method(m) => m.label().to_string(),
            CompareB::Preset(p) => p.file_name().map_or_else(
                || p.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            ),
        };
        (a, b)
    }

    /// How far the last viewport frame had got.
    pub fn viewport_quality(&self) -> Option<viewport::Quality> {
        self.quality
    }

    pub fn viewport_idle(&self) -> bool {
        self.viewport
            .as_ref()
            .is_none_or(|v| v.busy_since.is_none())
    }

    /// The loaded mesh's size and framing, once the viewport has it.
    pub fn mesh_info(&self) -> Option<viewport::MeshInfo> {
        self.mesh_info
    }

    /// The mesh whose units prompt is open.
    pub fn units_prompt_for(&self) -> Option<&Path> {
        self.units_prompt.as_deref()
    }

    /// Whether the unsaved-changes prompt is waiting for an answer.
    pub fn prompt_open(&self) -> bool {
        self.pending.is_some()
    }

    /// The status bar's message.
    pub fn status(&self) -> &str {
        &self.status
    }

    /// Whether the background analysis (fits, taps, tables) is current.
    pub fn analysis_done(&self) -> bool {
        !self.analysis.busy()
            && self
                .latest
                .as_ref()
                .is_some_and(|a| a.key == self.analysis_key())
    }

    /// Recomputes the plotted curves if the profile changed (fast models
    /// here, layered stacks come from the analysis thread).
    fn refresh_curves(&mut self) {
        let spec = &self.doc.preset.profile;
        if self.curves_for.as_ref() == Some(spec) {
            return;
        }
        self.curves_for = Some(spec.clone());
        self.curves = if analysis::is_slow(spec) {
            self.latest
                .as_ref()
                .filter(|a| a.key.profile == *spec)
                .map(|a| Ok(a.curves.clone()))
        } else {
            Some(
                spec.build()
                    .map(|p| Curves::of(p.as_ref(), None))
                    .map_err(|e| e.to_string()),
            )
        };
    }

    fn analysis_key(&self) -> AnalysisKey {
        AnalysisKey {
            profile: self.doc.preset.profile.clone(),
            taps: self.doc.preset.rendering.taps,
            overlay: self.ui_state.overlay,
            thickness_max_mm: self.doc.preset.rendering.thickness_remap_mm.1.max(1.0),
        }
    }

    /// Opens `path` now (the caller has dealt with unsaved changes).
    pub fn open_now(&mut self, path: &Path) {
        match Preset::load(path) {
            Ok(p) => {
                self.doc = Document::new(p, Some(path.to_owned()));
                self.ui_state.add_recent(path);
                self.status = format!("Opened {}", path.display());
            }
            Err(e) => self.status = format!("Error: {e}"),
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
                self.status = format!("Saved {}", path.display());
                // Save, then what the unsaved-changes prompt was for.
                if let Some(action) = self.after_save.take() {
                    self.run_pending(action);
                }
            }
            Err(e) => {
                // Not saved: the quit (or open) it was for does not happen,
                // now or after some later save.
                self.after_save = None;
                self.status = format!("Error: {e}");
            }
        }
    }

    /// Whether the editor may close now (Quit answered).
    pub fn close_allowed(&self) -> bool {
        self.allow_close
    }

    /// Runs `action` now, or asks first if there are unsaved changes.
    fn guarded(&mut self, action: Pending) {
        if self.doc.is_dirty() {
            self.pending = Some(action);
        } else {
            self.run_pending(action);
        }
    }

    fn run_pending(&mut self, action: Pending) {
        match action {
            Pending::Open(p) => self.open_now(&p),
            Pending::New(p) => {
                self.status = format!("New look from \"{}\"", p.name);
                self.doc = Document::new(*p, None);
            }
            Pending::Quit => self.allow_close = true,
        }
    }

    fn open_dialog(&mut self, kind: DialogKind) {
        // Where this kind of dialog was last used, else the look's folder,
        // else the working directory.
        let dir = self
            .ui_state
            .folders
            .get(kind.folder_key())
            .filter(|d| d.is_dir())
            .cloned()
            .or_else(|| {
                self.doc
                    .path
                    .as_ref()
                    .and_then(|p| p.parent().map(Path::to_path_buf))
                    .filter(|d| !d.as_os_str().is_empty())
            })
            .or_else(|| std::env::current_dir().ok())
            .unwrap_or_default();
        let name = match &kind {
            DialogKind::SaveAs => format!("{}.ron", file_stem(&self.doc.preset.name)),
            DialogKind::Export(f) => {
                format!("{}.{}", file_stem(&self.doc.preset.name), f.extension())
            }
            _ => String::new(),
        };
        self.export_notes = None;
        if let DialogKind::Export(format) = kind {
            let preset = self.doc.preset.clone();
            let (tx, rx) = std::sync::mpsc::channel();
            std::thread::spawn(move || {
                let notes = crate::export::export_notes(&preset, format)
                    .unwrap_or_else(|e| vec![format!("Cannot export this look: {e}")]);
                let _ = tx.send(notes);
            });
            self.export_notes = Some(rx);
        }
        self.dialog = Some(FileDialog {
            kind,
            path: dir.join(name).display().to_string(),
            notes: None,
        });
    }

    /// Starts an export on its own thread (table bakes take seconds).
    pub fn export(&mut self, format: Format, out: PathBuf) {
        let preset = self.doc.preset.clone();
        let source = self.doc.path.clone();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let r = crate::export::export(&preset, source.as_deref(), format, &out)
                .map_err(|e| e.to_string());
            let _ = tx.send(r);
        });
        self.exports.push(rx);
        self.status = format!("Exporting {} …", format.id());
    }

    /// Loads an equirectangular HDR map on its own thread (decoding and
    /// projecting a large map takes a while) and lights the head with it.
    pub fn load_environment(&mut self, path: PathBuf) {
        let (tx, rx) = std::sync::mpsc::channel();
        self.status = format!("Loading environment {} …", path.display());
        std::thread::spawn(move || {
            let r = crate::render::environment::Environment::load(&path)
                .map(|e| (path, e.irradiance_sh()))
                .map_err(|e| e.to_string());
            let _ = tx.send(r);
        });
        self.environment_load = Some(rx);
    }

    fn handle_drops(&mut self, ctx: &egui::Context) {
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
            match ext.as_str() {
                "ron" => self.guarded(Pending::Open(path)),
                "obj" | "gltf" | "glb" => {
                    self.status = format!("Loading mesh {} …", path.display());
                    self.mesh = Some(path);
                }
                "hdr" => self.load_environment(path),
                _ => {
                    self.status = format!(
                        "Error: {}: not a preset (.ron), mesh (.obj, .gltf, .glb) or environment (.hdr)",
                        path.display()
                    )
                }
            }
        }
    }

    fn shortcuts(&mut self, ctx: &egui::Context) {
        use egui::{Key, KeyboardShortcut, Modifiers};
        let cmd_shift = Modifiers::COMMAND | Modifiers::SHIFT;
        let (redo, undo, redo_y, save_as, save, open, toggle) = ctx.input_mut(|i| {
            (
                i.consume_shortcut(&KeyboardShortcut::new(cmd_shift, Key::Z)),
                i.consume_shortcut(&KeyboardShortcut::new(Modifiers::COMMAND, Key::Z)),
                i.consume_shortcut(&KeyboardShortcut::new(Modifiers::COMMAND, Key::Y)),
                i.consume_shortcut(&KeyboardShortcut::new(cmd_shift, Key::S)),
                i.consume_shortcut(&KeyboardShortcut::new(Modifiers::COMMAND, Key::S)),
                i.consume_shortcut(&KeyboardShortcut::new(Modifiers::COMMAND, Key::O)),
                i.key_pressed(Key::Space),
            )
        });
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
        // Space flips between B alone and A alone in every compare mode
        // (from the mode's own view it shows B first); Escape goes back to
        // the mode's view. Not while typing in a field.
        let escape = ctx.input(|i| i.key_pressed(Key::Escape));
        if ctx.memory(|m| m.focused().is_none()) && self.ui_state.compare != CompareMode::Off {
            if toggle {
                self.ab = match self.ab {
                    AbView::B => AbView::A,
                    AbView::Both | AbView::A => AbView::B,
                };
            } else if escape {
                self.ab = AbView::Both;
            }
        }
    }

    /// The whole editor for one frame.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        let t0 = std::time::Instant::now();
        let ctx = ui.ctx().clone();
        self.handle_drops(&ctx);
        self.shortcuts(&ctx);
        self.poll_workers();

        // Panels draw no background of their own: the window's clear colour
        // is the panel colour (`EframeApp::clear_color`). On lavapipe the
        // UI's frame is fill-bound (1500×900: 11 frames a second with the
        // fills, measured by tools/measure_live.sh), and a cleared pixel
        // costs nothing next to a blended one.
        // The side panels never take more than 30 % and 33 % of the window:
        // wide rows scroll inside them (ScrollArea::both) instead of
        // widening them, so the viewport keeps at least 37 % (470 points
        // of a 1280-point window) and compare views fit.
        let width = ui.ctx().content_rect().width();
        let max_side = [0.30 * width, 0.33 * width];
        let style = ui.style().clone();
        let bare = |f: egui::Frame| f.fill(egui::Color32::TRANSPARENT);
        let side = bare(egui::Frame::side_top_panel(&style));
        egui::Panel::top("menu")
            .frame(side)
            .show(ui, |ui| self.menu_bar(ui));
        egui::Panel::bottom("status")
            .frame(side)
            .show(ui, |ui| self.status_bar(ui));
        let params = egui::Panel::left("params")
            .frame(side)
            .resizable(true)
            .default_size(360.0)
            .max_size(max_side[0])
            .show(ui, |ui| {
                egui::ScrollArea::both().show(ui, |ui| self.params_panel(ui));
            });
        self.panel_rects[0] = Some(params.response.rect);
        // Edits above change the preset; the plots below use it this frame.
        self.refresh_curves();
        self.analysis.request(self.analysis_key());
        let plots = egui::Panel::right("plots")
            .frame(side)
            .resizable(true)
            .default_size(420.0)
            .max_size(max_side[1])
            .show(ui, |ui| {
                // Vertical only: the plot takes the panel's width (its rows
                // wrap rather than widen it).
                egui::ScrollArea::vertical().show(ui, |ui| plots::show(ui, self));
            });
        self.panel_rects[1] = Some(plots.response.rect);
        let ui_ms = t0.elapsed().as_secs_f64() * 1e3;
        egui::CentralPanel::default()
            .frame(bare(egui::Frame::central_panel(&style)))
            .show(ui, |ui| self.viewport_panel(ui));
        self.dialogs(&ctx);
        if self.allow_close {
            // Quit answered (Save or Discard): close now, not at the next
            // frame, which may never come without input.
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        // One undo step per gesture: commit once no button is held and no
        // field is being typed into.
        if !ctx.input(|i| i.pointer.any_down()) && ctx.memory(|m| m.focused().is_none()) {
            self.doc.commit();
        }
        let title = self.doc.title();
        if title != self.last_title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.last_title = title;
        }
        self.ui_ms = ui_ms;
        self.report_timings();
        if let Some(log) = self.frame_log.as_mut() {
            use std::io::Write;
            let _ = writeln!(log, "{:.3} ui {ui_ms:.1}", unix_seconds());
        }
    }

    /// Start-up and per-frame timings on stderr with SCATTERLAB_TIMINGS=1
    /// (the budgets: first frame < 3 s, UI < 8 ms a frame).
    fn report_timings(&mut self) {
        if std::env::var_os("SCATTERLAB_TIMINGS").is_none() {
            return;
        }
        let t = self.started.elapsed().as_secs_f64();
        if !self.reported.0 {
            self.reported.0 = true;
            eprintln!(
                "timing: first UI frame {t:.2} s after start-up (UI {:.2} ms)",
                self.ui_ms
            );
        }
        if !self.reported.1 && self.texture.is_some() {
            self.reported.1 = true;
            eprintln!("timing: first viewport frame {t:.2} s after start-up");
        }
        eprintln!("timing: UI {:.2} ms", self.ui_ms);
    }

    fn poll_workers(&mut self) {
        if let Some((key, result)) = self.analysis.poll() {
            match result {
                Ok(a) => {
                    if analysis::is_slow(&key.profile) && key.profile == self.doc.preset.profile {
                        self.curves = Some(Ok(a.curves.clone()));
                    }
                    self.latest = Some(a);
                }
                Err(e) => {
                    if key.profile == self.doc.preset.profile {
                        self.curves = Some(Err(e));
                    }
                }
            }
        }
        if let Some(rx) = &self.environment_load {
            match rx.try_recv() {
                Ok(Ok((path, sh))) => {
                    let v = &mut self.ui_state.view;
                    v.environment_map_sh = Some(sh);
                    v.environment = state::EnvironmentChoice::Map;
                    self.status = format!("Environment {}", path.display());
                    self.ui_state.environment_file = Some(path);
                    self.environment_load = None;
                }
                Ok(Err(e)) => {
                    self.status = format!("Error: {e}");
                    self.environment_load = None;
                }
                Err(std::sync::mpsc::TryRecvError::Empty) => {}
                Err(_) => self.environment_load = None,
            }
        }
        let mut done = Vec::new();
        self.exports.retain(|rx| match rx.try_recv() {
            Ok(r) => {
                done.push(r);
                false
            }
            Err(std::sync::mpsc::TryRecvError::Empty) => true,
            Err(_) => false,
        });
        for r in done {
            self.status = match r {
                Ok(paths) => format!(
                    "Exported {}",
                    paths
                        .iter()
                        .map(|p| p.display().to_string())
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
                Err(e) => format!("Error: {e}"),
            };
        }
    }

    fn menu_bar(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
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
                ui.separator();
                if ui
                    .button("Load mesh…")
                    .on_hover_text("An OBJ or glTF with UVs, in metres.")
                    .clicked()
                {
                    self.open_dialog(DialogKind::Mesh);
                    ui.close();
                }
                if ui.button("Default head").clicked() {
                    if self.mesh.is_some() {
                        self.status = "Loading the default head …".into();
                    }
                    self.mesh = None;
                    ui.close();
                }
                ui.separator();
                if ui.button("Quit").clicked() {
                    self.guarded(Pending::Quit);
                    ui.close();
                }
            });
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
            ui.menu_button("Export", |ui| {
                for f in Format::ALL {
                    let tip = match f {
                        Format::Unity => "HDRP DiffusionProfileSettings .asset",
                        Format::Unreal => "SubsurfaceProfile struct text + Python",
                        Format::Blender => "Principled BSDF Python snippet",
                        Format::Materialx => "MaterialX OpenPBR Surface (.mtlx)",
                        Format::Godot => "Godot 4 StandardMaterial3D (.tres); Godot's kernel is fixed, so the dialog states the error",
                        Format::LutPng | Format::LutExr => {
                            "pre-integrated and shadow tables (takes a few seconds)"
                        }
                        Format::ProfilePng | Format::ProfileExr => {
                            "1D r·R(r) texture and transmittance strip"
                        }
                        Format::SamplesJson => "Burley sample pattern",
                        Format::Ron => "scatterlab preset",
                        _ => "separable kernel and Burley samples as arrays",
                    };
                    if ui.button(f.id()).on_hover_text(tip).clicked() {
                        self.open_dialog(DialogKind::Export(f));
                        ui.close();
                    }
                }
            });
            ui.separator();
            let dirty = if self.doc.is_dirty() { " *" } else { "" };
            ui.label(format!("{}{}", self.doc.preset.name, dirty))
                .on_hover_text("* = unsaved changes");
        });
    }

    fn status_bar(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            if !self.exports.is_empty()
                || self.analysis.busy()
                || self.environment_load.is_some()
            {
                ui.spinner();
            }
            let color = if self.status.starts_with("Error") {
                ui.visuals().error_fg_color
            } else {
                ui.visuals().text_color()
            };
            // The viewport's line on the right, whole; the status message
            // in what is left, cut short (full text on hover) rather than
            // written over it in a narrow window.
            ui.with_layout(egui::Layout::right_to_left(egui::Align::Center), |ui| {
                ui.add(
                    egui::Label::new(format!("{} · UI {:.1} ms", self.frame_info, self.ui_ms))
                        .wrap_mode(egui::TextWrapMode::Extend),
                )
                    .on_hover_text("Viewport: method, preview / refining / converged, size, render-thread wall time (GPU time of the SSS passes), adapter. UI: this frame's time in the panels and plots.");
                ui.with_layout(egui::Layout::left_to_right(egui::Align::Center), |ui| {
                    ui.add(
                        egui::Label::new(egui::RichText::new(&self.status).color(color))
                            .truncate(),
                    )
                    .on_hover_text(&self.status);
                });
            });
        });
    }

    fn params_panel(&mut self, ui: &mut egui::Ui) {
        let p = &mut self.doc.preset;
        ui.heading("Look");
        ui.horizontal(|ui| {
            ui.label("Name");
            ui.text_edit_singleline(&mut p.name).on_hover_text(
                "The look's name, used in exports (Unity m_Name, Unreal asset name).",
            );
        });
        ui.separator();
        params_ui::model_picker(ui, &mut p.profile);
        params_ui::model_params(ui, &mut p.profile);
        // The model's error, from the last build (never rebuilt per frame:
        // layered stacks take seconds).
        if let Some(Err(e)) = &self.curves {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
        if let Err(e) = p.rendering.validate() {
            ui.colored_label(ui.visuals().error_fg_color, e.to_string());
        }
        ui.separator();
        egui::CollapsingHeader::new("Rendering")
            .default_open(true)
            .show(ui, |ui| params_ui::rendering(ui, &mut p.rendering));
        ui.separator();
        egui::CollapsingHeader::new("Engines (live)")
            .default_open(true)
            .show(ui, |ui| self.engine_readouts(ui));
    }

    fn engine_readouts(&mut self, ui: &mut egui::Ui) {
        use crate::model::units::{UnityProfile, UnrealProfile, UNREAL_DEFAULT_WORLD_UNIT_SCALE};
        let p = &self.doc.preset;
        let burley = match &p.profile {
            crate::settings::ProfileSpec::Burley(b) => {
                b.build().map(|b| (b, 0.0)).map_err(|e| e.to_string())
            }
            _ => match self.latest.as_ref().filter(|a| a.key.profile == p.profile) {
                Some(a) => a.burley_fit.clone().unwrap_or_else(|| Err("no fit".into())),
                None => {
                    ui.horizontal(|ui| {
                        ui.spinner();
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

    fn viewport_panel(&mut self, ui: &mut egui::Ui) {
        // Camera distance that frames the mesh (Reset view, zoom limits).
        let framing = self.mesh_info.map_or(
            crate::settings::OrbitView::default().camera_distance_m,
            |i| i.framing_distance_m,
        );
        self.compare_toolbar_ui(ui);
        self.view_toolbar_ui(ui, framing);
        let avail = ui.available_size();
        let (rect, _) = ui.allocate_exact_size(avail, egui::Sense::hover());
        // The panels' resize handles reach a few points into the viewport:
        // leave them to the panels, so the edges stay grabbable.
        let grab = ui.style().interaction.resize_grab_radius_side + 2.0;
        let response = ui.interact(
            rect.shrink2(egui::vec2(grab, 0.0)),
            ui.scope_id().with("viewport"),
            egui::Sense::click_and_drag(),
        );
        self.viewport_input(ui, rect, &response, framing);
        response.on_hover_text("Left drag: orbit · right or Shift+drag: light · middle drag: pan · wheel: zoom · Space: A/B");
        let req = self.frame_request(ui, rect);
        let valid =
            self.doc.preset.rendering.validate().is_ok() && !matches!(self.curves, Some(Err(_)));
        let replies = match self.viewport.as_mut() {
            Some(vp) => {
                if valid {
                    vp.request(req);
                }
                vp.poll()
            }
            None => Vec::new(),
        };
        for reply in replies {
            self.handle_reply(ui.ctx(), reply);
        }
        self.viewport_overlays_ui(ui, rect);
    }

    /// Compare mode, B, the split and A/B alone: rows that wrap.
    fn compare_toolbar_ui(&mut self, ui: &mut egui::Ui) {
        let (a_name, b_name) = self.side_names();
        // Wraps onto more rows where the viewport is narrow, so the
        // viewport below never grows past its panel.
        ui.horizontal_wrapped(|ui| {
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
                    .selectable_label(self.ui_state.compare == m && self.ab == AbView::Both, name)
                    .clicked()
                {
                    self.ui_state.compare = m;
                    self.ab = AbView::Both;
                }
            }
            if self.ui_state.compare != CompareMode::Off {
                // B and its controls on a row of their own: a widget that
                // overflows a row widens everything under it.
                ui.end_row();
                ui.menu_button(format!("B: {b_name}"), |ui| {
                    for m in crate::settings::rendering::MethodId::ALL {
                        if ui.button(m.label()).clicked() {
                            self.ui_state.compare_b = CompareB::Method(m);
                            ui.close();
                        }
                    }
                    if ui.button("a preset file…").clicked() {
                        self.open_dialog(DialogKind::CompareB);
                        ui.close();
                    }
                });
                if self.ui_state.compare == CompareMode::Split {
                    ui.spacing_mut().slider_width = 90.0;
                    ui.add(egui::Slider::new(&mut self.ui_state.split, 0.0..=1.0).text("split"))
                        .on_hover_text("Where the split line sits: A left of it, B right.");
                }
                for (side, name) in [(AbView::A, "A alone"), (AbView::B, "B alone")] {
                    if ui
                        .selectable_label(self.ab == side, name)
                        .on_hover_text(format!(
                            "Space flips between A alone and B alone (A: {a_name}, B: {b_name})."
                        ))
                        .clicked()
                    {
                        self.ab = if self.ab == side { AbView::Both } else { side };
                    }
                }
            }
        });
    }

    /// Environment, light, exposure, Reset view, and a loaded mesh's
    /// Units… and Maps…: rows that wrap. `framing`: the camera distance
    /// that frames the mesh (m).
    fn view_toolbar_ui(&mut self, ui: &mut egui::Ui, framing: f32) {
        let mut open_environment = false;
        // Wraps onto a second row where the viewport is narrow.
        ui.horizontal_wrapped(|ui| {
            let v = &mut self.ui_state.view;
            ui.label("Environment");
            ui.selectable_value(
                &mut v.environment,
                state::EnvironmentChoice::Studio,
                "studio sky",
            );
            ui.selectable_value(&mut v.environment, state::EnvironmentChoice::Black, "black")
                .on_hover_text("No environment light: the key light alone.");
            if v.environment_map_sh.is_some() {
                let name = self
                    .ui_state
                    .environment_file
                    .as_ref()
                    .and_then(|p| p.file_name())
                    .map_or("HDR map".into(), |n| n.to_string_lossy().into_owned());
                let tip = self.ui_state.environment_file.as_ref().map_or(
                    "The last HDR map loaded.".into(),
                    |p| {
                        format!(
                            "{} (its irradiance, as order-2 spherical harmonics)",
                            p.display()
                        )
                    },
                );
                ui.selectable_value(&mut v.environment, state::EnvironmentChoice::Map, name)
                    .on_hover_text(tip);
            }
            if ui
                .button("HDR…")
                .on_hover_text(
                    "Light the head with an equirectangular Radiance .hdr map \
                     (or drop one onto the window).",
                )
                .clicked()
            {
                open_environment = true;
            }
            ui.add(
                egui::DragValue::new(&mut v.orbit.light_intensity)
                    .range(0.0..=50.0)
                    .speed(0.05)
                    .prefix("light "),
            )
            .on_hover_text("Irradiance of the key light (linear).");
            ui.add(
                egui::DragValue::new(&mut v.orbit.exposure)
                    .range(0.01..=20.0)
                    .speed(0.01)
                    .prefix("exposure "),
            );
            if ui
                .button("Reset view")
                .on_hover_text(
                    "Camera, key light and exposure back to their defaults; the environment stays.",
                )
                .clicked()
            {
                v.orbit = crate::settings::OrbitView {
                    camera_distance_m: framing,
                    ..Default::default()
                };
            }
            if let Some(p) = self.mesh.clone() {
                if ui
                    .button("Units…")
                    .on_hover_text("Metres per unit of this mesh: its size, the camera and the scattering distances in mm depend on it.")
                    .clicked()
                {
                    self.units_prompt = Some(p.clone());
                }
                if ui
                    .button("Maps…")
                    .on_hover_text("This mesh's albedo, normal, roughness, SSS mask and thickness maps: files, V-flip and colour space.")
                    .clicked()
                {
                    self.maps_window = Some(p);
                }
            }
        });
        if open_environment {
            self.open_dialog(DialogKind::Environment);
        }
    }

    /// Orbit (left drag), light (right or Shift+drag), pan (middle drag)
    /// and zoom (wheel, within 0.15–8× `framing`).
    fn viewport_input(
        &mut self,
        ui: &egui::Ui,
        rect: egui::Rect,
        response: &egui::Response,
        framing: f32,
    ) {
        // Orbit (left drag), light (right drag or shift+drag), pan (middle drag), zoom (wheel).
        let v = &mut self.ui_state.view;
        let d = response.drag_delta();
        let shift = ui.input(|i| i.modifiers.shift);
        if response.dragged_by(egui::PointerButton::Secondary)
            || (shift && response.dragged_by(egui::PointerButton::Primary))
        {
            v.orbit.light_azimuth_rad -= d.x * 0.01;
            v.orbit.light_elevation_rad =
                (v.orbit.light_elevation_rad - d.y * 0.01).clamp(-1.5, 1.5);
        } else if response.dragged_by(egui::PointerButton::Primary) {
            v.orbit.camera_yaw_rad -= d.x * 0.01;
            v.orbit.camera_pitch_rad = (v.orbit.camera_pitch_rad + d.y * 0.01).clamp(-1.4, 1.4);
        } else if response.dragged_by(egui::PointerButton::Middle) {
            let k = v.orbit.camera_distance_m / rect.height().max(1.0) * 0.55;
            v.orbit.camera_pan_m[0] -= d.x * k;
            v.orbit.camera_pan_m[1] += d.y * k;
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y);
            if scroll != 0.0 {
                self.last_wheel = Some(std::time::Instant::now());
                // Zoom from a close-up of a pore to the whole mesh in a
                // corner, whatever its size.
                v.orbit.camera_distance_m = (v.orbit.camera_distance_m * (-scroll * 0.002).exp())
                    .clamp(0.15 * framing, 8.0 * framing);
            }
        }
    }

    /// What the viewport should show now, as a request for the render
    /// thread (sent only if it differs from the last).
    fn frame_request(&mut self, ui: &egui::Ui, rect: egui::Rect) -> viewport::Request {
        let ppp = ui.ctx().pixels_per_point();
        let size = (
            ((rect.width() * ppp) as u32).clamp(16, 4096),
            ((rect.height() * ppp) as u32).clamp(16, 4096),
        );
        let b = if self.ui_state.compare == CompareMode::Off || self.ab == AbView::A {
            None
        } else {
            match viewport::b_look(&self.doc.preset, &self.ui_state.compare_b) {
                Ok(l) => Some((l, self.ui_state.compare, self.ui_state.split)),
                Err(e) => {
                    self.status = format!("Error: compare B: {e}");
                    None
                }
            }
        };
        // Live input: anything dragged (the orbit, a slider, a panel edge)
        // or the wheel in the last quarter second. Previews while it lasts;
        // the full frame, refined, once it stops.
        let wheel_recent = self
            .last_wheel
            .is_some_and(|t| t.elapsed() < std::time::Duration::from_millis(250));
        if wheel_recent {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(260));
        }
        let interactive = ui.ctx().dragged_id().is_some() || wheel_recent;
        let req = viewport::Request {
            interactive,
            a: viewport::Look::of(&self.doc.preset),
            b,
            show_b: self.ab == AbView::B && self.ui_state.compare != CompareMode::Off,
            view: self.ui_state.view,
            size,
            mesh: self.mesh.clone(),
            seq: 0,
            mesh_settings: self
                .mesh
                .as_ref()
                .and_then(|p| self.ui_state.meshes.get(p))
                .cloned()
                .unwrap_or_default(),
        };
        req
    }

    /// One reply from the render thread: a frame to show, an error, or a
    /// loaded mesh to frame.
    fn handle_reply(&mut self, ctx: &egui::Context, reply: viewport::Reply) {
        match reply {
            viewport::Reply::Frame {
                image,
                stats,
                wall_ms,
                note,
                quality,
                seq,
            } => {
                if let Some(log) = self.frame_log.as_mut() {
                    use std::io::Write;
                    let _ = writeln!(
                        log,
                        "{:.3} frame {} {}x{} seq={seq} render_ms={wall_ms:.1}",
                        unix_seconds(),
                        match quality {
                            viewport::Quality::Preview { .. } => "preview",
                            viewport::Quality::Refining { .. } => "refining",
                            viewport::Quality::Converged { .. } => "converged",
                        },
                        image.width(),
                        image.height(),
                    );
                }
                self.quality = Some(quality);
                let ci = egui::ColorImage::from_rgba_unmultiplied(
                    [image.width() as usize, image.height() as usize],
                    image.as_raw(),
                );
                let n = self.last_frame.as_ref().map_or(0, |f| f.1) + 1;
                self.last_frame = Some((image, n));
                match &mut self.texture {
                    Some(t) => t.set(ci, egui::TextureOptions::LINEAR),
                    None => {
                        self.texture =
                            Some(ctx.load_texture("viewport", ci, egui::TextureOptions::LINEAR))
                    }
                }
                self.frame_info = format!(
                    "{} · {} · {}×{} · {:.0} ms{}{} · {}",
                    stats.method,
                    quality.describe(),
                    stats.width,
                    stats.height,
                    wall_ms,
                    stats
                        .sss_gpu_ms
                        .map(|m| format!(" (SSS {m:.1} ms)"))
                        .unwrap_or_default(),
                    note.map(|n| format!(" · {n}")).unwrap_or_default(),
                    stats.adapter
                );
            }
            // The same request is not sent again (it would fail
            // again); the next change renders.
            viewport::Reply::Error(e) => self.status = format!("Error: viewport: {e}"),
            viewport::Reply::MeshLoaded(p, info) => {
                self.mesh_info = Some(info);
                // Frame a mesh the artist loads, or new units of
                // it; the default head at start-up keeps the
                // remembered view.
                let key = (p.clone(), info.metres_per_unit);
                let first_head = self.framed_for.is_none() && p.is_none();
                if self.framed_for.as_ref() != Some(&key) && !first_head {
                    self.ui_state.view.orbit.camera_distance_m = info.framing_distance_m;
                    self.ui_state.view.orbit.camera_pan_m = [0.0; 2];
                }
                self.framed_for = Some(key);
                if let Some(p) = &p {
                    if !self.ui_state.meshes.contains_key(p) {
                        self.units_prompt = Some(p.clone());
                    }
                }
                match &p {
                    Some(p) => self.status = format!("Mesh {}", p.display()),
                    // The first load of the default head is not news.
                    // After a failed load the error stays readable.
                    None if self.status.starts_with("Error") => {
                        self.status.push_str(" (showing the default head)");
                        self.mesh = None;
                    }
                    None if self.mesh.is_some() || self.status.starts_with("Loading") => {
                        self.status = "Default head".into();
                        self.mesh = None;
                    }
                    None => {}
                }
            }
        }
    }

    /// What is drawn over the viewport: the frame, progress bars, the
    /// compare labels and the rendering note.
    fn viewport_overlays_ui(&mut self, ui: &mut egui::Ui, rect: egui::Rect) {
        let painter = ui.painter_at(rect);
        if self.texture.is_none() {
            painter.rect_filled(rect, 0.0, egui::Color32::from_gray(20));
        }
        if let Some(t) = &self.texture {
            let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            painter.image(t.id(), rect, uv, egui::Color32::WHITE);
        }
        let busy = self
            .viewport
            .as_ref()
            .and_then(|v| v.busy_since)
            .map(|t| t.elapsed().as_secs_f32());
        // A progress bar at the viewport's bottom left, `lift` px up.
        let progress = |ui: &mut egui::Ui, done: f32, text: String, lift: f32| {
            let width = rect.width().min(360.0) - 16.0;
            let area = egui::Rect::from_min_size(
                rect.left_bottom() + egui::vec2(8.0, -lift),
                egui::vec2(width, 24.0),
            );
            ui.put(
                area,
                egui::ProgressBar::new(done).text(text).desired_width(width),
            );
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(100));
        };
        if self.status.starts_with("Loading mesh") {
            // The mesh loads and bakes thickness and curvature on the
            // render thread; show how far the bake has got.
            let done = crate::render::mesh::bake_fraction();
            progress(
                ui,
                done,
                "loading the mesh, baking thickness …".into(),
                32.0,
            );
        }
        if let (Some(_), Some((phase, done))) = (busy, crate::render::ground_truth::progress()) {
            // `reference` is the ground truth, computed on the CPU on the
            // render thread: tens of seconds for a full viewport. Above the
            // "rendering … s" line.
            let text = if phase == 1 {
                "ground truth: irradiance over the surface …"
            } else {
                "ground truth: integrating each pixel …"
            };
            progress(ui, done, format!("{text} {:.0} %", 100.0 * done), 64.0);
        }
        let label = match (self.viewport.is_none(), busy) {
            (true, _) => Some("viewport off".to_string()),
            // Not while dragging: previews keep coming, and the wait runs
            // from the drag's first request (the status bar says "preview").
            (_, Some(s))
                if (s > 0.3 && ui.ctx().dragged_id().is_none()) || self.texture.is_none() =>
            {
                Some(format!("rendering … {s:.1} s"))
            }
            _ => None,
        };
        self.compare_labels_ui(&painter, rect);
        self.viewport_rect = Some(rect);
        if let Some(l) = label {
            painter.text(
                rect.center_bottom() - egui::vec2(0.0, 12.0),
                egui::Align2::CENTER_BOTTOM,
                l,
                egui::FontId::proportional(14.0),
                egui::Color32::LIGHT_GRAY,
            );
        }
        if busy.is_some() {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(100));
        }
    }

    /// Each side of a comparison labelled on its own half, on a dark plate
    /// that reads over skin (kept for the UI tests: `viewport_layout`).
    fn compare_labels_ui(&mut self, painter: &egui::Painter, rect: egui::Rect) {
        self.compare_labels.clear();
        if self.ui_state.compare != CompareMode::Off {
            let (a_name, b_name) = self.side_names();
            let (a, b) = (format!("A · {a_name}"), format!("B · {b_name}"));
            let top = rect.top() + 8.0;
            let labels: Vec<(String, egui::Pos2, egui::Align2)> =
                match (self.ab, self.ui_state.compare) {
                    (AbView::A, _) => vec![(
                        a,
                        egui::pos2(rect.left() + 8.0, top),
                        egui::Align2::LEFT_TOP,
                    )],
                    (AbView::B, _) => vec![(
                        b,
                        egui::pos2(rect.left() + 8.0, top),
                        egui::Align2::LEFT_TOP,
                    )],
                    (_, CompareMode::SideBySide) => vec![
                        (
                            a,
                            egui::pos2(rect.left() + 8.0, top),
                            egui::Align2::LEFT_TOP,
                        ),
                        (
                            b,
                            egui::pos2(rect.center().x + 8.0, top),
                            egui::Align2::LEFT_TOP,
                        ),
                    ],
                    (_, CompareMode::Split) => {
                        let x = rect.left() + self.ui_state.split * rect.width();
                        vec![
                            (a, egui::pos2(x - 8.0, top), egui::Align2::RIGHT_TOP),
                            (b, egui::pos2(x + 8.0, top), egui::Align2::LEFT_TOP),
                        ]
                    }
                    _ => vec![(
                        format!("|A − B| · A {a_name} · B {b_name}"),
                        egui::pos2(rect.left() + 8.0, top),
                        egui::Align2::LEFT_TOP,
                    )],
                };
            for (text, pos, align) in labels {
                let galley = painter.layout_no_wrap(
                    text.clone(),
                    egui::FontId::proportional(15.0),
                    egui::Color32::WHITE,
                );
                let mut r = align.anchor_size(pos, galley.size()).expand(4.0);
                // Keep the plate inside the viewport.
                r = r.translate(egui::vec2(
                    (rect.left() + 2.0 - r.left()).max(0.0)
                        - (r.right() - rect.right() + 2.0).max(0.0),
                    0.0,
                ));
                painter.rect_filled(r, 4.0, egui::Color32::from_black_alpha(150));
                painter.galley(r.min + egui::vec2(4.0, 4.0), galley, egui::Color32::WHITE);
                self.compare_labels.push((text, r));
            }
        }
    }

    /// Asks for a mesh's units: metres per unit with common choices, a
    /// live height readout and a suggestion from the bounds (a head is
    /// 18–40 cm tall with or without its neck). Every change applies at once (the mesh reloads and
    /// the camera frames it) and is remembered for the file.
    fn units_prompt(&mut self, ctx: &egui::Context) {
        let Some(path) = self.units_prompt.clone() else {
            return;
        };
        let Some(info) = self.mesh_info else {
            return;
        };
        let size = info.size;
        let h = size.height_units.max(1e-9);
        let current = self
            .ui_state
            .meshes
            .get(&path)
            .map_or(1.0, |m| m.metres_per_unit);
        let mut mpu = current;
        let mut open = true;
        let mut done = false;
        egui::Window::new("Mesh units")
            .collapsible(false)
            .resizable(false)
            .anchor(egui::Align2::CENTER_CENTER, egui::vec2(0.0, 0.0))
            .open(&mut open)
            .show(ctx, |ui| {
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
                        ui.selectable_value(&mut mpu, v, label);
                    }
                });
                let speed = mpu * 0.01;
                ui.add(
                    egui::DragValue::new(&mut mpu)
                        .range(1e-6..=1e3)
                        .speed(speed)
                        .max_decimals(6)
                        .suffix(" m/unit"),
                )
                .on_hover_text("Metres per unit of the file (Unity's worldScale convention).");
                let height_cm = h * mpu * 100.0;
                let (lo, hi) = PLAUSIBLE_HEIGHT_M;
                let mut text = format!("Head height = {height_cm:.1} cm");
                let mut plausible = (100.0 * lo..=100.0 * hi).contains(&height_cm);
                if let Some(c) = size.cranium_units {
                    let across_cm = c * mpu * 100.0;
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
                    None => format!("Use {suggested} m/unit ({:.1} cm tall)", h * suggested * 100.0),
                };
                if ui
                    .button(label)
                    .on_hover_text(match size.cranium_units {
                        Some(_) => "The units that make the head an adult's size (a common unit when one is within 20 %).",
                        None => "No head found above a neck: a common unit that makes the mesh 18–40 cm tall, or the exact scale for 25 cm.",
                    })
                    .clicked()
                {
                    mpu = suggested;
                }
                if ui.button("OK").clicked() {
                    done = true;
                }
            });
        if mpu != current || !self.ui_state.meshes.contains_key(&path) {
            self.ui_state
                .meshes
                .entry(path.clone())
                .or_default()
                .metres_per_unit = mpu;
        }
        if done || !open {
            self.units_prompt = None;
        }
    }

    /// The loaded mesh's map slots: for each, the file (or the mesh's own
    /// map), a V-flip for maps whose V runs up, and the texels' encoding.
    /// Changes apply at once (the mesh reloads with them) and are
    /// remembered for the file.
    fn maps_window(&mut self, ctx: &egui::Context) {
        use crate::render::textures::{MapSlot, TextureSlot, SLOTS};
        let Some(path) = self.maps_window.clone() else {
            return;
        };
        let mut settings = self.ui_state.meshes.get(&path).cloned().unwrap_or_default();
        let mut open = true;
        let mut choose = None;
        egui::Window::new("Mesh maps")
            .collapsible(false)
            .resizable(false)
            .open(&mut open)
            .show(ctx, |ui| {
                egui::Grid::new("mesh_maps").num_columns(5).show(ui, |ui| {
                    for (k, slot) in SLOTS.into_iter().enumerate() {
                        let m = &mut settings.maps[k];
                        let label = match slot {
                            TextureSlot::Albedo => "Albedo",
                            TextureSlot::Normal => "Normal",
                            TextureSlot::Roughness => "Roughness",
                            TextureSlot::Mask => "SSS mask",
                            TextureSlot::Thickness => "Thickness",
                        };
                        ui.label(label);
                        let file = m.path.as_ref().and_then(|p| p.file_name()).map_or_else(
                            || "the mesh's own".to_string(),
                            |n| n.to_string_lossy().into_owned(),
                        );
                        if ui
                            .button(format!("{label}: {file}"))
                            .on_hover_text("Choose a PNG or JPEG that replaces this map.")
                            .clicked()
                        {
                            choose = Some(k);
                        }
                        if ui
                            .add_enabled(m.path.is_some(), egui::Button::new("Clear"))
                            .on_hover_text("Back to the mesh's own map.")
                            .clicked()
                        {
                            m.path = None;
                        }
                        ui.checkbox(&mut m.flip_v, format!("{label}: flip V"))
                            .on_hover_text("For maps made with V up (OpenGL's bottom-left origin) on a mesh with glTF's top-left origin, or the other way round.");
                        egui::ComboBox::from_id_salt(("map_space", k))
                            .selected_text(if m.srgb { "sRGB" } else { "linear" })
                            .show_ui(ui, |ui| {
                                ui.selectable_value(&mut m.srgb, true, "sRGB");
                                ui.selectable_value(&mut m.srgb, false, "linear");
                            })
                            .response
                            .on_hover_text(format!(
                                "How the file's texels are encoded ({} is usual for this map).",
                                if MapSlot::default_for(slot).srgb { "sRGB" } else { "linear" }
                            ));
                        ui.end_row();
                    }
                });
            });
        if self.ui_state.meshes.get(&path) != Some(&settings) {
            self.ui_state.meshes.insert(path.clone(), settings);
        }
        if let Some(k) = choose {
            self.open_dialog(DialogKind::Map(k));
        }
        if !open {
            self.maps_window = None;
        }
    }

    fn dialogs(&mut self, ctx: &egui::Context) {
        self.units_prompt(ctx);
        self.maps_window(ctx);
        self.overwrite_prompt(ctx);
        self.unsaved_prompt(ctx);
        self.file_dialog(ctx);
    }

    /// The unsaved-changes prompt for a pending open, new or quit: Save
    /// (Save As first for a look without a file), Discard, Cancel.
    fn unsaved_prompt(&mut self, ctx: &egui::Context) {
        if let Some(pending) = self.pending.clone() {
            let modal =
                egui::Modal::new(egui::Id::unique("scatterlab_unsaved_prompt")).show(ctx, |ui| {
                    ui.heading("Unsaved changes");
                    ui.label(format!(
                        "\"{}\" has changes that are not saved.",
                        self.doc.preset.name
                    ));
                    let mut choice = None;
                    ui.horizontal(|ui| {
                        if ui.button("Save").clicked() {
                            choice = Some(0);
                        }
                        if ui.button("Discard changes").clicked() {
                            choice = Some(1);
                        }
                        if ui.button("Cancel").clicked() {
                            choice = Some(2);
                        }
                    });
                    choice
                });
            match modal.inner {
                Some(0) => {
                    self.pending = None;
                    if self.doc.path.is_none() {
                        // No file yet: Save As first, then carry on.
                        self.after_save = Some(pending);
                        self.open_dialog(DialogKind::SaveAs);
                    } else {
                        self.save();
                        if !self.doc.is_dirty() {
                            self.run_pending(pending);
                        }
                    }
                }
                Some(1) => {
                    self.pending = None;
                    self.run_pending(pending);
                }
                Some(_) => self.pending = None,
                None => {}
            }
        }
    }

    /// The open file dialog: a path field, the folder's matching files,
    /// OK and Cancel.
    fn file_dialog(&mut self, ctx: &egui::Context) {
        let Some(mut dialog) = self.dialog.clone() else {
            return;
        };
        if let Some(notes) = self.export_notes.as_ref().and_then(|rx| rx.try_recv().ok()) {
            dialog.notes = Some(notes);
            self.export_notes = None;
        }
        let title = match &dialog.kind {
            DialogKind::Open => "Open preset".to_string(),
            DialogKind::SaveAs => "Save preset as".into(),
            DialogKind::Export(f) => format!("Export {}", f.id()),
            DialogKind::CompareB => "Preset to compare against (B)".into(),
            DialogKind::Mesh => "Load mesh (.obj, .gltf, .glb)".into(),
            DialogKind::Environment => "Environment map (equirectangular .hdr)".into(),
            DialogKind::Map(k) => format!(
                "{} map (.png, .jpg)",
                crate::render::textures::SLOTS[*k].name()
            ),
        };
        let mut close = false;
        let mut accept = false;
        egui::Modal::new(egui::Id::unique("scatterlab_file_dialog")).show(ctx, |ui| {
            ui.heading(&title);
            if let DialogKind::Export(_) = dialog.kind {
                match &dialog.notes {
                    Some(notes) => {
                        for n in notes {
                            ui.label(n);
                        }
                    }
                    None => {
                        ui.horizontal(|ui| {
                            ui.spinner();
                            ui.label("Estimating how closely the target holds this look …");
                        });
                    }
                }
                ui.separator();
            }
            let r = ui.add(egui::TextEdit::singleline(&mut dialog.path).desired_width(520.0));
            if r.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)) {
                accept = true;
            }
            // The folder's matching files, to click.
            let p = PathBuf::from(&dialog.path);
            let dir = if p.is_dir() {
                p.clone()
            } else {
                p.parent().map(Path::to_path_buf).unwrap_or_default()
            };
            let exts: &[&str] = match dialog.kind {
                DialogKind::Mesh => &["obj", "gltf", "glb"],
                DialogKind::Environment => &["hdr"],
                DialogKind::Map(_) => &["png", "jpg", "jpeg"],
                DialogKind::Export(f) => &[f.extension()],
                _ => &["ron"],
            };
            egui::ScrollArea::vertical()
                .max_height(240.0)
                .show(ui, |ui| {
                    if let Some(parent) = dir.parent() {
                        if ui.button("[up] ..").clicked() {
                            dialog.path = parent.display().to_string();
                        }
                    }
                    let mut entries: Vec<PathBuf> = std::fs::read_dir(&dir)
                        .map(|rd| rd.filter_map(|e| e.ok().map(|e| e.path())).collect())
                        .unwrap_or_default();
                    entries.sort();
                    for e in entries {
                        let name = e
                            .file_name()
                            .map(|n| n.to_string_lossy().into_owned())
                            .unwrap_or_default();
                        if name.starts_with('.') {
                            continue;
                        }
                        let is_dir = e.is_dir();
                        let matches = e
                            .extension()
                            .and_then(|x| x.to_str())
                            .is_some_and(|x| exts.contains(&x.to_ascii_lowercase().as_str()));
                        if is_dir {
                            if ui.button(format!("{name}/")).clicked() {
                                dialog.path = e.display().to_string();
                            }
                        } else if matches && ui.button(&name).clicked() {
                            dialog.path = e.display().to_string();
                        }
                    }
                });
            ui.horizontal(|ui| {
                if ui.button("OK").clicked() {
                    accept = true;
                }
                if ui.button("Cancel").clicked() {
                    close = true;
                }
            });
        });
        if close && !accept && dialog.kind == DialogKind::SaveAs {
            // Cancelled: nothing saved, so nothing to carry on with.
            self.after_save = None;
        }
        if accept {
            close = true;
            self.accept_dialog(&dialog, &mut close);
        }
        self.dialog = if close { None } else { Some(dialog) };
    }

    /// OK in a file dialog: remember its folder, then write, open or load
    /// — or first ask, where a Save As or export would replace files.
    fn accept_dialog(&mut self, dialog: &FileDialog, close: &mut bool) {
        let path = PathBuf::from(dialog.path.trim());
        if let Some(dir) = path.parent().filter(|d| d.is_dir()) {
            self.ui_state
                .folders
                .insert(dialog.kind.folder_key().into(), dir.to_path_buf());
        }
        let existing: Vec<PathBuf> = match &dialog.kind {
            DialogKind::SaveAs => vec![path.clone()],
            DialogKind::Export(f) => crate::export::planned_paths(*f, &path),
            _ => Vec::new(),
        }
        .into_iter()
        .filter(|p| p.exists())
        .collect();
        if dialog.kind.writes() && !existing.is_empty() {
            self.overwrite = Some(Overwrite {
                kind: dialog.kind.clone(),
                path,
                existing,
            });
        } else {
            self.write_or_open(dialog.kind.clone(), path, close);
        }
    }

    /// Asks before a Save As or export replaces files; Replace writes,
    /// Cancel goes back to the dialog at the same path.
    fn overwrite_prompt(&mut self, ctx: &egui::Context) {
        let Some(o) = self.overwrite.clone() else {
            return;
        };
        let modal =
            egui::Modal::new(egui::Id::unique("scatterlab_overwrite_prompt")).show(ctx, |ui| {
                ui.heading("Replace existing files?");
                for p in &o.existing {
                    ui.label(format!("{} exists.", p.display()));
                }
                let mut choice = None;
                ui.horizontal(|ui| {
                    if ui.button("Replace").clicked() {
                        choice = Some(true);
                    }
                    if ui.button("Cancel").clicked() {
                        choice = Some(false);
                    }
                });
                choice
            });
        match modal.inner {
            Some(true) => {
                self.overwrite = None;
                let mut close = true;
                self.write_or_open(o.kind, o.path, &mut close);
            }
            Some(false) => {
                self.overwrite = None;
                self.dialog = Some(FileDialog {
                    kind: o.kind,
                    path: o.path.display().to_string(),
                    notes: None,
                });
            }
            None => {}
        }
    }

    /// What a file dialog's OK does with `path`; `close` false keeps the
    /// dialog open (a preset B that does not load).
    fn write_or_open(&mut self, kind: DialogKind, path: PathBuf, close: &mut bool) {
        {
            match kind {
                DialogKind::Open => self.guarded(Pending::Open(path)),
                DialogKind::SaveAs => self.save_as(&path),
                DialogKind::Export(f) => self.export(f, path),
                DialogKind::CompareB => match Preset::load(&path) {
                    Ok(_) => self.ui_state.compare_b = CompareB::Preset(path),
                    Err(e) => {
                        self.status = format!("Error: {e}");
                        *close = false;
                    }
                },
                DialogKind::Mesh => self.mesh = Some(path),
                DialogKind::Environment => self.load_environment(path),
                DialogKind::Map(k) => {
                    if let Some(mesh) = self.mesh.clone() {
                        self.ui_state.meshes.entry(mesh).or_default().maps[k].path = Some(path);
                    }
                }
            }
        }
    }
}

/// Seconds since the Unix epoch (the frame log's clock, which
/// `tools/measure_live.sh` shares through `date +%s.%N`).
fn unix_seconds() -> f64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// A file name from a look's name.
fn file_stem(name: &str) -> String {
    let s: String = name
        .chars()
        .map(|c| {
            if c.is_alphanumeric() || c == '-' {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect();
    let s = s.trim_matches('_').to_string();
    if s.is_empty() {
        "look".into()
    } else {
        s
    }
}

/// eframe's wrapper: persistence and the close prompt.
struct EframeApp {
    app: EditorApp,
    /// Close once the viewport has shown a frame (smoke test).
    exit_after_first_frame: bool,
}

impl eframe::App for EframeApp {
    /// The panels' colour: they draw no fill of their own (see
    /// [`EditorApp::show`]).
    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        visuals.panel_fill.to_normalized_gamma_f32()
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let app = &mut self.app;
        if self.exit_after_first_frame && app.has_viewport_frame() {
            app.allow_close = true;
        }
        if ui.ctx().input(|i| i.viewport().close_requested())
            && app.doc.is_dirty()
            && !app.allow_close
        {
            ui.ctx()
                .send_viewport_cmd(egui::ViewportCommand::CancelClose);
            app.pending = Some(Pending::Quit);
        }
        if app.allow_close {
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
        }
        app.show(ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        let mut s = self.app.ui_state.clone();
        s.last_preset = self.app.doc.path.clone();
        eframe::set_value(storage, STORAGE_KEY, &s);
    }
}

/// Opens the editor window on `preset` (else the last preset, else the
/// embedded default skin).
/// `compare`: open comparing in this mode, B the look with this method
/// (`None`: B as last time).
pub fn run(
    preset: Option<PathBuf>,
    exit_after_first_frame: bool,
    compare: Option<(CompareMode, Option<crate::settings::rendering::MethodId>)>,
) -> anyhow::Result<()> {
    let started = std::time::Instant::now();
    let initial = match &preset {
        Some(p) => Some((Preset::load(p)?, Some(p.clone()))),
        None => None,
    };
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("scatterlab")
            .with_app_id("scatterlab")
            .with_inner_size([1500.0, 900.0])
            .with_min_inner_size([900.0, 560.0])
            .with_drag_and_drop(true),
        persist_window: true,
        ..Default::default()
    };
    eframe::run_native(
        "scatterlab",
        options,
        Box::new(move |cc| {
            let mut ui_state: UiState = cc
                .storage
                .and_then(|s| eframe::get_value(s, STORAGE_KEY))
                .unwrap_or_default();
            if let Some((mode, b)) = compare {
                ui_state.compare = mode;
                if let Some(m) = b {
                    ui_state.compare_b = CompareB::Method(m);
                }
            }
            let initial = initial.or_else(|| {
                let p = ui_state.last_preset.clone()?;
                Preset::load(&p).ok().map(|preset| (preset, Some(p)))
            });
            let mut app = EditorApp::new(Some(&cc.egui_ctx), ui_state, initial, true);
            app.started = started;
            Ok(Box::new(EframeApp {
                app,
                exit_after_first_frame,
            }))
        }),
    )
    .map_err(|e| anyhow::anyhow!("cannot open the editor window: {e}"))
}
