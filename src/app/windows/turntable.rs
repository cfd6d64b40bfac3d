//! File → Save turntable…: N converged frames around the head, written as
//! an animated GIF, an animated PNG (APNG: full colour, where GIF has 256)
//! and a PNG sequence, on a thread of its own with a progress bar and
//! Cancel.
//!
//! Each frame is the viewport's own request (look, comparison, mesh, maps,
//! light, environment, size) with the camera turned by 360°·k/N about the
//! head, rendered by a second render thread (`viewport::Viewport`) until it
//! converges, so a turntable shows what the viewport would. The lights
//! (key, fill and rim) turn with the camera unless asked not to (the head then spins under a
//! fixed studio light); an HDR environment stays put. Nothing is written
//! until every frame is in: a cancelled turntable leaves no files.

use super::{Action, Menu, Window, WindowView};
pub use crate::app::state::TurntableSettings;
use crate::app::viewport::{Request, Viewport};
use crate::app::DialogKind;
use std::path::{Path, PathBuf};
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
        req.want_radiance = false;
        req.view.orbit.camera_yaw_rad += turn;
        if settings.light_follows {
            let o = &mut req.view.orbit;
            o.light_azimuth_rad += turn;
            o.fill.azimuth_rad += turn;
            o.rim.azimuth_rad += turn;
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
        let apng =
            crate::export::frames::encode_apng(frames, delay_ms).map_err(|e| at(&path, &e))?;
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

/// File → Save turntable: its open flag and the turntable rendering.
#[derive(Default)]
pub struct TurntableWindow {
    open: bool,
    job: Option<TurntableJob>,
}

impl TurntableWindow {
    /// Frames done and in all of the turntable rendering.
    pub fn progress(&self) -> Option<(u32, u32)> {
        self.job.as_ref().map(|j| (j.done, j.total))
    }

    /// Starts a turntable to `gif` from `base` (the viewport's request).
    pub fn start(
        &mut self,
        base: Request,
        settings: TurntableSettings,
        gif: PathBuf,
        wake: impl Fn() + Send + 'static,
    ) {
        self.job = Some(TurntableJob::start(base, settings, gif, wake));
        self.open = true;
    }

    /// A finished turntable's line for the status bar, if one finished.
    fn finished(&mut self, ctx: &egui::Context) -> Option<String> {
        let job = self.job.as_mut()?;
        let Some(r) = job.poll() else {
            ctx.request_repaint_after(Duration::from_millis(200));
            return None;
        };
        let (out, frames) = (job.out.clone(), job.total);
        self.job = None;
        Some(match r {
            Ok(files) => {
                let apng = files.contains(&apng_path(&out));
                let pngs = files.len() - 1 - apng as usize;
                format!(
                    "Saved turntable {} ({frames} frames{}{})",
                    out.display(),
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
        })
    }
}

/// Frames, one turn's time, the light and the extra files.
fn settings_ui(ui: &mut egui::Ui, s: &mut TurntableSettings) {
    egui::Grid::new("turntable_settings")
        .num_columns(2)
        .show(ui, |ui| {
            ui.label("Frames");
            ui.add(
                egui::DragValue::new(&mut s.frames)
                    .range(FRAME_RANGE)
                    .suffix(" frames"),
            )
            .on_hover_text(
                "Frames in one turn (360° / frames apart). Each is rendered until it converges.",
            );
            ui.end_row();
            ui.label("One turn");
            ui.add(
                egui::DragValue::new(&mut s.seconds)
                    .range(0.5..=60.0)
                    .speed(0.1)
                    .suffix(" s"),
            )
            .on_hover_text("How long the GIF takes for one turn.");
            ui.end_row();
        });
    ui.checkbox(&mut s.light_follows, "Lights turn with the camera")
        .on_hover_text("On: the head spins under a fixed studio light. Off: the camera walks round a head lit from one side. An HDR environment never turns.");
    ui.checkbox(&mut s.apng, "Also an animated PNG")
        .on_hover_text("<name>.png beside the GIF: an APNG in full colour (the GIF has 256 colours a frame). Browsers, Discord and most viewers play it; others show its first frame.");
    ui.checkbox(&mut s.png_sequence, "Also a PNG per frame")
        .on_hover_text("Written to <name>_frames/ beside the GIF.");
}

impl Window for TurntableWindow {
    fn title(&self) -> &'static str {
        "Save turntable"
    }
    fn menu(&self) -> Option<Menu> {
        Some(Menu::FileImages)
    }
    fn menu_tooltip(&self) -> &'static str {
        "N converged frames around the head as an animated GIF and a PNG per frame, with progress and Cancel"
    }
    /// Open as the artist left it; a turntable rendering shows its
    /// window anyway (Escape hides it, the render goes on; its close
    /// button or Cancel stops it).
    fn is_open(&self) -> bool {
        self.open
    }
    fn set_open(&mut self, open: bool) {
        self.open = open;
    }

    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        let mut actions: Vec<Action> = self.finished(ctx).into_iter().map(Action::Say).collect();
        if !self.open && self.job.is_none() {
            return actions;
        }
        let mut open = true;
        let mut settings = *view.turntable;
        egui::Window::new(self.title())
            .collapsible(false)
            .resizable(false)
            .default_pos(view.pos_in_viewport(40.0))
            .open(&mut open)
            .show(ctx, |ui| {
                ui.add_enabled_ui(self.job.is_none(), |ui| settings_ui(ui, &mut settings));
                ui.label("At the viewport's size and view, as the viewport shows it (a comparison too): the method's converged frames.");
                match self.job.as_ref() {
                    Some(job) => {
                        let f = if job.writing { 1.0 } else { job.done as f32 / job.total.max(1) as f32 };
                        ui.add(egui::ProgressBar::new(f).text(job.text()).desired_width(360.0));
                        if ui.button("Cancel turntable").clicked() {
                            job.cancel();
                        }
                    }
                    None => {
                        if ui.button("Save turntable as GIF…").clicked() {
                            actions.push(Action::OpenDialog(DialogKind::SaveTurntable));
                        }
                    }
                }
            });
        if settings != *view.turntable {
            actions.push(Action::SetTurntable(settings));
        }
        if !open {
            self.open = false;
            if let Some(job) = &self.job {
                job.cancel();
            }
        }
        actions
    }
}
