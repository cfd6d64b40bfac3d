//! File → Browse presets…: every shipped preset, then the presets in the
//! artist's own folders, as a thumbnail of the default head rendered by our
//! own renderer (its method, burley for the ground truth), cached on disk
//! so the second look costs nothing. A click on a shipped preset starts a
//! new look from it; on one of the artist's, opens that file; either asks
//! first if the open look has unsaved changes.

use super::{Action, Menu, Window, WindowView};
use crate::app::{state, DialogKind};
use crate::app::viewport::{Look, Request, Viewport};
use crate::settings::{library, Preset};
use std::path::{Path, PathBuf};
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

/// Each entry's label: its look's name, and for one of the artist's
/// files whose name another entry has too (a copy of a shipped preset
/// saved as `hero_skin.ron` is still "Skin1 (Jensen 2001)"), its file's
/// name after it.
fn labels(entries: &[Entry]) -> Vec<String> {
    let count = |name: &str| entries.iter().filter(|e| e.preset.name == name).count();
    entries
        .iter()
        .map(|e| match (&e.path, count(&e.preset.name)) {
            (Some(p), n) if n > 1 => format!(
                "{} ({})",
                e.preset.name,
                p.file_name().map_or_else(
                    || p.display().to_string(),
                    |f| f.to_string_lossy().into_owned()
                )
            ),
            _ => e.preset.name.clone(),
        })
        .collect()
}

/// FNV-1a, 64-bit: a hash that stays the same across runs and builds (the
/// cache's file names).
fn fnv1a(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The head the thumbnails are drawn on: the mesh the editor shows (its
/// file, units and maps) and the camera distance that frames it; `None`
/// in [`PresetBrowser::open`] is the procedural head.
#[derive(Debug, Clone, PartialEq)]
pub struct ThumbnailHead {
    pub mesh: PathBuf,
    pub settings: state::MeshSettings,
    pub framing_m: f32,
}

/// The cache file of `preset`'s thumbnail: its look, the head it is drawn
/// on (none: the procedural head, as before there was a choice) with the
/// size and modification time of its file and its maps' files (a mesh
/// saved again under the same name is drawn again), the thumbnail size and
/// [`THUMBNAIL_VERSION`] name it.
fn cache_path(dir: &Path, preset: &Preset, head: Option<&ThumbnailHead>) -> PathBuf {
    let look = ron::to_string(&(&preset.profile, &preset.rendering)).unwrap_or_default();
    let mut key = format!("{THUMBNAIL_VERSION} {}x{} {look}", THUMB.0, THUMB.1);
    if let Some(h) = head {
        let settings = ron::to_string(&h.settings).unwrap_or_default();
        key += &format!(" on {} {settings}", h.mesh.display());
        let maps = h.settings.maps.iter().filter_map(|m| m.path.as_deref());
        for file in std::iter::once(h.mesh.as_path()).chain(maps) {
            key += &file_stamp(file);
        }
    }
    dir.join(format!("{:016x}.png", fnv1a(key.as_bytes())))
}

/// A file's size and modification time (ns since the epoch), or nothing
/// where they cannot be read.
fn file_stamp(path: &Path) -> String {
    let Ok(m) = std::fs::metadata(path) else {
        return String::new();
    };
    let modified = m
        .modified()
        .ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |d| d.as_nanos());
    format!(" {} bytes at {modified}", m.len())
}

/// The request for a preset's thumbnail: the head on screen (`head`, else
/// the procedural head) from the front under the studio sky, its own method (burley stands in for the ground
/// truth, which takes minutes).
fn thumbnail_request(preset: &Preset, head: Option<&ThumbnailHead>) -> Request {
    // A look whose albedo is the material's (HDRP's) is drawn with the
    // default skin's, as the editor draws it as B by default; white
    // otherwise.
    let skin = crate::settings::albedo::look_albedo(&Preset::default_skin());
    let (preset, _, _) = crate::settings::albedo::b_as_drawn(
        preset.clone(),
        skin,
        state::MaterialAlbedo::LookA,
        Default::default(),
        None,
    );
    // On a mesh with a colour map of its own, the map tinted by each
    // look's albedo: the map alone would draw every look in the scan's
    // colour.
    let mut look = Look::of(&preset).with_map_colour(crate::render::textures::MapColour::Tinted);
    look.rendering.method = look.rendering.method.preview();
    let mut view = state::ViewState::default();
    // Closer than the framing of the whole head: the face fills it.
    view.orbit.camera_distance_m = 0.7 * head.map_or(view.orbit.camera_distance_m, |h| h.framing_m);
    Request {
        a: look,
        b: None,
        difference_scale: None,
        show_b: false,
        view,
        size: THUMB,
        mesh: head.map(|h| h.mesh.clone()),
        mesh_settings: head.map(|h| h.settings.clone()).unwrap_or_default(),
        interactive: false,
        refine_to_truth: false,
        seq: 0,
        background_map: None,
        want_radiance: false,
    }
}

/// The browser's thread: each preset's thumbnail from the cache, or
/// rendered (on `head`, the procedural head when `None`) and cached, sent
/// as it comes with `wake` after each.
fn fill_thumbnails(
    presets: &[Preset],
    cache: Option<PathBuf>,
    head: Option<ThumbnailHead>,
    tx: &std::sync::mpsc::Sender<Message>,
    wake: impl Fn(),
) {
    let mut viewport: Option<Viewport> = None;
    // The render thread frames the first frame of a mesh it loads
    // whole: load the head on screen with a frame that is not kept,
    // so that every thumbnail is framed alike.
    let warm_up = |vp: &mut Viewport| {
        if let (Some(h), Some(p)) = (head.as_ref(), presets.first()) {
            let mut req = thumbnail_request(p, Some(h));
            req.size = (16, 16);
            let _ = vp.render_converged(req, &|| false);
        }
    };
    for (k, preset) in presets.iter().enumerate() {
        let cached = cache.as_deref().map(|d| cache_path(d, preset, head.as_ref()));
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
        let vp = viewport.get_or_insert_with(|| {
            let mut vp = Viewport::start(|| {});
            warm_up(&mut vp);
            vp
        });
        let img = match vp.render_converged(thumbnail_request(preset, head.as_ref()), &|| false)
        {
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
}

impl PresetBrowser {
    /// Lists the shipped presets and starts filling in their thumbnails
    /// from `cache` (rendering and storing the missing ones).
    /// `wake` is called after each thumbnail, so it shows without input.
    pub fn open(
        cache: Option<PathBuf>,
        folders: &[PathBuf],
        head: Option<ThumbnailHead>,
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
        std::thread::spawn(move || fill_thumbnails(&presets, cache, head, &tx, wake));
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

/// File → Browse presets: the browser while it is open, and where its
/// thumbnails are cached.
pub struct BrowserWindow {
    browser: Option<PresetBrowser>,
    /// The head the editor shows, set before it opens: the thumbnails
    /// are drawn on it.
    pub head: Option<ThumbnailHead>,
    /// The thumbnails' cache folder (beside the editor's remembered
    /// state; UI tests set their own).
    pub thumbnail_dir: Option<PathBuf>,
}

impl Default for BrowserWindow {
    fn default() -> Self {
        Self {
            browser: None,
            head: None,
            thumbnail_dir: eframe::storage_dir("scatterlab").map(|d| d.join("thumbnails")),
        }
    }
}

impl BrowserWindow {
    /// Opens the browser (again) on the shipped presets and `folders`.
    pub fn open(&mut self, folders: &[PathBuf], wake: impl Fn() + Send + 'static) {
        self.browser = Some(PresetBrowser::open(
            self.thumbnail_dir.clone(),
            folders,
            self.head.clone(),
            wake,
        ));
    }

    /// Lists again with `folders` when it is open.
    pub fn relist(&mut self, folders: &[PathBuf], wake: impl Fn() + Send + 'static) {
        if self.browser.is_some() {
            self.open(folders, wake);
        }
    }

    /// The open browser (UI tests).
    pub fn browser(&self) -> Option<&PresetBrowser> {
        self.browser.as_ref()
    }
}

impl PresetBrowser {
    /// The progress bar or the error of the thumbnails.
    fn progress_ui(&self, ui: &mut egui::Ui) {
        let (done, all) = self.progress();
        if let Some(e) = &self.error {
            ui.colored_label(
                egui::Color32::from_rgb(240, 120, 90),
                format!("No thumbnail: {e}"),
            );
        } else if done < all {
            ui.add(
                egui::ProgressBar::new(done as f32 / all.max(1) as f32).text(format!(
                    "rendering thumbnails: {done} of {all} (cached for next time)"
                )),
            );
        }
    }

    /// The artist's folders: each can be removed, the look's own folder
    /// and a typed one added, or one chosen in the folder dialog (`choose`
    /// set). The folders as they should be, when changed.
    fn folders_ui(
        &mut self,
        ui: &mut egui::Ui,
        folders: &[PathBuf],
        doc_path: Option<&Path>,
        choose: &mut bool,
    ) -> Option<Vec<PathBuf>> {
        let mut changed = None;
        ui.horizontal_wrapped(|ui| {
            let label = ui.label("Your folders:");
            for (i, f) in folders.iter().enumerate() {
                if ui
                    .button(format!("{} ×", f.display()))
                    .on_hover_text("Stop listing this folder (its files stay).")
                    .clicked()
                {
                    let mut left = folders.to_vec();
                    left.remove(i);
                    changed = Some(left);
                }
            }
            let here = doc_path
                .and_then(Path::parent)
                .filter(|d| !library::is_shipped_presets(d))
                .map(Path::to_path_buf);
            if let Some(dir) = here.filter(|d| !folders.contains(d)) {
                if ui
                    .button("+ this look's folder")
                    .on_hover_text(format!("List the presets in {} here too.", dir.display()))
                    .clicked()
                {
                    changed = Some([folders, &[dir]].concat());
                }
            }
            if ui
                .button("+ choose folder…")
                .on_hover_text("Pick a folder of .ron presets in a folder dialog and list them here.")
                .clicked()
            {
                *choose = true;
            }
            if let Some(dir) = self.typed_folder_ui(ui, label.id) {
                if !folders.contains(&dir) {
                    changed = Some([folders, &[dir]].concat());
                }
            }
        });
        for s in &self.skipped {
            ui.colored_label(ui.visuals().warn_fg_color, format!("Not listed: {s}"));
        }
        changed
    }

    /// A folder typed into the field and added (Enter or "+ add"), once it
    /// is one.
    fn typed_folder_ui(&mut self, ui: &mut egui::Ui, label: egui::Id) -> Option<PathBuf> {
        let typed_id = egui::Id::unique("scatterlab_preset_folder_typed");
        let mut typed: String = ui.data(|d| d.get_temp(typed_id).unwrap_or_default());
        let field = ui
            .add(
                egui::TextEdit::singleline(&mut typed)
                    .hint_text("a folder of .ron presets")
                    .desired_width(180.0),
            )
            .labelled_by(label);
        let add = ui
            .button("+ add")
            .on_hover_text("List the presets in the folder typed here.")
            .clicked()
            || (field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter)));
        let mut added = None;
        if add && !typed.trim().is_empty() {
            let dir = PathBuf::from(typed.trim());
            if dir.is_dir() {
                added = Some(dir);
                typed.clear();
            } else {
                self.skipped
                    .insert(0, format!("{}: not a folder", dir.display()));
            }
        }
        ui.data_mut(|d| d.insert_temp(typed_id, typed));
        added
    }

    /// The thumbnails, by group; the one clicked (its look, and its file
    /// when it is one of the artist's).
    fn thumbnails_ui(&mut self, ui: &mut egui::Ui) -> Option<(Preset, Option<PathBuf>)> {
        let mut chosen = None;
        egui::ScrollArea::vertical()
            .auto_shrink(false)
            .show(ui, |ui| {
                let per_row = ((ui.available_width() / (THUMB.0 as f32 + 16.0)) as usize).max(1);
                egui::Grid::new("preset_thumbnails")
                    .spacing([8.0, 8.0])
                    .show(ui, |ui| {
                        let mut group = String::new();
                        let mut in_row = 0;
                        let labels = labels(&self.entries);
                        for (k, e) in self.entries.iter_mut().enumerate() {
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
                                let tip = format!(
                                    "{}\n{}",
                                    e.preset.source,
                                    e.preset.rendering.method.id()
                                );
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
                                        ui.add(egui::Button::image(egui::Image::new((
                                            tex.id(),
                                            size,
                                        ))))
                                        .on_hover_text(&tip)
                                        .clicked()
                                    }
                                    None => {
                                        let (rect, _) =
                                            ui.allocate_exact_size(size, egui::Sense::hover());
                                        ui.painter().rect_filled(
                                            rect,
                                            4.0,
                                            ui.visuals().faint_bg_color,
                                        );
                                        ui.put(rect, egui::Spinner::new());
                                        false
                                    }
                                };
                                let name_clicked = ui
                                    .add(
                                        egui::Button::new(
                                            egui::RichText::new(&labels[k]).small(),
                                        )
                                        .frame(false)
                                        .wrap(),
                                    )
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
        chosen
    }
}

impl Window for BrowserWindow {
    fn title(&self) -> &'static str {
        "Presets"
    }
    fn menu(&self) -> Option<Menu> {
        Some(Menu::FilePresets)
    }
    fn menu_label(&self) -> String {
        "Browse presets…".into()
    }
    fn menu_tooltip(&self) -> &'static str {
        "Every shipped preset, and those in your own folders, as a thumbnail of the head, rendered here and cached; click one to start from it"
    }
    fn is_open(&self) -> bool {
        self.browser.is_some()
    }
    /// Opening lists the presets: the menu item asks for it with
    /// [`Action::BrowsePresets`], which knows the folders.
    fn set_open(&mut self, open: bool) {
        if !open {
            self.browser = None;
        }
    }
    fn opens_with(&self) -> Option<Action> {
        Some(Action::BrowsePresets)
    }

    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        let Some(browser) = self.browser.as_mut() else {
            return Vec::new();
        };
        browser.poll();
        let (done, all) = browser.progress();
        if done < all && browser.error.is_none() {
            ctx.request_repaint_after(Duration::from_millis(100));
        }
        let mut open = true;
        let mut actions = Vec::new();
        egui::Window::new("Presets")
            .collapsible(false)
            .resizable(true)
            .default_width(5.0 * (THUMB.0 as f32 + 16.0))
            .default_height(ctx.content_rect().height() * 0.75)
            .open(&mut open)
            .show(ctx, |ui| {
                browser.progress_ui(ui);
                ui.label("Click a shipped preset to start a new look from it, one of yours to open it. The head on screen from the front under the studio sky (the procedural head close up, or your mesh framed whole), drawn with the preset's own method (burley for the ground truth); a profile whose albedo is the material's (HDRP's) with the default skin's albedo.");
                let mut choose = false;
                if let Some(f) =
                    browser.folders_ui(ui, view.preset_folders, view.doc_path, &mut choose)
                {
                    actions.push(Action::SetPresetFolders(f));
                }
                if choose {
                    actions.push(Action::OpenDialog(DialogKind::PresetFolder));
                }
                match browser.thumbnails_ui(ui) {
                    Some((_, Some(path))) => actions.push(Action::OpenPreset(path)),
                    Some((p, None)) => actions.push(Action::NewLook(Box::new(p))),
                    None => {}
                }
            });
        if !open
            || actions
                .iter()
                .any(|a| matches!(a, Action::OpenPreset(_) | Action::NewLook(_)))
        {
            self.browser = None;
        }
        actions
    }
}

#[cfg(test)]
mod cache_tests {
    use super::{cache_path, ThumbnailHead};
    use crate::settings::Preset;

    /// A mesh saved again under the same name (another modification time)
    /// gets another cache file: its thumbnails are drawn again, not read
    /// from the cache of the old mesh. The same file untouched keeps its.
    #[test]
    fn a_mesh_saved_again_is_drawn_again() {
        let dir = std::env::temp_dir().join(format!("scatterlab-thumbkey-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mesh = dir.join("head.obj");
        std::fs::write(&mesh, "v 0 0 0\n").unwrap();
        let set = |secs: u64| {
            let f = std::fs::File::options().write(true).open(&mesh).unwrap();
            f.set_modified(std::time::UNIX_EPOCH + std::time::Duration::from_secs(secs))
                .unwrap();
        };
        set(1_700_000_000);
        let head = ThumbnailHead {
            mesh: mesh.clone(),
            settings: Default::default(),
            framing_m: 0.5,
        };
        let preset = Preset::default_skin();
        let first = cache_path(&dir, &preset, Some(&head));
        assert_eq!(first, cache_path(&dir, &preset, Some(&head)));
        set(1_700_000_100);
        assert_ne!(first, cache_path(&dir, &preset, Some(&head)));
        std::fs::remove_dir_all(&dir).ok();
    }
}
