//! A loaded mesh: the units prompt, and the Maps window with its five map
//! slots, each with its file,
//! V-flip and encoding, a preview of the map on the mesh's UV layout (so
//! an upside-down map is obvious) and a flip-V suggestion where the layout
//! says so (`render::uv_layout`).

use super::{Action, Menu, Window, WindowView};
use crate::app::state::MeshSettings;
use crate::app::DialogKind;
use crate::render::textures::{MapSlot, TextureImage, TextureSlot, SLOTS};
use crate::render::uv_layout::{self, FlipEvidence, FlipVerdict};
use std::path::{Path, PathBuf};
use std::sync::mpsc::Receiver;

/// Preview side in pixels.
const PREVIEW: usize = 192;

/// One slot's preview: the map as the mesh samples it (flip applied) with
/// the layout over it, and the flip evidence; `None` where the slot has no
/// map (a neutral 1×1).
pub struct SlotPreview {
    pixels: Vec<u8>,
    evidence: FlipEvidence,
}

type Previews = Result<Vec<Option<SlotPreview>>, String>;

/// The previews of one mesh's slots as set, computed on a thread (loading
/// the mesh and its maps takes a while), with their textures once shown.
pub struct MapsPreview {
    key: (PathBuf, MeshSettings),
    rx: Option<Receiver<Previews>>,
    result: Option<Previews>,
    textures: Vec<Option<egui::TextureHandle>>,
}

impl MapsPreview {
    fn start(path: PathBuf, settings: MeshSettings, waker: crate::app::wake::Waker) -> Self {
        let (tx, rx) = std::sync::mpsc::channel();
        let (p, s) = (path.clone(), settings.clone());
        std::thread::spawn(move || {
            let _ = tx.send(previews(&p, &s));
            waker.wake();
        });
        Self {
            key: (path, settings),
            rx: Some(rx),
            result: None,
            textures: Vec::new(),
        }
    }

    /// Whether the thread has sent its result.
    pub fn ready(&self) -> bool {
        self.result.is_some()
    }

    /// The result, once the thread has sent it.
    fn poll(&mut self) -> Option<&Previews> {
        if let Some(r) = self.rx.as_ref().and_then(|rx| rx.try_recv().ok()) {
            self.result = Some(r);
            self.rx = None;
        }
        self.result.as_ref()
    }
}

/// Loads the mesh with the artist's slots applied and previews each map.
fn previews(path: &Path, settings: &MeshSettings) -> Previews {
    let mut mesh = crate::render::mesh::Mesh::load(path, settings.metres_per_unit)
        .map_err(|e| e.to_string())?;
    let maps = std::sync::Arc::make_mut(&mut mesh.textures);
    // The thickness range does not change the texels previewed.
    crate::render::textures::apply_slots(maps, &settings.maps, 1.0).map_err(|e| e.to_string())?;
    let uvs: Vec<[f32; 2]> = mesh.vertices.iter().map(|v| v.uv).collect();
    let maps = &*mesh.textures;
    let one = |map: Option<&TextureImage>| {
        map.filter(|m| m.width > 1 || m.height > 1)
            .map(|m| SlotPreview {
                pixels: uv_layout::preview(&uvs, &mesh.indices, m, PREVIEW),
                evidence: uv_layout::flip_evidence(&uvs, &mesh.indices, m),
            })
    };
    Ok(SLOTS
        .into_iter()
        .map(|slot| match slot {
            TextureSlot::Albedo => one(Some(&maps.albedo)),
            TextureSlot::Normal => one(Some(&maps.normal)),
            TextureSlot::Roughness => one(Some(&maps.roughness)),
            TextureSlot::Mask => one(Some(&maps.mask)),
            TextureSlot::Thickness => one(maps.thickness.as_ref().map(|t| &t.0)),
        })
        .collect())
}

/// What the Maps window says under a slot's preview, and whether it
/// suggests flipping.
pub fn flip_advice(e: &FlipEvidence, flipped_now: bool) -> (String, bool) {
    let figures = format!(
        "outline contrast {:.2} as shown, {:.2} flipped",
        e.as_is, e.flipped
    );
    match e.verdict() {
        FlipVerdict::Aligned => (format!("Lines up with the UV layout ({figures})."), false),
        FlipVerdict::Flip => (
            format!(
                "Upside down for this layout: {} flip V ({figures}).",
                if flipped_now { "turn off" } else { "turn on" }
            ),
            true,
        ),
        FlipVerdict::Unclear => (
            format!("The layout cannot tell whether this map is upside down ({figures}): check the preview."),
            false,
        ),
    }
}

fn slot_label(slot: TextureSlot) -> &'static str {
    match slot {
        TextureSlot::Albedo => "Albedo",
        TextureSlot::Normal => "Normal",
        TextureSlot::Roughness => "Roughness",
        TextureSlot::Mask => "SSS mask",
        TextureSlot::Thickness => "Thickness",
    }
}

/// A mesh's Maps window: open for the loaded mesh, with its slots'
/// previews.
#[derive(Default)]
pub struct MapsWindow {
    open: bool,
    /// The mesh it was opened for: it stays on it (a map that fails to
    /// load must still be there to clear) until closed.
    for_mesh: Option<PathBuf>,
    preview: Option<MapsPreview>,
}

impl MapsWindow {
    /// Whether the previews are computed (UI tests).
    pub fn preview_ready(&self) -> bool {
        self.preview.as_ref().is_some_and(|p| p.ready())
    }
}

/// The previews' error or their spinner, while there is one.
fn preview_state_ui(ui: &mut egui::Ui, preview: &mut Option<MapsPreview>, waiting: bool) {
    let result = preview.as_mut().and_then(|p| p.poll().map(|r| r.is_ok()));
    if let Some(Err(e)) = preview.as_ref().and_then(|p| p.result.as_ref()) {
        ui.colored_label(
            egui::Color32::from_rgb(240, 120, 90),
            format!("No preview: {e}"),
        );
    }
    if result.is_none() && waiting {
        ui.horizontal(|ui| {
            crate::app::report::spinner(ui);
            ui.label("Previewing the maps on the UV layout …");
        });
    }
}

/// Slot `k`'s preview on the UV layout and its flip advice (with a
/// button that applies a suggested flip).
fn slot_preview_ui(
    ui: &mut egui::Ui,
    k: usize,
    preview: &mut Option<MapsPreview>,
    m: &mut MapSlot,
) {
    let label = slot_label(SLOTS[k]);
    let Some(p) = preview.as_mut() else { return };
    let Some(Ok(slots)) = p.result.as_ref() else {
        return;
    };
    let Some(s) = slots.get(k).and_then(|s| s.as_ref()) else {
        ui.label("No map: a neutral value everywhere.");
        return;
    };
    if p.textures.len() < SLOTS.len() {
        p.textures.resize_with(SLOTS.len(), || None);
    }
    let tex = p.textures[k].get_or_insert_with(|| {
        ui.ctx().load_texture(
            format!("map_preview_{k}"),
            egui::ColorImage::from_rgba_unmultiplied([PREVIEW, PREVIEW], &s.pixels),
            egui::TextureOptions::LINEAR,
        )
    });
    ui.add(egui::Image::new((tex.id(), egui::vec2(PREVIEW as f32, PREVIEW as f32))))
        .on_hover_text("The map as the mesh samples it (V down, flip applied), darkened where no triangle samples it, with the UV islands' outlines in yellow: the map's own outlines should fall on them.");
    let (text, suggest) = flip_advice(&s.evidence, m.flip_v);
    ui.set_max_width(PREVIEW as f32 + 140.0);
    if suggest {
        ui.colored_label(egui::Color32::from_rgb(240, 170, 60), text);
        if ui
            .button(format!("{label}: apply the suggested flip"))
            .clicked()
        {
            m.flip_v = !m.flip_v;
        }
    } else {
        ui.label(text);
    }
}

impl Window for MapsWindow {
    fn title(&self) -> &'static str {
        "Mesh maps"
    }
    fn menu(&self) -> Option<Menu> {
        Some(Menu::Mesh)
    }
    fn menu_label(&self) -> String {
        "Maps…".into()
    }
    fn menu_tooltip(&self) -> &'static str {
        "This mesh's albedo, normal, roughness, SSS mask and thickness maps: files, V-flip and colour space."
    }
    fn is_open(&self) -> bool {
        self.open
    }
    fn set_open(&mut self, open: bool) {
        self.open = open;
    }

    /// The loaded mesh's map slots: for each, the file (or the mesh's own
    /// map), a V-flip for maps whose V runs up, the texels' encoding, and
    /// the map previewed on the UV layout with a flip-V suggestion.
    /// Changes apply at once (the mesh reloads with them) and are
    /// remembered for the file.
    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        if !self.open {
            (self.for_mesh, self.preview) = (None, None);
            return Vec::new();
        }
        let Some(path) = self.for_mesh.clone().or(view.mesh.map(Path::to_path_buf)) else {
            // No mesh of the artist's: nothing to show, and closed.
            self.open = false;
            return Vec::new();
        };
        self.for_mesh = Some(path.clone());
        let before = view.meshes.get(&path).cloned().unwrap_or_default();
        let mut settings = before.clone();
        let key = (path.clone(), settings.clone());
        if self.preview.as_ref().map(|p| &p.key) != Some(&key) {
            self.preview = Some(MapsPreview::start(
                path.clone(),
                settings.clone(),
                view.waker.clone(),
            ));
        }
        let preview = &mut self.preview;
        let waiting = preview.as_ref().is_some_and(|p| p.rx.is_some());
        let mut choose = None;
        // Inside the viewport, clear of the Look panel (at 1280×720 it had
        // covered it).
        egui::Window::new("Mesh maps")
            .collapsible(false)
            .resizable(false)
            .default_pos(view.pos_in_viewport(8.0))
            .open(&mut self.open)
            .show(ctx, |ui| {
                preview_state_ui(ui, preview, waiting);
                egui::ScrollArea::vertical()
                    .max_height(ctx.content_rect().height() * 0.8)
                    .show(ui, |ui| {
                        egui::Grid::new("mesh_maps")
                            .num_columns(2)
                            .spacing([12.0, 10.0])
                            .show(ui, |ui| {
                                for (k, slot) in SLOTS.into_iter().enumerate() {
                                    if map_slot_ui(ui, k, slot, &mut settings.maps[k]) {
                                        choose = Some(k);
                                    }
                                    ui.vertical(|ui| {
                                        slot_preview_ui(ui, k, preview, &mut settings.maps[k])
                                    });
                                    ui.end_row();
                                }
                            });
                    });
            });
        if waiting {
            ctx.request_repaint_after(std::time::Duration::from_millis(100));
        }
        let mut actions = Vec::new();
        if settings != before || !view.meshes.contains_key(&path) {
            actions.push(Action::SetMeshSettings(path, settings));
        }
        if let Some(k) = choose {
            actions.push(Action::OpenDialog(DialogKind::Map(k)));
        }
        actions
    }
}

/// One map slot's file, clear, flip-V and colour space controls; whether
/// the artist asked to choose its file.
fn map_slot_ui(ui: &mut egui::Ui, k: usize, slot: TextureSlot, m: &mut MapSlot) -> bool {
    let label = slot_label(slot);
    let mut choose = false;
    ui.vertical(|ui| {
        ui.strong(label);
        let file = m.path.as_ref().and_then(|p| p.file_name()).map_or_else(
            || "the mesh's own".to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        if ui
            .button(format!("{label}: {file}"))
            .on_hover_text("Choose a PNG or JPEG that replaces this map.")
            .clicked()
        {
            choose = true;
        }
        ui.horizontal(|ui| {
            if ui
                .add_enabled(m.path.is_some(), egui::Button::new("Clear"))
                .on_hover_text("Back to the mesh's own map.")
                .clicked()
            {
                m.path = None;
            }
            ui.checkbox(&mut m.flip_v, format!("{label}: flip V"))
                .on_hover_text("For maps made with V up (OpenGL's bottom-left origin) on a mesh with glTF's top-left origin, or the other way round.");
        });
        egui::ComboBox::from_id_salt(("map_space", k))
            .selected_text(if m.srgb { "sRGB" } else { "linear" })
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut m.srgb, true, "sRGB");
                ui.selectable_value(&mut m.srgb, false, "linear");
            })
            .response
            .on_hover_text(format!(
                "How the file's texels are encoded ({} is usual for this map).",
                if MapSlot::default_for(slot).srgb { "sRGB" } else { "linear" }
            ));
    });
    choose
}
