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

/// A frame's scene-linear radiance, before exposure and the display
/// transform (what the composite pass tone-maps: scattered × albedo^post +
/// specular), row-major with y down; alpha the coverage, 0 on the
/// background (whose light is not the mesh's). The editor's pixel probe
/// and histogram read it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SceneLinear {
    pub width: u32,
    pub height: u32,
    pub radiance: Vec<[f32; 4]>,
    /// The specular part of the radiance (never scattered); empty where
    /// not read.
    pub specular: Vec<[f32; 3]>,
}

/// Relative luminance of linear Rec. 709 / sRGB primaries (ITU-R BT.709-6
/// item 3.3; IEC 61966-2-1's Y row).
pub fn luminance(rgb: [f32; 3]) -> f32 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// A histogram of the mesh's luminance in stops: bin k counts the covered
/// pixels with log2(Y / 0.18) in [lo + k·step, lo + (k+1)·step); those
/// below `lo` (and black ones) fall in the first bin, those above the last
/// in the last.
#[derive(Clone, Debug, PartialEq)]
pub struct StopsHistogram {
    /// The first bin's lower edge (stops from 18 % grey).
    pub lo_ev: f32,
    pub step_ev: f32,
    pub counts: Vec<u32>,
    /// Covered pixels counted.
    pub pixels: u32,
    /// The median's stops from 18 % grey.
    pub median_ev: Option<f32>,
}

impl SceneLinear {
    /// The radiance at pixel (x, y), if it is on the mesh.
    pub fn at(&self, x: u32, y: u32) -> Option<[f32; 3]> {
        if x >= self.width || y >= self.height {
            return None;
        }
        let p = self.radiance.get((y * self.width + x) as usize)?;
        (p[3] > 0.0).then_some([p[0], p[1], p[2]])
    }

    /// The light through the skin alone: the radiance less its specular
    /// (scattered × albedo^post on the mesh), alpha the coverage; the
    /// radiance itself where the specular was not read.
    pub fn subsurface(&self) -> Vec<[f32; 4]> {
        self.radiance
            .iter()
            .enumerate()
            .map(|(i, p)| match self.specular.get(i) {
                Some(s) if p[3] > 0.0 => [p[0] - s[0], p[1] - s[1], p[2] - s[2], p[3]],
                _ => *p,
            })
            .collect()
    }

    /// `pixels` (this frame's size) averaged over k×k blocks, a box
    /// filter: on the mesh's edge the colour comes out premultiplied by
    /// the coverage, as OpenEXR keeps it.
    pub fn box_downsample(&self, pixels: &[[f32; 4]], k: u32) -> (u32, u32, Vec<[f32; 4]>) {
        let k = k.max(1);
        let (w, h) = (self.width / k, self.height / k);
        let n = (k * k) as f32;
        let mut out = Vec::with_capacity((w * h) as usize);
        for y in 0..h {
            for x in 0..w {
                let mut sum = [0.0f32; 4];
                for dy in 0..k {
                    for dx in 0..k {
                        let p = pixels[((y * k + dy) * self.width + x * k + dx) as usize];
                        for c in 0..4 {
                            sum[c] += p[c];
                        }
                    }
                }
                out.push(sum.map(|v| v / n));
            }
        }
        (w, h, out)
    }

    /// The mesh's luminance as a histogram of `bins` bins of `step_ev`
    /// stops from `lo_ev`.
    pub fn histogram(&self, lo_ev: f32, step_ev: f32, bins: usize) -> StopsHistogram {
        let mut counts = vec![0u32; bins.max(1)];
        let mut evs: Vec<f32> = Vec::new();
        for p in self.radiance.iter().filter(|p| p[3] > 0.0) {
            let y = luminance([p[0], p[1], p[2]]);
            let ev = if y > 0.0 {
                (y / 0.18).log2()
            } else {
                f32::NEG_INFINITY
            };
            let k = ((ev - lo_ev) / step_ev)
                .floor()
                .clamp(0.0, (counts.len() - 1) as f32);
            counts[k as usize] += 1;
            evs.push(ev);
        }
        let median_ev = (!evs.is_empty()).then(|| {
            let mid = evs.len() / 2;
            *evs.select_nth_unstable_by(mid, f32::total_cmp).1
        });
        StopsHistogram {
            lo_ev,
            step_ev,
            counts,
            pixels: evs.len() as u32,
            median_ev,
        }
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

#[cfg(test)]
mod tests {
    use super::SceneLinear;

    /// Stops from 18 % grey by hand: grey (Y 0.18) is 0 EV, twice it +1,
    /// a quarter of it −2; BT.709's weights make pure green 0.7152 (log2
    /// of 0.7152 / 0.18 = 1.990 stops); black goes to the first bin and
    /// the background is not counted.
    #[test]
    fn histogram_counts_stops_from_grey() {
        let px = |rgb: [f32; 3], a: f32| [rgb[0], rgb[1], rgb[2], a];
        let radiance = vec![
            px([0.18; 3], 1.0),
            px([0.36; 3], 1.0),
            px([0.045; 3], 1.0),
            px([0.0, 1.0, 0.0], 1.0),
            px([0.0; 3], 1.0),
            px([5.0; 3], 0.0),
        ];
        let s = SceneLinear {
            width: 3,
            height: 2,
            radiance,
            specular: Vec::new(),
        };
        let h = s.histogram(-4.0, 0.5, 16);
        assert_eq!(h.pixels, 5);
        let bin = |ev: f32| ((ev + 4.0) / 0.5).floor() as usize;
        assert_eq!(h.counts[bin(0.0)], 1);
        assert_eq!(h.counts[bin(1.0)], 1);
        assert_eq!(h.counts[bin(-2.0)], 1);
        assert_eq!(h.counts[bin(1.99)], 1, "green: {:?}", h.counts);
        assert_eq!(h.counts[0], 1, "black");
        assert_eq!(h.median_ev, Some(0.0));
        assert_eq!(s.at(2, 1), None, "background");
        assert_eq!(s.at(1, 0), Some([0.36; 3]));
    }
}
