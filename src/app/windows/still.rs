//! File → Save image at size…: the viewport's view (look, comparison,
//! mesh, light) rendered offscreen at a chosen size up to 4096 a side,
//! supersampled, until it converges, on a thread of its own with progress
//! and Cancel; written as a PNG (what the viewport shows) or an OpenEXR
//! (the scene-linear light, the background transparent), with the
//! subsurface layer beside it if asked, each to a temporary path and
//! renamed.
//!
//! Supersampling renders k times the size a side and averages each k×k
//! block (a box filter: every rendered pixel weighs the same, so a flat
//! colour stays exactly that colour).

use super::{Action, Menu, Window, WindowView};
pub use crate::app::state::StillSettings;
use crate::app::viewport::{Request, Viewport, MAX_REFINE_FRAMES};
use crate::app::DialogKind;
use std::path::{Path, PathBuf};
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

/// A still being rendered.
pub struct StillJob {
    cancel: Arc<AtomicBool>,
    rx: Receiver<Result<(u32, u32), String>>,
    pub out: PathBuf,
    settings: StillSettings,
    started: Instant,
    /// The frames rendered so far and their mean time (ms), from the
    /// render thread.
    progress: Arc<std::sync::Mutex<(u32, f64)>>,
}

/// How far a still has got, for its window: the fraction of the most
/// frames it may take ([`MAX_REFINE_FRAMES`]: it stops as soon as the
/// frame stops changing, often far sooner) and a line with the frame, the
/// time a frame and the most time left. `frames` done, `frame_ms` their
/// mean time, `elapsed_s` since it started.
pub fn progress_text(frames: u32, frame_ms: f64, elapsed_s: f64) -> (f32, String) {
    if frames == 0 {
        return (0.0, format!("the first frame … {elapsed_s:.0} s"));
    }
    let most = MAX_REFINE_FRAMES;
    let left_s = (most.saturating_sub(frames)) as f64 * frame_ms / 1e3;
    (
        frames as f32 / most as f32,
        format!(
            "frame {frames} of at most {most} · {:.1} s a frame · at most {left_s:.0} s left (it stops once the frame stops changing) · {elapsed_s:.0} s",
            frame_ms / 1e3
        ),
    )
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
        let progress = Arc::new(std::sync::Mutex::new((0u32, 0.0f64)));
        let (tx, rx) = std::sync::mpsc::channel();
        let (theirs, path, told) = (cancel.clone(), out.clone(), progress.clone());
        std::thread::spawn(move || {
            // Only the refining frames count (a ground truth's tiles and its
            // coarse frame are not frames of the running mean).
            let on_frame = |q: crate::app::viewport::Quality, ms: f64| {
                if !matches!(q, crate::app::viewport::Quality::Refining { .. }) {
                    return;
                }
                if let Ok(mut p) = told.lock() {
                    p.1 = (p.1 * p.0 as f64 + ms) / (p.0 + 1) as f64;
                    p.0 += 1;
                }
            };
            let r = render_still(base, settings, &theirs, &path, &on_frame);
            let _ = tx.send(r);
            wake();
        });
        Self {
            cancel,
            rx,
            out,
            settings,
            started: Instant::now(),
            progress,
        }
    }
}

/// Renders and writes the still; its size.
fn render_still(
    base: Request,
    s: StillSettings,
    cancel: &AtomicBool,
    out: &Path,
    on_frame: &dyn Fn(crate::app::viewport::Quality, f64),
) -> Result<(u32, u32), String> {
    let k = s.supersample.max(1);
    let needs_linear = is_exr(out) || s.subsurface_file;
    if needs_linear {
        let comparing = base
            .b
            .as_ref()
            .is_some_and(|(_, mode, _)| *mode != crate::app::state::CompareMode::Off)
            && !base.show_b;
        linear_refused(comparing, &s).map_or(Ok(()), Err)?;
    }
    let mut req = base;
    req.interactive = false;
    req.size = (s.width * k, s.height * k);
    req.want_radiance = needs_linear;
    // The method's converged frame is the still (the ground truth that
    // "to truth" would go on to is not waited for).
    req.refine_to_truth = false;
    let (exposure, tone_map) = (req.view.orbit.exposure, req.view.tone_map);
    let mut viewport = Viewport::start(|| {});
    let (image, radiance) = viewport
        .render_converged_with(req, &|| cancel.load(Ordering::Relaxed), on_frame)?
        .ok_or_else(|| CANCELLED.to_string())?;
    let linear = || {
        radiance.as_deref().ok_or_else(|| {
            "the frame's linear light could not be read back from the GPU: save a PNG without the subsurface layer".to_string()
        })
    };
    let size = if is_exr(out) {
        let r = linear()?;
        let (w, h, pixels) = r.box_downsample(&r.radiance, k);
        let bytes = crate::export::rgba_exr_bytes((w, h), &pixels, EXR_NOTE)?;
        crate::fsutil::write_atomic(out, &bytes).map_err(|e| e.to_string())?;
        (w, h)
    } else {
        let still = crate::export::frames::box_downsample(&image, k);
        crate::fsutil::write_atomic(out, &png_bytes(&still)?).map_err(|e| e.to_string())?;
        still.dimensions()
    };
    if s.subsurface_file {
        let r = linear()?;
        let (w, h, pixels) = r.box_downsample(&r.subsurface(), k);
        let path = subsurface_path(out);
        let bytes = if is_exr(out) {
            crate::export::rgba_exr_bytes((w, h), &pixels, SUBSURFACE_NOTE)?
        } else {
            png_bytes(&display_rgba((w, h), &pixels, exposure, tone_map))?
        };
        crate::fsutil::write_atomic(&path, &bytes).map_err(|e| e.to_string())?;
    }
    Ok(size)
}

const EXR_NOTE: &str = "scatterlab still: scene-linear radiance (scattered x albedo + specular) before exposure and the display transform; alpha the mesh's coverage, the background transparent (0), colour premultiplied";
const SUBSURFACE_NOTE: &str = "scatterlab still, subsurface layer: the light through the skin (scattered x albedo), no specular, before exposure and the display transform; alpha the coverage";

/// The most bytes one GPU buffer may hold here (wgpu's downlevel limit,
/// `render::context`): the linear light is read back as 8 bytes a pixel.
const MAX_READBACK_BYTES: u64 = 256 << 20;

/// Why a still's linear light (an EXR, the subsurface layer) cannot be
/// had, said before rendering: it is one look's (not a comparison's), and
/// it is read back in one buffer.
fn linear_refused(comparing: bool, s: &StillSettings) -> Option<String> {
    if comparing {
        return Some("an EXR or the subsurface layer holds one look's linear light: turn Compare off (or save a PNG without the subsurface layer)".into());
    }
    let k = u64::from(s.supersample.max(1));
    let bytes = u64::from(s.width) * k * u64::from(s.height) * k * 8;
    (bytes > MAX_READBACK_BYTES).then(|| {
        format!(
            "an EXR or the subsurface layer of {}×{} at {k}× reads back {} MB of linear light, over the {} MB a GPU buffer holds here: use less supersampling or a smaller size (at most {:.1} million pixels rendered)",
            s.width,
            s.height,
            bytes >> 20,
            MAX_READBACK_BYTES >> 20,
            (MAX_READBACK_BYTES / 8) as f64 / 1e6
        )
    })
}

/// Whether `out` asks for OpenEXR (else a PNG).
fn is_exr(out: &Path) -> bool {
    out.extension()
        .is_some_and(|x| x.eq_ignore_ascii_case("exr"))
}

/// Where a still's subsurface layer goes: beside it, `_subsurface` added
/// to its name.
pub fn subsurface_path(out: &Path) -> PathBuf {
    let stem = out.file_stem().map_or("still".into(), |s| s.to_string_lossy());
    let ext = out.extension().map_or("png".into(), |s| s.to_string_lossy());
    out.with_file_name(format!("{stem}_subsurface.{ext}"))
}

/// The files a still to `out` writes with `s`.
pub fn planned_paths(out: &Path, s: &StillSettings) -> Vec<PathBuf> {
    let mut paths = vec![out.to_path_buf()];
    if s.subsurface_file {
        paths.push(subsurface_path(out));
    }
    paths
}

fn png_bytes(img: &image::RgbaImage) -> Result<Vec<u8>, String> {
    let mut png = Vec::new();
    img.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .map_err(|e| e.to_string())?;
    Ok(png)
}

/// Premultiplied linear RGBA through the exposure and the display
/// transform to 8-bit sRGB with straight alpha (a PNG's): the colour is
/// divided by the coverage first.
fn display_rgba(
    (w, h): (u32, u32),
    pixels: &[[f32; 4]],
    exposure: f32,
    tone_map: crate::render::tonemap::ToneMap,
) -> image::RgbaImage {
    use crate::model::colour::linear_to_srgb8;
    image::RgbaImage::from_fn(w, h, |x, y| {
        let p = pixels[(y * w + x) as usize];
        if p[3] <= 0.0 {
            return image::Rgba([0, 0, 0, 0]);
        }
        let c = tone_map.apply([p[0], p[1], p[2]].map(|v| exposure * v / p[3]));
        let c = c.map(|v| linear_to_srgb8(v.clamp(0.0, 1.0)));
        image::Rgba([c[0], c[1], c[2], (p[3].clamp(0.0, 1.0) * 255.0).round() as u8])
    })
}

/// File → Save image at size: its open flag and the still rendering.
#[derive(Default)]
pub struct StillWindow {
    open: bool,
    job: Option<StillJob>,
    /// What the last still came to (saved, cancelled or its error), shown
    /// in the window until the next one starts.
    last: Option<String>,
}

impl StillWindow {
    /// Whether a still is rendering.
    pub fn running(&self) -> bool {
        self.job.is_some()
    }

    /// Starts the still to `out` from `base` (the viewport's request).
    pub fn start(
        &mut self,
        base: Request,
        settings: StillSettings,
        out: PathBuf,
        wake: impl Fn() + Send + 'static,
    ) {
        self.job = Some(StillJob::start(base, settings, out, wake));
        self.last = None;
        self.open = true;
    }

    /// A finished still's line for the status bar, if one finished.
    fn poll(&mut self, ctx: &egui::Context) -> Option<String> {
        let job = self.job.as_ref()?;
        let Ok(r) = job.rx.try_recv() else {
            ctx.request_repaint_after(Duration::from_millis(200));
            return None;
        };
        let (out, secs, k, subsurface) = (
            job.out.clone(),
            job.started.elapsed().as_secs_f64(),
            job.settings.supersample,
            job.settings.subsurface_file,
        );
        self.job = None;
        Some(match r {
            Ok((w, h)) => format!(
                "Saved image {} ({w}×{h}, {k}× supersampled, converged, {secs:.1} s){}",
                out.display(),
                if subsurface {
                    format!(" and its subsurface layer {}", subsurface_path(&out).display())
                } else {
                    String::new()
                }
            ),
            Err(e) if e == CANCELLED => format!("Image {CANCELLED}"),
            Err(e) => format!("Error: {}: {e}", out.display()),
        })
    }

    fn cancel(&self) {
        if let Some(job) = &self.job {
            job.cancel.store(true, Ordering::Relaxed);
        }
    }
}

/// The size, its presets and the supersampling (while no still renders).
fn settings_ui(ui: &mut egui::Ui, s: &mut StillSettings) {
    ui.horizontal(|ui| {
        ui.add(
            egui::DragValue::new(&mut s.width)
                .range(16..=MAX_SIDE)
                .suffix(" px"),
        )
        .on_hover_text("Width of the saved image (16–4096 px).");
        ui.label("×");
        ui.add(
            egui::DragValue::new(&mut s.height)
                .range(16..=MAX_SIDE)
                .suffix(" px"),
        )
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
    ui.checkbox(&mut s.subsurface_file, "Subsurface layer as its own file")
        .on_hover_text("Also write the light through the skin alone (scattered × albedo, no specular; the background transparent) beside the image, its name ending in _subsurface: linear in an .exr, through the exposure and display transform in a .png. One look alone (Compare off). The viewport's \"SSS only\" view, what scattering adds as |ΔL*|, is saved as seen by Save image (F12).");
    ui.label("A name ending in .exr saves the scene-linear light (before exposure and the display transform) with a transparent background; .png saves what the viewport shows.");
    ui.label(format!(
        "Renders {}×{} offscreen, whatever the window's size: the viewport's look, comparison, mesh, light and camera (the framing follows the aspect).",
        s.width * s.supersample,
        s.height * s.supersample
    ));
}

impl Window for StillWindow {
    fn title(&self) -> &'static str {
        "Save image at size"
    }
    fn menu(&self) -> Option<Menu> {
        Some(Menu::FileImages)
    }
    fn menu_tooltip(&self) -> &'static str {
        "The viewport's view rendered offscreen at up to 4096×4096, supersampled, until it converges, as a PNG, with progress and Cancel"
    }
    /// Open as the artist left it; a still rendering shows its window
    /// anyway (Escape hides it, the render goes on; its close button or
    /// Cancel stops it).
    fn is_open(&self) -> bool {
        self.open
    }
    fn set_open(&mut self, open: bool) {
        self.open = open;
    }

    /// Size, presets, supersampling, Save…, then progress with Cancel.
    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        let finished = self.poll(ctx);
        if let Some(line) = &finished {
            self.last = Some(line.clone());
        }
        let mut actions: Vec<Action> = finished.into_iter().map(Action::Say).collect();
        if !self.open && self.job.is_none() {
            return actions;
        }
        let mut open = true;
        let mut settings = *view.still;
        egui::Window::new(self.title())
            .collapsible(false)
            .resizable(false)
            .default_pos(view.pos_in_viewport(8.0))
            .open(&mut open)
            .show(ctx, |ui| {
                ui.add_enabled_ui(self.job.is_none(), |ui| settings_ui(ui, &mut settings));
                match self.job.as_ref() {
                    Some(job) => {
                        let (frames, ms) = job.progress.lock().map_or((0, 0.0), |p| *p);
                        let (done, text) =
                            progress_text(frames, ms, job.started.elapsed().as_secs_f64());
                        ui.label(format!(
                            "rendering {}×{} until it converges:",
                            job.settings.width * job.settings.supersample,
                            job.settings.height * job.settings.supersample,
                        ));
                        ui.add(egui::ProgressBar::new(done).show_percentage().animate(true));
                        ui.label(text);
                        if ui.button("Cancel image").clicked() {
                            self.cancel();
                        }
                    }
                    None => {
                        match &self.last {
                            Some(saved) if saved.starts_with("Saved") => {
                                ui.label(format!("Done: {saved}"));
                            }
                            Some(other) => {
                                ui.label(other);
                            }
                            None => {}
                        }
                        if ui.button("Save image (PNG or EXR)…").clicked() {
                            actions.push(Action::OpenDialog(DialogKind::SaveStill));
                        }
                    }
                }
            });
        if settings != *view.still {
            actions.push(Action::SetStill(settings));
        }
        if !open {
            self.open = false;
            self.cancel();
        }
        actions
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The progress line's numbers, worked by hand: 4 frames of 2 s of at
    /// most 64 is 4/64 = 6.25 % with at most 60 × 2 = 120 s left.
    #[test]
    fn progress_says_the_frame_and_the_most_time_left() {
        let (f, text) = progress_text(4, 2000.0, 9.0);
        assert!((f - 0.0625).abs() < 1e-6);
        assert!(text.starts_with("frame 4 of at most 64 · 2.0 s a frame · at most 120 s left"), "{text}");
        assert_eq!(progress_text(0, 0.0, 3.0), (0.0, "the first frame … 3 s".to_string()));
    }

    /// An EXR or subsurface layer is refused before rendering while
    /// comparing, and where its linear light (8 bytes a pixel) would pass
    /// the 256 MiB a buffer holds: 4096² at 1× (128 MiB) and 5792² at 1×
    /// (255.9 MiB) go, 4096² at 2× (512 MiB) and 5793² (256.05 MiB) do not.
    #[test]
    fn linear_stills_are_refused_before_rendering_where_they_cannot_be_read() {
        let s = |w, h, k| StillSettings {
            width: w,
            height: h,
            supersample: k,
            subsurface_file: false,
        };
        assert_eq!(linear_refused(false, &s(4096, 4096, 1)), None);
        assert_eq!(linear_refused(false, &s(5792, 5792, 1)), None);
        let big = linear_refused(false, &s(4096, 4096, 2)).expect("512 MiB refused");
        assert!(big.contains("512 MB") && big.contains("supersampling"), "{big}");
        assert!(linear_refused(false, &s(5793, 5793, 1)).is_some());
        let cmp = linear_refused(true, &s(64, 64, 1)).expect("comparing refused");
        assert!(cmp.contains("Compare off"), "{cmp}");
    }

    /// Supersampling never renders past 8192 a side.
    #[test]
    fn factors_keep_the_render_within_bounds() {
        let s = |w, h| StillSettings {
            width: w,
            height: h,
            supersample: 1,
            subsurface_file: false,
        };
        assert_eq!(factors(&s(4096, 4096)), vec![1, 2]);
        assert_eq!(factors(&s(2048, 1024)), vec![1, 2, 3, 4]);
        assert_eq!(factors(&s(3000, 100)), vec![1, 2]);
    }
}
