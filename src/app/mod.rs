//! The editor: egui on eframe. Parameters on the left, the live head in
//! the middle (render thread, `viewport.rs`), plots on the right; presets,
//! undo, compare and export from the menu bar.

mod actions;
pub mod analysis;
mod autosave;
mod colour_ui;
pub mod compare;
mod dialogs;
mod files;
mod jobs;
mod keys;
mod look_panel;
pub mod menus;
mod overlays;
mod params_ui;
mod parts;
mod plots;
mod report;
mod run;
pub use run::{run, MeshArg, RunArgs};
pub mod state;
pub mod toolbars;
pub mod viewport;
mod viewport_ui;
pub mod wake;
pub mod widget_map;
pub mod windows;

use crate::export::Format;
use crate::settings::{library, Preset};
use analysis::{Analysis, AnalysisKey, Background, Curves};
use jobs::Jobs;
pub use parts::ViewportState;
use parts::{Dialogs, Layout, MeshState, ProfileState, Report};
use state::{CompareB, CompareMode, Document, UiState};
use std::path::{Path, PathBuf};

const STORAGE_KEY: &str = "scatterlab_ui";

/// What a file dialog is for.
#[derive(Debug, Clone, PartialEq)]
pub enum DialogKind {
    Open,
    /// An engine's file (Unity, Unreal, MaterialX, Godot, Blender) as a
    /// new, unsaved look.
    Import,
    SaveAs,
    Export(Format),
    CompareB,
    Mesh,
    Environment,
    /// A map file for slot k of the loaded mesh (`textures::SLOTS`).
    Map(usize),
    /// The viewport's frame as a PNG (File → Save image, F12).
    SaveImage,
    /// A turntable GIF (and its PNG frames): File → Save turntable.
    SaveTurntable,
    /// An offscreen render at a chosen size: File → Save image at size.
    SaveStill,
    /// A reference photograph (File → Reference image).
    Reference,
    /// A folder of the artist's presets for the browser (Presets window's
    /// "+ choose folder…").
    PresetFolder,
}

impl DialogKind {
    /// The folder memory this dialog shares (`UiState::folders`).
    fn folder_key(&self) -> &'static str {
        match self {
            DialogKind::Open | DialogKind::SaveAs | DialogKind::CompareB => "preset",
            DialogKind::Import => "import",
            DialogKind::Export(_) => "export",
            DialogKind::Mesh => "mesh",
            DialogKind::Environment => "environment",
            DialogKind::Map(_) => "map",
            DialogKind::Reference => "reference",
            DialogKind::PresetFolder => "preset_folder",
            DialogKind::SaveImage | DialogKind::SaveTurntable | DialogKind::SaveStill => "image",
        }
    }

    /// The file extensions this dialog lists (lower case, no dot); folders
    /// are always listed.
    fn extensions(&self) -> Vec<&'static str> {
        let exts: &[&'static str] = match self {
            DialogKind::Mesh => &crate::render::mesh::Mesh::EXTENSIONS,
            DialogKind::Environment => &["hdr"],
            DialogKind::Map(_) | DialogKind::Reference => &["png", "jpg", "jpeg"],
            DialogKind::SaveImage => &["png"],
            DialogKind::SaveStill => &["png", "exr"],
            DialogKind::SaveTurntable => &["gif"],
            DialogKind::Export(f) => return vec![f.extension()],
            // What the export targets' readers read (`Target::reader`).
            DialogKind::Import => return crate::export::importable_extensions(false),
            DialogKind::CompareB => return crate::export::importable_extensions(true),
            DialogKind::Open | DialogKind::SaveAs | DialogKind::PresetFolder => {
                return vec![crate::settings::PRESET_EXTENSION]
            }
        };
        exts.to_vec()
    }

    /// The dialog's title.
    fn title(&self) -> String {
        match self {
            DialogKind::Open => "Open preset (.ron)".to_string(),
            DialogKind::Import => "Import an engine's file".into(),
            DialogKind::SaveAs => "Save preset as (.ron)".into(),
            DialogKind::Export(f) => format!("Export: {} (.{})", f.name(), f.extension()),
            DialogKind::CompareB => "Compare with (B): a preset or engine file".into(),
            DialogKind::Mesh => "Load mesh (.obj, .gltf, .glb)".into(),
            DialogKind::Environment => "Environment map (equirectangular .hdr)".into(),
            DialogKind::SaveImage => "Save the viewport image (.png)".into(),
            DialogKind::SaveStill => {
                "Save the image at size (.png, or .exr for linear light)".into()
            }
            DialogKind::Reference => "Reference image (.png, .jpg)".into(),
            DialogKind::PresetFolder => "Add a folder of your presets (.ron)".into(),
            DialogKind::SaveTurntable => "Save turntable (.gif)".into(),
            DialogKind::Map(k) => format!(
                "{} map (.png, .jpg)",
                crate::render::textures::SLOTS[*k].name()
            ),
        }
    }

    /// Whether the dialog writes files (and must ask before replacing).
    fn writes(&self) -> bool {
        matches!(
            self,
            DialogKind::SaveAs
                | DialogKind::Export(_)
                | DialogKind::SaveImage
                | DialogKind::SaveTurntable
                | DialogKind::SaveStill
        )
    }
}

/// An open file dialog: what it is for and the picker (`egui_file`, a
/// maintained egui dialog: folders first, the typed name kept while
/// browsing folders).
struct FileDialog {
    kind: DialogKind,
    picker: egui_file::FileDialog,
    /// Export only: what the target will not hold exactly
    /// (`export::export_notes`, computed on a thread: fits take a while).
    notes: Option<Vec<String>>,
}

/// A write that would replace files, waiting for the artist.
#[derive(Debug, Clone, PartialEq)]
pub struct Overwrite {
    pub kind: DialogKind,
    pub path: PathBuf,
    pub existing: Vec<PathBuf>,
    /// The export's notes, for the dialog that Cancel goes back to.
    pub notes: Option<Vec<String>>,
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
    /// The difference scale's number plates, top first.
    pub scale_plates: Vec<egui::Rect>,
    pub params: Option<egui::Rect>,
    pub plots: Option<egui::Rect>,
}

/// An action waiting for the unsaved-changes prompt.
#[derive(Debug, Clone, PartialEq)]
pub enum Pending {
    Open(PathBuf),
    New(Box<Preset>),
    Quit,
}

/// A compared file, the plot range its curves were taken on and A's
/// profile (the difference shown is against it).
type BCurvesKey = (PathBuf, Option<u64>, String);
/// Its name, curves and relative L2 distance of r·R(r) from A per
/// channel, or why it cannot be overlaid.
type BCurves = Result<(String, Curves, [f64; 3]), String>;

pub struct EditorApp {
    pub doc: Document,
    pub ui_state: UiState,
    allow_close: bool,
    /// The look's analysis and curves, B's curves and look, the imported file, and the table previews.
    profile: ProfileState,
    /// The viewport: its render thread, the frame shown and how far it got, and what it shows (A/B, before).
    view: ViewportState,
    /// The loaded mesh, its size, and its units prompt and Maps window.
    meshes: MeshState,
    /// Open dialogs, prompts and windows, and what waits on them.
    dialogs: Dialogs,
    /// Work on other threads: exports, an environment map loading, a turntable.
    jobs: Jobs,
    /// The status line, notifications, the frame log and timings.
    report: Report,
    /// Where things were drawn (the viewport, labels, panels, plot), for layout and UI tests.
    layout: Layout,
    /// The look's autosave and what an earlier run left to recover (off
    /// unless [`EditorApp::with_autosave`]).
    autosave: Option<autosave::Autosave>,
    /// Wakes the UI when a background job finishes (each job's thread
    /// holds a clone).
    waker: wake::Waker,
    /// The windows that are types of their own (`app/windows/`).
    windows: windows::Windows,
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
        // Background threads wake the UI when they finish.
        let waker = wake::Waker::new(ctx);
        let mut app = Self {
            doc: Document::new(preset, path),
            ui_state,
            allow_close: false,
            profile: ProfileState::new(&waker),
            view: ViewportState::new(viewport.then(|| viewport::Viewport::start(waker.as_fn()))),
            meshes: MeshState::default(),
            dialogs: Dialogs::default(),
            jobs: Jobs::default(),
            report: Report::new(),
            layout: Layout::default(),
            autosave: None,
            waker,
            windows: Default::default(),
        };
        app.refresh_curves();
        if viewport {
            app.reload_background();
        }
        app
    }

    /// Look A's albedo without building a slow model each frame: Burley's
    /// A, else the total reflectance of the curves the analysis thread
    /// computed for the look (clamped to [0, 1]; the kernels without a
    /// colour draw the default skin's, as `look_albedo` says), else
    /// [`crate::settings::albedo::look_albedo`] where the model is quick to build.
    pub(super) fn a_albedo(&self) -> crate::model::Rgb {
        self.profile.a_albedo(&self.doc.preset)
    }

    /// The relative L2 distance of B's r·R(r) from A's per channel, when
    /// B is a file whose curves are overlaid.
    fn b_difference(&self) -> Option<[f64; 3]> {
        match &self.profile.b_curves {
            Some((_, Ok((_, _, d)))) => Some(*d),
            _ => None,
        }
    }

    /// The look's curves could not be computed (the viewport does not draw
    /// it).
    fn curves_failed(&self) -> bool {
        matches!(self.profile.curves, Some(Err(_)))
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

    /// Recomputes the plotted curves if the profile changed (fast models
    /// here, layered stacks come from the analysis thread).
    fn refresh_curves(&mut self) {
        let spec = &self.doc.preset.profile;
        if self.profile.curves_for.as_ref() == Some(spec) {
            return;
        }
        self.profile.curves_for = Some(spec.clone());
        self.profile.curves = if analysis::is_slow(spec) {
            self.profile
                .latest
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

    /// The whole editor for one frame.
    pub fn show(&mut self, ui: &mut egui::Ui) {
        let t0 = std::time::Instant::now();
        let ctx = ui.ctx().clone();
        self.start_frame(&ctx);
        let drawn = self.drawn();

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
            .show(ui, |ui| self.menu_bar_ui(ui));
        egui::Panel::bottom("status").frame(side).show(ui, |ui| {
            self.report.status_bar_ui(ui, self.status_bar_view())
        });
        let params = egui::Panel::left("params")
            .frame(side)
            .resizable(true)
            .default_size(360.0)
            .max_size(max_side[0])
            .show(ui, |ui| {
                egui::ScrollArea::both()
                    .show(ui, |ui| self.look_panel().ui(ui))
                    .inner
            });
        self.layout.panel_rects[0] = Some(params.response.rect);
        self.apply(params.inner);
        // Edits above change the preset; the plots below use it this frame.
        self.refresh_curves();
        if self.profile.analysis.request(self.analysis_key()) {
            self.log_line(format_args!("analysis request"));
        }
        let plots = egui::Panel::right("plots")
            .frame(side)
            .resizable(true)
            .default_size(420.0)
            .max_size(max_side[1])
            .show(ui, |ui| {
                // Vertical only: the plot takes the panel's width (its rows
                // wrap rather than widen it).
                egui::ScrollArea::vertical()
                    .show(ui, |ui| self.plots_panel().ui(ui))
                    .inner
            });
        self.layout.panel_rects[1] = Some(plots.response.rect);
        let (plot_rect, asked) = plots.inner;
        self.layout.plot_rect = plot_rect;
        self.apply(asked);
        let ui_ms = t0.elapsed().as_secs_f64() * 1e3;
        egui::CentralPanel::default()
            .frame(bare(egui::Frame::central_panel(&style)))
            .show(ui, |ui| self.viewport_panel_ui(ui));
        self.dialogs_ui(&ctx);
        self.windows_ui(&ctx);
        self.report.notices_ui(&ctx, self.viewport_rect());
        self.finish_frame(&ctx, drawn, ui_ms);
    }

    /// The frame's start: linear colour numbers (once), the interface's
    /// scale and theme, dropped files, shortcuts, and what the background
    /// threads and the render thread finished.
    fn start_frame(&mut self, ctx: &egui::Context) {
        // Colour pickers show linear numbers, as every field here is linear
        // (set once: the picker's toggle may change it after).
        let id = egui::Id::unique("scatterlab-linear-colour-numbers");
        if !ctx.data(|d| d.get_temp::<bool>(id).unwrap_or(false)) {
            ctx.data_mut(|d| d.insert_temp(id, true));
            ctx.all_styles_mut(|s| {
                s.visuals.numeric_color_space = egui::style::NumericColorSpace::Linear
            });
        }
        run::apply_interface(ctx, &mut self.ui_state, &mut self.layout.applied_scale);
        self.waker.attach(ctx);
        let dropped = keys::dropped(ctx);
        self.apply(dropped);
        self.keys(ctx);
        self.poll_workers();
        self.poll_viewport(ctx);
    }

    /// The frame's end: a quit answered closes the window, a gesture that
    /// ended commits its undo step, the autosave, another frame if what
    /// was drawn first changed, and the report (`drawn`: what the first
    /// panels showed; `ui_ms`: the panels' time).
    fn finish_frame(&mut self, ctx: &egui::Context, drawn: report::Drawn, ui_ms: f64) {
        if self.allow_close {
            // Quit answered (Save or Discard): close now, not at the next
            // frame, which may never come without input. A clean quit
            // leaves nothing to recover.
            self.autosave_clear();
            ctx.send_viewport_cmd(egui::ViewportCommand::Close);
        }
        // One undo step per gesture: commit once no button is held and no
        // field is being typed into.
        if !ctx.input(|i| i.pointer.any_down()) && ctx.memory(|m| m.focused().is_none()) {
            self.doc.commit();
        }
        self.autosave_tick(Some(ctx), false);
        // A reply, a prompt's answer or a finished job can change what the
        // menu and status bars drew at the frame's start: draw it again
        // now, not at the next input.
        if self.drawn() != drawn {
            ctx.request_repaint();
        }
        let has_frame = self.viewport().has_frame();
        self.report
            .end_frame(ctx, (self.doc.title(), drawn), ui_ms, has_frame);
    }

    /// The left panel over the look, its analysis and the head's surface
    /// colour.
    fn look_panel(&mut self) -> look_panel::LookPanel<'_> {
        let colour_map_mean = self.colour_map_mean();
        look_panel::LookPanel {
            preset: &self.doc.preset,
            profile: &self.profile,
            map_colour: &mut self.ui_state.map_colour,
            colour_map_mean,
        }
    }

    /// The right panel over the look, the plot's settings and the
    /// analysis, with what B is drawn with.
    fn plots_panel(&mut self) -> plots::PlotsPanel<'_> {
        let colour_map_mean = self.colour_map_mean();
        let auto_log_radius = self.plot_auto_log_radius();
        plots::PlotsPanel {
            doc: &self.doc,
            ui_state: &mut self.ui_state,
            profile: &mut self.profile,
            colour_map_mean,
            auto_log_radius,
        }
    }

    /// What the panels drawn first (menu, status bar, the look's fields)
    /// show that code later in the frame may change.
    fn drawn(&self) -> report::Drawn {
        report::Drawn {
            status: self.report.status.clone(),
            frame_info: self.viewport().frame_info().to_owned(),
            busy: self.busy(),
            preset: self.doc.preset.clone(),
            path: self.doc.path.clone(),
        }
    }

    /// A line in the frame log ([`Report::log_line`]).
    fn log_line(&mut self, line: std::fmt::Arguments) {
        self.report.log_line(line);
    }

    /// Puts `text` in the status line ([`Report::say`]).
    fn say(&mut self, text: impl Into<String>) {
        self.report.say(text);
    }

    /// The status bar's message.
    pub fn status(&self) -> &str {
        &self.report.status
    }

    /// The notifications on screen (errors and warnings not yet dismissed).
    pub fn notices(&self) -> &[String] {
        &self.report.notices
    }

    /// Where the profile plot was drawn (UI tests).
    pub fn plot_rect(&self) -> Option<egui::Rect> {
        self.layout.plot_rect
    }

    /// The latest finished analysis of the look (fits, tables), if any.
    pub fn latest_analysis(&self) -> Option<&analysis::Analysis> {
        self.profile.latest.as_ref()
    }

    /// Whether the plot's radius axis is logarithmic now (set, or
    /// automatic for these curves).
    pub fn plot_log_radius(&self) -> bool {
        self.ui_state
            .log_radius
            .unwrap_or_else(|| self.plot_auto_log_radius())
    }

    /// The automatic radius axis: logarithmic where any curve drawn needs
    /// it ([`plots::auto_log_radius`]): the look's, the overlay fit's (when its
    /// numbers are sane enough to draw) and B's (a narrow B or fit is a
    /// spike at 0 on a linear axis too).
    fn plot_auto_log_radius(&self) -> bool {
        let overlay = self
            .profile
            .latest
            .as_ref()
            .filter(|a| {
                a.key.profile == self.doc.preset.profile && a.key.overlay == self.ui_state.overlay
            })
            .and_then(|a| a.overlay.as_ref());
        let b_shown = self.ui_state.compare != CompareMode::Off
            && matches!(self.ui_state.compare_b, CompareB::Preset(_));
        matches!(&self.profile.curves, Some(Ok(c)) if plots::auto_log_radius(c))
            || matches!(overlay, Some(Ok(o)) if plots::overlay_is_sane(o) && plots::auto_log_radius(&o.curves))
            || (b_shown
                && matches!(
                    self.profile.b_curves.as_ref().map(|b| &b.1),
                    Some(Ok((_, c, _))) if plots::auto_log_radius(c)
                ))
    }

    /// What the main plot draws now, per channel (for tests).
    pub fn plot_series(&self) -> Option<[Vec<[f64; 2]>; 3]> {
        match &self.profile.curves {
            Some(Ok(c)) => Some(plots::series(
                c,
                self.ui_state.plot_quantity,
                self.ui_state.log_y,
            )),
            _ => None,
        }
    }

    /// Whether the background analysis (fits, taps, tables) is current.
    pub fn analysis_done(&self) -> bool {
        !self.profile.analysis.busy()
            && self
                .profile
                .latest
                .as_ref()
                .is_some_and(|a| a.key == self.analysis_key())
    }

    /// Whether the analysis thread is working.
    pub(super) fn analysis_busy(&self) -> bool {
        self.profile.analysis.busy()
    }

    /// Makes the next analysis panic (tests of the recovery).
    #[doc(hidden)]
    pub fn inject_analysis_panic(&self) {
        self.profile.analysis.inject_panic();
    }
}

/// Seconds since the Unix epoch (the frame log's clock, which
/// `tools/measure_live.sh` shares through `date +%s.%N`).
fn unix_seconds() -> f64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0.0, |d| d.as_secs_f64())
}

/// A file name from a look's name: its words in lower case joined by one
/// underscore ("Skin1 (Jensen 2001)" → `skin1_jensen_2001`), "look" if it
/// has none. Tested by `file_names_are_clean`.
fn file_stem(name: &str) -> String {
    let words: Vec<String> = name
        .split(|c: char| !(c.is_alphanumeric() || c == '-'))
        .map(|w| w.trim_matches('-').to_lowercase())
        .filter(|w| !w.is_empty())
        .collect();
    if words.is_empty() {
        "look".into()
    } else {
        words.join("_")
    }
}

#[cfg(test)]
mod file_name_tests {
    #[test]
    fn file_names_are_clean() {
        for (name, want) in [
            ("Skin1 (Jensen 2001)", "skin1_jensen_2001"),
            ("Skin (Unity HDRP default)", "skin_unity_hdrp_default"),
            ("  Marble -- polished!  ", "marble_polished"),
            ("Wax/Candle: warm", "wax_candle_warm"),
            ("Peau Crème", "peau_crème"),
            ("()", "look"),
        ] {
            assert_eq!(super::file_stem(name), want, "{name}");
        }
    }
}
