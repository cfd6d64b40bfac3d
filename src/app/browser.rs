//! File → Browse presets…: every shipped preset as a thumbnail of the
//! default head rendered by our own renderer (its method, burley for the
//! ground truth), cached on disk so the second look costs nothing. A click
//! starts a new look from that preset, asking first if the open one has
//! unsaved changes.

use super::viewport::{Look, Request, Viewport};
use super::*;
use std::sync::mpsc::Receiver;
use std::time::Duration;

/// Thumbnail size in pixels (portrait, like a head).
pub const THUMB: (u32, u32) = (120, 150);

/// Bumped when the renderer's look changes, so older cached thumbnails are
/// not shown.
const THUMBNAIL_VERSION: u32 = 1;

/// One preset in the browser.
struct Entry {
    preset: Preset,
    image: Option<image::RgbaImage>,
    texture: Option<egui::TextureHandle>,
}

enum Message {
    /// Preset k's thumbnail, and whether it was rendered (not cached).
    Thumb(usize, image::RgbaImage, bool),
    Failed(String),
}

/// The browser's presets and the thread filling in their thumbnails.
pub struct PresetBrowser {
    entries: Vec<Entry>,
    rx: Option<Receiver<Message>>,
    /// Thumbnails rendered (not read from the cache) this time.
    pub rendered: usize,
    error: Option<String>,
}

/// FNV-1a, 64-bit: a hash that stays the same across runs and builds (the
/// cache's file names).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The cache file of `preset`'s thumbnail: its look, the thumbnail size
/// and [`THUMBNAIL_VERSION`] name it.
fn cache_path(dir: &Path, preset: &Preset) -> PathBuf {
    let look = ron::to_string(&(&preset.profile, &preset.rendering)).unwrap_or_default();
    let key = format!("{THUMBNAIL_VERSION} {}x{} {look}", THUMB.0, THUMB.1);
    dir.join(format!("{:016x}.png", fnv1a(key.as_bytes())))
}

/// The request for a preset's thumbnail: the default head from the front
/// under the studio sky, its own method (burley stands in for the ground
/// truth, which takes minutes).
fn thumbnail_request(preset: &Preset) -> Request {
    let mut look = Look::of(preset);
    look.rendering.method = look.rendering.method.preview();
    let mut view = state::ViewState::default();
    // Closer than the framing of the whole head: the face fills it.
    view.orbit.camera_distance_m *= 0.7;
    Request {
        a: look,
        b: None,
        difference_scale: None,
        show_b: false,
        view,
        size: THUMB,
        mesh: None,
        mesh_settings: Default::default(),
        interactive: false,
        refine_to_truth: false,
        seq: 0,
        background_map: None,
    }
}

impl PresetBrowser {
    /// Lists the shipped presets and starts filling in their thumbnails
    /// from `cache` (rendering and storing the missing ones).
    /// `wake` is called after each thumbnail, so it shows without input.
    pub fn open(cache: Option<PathBuf>, wake: impl Fn() + Send + 'static) -> Self {
        let entries: Vec<Entry> = library::PRESETS
            .iter()
            .filter_map(|(file, _)| library::load(file).ok())
            .map(|preset| Entry {
                preset,
                image: None,
                texture: None,
            })
            .collect();
        let presets: Vec<Preset> = entries.iter().map(|e| e.preset.clone()).collect();
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let mut viewport: Option<Viewport> = None;
            for (k, preset) in presets.iter().enumerate() {
                let cached = cache.as_deref().map(|d| cache_path(d, preset));
                if let Some(img) = cached
                    .as_deref()
                    .and_then(|p| image::open(p).ok())
                    .map(|i| i.to_rgba8())
                    .filter(|i| i.dimensions() == THUMB)
                {
                    if tx.send(Message::Thumb(k, img, false)).is_err() {
                        return;
                    }
                    wake();
                    continue;
                }
                let vp = viewport.get_or_insert_with(|| Viewport::start(|| {}));
                let img = match vp.render_converged(thumbnail_request(preset), &|| false) {
                    Ok(Some(img)) => img,
                    Ok(None) => return,
                    Err(e) => {
                        let _ = tx.send(Message::Failed(format!("{}: {e}", preset.name)));
                        wake();
                        return;
                    }
                };
                if let Some(p) = &cached {
                    // A cache that cannot be written costs a render next
                    // time, nothing else.
                    let mut png = Vec::new();
                    if img
                        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
                        .is_ok()
                    {
                        let _ = p.parent().map(std::fs::create_dir_all);
                        let _ = crate::fsutil::write_atomic(p, &png);
                    }
                }
                if tx.send(Message::Thumb(k, img, true)).is_err() {
                    return;
                }
                wake();
            }
        });
        Self {
            entries,
            rx: Some(rx),
            rendered: 0,
            error: None,
        }
    }

    fn poll(&mut self) {
        let Some(rx) = &self.rx else { return };
        loop {
            match rx.try_recv() {
                Ok(Message::Thumb(k, img, rendered)) => {
                    if let Some(e) = self.entries.get_mut(k) {
                        e.image = Some(img);
                        e.texture = None;
                    }
                    self.rendered += usize::from(rendered);
                }
                Ok(Message::Failed(e)) => self.error = Some(e),
                Err(std::sync::mpsc::TryRecvError::Empty) => break,
                Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                    self.rx = None;
                    break;
                }
            }
        }
    }

    /// Thumbnails in so far, and presets in all.
    pub fn progress(&self) -> (usize, usize) {
        (
            self.entries.iter().filter(|e| e.image.is_some()).count(),
            self.entries.len(),
        )
    }

    /// Preset `name`'s thumbnail, once in (UI tests).
    pub fn thumbnail(&self, name: &str) -> Option<&image::RgbaImage> {
        self.entries
            .iter()
            .find(|e| e.preset.name == name)
            .and_then(|e| e.image.as_ref())
    }
}

impl EditorApp {
    /// The thumbnails' cache folder: beside the editor's remembered state.
    pub(super) fn default_thumbnail_dir() -> Option<PathBuf> {
        eframe::storage_dir("scatterlab").map(|d| d.join("thumbnails"))
    }

    /// Test hook: keep thumbnails in `dir` instead.
    pub fn set_thumbnail_dir(&mut self, dir: PathBuf) {
        self.dialogs.thumbnail_dir = Some(dir);
    }

    /// The open preset browser (UI tests).
    pub fn preset_browser(&self) -> Option<&PresetBrowser> {
        self.dialogs.browser.as_ref()
    }

    /// The preset browser window, while open.
    pub(super) fn browser_window_ui(&mut self, ctx: &egui::Context) {
        let Some(mut browser) = self.dialogs.browser.take() else {
            return;
        };
        browser.poll();
        let (done, all) = browser.progress();
        if done < all && browser.error.is_none() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
        let mut open = true;
        let mut chosen = None;
        egui::Window::new("Presets")
            .collapsible(false)
            .resizable(true)
            .default_width(5.0 * (THUMB.0 as f32 + 16.0))
            .default_height(ctx.content_rect().height() * 0.75)
            .open(&mut open)
            .show(ctx, |ui| {
                if let Some(e) = &browser.error {
                    ui.colored_label(egui::Color32::from_rgb(240, 120, 90), format!("No thumbnail: {e}"));
                } else if done < all {
                    ui.add(
                        egui::ProgressBar::new(done as f32 / all.max(1) as f32)
                            .text(format!("rendering thumbnails: {done} of {all} (cached for next time)")),
                    );
                }
                ui.label("Click a preset to start a new look from it. The default head from the front under the studio sky, drawn with the preset's own method (burley for the ground truth).");
                egui::ScrollArea::vertical().auto_shrink(false).show(ui, |ui| {
                    let per_row = ((ui.available_width() / (THUMB.0 as f32 + 16.0)) as usize).max(1);
                    egui::Grid::new("preset_thumbnails").spacing([8.0, 8.0]).show(ui, |ui| {
                        for (k, e) in browser.entries.iter_mut().enumerate() {
                            let size = egui::vec2(THUMB.0 as f32, THUMB.1 as f32);
                            ui.vertical(|ui| {
                                ui.set_width(size.x);
                                let tip = format!("{}\n{}", e.preset.source, e.preset.rendering.method.id());
                                let clicked = match &e.image {
                                    Some(img) => {
                                        let tex = e.texture.get_or_insert_with(|| {
                                            ui.ctx().load_texture(
                                                format!("preset_thumb_{k}"),
                                                egui::ColorImage::from_rgba_unmultiplied(
                                                    [img.width() as usize, img.height() as usize],
                                                    img.as_raw(),
                                                ),
                                                egui::TextureOptions::LINEAR,
                                            )
                                        });
                                        ui.add(egui::Button::image(egui::Image::new((tex.id(), size))))
                                            .on_hover_text(&tip)
                                            .clicked()
                                    }
                                    None => {
                                        let (rect, _) = ui.allocate_exact_size(size, egui::Sense::hover());
                                        ui.painter().rect_filled(rect, 4.0, ui.visuals().faint_bg_color);
                                        ui.put(rect, egui::Spinner::new());
                                        false
                                    }
                                };
                                let name_clicked = ui
                                    .add(egui::Button::new(egui::RichText::new(&e.preset.name).small()).frame(false).wrap())
                                    .on_hover_text(&tip)
                                    .clicked();
                                if clicked || name_clicked {
                                    chosen = Some(e.preset.clone());
                                }
                            });
                            if (k + 1) % per_row == 0 {
                                ui.end_row();
                            }
                        }
                    });
                });
            });
        if let Some(p) = chosen {
            self.guarded(Pending::New(Box::new(p)));
            open = false;
        }
        if open {
            self.dialogs.browser = Some(browser);
        }
    }
}
