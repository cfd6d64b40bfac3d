//! The viewport panel: its toolbars, the mouse's orbit, pan and zoom, the
//! request each frame makes of the render thread, the replies, and the
//! overlays and compare labels drawn over the frame.

use super::*;

impl EditorApp {
    pub(super) fn viewport_panel(&mut self, ui: &mut egui::Ui) {
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
        self.viewport_input(ui, rect, &response, framing);
        response.on_hover_text("Left drag: orbit · right or Shift+drag: light · middle drag: pan · wheel: zoom · Space: A/B");
        let req = self.frame_request(ui, rect);
        let valid = self.doc.preset.rendering.validate().is_ok()
            && !matches!(self.profile.curves, Some(Err(_)));
        let replies = match self.view.viewport.as_mut() {
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
    pub(super) fn compare_toolbar_ui(&mut self, ui: &mut egui::Ui) {
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
                    .selectable_label(self.ui_state.compare == m && self.view.ab == AbView::Both, name)
                    .clicked()
                {
                    self.ui_state.compare = m;
                    self.view.ab = AbView::Both;
                }
            }
            let before = self.doc.before_last_edit().is_some();
            if !before {
                self.view.show_before = false;
            }
            ui.add_enabled_ui(before, |ui| {
                ui.toggle_value(&mut self.view.show_before, "before")
                    .on_hover_text("Flicker: show the look as it was before the last edit (F toggles), to see what the edit changed.")
                    .on_disabled_hover_text("No edit yet to compare with.");
            });
            let none = CompareB::Method(crate::settings::rendering::MethodId::None);
            let sss_only = self.ui_state.compare == CompareMode::Difference
                && self.ui_state.compare_b == none
                && self.view.ab == AbView::Both;
            if ui
                .selectable_label(sss_only, "SSS only")
                .on_hover_text("What scattering adds: the difference view of this look against the same look without SSS (method none), |ΔL*| on the fixed scale at the right edge. Click again to go back.")
                .clicked()
            {
                if sss_only {
                    self.ui_state.compare = CompareMode::Off;
                } else {
                    self.ui_state.compare = CompareMode::Difference;
                    self.ui_state.compare_b = none;
                    self.view.ab = AbView::Both;
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
                    if ui
                        .button("a preset or engine file…")
                        .on_hover_text("B is the look in a preset, or what an engine draws from its file (Unity .asset, Unreal text, MaterialX, Godot .tres, Blender .py), with how far its r·R(r) is from A")
                        .clicked()
                    {
                        self.open_dialog(DialogKind::CompareB);
                        ui.close();
                    }
                });
                // How far a file's look is from A: what the round trip costs.
                if let (CompareB::Preset(_), Some((_, Ok((_, _, d))))) =
                    (&self.ui_state.compare_b, self.profile.b_curves.as_ref())
                {
                    ui.label(format!(
                        "B − A: {:.1} / {:.1} / {:.1} %",
                        100.0 * d[0],
                        100.0 * d[1],
                        100.0 * d[2]
                    ))
                    .on_hover_text("Relative L2 difference of r·R(r) between B's look and A's, per channel (to A's 99.7 % radius): for a file exported from A, the round-trip error of that engine.");
                }
                if self.ui_state.compare == CompareMode::Difference {
                    ui.add_enabled(
                        !self.ui_state.difference_auto,
                        egui::DragValue::new(&mut self.ui_state.difference_scale)
                            .range(0.1..=100.0)
                            .speed(0.05)
                            .max_decimals(1)
                            .prefix("white = ")
                            .suffix(" ΔL*"),
                    )
                    .on_hover_text("The difference that shows white: |A − B| of CIE lightness L* (0 black, 100 white; about 1 is just noticeable side by side). Fixed, so compares read on one scale.");
                    ui.checkbox(&mut self.ui_state.difference_auto, "auto")
                        .on_hover_text("Scale each difference view to its own largest difference instead (the scale then changes with every pair).");
                }
                if self.ui_state.compare == CompareMode::Split {
                    ui.spacing_mut().slider_width = 90.0;
                    ui.add(egui::Slider::new(&mut self.ui_state.split, 0.0..=1.0).text("split"))
                        .on_hover_text("Where the split line sits: A left of it, B right.");
                }
                for (side, name) in [(AbView::A, "A alone"), (AbView::B, "B alone")] {
                    if ui
                        .selectable_label(self.view.ab == side, name)
                        .on_hover_text(format!(
                            "Space flips between A alone and B alone (A: {a_name}, B: {b_name})."
                        ))
                        .clicked()
                    {
                        self.view.ab = if self.view.ab == side { AbView::Both } else { side };
                    }
                }
            }
        });
    }

    /// Environment, light (rigs and intensity), exposure, Reset view, and a
    /// loaded mesh's Units… and Maps…: one row at 1280×720 (the environment
    /// and the light are menus, the intensity inside the light's). It wraps
    /// only where the viewport is narrower still. `framing`: the camera
    /// distance that frames the mesh (m).
    pub(super) fn view_toolbar_ui(&mut self, ui: &mut egui::Ui, framing: f32) {
        let mut open_environment = false;
        ui.horizontal_wrapped(|ui| {
            let v = &mut self.ui_state.view;
            let map_name = self
                .ui_state
                .environment_file
                .as_ref()
                .and_then(|p| p.file_name())
                .map_or("HDR map".into(), |n| n.to_string_lossy().into_owned());
            let current = match v.environment {
                state::EnvironmentChoice::Studio => "studio sky".to_owned(),
                state::EnvironmentChoice::Black => "black".to_owned(),
                state::EnvironmentChoice::Map => map_name.clone(),
            };
            let env = egui::ComboBox::from_id_salt("environment")
                .selected_text(current.clone())
                .show_ui(ui, |ui| {
                    ui.selectable_value(
                        &mut v.environment,
                        state::EnvironmentChoice::Studio,
                        "studio sky",
                    )
                    .on_hover_text("The procedural studio sky.");
                    ui.selectable_value(&mut v.environment, state::EnvironmentChoice::Black, "black")
                        .on_hover_text("No environment light: the key light alone.");
                    if v.environment_map_sh.is_some() {
                        let tip = self.ui_state.environment_file.as_ref().map_or(
                            "The last HDR map loaded.".into(),
                            |p| {
                                format!(
                                    "{} (its irradiance, as order-2 spherical harmonics)",
                                    p.display()
                                )
                            },
                        );
                        ui.selectable_value(
                            &mut v.environment,
                            state::EnvironmentChoice::Map,
                            map_name,
                        )
                        .on_hover_text(tip);
                    }
                    if ui
                        .button("HDR map…")
                        .on_hover_text(
                            "Light the head with an equirectangular Radiance .hdr map \
                             (or drop one onto the window).",
                        )
                        .clicked()
                    {
                        open_environment = true;
                        ui.close();
                    }
                })
                .response;
            env.widget_info(|| {
                let mut info =
                    egui::WidgetInfo::labeled(egui::accesskit::Role::ComboBox, true, "Environment");
                info.current_text_value = Some(current.clone());
                info
            });
            env.on_hover_text("Environment: what lights the head besides the key light.");
            let current = state::LightRig::current(v);
            let rig_label = current.map_or("Light: custom".to_owned(), |r| format!("Light: {}", r.label()));
            ui.menu_button(rig_label, |ui| {
                for rig in state::LightRig::ALL {
                    if ui
                        .selectable_label(current == Some(rig), rig.label())
                        .on_hover_text(rig.tip())
                        .clicked()
                    {
                        if !rig.apply(v) {
                            // The HDR rig with no map loaded: ask for one;
                            // the map lights the head once it has loaded.
                            open_environment = true;
                            self.view.hdr_rig_pending = true;
                        }
                        ui.close();
                    }
                }
                ui.separator();
                ui.add(
                    egui::DragValue::new(&mut v.orbit.light_intensity)
                        .range(0.0..=50.0)
                        .speed(0.05)
                        .prefix("intensity "),
                )
                .on_hover_text("Irradiance of the key light (linear).");
                ui.add(
                    egui::DragValue::new(&mut v.orbit.exposure)
                        .range(0.01..=20.0)
                        .speed(0.01)
                        .prefix("exposure "),
                )
                .on_hover_text("Multiplier before tonemapping.");
            })
            .response
            .on_hover_text("Lighting set-ups that show scattering, each one click: the key light's direction is relative to the camera. Right-drag the view or drag the light gizmo (bottom right) to move the light. The key light's intensity and the exposure are in here too.");
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
            ui.checkbox(&mut self.ui_state.refine_to_truth, "refine to the truth")
                .on_hover_text(
                    "Once the method's frame has converged, go on to the ground truth (reference) of the same view and keep it as the converged state: a coarse one first, then the full frame, with progress and the time left. A alone; while comparing, the two sides stay as they are.",
                );
            if let Some(p) = self.meshes.mesh.clone() {
                if ui
                    .button("Units…")
                    .on_hover_text("Metres per unit of this mesh: its size, the camera and the scattering distances in mm depend on it.")
                    .clicked()
                {
                    self.meshes.units_prompt = Some(p.clone());
                }
                if ui
                    .button("Maps…")
                    .on_hover_text("This mesh's albedo, normal, roughness, SSS mask and thickness maps: files, V-flip and colour space.")
                    .clicked()
                {
                    self.meshes.maps_window = Some(p);
                }
            }
        });
        if open_environment {
            self.open_dialog(DialogKind::Environment);
        }
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
                    let look = entry.2.clone().map(|p| viewport::Look::of(&p));
                    self.profile.b_look_cache = Some(entry);
                    look
                }
                b => viewport::b_look(&self.doc.preset, b),
            };
            match b_look {
                Ok(l) => Some((l, self.ui_state.compare, self.ui_state.split)),
                Err(e) => {
                    self.report.status = format!("Error: compare B: {e}");
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
            ),
            b,
            show_b: self.view.ab == AbView::B && self.ui_state.compare != CompareMode::Off,
            view: self.ui_state.view,
            size,
            mesh: self.meshes.mesh.clone(),
            seq: 0,
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
                if let Some(log) = self.report.frame_log.as_mut() {
                    use std::io::Write;
                    let _ = writeln!(
                        log,
                        "{:.3} frame {} {}x{} seq={seq} render_ms={wall_ms:.1} method={}",
                        unix_seconds(),
                        match quality {
                            viewport::Quality::Preview { .. } => "preview",
                            viewport::Quality::Coarse { .. } => "coarse",
                            viewport::Quality::Refining { .. } => "refining",
                            viewport::Quality::Converged { .. } => "converged",
                        },
                        image.width(),
                        image.height(),
                        stats.method,
                    );
                }
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
                    stats.adapter
                );
            }
            // The same request is not sent again (it would fail
            // again); the next change renders.
            viewport::Reply::Error(e) => self.report.status = format!("Error: viewport: {e}"),
            viewport::Reply::MeshLoaded(p, info) => {
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
                        self.report.status = format!(
                            "The remembered view showed about {:.0} % of the head: framed the whole head (Reset view does the same)",
                            100.0 * seen
                        );
                    }
                }
                self.view.framed_for = Some(key);
                if let Some(p) = &p {
                    if !self.ui_state.meshes.contains_key(p) {
                        self.meshes.units_prompt = Some(p.clone());
                    }
                }
                match &p {
                    Some(p) => self.report.status = format!("Mesh {}", p.display()),
                    // The first load of the default head is not news.
                    // After a failed load the error stays readable.
                    None if self.report.status.starts_with("Error") => {
                        self.report.status.push_str(" (showing the default head)");
                        self.meshes.mesh = None;
                    }
                    None if self.meshes.mesh.is_some()
                        || self.report.status.starts_with("Loading") =>
                    {
                        self.report.status = "Default head".into();
                        self.meshes.mesh = None;
                    }
                    None => {}
                }
            }
        }
    }

    /// What is drawn over the viewport: the frame, progress bars, the
    /// compare labels and the rendering note.
    pub(super) fn viewport_overlays_ui(&mut self, ui: &mut egui::Ui, rect: egui::Rect) {
        let painter = ui.painter_at(rect);
        if self.view.texture.is_none() {
            painter.rect_filled(rect, 0.0, egui::Color32::from_gray(20));
        }
        if let Some(t) = &self.view.texture {
            let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            painter.image(t.id(), rect, uv, egui::Color32::WHITE);
        }
        let busy = self
            .view
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
        if self.report.status.starts_with("Loading mesh") {
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
        // Also after a coarse ground truth has arrived (the view is no
        // longer "busy": its full frame is on the way). The progress is the
        // process's: only an editor with a viewport has a ground truth of
        // its own (the UI tests run several editors in one process).
        let truth =
            crate::render::ground_truth::progress().filter(|_| self.view.viewport.is_some());
        if let Some((phase, done, total)) = truth {
            // `reference` is the ground truth, computed on the CPU on the
            // render thread: tens of seconds for a full viewport. Above the
            // "rendering … s" line.
            let text = if phase == 1 {
                "ground truth: irradiance over the surface …"
            } else {
                "ground truth: integrating each pixel …"
            };
            // The time left, from this phase's pace since the UI first saw
            // it (a new phase, or a new frame's: its fraction starts again).
            let now = std::time::Instant::now();
            let (first_at, first_done) = match self.view.truth_phase {
                Some((p, t, d0, last)) if p == (phase, total) && done >= last => (t, d0),
                _ => (now, done),
            };
            self.view.truth_phase = Some(((phase, total), first_at, first_done, done));
            let (spent, gained) = ((now - first_at).as_secs_f32(), done - first_done);
            let left = if gained > 0.02 && spent > 0.5 {
                format!(" · {:.0} s left", spent / gained * (1.0 - done))
            } else {
                String::new()
            };
            progress(
                ui,
                done,
                format!("{text} {:.0} %{left}", 100.0 * done),
                64.0,
            );
        }
        if crate::render::ground_truth::progress().is_none() {
            self.view.truth_phase = None;
        }
        // After a coarse ground truth the full one is on its way with no
        // reply to wake the UI: look again for its progress bar.
        if matches!(self.view.quality, Some(viewport::Quality::Coarse { .. })) {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(250));
        }
        let label = match (self.view.viewport.is_none(), busy) {
            (true, _) => Some("viewport off".to_string()),
            // Not while dragging: previews keep coming, and the wait runs
            // from the drag's first request (the status bar says "preview").
            (_, Some(s))
                if (s > 0.3 && ui.ctx().dragged_id().is_none()) || self.view.texture.is_none() =>
            {
                Some(format!("rendering … {s:.1} s"))
            }
            _ => None,
        };
        self.compare_labels_ui(&painter, rect);
        self.difference_scale_ui(&painter, rect);
        if self.view.show_before {
            // Say so: the frame is not the look being edited.
            let at = rect.center_top() + egui::vec2(0.0, 36.0);
            let font = egui::FontId::proportional(15.0);
            let text = "before the last edit (F: back)";
            let galley = painter.layout_no_wrap(text.into(), font, egui::Color32::WHITE);
            let plate = egui::Rect::from_center_size(at, galley.size()).expand(4.0);
            painter.rect_filled(
                plate,
                3.0,
                egui::Color32::from_rgba_unmultiplied(120, 60, 0, 220),
            );
            painter.galley(
                plate.min + egui::vec2(4.0, 4.0),
                galley,
                egui::Color32::WHITE,
            );
        }
        self.light_gizmo_ui(ui, rect);
        self.layout.viewport_rect = Some(rect);
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

    /// Numbers beside the difference view's colour bar (the frame's right
    /// 12 pixels, `compare::difference_view`): 0 at the bottom, the scale at
    /// the top and half-way, in ΔL* (CIE lightness).
    fn difference_scale_ui(&self, painter: &egui::Painter, rect: egui::Rect) {
        let Some(scale) = self.view.difference_shown else {
            return;
        };
        if self.ui_state.compare != CompareMode::Difference || self.view.ab != AbView::Both {
            return;
        }
        let ppp = painter.ctx().pixels_per_point();
        let bar = 12.0 / ppp;
        let x = rect.right() - bar - 4.0;
        for (t, text) in [
            (
                1.0,
                format!(
                    "{scale:.1} ΔL*{}",
                    if self.ui_state.difference_auto {
                        " (auto)"
                    } else {
                        ""
                    }
                ),
            ),
            (0.5, format!("{:.1}", 0.5 * scale)),
            (0.0, "0".to_owned()),
        ] {
            let y = rect.bottom() - t * rect.height();
            let align = match t {
                1.0 => egui::Align2::RIGHT_TOP,
                0.0 => egui::Align2::RIGHT_BOTTOM,
                _ => egui::Align2::RIGHT_CENTER,
            };
            let galley_rect = painter.text(
                egui::pos2(
                    x,
                    y + if t == 1.0 {
                        2.0
                    } else if t == 0.0 {
                        -2.0
                    } else {
                        0.0
                    },
                ),
                align,
                &text,
                egui::FontId::proportional(12.0),
                egui::Color32::WHITE,
            );
            // A plate under the number so it reads over the heat map.
            painter.rect_filled(
                galley_rect.expand(2.0),
                2.0,
                egui::Color32::from_black_alpha(160),
            );
            painter.text(
                galley_rect.min,
                egui::Align2::LEFT_TOP,
                &text,
                egui::FontId::proportional(12.0),
                egui::Color32::WHITE,
            );
        }
    }

    /// The key light's direction as seen from the camera, at the
    /// viewport's bottom right: a disc where the light is, filled when it
    /// faces the viewer and hollow when it is behind the head (the light
    /// vector's x and y in the camera's frame, `OrbitView::light_in_view`).
    /// Dragging it moves the light as a right drag on the view does.
    fn light_gizmo_ui(&mut self, ui: &mut egui::Ui, rect: egui::Rect) {
        let radius = 30.0;
        if rect.width() < 6.0 * radius || rect.height() < 6.0 * radius {
            return;
        }
        // Clear of the difference view's colour bar (the right 12 px).
        let centre = rect.right_bottom() - egui::vec2(radius + 28.0, radius + 14.0);
        let area = egui::Rect::from_center_size(centre, egui::Vec2::splat(2.0 * radius + 8.0));
        let response = ui.interact(area, ui.scope_id().with("light gizmo"), egui::Sense::drag());
        let o = &mut self.ui_state.view.orbit;
        if response.dragged() {
            let d = response.drag_delta();
            o.light_azimuth_rad -= d.x * 0.02;
            o.light_elevation_rad = (o.light_elevation_rad - d.y * 0.02).clamp(-1.5, 1.5);
        }
        let [x, y, z] = o.light_in_view();
        let relative = (o.light_azimuth_rad - o.camera_yaw_rad)
            .to_degrees()
            .rem_euclid(360.0);
        let value = format!(
            "{:.0}° from the camera, {:.0}° up, {}",
            if relative > 180.0 {
                relative - 360.0
            } else {
                relative
            },
            o.light_elevation_rad.to_degrees(),
            if z >= 0.0 { "in front" } else { "behind" }
        );
        response.widget_info(|| {
            let mut info =
                egui::WidgetInfo::labeled(egui::accesskit::Role::Slider, true, "Light direction");
            info.current_text_value = Some(value.clone());
            info
        });
        let response = response.on_hover_text(format!(
            "The key light, seen from the camera: {value}. A filled disc faces you; a hollow one is behind the head. Drag here (or right-drag the view) to move it."
        ));
        let painter = ui.painter_at(rect);
        let plate = egui::Color32::from_black_alpha(150);
        painter.circle_filled(centre, radius + 4.0, plate);
        let grey = egui::Stroke::new(1.0, egui::Color32::from_gray(120));
        painter.circle_stroke(centre, radius, grey);
        painter.line_segment(
            [
                centre - egui::vec2(radius, 0.0),
                centre + egui::vec2(radius, 0.0),
            ],
            grey,
        );
        painter.line_segment(
            [
                centre - egui::vec2(0.0, radius),
                centre + egui::vec2(0.0, radius),
            ],
            grey,
        );
        let sun = egui::Color32::from_rgb(255, 214, 90);
        let at = centre + egui::vec2(x, -y) * radius;
        let width = if response.hovered() || response.dragged() {
            2.5
        } else {
            1.5
        };
        painter.line_segment([centre, at], egui::Stroke::new(width, sun));
        if z >= 0.0 {
            painter.circle_filled(at, 5.0, sun);
        } else {
            painter.circle_stroke(at, 5.0, egui::Stroke::new(2.0, sun));
        }
        painter.text(
            centre - egui::vec2(0.0, radius + 6.0),
            egui::Align2::CENTER_BOTTOM,
            "light",
            egui::FontId::proportional(11.0),
            egui::Color32::LIGHT_GRAY,
        );
    }

    /// Each side of a comparison labelled on its own half, on a dark plate
    /// that reads over skin (kept for the UI tests: `viewport_layout`).
    pub(super) fn compare_labels_ui(&mut self, painter: &egui::Painter, rect: egui::Rect) {
        self.layout.compare_labels.clear();
        if self.ui_state.compare != CompareMode::Off {
            let (a_name, b_name) = self.side_names();
            let (a, b) = (format!("A · {a_name}"), format!("B · {b_name}"));
            let top = rect.top() + 8.0;
            let labels: Vec<(String, egui::Pos2, egui::Align2)> =
                match (self.view.ab, self.ui_state.compare) {
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
                self.layout.compare_labels.push((text, r));
            }
        }
    }
}
