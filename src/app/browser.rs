//! File → Browse presets…: every shipped preset, then the presets in the
//! artist's own folders, as a thumbnail of the default head rendered by our
//! own renderer (its method, burley for the ground truth), cached on disk
//! so the second look costs nothing. A click on a shipped preset starts a
//! new look from it; on one of the artist's, opens that file; either asks
//! first if the open look has unsaved changes.

use super::viewport::{Look, Request, Viewport};
use super::*;
use std::sync::mpsc::Receiver;
use std::time::Duration;

/// Thumbnail size in pixels (portrait, like a head).
pub const THUMB: (u32, u32) = (120, 150);

/// Bumped when the renderer's look changes, so older cached thumbnails are
/// not shown.
const THUMBNAIL_VERSION: u32 = 2;

/// One preset in the browser.
struct Entry {
    /// The artist's file, for a preset from their folders.
    path: Option<PathBuf>,
    /// The group it is listed under ("shipped", or the folder).
    group: String,
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
    /// Files and folders of the artist's that could not be listed, and why.
    pub skipped: Vec<String>,
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
    // A look whose albedo is the material's (HDRP's) is drawn with the
    // default skin's, as the editor draws it as B by default; white
    // otherwise.
    let skin = super::albedo::look_albedo(&Preset::default_skin());
    let (preset, _, _) = super::albedo::b_as_drawn(
        preset.clone(),
        skin,
        state::MaterialAlbedo::LookA,
        Default::default(),
        None,
    );
    let mut look = Look::of(&preset);
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
    pub fn open(
        cache: Option<PathBuf>,
        folders: &[PathBuf],
        wake: impl Fn() + Send + 'static,
    ) -> Self {
        let mut entries: Vec<Entry> = library::PRESETS
            .iter()
            .filter_map(|(file, _)| library::load(file).ok())
            .map(|preset| Entry {
                path: None,
                group: "shipped".into(),
                preset,
                image: None,
                texture: None,
            })
            .collect();
        let mut skipped = Vec::new();
        for dir in folders {
            let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
                .map(|d| {
                    d.filter_map(Result::ok)
                        .map(|e| e.path())
                        .filter(|p| crate::settings::is_preset_file(p))
                        .collect()
                })
                .unwrap_or_else(|e| {
                    skipped.push(format!("{}: {e}", dir.display()));
                    Vec::new()
                });
            files.sort();
            for f in files {
                match Preset::load(&f) {
                    Ok(preset) => entries.push(Entry {
                        path: Some(f),
                        group: dir.display().to_string(),
                        preset,
                        image: None,
                        texture: None,
                    }),
                    Err(e) => skipped.push(e.to_string()),
                }
            }
        }
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
            skipped,
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

    /// The presets listed from the artist's folders (UI tests).
    pub fn own_presets(&self) -> Vec<&Path> {
        self.entries
            .iter()
            .filter_map(|e| e.path.as_deref())
            .collect()
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
        let mut folders_changed = false;
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
                ui.label("Click a shipped preset to start a new look from it, one of yours to open it. The default head from the front under the studio sky, drawn with the preset's own method (burley for the ground truth); a profile whose albedo is the material's (HDRP's) with the default skin's albedo.");
                ui.horizontal_wrapped(|ui| {
                    ui.label("Your folders:");
                    let mut remove = None;
                    for (i, f) in self.ui_state.preset_folders.iter().enumerate() {
                        if ui
                            .button(format!("{} ×", f.display()))
                            .on_hover_text("Stop listing this folder (its files stay).")
                            .clicked()
                        {
                            remove = Some(i);
                        }
                    }
                    if let Some(i) = remove {
                        self.ui_state.preset_folders.remove(i);
                        folders_changed = true;
                    }
                    let here = self
                        .doc
                        .path
                        .as_deref()
                        .and_then(Path::parent)
                        .filter(|d| !super::files::is_shipped_presets(d))
                        .map(Path::to_path_buf);
                    if let Some(dir) = here.filter(|d| !self.ui_state.preset_folders.contains(d)) {
                        if ui
                            .button("+ this look's folder")
                            .on_hover_text(format!("List the presets in {} here too.", dir.display()))
                            .clicked()
                        {
                            self.ui_state.preset_folders.push(dir);
                            folders_changed = true;
                        }
                    }
                    let typed_id = egui::Id::unique("scatterlab_preset_folder_typed");
                    let mut typed: String = ui.data(|d| d.get_temp(typed_id).unwrap_or_default());
                    let field = ui.add(egui::TextEdit::singleline(&mut typed).hint_text("a folder of .ron presets").desired_width(180.0));
                    let add = ui.button("+ add").on_hover_text("List the presets in the folder typed here.").clicked()
                        || (field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)));
                    if add && !typed.trim().is_empty() {
                        let dir = PathBuf::from(typed.trim());
                        if dir.is_dir() {
                            if !self.ui_state.preset_folders.contains(&dir) {
                                self.ui_state.preset_folders.push(dir);
                                folders_changed = true;
                            }
                            typed.clear();
                        } else {
                            browser.skipped.insert(0, format!("{}: not a folder", dir.display()));
                        }
                    }
                    ui.data_mut(|d| d.insert_temp(typed_id, typed));
                });
                for s in &browser.skipped {
                    ui.colored_label(ui.visuals().warn_fg_color, format!("Not listed: {s}"));
                }
                egui::ScrollArea::vertical().auto_shrink(false).show(ui, |ui| {
                    let per_row = ((ui.available_width() / (THUMB.0 as f32 + 16.0)) as usize).max(1);
                    egui::Grid::new("preset_thumbnails").spacing([8.0, 8.0]).show(ui, |ui| {
                        let mut group = String::new();
                        let mut in_row = 0;
                        for (k, e) in browser.entries.iter_mut().enumerate() {
                            if e.group != group {
                                if in_row > 0 {
                                    ui.end_row();
                                }
                                group = e.group.clone();
                                ui.strong(&group);
                                ui.end_row();
                                in_row = 0;
                            }
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
                                    chosen = Some((e.preset.clone(), e.path.clone()));
                                }
                            });
                            in_row += 1;
                            if in_row % per_row == 0 {
                                ui.end_row();
                            }
                        }
                    });
                });
            });
        match chosen {
            Some((_, Some(path))) => {
                self.guarded(Pending::Open(path));
                open = false;
            }
            Some((p, None)) => {
                self.guarded(Pending::New(Box::new(p)));
                open = false;
            }
            None => {}
        }
        if open && folders_changed {
            // List again with the folders as they are now (cached
            // thumbnails come back at once).
            self.dialogs.browser = Some(PresetBrowser::open(
                self.dialogs.thumbnail_dir.clone(),
                &self.ui_state.preset_folders,
                self.waker.as_fn(),
            ));
        } else if open {
            self.dialogs.browser = Some(browser);
        }
    }
}
