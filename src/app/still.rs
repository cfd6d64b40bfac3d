//! File → Save image at size…: the viewport's view (look, comparison,
//! mesh, light) rendered offscreen at a chosen size up to 4096 a side,
//! supersampled, until it converges, on a thread of its own with progress
//! and Cancel; written as a PNG to a temporary path and renamed.
//!
//! Supersampling renders k times the size a side and averages each k×k
//! block (a box filter: every rendered pixel weighs the same, so a flat
//! colour stays exactly that colour).

pub use super::state::StillSettings;
use super::viewport::{Request, Viewport};
use super::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Receiver;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The largest saved side, and the largest side rendered (supersampled).
pub const MAX_SIDE: u32 = 4096;
pub const MAX_RENDER_SIDE: u32 = 8192;

/// The supersampling factors `settings` allows: k with size·k within
/// [`MAX_RENDER_SIDE`].
pub fn factors(settings: &StillSettings) -> Vec<u32> {
    [1, 2, 3, 4]
        .into_iter()
        .filter(|k| settings.width.max(settings.height) * k <= MAX_RENDER_SIDE)
        .collect()
}

/// Each k×k block of `img` averaged into one pixel: the colour channels
/// in linear light (sRGB decoded, averaged, encoded again, so an edge
/// between light and dark is not darkened), alpha as it is; `img` is k
/// times the output a side.
pub fn box_downsample(img: &image::RgbaImage, k: u32) -> image::RgbaImage {
    if k <= 1 {
        return img.clone();
    }
    let (w, h) = (img.width() / k, img.height() / k);
    let n = (k * k) as f64;
    image::RgbaImage::from_fn(w, h, |x, y| {
        let mut sum = [0.0f64; 4];
        for dy in 0..k {
            for dx in 0..k {
                let p = img.get_pixel(x * k + dx, y * k + dy);
                for c in 0..3 {
                    sum[c] += crate::render::compare::srgb_to_linear(p[c]) as f64;
                }
                sum[3] += p[3] as f64;
            }
        }
        let rgb = [0, 1, 2].map(|c| super::analysis::linear_to_srgb8(sum[c] / n));
        image::Rgba([rgb[0], rgb[1], rgb[2], (sum[3] / n).round() as u8])
    })
}

/// A still being rendered.
pub struct StillJob {
    cancel: Arc<AtomicBool>,
    rx: Receiver<Result<(u32, u32), String>>,
    pub out: PathBuf,
    settings: StillSettings,
    started: Instant,
}

const CANCELLED: &str = "cancelled: nothing written";

impl StillJob {
    /// Starts rendering `base` at `settings`' size into `out`.
    pub fn start(
        base: Request,
        settings: StillSettings,
        out: PathBuf,
        wake: impl Fn() + Send + 'static,
    ) -> Self {
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = std::sync::mpsc::channel();
        let (theirs, path) = (cancel.clone(), out.clone());
        std::thread::spawn(move || {
            let r = render_still(base, settings, &theirs, &path);
            let _ = tx.send(r);
            wake();
        });
        Self {
            cancel,
            rx,
            out,
            settings,
            started: Instant::now(),
        }
    }
}

/// Renders and writes the still; its size.
fn render_still(
    base: Request,
    s: StillSettings,
    cancel: &AtomicBool,
    out: &Path,
) -> Result<(u32, u32), String> {
    let k = s.supersample.max(1);
    let mut req = base;
    req.interactive = false;
    req.size = (s.width * k, s.height * k);
    let mut viewport = Viewport::start(|| {});
    let image = viewport
        .render_converged(req, &|| cancel.load(Ordering::Relaxed))?
        .ok_or_else(|| CANCELLED.to_string())?;
    let still = box_downsample(&image, k);
    let mut png = Vec::new();
    still
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| e.to_string())?;
    crate::fsutil::write_atomic(out, &png).map_err(|e| e.to_string())?;
    Ok(still.dimensions())
}

impl EditorApp {
    /// The "Save image at size" window: size, presets, supersampling,
    /// Save…, then progress with Cancel.
    pub(super) fn still_window_ui(&mut self, ctx: &egui::Context) {
        if let Some(job) = self.jobs.still.as_ref() {
            match job.rx.try_recv() {
                Ok(r) => {
                    let (out, secs) = (job.out.clone(), job.started.elapsed().as_secs_f64());
                    self.jobs.still = None;
                    self.say(match r {
                        Ok((w, h)) => format!(
                            "Saved image {} ({w}×{h}, {}× supersampled, converged, {secs:.1} s)",
                            out.display(),
                            self.ui_state.still.supersample
                        ),
                        Err(e) if e == CANCELLED => format!("Image {CANCELLED}"),
                        Err(e) => format!("Error: {}: {e}", out.display()),
                    });
                }
                Err(_) => ctx.request_repaint_after(Duration::from_millis(200)),
            }
        }
        if !self.dialogs.still_open && self.jobs.still.is_none() {
            return;
        }
        let mut open = true;
        let (mut save, mut cancel) = (false, false);
        let running = self.jobs.still.is_some();
        // Inside the viewport, clear of the Look panel.
        let at = self.window_pos_in_viewport(8.0);
        egui::Window::new("Save image at size")
            .collapsible(false)
            .resizable(false)
            .default_pos(at)
            .open(&mut open)
            .show(ctx, |ui| {
                let s = &mut self.ui_state.still;
                ui.add_enabled_ui(!running, |ui| {
                    ui.horizontal(|ui| {
                        ui.add(egui::DragValue::new(&mut s.width).range(16..=MAX_SIDE).suffix(" px"))
                            .on_hover_text("Width of the saved image (16–4096 px).");
                        ui.label("×");
                        ui.add(egui::DragValue::new(&mut s.height).range(16..=MAX_SIDE).suffix(" px"))
                            .on_hover_text("Height of the saved image (16–4096 px).");
                    });
                    ui.horizontal(|ui| {
                        for (w, h) in [(1920, 1080), (2048, 2048), (3840, 2160), (4096, 4096)] {
                            if ui.button(format!("{w}×{h}")).clicked() {
                                (s.width, s.height) = (w, h);
                            }
                        }
                    });
                    let allowed = factors(s);
                    if !allowed.contains(&s.supersample) {
                        s.supersample = allowed.last().copied().unwrap_or(1);
                    }
                    ui.horizontal(|ui| {
                        ui.label("Supersampling");
                        for k in [1, 2, 3, 4] {
                            ui.add_enabled_ui(allowed.contains(&k), |ui| {
                                ui.radio_value(&mut s.supersample, k, format!("{k}×"))
                                    .on_hover_text(format!("Render {k}×{k} pixels for each saved pixel and average them (a box filter)."))
                                    .on_disabled_hover_text(format!("At most {MAX_RENDER_SIDE} px a side are rendered."));
                            });
                        }
                    });
                    ui.label(format!(
                        "Renders {}×{} offscreen, whatever the window's size: the viewport's look, comparison, mesh, light and camera (the framing follows the aspect).",
                        s.width * s.supersample,
                        s.height * s.supersample
                    ));
                });
                match self.jobs.still.as_ref() {
                    Some(job) => {
                        ui.horizontal(|ui| {
                            super::report::spinner(ui);
                            ui.label(format!(
                                "rendering {}×{} until it converges … {:.0} s",
                                job.settings.width * job.settings.supersample,
                                job.settings.height * job.settings.supersample,
                                job.started.elapsed().as_secs_f64()
                            ));
                        });
                        if ui.button("Cancel image").clicked() {
                            cancel = true;
                        }
                    }
                    None => {
                        if ui.button("Save image as PNG…").clicked() {
                            save = true;
                        }
                    }
                }
            });
        if cancel {
            if let Some(job) = &self.jobs.still {
                job.cancel.store(true, Ordering::Relaxed);
            }
        }
        if save {
            self.open_dialog(DialogKind::SaveStill);
        }
        if !open {
            self.dialogs.still_open = false;
            if let Some(job) = &self.jobs.still {
                job.cancel.store(true, Ordering::Relaxed);
            }
        }
    }

    /// Whether a still is rendering (UI tests).
    pub fn still_running(&self) -> bool {
        self.jobs.still.is_some()
    }

    /// Starts the still to `out` from the viewport's current request.
    pub(super) fn start_still(&mut self, out: PathBuf) {
        let Some(base) = self.viewport_request() else {
            self.say(format!(
                "Error: {}: no viewport view to render (wait for the head to appear)",
                out.display()
            ));
            return;
        };
        self.jobs.still = Some(StillJob::start(
            base,
            self.ui_state.still,
            out,
            self.waker.as_fn(),
        ));
        self.dialogs.still_open = true;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box filter keeps a flat colour exactly and averages a block in
    /// linear light: a 2×2 block of black and three whites is 0.75 linear,
    /// sRGB 1.055 · 0.75^(1/2.4) − 0.055 = 0.8808 → 225 (IEC 61966-2-1),
    /// where averaging the bytes would give 191.
    #[test]
    fn box_downsampling_averages_each_block() {
        let flat = image::RgbaImage::from_pixel(8, 6, image::Rgba([10, 200, 33, 255]));
        let d = box_downsample(&flat, 2);
        assert_eq!(d.dimensions(), (4, 3));
        assert!(d.pixels().all(|p| *p == image::Rgba([10, 200, 33, 255])));
        let mut block = image::RgbaImage::from_pixel(2, 2, image::Rgba([255, 255, 255, 255]));
        block.put_pixel(0, 0, image::Rgba([0, 0, 0, 255]));
        let want = ((1.055 * 0.75f64.powf(1.0 / 2.4) - 0.055) * 255.0).round() as u8;
        assert_eq!(want, 225);
        assert_eq!(
            *box_downsample(&block, 2).get_pixel(0, 0),
            image::Rgba([want, want, want, 255])
        );
    }

    /// Supersampling never renders past 8192 a side.
    #[test]
    fn factors_keep_the_render_within_bounds() {
        let s = |w, h| StillSettings {
            width: w,
            height: h,
            supersample: 1,
        };
        assert_eq!(factors(&s(4096, 4096)), vec![1, 2]);
        assert_eq!(factors(&s(2048, 1024)), vec![1, 2, 3, 4]);
        assert_eq!(factors(&s(3000, 100)), vec![1, 2]);
    }
}
