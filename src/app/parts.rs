//! The parts `EditorApp` is made of, each owning one concern's state: the
//! profile's analysis, the viewport, the mesh, dialogs, background jobs,
//! the status report and the layout.

use super::*;

/// The look's analysis and curves, B's curves and look, the imported file, and the table previews.
pub(super) struct ProfileState {
    pub(super) analysis: Background<AnalysisKey, Result<Analysis, String>>,
    pub(super) latest: Option<Analysis>,
    /// Curves of the current look (computed in the frame of the edit).
    pub(super) curves: Option<Result<Curves, String>>,
    pub(super) curves_for: Option<crate::settings::ProfileSpec>,
    /// Curves of a compared preset (B), keyed by its file and the plot range.
    pub(super) b_curves: Option<(BCurvesKey, BCurves)>,
    /// The engine file the look was last imported from, with its own
    /// fields (the Engines readout shows them).
    pub(super) imported: Option<(PathBuf, crate::export::ImportedLook)>,
    /// The table preview and transmittance strip, with the analysis they show.
    pub(super) preview_textures: Option<(
        AnalysisKey,
        Option<egui::TextureHandle>,
        egui::TextureHandle,
    )>,
}

/// The viewport: its render thread, the frame shown and how far it got, and what it shows (A/B, before).
pub struct ViewportState {
    pub(super) viewport: Option<viewport::Viewport>,
    /// The pointer rests over the viewport: its mouse hint is shown.
    pub(super) show_mouse_hint: bool,
    /// The GPU adapter's whole name and its driver with the driver's
    /// version (the status bar shows the name's first words, all of it on
    /// hover).
    pub(super) adapter: String,
    /// The loaded HDR map, drawn behind the head when asked.
    pub(super) background_map: Option<viewport::SharedMap>,
    pub(super) texture: Option<egui::TextureHandle>,
    pub(super) frame_info: String,
    /// The HDR light rig was chosen with no map loaded: apply it once the
    /// map the dialog asked for has loaded.
    pub(super) hdr_rig_pending: bool,
    /// While comparing: both as the mode shows them, or one side alone.
    pub(super) ab: AbView,
    /// The mesh and units the camera was last framed for.
    pub(super) framed_for: Option<(Option<PathBuf>, f32)>,
    /// The scale of the difference view on screen (white, |ΔL*|), if one is.
    pub(super) difference_shown: Option<f32>,
    /// The viewport shows the look before the last edit ("before", F).
    pub(super) show_before: bool,
    /// The last viewport frame, and how many have arrived.
    pub(super) last_frame: Option<(image::RgbaImage, u64)>,
    /// The last frame's scene-linear radiance, where the render thread
    /// sent it (a settled view of one look), for the probe and histogram.
    pub(super) radiance: Option<std::sync::Arc<crate::render::SceneLinear>>,
    /// How far the last frame had got (preview, refining, converged).
    pub(super) quality: Option<viewport::Quality>,
    /// The newest frames' quality, size and status line, oldest first
    /// (several can arrive within one UI frame; tests read them).
    pub(super) history: std::collections::VecDeque<(viewport::Quality, (u32, u32), String)>,
    /// The ground truth's (phase, items) on its progress bar, when the UI
    /// first saw it, the fraction then and the last fraction seen (for the
    /// time left).
    pub(super) truth_phase: Option<((u32, u32), std::time::Instant, f32, f32)>,
    /// B's look from its file, by path and modification time: read again
    /// only when the file changes, not on every UI frame (an engine file's
    /// import measures its round trip, `godot::read::round_trip_note`).
    pub(super) b_look: Option<(
        PathBuf,
        Option<std::time::SystemTime>,
        Result<Preset, String>,
    )>,
    /// When the mouse wheel last zoomed (zooming is live input too).
    pub(super) last_wheel: Option<std::time::Instant>,
}

/// The loaded mesh, its size, and its units prompt and Maps window.
#[derive(Default)]
pub(super) struct MeshState {
    pub(super) mesh: Option<PathBuf>,
    /// The loaded mesh's size and framing (from the render thread).
    pub(super) mesh_info: Option<viewport::MeshInfo>,
}

/// Open dialogs, prompts and windows, and what waits on them.
#[derive(Default)]
pub(super) struct Dialogs {
    pub(super) dialog: Option<FileDialog>,
    /// Run after the Save As dialog saves (Save in the unsaved-changes
    /// prompt of a look that has no file yet).
    pub(super) after_save: Option<Pending>,
    /// The open export dialog's notes, while they are being computed.
    pub(super) export_notes: Option<std::sync::mpsc::Receiver<Vec<String>>>,
    /// `edit --budget DIR`: a budget report's merges, and their window.
    /// The windows open at the last frame (`dialogs_ui` brings a newly
    /// opened one to the front).
    pub(super) open_last_frame: Vec<&'static str>,
}

/// The status line, notifications, the frame log and timings.
pub(super) struct Report {
    pub(super) status: String,
    /// Errors and warnings shown as notifications until dismissed (the
    /// status bar keeps only the latest), and the status last looked at.
    pub(super) notices: Vec<String>,
    pub(super) status_seen: String,
    /// SCATTERLAB_FRAME_LOG: a line per viewport frame and UI frame
    /// (`tools/measure_live.sh` reads it).
    pub(super) frame_log: Option<std::io::LineWriter<std::fs::File>>,
    /// UI time of the last frame outside the viewport (ms).
    pub(super) ui_ms: f64,
    /// The status line the frame log last wrote.
    pub(super) logged_status: String,
    /// When the editor was created, and whether the first UI frame and the
    /// first viewport frame were reported (SCATTERLAB_TIMINGS=1 prints them).
    pub(super) started: std::time::Instant,
    pub(super) reported: (bool, bool),
    pub(super) last_title: String,
}

/// Where things were drawn (the viewport, labels, panels, plot), for layout and UI tests.
#[derive(Default)]
pub(super) struct Layout {
    /// Where the viewport was drawn, and the compare labels on it.
    pub(super) viewport_rect: Option<egui::Rect>,
    pub(super) compare_labels: Vec<(String, egui::Rect)>,
    /// The pixel probe's text, while the pointer is over the viewport.
    pub(super) probe: Option<String>,
    /// The side panels' rects (the viewport must stay between them).
    pub(super) panel_rects: [Option<egui::Rect>; 2],
    /// Where the profile plot was drawn (its legend goes under it).
    pub(super) plot_rect: Option<egui::Rect>,
    /// The interface scale set on the context last frame.
    pub(super) applied_scale: Option<f32>,
    /// The difference scale's number plates, top first.
    pub(super) scale_plates: Vec<egui::Rect>,
}

impl Dialogs {
    /// A window opened (again) since the last frame comes to the front
    /// (egui keeps a reopened window where it was in the stack), so that
    /// Escape closes what the artist opened last; `open` is every open
    /// window's title.
    pub(super) fn bring_new_to_front(&mut self, ctx: &egui::Context, open: Vec<&'static str>) {
        for t in &open {
            if !self.open_last_frame.contains(t) {
                ctx.move_to_top(egui::LayerId::new(
                    egui::Order::Middle,
                    dialogs::window_id(t),
                ));
            }
        }
        self.open_last_frame = open;
    }

    /// Works out the export's notes for `format` on a thread (a table
    /// bake's fit takes a while), for the export dialog; none without a
    /// format.
    pub(super) fn work_out_export_notes(
        &mut self,
        preset: &Preset,
        format: Option<Format>,
        mesh: Option<&std::path::Path>,
        waker: &wake::Waker,
    ) {
        self.export_notes = None;
        let Some(format) = format else {
            return;
        };
        let preset = preset.clone();
        // glTF writes the mesh on screen: said first.
        let on = (format == Format::Gltf).then(|| match mesh {
            Some(p) => format!(
                "Mesh: {}, as on screen, with its UVs; its colour map, where it has one and the look draws it, as the base colour's texture, and its normal map, where it has one.",
                p.display()
            ),
            None => "Mesh: scatterlab's procedural head, as on screen (no maps written).".into(),
        });
        let (tx, rx) = std::sync::mpsc::channel();
        let waker = waker.clone();
        std::thread::spawn(move || {
            let mut notes = crate::export::export_notes(&preset, format)
                .unwrap_or_else(|e| vec![format!("Cannot export this look: {e}")]);
            notes.splice(0..0, on);
            let _ = tx.send(notes);
            waker.wake();
        });
        self.export_notes = Some(rx);
    }
}

impl Layout {
    /// The viewport's rect, the compare labels drawn on it (text, rect),
    /// and the left and right panels' rects, as last drawn.
    pub(super) fn viewport_layout(&self) -> ViewportLayout {
        ViewportLayout {
            viewport: self.viewport_rect,
            labels: self.compare_labels.clone(),
            scale_plates: self.scale_plates.clone(),
            params: self.panel_rects[0],
            plots: self.panel_rects[1],
        }
    }
}

impl MeshState {
    /// The loaded mesh's colour map's mean colour, if it has one.
    pub(super) fn colour_map_mean(&self) -> Option<[f32; 3]> {
        self.mesh_info.and_then(|i| i.colour_map_mean)
    }

    /// The camera distance that frames the loaded mesh (m): Reset view,
    /// F and the zoom's limits.
    pub(super) fn framing_distance_m(&self) -> f32 {
        self.mesh_info.map_or(
            crate::settings::OrbitView::default().camera_distance_m,
            |i| i.framing_distance_m,
        )
    }
}

impl ProfileState {
    /// Look A's (`p`'s) albedo without building a slow model each frame:
    /// Burley's A, else the total reflectance of the curves the analysis
    /// thread computed for the look (clamped to [0, 1]; the kernels without
    /// a colour draw the default skin's, as `look_albedo` says), else
    /// `look_albedo` where the model is quick to build.
    pub(super) fn a_albedo(&self, p: &Preset) -> crate::model::Rgb {
        use crate::settings::ProfileSpec;
        if matches!(
            p.profile,
            ProfileSpec::Burley(_) | ProfileSpec::Jimenez2012(_) | ProfileSpec::Artist(_)
        ) || !analysis::is_slow(&p.profile)
        {
            return crate::settings::albedo::look_albedo(p);
        }
        match (&self.curves, &self.curves_for) {
            (Some(Ok(c)), Some(spec)) if *spec == p.profile => c.total.map(|t| t.clamp(0.0, 1.0)),
            _ => crate::settings::albedo::KERNEL_SURFACE_ALBEDO.map(|c| c as f64),
        }
    }

    /// Takes in the analysis thread's result, if one came: the latest
    /// analysis, and a slow model's curves or the error when it is of
    /// `current` (the look's profile now). `Err`: the thread survived a
    /// panic, which is worth a notice.
    pub(super) fn take_analysis(
        &mut self,
        current: &crate::settings::ProfileSpec,
    ) -> Option<Result<(), String>> {
        let (key, result) = self.analysis.poll()?;
        match result {
            Ok(a) => {
                if analysis::is_slow(&key.profile) && key.profile == *current {
                    self.curves = Some(Ok(a.curves.clone()));
                }
                self.latest = Some(a);
                Some(Ok(()))
            }
            Err(e) => {
                let failed = e.contains("thread failed").then(|| e.clone());
                if key.profile == *current {
                    self.curves = Some(Err(e));
                }
                Some(failed.map_or(Ok(()), Err))
            }
        }
    }

    /// No analysis yet; its thread started, waking the UI with `waker`.
    pub(super) fn new(waker: &wake::Waker) -> Self {
        Self {
            analysis: Background::start(
                "scatterlab-analysis",
                analysis::analyse,
                Err,
                waker.as_fn(),
            ),
            latest: None,
            curves: None,
            curves_for: None,
            preview_textures: None,
            b_curves: None,
            imported: None,
        }
    }
}

impl ViewportState {
    /// Nothing shown yet, on `viewport`'s render thread (none: the UI
    /// tests of the panels).
    pub(super) fn new(viewport: Option<viewport::Viewport>) -> Self {
        Self {
            viewport,
            texture: None,
            frame_info: String::new(),
            hdr_rig_pending: false,
            ab: AbView::Both,
            framed_for: None,
            show_before: false,
            difference_shown: None,
            last_frame: None,
            radiance: None,
            background_map: None,
            show_mouse_hint: false,
            adapter: String::new(),
            quality: None,
            history: Default::default(),
            truth_phase: None,
            last_wheel: None,
            b_look: None,
        }
    }
}

impl Report {
    /// "Ready." and the frame log (`SCATTERLAB_FRAME_LOG`) opened.
    pub(super) fn new() -> Self {
        Self {
        status:
            "Ready. Drag a preset (.ron), mesh (.obj/.gltf/.glb) or environment (.hdr) onto the window to open it."
                .into(),
        notices: Vec::new(),
        status_seen: String::new(),
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
        ui_ms: 0.0,
        logged_status: String::new(),
        started: std::time::Instant::now(),
        reported: (false, false),
        last_title: String::new(),}
    }
}

/// What the viewport shows and how far it got (the editor's tests read
/// these through [`EditorApp::viewport`]).
impl ViewportState {
    /// While comparing: both sides, or A or B alone.
    pub fn ab(&self) -> AbView {
        self.ab
    }

    /// Whether the viewport shows the look before the last edit.
    pub fn show_before(&self) -> bool {
        self.show_before
    }

    /// The status bar's viewport readout (method, size, time, adapter).
    pub fn frame_info(&self) -> &str {
        &self.frame_info
    }

    /// Whether the viewport has shown a rendered frame.
    pub fn has_frame(&self) -> bool {
        self.texture.is_some()
    }

    /// The last viewport frame and the number of frames received so far.
    pub fn frame(&self) -> Option<(&image::RgbaImage, u64)> {
        self.last_frame.as_ref().map(|(i, n)| (i, *n))
    }

    /// How far the last viewport frame had got.
    pub fn quality(&self) -> Option<viewport::Quality> {
        self.quality
    }

    /// The newest viewport frames (up to [`overlays::FRAME_HISTORY`]) as they
    /// arrived: quality, size and the status line each set.
    pub fn history(&self) -> impl Iterator<Item = &(viewport::Quality, (u32, u32), String)> + '_ {
        self.history.iter()
    }

    /// Whether the viewport has rendered everything asked of it.
    pub fn idle(&self) -> bool {
        self.viewport
            .as_ref()
            .is_none_or(|v| v.busy_since.is_none())
    }

    /// The viewport's last request (what a turntable turns).
    pub(super) fn request(&self) -> Option<viewport::Request> {
        self.viewport
            .as_ref()
            .and_then(|v| v.last_request())
            .cloned()
    }

    /// The scale (white, |ΔL*|) of the difference view on screen, if any.
    pub fn difference_scale_shown(&self) -> Option<f32> {
        self.difference_shown
    }

    /// Makes the render thread fail on its next request (tests of the
    /// recovery; nothing in the editor calls it).
    #[doc(hidden)]
    pub fn inject_fault(&self, fault: viewport::Fault) {
        if let Some(v) = &self.viewport {
            v.inject_fault(fault);
        }
    }
}
