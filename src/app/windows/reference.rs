//! File → Reference image…: a photograph beside the render (its own
//! window) or over it (on the viewport, at an opacity), and an eyedropper
//! that samples it into one of the look's colour fields.
//!
//! The eyedropper averages the 5×5 texels under the click (a photo's
//! noise and JPEG blocks would make one texel a poor sample), decodes
//! them from sRGB to linear (IEC 61966-2-1), as every colour field here is
//! linear, and writes the field as one undoable edit.

use super::{Action, Menu, Window, WindowView};
use std::path::{Path, PathBuf};

/// The colour field the eyedropper writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum PickInto {
    /// Burley's albedo A (the look's colour).
    #[default]
    Albedo,
    /// The transmission tint.
    TransmissionTint,
}

impl PickInto {
    pub fn label(self) -> &'static str {
        match self {
            PickInto::Albedo => "Albedo",
            PickInto::TransmissionTint => "Transmission tint",
        }
    }
}

/// A loaded reference image.
pub struct Reference {
    pub path: PathBuf,
    pub image: image::RgbaImage,
    texture: Option<egui::TextureHandle>,
    /// Drawn over the viewport (else in its own window).
    pub over: bool,
    pub opacity: f32,
    pub pick_into: PickInto,
    /// The last colour picked (linear), for the window's swatch.
    pub picked: Option<[f64; 3]>,
}

/// The mean linear colour of the 5×5 texels around (x, y) (clamped to the
/// image).
pub fn sample(img: &image::RgbaImage, x: u32, y: u32) -> [f64; 3] {
    let mut sum = [0.0f64; 3];
    let mut n = 0.0;
    for dy in -2i64..=2 {
        for dx in -2i64..=2 {
            let px = (x as i64 + dx).clamp(0, img.width() as i64 - 1) as u32;
            let py = (y as i64 + dy).clamp(0, img.height() as i64 - 1) as u32;
            let p = img.get_pixel(px, py);
            for c in 0..3 {
                sum[c] += crate::model::colour::srgb8_to_linear(p[c]) as f64;
            }
            n += 1.0;
        }
    }
    sum.map(|s| s / n)
}

/// File → Reference image: the loaded photo, if any (the window is open
/// while there is one).
#[derive(Default)]
pub struct ReferenceWindow {
    reference: Option<Reference>,
}

impl ReferenceWindow {
    /// Loads `path` as the reference image; the line for the status bar.
    pub fn load(&mut self, path: PathBuf) -> String {
        match crate::render::textures::decode_bounded(&path) {
            Ok(img) => {
                let said = format!(
                    "Reference image {} ({}×{}): click it to pick a colour",
                    path.display(),
                    img.width(),
                    img.height()
                );
                self.reference = Some(Reference {
                    path,
                    image: img.to_rgba8(),
                    texture: None,
                    over: false,
                    opacity: 0.5,
                    pick_into: PickInto::Albedo,
                    picked: None,
                });
                said
            }
            Err(e) => format!("Error: {}: {e}", path.display()),
        }
    }

    /// The last colour picked into the look (the window's swatch).
    pub fn set_picked(&mut self, rgb: [f64; 3]) {
        if let Some(r) = self.reference.as_mut() {
            r.picked = Some(rgb);
        }
    }

    /// The reference image's file.
    pub fn path(&self) -> Option<&Path> {
        self.reference.as_ref().map(|r| r.path.as_path())
    }

    /// The reference over the viewport, when asked.
    pub fn overlay_ui(&self, painter: &egui::Painter, rect: egui::Rect) {
        let Some(r) = self.reference.as_ref().filter(|r| r.over) else {
            return;
        };
        let Some(tex) = r.texture.as_ref() else {
            return;
        };
        let aspect = r.image.width() as f32 / r.image.height().max(1) as f32;
        let size = if rect.width() / rect.height() > aspect {
            egui::vec2(rect.height() * aspect, rect.height())
        } else {
            egui::vec2(rect.width(), rect.width() / aspect)
        };
        let at = egui::Rect::from_center_size(rect.center(), size);
        let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
        painter.image(
            tex.id(),
            at,
            uv,
            egui::Color32::from_white_alpha((r.opacity.clamp(0.0, 1.0) * 255.0) as u8),
        );
    }
}

impl Reference {
    /// The window's rows: over the render, the eyedropper's field, the
    /// photo (a click picks); the colour picked, if one was.
    fn ui(&mut self, ui: &mut egui::Ui) -> Option<[f64; 3]> {
        let mut picked = None;
        ui.horizontal(|ui| {
            ui.checkbox(&mut self.over, "over the render")
                .on_hover_text("Draw the reference over the viewport (scaled to fit) at this opacity, to line up and compare; off: here only.");
            ui.add_enabled(self.over, egui::Slider::new(&mut self.opacity, 0.0..=1.0).text("opacity"));
        });
        ui.horizontal(|ui| {
            ui.label("Click the image to pick into");
            egui::ComboBox::from_id_salt("pick_into")
                .selected_text(self.pick_into.label())
                .show_ui(ui, |ui| {
                    for p in [PickInto::Albedo, PickInto::TransmissionTint] {
                        ui.selectable_value(&mut self.pick_into, p, p.label());
                    }
                });
            if let Some(c) = self.picked {
                let s = c.map(crate::app::analysis::linear_to_srgb8);
                let (rect, _) =
                    ui.allocate_exact_size(egui::vec2(18.0, 18.0), egui::Sense::hover());
                ui.painter()
                    .rect_filled(rect, 3.0, egui::Color32::from_rgb(s[0], s[1], s[2]));
            }
        });
        let tex = self.texture.get_or_insert_with(|| {
            // Shown within the GPU's largest texture (a 61 MP photo
            // is wider); the eyedropper reads the full image.
            let max = ui.ctx().input(|i| i.max_texture_side).max(64) as u32;
            let (w, h) = self.image.dimensions();
            let shown = if w > max || h > max {
                let k = max as f64 / w.max(h) as f64;
                image::imageops::resize(
                    &self.image,
                    ((w as f64 * k) as u32).max(1),
                    ((h as f64 * k) as u32).max(1),
                    image::imageops::FilterType::Triangle,
                )
            } else {
                self.image.clone()
            };
            ui.ctx().load_texture(
                "reference",
                egui::ColorImage::from_rgba_unmultiplied(
                    [shown.width() as usize, shown.height() as usize],
                    shown.as_raw(),
                ),
                egui::TextureOptions::LINEAR,
            )
        });
        let w = ui.available_width().max(64.0);
        let size = egui::vec2(
            w,
            w * self.image.height() as f32 / self.image.width().max(1) as f32,
        );
        let response = ui
            .add(egui::Image::new((tex.id(), size)).sense(egui::Sense::click()))
            .on_hover_cursor(egui::CursorIcon::Crosshair)
            .on_hover_text(
                "Click: the colour under the pointer (a 5×5 mean) into the chosen field.",
            );
        if let Some(pos) = response
            .interact_pointer_pos()
            .filter(|_| response.clicked())
        {
            let f = (pos - response.rect.min) / response.rect.size();
            let x = (f.x * self.image.width() as f32).clamp(0.0, self.image.width() as f32 - 1.0)
                as u32;
            let y = (f.y * self.image.height() as f32).clamp(0.0, self.image.height() as f32 - 1.0)
                as u32;
            picked = Some(sample(&self.image, x, y));
        }
        ui.small(self.path.display().to_string());
        picked
    }
}

impl Window for ReferenceWindow {
    fn title(&self) -> &'static str {
        "Reference"
    }
    /// Opened by loading a photo (File → Reference image…).
    fn menu(&self) -> Option<Menu> {
        None
    }
    fn is_open(&self) -> bool {
        self.reference.is_some()
    }
    fn set_open(&mut self, open: bool) {
        if !open {
            self.reference = None;
        }
    }

    /// Beside the render, or its controls while it is over the viewport.
    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        let Some(r) = self.reference.as_mut() else {
            return Vec::new();
        };
        let mut open = true;
        // Over the Profile panel: egui's own first place covered the Look
        // panel's Albedo fields the eyedropper picks into.
        let (pos, width) = view.over_profile_panel(360.0, 200.0);
        let picked = egui::Window::new("Reference")
            .open(&mut open)
            .default_pos(pos)
            .default_width(width)
            .show(ctx, |ui| r.ui(ui))
            .and_then(|i| i.inner.flatten());
        let into = r.pick_into;
        if !open {
            self.reference = None;
        }
        picked
            .map(|c| Action::PickColour(c, into))
            .into_iter()
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The eyedropper's sample is the linear mean of the 5×5 block: a
    /// block of sRGB 188 (0.5029 linear, IEC 61966-2-1) with one black
    /// texel averages to 0.5029 × 24/25.
    #[test]
    fn samples_are_linear_means_of_five_by_five() {
        let mut img = image::RgbaImage::from_pixel(9, 9, image::Rgba([188, 188, 188, 255]));
        img.put_pixel(4, 4, image::Rgba([0, 0, 0, 255]));
        let s = sample(&img, 4, 4);
        let g = ((188.0f64 / 255.0 + 0.055) / 1.055).powf(2.4);
        assert!((s[0] - g * 24.0 / 25.0).abs() < 1e-6, "{s:?}");
        // At a corner the block is clamped to the image.
        let c = sample(&img, 0, 0);
        assert!((c[1] - g).abs() < 1e-6);
    }
}
