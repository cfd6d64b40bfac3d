//! The viewport panel as a type (issue 51), as Rerun's panels are: it
//! borrows the viewport's state, what it shows (the look, its mesh, the
//! view and compare settings) and where it draws, and returns what else it
//! changes as [`Action`]s for `EditorApp::apply`: the camera and light the
//! mouse moved ([`Action::SetView`]), lines for the status bar and the
//! frame log, a loaded mesh to frame. Each frame it takes the mouse's
//! orbit, light, pan and zoom, sends the render thread what to show (only
//! when that changed) and takes in its replies; what is drawn over the
//! frame is `overlays.rs`. Its toolbars are `toolbars.rs`'s.

use super::windows::{reference::ReferenceWindow, Action};
use super::*;

/// Viewport frames kept in [`ViewportState::history`].
pub(super) const FRAME_HISTORY: usize = 256;

/// The viewport panel for one frame.
pub(super) struct ViewportPanel<'a> {
    /// The viewport's own state: its render thread, the frame shown, A/B
    /// and "before", B's look read from its file.
    pub view: &'a mut ViewportState,
    /// The camera and light as this frame's mouse leaves them (returned
    /// as [`Action::SetView`] where they changed).
    pub camera: state::ViewState,
    pub ui_state: &'a UiState,
    pub doc: &'a Document,
    pub meshes: &'a MeshState,
    /// Where the viewport, its labels and the probe were drawn.
    pub layout: &'a mut Layout,
    /// Look A's albedo (B from an engine that keeps the albedo in the
    /// material is drawn with it: [`crate::settings::albedo::b_as_drawn`]).
    pub a_albedo: crate::model::Rgb,
    /// The look can be drawn: its rendering settings are valid and its
    /// curves did not fail.
    pub valid: bool,
    /// The status line as the frame began (a mesh loading shows the
    /// bake's progress; a mesh that arrives in this frame replaces it when
    /// its reply is applied, and the frame is drawn again then).
    pub status: String,
    /// The names of A and B, for the compare labels.
    pub names: (String, String),
    /// The reference photograph drawn over the frame, if one is shown.
    pub reference: &'a ReferenceWindow,
    /// A file dialog or a modal prompt is up (the probe stands down).
    pub dialog_up: bool,
    /// What this frame asks for, in order.
    pub actions: Vec<Action>,
}

impl ViewportPanel<'_> {
    /// Draws the viewport and takes its input; what it asks of the rest
    /// of the editor. A loaded mesh's framing comes last, after the
    /// mouse's view.
    pub(super) fn show(mut self, ui: &mut egui::Ui) -> Vec<Action> {
        let framing = self.meshes.framing_distance_m();
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
        // Named for AccessKit: tools that drive the window find it so.
        response.widget_info(|| {
            egui::WidgetInfo::labeled(egui::accesskit::Role::Canvas, true, "Viewport")
        });
        self.input(ui, rect, &response, framing);
        // The ground truth's next tiles are those nearest the pointer.
        if let Some(vp) = &self.view.viewport {
            let at = response.hover_pos().map(|p| {
                let f = (p - rect.min) / rect.size();
                [f.x, f.y]
            });
            vp.set_focus(at);
        }
        // The mouse's meaning, inside the viewport (a tooltip at the
        // pointer covered the status bar).
        self.view.show_mouse_hint = response.hovered() && !response.dragged();
        let req = self.frame_request(ui, rect);
        let interactive = req.interactive;
        let display = req.view.tone_map.label();
        let turn = req.view.background.turn_deg;
        let fill = req.view.orbit.fill.intensity;
        let valid = self.valid;
        let (replies, sent) = match self.view.viewport.as_mut() {
            Some(vp) => {
                let before = vp.seq();
                if valid {
                    vp.request(req);
                }
                (vp.poll(), (vp.seq() != before).then(|| vp.seq()))
            }
            None => (Vec::new(), None),
        };
        // Each new request in the frame log: what the render thread was
        // asked for, and when (tools/measure_live.sh's profile).
        if let Some(seq) = sent {
            self.actions.push(Action::Log(format!(
                "request seq={seq} interactive={} turn={turn} fill={fill} display={display}",
                u8::from(interactive)
            )));
        }
        let mut replied = Vec::new();
        for reply in replies {
            replied.extend(self.view.receive(ui.ctx(), reply));
        }
        self.overlays_ui(ui, rect);
        let mut actions = std::mem::take(&mut self.actions);
        if self.camera != self.ui_state.view {
            actions.push(Action::SetView(self.camera));
        }
        actions.extend(replied);
        actions
    }

    /// Orbit (left drag), light (right or Shift+drag), pan (middle drag)
    /// and zoom (wheel, within 0.15–8× `framing`).
    fn input(&mut self, ui: &egui::Ui, rect: egui::Rect, response: &egui::Response, framing: f32) {
        // Orbit (left drag), light (right drag or shift+drag), pan (middle drag), zoom (wheel).
        let v = &mut self.camera;
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
                self.view.last_wheel = Some(std::time::Instant::now());
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
        let b = if self.ui_state.compare == CompareMode::Off || self.view.ab == AbView::A {
            None
        } else {
            let b_look = match &self.ui_state.compare_b {
                CompareB::Preset(path) => {
                    let modified = std::fs::metadata(path).and_then(|m| m.modified()).ok();
                    let entry = match self.view.b_look.take() {
                        Some(e) if e.0 == *path && e.1 == modified => e,
                        _ => (path.clone(), modified, viewport::load_look(path)),
                    };
                    let look = entry.2.clone().map(|p| {
                        let (p, map_colour, _) = crate::settings::albedo::b_as_drawn(
                            p,
                            self.a_albedo,
                            self.ui_state.b_material_albedo,
                            self.ui_state.map_colour,
                            self.meshes.colour_map_mean(),
                        );
                        viewport::Look::of(&p).with_map_colour(map_colour)
                    });
                    self.view.b_look = Some(entry);
                    look
                }
                b => viewport::b_look(&self.doc.preset, b)
                    .map(|l| l.with_map_colour(self.ui_state.map_colour)),
            };
            match b_look {
                Ok(l) => Some((l, self.ui_state.compare, self.ui_state.split)),
                Err(e) => {
                    self.actions
                        .push(Action::Say(format!("Error: compare B: {e}")));
                    None
                }
            }
        };
        // Live input: anything dragged (the orbit, a slider, a panel edge)
        // or the wheel in the last quarter second. Previews while it lasts;
        // the full frame, refined, once it stops.
        let wheel_recent = self
            .view
            .last_wheel
            .is_some_and(|t| t.elapsed() < std::time::Duration::from_millis(250));
        if wheel_recent {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(260));
        }
        let interactive = ui.ctx().dragged_id().is_some() || wheel_recent;
        let difference_scale = (self.ui_state.compare == CompareMode::Difference
            && !self.ui_state.difference_auto)
            .then_some(self.ui_state.difference_scale);
        let req = viewport::Request {
            difference_scale,
            interactive,
            refine_to_truth: self.ui_state.refine_to_truth,
            a: viewport::Look::of(
                self.view
                    .show_before
                    .then(|| self.doc.before_last_edit())
                    .flatten()
                    .unwrap_or(&self.doc.preset),
            )
            .with_map_colour(self.ui_state.map_colour),
            b,
            show_b: self.view.ab == AbView::B && self.ui_state.compare != CompareMode::Off,
            view: self.camera,
            size,
            mesh: self.meshes.mesh.clone(),
            seq: 0,
            background_map: self.view.background_map.clone(),
            want_radiance: true,
            mesh_settings: self
                .meshes
                .mesh
                .as_ref()
                .and_then(|p| self.ui_state.meshes.get(p))
                .cloned()
                .unwrap_or_default(),
        };
        req
    }
}

impl ViewportState {
    /// One reply from the render thread taken in: a frame to show (and
    /// its line in the frame log), an error or warning to say, or a
    /// loaded mesh to frame ([`Action::MeshLoaded`]).
    pub(super) fn receive(&mut self, ctx: &egui::Context, reply: viewport::Reply) -> Vec<Action> {
        let mut actions = Vec::new();
        match reply {
            viewport::Reply::Frame {
                difference_scale,
                image,
                stats,
                wall_ms,
                note,
                quality,
                seq,
                radiance,
            } => {
                self.radiance = radiance;
                // A ground truth in tiles adds how far it has got and the
                // time left it showed (tools/measure_live.sh checks both).
                let tiles = match quality {
                    viewport::Quality::Truth {
                        done,
                        tiles,
                        left_s,
                        ..
                    } => format!(
                        " tiles={done}/{tiles} left_s={}",
                        left_s.map_or("none".into(), |s| format!("{s:.2}"))
                    ),
                    _ => String::new(),
                };
                actions.push(Action::Log(format!(
                    "frame {} {}x{} seq={seq} render_ms={wall_ms:.1} method={}{tiles}",
                    match quality {
                        viewport::Quality::Preview { .. } => "preview",
                        viewport::Quality::Coarse { .. } => "coarse",
                        viewport::Quality::Truth { .. } => "truth-tiles",
                        viewport::Quality::Refining { .. } => "refining",
                        viewport::Quality::Converged { .. } => "converged",
                    },
                    image.width(),
                    image.height(),
                    stats.method,
                )));
                self.quality = Some(quality);
                self.difference_shown = difference_scale;
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
                self.frame_info = frame_info(&stats, quality, wall_ms, note);
                // The driver in the frame log, and an old lavapipe named
                // once, with its upgrade.
                if self.adapter.is_empty() {
                    actions.push(Action::Log(format!("driver {}", stats.driver)));
                    if let Some(advice) = &stats.driver_advice {
                        actions.push(Action::Say(format!("Warning: {advice}")));
                    }
                }
                self.adapter = format!("{}; driver {}", stats.adapter, stats.driver);
                let size = (self.last_frame.as_ref()).map_or((0, 0), |f| f.0.dimensions());
                self.history
                    .push_back((quality, size, self.frame_info.clone()));
                if self.history.len() > FRAME_HISTORY {
                    self.history.pop_front();
                }
            }
            // The same request is not sent again (it would fail
            // again); the next change renders.
            viewport::Reply::Error(e) => actions.push(Action::Say(format!("Error: viewport: {e}"))),
            viewport::Reply::Recovered { message, .. } => {
                // In the log too: a soak or a bug report counts them.
                eprintln!("warning: {message}");
                actions.push(Action::Say(format!("Warning: {message}")))
            }
            viewport::Reply::MeshLoaded(p, info) => actions.push(Action::MeshLoaded(p, info)),
            viewport::Reply::MeshFailed {
                asked,
                error,
                kept,
                kept_settings,
            } => actions.push(Action::MeshFailed {
                asked,
                error,
                kept,
                kept_settings,
            }),
        }
        actions
    }
}

/// The status bar's line for a frame: method, how far it got, size, time
/// (the SSS pass's too), the note, and the adapter's first words (its
/// whole name on hover).
fn frame_info(
    stats: &crate::render::FrameStats,
    quality: viewport::Quality,
    wall_ms: f64,
    note: Option<String>,
) -> String {
    format!(
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
        stats.adapter.split(" (").next().unwrap_or(&stats.adapter)
    )
}
