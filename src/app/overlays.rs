//! What the viewport draws: the frame itself and what goes over it (the
//! progress bars, the compare labels and the rendering note, the
//! difference view's scale, the light gizmo).

use super::viewport_ui::ViewportPanel;
use super::*;

impl ViewportPanel<'_> {
    /// What is drawn over the viewport: the frame, progress bars, the
    /// compare labels and the rendering note.
    pub(super) fn overlays_ui(&mut self, ui: &mut egui::Ui, rect: egui::Rect) {
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
        self.progress_bars_ui(ui, rect);
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
        self.reference.overlay_ui(&painter, rect);
        self.compare_labels_ui(&painter, rect);
        self.difference_scale_ui(&painter, rect);
        if self.view.show_before {
            before_plate_ui(&painter, rect);
        }
        self.light_gizmo_ui(ui, rect);
        self.probe_ui(ui, &painter, rect);
        if self.view.show_mouse_hint && label.is_none() {
            painter.text(
                rect.left_bottom() + egui::vec2(8.0, -8.0),
                egui::Align2::LEFT_BOTTOM,
                "drag: orbit · right/Shift drag: light · middle: pan · wheel: zoom · Space: A/B",
                egui::FontId::proportional(12.0),
                egui::Color32::from_white_alpha(150),
            );
        }
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

    /// The progress bars at the viewport's bottom left: the mesh's bake
    /// and the ground truth's cells or tiles.
    fn progress_bars_ui(&mut self, ui: &mut egui::Ui, rect: egui::Rect) {
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
        if let Some(viewport::Quality::Truth {
            done,
            tiles,
            left_s,
            ..
        }) = self
            .view
            .quality
            .filter(|q| matches!(q, viewport::Quality::Truth { tiles, .. } if *tiles > 0))
        {
            // The tiles' own bar (their gathers report no other; the
            // cells' bar shows before the first tiles).
            let left = left_s.map_or(String::new(), |s| format!(" · {s:.0} s left"));
            let text = format!("ground truth: {done} of {tiles} tiles{left}");
            progress(ui, done as f32 / tiles as f32, text, 64.0);
        } else if let Some((done, text)) = self.truth_progress() {
            // Above the "rendering … s" line.
            progress(ui, done, text, 64.0);
        }
        if crate::render::ground_truth::progress().is_none() {
            self.view.truth_phase = None;
        }
        // After a coarse ground truth the full one is on its way with no
        // reply to wake the UI: look again for its progress bar.
        if matches!(
            self.view.quality,
            Some(viewport::Quality::Coarse { .. } | viewport::Quality::Truth { .. })
        ) {
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_millis(250));
        }
    }

    /// The ground truth's progress bar, if one is being computed: the
    /// fraction done and its text, with the time left.
    fn truth_progress(&mut self) -> Option<(f32, String)> {
        // Also after a coarse ground truth has arrived (the view is no
        // longer "busy": its full frame is on the way). The progress is the
        // process's: only an editor with a viewport has a ground truth of
        // its own (the UI tests run several editors in one process).
        let truth =
            crate::render::ground_truth::progress().filter(|_| self.view.viewport.is_some());
        truth.map(|(phase, done, total)| {
            // `reference` is the ground truth, computed on the CPU on the
            // render thread: tens of seconds for a full viewport.
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
            (done, format!("{text} {:.0} %{left}", 100.0 * done))
        })
    }

    /// Numbers beside the difference view's colour bar (the frame's right
    /// 12 pixels, `compare::difference_view`): 0 at the bottom, the scale at
    /// the top and half-way, in ΔL* (CIE lightness).
    pub(super) fn difference_scale_ui(&mut self, painter: &egui::Painter, rect: egui::Rect) {
        self.layout.scale_plates.clear();
        let Some(top) = self.scale_top_text() else {
            return;
        };
        let scale = self.view.difference_shown.unwrap_or(0.0);
        let ppp = painter.ctx().pixels_per_point();
        let bar = 12.0 / ppp;
        let x = rect.right() - bar - 4.0;
        for (t, text) in [
            (1.0, top),
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
            self.layout.scale_plates.push(galley_rect.expand(2.0));
            painter.text(
                galley_rect.min,
                egui::Align2::LEFT_TOP,
                &text,
                egui::FontId::proportional(12.0),
                egui::Color32::WHITE,
            );
        }
    }

    /// The difference view's top number ("5.0 ΔL* (auto)"), when its
    /// scale is on screen.
    fn scale_top_text(&self) -> Option<String> {
        let scale = self.view.difference_shown?;
        if self.ui_state.compare != CompareMode::Difference || self.view.ab != AbView::Both {
            return None;
        }
        let auto = if self.ui_state.difference_auto {
            " (auto)"
        } else {
            ""
        };
        Some(format!("{scale:.1} ΔL*{auto}"))
    }

    /// The key light's direction as seen from the camera, at the
    /// viewport's bottom right: a disc where the light is, filled when it
    /// faces the viewer and hollow when it is behind the head (the light
    /// vector's x and y in the camera's frame, `OrbitView::light_in_view`).
    /// Dragging it moves the light as a right drag on the view does.
    pub(super) fn light_gizmo_ui(&mut self, ui: &mut egui::Ui, rect: egui::Rect) {
        let radius = 30.0;
        if rect.width() < 6.0 * radius || rect.height() < 6.0 * radius {
            return;
        }
        // Clear of the difference view's colour bar (the right 12 px).
        let centre = rect.right_bottom() - egui::vec2(radius + 28.0, radius + 14.0);
        let area = egui::Rect::from_center_size(centre, egui::Vec2::splat(2.0 * radius + 8.0));
        let response = ui.interact(area, ui.scope_id().with("light gizmo"), egui::Sense::drag());
        let o = &mut self.camera.orbit;
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
    /// The pixel probe: under the pointer, the frame's sRGB bytes, the
    /// scene-linear radiance there (before exposure and the display
    /// transform; once the view has settled) and CIE L*; while comparing,
    /// the bytes decoded to display-linear values, side by side both
    /// sides' L* and their difference, on a difference view the |ΔL*| its
    /// colour stands for.
    fn probe_ui(&mut self, ui: &egui::Ui, painter: &egui::Painter, rect: egui::Rect) {
        use crate::render::compare;
        self.layout.probe = None;
        // A file dialog or a prompt holds the artist's attention: the
        // probe, left where the pointer last was, read on behind it.
        if self.dialog_up {
            return;
        }
        let Some(pos) = ui.ctx().pointer_hover_pos().filter(|p| rect.contains(*p)) else {
            return;
        };
        if ui
            .ctx()
            .layer_id_at(pos)
            .is_some_and(|l| l.order != egui::Order::Background)
        {
            // A window over the viewport.
            return;
        }
        let Some((img, _)) = &self.view.last_frame else {
            return;
        };
        let (w, h) = (img.width() as f32, img.height() as f32);
        let x = (((pos.x - rect.left()) / rect.width()) * w).clamp(0.0, w - 1.0) as u32;
        let y = (((pos.y - rect.top()) / rect.height()) * h).clamp(0.0, h - 1.0) as u32;
        let Some(p) = compare::probe(img, x, y) else {
            return;
        };
        let pixel = |name: &str, p: &compare::Probe| {
            format!(
                "{name}sRGB {} {} {} · display-linear {:.3} {:.3} {:.3} · L* {:.1}",
                p.srgb[0], p.srgb[1], p.srgb[2], p.linear[0], p.linear[1], p.linear[2], p.lightness
            )
        };
        // One look alone: the scene-linear radiance under the pointer, as
        // the render thread read it back once the view settled.
        let scene = self
            .view
            .radiance
            .as_deref()
            .filter(|r| (r.width, r.height) == img.dimensions());
        let alone = |p: &compare::Probe| alone_text(p, scene.map(|r| r.at(x, y)));
        let comparing = self.ui_state.compare != CompareMode::Off && self.view.ab == AbView::Both;
        let text = match (comparing, self.ui_state.compare) {
            (true, CompareMode::Difference) => match self.view.difference_shown {
                Some(scale) => format!(
                    "|ΔL*| {:.2} (white = {scale:.1})",
                    compare::heat_value(p.srgb, scale)
                ),
                None => pixel("", &p),
            },
            (true, CompareMode::SideBySide) => {
                let half = img.width() / 2;
                let (ax, bx) = if x < half {
                    (x, x + half)
                } else {
                    (x - half, x)
                };
                match (compare::probe(img, ax, y), compare::probe(img, bx, y)) {
                    (Some(a), Some(b)) => format!(
                        "{}\nA L* {:.1} · B L* {:.1} · ΔL* {:+.2}",
                        pixel(if x < half { "A " } else { "B " }, &p),
                        a.lightness,
                        b.lightness,
                        b.lightness - a.lightness
                    ),
                    _ => pixel("", &p),
                }
            }
            (true, CompareMode::Split) => {
                let side = if (x as f32) < self.ui_state.split * w {
                    "A "
                } else {
                    "B "
                };
                pixel(side, &p)
            }
            _ => alone(&p),
        };
        let galley = painter.layout_no_wrap(
            text.clone(),
            egui::FontId::monospace(12.0),
            egui::Color32::WHITE,
        );
        let r = egui::Align2::RIGHT_TOP
            .anchor_size(rect.right_top() + egui::vec2(-24.0, 40.0), galley.size())
            .expand(4.0);
        let r = r.translate(egui::vec2((rect.left() + 2.0 - r.left()).max(0.0), 0.0));
        painter.rect_filled(r, 4.0, egui::Color32::from_black_alpha(170));
        painter.galley(r.min + egui::vec2(4.0, 4.0), galley, egui::Color32::WHITE);
        self.layout.probe = Some(text);
    }

    pub(super) fn compare_labels_ui(&mut self, painter: &egui::Painter, rect: egui::Rect) {
        self.layout.compare_labels.clear();
        if self.ui_state.compare != CompareMode::Off {
            let (a_name, b_name) = self.names.clone();
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
            // Wrapped clear of the difference scale's top number (and its
            // colour bar) at the viewport's top right.
            let beside_scale = self.scale_top_text().map_or(16.0, |t| {
                let ppp = painter.ctx().pixels_per_point();
                let number = painter
                    .layout_no_wrap(t, egui::FontId::proportional(12.0), egui::Color32::WHITE)
                    .size()
                    .x;
                12.0 / ppp + 4.0 + number + 24.0
            });
            let wrap = (rect.width() - beside_scale).max(80.0);
            for (text, pos, align) in labels {
                let galley = painter.layout(
                    text.clone(),
                    egui::FontId::proportional(15.0),
                    egui::Color32::WHITE,
                    wrap,
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

/// Says so when the frame shown is the look before the last edit, not the
/// one being edited.
fn before_plate_ui(painter: &egui::Painter, rect: egui::Rect) {
    // Say so: the frame is not the look being edited.
    let at = rect.center_top() + egui::vec2(0.0, 36.0);
    let font = egui::FontId::proportional(15.0);
    let text = "before the last edit (\\: back)";
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

/// The probe's text for one look alone: the bytes, the scene-linear
/// radiance read back at the pixel (`Some(None)`: off the mesh; `None`:
/// not read yet) and L*.
fn alone_text(p: &crate::render::compare::Probe, scene: Option<Option<[f32; 3]>>) -> String {
    let srgb = format!("sRGB {} {} {}", p.srgb[0], p.srgb[1], p.srgb[2]);
    match scene {
        Some(Some(l)) => format!(
            "{srgb} · scene-linear {:.4} {:.4} {:.4} · L* {:.1}",
            l[0], l[1], l[2], p.lightness
        ),
        Some(None) => format!("{srgb} · background, not the mesh · L* {:.1}", p.lightness),
        None => format!(
            "{srgb} · L* {:.1} · scene-linear once the view settles",
            p.lightness
        ),
    }
}
