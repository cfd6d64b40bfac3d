//! The status line, the notifications, the window title, the frame log
//! and the start-up timings: what the editor tells the artist, `Report`'s
//! own, and the one way to say something, [`Report::say`].

use super::*;

/// What the first panels of a frame showed ([`EditorApp::drawn`]).
#[derive(PartialEq)]
pub(super) struct Drawn {
    pub(super) status: String,
    pub(super) frame_info: String,
    pub(super) busy: bool,
    pub(super) preset: Preset,
    pub(super) path: Option<PathBuf>,
}

/// What the status bar shows beside the status line.
pub(super) struct StatusBarView<'a> {
    /// A job or the viewport is working (the spinner).
    pub(super) busy: bool,
    /// The viewport's line: method, quality, size, times.
    pub(super) frame_info: &'a str,
    /// The GPU adapter and driver (on hover).
    pub(super) adapter: &'a str,
}

impl Report {
    /// Puts `text` in the status line (an error or warning, starting so,
    /// also becomes a notification).
    pub(super) fn say(&mut self, text: impl Into<String>) {
        self.status = text.into();
    }

    /// Every new error or warning in the status line becomes a notification
    /// at the viewport's top right that stays until its × is clicked (the
    /// same message again is not stacked twice); at most five, oldest first
    /// dropped.
    pub(super) fn notices_ui(&mut self, ctx: &egui::Context, viewport: Option<egui::Rect>) {
        if self.status != self.status_seen {
            self.status_seen = self.status.clone();
            let s = &self.status;
            if (s.starts_with("Error") || s.starts_with("Warning")) && !self.notices.contains(s) {
                self.notices.push(s.clone());
                if self.notices.len() > 5 {
                    self.notices.remove(0);
                }
            }
        }
        let Some(rect) = viewport else {
            return;
        };
        let mut dismiss = None;
        let width = (rect.width() - 16.0).clamp(160.0, 420.0);
        egui::Area::new(egui::Id::unique("scatterlab_notices"))
            .order(egui::Order::Foreground)
            .fixed_pos(rect.right_top() + egui::vec2(-width - 8.0, 8.0))
            .show(ctx, |ui| {
                ui.set_width(width);
                for (i, n) in self.notices.iter().enumerate() {
                    egui::Frame::popup(ui.style()).show(ui, |ui| {
                        ui.set_width(width - 16.0);
                        ui.horizontal_top(|ui| {
                            let close = ui.small_button("×");
                            close.widget_info(|| {
                                egui::WidgetInfo::labeled(
                                    egui::accesskit::Role::Button,
                                    true,
                                    "Dismiss notification",
                                )
                            });
                            if close.on_hover_text("Dismiss").clicked() {
                                dismiss = Some(i);
                            }
                            let colour = if n.starts_with("Error") {
                                ui.visuals().error_fg_color
                            } else {
                                ui.visuals().warn_fg_color
                            };
                            ui.add(egui::Label::new(egui::RichText::new(n).color(colour)).wrap());
                        });
                    });
                }
            });
        if let Some(i) = dismiss {
            self.notices.remove(i);
        }
    }

    /// Start-up and per-frame timings on stderr with SCATTERLAB_TIMINGS=1
    /// (the budgets: first frame < 3 s, UI < 8 ms a frame).
    fn report_timings(&mut self, has_viewport_frame: bool) {
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
        if !self.reported.1 && has_viewport_frame {
            self.reported.1 = true;
            eprintln!("timing: first viewport frame {t:.2} s after start-up");
        }
        eprintln!("timing: UI {:.2} ms", self.ui_ms);
    }

    /// The frame's end: the window's `title`, the timings and the frame
    /// log (`drawn` is what the frame's first panels showed).
    pub(super) fn end_frame(
        &mut self,
        ctx: &egui::Context,
        (title, drawn): (String, Drawn),
        ui_ms: f64,
        has_viewport_frame: bool,
    ) {
        if title != self.last_title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.last_title = title;
        }
        self.ui_ms = ui_ms;
        self.report_timings(has_viewport_frame);
        if let Some(log) = self.frame_log.as_mut() {
            use std::io::Write;
            let t = unix_seconds();
            // What asked for this frame (egui's record of the calls to
            // request_repaint, file and line): what keeps the window
            // drawing when nothing moves.
            let why: Vec<String> = ctx
                .repaint_causes()
                .iter()
                .map(|c| {
                    let file = c.file.rsplit(['/', '\\']).take(2).collect::<Vec<_>>();
                    format!("{}/{}:{}", file.get(1).unwrap_or(&""), file[0], c.line)
                })
                .collect();
            let _ = writeln!(log, "{t:.3} ui {ui_ms:.1} why={}", why.join(","));
            // The status line as this frame drew it, when it changed (a
            // test reads when a job's result reached the screen).
            if drawn.status != self.logged_status {
                let _ = writeln!(log, "{t:.3} status {}", drawn.status);
                self.logged_status = drawn.status;
            }
        }
    }

    /// A line in the frame log (`SCATTERLAB_FRAME_LOG`), stamped with the
    /// time.
    pub(super) fn log_line(&mut self, line: std::fmt::Arguments) {
        if let Some(log) = self.frame_log.as_mut() {
            use std::io::Write;
            let _ = writeln!(log, "{:.3} {line}", unix_seconds());
        }
    }

    /// The status bar: the spinner while `view.busy`, the status line (cut
    /// short, whole on hover) and the viewport's line on the right.
    pub(super) fn status_bar_ui(&self, ui: &mut egui::Ui, view: StatusBarView) {
        ui.horizontal(|ui| {
            if view.busy {
                spinner(ui);
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
                    egui::Label::new(format!("{} · UI {:.1} ms", view.frame_info, self.ui_ms))
                        .wrap_mode(egui::TextWrapMode::Extend),
                )
                    .on_hover_text(format!("Viewport: method, preview / refining / converged, size, render-thread wall time (GPU time of the SSS passes), adapter ({}). UI: this frame's time in the panels and plots.", view.adapter));
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
}

/// A busy spinner that asks for the next frame in 100 ms, not at once:
/// egui's own asks at once, so while the analysis, an export or the
/// viewport worked the whole window was redrawn as fast as lavapipe could
/// (30 frames a second after a scattering-distance drag, each frame
/// 10–20 ms of CPU taken from the render thread on 2 cores). Drawn as
/// egui's spinner draws itself (`egui::Spinner::paint_at`).
pub(super) fn spinner(ui: &mut egui::Ui) -> egui::Response {
    let size = ui.style().spacing.interact_size.y;
    let (rect, response) = ui.allocate_exact_size(egui::vec2(size, size), egui::Sense::hover());
    response.widget_info(|| egui::WidgetInfo::new(egui::accesskit::Role::ProgressIndicator));
    if ui.is_rect_visible(rect) {
        let colour = ui.visuals().strong_text_color();
        let radius = 0.5 * rect.height().min(rect.width()) - 2.0;
        let n = (radius.round() as u32).clamp(8, 128);
        let time = ui.input(|i| i.time);
        let start = time * std::f64::consts::TAU;
        let end = start + 240f64.to_radians() * time.sin();
        let points: Vec<egui::Pos2> = (0..n)
            .map(|i| {
                let angle = start + (end - start) * f64::from(i) / f64::from(n);
                rect.center() + radius * egui::vec2(angle.cos() as f32, angle.sin() as f32)
            })
            .collect();
        ui.painter()
            .add(egui::Shape::line(points, egui::Stroke::new(3.0, colour)));
        ui.ctx()
            .request_repaint_after(std::time::Duration::from_millis(100));
    }
    response
}
