//! What a frame reads back besides its 8-bit output: the linear layers
//! the composite pass read ([`FrameLayers`]: `render --out FILE.exr`, the
//! bench's comparison with the ground truth), read in one submission, and
//! the SSS passes' sample counters.

use super::context::{GpuContext, GpuError};
use super::readback::{readback, rgba_halves};
use super::targets::{HdrTarget, Targets};

/// What a frame reads back besides its 8-bit output.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Want {
    Image,
    /// The scattered diffuse ([`FrameLayers::scattered`]) only.
    Diffuse,
    Layers,
}

/// Linear float layers of one frame, row-major with y down, as the
/// composite pass (`composite.wgsl`, `fs_composite`) read them, before
/// exposure and tone mapping: `render --out FILE.exr` writes them.
#[derive(Clone, Debug, Default)]
pub struct FrameLayers {
    pub width: u32,
    pub height: u32,
    /// The scattered diffuse irradiance the composite used: the method's
    /// output on SSS pixels, the scene's diffuse elsewhere (what the bench
    /// compares with the ground truth). Alpha: the SSS mask (as the
    /// method wrote it on SSS pixels, the scene's elsewhere).
    pub scattered: Vec<[f32; 4]>,
    /// The scene pass's diffuse irradiance × albedo^pre, before any SSS
    /// pass (`scene.wgsl`'s target 0; `preintegrated` scatters in the scene
    /// pass, so for it this is already its scattered light). Alpha: the SSS
    /// mask, −1 on eyes and teeth, −2 on the background.
    pub unscattered: Vec<[f32; 4]>,
    /// albedo^post (8-bit linear, as the composite reads it). Alpha:
    /// coverage, 1 on the mesh and 0 on the background.
    pub albedo: Vec<[f32; 4]>,
    /// Specular radiance (never blurred).
    pub specular: Vec<[f32; 3]>,
}

impl FrameLayers {
    /// The linear radiance the composite pass tone-maps: scattered ×
    /// albedo^post + specular on the mesh, 0 on the background (which the
    /// composite paints a studio grey). Alpha: coverage.
    pub fn radiance(&self) -> Vec<[f32; 4]> {
        (0..self.albedo.len())
            .map(|i| {
                let (d, a, sp) = (self.scattered[i], self.albedo[i], self.specular[i]);
                if a[3] <= 0.0 {
                    return [0.0; 4];
                }
                [
                    d[0] * a[0] + sp[0],
                    d[1] * a[1] + sp[1],
                    d[2] * a[2] + sp[2],
                    a[3],
                ]
            })
            .collect()
    }
}

/// Submits `encoder` and reads back the 8-bit output and what `want`
/// asks for: the scattered diffuse irradiance composite used (the shown
/// texture on SSS pixels, the scene's diffuse elsewhere), or every layer.
pub(super) fn read_frame(
    ctx: &GpuContext,
    encoder: wgpu::CommandEncoder,
    t: &Targets,
    shown: &wgpu::Texture,
    want: Want,
    (width, height): (u32, u32),
) -> Result<(image::RgbaImage, Option<FrameLayers>), GpuError> {
    let mut wanted: Vec<(&wgpu::Texture, u32)> = vec![(&t.output, 4)];
    if want != Want::Image {
        wanted.push((t.texture(HdrTarget::Diffuse), 8));
        wanted.push((shown, 8));
    }
    let rg11b10 = t.specular_texture.format() == wgpu::TextureFormat::Rg11b10Ufloat;
    if want == Want::Layers {
        wanted.push((&t.albedo_texture, 4));
        wanted.push((&t.specular_texture, if rg11b10 { 4 } else { 8 }));
    }
    let mut bytes = ctx.checked("frame", || readback(ctx, encoder, &wanted, width, height))??;
    let image = image::RgbaImage::from_raw(width, height, std::mem::take(&mut bytes[0]))
        .ok_or_else(|| GpuError::Readback("size mismatch".into()))?;
    if want == Want::Image {
        return Ok((image, None));
    }
    let unscattered = rgba_halves(&bytes[1]);
    let scattered = rgba_halves(&bytes[2])
        .into_iter()
        .zip(&unscattered)
        .map(|(o, d)| if o[3] > 1.0 / 255.0 { o } else { *d })
        .collect();
    let mut layers = FrameLayers {
        width,
        height,
        scattered,
        ..Default::default()
    };
    if want == Want::Layers {
        layers.albedo = bytes[3]
            .chunks_exact(4)
            .map(|p| p.try_into().map(|p: [u8; 4]| p.map(|v| v as f32 / 255.0)))
            .collect::<Result<_, _>>()
            .map_err(|_| GpuError::Readback("albedo texels".into()))?;
        layers.specular = if rg11b10 {
            super::readback::rg11b10(&bytes[4])
        } else {
            rgba_halves(&bytes[4])
                .into_iter()
                .map(|p| [p[0], p[1], p[2]])
                .collect()
        };
        layers.unscattered = unscattered;
    }
    Ok((image, Some(layers)))
}

/// Samples the SSS passes took and pixels the LOD skipped: the GPU's
/// counters where a pass counted them (and that pass's sample count in the
/// timer), else pixels × the method's samples per pixel.
pub(super) fn sss_counts(
    ctx: &GpuContext,
    scattered: &super::sss::Scattered,
    counters_read: &wgpu::Buffer,
    sss_pixels: u64,
    timer: &mut super::timing::PassTimer,
) -> (u64, u64) {
    let measured = scattered
        .counted_pass
        .and_then(|_| super::readback::read_u32x4(ctx, counters_read));
    let counts = match measured {
        Some(c) => (c[0] as u64, c[2] as u64),
        None => (sss_pixels * scattered.samples_per_pixel as u64, 0),
    };
    if let Some(label) = scattered.counted_pass {
        timer.set_samples(label, counts.0);
    }
    counts
}
