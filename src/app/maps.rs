//! A loaded mesh: the units prompt, and the Maps window with its five map
//! slots, each with its file,
//! V-flip and encoding, a preview of the map on the mesh's UV layout (so
//! an upside-down map is obvious) and a flip-V suggestion where the layout
//! says so (`render::uv_layout`).

use super::state::MeshSettings;
use super::*;
use crate::render::mesh::{CRANIUM_M, PLAUSIBLE_CRANIUM_M, PLAUSIBLE_HEIGHT_M};
use crate::render::textures::{MapSlot, TextureImage, TextureSlot, SLOTS};
use crate::render::uv_layout::{self, FlipEvidence, FlipVerdict};
use std::sync::mpsc::Receiver;

/// Preview side in pixels.
const PREVIEW: usize = 192;

/// One slot's preview: the map as the mesh samples it (flip applied) with
/// the layout over it, and the flip evidence; `None` where the slot has no
/// map (a neutral 1×1).
pub(super) struct SlotPreview {
    pixels: Vec<u8>,
    evidence: FlipEvidence,
}

type Previews = Result<Vec<Option<SlotPreview>>, String>;

/// The previews of one mesh's slots as set, computed on a thread (loading
/// the mesh and its maps takes a while), with their textures once shown.
pub(super) struct MapsPreview {
    key: (PathBuf, MeshSettings),
    rx: Option<Receiver<Previews>>,
    result: Option<Previews>,
    textures: Vec<Option<egui::TextureHandle>>,
}

impl MapsPreview {
    fn start(path: PathBuf, settings: MeshSettings, waker: super::wake::Waker) -> Self {
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
    pub(super) fn ready(&self) -> bool {
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

/// The shipped head scan and its settings (`EditorApp::open_scanned_head`).
pub fn scanned_head() -> Option<(PathBuf, super::state::MeshSettings)> {
    use crate::render::textures::MapSlot;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scan");
    let mesh = dir.join("LeePerrySmith.glb");
    let (colour, normal) = (
        dir.join("Map-COL.jpg"),
        dir.join("Infinite-Level_02_Tangent_SmoothUV.jpg"),
    );
    if !(mesh.is_file() && colour.is_file() && normal.is_file()) {
        return None;
    }
    let mut settings = super::state::MeshSettings {
        metres_per_unit: 0.0462,
        ..Default::default()
    };
    settings.maps[0] = MapSlot {
        path: Some(colour),
        flip_v: true,
        srgb: true,
    };
    settings.maps[1] = MapSlot {
        path: Some(normal),
        flip_v: true,
        srgb: false,
    };
    Some((mesh, settings))
}

impl EditorApp {
    /// The mesh the viewport is asked to show (`None`: the default head).
    pub fn mesh_path(&self) -> Option<&Path> {
        self.meshes.mesh.as_deref()
    }

    /// The loaded mesh's size and framing, once the viewport has it.
    pub fn mesh_info(&self) -> Option<viewport::MeshInfo> {
        self.meshes.mesh_info
    }

    /// The mesh whose units prompt is open.
    pub fn units_prompt_for(&self) -> Option<&Path> {
        self.meshes.units_prompt.as_deref()
    }

    /// Whether the Maps window's previews are computed (UI tests).
    pub fn maps_preview_ready(&self) -> bool {
        self.meshes.maps_preview.as_ref().is_some_and(|p| p.ready())
    }

    /// Opens the shipped head scan (Lee Perry-Smith, CC BY 3.0:
    /// assets/scan/ATTRIBUTION.md) at 0.0462 m/unit with its colour and
    /// normal maps, flipped as they are made (V up), in the map's own
    /// colour (the Look panel offers it tinted by the look's albedo, for
    /// looks to differ on it); units and maps the artist has set for it
    /// before are kept. False where the files are missing (a copy of the
    /// binary without the repository).
    pub fn open_scanned_head(&mut self) -> bool {
        let Some((path, settings)) = scanned_head() else {
            return false;
        };
        self.ui_state.meshes.entry(path.clone()).or_insert(settings);
        self.load_mesh(Some(path));
        true
    }

    /// Shows the mesh at `path` in the viewport, or the default head.
    pub(super) fn load_mesh(&mut self, path: Option<PathBuf>) {
        match &path {
            Some(p) => self.say(format!("Loading mesh {} …", p.display())),
            None if self.meshes.mesh.is_some() => self.say("Loading the default head …"),
            None => {}
        }
        self.meshes.mesh = path;
    }

    /// Shows `mesh` in the viewport (`edit --mesh`), with its units if
    /// given: they are remembered for the file as the units prompt would.
    pub fn open_mesh(&mut self, mesh: MeshArg) {
        if let Some(m) = mesh.metres_per_unit {
            self.ui_state
                .meshes
                .entry(mesh.path.clone())
                .or_default()
                .metres_per_unit = m;
        }
        self.load_mesh(Some(mesh.path));
    }

    /// Asks for a mesh's units: metres per unit with common choices, a
    /// live height readout and a suggestion from the bounds (a head is
    /// 18–40 cm tall with or without its neck). Every change applies at once (the mesh reloads and
    /// the camera frames it) and is remembered for the file.
    pub(super) fn units_prompt_ui(&mut self, ctx: &egui::Context) {
        let Some(path) = self.meshes.units_prompt.clone() else {
            return;
        };
        let Some(info) = self.meshes.mesh_info else {
            return;
        };
        let size = info.size;
        let h = size.height_units.max(1e-9);
        let current = self
            .ui_state
            .meshes
            .get(&path)
            .map_or(1.0, |m| m.metres_per_unit);
        let mut mpu = current;
        let mut open = true;
        let mut done = false;
        egui::Window::new("Mesh units")
            .collapsible(false)
            .resizable(false)
            .anchor(egui::Align2::CENTER_CENTER, egui::vec2(0.0, 0.0))
            .open(&mut open)
            .show(ctx, |ui| {
                let name = path.file_name().map_or_else(
                    || path.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                );
                ui.label(format!("{name} is {h:.4} units tall."));
                ui.horizontal(|ui| {
                    for (label, v) in [
                        ("m", 1.0),
                        ("dm", 0.1),
                        ("cm", 0.01),
                        ("mm", 0.001),
                        ("inch", 0.0254),
                    ] {
                        ui.selectable_value(&mut mpu, v, label);
                    }
                });
                let speed = mpu * 0.01;
                ui.add(
                    egui::DragValue::new(&mut mpu)
                        .range(MeshArg::METRES_PER_UNIT)
                        .speed(speed)
                        .max_decimals(6)
                        .suffix(" m/unit"),
                )
                .on_hover_text("Metres per unit of the file (Unity's worldScale convention).");
                let height_cm = h * mpu * 100.0;
                let (lo, hi) = PLAUSIBLE_HEIGHT_M;
                let mut text = format!("Mesh height = {height_cm:.1} cm");
                let mut plausible = (100.0 * lo..=100.0 * hi).contains(&height_cm);
                if let Some(c) = size.cranium_units {
                    let across_cm = c * mpu * 100.0;
                    let (lo, hi) = PLAUSIBLE_CRANIUM_M;
                    text += &format!(", the head {across_cm:.1} cm across");
                    plausible = (100.0 * lo..=100.0 * hi).contains(&across_cm);
                }
                let hover = format!(
                    "Across: the mean of the head's width (ears included) and depth (nose included) above the neck; an adult's is about {:.0} cm.",
                    100.0 * CRANIUM_M
                );
                if plausible {
                    ui.label(text).on_hover_text(hover);
                } else {
                    ui.colored_label(
                        egui::Color32::from_rgb(240, 170, 60),
                        format!("{text}: not a head's size"),
                    )
                    .on_hover_text(hover);
                }
                let suggested = size.suggest_metres_per_unit();
                let label = match size.cranium_units {
                    Some(c) => format!(
                        "Use {suggested} m/unit ({:.1} cm across, {:.1} cm tall)",
                        c * suggested * 100.0,
                        h * suggested * 100.0
                    ),
                    None => format!("Use {suggested} m/unit ({:.1} cm tall)", h * suggested * 100.0),
                };
                if ui
                    .button(label)
                    .on_hover_text(match size.cranium_units {
                        Some(_) => "The units that make the head an adult's size (a common unit when one is within 20 %).",
                        None => "No head found above a neck: a common unit that makes the mesh 18–40 cm tall, or the exact scale for 25 cm.",
                    })
                    .clicked()
                {
                    mpu = suggested;
                }
                if ui.button("OK").clicked() {
                    done = true;
                }
            });
        if mpu != current || !self.ui_state.meshes.contains_key(&path) {
            self.ui_state
                .meshes
                .entry(path.clone())
                .or_default()
                .metres_per_unit = mpu;
        }
        if done || !open {
            self.meshes.units_prompt = None;
        }
    }

    /// The loaded mesh's map slots: for each, the file (or the mesh's own
    /// map), a V-flip for maps whose V runs up, the texels' encoding, and
    /// the map previewed on the UV layout with a flip-V suggestion.
    /// Changes apply at once (the mesh reloads with them) and are
    /// remembered for the file.
    pub(super) fn maps_window_ui(&mut self, ctx: &egui::Context) {
        let Some(path) = self.meshes.maps_window.clone() else {
            self.meshes.maps_preview = None;
            return;
        };
        let mut settings = self.ui_state.meshes.get(&path).cloned().unwrap_or_default();
        let key = (path.clone(), settings.clone());
        if self.meshes.maps_preview.as_ref().map(|p| &p.key) != Some(&key) {
            self.meshes.maps_preview = Some(MapsPreview::start(
                path.clone(),
                settings.clone(),
                self.waker.clone(),
            ));
        }
        let mut preview = self.meshes.maps_preview.take();
        let waiting = preview.as_ref().is_some_and(|p| p.rx.is_some());
        let mut open = true;
        let mut choose = None;
        // Inside the viewport, clear of the Look panel (at 1280×720 it had
        // covered it).
        let at = self.window_pos_in_viewport(8.0);
        egui::Window::new("Mesh maps")
            .collapsible(false)
            .resizable(false)
            .default_pos(at)
            .open(&mut open)
            .show(ctx, |ui| {
                let result = preview.as_mut().and_then(|p| p.poll().map(|r| r.is_ok()));
                if let Some(Err(e)) = preview.as_ref().and_then(|p| p.result.as_ref()) {
                    ui.colored_label(egui::Color32::from_rgb(240, 120, 90), format!("No preview: {e}"));
                }
                if result.is_none() && waiting {
                    ui.horizontal(|ui| {
                        super::report::spinner(ui);
                        ui.label("Previewing the maps on the UV layout …");
                    });
                }
                egui::ScrollArea::vertical().max_height(ctx.content_rect().height() * 0.8).show(ui, |ui| {
                    egui::Grid::new("mesh_maps").num_columns(2).spacing([12.0, 10.0]).show(ui, |ui| {
                        for (k, slot) in SLOTS.into_iter().enumerate() {
                            let m = &mut settings.maps[k];
                            let label = slot_label(slot);
                            if map_slot_ui(ui, k, slot, m) {
                                choose = Some(k);
                            }
                            ui.vertical(|ui| {
                                let Some(p) = preview.as_mut() else { return };
                                let Some(Ok(slots)) = p.result.as_ref() else { return };
                                match slots.get(k).and_then(|s| s.as_ref()) {
                                    None => {
                                        ui.label("No map: a neutral value everywhere.");
                                    }
                                    Some(s) => {
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
                                            if ui.button(format!("{label}: apply the suggested flip")).clicked() {
                                                m.flip_v = !m.flip_v;
                                            }
                                        } else {
                                            ui.label(text);
                                        }
                                    }
                                }
                            });
                            ui.end_row();
                        }
                    });
                });
            });
        self.meshes.maps_preview = preview;
        if waiting {
            ctx.request_repaint_after(std::time::Duration::from_millis(100));
        }
        if self.ui_state.meshes.get(&path) != Some(&settings) {
            self.ui_state.meshes.insert(path.clone(), settings);
        }
        if let Some(k) = choose {
            self.open_dialog(DialogKind::Map(k));
        }
        if !open {
            self.meshes.maps_window = None;
        }
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
