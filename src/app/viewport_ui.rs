//! The viewport panel: its toolbars, the mouse's orbit, pan and zoom, its
//! keys, the request each frame makes of the render thread and the replies
//! (a loaded mesh framed, a restored one kept as it was); what is drawn
//! over the frame is `overlays.rs`.

use super::windows::Window;
use super::*;

impl EditorApp {
    pub(super) fn viewport_panel_ui(&mut self, ui: &mut egui::Ui) {
        // Camera distance that frames the mesh (Reset view, zoom limits).
        let framing = self.meshes.mesh_info.map_or(
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
        // Named for AccessKit: tools that drive the window find it so.
        response.widget_info(|| {
            egui::WidgetInfo::labeled(egui::accesskit::Role::Canvas, true, "Viewport")
        });
        self.viewport_input(ui, rect, &response, framing);
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
        let valid = self.doc.preset.rendering.validate().is_ok()
            && !matches!(self.profile.curves, Some(Err(_)));
        let interactive = req.interactive;
        let display = req.view.tone_map.label();
        let turn = req.view.background.turn_deg;
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
            self.log_line(format_args!(
                "request seq={seq} interactive={} turn={turn} display={display}",
                u8::from(interactive)
            ));
        }
        for reply in replies {
            self.handle_reply(ui.ctx(), reply);
        }
        self.viewport_overlays_ui(ui, rect);
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
            self.handle_reply(ctx, reply);
        }
    }

    /// The compare toolbar ([`toolbars::CompareBar`]).
    pub(super) fn compare_toolbar_ui(&mut self, ui: &mut egui::Ui) {
        let b_file = match &self.profile.b_look_cache {
            Some((_, _, Ok(b))) if matches!(self.ui_state.compare_b, CompareB::Preset(_)) => {
                Some(b)
            }
            _ => None,
        };
        let readout = match (&self.ui_state.compare_b, self.profile.b_curves.as_ref()) {
            (CompareB::Preset(_), Some((_, Ok((_, _, d))))) => Some(toolbars::BReadout {
                difference: *d,
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

    /// The view toolbar ([`toolbars::ViewBar`]). `framing`: the camera
    /// distance that frames the mesh (m).
    pub(super) fn view_toolbar_ui(&mut self, ui: &mut egui::Ui, framing: f32) {
        let bar = toolbars::ViewBar {
            view: self.ui_state.view,
            environment_file: self.ui_state.environment_file.as_deref(),
            refine_to_truth: self.ui_state.refine_to_truth,
            framing,
            mesh_items: if self.meshes.mesh.is_some() {
                self.windows.items(windows::Menu::Mesh)
            } else {
                Vec::new()
            },
        };
        let actions = bar.ui(ui);
        self.apply(actions);
    }

    /// Orbit (left drag), light (right or Shift+drag), pan (middle drag)
    /// and zoom (wheel, within 0.15–8× `framing`).
    pub(super) fn viewport_input(
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
    pub(super) fn frame_request(&mut self, ui: &egui::Ui, rect: egui::Rect) -> viewport::Request {
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
                    let entry = match self.profile.b_look_cache.take() {
                        Some(e) if e.0 == *path && e.1 == modified => e,
                        _ => (path.clone(), modified, viewport::load_look(path)),
                    };
                    let look = entry.2.clone().map(|p| {
                        let (p, map_colour, _) = self.b_drawn(p);
                        viewport::Look::of(&p).with_map_colour(map_colour)
                    });
                    self.profile.b_look_cache = Some(entry);
                    look
                }
                b => viewport::b_look(&self.doc.preset, b)
                    .map(|l| l.with_map_colour(self.ui_state.map_colour)),
            };
            match b_look {
                Ok(l) => Some((l, self.ui_state.compare, self.ui_state.split)),
                Err(e) => {
                    self.say(format!("Error: compare B: {e}"));
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
            view: self.ui_state.view,
            size,
            mesh: self.meshes.mesh.clone(),
            seq: 0,
            background_map: self.view.background_map.clone(),
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

    /// One reply from the render thread: a frame to show, an error, or a
    /// loaded mesh to frame.
    pub(super) fn handle_reply(&mut self, ctx: &egui::Context, reply: viewport::Reply) {
        match reply {
            viewport::Reply::Frame {
                difference_scale,
                image,
                stats,
                wall_ms,
                note,
                quality,
                seq,
            } => {
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
                self.log_line(format_args!(
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
                ));
                self.view.quality = Some(quality);
                self.view.difference_shown = difference_scale;
                let ci = egui::ColorImage::from_rgba_unmultiplied(
                    [image.width() as usize, image.height() as usize],
                    image.as_raw(),
                );
                let n = self.view.last_frame.as_ref().map_or(0, |f| f.1) + 1;
                self.view.last_frame = Some((image, n));
                match &mut self.view.texture {
                    Some(t) => t.set(ci, egui::TextureOptions::LINEAR),
                    None => {
                        self.view.texture =
                            Some(ctx.load_texture("viewport", ci, egui::TextureOptions::LINEAR))
                    }
                }
                self.view.frame_info = format!(
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
                    // The adapter's first words (its whole name on hover).
                    stats.adapter.split(" (").next().unwrap_or(&stats.adapter)
                );
                // The driver in the frame log, and an old lavapipe named
                // once, with its upgrade.
                if self.view.adapter.is_empty() {
                    self.log_line(format_args!("driver {}", stats.driver));
                    if let Some(advice) = &stats.driver_advice {
                        self.say(format!("Warning: {advice}"));
                    }
                }
                self.view.adapter = format!("{}; driver {}", stats.adapter, stats.driver);
                let size = (self.view.last_frame.as_ref()).map_or((0, 0), |f| f.0.dimensions());
                self.view
                    .history
                    .push_back((quality, size, self.view.frame_info.clone()));
                if self.view.history.len() > super::overlays::FRAME_HISTORY {
                    self.view.history.pop_front();
                }
            }
            // The same request is not sent again (it would fail
            // again); the next change renders.
            viewport::Reply::Error(e) => self.say(format!("Error: viewport: {e}")),
            viewport::Reply::Recovered { message, .. } => {
                // In the log too: a soak or a bug report counts them.
                eprintln!("warning: {message}");
                self.say(format!("Warning: {message}"))
            }
            viewport::Reply::MeshLoaded(p, info) => self.mesh_loaded(p, info),
        }
    }

    /// The render thread loaded a mesh (`None`: the default head): frame
    /// it (a mesh the artist loads, or new units of it; the default head at
    /// start-up keeps the remembered view), ask its units if new, say it.
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
        // mesh that failed to load is replaced by the head after
        // an error, which the arms below handle.)
        if p.is_none() && self.meshes.mesh.is_some() && !self.status().starts_with("Error") {
            return;
        }
        self.meshes.mesh_info = Some(info);
        // Frame a mesh the artist loads, or new units of
        // it; the default head at start-up keeps the
        // remembered view.
        let key = (p.clone(), info.metres_per_unit);
        let first_head = self.view.framed_for.is_none() && p.is_none();
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
        if let Some(p) = &p {
            if !self.ui_state.meshes.contains_key(p) {
                self.windows.units.set_open(true);
            }
        }
        match &p {
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

    /// The viewport's keys (not while typing in a field): F frames the
    /// mesh (as Blender, Maya and Substance do: the camera's distance and
    /// pan reset, its direction kept); Backslash flickers to the look
    /// before the last edit (Lightroom's before/after key); Escape closes
    /// the topmost window, else while comparing goes back to the mode's
    /// view; while comparing, Space (`toggle`) flips between B alone and A
    /// alone (from the mode's own view it shows B first).
    pub(super) fn viewport_keys(&mut self, ctx: &egui::Context, toggle: bool) {
        use egui::{Key, Modifiers};
        let free = ctx.memory(|m| m.focused().is_none());
        if free && ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::F)) {
            let framing = self.meshes.mesh_info.map_or(
                crate::settings::OrbitView::default().camera_distance_m,
                |i| i.framing_distance_m,
            );
            let o = &mut self.ui_state.view.orbit;
            o.camera_distance_m = framing;
            o.camera_pan_m = crate::settings::OrbitView::default().camera_pan_m;
            self.say("Framed the mesh (F)");
        }
        if free
            && ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::Backslash))
            && self.doc.before_last_edit().is_some()
        {
            self.view.show_before = !self.view.show_before;
        }
        // Escape in a field being typed into or in an open list is theirs
        // (it cancels the edit, closes the list), not the window's.
        if ctx.input(|i| i.key_pressed(Key::Escape))
            && free
            && !egui::Popup::is_any_open(ctx)
            && self.close_topmost_window(ctx)
        {
            ctx.input_mut(|i| i.consume_key(Modifiers::NONE, Key::Escape));
            return;
        }
        let escape = ctx.input(|i| i.key_pressed(Key::Escape));
        if ctx.memory(|m| m.focused().is_none()) && self.ui_state.compare != CompareMode::Off {
            if toggle {
                self.view.ab = match self.view.ab {
                    AbView::B => AbView::A,
                    AbView::Both | AbView::A => AbView::B,
                };
            } else if escape {
                self.view.ab = AbView::Both;
            }
        }
    }

    /// What the status bar shows of the viewport and the work under way.
    pub(super) fn status_bar_view(&self) -> report::StatusBarView<'_> {
        report::StatusBarView {
            busy: self.busy(),
            frame_info: self.viewport().frame_info(),
            adapter: &self.view.adapter,
        }
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
}
