//! Side-by-side comparison of two frames: a split view with a divider, and
//! a difference heat map |A − B| of linear luminance with a colour scale.

use image::{Rgba, RgbaImage};

/// Left of `split` (0–1 of the width) shows `a`, right shows `b`, with a
/// 2-pixel light divider.
pub fn split_view(a: &RgbaImage, b: &RgbaImage, split: f32) -> RgbaImage {
    let (w, h) = a.dimensions();
    let x0 = (split.clamp(0.0, 1.0) * w as f32).round() as u32;
    RgbaImage::from_fn(w, h, |x, y| {
        if x + 1 >= x0 && x <= x0 {
            Rgba([230, 230, 230, 255])
        } else if x < x0 {
            *a.get_pixel(x, y)
        } else {
            *b.get_pixel(x, y)
        }
    })
}

/// An sRGB-encoded byte as linear (IEC 61966-2-1).
pub fn srgb_to_linear(v: u8) -> f32 {
    crate::model::colour::srgb8_to_linear(v)
}

fn luminance(p: &Rgba<u8>) -> f32 {
    0.2126 * srgb_to_linear(p[0]) + 0.7152 * srgb_to_linear(p[1]) + 0.0722 * srgb_to_linear(p[2])
}

/// A perceptually ordered black → purple → orange → yellow ramp (an
/// approximation of matplotlib's "inferno") for t in [0, 1].
pub fn heat(t: f32) -> [u8; 3] {
    const STOPS: [(f32, [f32; 3]); 5] = [
        (0.0, [0.0, 0.0, 0.02]),
        (0.25, [0.34, 0.06, 0.43]),
        (0.5, [0.73, 0.21, 0.33]),
        (0.75, [0.98, 0.55, 0.04]),
        (1.0, [0.99, 1.0, 0.64]),
    ];
    let t = t.clamp(0.0, 1.0);
    let i = STOPS
        .iter()
        .rposition(|s| s.0 <= t)
        .unwrap_or(0)
        .min(STOPS.len() - 2);
    let (a, b) = (STOPS[i], STOPS[i + 1]);
    let f = (t - a.0) / (b.0 - a.0);
    [0, 1, 2].map(|c| ((a.1[c] + f * (b.1[c] - a.1[c])) * 255.0).round() as u8)
}

/// CIE 1976 lightness L* (0 black … 100 white) of a displayed sRGB pixel:
/// Y from the decoded channels (Rec. 709 weights, white Y = 1), then
/// L* = 116 f(Y) − 16 with f(t) = t^(1/3) above (6/29)³ and
/// t / (3 (6/29)²) + 4/29 below (CIE 15:2004, eq. 8.1 and 8.11; Poynton,
/// "Digital Video and HD", 2nd ed., eq. 25.8). Tested against published
/// values in `lightness_matches_published_values`.
pub fn lightness(p: &Rgba<u8>) -> f32 {
    const D: f32 = 6.0 / 29.0;
    let y = luminance(p);
    let f = if y > D * D * D {
        y.cbrt()
    } else {
        y / (3.0 * D * D) + 4.0 / 29.0
    };
    116.0 * f - 16.0
}

/// |A − B| of CIE L* (perceived lightness, 0–100: a difference of about 1
/// is just noticeable side by side) as a heat map scaled to `scale` (or to
/// the largest difference when `None`), with a 12-pixel colour bar at the
/// right edge (bottom 0, top = scale). Returns the image and the scale
/// used, in ΔL*.
pub fn difference_view(a: &RgbaImage, b: &RgbaImage, scale: Option<f32>) -> (RgbaImage, f32) {
    let (w, h) = a.dimensions();
    let diffs: Vec<f32> = a
        .pixels()
        .zip(b.pixels())
        .map(|(p, q)| (lightness(p) - lightness(q)).abs())
        .collect();
    let max = scale
        .unwrap_or_else(|| diffs.iter().copied().fold(0.0, f32::max))
        .max(1e-6);
    let bar = 12.min(w / 4);
    let img = RgbaImage::from_fn(w, h, |x, y| {
        let t = if x >= w - bar {
            1.0 - y as f32 / (h.max(2) - 1) as f32
        } else {
            diffs[(y * w + x) as usize] / max
        };
        let [r, g, b] = heat(t);
        Rgba([r, g, b, 255])
    });
    (img, max)
}

/// What one pixel of a displayed frame holds: its sRGB bytes, their
/// decoded (display-linear) values and CIE L* ([`lightness`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Probe {
    pub srgb: [u8; 3],
    pub linear: [f32; 3],
    pub lightness: f32,
}

/// The pixel at (x, y) of `img`, if inside it.
pub fn probe(img: &RgbaImage, x: u32, y: u32) -> Option<Probe> {
    (x < img.width() && y < img.height()).then(|| {
        let p = img.get_pixel(x, y);
        Probe {
            srgb: [p[0], p[1], p[2]],
            linear: [0, 1, 2].map(|c| srgb_to_linear(p[c])),
            lightness: lightness(p),
        }
    })
}

/// The |ΔL*| a pixel of a difference view stands for, at the view's
/// white `scale`: [`heat`] inverted by the nearest of 1024 steps of its
/// ramp (within half a step, 1/2048 of the scale, where the bytes are
/// exact).
pub fn heat_value(rgb: [u8; 3], scale: f32) -> f32 {
    let d = |t: f32| {
        let h = heat(t);
        (0..3)
            .map(|c| (h[c] as i32 - rgb[c] as i32).pow(2))
            .sum::<i32>()
    };
    let best = (0..=1024)
        .map(|i| i as f32 / 1024.0)
        .min_by_key(|&t| d(t))
        .unwrap_or(0.0);
    best * scale
}

/// The mean and largest |ΔL*| between two frames over the pixels where
/// either shows the head, and how many those are. On a plain background
/// the head is every pixel that differs from the background colour (the
/// top-left corner's); behind an HDR map (`plain_background` false) the
/// background varies, and the pixels taken are those where the frames
/// differ (the map is the same on both sides).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DifferenceStats {
    pub mean: f32,
    pub max: f32,
    pub pixels: usize,
}

pub fn difference_stats(a: &RgbaImage, b: &RgbaImage, plain_background: bool) -> DifferenceStats {
    let bg = *a.get_pixel(0, 0);
    let (mut sum, mut max, mut n) = (0.0f64, 0.0f32, 0usize);
    for (p, q) in a.pixels().zip(b.pixels()) {
        let skip = if plain_background {
            *p == bg && *q == bg
        } else {
            p == q
        };
        if skip {
            continue;
        }
        let d = (lightness(p) - lightness(q)).abs();
        sum += d as f64;
        max = max.max(d);
        n += 1;
    }
    DifferenceStats {
        mean: if n > 0 { (sum / n as f64) as f32 } else { 0.0 },
        max,
        pixels: n,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// sRGB 119 grey has L* 50.0 (Y = 0.1842: CIE 15:2004, the
    /// lightness of middle grey; Poynton eq. 25.8); the probe reads the
    /// bytes, their decoding and L*.
    #[test]
    fn the_probe_reads_bytes_linear_and_lightness() {
        let img = RgbaImage::from_pixel(4, 4, Rgba([119, 119, 119, 255]));
        let p = probe(&img, 1, 2).unwrap();
        assert_eq!(p.srgb, [119; 3]);
        assert!((p.linear[0] - 0.1845).abs() < 1e-3, "{p:?}");
        assert!((p.lightness - 50.0).abs() < 0.1, "{p:?}");
        assert_eq!(probe(&img, 4, 0), None);
    }

    /// A difference view's pixel reads back as the ΔL* it was drawn
    /// from, to a fraction of the ramp's 8-bit step.
    #[test]
    fn heat_pixels_read_back_as_their_difference() {
        for d in [0.0f32, 0.7, 2.5, 4.1, 5.0] {
            let back = heat_value(heat(d / 5.0), 5.0);
            assert!((back - d).abs() < 0.05, "{d} read back as {back}");
        }
    }

    /// Mean and max over the head only: background pixels on both sides
    /// are left out. Two grey levels of known L*: sRGB 119 (50.0) and
    /// 255 (100).
    #[test]
    fn difference_statistics_leave_out_the_background() {
        let bg = Rgba([20, 20, 20, 255]);
        let mut a = RgbaImage::from_pixel(10, 10, bg);
        let mut b = a.clone();
        for x in 0..5 {
            a.put_pixel(x, 5, Rgba([119, 119, 119, 255]));
            b.put_pixel(x, 5, Rgba([119, 119, 119, 255]));
        }
        a.put_pixel(9, 9, Rgba([255, 255, 255, 255]));
        b.put_pixel(9, 9, Rgba([119, 119, 119, 255]));
        let s = difference_stats(&a, &b, true);
        assert_eq!(s.pixels, 6);
        assert!((s.max - 50.0).abs() < 0.1, "{s:?}");
        assert!((s.mean - 50.0 / 6.0).abs() < 0.05, "{s:?}");
        // Behind a map only the pixels that differ count.
        let s = difference_stats(&a, &b, false);
        assert_eq!(s.pixels, 1);
        assert!((s.mean - 50.0).abs() < 0.1, "{s:?}");
    }

    #[test]
    fn split_takes_each_side_from_its_image() {
        let a = RgbaImage::from_pixel(10, 4, Rgba([10, 0, 0, 255]));
        let b = RgbaImage::from_pixel(10, 4, Rgba([0, 0, 10, 255]));
        let s = split_view(&a, &b, 0.5);
        assert_eq!(*s.get_pixel(1, 1), Rgba([10, 0, 0, 255]));
        assert_eq!(*s.get_pixel(8, 1), Rgba([0, 0, 10, 255]));
        assert_eq!(*s.get_pixel(5, 1), Rgba([230, 230, 230, 255]));
    }

    #[test]
    fn identical_frames_give_a_black_difference_and_the_bar_spans_the_ramp() {
        let a = RgbaImage::from_pixel(64, 32, Rgba([120, 90, 80, 255]));
        let (d, _) = difference_view(&a, &a, Some(5.0));
        assert_eq!(*d.get_pixel(5, 5), Rgba([0, 0, 5, 255]));
        assert_eq!(&d.get_pixel(60, 0).0[..3], &heat(1.0)[..]);
        assert_eq!(&d.get_pixel(60, 31).0[..3], &heat(0.0)[..]);
        // The auto scale is the largest difference: white vs black is 100.
        let b = RgbaImage::from_pixel(64, 32, Rgba([255, 255, 255, 255]));
        let c = RgbaImage::from_pixel(64, 32, Rgba([0, 0, 0, 255]));
        let (_, s) = difference_view(&b, &c, None);
        assert!((s - 100.0).abs() < 1e-3, "{s}");
    }

    /// Published CIELAB values of sRGB colours (Lindbloom's calculator and
    /// the CSS Color 4 specification's examples, D65): sRGB 119 grey is
    /// L* 50.0 (the middle of CIELAB), 255 is 100, 0 is 0, 18 % grey (Y =
    /// 0.18) is L* 49.5, and pure sRGB red (255, 0, 0) is L* 53.24.
    #[test]
    fn lightness_matches_published_values() {
        let l = |r, g, b| lightness(&Rgba([r, g, b, 255]));
        assert!(
            (l(119, 119, 119) - 50.0).abs() < 0.1,
            "{}",
            l(119, 119, 119)
        );
        assert!((l(255, 255, 255) - 100.0).abs() < 1e-3);
        assert!(l(0, 0, 0).abs() < 1e-4);
        assert!((l(255, 0, 0) - 53.24).abs() < 0.02, "{}", l(255, 0, 0));
        // sRGB 118 decodes to Y = 0.1812: L* = 116 · 0.1812^(1/3) − 16.
        assert!(
            (l(118, 118, 118) - 49.6).abs() < 0.1,
            "{}",
            l(118, 118, 118)
        );
    }
}
