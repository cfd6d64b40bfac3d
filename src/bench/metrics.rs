//! Error of a frame against the reference: relative RMSE of the scattered
//! irradiance (linear HDR) over SSS pixels, and FLIP (Andersson et al.
//! 2020, through the nv-flip crate) on the tonemapped sRGB images.

use image::RgbaImage;

/// Pixels whose SSS mask (the diffuse target's alpha) exceeds 1/255.
pub fn sss_mask(diffuse: &[[f32; 4]]) -> Vec<bool> {
    diffuse.iter().map(|p| p[3] > 1.0 / 255.0).collect()
}

/// The SSS pixels at least `margin` pixels (Chebyshev) from every pixel
/// that is not SSS (background, eyes, brows, the image border): away from
/// the mask edges and silhouettes, where the screen-space methods
/// renormalise their weights over the SSS pixels they see and the ground
/// truth does not.
pub fn interior(mask: &[bool], width: usize, margin: usize) -> Vec<bool> {
    let height = mask.len() / width.max(1);
    let m = margin as isize;
    (0..mask.len())
        .map(|i| {
            let (x, y) = ((i % width) as isize, (i / width) as isize);
            mask[i]
                && (-m..=m).all(|dy| {
                    (-m..=m).all(|dx| {
                        let (u, v) = (x + dx, y + dy);
                        u >= 0
                            && v >= 0
                            && (u as usize) < width
                            && (v as usize) < height
                            && mask[v as usize * width + u as usize]
                    })
                })
        })
        .collect()
}

/// √(Σ|a − r|²) / √(Σ|r|²) over the masked pixels' RGB; 0 with no pixel.
pub fn relative_rmse(actual: &[[f32; 4]], reference: &[[f32; 4]], mask: &[bool]) -> f64 {
    let (mut num, mut den) = (0.0f64, 0.0f64);
    for ((a, r), m) in actual.iter().zip(reference).zip(mask) {
        if *m {
            for c in 0..3 {
                num += (a[c] as f64 - r[c] as f64).powi(2);
                den += (r[c] as f64).powi(2);
            }
        }
    }
    if den > 0.0 {
        (num / den).sqrt()
    } else {
        0.0
    }
}

/// Σ|a − r|² over the masked pixels' RGB.
pub fn squared_error(actual: &[[f32; 4]], reference: &[[f32; 4]], mask: &[bool]) -> f64 {
    actual
        .iter()
        .zip(reference)
        .zip(mask)
        .filter(|(_, m)| **m)
        .map(|((a, r), _)| {
            (0..3)
                .map(|c| (a[c] as f64 - r[c] as f64).powi(2))
                .sum::<f64>()
        })
        .sum()
}

/// The share of the squared error over `all` that lies outside `inner`
/// (the band along mask edges and silhouettes); 0 without error.
pub fn edge_share(
    actual: &[[f32; 4]],
    reference: &[[f32; 4]],
    all: &[bool],
    inner: &[bool],
) -> f64 {
    let total = squared_error(actual, reference, all);
    if total > 0.0 {
        1.0 - squared_error(actual, reference, inner) / total
    } else {
        0.0
    }
}

/// FLIP's per-pixel error map (0–1) of `test` against `reference`, at the
/// crate's default 67 pixels per degree (a 0.7 m viewing distance of a
/// 24-inch 4K monitor, FLIP's own default).
pub fn flip_map(reference: &RgbaImage, test: &RgbaImage) -> Vec<f32> {
    let rgb =
        |img: &RgbaImage| -> Vec<u8> { img.pixels().flat_map(|p| [p[0], p[1], p[2]]).collect() };
    let (w, h) = reference.dimensions();
    let r = nv_flip::FlipImageRgb8::with_data(w, h, &rgb(reference));
    let t = nv_flip::FlipImageRgb8::with_data(w, h, &rgb(test));
    nv_flip::flip(r, t, nv_flip::DEFAULT_PIXELS_PER_DEGREE).to_vec()
}

/// Mean of `values` over the masked pixels (0 with none).
pub fn masked_mean(values: &[f32], mask: &[bool]) -> f64 {
    let (sum, n) = values
        .iter()
        .zip(mask)
        .filter(|(_, m)| **m)
        .fold((0.0f64, 0usize), |(s, n), (v, _)| (s + *v as f64, n + 1));
    if n > 0 {
        sum / n as f64
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 5×5 all-SSS image with margin 1: its 3×3 middle; a hole at the
    /// centre removes the whole middle (every pixel of it touches it).
    #[test]
    fn interior_by_hand() {
        let mut mask = vec![true; 25];
        assert_eq!(interior(&mask, 5, 1).iter().filter(|m| **m).count(), 9);
        mask[12] = false;
        assert_eq!(interior(&mask, 5, 1).iter().filter(|m| **m).count(), 0);
    }

    #[test]
    fn relative_rmse_by_hand() {
        // Reference (1, 2, 2) → |r|² = 9; actual off by (0, 0, 3) → 9: ratio 1.
        let r = [[1.0, 2.0, 2.0, 1.0], [5.0, 5.0, 5.0, 0.0]];
        let a = [[1.0, 2.0, 5.0, 1.0], [0.0, 0.0, 0.0, 0.0]];
        let m = sss_mask(&r);
        assert_eq!(m, vec![true, false]);
        assert!((relative_rmse(&a, &r, &m) - 1.0).abs() < 1e-12);
        assert_eq!(relative_rmse(&r, &r, &m), 0.0);
    }

    #[test]
    fn flip_is_zero_for_equal_images_and_grows_with_difference() {
        let a = RgbaImage::from_pixel(32, 32, image::Rgba([120, 90, 80, 255]));
        let mut b = a.clone();
        for x in 8..24 {
            b.put_pixel(x, 16, image::Rgba([250, 250, 250, 255]));
        }
        let mask = vec![true; 32 * 32];
        assert!(masked_mean(&flip_map(&a, &a), &mask) < 1e-6);
        let e = masked_mean(&flip_map(&a, &b), &mask);
        assert!(e > 1e-3, "{e}");
    }
}
