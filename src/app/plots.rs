//! R(r) / r·R(r) per channel with the 0.997-energy radii, the fitted
//! overlay and its error, the separable taps as stems, and previews of the
//! pre-integrated table and the transmittance strip.

use super::analysis::Curves;
use super::parts::ProfileState;
use super::state::{CompareB, CompareMode, OverlayModel, PlotQuantity};
use super::state::{Document, UiState};
use super::windows::Action;
use egui::Color32;
use egui_plot::{Line, Plot, PlotPoints, Points, VLine};

const CHANNEL_COLORS: [Color32; 3] = [
    Color32::from_rgb(230, 70, 60),
    Color32::from_rgb(80, 190, 80),
    Color32::from_rgb(70, 120, 230),
];

/// The fitted overlay of the last analysis, or why there is none.
type FitOverlay = Option<Result<super::analysis::Overlay, String>>;

/// A label and its three channels' points.
type NamedSeries = (String, [Vec<[f64; 2]>; 3]);

/// The plotted value of channel `c` at point `i` (log axes plot log10).
fn value(curves: &Curves, q: PlotQuantity, i: usize, c: usize, log: bool) -> Option<f64> {
    let v = match q {
        PlotQuantity::R => curves.r[i][c],
        PlotQuantity::RTimesR => curves.r_times_r[i][c],
    };
    if log {
        (v > 0.0 && v.is_finite()).then(|| v.log10())
    } else {
        v.is_finite().then_some(v)
    }
}

/// Decades a log axis shows below the smallest channel's value at its
/// 99.7 % energy radius: the tail that still carries energy, and one more.
const LOG_DECADES_BELOW_TAIL: f64 = 1.0;

/// Decades a log axis shows below the largest value at most.
const LOG_DECADES_MAX: f64 = 8.0;

/// The lowest log10 value a log axis shows for `curves`: one decade under
/// the smallest channel's value at its 99.7 % energy radius, and at most
/// eight decades under the peak. A Gaussian-sum or Jimenez tail falls to
/// 10⁻⁴⁷ within the plotted radii; below this it carries no energy an
/// artist can see, and would squash the useful range into a corner.
pub fn log_floor(curves: &Curves, q: PlotQuantity) -> Option<f64> {
    let logs =
        |c: usize| (0..curves.radius_mm.len()).filter_map(move |i| value(curves, q, i, c, true));
    let peak = (0..3).flat_map(logs).fold(f64::NEG_INFINITY, f64::max);
    if !peak.is_finite() {
        return None;
    }
    let tail = (0..3)
        .filter_map(|c| {
            // The first plotted radius at or past the channel's 99.7 % radius.
            let i = curves
                .radius_mm
                .iter()
                .position(|r| *r >= curves.radius_997_mm[c])?;
            value(curves, q, i, c, true)
        })
        .fold(f64::INFINITY, f64::min);
    let floor = if tail.is_finite() {
        tail - LOG_DECADES_BELOW_TAIL
    } else {
        peak - LOG_DECADES_MAX
    };
    Some(floor.max(peak - LOG_DECADES_MAX))
}

/// The series the main plot draws, per channel: (radius mm, value) points
/// (exposed for tests: what the plot shows). On a log axis, points below
/// [`log_floor`] are left out.
pub fn series(curves: &Curves, q: PlotQuantity, log: bool) -> [Vec<[f64; 2]>; 3] {
    let floor = if log { log_floor(curves, q) } else { None };
    [0, 1, 2].map(|c| {
        (0..curves.radius_mm.len())
            .filter_map(|i| value(curves, q, i, c, log).map(|v| [curves.radius_mm[i], v]))
            .filter(|p| floor.is_none_or(|f| p[1] >= f))
            .collect()
    })
}

/// Whether the radius axis is logarithmic when the artist has not said
/// (`UiState::log_radius` None): where some channel's r·R(r) falls to half
/// its peak within 5 % of the plotted range, a linear axis shows it as a
/// spike at zero (the default skin's blue: half its peak by 0.2 mm of
/// 12.5 mm), and a log axis spreads it out.
pub fn auto_log_radius(curves: &Curves) -> bool {
    let r = &curves.radius_mm;
    let r_max = r.last().copied().unwrap_or(0.0);
    if r_max <= 0.0 {
        return false;
    }
    (0..3).any(|c| {
        let v: Vec<f64> = curves.r_times_r.iter().map(|x| x[c]).collect();
        let (peak_at, peak) = v
            .iter()
            .enumerate()
            .fold((0, 0.0), |b, (i, &x)| if x > b.1 { (i, x) } else { b });
        // Where it falls under half its peak, past the peak.
        peak > 0.0
            && (peak_at..v.len())
                .find(|&i| v[i] < 0.5 * peak)
                .is_some_and(|i| r[i] < 0.05 * r_max)
    })
}

/// `points` on a log radius axis: x → log10(x), the point at r = 0 left
/// out.
pub fn log_radius(points: &[[f64; 2]]) -> Vec<[f64; 2]> {
    points
        .iter()
        .filter(|p| p[0] > 0.0)
        .map(|p| [p[0].log10(), p[1]])
        .collect()
}

/// How a legend entry's line is drawn.
#[derive(Clone, Copy)]
enum Stroke {
    Solid,
    Dashed,
    Dotted,
    Stem,
}

/// One legend entry: a short line in the entry's colour, then its name.
/// The legend sits under the plot, never over the curves.
fn legend_entry_ui(ui: &mut egui::Ui, color: Color32, stroke: Stroke, name: &str) {
    // The line and its name stay together: start a row if both do not fit.
    let text = egui::WidgetText::from(name).into_galley(
        ui,
        Some(egui::TextWrapMode::Extend),
        f32::INFINITY,
        egui::TextStyle::Body,
    );
    let needed = 24.0 + 2.0 * ui.spacing().item_spacing.x + text.size().x;
    if ui.available_size_before_wrap().x < needed {
        ui.end_row();
    }
    let (rect, _) = ui.allocate_exact_size(egui::vec2(24.0, 12.0), egui::Sense::hover());
    let painter = ui.painter_at(rect);
    let y = rect.center().y;
    let line = egui::Stroke::new(2.0, color);
    match stroke {
        Stroke::Solid => {
            painter.line_segment(
                [egui::pos2(rect.left(), y), egui::pos2(rect.right(), y)],
                line,
            );
        }
        Stroke::Dashed => {
            for k in 0..3 {
                let x = rect.left() + 9.0 * k as f32;
                painter.line_segment([egui::pos2(x, y), egui::pos2(x + 5.0, y)], line);
            }
        }
        Stroke::Dotted => {
            for k in 0..5 {
                painter.circle_filled(
                    egui::pos2(rect.left() + 2.0 + 5.0 * k as f32, y),
                    1.2,
                    color,
                );
            }
        }
        Stroke::Stem => {
            let x = rect.center().x;
            painter.line_segment(
                [
                    egui::pos2(x, rect.bottom()),
                    egui::pos2(x, rect.top() + 3.0),
                ],
                line,
            );
            painter.circle_filled(egui::pos2(x, rect.top() + 3.0), 3.0, color);
        }
    }
    // Whole: an entry that does not fit moves to the next row.
    ui.add(egui::Label::new(name).wrap_mode(egui::TextWrapMode::Extend));
}

/// Whether an overlay fit's numbers are worth drawing: a shape error and a
/// colour change each under 100 % on every channel. A fit past that (a
/// Jimenez kernel, which takes the default skin's colour, of Ketchup:
/// +456 % red) is named, not drawn.
pub fn overlay_is_sane(o: &super::analysis::Overlay) -> bool {
    (0..3).all(|c| o.error[c] < 1.0 && o.energy_change[c].abs() < 1.0)
}

/// The right panel: the plot's controls, the profile plot with the fit
/// and B, and the table previews. It writes only the plot's settings and
/// its own caches; a change of the look ("Use fit") is an [`Action`].
pub(super) struct PlotsPanel<'a> {
    /// The look (read).
    pub(super) doc: &'a Document,
    /// The plot's settings (its controls write them) and B's choices.
    pub(super) ui_state: &'a mut UiState,
    /// The analysis and the panel's caches (B's curves, the previews).
    pub(super) profile: &'a mut ProfileState,
    /// The loaded mesh's colour map's mean, if any.
    pub(super) colour_map_mean: Option<[f32; 3]>,
    /// The radius axis is logarithmic when automatic.
    pub(super) auto_log_radius: bool,
}

impl PlotsPanel<'_> {
    /// Draws the panel; where the plot went, and what it asks.
    pub(super) fn ui(mut self, ui: &mut egui::Ui) -> (Option<egui::Rect>, Vec<Action>) {
        let chosen = self.ui_state.overlay;
        let overlay = self
            .profile
            .latest
            .as_ref()
            .filter(|a| a.key.profile == self.doc.preset.profile && a.key.overlay == chosen)
            .and_then(|a| a.overlay.clone());
        let auto = self.auto_log_radius;
        controls_ui(ui, self.ui_state, auto);
        let s = &self.ui_state;
        let (q, log, show_taps) = (s.plot_quantity, s.log_y, s.show_taps);
        let log_r = s.log_radius.unwrap_or(auto);
        let unit = match q {
            PlotQuantity::R => "1/mm²",
            PlotQuantity::RTimesR => "1/mm",
        };
        let apply = overlay_status_ui(ui, &overlay, s.overlay);
        // An overlay whose numbers are not sane is named above, not drawn.
        let overlay = overlay.filter(|o| o.as_ref().map_or(true, overlay_is_sane));
        let b_series = self.compared_preset_series(ui, q, log);
        let plot_rect = match &self.profile.curves {
            Some(Ok(curves)) => Some(profile_plot_ui(
                ui,
                &self.taps(),
                curves,
                (&overlay, &b_series),
                (q, log, show_taps, unit),
                log_r,
            )),
            Some(Err(e)) => {
                ui.colored_label(ui.visuals().error_fg_color, e);
                None
            }
            None => {
                ui.horizontal(|ui| {
                    super::report::spinner(ui);
                    ui.label("computing the layered profile …");
                });
                None
            }
        };
        let mut actions = Vec::new();
        if let Some((spec, what)) = apply {
            let mut p = self.doc.preset.clone();
            // The description follows the model: what the look is now, and
            // what it was fitted to.
            p.description = format!(
                "{what} of \"{}\". Before the fit: {}",
                p.name, p.description
            )
            .trim()
            .to_owned();
            p.profile = spec;
            actions.push(Action::SetLook(Box::new(p)));
        }
        ui.separator();
        self.previews_ui(ui);
        (plot_rect, actions)
    }

    /// The separable taps of the look's latest analysis, if it is of the
    /// look now.
    fn taps(&self) -> Vec<crate::model::separable::Tap> {
        self.profile
            .latest
            .as_ref()
            .filter(|a| a.key.profile == self.doc.preset.profile)
            .map(|a| a.taps.clone())
            .unwrap_or_default()
    }

    /// B's curves when B is a preset file (dotted on the plot), cached by its
    /// file and the plot range; a warning where it cannot be overlaid.
    fn compared_preset_series(
        &mut self,
        ui: &mut egui::Ui,
        q: PlotQuantity,
        log: bool,
    ) -> Option<NamedSeries> {
        match (
            &self.ui_state.compare,
            &self.ui_state.compare_b,
            &self.profile.curves,
        ) {
            (CompareMode::Off, ..) | (_, CompareB::Method(_), _) => None,
            (_, CompareB::Preset(path), Some(Ok(curves))) => {
                let r_max = curves.radius_mm.last().copied();
                let a_spec = &self.doc.preset.profile;
                // B's material albedo (`settings::albedo::b_as_drawn`) is part of what it draws.
                let key = (
                    path.clone(),
                    r_max.map(f64::to_bits),
                    format!(
                        "{a_spec:?} {:?} {:?}",
                        self.ui_state.b_material_albedo, self.colour_map_mean
                    ),
                );
                if self.profile.b_curves.as_ref().map(|b| &b.0) != Some(&key) {
                    let loaded = super::viewport::load_look(path).and_then(|p| {
                        let (p, _, albedo) = crate::settings::albedo::b_as_drawn(
                            p,
                            self.profile.a_albedo(&self.doc.preset),
                            self.ui_state.b_material_albedo,
                            self.ui_state.map_colour,
                            self.colour_map_mean,
                        );
                        let name = match albedo {
                            Some(a) => format!("{} ({a} albedo)", p.name),
                            None => p.name.clone(),
                        };
                        if super::analysis::is_slow(&p.profile) || super::analysis::is_slow(a_spec)
                        {
                            return Err("layered stacks are not overlaid".into());
                        }
                        let m = p.profile.build().map_err(|e| e.to_string())?;
                        let a = a_spec.build().map_err(|e| e.to_string())?;
                        // How far B's r·R(r) is from A's, to A's 99.7 % radius.
                        let reach = a.radius_for_energy(0.997);
                        let d = crate::model::relative_l2_rr(a.as_ref(), m.as_ref(), reach);
                        Ok((name, Curves::of(m.as_ref(), r_max), d))
                    });
                    self.profile.b_curves = Some((key, loaded));
                }
                match self.profile.b_curves.as_ref().map(|b| &b.1) {
                    Some(Ok((name, c, _))) => Some((format!("B: {name}"), series(c, q, log))),
                    Some(Err(e)) => {
                        ui.colored_label(ui.visuals().warn_fg_color, format!("B overlay: {e}"));
                        None
                    }
                    None => None,
                }
            }
            _ => None,
        }
    }

    /// The pre-integrated table and the transmittance strip of the last
    /// analysis (uploaded once per result).
    fn previews_ui(&mut self, ui: &mut egui::Ui) {
        // Borrowed, not cloned per frame: only `preview_textures` changes below.
        let Some(a) = self
            .profile
            .latest
            .as_ref()
            .filter(|a| a.key.profile == self.doc.preset.profile)
        else {
            ui.horizontal(|ui| {
                super::report::spinner(ui);
                ui.label("baking tables …");
            });
            return;
        };
        ui.label("Pre-integrated table D(N·L, 1/r)")
            .on_hover_text("Penner 2011: x = N·L from −1 to 1, y = curvature 1/r from 1/100 to 1/1 mm⁻¹ (top to bottom). Linear D shown in sRGB.");
        // Uploaded once per analysis result, not per frame.
        if self.profile.preview_textures.as_ref().map(|t| &t.0) != Some(&a.key) {
            let n = a.lut_size;
            let rgba: Vec<u8> = a
                .lut_preview
                .iter()
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect();
            let lut = (a.lut_preview.len() == n * n).then(|| {
                let img = egui::ColorImage::from_rgba_unmultiplied([n, n], &rgba);
                ui.ctx()
                    .load_texture("lut_preview", img, egui::TextureOptions::NEAREST)
            });
            let strip: Vec<u8> = a
                .transmittance
                .iter()
                .flat_map(|t| {
                    let c = t.map(super::analysis::linear_to_srgb8);
                    [c[0], c[1], c[2], 255]
                })
                .collect();
            let img = egui::ColorImage::from_rgba_unmultiplied([a.transmittance.len(), 1], &strip);
            let strip = ui
                .ctx()
                .load_texture("transmittance", img, egui::TextureOptions::LINEAR);
            self.profile.preview_textures = Some((a.key.clone(), lut, strip));
        }
        let Some((_, lut, strip)) = &self.profile.preview_textures else {
            return;
        };
        if let Some(lut) = lut {
            ui.image((lut.id(), egui::vec2(192.0, 192.0)));
        }
        // Seconds to one decimal: a width that does not change with load (the
        // panels snapshot failed once when the bake passed 1000 ms).
        ui.small(format!("background bake {:.1} s", a.seconds));
        ui.label(format!(
            "Transmittance T(d), d = 0 … {:.1} mm",
            a.key.thickness_max_mm
        ))
        .on_hover_text(
            "Light through a slab of thickness d (left thin, right thick), shown in sRGB.",
        );
        ui.image((strip.id(), egui::vec2(384.0, 24.0)));
    }
}

/// The plot's controls: r·R(r) or R(r), log, taps, the fitted overlay.
fn controls_ui(ui: &mut egui::Ui, s: &mut super::state::UiState, auto_log_r: bool) {
    ui.heading("Profile");
    ui.horizontal(|ui| {
        ui.selectable_value(&mut s.plot_quantity, PlotQuantity::RTimesR, "r·R(r)")
            .on_hover_text("Radial energy density (1/mm): where the light comes out.");
        ui.selectable_value(&mut s.plot_quantity, PlotQuantity::R, "R(r)")
            .on_hover_text("Diffuse reflectance per area (1/mm²).");
        ui.checkbox(&mut s.log_y, "log")
            .on_hover_text("Logarithmic value axis (log10).");
        let mut log_r = s.log_radius.unwrap_or(auto_log_r);
        let label = if s.log_radius.is_none() { "log r (auto)" } else { "log r" };
        if ui
            .checkbox(&mut log_r, label)
            .on_hover_text("Logarithmic radius axis, the last three decades of the range. Automatic until you set it: on where a channel falls to half its peak within 5 % of the range (a linear axis would show a spike at zero). Right-click: automatic again.")
            .secondary_clicked()
        {
            s.log_radius = None;
        } else if log_r != s.log_radius.unwrap_or(auto_log_r) {
            s.log_radius = Some(log_r);
        }
        ui.checkbox(&mut s.show_taps, "taps").on_hover_text(
            "The separable kernel's taps as stems (weight per channel at its offset).",
        );
    });
    ui.horizontal(|ui| {
        egui::ComboBox::from_label("Overlay")
            .selected_text(match s.overlay {
                OverlayModel::None => "none",
                OverlayModel::Burley => "Burley fit",
                OverlayModel::Jimenez => "Jimenez 2012 fit",
                OverlayModel::Artist => "artist fit",
                OverlayModel::Gaussians4 => "4 Gaussians fit",
            })
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut s.overlay, OverlayModel::None, "none");
                ui.selectable_value(&mut s.overlay, OverlayModel::Burley, "Burley fit");
                ui.selectable_value(&mut s.overlay, OverlayModel::Jimenez, "Jimenez 2012 fit");
                ui.selectable_value(&mut s.overlay, OverlayModel::Artist, "artist fit");
                ui.selectable_value(&mut s.overlay, OverlayModel::Gaussians4, "4 Gaussians fit");
            })
            .response
            .on_hover_text(
                "A model fitted to the current profile (least squares on r·R(r)), drawn dashed.",
            );
    });
}

/// The overlay fit's error and its "Use fit" button (returns the fit's
/// look when pressed, and a sentence on what it is), or why there is none,
/// or a spinner while fitting.
fn overlay_status_ui(
    ui: &mut egui::Ui,
    overlay: &FitOverlay,
    chosen: OverlayModel,
) -> Option<(crate::settings::ProfileSpec, String)> {
    let mut apply = None;
    match overlay {
        Some(Ok(o)) => {
            ui.horizontal_wrapped(|ui| {
                if !overlay_is_sane(o) {
                    // Its numbers mean nothing, and using it would wreck
                    // the look: named, with nothing to use.
                    ui.colored_label(
                        ui.visuals().warn_fg_color,
                        format!("{} cannot hold this look: not drawn (choose another overlay).", o.label),
                    )
                    .on_hover_text(format!(
                        "Its shape error or colour change passes 100 % (colour change R {:+.0} %, G {:+.0} %, B {:+.0} %): no fit to use.",
                        100.0 * o.energy_change[0],
                        100.0 * o.energy_change[1],
                        100.0 * o.energy_change[2]
                    ));
                    return;
                }
                ui.label(format!(
                    "{}: shape error (relative L2 of r·R(r)/total) R {:.2} %, G {:.2} %, B {:.2} %",
                    o.label,
                    100.0 * o.error[0],
                    100.0 * o.error[1],
                    100.0 * o.error[2]
                ))
                .on_hover_text(
                    "How far the fitted profile's shape is from the look's, each normalised by its total reflectance.",
                );
                let e = o.energy_change;
                if e.iter().any(|v| v.abs() >= 5e-4) {
                    ui.colored_label(
                        ui.visuals().warn_fg_color,
                        format!(
                            "colour changes: R {:+.1} %, G {:+.1} %, B {:+.1} %",
                            100.0 * e[0],
                            100.0 * e[1],
                            100.0 * e[2]
                        ),
                    )
                    .on_hover_text(
                        "Using the fit changes the look's total reflectance, the colour the head shows: an energy-normalised kernel (Jimenez 2012, artist) takes the default skin colour, and Burley cannot hold a total above 1.",
                    );
                } else {
                    ui.label("colour kept");
                }
                if ui
                    .button("Use fit")
                    .on_hover_text("Replace the look's model with the fitted one (undoable).")
                    .clicked()
                {
                    apply = Some((
                        o.spec.clone(),
                        format!(
                            "A {} (shape error R {:.1} %, G {:.1} %, B {:.1} %)",
                            o.label,
                            100.0 * o.error[0],
                            100.0 * o.error[1],
                            100.0 * o.error[2]
                        ),
                    ));
                }
            });
        }
        Some(Err(e)) => {
            ui.colored_label(ui.visuals().error_fg_color, format!("fit: {e}"));
        }
        None if chosen != OverlayModel::None => {
            ui.horizontal(|ui| {
                super::report::spinner(ui);
                ui.label("fitting …");
            });
        }
        None => {}
    }
    apply
}

/// The profile plot with its 99.7 % radii, the overlay, B and the taps,
/// the legend under it and the totals; returns where the plot went.
/// A radius axis mark in mm: on a log axis the mark is log10(r).
fn radius_mark(value: f64, log_r: bool) -> String {
    if !log_r {
        return format!("{value}");
    }
    let r = 10f64.powf(value);
    if r >= 1.0 {
        format!("{r:.0}")
    } else {
        format!("{r:.prec$}", prec = (-value).ceil() as usize)
    }
}

fn profile_plot_ui(
    ui: &mut egui::Ui,
    taps: &[crate::model::separable::Tap],
    curves: &Curves,
    (overlay, b_series): (&FitOverlay, &Option<NamedSeries>),
    (q, log, show_taps, unit): (PlotQuantity, bool, bool, &str),
    log_r: bool,
) -> egui::Rect {
    // Points on the radius axis in use: log10(r) on a log axis.
    let x = |pts: &[[f64; 2]]| if log_r { log_radius(pts) } else { pts.to_vec() };
    let xr = |r: f64| if log_r { r.max(1e-12).log10() } else { r };
    let lines = series(curves, q, log).map(|s| x(&s));
    let r997 = curves.radius_997_mm;
    let plot = Plot::new("profile_plot")
        .height(280.0)
        .x_axis_label(if log_r {
            "radius (mm, log)"
        } else {
            "radius (mm)"
        })
        .x_axis_formatter(move |mark, _| radius_mark(mark.value, log_r))
        .y_axis_label(if log {
            format!("log10 value ({unit})")
        } else {
            unit.to_string()
        })
        .show(ui, |plot| {
            for c in 0..3 {
                let name = ["R", "G", "B"][c];
                plot.line(
                    Line::new(name, PlotPoints::from(lines[c].clone()))
                        .color(CHANNEL_COLORS[c])
                        .width(2.0),
                );
                plot.vline(
                    VLine::new("99.7 % energy radius", xr(r997[c]))
                        .color(CHANNEL_COLORS[c].gamma_multiply(0.6))
                        .style(egui_plot::LineStyle::dotted_dense()),
                );
            }
            if let Some(Ok(o)) = &overlay {
                let ol = series(&o.curves, q, log).map(|s| x(&s));
                for c in 0..3 {
                    plot.line(
                        Line::new(o.label.clone(), PlotPoints::from(ol[c].clone()))
                            .color(CHANNEL_COLORS[c].gamma_multiply(0.7))
                            .style(egui_plot::LineStyle::dashed_loose()),
                    );
                }
            }
            if let Some((label, b)) = &b_series {
                for c in 0..3 {
                    plot.line(
                        Line::new(label.clone(), PlotPoints::from(x(&b[c])))
                            .color(CHANNEL_COLORS[c].gamma_multiply(0.5))
                            .style(egui_plot::LineStyle::dotted_loose()),
                    );
                }
            }
            if show_taps && !log && !taps.is_empty() {
                let peak = lines.iter().flatten().map(|p| p[1]).fold(0.0, f64::max);
                for (c, pts) in scaled_taps(taps, peak).iter().enumerate() {
                    plot.points(
                        Points::new("separable taps (scaled)", PlotPoints::from(x(pts)))
                            .stems(0.0)
                            .radius(3.0)
                            .color(CHANNEL_COLORS[c].gamma_multiply(0.5)),
                    );
                }
            }
        });
    let plot_rect = plot.response.rect;
    legend_ui(ui, overlay, b_series, show_taps && !log && !taps.is_empty());
    ui.label(format!(
        "Total reflectance {:.3} / {:.3} / {:.3} · 99.7 % radius {:.2} / {:.2} / {:.2} mm",
        curves.total[0], curves.total[1], curves.total[2], r997[0], r997[1], r997[2]
    ));
    plot_rect
}

/// The separable taps at positive offsets, per channel, as (mm, weight)
/// points with the weights scaled so that the largest reaches `peak` (the
/// plot's highest value).
fn scaled_taps(taps: &[crate::model::separable::Tap], peak: f64) -> [Vec<[f64; 2]>; 3] {
    let wmax = taps.iter().flat_map(|t| t.weight).fold(1e-12, f64::max);
    std::array::from_fn(|c| {
        taps.iter()
            .filter(|t| t.offset_mm >= 0.0)
            .map(|t| [t.offset_mm, t.weight[c] / wmax * peak])
            .collect()
    })
}

/// The profile plot's legend: R, G, B in that order, then what else is
/// drawn, the fit by its name; under the plot, off the curves.
fn legend_ui(ui: &mut egui::Ui, overlay: &FitOverlay, b_series: &Option<NamedSeries>, taps: bool) {
    ui.horizontal_wrapped(|ui| {
        for c in 0..3 {
            legend_entry_ui(ui, CHANNEL_COLORS[c], Stroke::Solid, ["R", "G", "B"][c]);
        }
        legend_entry_ui(ui, Color32::GRAY, Stroke::Dotted, "99.7 % energy radius");
        if let Some(Ok(o)) = overlay {
            legend_entry_ui(ui, Color32::GRAY, Stroke::Dashed, &o.label);
        }
        if let Some((label, _)) = b_series {
            legend_entry_ui(ui, Color32::GRAY, Stroke::Dotted, label);
        }
        if taps {
            legend_entry_ui(ui, Color32::GRAY, Stroke::Stem, "separable taps (scaled)");
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::gaussian::GaussianSum;

    /// d'Eon 2007's normalised Gaussian G(v, r) = e^(−r²/2v)/(2πv) holds
    /// 1 − e^(−r²/2v) of its energy within r, so its 99.7 % radius is
    /// √(−2v ln 0.003) and r·R there is r₉₉₇ · 0.003/(2πv) (closed form,
    /// not the model code). Three channels of variance 4, 1 and 0.05 mm²:
    /// the log axis stops one decade under the lowest of those (the red
    /// channel's, 10^−3.089), not at the blue channel's 10^−300 tail.
    #[test]
    fn log_axis_stops_a_decade_under_the_tail() {
        let variances = [4.0, 1.0, 0.05];
        let terms: Vec<(f64, [f64; 3])> = (0..3)
            .map(|c| {
                let mut w = [0.0; 3];
                w[c] = 1.0;
                (variances[c], w)
            })
            .collect();
        let sum = GaussianSum::new(&terms).unwrap();
        let curves = Curves::of(&sum, None);
        let tail = variances
            .map(|v: f64| {
                let r997 = (-2.0 * v * 0.003f64.ln()).sqrt();
                (r997 * 0.003 / (2.0 * std::f64::consts::PI * v)).log10()
            })
            .into_iter()
            .fold(f64::INFINITY, f64::min);
        assert!((tail + 3.089).abs() < 1e-3, "{tail}");
        let floor = log_floor(&curves, PlotQuantity::RTimesR).unwrap();
        // The first plotted radius at or past r₉₉₇: within 0.05 decade.
        assert!((floor - (tail - 1.0)).abs() < 0.05, "floor {floor}");
        let shown = series(&curves, PlotQuantity::RTimesR, true);
        let lowest = shown
            .iter()
            .flatten()
            .map(|p| p[1])
            .fold(f64::INFINITY, f64::min);
        assert!(lowest >= floor && lowest < floor + 0.5, "lowest {lowest}");
        // Unclamped, the narrow blue channel runs hundreds of decades down.
        let raw = (0..curves.radius_mm.len())
            .filter_map(|i| value(&curves, PlotQuantity::RTimesR, i, 2, true))
            .fold(f64::INFINITY, f64::min);
        assert!(raw < -50.0, "{raw}");
    }
}
