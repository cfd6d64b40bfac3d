//! What the editor shows, read back: the accessors the UI tests, the
//! window tests and the screenshot tools use to see the editor's state
//! without reaching into its parts, and the test-only fault switches
//! (`doc(hidden)`) that `tests/ui/recovery.rs` turns on.

use super::analysis::Analysis;
use super::{plots, viewport, AbView, EditorApp, ViewportLayout};
use std::path::Path;

impl EditorApp {
    /// While comparing: both sides, or A or B alone.
    pub fn ab(&self) -> AbView {
        self.view.ab
    }

    /// Whether the viewport shows the look before the last edit.
    pub fn show_before(&self) -> bool {
        self.view.show_before
    }

    /// Where the profile plot was drawn (UI tests).
    pub fn plot_rect(&self) -> Option<egui::Rect> {
        self.layout.plot_rect
    }

    /// The latest finished analysis of the look (fits, tables), if any.
    pub fn latest_analysis(&self) -> Option<&Analysis> {
        self.profile.latest.as_ref()
    }

    /// Whether the plot's radius axis is logarithmic now (set, or
    /// automatic for these curves).
    pub fn plot_log_radius(&self) -> bool {
        self.ui_state.log_radius.unwrap_or_else(
            || matches!(&self.profile.curves, Some(Ok(c)) if plots::auto_log_radius(c)),
        )
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

    /// The status bar's viewport readout (method, size, time, adapter).
    pub fn frame_info(&self) -> &str {
        &self.view.frame_info
    }

    /// Whether the viewport has shown a rendered frame.
    pub fn has_viewport_frame(&self) -> bool {
        self.view.texture.is_some()
    }

    /// The last viewport frame and the number of frames received so far.
    pub fn viewport_frame(&self) -> Option<(&image::RgbaImage, u64)> {
        self.view.last_frame.as_ref().map(|(i, n)| (i, *n))
    }

    /// The viewport's rect, the compare labels drawn on it (text, rect),
    /// and the left and right panels' rects, as last drawn.
    pub fn viewport_layout(&self) -> ViewportLayout {
        ViewportLayout {
            viewport: self.layout.viewport_rect,
            labels: self.layout.compare_labels.clone(),
            params: self.layout.panel_rects[0],
            plots: self.layout.panel_rects[1],
        }
    }

    /// How far the last viewport frame had got.
    pub fn viewport_quality(&self) -> Option<viewport::Quality> {
        self.view.quality
    }

    /// Whether the viewport has rendered everything asked of it.
    pub fn viewport_idle(&self) -> bool {
        self.view
            .viewport
            .as_ref()
            .is_none_or(|v| v.busy_since.is_none())
    }

    /// The loaded mesh's size and framing, once the viewport has it.
    pub fn mesh_info(&self) -> Option<viewport::MeshInfo> {
        self.meshes.mesh_info
    }

    /// The mesh the viewport is asked to show (`None`: the default head).
    pub fn mesh_path(&self) -> Option<&Path> {
        self.meshes.mesh.as_deref()
    }

    /// The mesh whose units prompt is open.
    pub fn units_prompt_for(&self) -> Option<&Path> {
        self.meshes.units_prompt.as_deref()
    }

    /// Whether the unsaved-changes prompt is waiting for an answer.
    pub fn prompt_open(&self) -> bool {
        self.dialogs.pending.is_some()
    }

    /// Whether a modal prompt is up: unsaved changes, replace existing
    /// files, or recover an earlier editor's work.
    pub fn modal_prompt_open(&self) -> bool {
        self.dialogs.pending.is_some()
            || self.dialogs.overwrite.is_some()
            || self.autosave.as_ref().is_some_and(|a| a.found.is_some())
    }

    /// Makes the render thread fail on its next request (tests of the
    /// recovery; nothing in the editor calls it).
    #[doc(hidden)]
    pub fn inject_render_fault(&self, fault: viewport::Fault) {
        if let Some(v) = &self.view.viewport {
            v.inject_fault(fault);
        }
    }

    /// Makes the next analysis panic (tests of the recovery).
    #[doc(hidden)]
    pub fn inject_analysis_panic(&self) {
        self.profile.analysis.inject_panic();
    }

    /// The status bar's message.
    pub fn status(&self) -> &str {
        &self.report.status
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

    /// Whether the Maps window's previews are computed (UI tests).
    pub fn maps_preview_ready(&self) -> bool {
        self.meshes.maps_preview.as_ref().is_some_and(|p| p.ready())
    }

    /// The whole editor for one frame.
    /// The scale (white, |ΔL*|) of the difference view on screen, if any.
    pub fn difference_scale_shown(&self) -> Option<f32> {
        self.view.difference_shown
    }

    /// The notifications on screen (errors and warnings not yet dismissed).
    pub fn notices(&self) -> &[String] {
        &self.report.notices
    }
}
