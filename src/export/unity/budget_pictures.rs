//! The budget report's pictures: each merge's r·R(r) chart and the
//! default head rendered with a profile and its merge side by side, with
//! the |ΔL*| between them.

use super::budget_run::write;
use crate::settings::Preset;
use anyhow::{bail, Context, Result};
use std::path::Path;

/// The default skin's albedo, which HDRP keeps in the material (a profile
/// read from HDRP has albedo 1, a white head).
fn skin_albedo() -> crate::model::Rgb {
    match &Preset::default_skin().profile {
        crate::settings::ProfileSpec::Burley(b) => b.albedo,
        _ => [0.8, 0.5, 0.4],
    }
}

/// A profile as the report draws it: with the default skin's albedo, as a
/// material would give it, said in its description.
pub(super) fn with_material_albedo(p: &Preset) -> Preset {
    let mut p = p.clone();
    if let crate::settings::ProfileSpec::Burley(b) = &mut p.profile {
        b.albedo = skin_albedo();
    }
    p.rendering.albedo_in_material = false;
    p.description = format!(
        "{} Drawn with the default skin's albedo: HDRP keeps the albedo in the material.",
        p.description
    )
    .trim()
    .to_owned();
    p
}

/// r·R(r)/A per channel of each member (thin) and of the merge (thick).
pub(super) fn curves_chart(
    path: &Path,
    members: &[(&str, &Preset)],
    merged: &Preset,
) -> Result<()> {
    use plotters::prelude::*;
    crate::bench::chart::register_font()?;
    let profiles: Vec<(String, Box<dyn crate::model::RadialProfile>, bool)> = members
        .iter()
        .map(|(n, p)| Ok((n.to_string(), p.build_profile()?, false)))
        .chain(std::iter::once(Ok((
            "merged".to_string(),
            merged.build_profile()?,
            true,
        ))))
        .collect::<Result<_>>()?;
    let (w, h) = (1200u32, 380u32);
    let mut buf = vec![0u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
        let panels = root.split_evenly((1, 3));
        for (c, area) in panels.iter().enumerate() {
            let r_max = profiles
                .iter()
                .map(|(_, p, _)| p.inverse_cdf(c, 0.95))
                .fold(0.0f64, f64::max)
                .max(1e-3);
            let curve = |p: &dyn crate::model::RadialProfile| -> Vec<(f64, f64)> {
                let a = p.total_reflectance()[c].max(1e-12);
                (0..=200)
                    .map(|i| {
                        let r = r_max * i as f64 / 200.0;
                        (r, p.r_reflectance(r)[c] / a)
                    })
                    .collect()
            };
            let y_max = profiles
                .iter()
                .flat_map(|(_, p, _)| curve(p.as_ref()))
                .map(|(_, y)| y)
                .fold(0.0f64, f64::max)
                .max(1e-9);
            let mut chart = ChartBuilder::on(area)
                .caption(["red", "green", "blue"][c], ("sans-serif", 16))
                .margin(10)
                .x_label_area_size(36)
                .y_label_area_size(56)
                .build_cartesian_2d(0.0..r_max, 0.0..y_max * 1.05)
                .map_err(|e| anyhow::anyhow!("{e}"))?;
            chart
                .configure_mesh()
                .x_desc("r (mm)")
                .y_desc("r·R(r) / A (1/mm)")
                .label_style(("sans-serif", 12))
                .draw()
                .map_err(|e| anyhow::anyhow!("{e}"))?;
            let palette = [
                RGBColor(31, 119, 180),
                RGBColor(255, 127, 14),
                RGBColor(44, 160, 44),
                RGBColor(214, 39, 40),
                RGBColor(148, 103, 189),
                RGBColor(140, 86, 75),
            ];
            for (k, (name, p, merged)) in profiles.iter().enumerate() {
                let style = if *merged {
                    BLACK.stroke_width(3)
                } else {
                    palette[k % palette.len()].stroke_width(1)
                };
                let s = chart
                    .draw_series(LineSeries::new(curve(p.as_ref()), style))
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
                if c == 0 {
                    s.label(name.clone())
                        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], style));
                }
            }
            if c == 0 {
                chart
                    .configure_series_labels()
                    .label_font(("sans-serif", 12))
                    .background_style(WHITE.mix(0.85))
                    .border_style(BLACK)
                    .draw()
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
            }
        }
        root.present().map_err(|e| anyhow::anyhow!("{e}"))?;
    }
    let img = image::RgbImage::from_raw(w, h, buf).context("chart buffer")?;
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )?;
    write(path, &bytes)
}

/// The default head, rendered with a look and its merge side by side.
pub(super) struct HeadRenderer {
    renderer: crate::render::renderer::Renderer,
    /// The default head, framed whole, and the side in pixels.
    view: crate::settings::OrbitView,
    size: u32,
}

impl HeadRenderer {
    pub(super) fn new(size: u32) -> Result<Self> {
        use crate::settings::OrbitView;
        if !(32..=2048).contains(&size) {
            bail!("--render-size {size}: 32–2048 pixels");
        }
        let mesh = crate::render::Mesh::default_head()?;
        let d = OrbitView::default();
        let view = OrbitView {
            camera_distance_m: mesh.framing_distance_m(d.fov_y_rad),
            ..d
        };
        let renderer = crate::render::renderer::Renderer::new(
            crate::render::context::GpuContext::new_headless()?,
            &mesh,
        )?;
        Ok(Self {
            renderer,
            view,
            size,
        })
    }

    fn image(&mut self, look: &Preset) -> Result<image::RgbaImage> {
        use crate::render::sss::ProfileInputs;
        // HDRP keeps the albedo in the material: the default skin's.
        let p = with_material_albedo(look);
        let profile = p.build_profile()?;
        // The look's own rendering (method, transmission, tint,
        // texturing), as `render` draws a preset.
        let settings = crate::render::settings::RenderSettings {
            deterministic: true,
            ..crate::render::settings::RenderSettings::for_look(
                &p.rendering,
                self.view,
                [[0.0; 3]; 9],
                (self.size, self.size),
            )
        };
        let inputs = ProfileInputs::for_look(
            &p.profile,
            profile.as_ref(),
            settings.method,
            (p.rendering.samples, p.rendering.taps),
            &Default::default(),
        )?;
        Ok(self.renderer.render(&inputs, &settings)?.0)
    }

    /// Old | merged | |ΔL*| heat map; returns the mean and max ΔL* over
    /// the pixels where either frame has the head.
    pub(super) fn side_by_side(
        &mut self,
        old: &Preset,
        merged: &Preset,
        path: &Path,
    ) -> Result<(f32, f32)> {
        let a = self.image(old)?;
        let b = self.image(merged)?;
        let (w, h) = a.dimensions();
        let bg = *a.get_pixel(0, 0);
        let (mut sum, mut max, mut n) = (0.0f32, 0.0f32, 0usize);
        for (pa, pb) in a.pixels().zip(b.pixels()) {
            if *pa == bg && *pb == bg {
                continue;
            }
            let d = (crate::render::compare::lightness(pa) - crate::render::compare::lightness(pb))
                .abs();
            sum += d;
            max = max.max(d);
            n += 1;
        }
        let (heat, _) = crate::render::compare::difference_view(&a, &b, Some(5.0));
        let mut out = image::RgbaImage::new(3 * w, h);
        image::imageops::overlay(&mut out, &a, 0, 0);
        image::imageops::overlay(&mut out, &b, w as i64, 0);
        image::imageops::overlay(&mut out, &heat, 2 * w as i64, 0);
        let mut bytes = Vec::new();
        out.write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )?;
        write(path, &bytes)?;
        Ok((if n > 0 { sum / n as f32 } else { 0.0 }, max))
    }
}
