//! File → Save turntable…: N converged frames around the head, written as
//! an animated GIF, an animated PNG (APNG: full colour, where GIF has 256)
//! and a PNG sequence, on a thread of its own with a progress bar and
//! Cancel.
//!
//! Each frame is the viewport's own request (look, comparison, mesh, maps,
//! light, environment, size) with the camera turned by 360°·k/N about the
//! head, rendered by a second render thread (`viewport::Viewport`) until it
//! converges, so a turntable shows what the viewport would. The key light
//! turns with the camera unless asked not to (the head then spins under a
//! fixed studio light); an HDR environment stays put. Nothing is written
//! until every frame is in: a cancelled turntable leaves no files.

pub use super::state::TurntableSettings;
use super::viewport::{Request, Viewport};
use super::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::Receiver;
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The frame counts the window offers (a field would allow any).
pub const FRAME_RANGE: std::ops::RangeInclusive<u32> = 2..=360;

/// The files a turntable at `gif` writes: the GIF, the APNG, then the
/// frames.
pub fn planned_paths(gif: &Path, settings: &TurntableSettings) -> Vec<PathBuf> {
    let mut out = vec![gif.to_path_buf()];
    if settings.apng {
        out.push(apng_path(gif));
    }
    if settings.png_sequence {
        let (dir, stem) = frames_dir(gif);
        out.extend((0..settings.frames).map(|k| dir.join(format!("{stem}_{k:03}.png"))));
    }
    out
}

/// `<stem>.png` beside the GIF: the APNG (a viewer without APNG shows its
/// first frame).
pub fn apng_path(gif: &Path) -> PathBuf {
    gif.with_extension("png")
}

/// The frames as an APNG looping forever, each shown `delay_ms`: RGBA 8
/// bits, every frame whole (no blending or offsets), so each decodes to
/// exactly the frame given (APNG 1.0 specification, Mozilla: acTL with
/// num_plays 0, an fcTL per frame, the first in IDAT).
pub fn encode_apng(frames: &[image::RgbaImage], delay_ms: u32) -> Result<Vec<u8>, String> {
    let first = frames.first().ok_or("no frames")?;
    let (w, h) = first.dimensions();
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        enc.set_animated(frames.len() as u32, 0)
            .map_err(|e| e.to_string())?;
        let delay = delay_ms.clamp(1, u16::MAX as u32) as u16;
        enc.set_frame_delay(delay, 1000)
            .map_err(|e| e.to_string())?;
        let mut writer = enc.write_header().map_err(|e| e.to_string())?;
        for f in frames {
            if f.dimensions() != (w, h) {
                return Err(format!(
                    "frame of {}×{} in a {w}×{h} animation",
                    f.width(),
                    f.height()
                ));
            }
            writer
                .write_image_data(f.as_raw())
                .map_err(|e| e.to_string())?;
        }
        writer.finish().map_err(|e| e.to_string())?;
    }
    Ok(bytes)
}

/// `<folder>/<stem>_frames` and the stem, for the PNG sequence.
fn frames_dir(gif: &Path) -> (PathBuf, String) {
    let stem = gif
        .file_stem()
        .map_or_else(|| "turntable".into(), |s| s.to_string_lossy().into_owned());
    let dir = gif
        .parent()
        .unwrap_or_else(|| Path::new(""))
        .join(format!("{stem}_frames"));
    (dir, stem)
}

enum Progress {
    /// Frames rendered so far.
    Frame(u32),
    /// Encoding and writing.
    Writing,
    Finished(Result<Vec<PathBuf>, String>),
}

/// A turntable being rendered.
pub struct TurntableJob {
    cancel: Arc<AtomicBool>,
    rx: Receiver<Progress>,
    pub out: PathBuf,
    pub total: u32,
    pub done: u32,
    writing: bool,
    started: Instant,
}

impl TurntableJob {
    /// Starts rendering `base` turned through one revolution.
    pub fn start(
        base: Request,
        settings: TurntableSettings,
        out: PathBuf,
        wake: impl Fn() + Send + 'static,
    ) -> Self {
        let cancel = Arc::new(AtomicBool::new(false));
        let (tx, rx) = std::sync::mpsc::channel();
        let (theirs, path) = (cancel.clone(), out.clone());
        std::thread::spawn(move || {
            let send = |p: Progress| {
                let _ = tx.send(p);
                wake();
            };
            let r = render(&base, &settings, &theirs, &send).and_then(|frames| {
                send(Progress::Writing);
                write(&frames, &settings, &path)
            });
            send(Progress::Finished(r));
        });
        Self {
            cancel,
            rx,
            out,
            total: settings.frames,
            done: 0,
            writing: false,
            started: Instant::now(),
        }
    }

    /// Asks the thread to stop (it answers with an error, writing nothing).
    pub fn cancel(&self) {
        self.cancel.store(true, Ordering::Relaxed);
    }

    /// The result once finished.
    fn poll(&mut self) -> Option<Result<Vec<PathBuf>, String>> {
        let mut finished = None;
        for p in self.rx.try_iter() {
            match p {
                Progress::Frame(k) => self.done = k,
                Progress::Writing => self.writing = true,
                Progress::Finished(r) => finished = Some(r),
            }
        }
        finished
    }

    /// For the progress bar.
    fn text(&self) -> String {
        if self.writing {
            return format!("writing {} …", self.out.display());
        }
        let elapsed = self.started.elapsed().as_secs_f64();
        let left = if self.done > 0 {
            let per = elapsed / self.done as f64;
            format!(
                " · about {:.0} s left",
                per * (self.total - self.done) as f64
            )
        } else {
            String::new()
        };
        format!("frame {} of {}{left}", self.done + 1, self.total)
    }
}

const CANCELLED: &str = "cancelled: nothing written";

/// Renders the frames, each until it converges.
fn render(
    base: &Request,
    settings: &TurntableSettings,
    cancel: &AtomicBool,
    send: &dyn Fn(Progress),
) -> Result<Vec<image::RgbaImage>, String> {
    let mut viewport = Viewport::start(|| {});
    let n = settings.frames.max(1);
    let mut frames = Vec::with_capacity(n as usize);
    for k in 0..n {
        let turn = std::f32::consts::TAU * k as f32 / n as f32;
        let mut req = base.clone();
        req.interactive = false;
        req.view.orbit.camera_yaw_rad += turn;
        if settings.light_follows {
            req.view.orbit.light_azimuth_rad += turn;
        }
        let image = viewport
            .render_converged(req, &|| cancel.load(Ordering::Relaxed))
            .map_err(|e| format!("frame {}: {e}", k + 1))?
            .ok_or_else(|| CANCELLED.to_string())?;
        frames.push(image);
        send(Progress::Frame(k + 1));
    }
    Ok(frames)
}

/// Encodes the GIF (looping, `seconds` a turn) and the PNG sequence, each
/// file written to a temporary path and renamed.
fn write(
    frames: &[image::RgbaImage],
    settings: &TurntableSettings,
    gif: &Path,
) -> Result<Vec<PathBuf>, String> {
    use image::codecs::gif::{GifEncoder, Repeat};
    let at = |p: &Path, e: &dyn std::fmt::Display| format!("{}: {e}", p.display());
    let delay_ms = (1000.0 * settings.seconds / frames.len().max(1) as f32)
        .round()
        .max(20.0) as u32;
    let mut bytes = Vec::new();
    {
        // Speed 10 of 30: NeuQuant's palette per frame, good for skin.
        let mut enc = GifEncoder::new_with_speed(&mut bytes, 10);
        enc.set_repeat(Repeat::Infinite).map_err(|e| at(gif, &e))?;
        let delay = image::Delay::from_numer_denom_ms(delay_ms, 1);
        enc.encode_frames(
            frames
                .iter()
                .map(|f| image::Frame::from_parts(f.clone(), 0, 0, delay)),
        )
        .map_err(|e| at(gif, &e))?;
    }
    let mut written = Vec::new();
    if settings.apng {
        let path = apng_path(gif);
        let apng = encode_apng(frames, delay_ms).map_err(|e| at(&path, &e))?;
        crate::fsutil::write_atomic(&path, &apng).map_err(|e| at(&path, &e))?;
        written.push(path);
    }
    if settings.png_sequence {
        let (dir, _) = frames_dir(gif);
        std::fs::create_dir_all(&dir).map_err(|e| at(&dir, &e))?;
        for (f, path) in frames.iter().zip(
            planned_paths(gif, settings)
                .into_iter()
                .skip(1 + settings.apng as usize),
        ) {
            let mut png = Vec::new();
            f.write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
                .map_err(|e| at(&path, &e))?;
            crate::fsutil::write_atomic(&path, &png).map_err(|e| at(&path, &e))?;
            written.push(path);
        }
    }
    crate::fsutil::write_atomic(gif, &bytes).map_err(|e| at(gif, &e))?;
    written.insert(0, gif.to_path_buf());
    Ok(written)
}

impl EditorApp {
    /// File → Save turntable…: its settings, Save…, then the progress
    /// with Cancel.
    pub(super) fn turntable_window_ui(&mut self, ctx: &egui::Context) {
        if let Some(job) = self.jobs.turntable.as_mut() {
            if let Some(r) = job.poll() {
                let out = job.out.clone();
                self.jobs.turntable = None;
                self.say(match r {
                    Ok(files) => {
                        let apng = files.contains(&apng_path(&out));
                        let pngs = files.len() - 1 - apng as usize;
                        format!(
                            "Saved turntable {} ({} frames{}{})",
                            out.display(),
                            self.ui_state.turntable.frames,
                            if apng { ", an APNG" } else { "" },
                            if pngs > 0 {
                                format!(", and {pngs} PNGs")
                            } else {
                                String::new()
                            }
                        )
                    }
                    Err(e) if e == CANCELLED => format!("Turntable {CANCELLED}"),
                    Err(e) => format!("Error: turntable {}: {e}", out.display()),
                });
            } else {
                ctx.request_repaint_after(Duration::from_millis(200));
            }
        }
        if !self.dialogs.turntable_open && self.jobs.turntable.is_none() {
            return;
        }
        let mut open = true;
        let mut save = false;
        let mut cancel = false;
        let running = self.jobs.turntable.is_some();
        let at = self.window_pos_in_viewport(40.0);
        egui::Window::new("Save turntable")
            .collapsible(false)
            .resizable(false)
            .default_pos(at)
            .open(&mut open)
            .show(ctx, |ui| {
                let s = &mut self.ui_state.turntable;
                ui.add_enabled_ui(!running, |ui| {
                    egui::Grid::new("turntable_settings").num_columns(2).show(ui, |ui| {
                        ui.label("Frames");
                        ui.add(egui::DragValue::new(&mut s.frames).range(FRAME_RANGE).suffix(" frames"))
                            .on_hover_text("Frames in one turn (360° / frames apart). Each is rendered until it converges.");
                        ui.end_row();
                        ui.label("One turn");
                        ui.add(egui::DragValue::new(&mut s.seconds).range(0.5..=60.0).speed(0.1).suffix(" s"))
                            .on_hover_text("How long the GIF takes for one turn.");
                        ui.end_row();
                    });
                    ui.checkbox(&mut s.light_follows, "Key light turns with the camera")
                        .on_hover_text("On: the head spins under a fixed studio light. Off: the camera walks round a head lit from one side. An HDR environment never turns.");
                    ui.checkbox(&mut s.apng, "Also an animated PNG")
                        .on_hover_text("<name>.png beside the GIF: an APNG in full colour (the GIF has 256 colours a frame). Browsers, Discord and most viewers play it; others show its first frame.");
                    ui.checkbox(&mut s.png_sequence, "Also a PNG per frame")
                        .on_hover_text("Written to <name>_frames/ beside the GIF.");
                });
                ui.label("At the viewport's size and view, as the viewport shows it (a comparison too): the method's converged frames.");
                match self.jobs.turntable.as_ref() {
                    Some(job) => {
                        let f = if job.writing { 1.0 } else { job.done as f32 / job.total.max(1) as f32 };
                        ui.add(egui::ProgressBar::new(f).text(job.text()).desired_width(360.0));
                        if ui.button("Cancel turntable").clicked() {
                            cancel = true;
                        }
                    }
                    None => {
                        if ui.button("Save turntable as GIF…").clicked() {
                            save = true;
                        }
                    }
                }
            });
        if cancel {
            if let Some(job) = &self.jobs.turntable {
                job.cancel();
            }
        }
        if save {
            self.open_dialog(DialogKind::SaveTurntable);
        }
        if !open {
            self.dialogs.turntable_open = false;
            if let Some(job) = &self.jobs.turntable {
                job.cancel();
            }
        }
    }

    /// Frames done and in all of the turntable rendering (UI tests).
    pub fn turntable_progress(&self) -> Option<(u32, u32)> {
        self.jobs.turntable.as_ref().map(|j| (j.done, j.total))
    }

    /// Starts a turntable to `gif` from the viewport's current request
    /// (the window polls it while it runs).
    pub(super) fn start_turntable(&mut self, gif: PathBuf) {
        let Some(base) = self.viewport_request() else {
            self.say(format!(
                "Error: {}: no viewport to turn (wait for the head to appear)",
                gif.display()
            ));
            return;
        };
        self.jobs.turntable = Some(TurntableJob::start(
            base,
            self.ui_state.turntable,
            gif,
            self.waker.as_fn(),
        ));
        self.dialogs.turntable_open = true;
    }
}
