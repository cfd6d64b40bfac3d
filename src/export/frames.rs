//! Rendered frames as files: a supersampled still's box filter and the
//! turntable's animated PNG. The editor's Save image at size and Save
//! turntable write through these; the tests read the files back with
//! `image`'s decoders.

use crate::model::colour::{linear_to_srgb8, srgb8_to_linear};

/// Each k×k block of `img` averaged into one pixel: the colour channels
/// in linear light (sRGB decoded, averaged, encoded again, so an edge
/// between light and dark is not darkened), alpha as it is; `img` is k
/// times the output a side.
pub fn box_downsample(img: &image::RgbaImage, k: u32) -> image::RgbaImage {
    if k <= 1 {
        return img.clone();
    }
    let (w, h) = (img.width() / k, img.height() / k);
    let n = (k * k) as f64;
    image::RgbaImage::from_fn(w, h, |x, y| {
        let mut sum = [0.0f64; 4];
        for dy in 0..k {
            for dx in 0..k {
                let p = img.get_pixel(x * k + dx, y * k + dy);
                for c in 0..3 {
                    sum[c] += srgb8_to_linear(p[c]) as f64;
                }
                sum[3] += p[3] as f64;
            }
        }
        let rgb = [0, 1, 2].map(|c| linear_to_srgb8((sum[c] / n) as f32));
        image::Rgba([rgb[0], rgb[1], rgb[2], (sum[3] / n).round() as u8])
    })
}

/// The frames as an APNG looping forever, each shown `delay_ms`: RGBA 8
/// bits, every frame whole (no blending or offsets), so each decodes to
/// exactly the frame given (APNG 1.0 specification, Mozilla: acTL with
/// num_plays 0, an fcTL per frame, the first in IDAT).
pub fn encode_apng(frames: &[image::RgbaImage], delay_ms: u32) -> Result<Vec<u8>, String> {
    let first = frames.first().ok_or("no frames")?;
    let (w, h) = first.dimensions();
    let mut bytes = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut bytes, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        enc.set_animated(frames.len() as u32, 0)
            .map_err(|e| e.to_string())?;
        let delay = delay_ms.clamp(1, u16::MAX as u32) as u16;
        enc.set_frame_delay(delay, 1000)
            .map_err(|e| e.to_string())?;
        let mut writer = enc.write_header().map_err(|e| e.to_string())?;
        for f in frames {
            if f.dimensions() != (w, h) {
                return Err(format!(
                    "frame of {}×{} in a {w}×{h} animation",
                    f.width(),
                    f.height()
                ));
            }
            writer
                .write_image_data(f.as_raw())
                .map_err(|e| e.to_string())?;
        }
        writer.finish().map_err(|e| e.to_string())?;
    }
    Ok(bytes)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A box filter keeps a flat colour exactly and averages a block in
    /// linear light: a 2×2 block of black and three whites is 0.75 linear,
    /// sRGB 1.055 · 0.75^(1/2.4) − 0.055 = 0.8808 → 225 (IEC 61966-2-1),
    /// where averaging the bytes would give 191.
    #[test]
    fn box_downsampling_averages_each_block() {
        let flat = image::RgbaImage::from_pixel(8, 6, image::Rgba([10, 200, 33, 255]));
        let d = box_downsample(&flat, 2);
        assert_eq!(d.dimensions(), (4, 3));
        assert!(d.pixels().all(|p| *p == image::Rgba([10, 200, 33, 255])));
        let mut block = image::RgbaImage::from_pixel(2, 2, image::Rgba([255, 255, 255, 255]));
        block.put_pixel(0, 0, image::Rgba([0, 0, 0, 255]));
        let want = ((1.055 * 0.75f64.powf(1.0 / 2.4) - 0.055) * 255.0).round() as u8;
        assert_eq!(want, 225);
        assert_eq!(
            *box_downsample(&block, 2).get_pixel(0, 0),
            image::Rgba([want, want, want, 255])
        );
    }
}
