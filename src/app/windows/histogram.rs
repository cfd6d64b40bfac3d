//! View → Histogram: the view's scene-linear luminance in stops, before
//! exposure and the display transform (as a camera's or Toolbag's
//! histogram reads the scene), with where the exposure puts display white
//! and 18 % grey. It reads the radiance the render thread sends with a
//! settled view of one look ([`crate::render::SceneLinear`]).

use super::{Action, Window, WindowView};
use crate::render::{SceneLinear, StopsHistogram};
use std::sync::Arc;

/// The histogram's first bin's lower edge, bin width and bin count: from
/// 10 stops under 18 % grey to 6 over, in quarter stops.
const LO_EV: f32 = -10.0;
const STEP_EV: f32 = 0.25;
const BINS: usize = 64;

#[derive(Default)]
pub struct HistogramWindow {
    open: bool,
    /// The radiance counted and its histogram (counted once per frame
    /// sent, not per repaint).
    counted: Option<(Arc<SceneLinear>, StopsHistogram)>,
}

impl HistogramWindow {
    /// The histogram shown, counted from `radiance` if it is new.
    fn histogram(&mut self, radiance: &Arc<SceneLinear>) -> &StopsHistogram {
        if !self
            .counted
            .as_ref()
            .is_some_and(|(r, _)| Arc::ptr_eq(r, radiance))
        {
            let h = radiance.histogram(LO_EV, STEP_EV, BINS);
            self.counted = Some((radiance.clone(), h));
        }
        &self.counted.as_ref().expect("counted above").1
    }

    /// The histogram last counted (UI tests).
    pub fn counted(&self) -> Option<&StopsHistogram> {
        self.counted.as_ref().map(|(_, h)| h)
    }
}

impl Window for HistogramWindow {
    fn title(&self) -> &'static str {
        "Histogram"
    }

    fn menu(&self) -> Option<super::Menu> {
        Some(super::Menu::View)
    }

    fn menu_tooltip(&self) -> &'static str {
        "The view's scene-linear luminance in stops, before exposure and the display transform, with where display white and 18 % grey fall"
    }

    fn is_open(&self) -> bool {
        self.open
    }

    fn set_open(&mut self, open: bool) {
        self.open = open;
    }

    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        let mut open = self.open;
        let exposure = view.view.orbit.exposure.max(1e-6);
        egui::Window::new(self.title())
            .open(&mut open)
            .resizable(true)
            .collapsible(true)
            .default_width(330.0)
            // The viewport's bottom left, clear of the head's middle.
            .default_pos(view.viewport_rect.map_or(egui::pos2(330.0, 400.0), |r| {
                r.left_bottom() + egui::vec2(8.0, -250.0)
            }))
            .show(ctx, |ui| match view.radiance {
                None => {
                    ui.label("The histogram comes once the view settles, for one look alone (not while comparing A and B).");
                }
                Some(r) => {
                    let h = self.histogram(r).clone();
                    histogram_ui(ui, &h, exposure);
                }
            });
        self.open = open;
        Vec::new()
    }
}

/// The bars, the exposure's display white and 18 % grey, and a summary.
fn histogram_ui(ui: &mut egui::Ui, h: &StopsHistogram, exposure: f32) {
    use egui_plot::{Bar, BarChart, Plot, VLine};
    // Scene luminance Y that the exposure maps to 1 (display white before
    // the display transform) and to 0.18, in stops from 18 % grey.
    let white_ev = (1.0 / (0.18 * exposure)).log2();
    // (+ 0.0: at 0 EV, "+0.00", not "-0.00".)
    let grey_ev = -exposure.log2() + 0.0;
    let bars: Vec<Bar> = h
        .counts
        .iter()
        .enumerate()
        .map(|(k, &n)| {
            let centre = h.lo_ev + (k as f32 + 0.5) * h.step_ev;
            Bar::new(f64::from(centre), f64::from(n)).width(f64::from(h.step_ev) * 0.95)
        })
        .collect();
    Plot::new("histogram_plot")
        .height(130.0)
        .allow_scroll(false)
        .allow_zoom(false)
        .allow_drag(false)
        .x_axis_label("stops from 18 % grey (scene-linear Y)")
        .y_axis_label("pixels")
        .show(ui, |plot| {
            plot.bar_chart(BarChart::new("pixels", bars).color(egui::Color32::LIGHT_GRAY));
            plot.vline(
                VLine::new("display white at this exposure", f64::from(white_ev))
                    .color(egui::Color32::from_rgb(240, 120, 90)),
            );
            plot.vline(
                VLine::new("18 % grey at this exposure", f64::from(grey_ev))
                    .color(egui::Color32::from_rgb(120, 170, 240))
                    .style(egui_plot::LineStyle::dashed_loose()),
            );
        });
    let above = h
        .counts
        .iter()
        .enumerate()
        .filter(|(k, _)| h.lo_ev + *k as f32 * h.step_ev >= white_ev)
        .map(|(_, &n)| n)
        .sum::<u32>();
    ui.label(format!(
        "{} pixels of the mesh · median {} · {:.1} % at or over display white ({:+.2} EV), 18 % grey at {:+.2} EV",
        h.pixels,
        h.median_ev
            .map_or("none".into(), |m| format!("{m:+.2} EV")),
        100.0 * above as f64 / f64::from(h.pixels.max(1)),
        white_ev,
        grey_ev
    ))
    .on_hover_text("Y = 0.2126 R + 0.7152 G + 0.0722 B of the linear radiance (ITU-R BT.709), before exposure and the display transform; 0 EV is Y = 0.18. The red line is the Y that the exposure makes 1.0 (the display transform then compresses it), the blue one the Y it makes 0.18. Binned in quarter stops from −10 to +6 EV; the first and last bins hold what lies beyond.");
}
