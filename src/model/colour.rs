//! The sRGB transfer functions (IEC 61966-2-1:1999, §5.2), the one place
//! scatterlab encodes or decodes sRGB: egui's own `ecolor` crate (a small
//! crate with no GPU or UI dependency, so the parsers and the fuzz builds
//! use it too) has the pair, written once here as names of ours.
//!
//! Decoding: c ≤ 0.04045 → c / 12.92, else ((c + 0.055) / 1.055)^2.4;
//! encoding: l ≤ 0.0031308 → 12.92 l, else 1.055 l^(1/2.4) − 0.055.

/// An sRGB-encoded value in [0, 1] to linear.
pub fn srgb_to_linear(c: f32) -> f32 {
    ecolor::linear_from_gamma(c)
}

/// A linear value in [0, 1] to its sRGB encoding (not clamped).
pub fn linear_to_srgb(l: f32) -> f32 {
    ecolor::gamma_from_linear(l)
}

/// An sRGB-encoded byte to linear.
pub fn srgb8_to_linear(v: u8) -> f32 {
    ecolor::linear_f32_from_gamma_u8(v)
}

/// A linear value to an 8-bit sRGB code, clamped to [0, 1] and rounded.
pub fn linear_to_srgb8(l: f32) -> u8 {
    ecolor::gamma_u8_from_linear_f32(l)
}

/// [`srgb_to_linear`] in f64, for the engine files' colours: an import
/// and export carry them at f64 precision (the MaterialX import is checked
/// to 1e-12 against the standard's equation), which ecolor's f32 pair
/// cannot; the standard's equation, written out.
pub fn srgb_to_linear_f64(c: f64) -> f64 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

/// [`linear_to_srgb`] in f64 (see [`srgb_to_linear_f64`]).
pub fn linear_to_srgb_f64(l: f64) -> f64 {
    if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    }
}

/// sRGB (0–1, encoded) to HSV: hue in degrees, saturation and value 0–1
/// (Smith 1978, "Color gamut transform pairs", the hexcone model), through
/// ecolor's `hsv_from_rgb`, which is that model on whatever values it is
/// given (here the displayed sRGB, as paint programs give HSV).
pub fn hsv_of(c: [f64; 3]) -> [f64; 3] {
    let (h, s, v) = ecolor::hsv_from_rgb(c.map(|x| x as f32));
    [h as f64 * 360.0, s as f64, v as f64]
}

/// HSV (hue in degrees, S and V 0–1) to sRGB 0–1, the inverse of
/// [`hsv_of`] (ecolor's `rgb_from_hsv`).
pub fn rgb_of_hsv([h, s, v]: [f64; 3]) -> [f64; 3] {
    ecolor::rgb_from_hsv(((h.rem_euclid(360.0) / 360.0) as f32, s as f32, v as f32))
        .map(|x| x as f64)
}

/// `#rrggbb`, `rrggbb`, `#rgb` or `rgb` as sRGB bytes (ecolor's
/// `Color32::from_hex`, which wants the `#`; an alpha is refused).
pub fn parse_hex(text: &str) -> Option<[u8; 3]> {
    let t = text.trim().trim_start_matches('#');
    if !matches!(t.len(), 3 | 6) {
        return None;
    }
    let c = ecolor::Color32::from_hex(&format!("#{t}")).ok()?;
    Some([c.r(), c.g(), c.b()])
}

/// sRGB bytes as `#rrggbb` (ecolor's `to_hex` without its alpha).
pub fn hex_of([r, g, b]: [u8; 3]) -> String {
    let mut hex = ecolor::Color32::from_rgb(r, g, b).to_hex();
    hex.truncate(7);
    hex
}

#[cfg(test)]
mod tests {
    use super::*;

    /// IEC 61966-2-1's own numbers, computed here in f64 from the
    /// standard's equations (not from ecolor): code 128 decodes to
    /// ((128/255 + 0.055)/1.055)^2.4 = 0.215861; the toe is linear
    /// (10/255/12.92); 18 % grey encodes to code 118.
    #[test]
    fn the_pair_gives_the_standards_values() {
        let decode = |c: f64| {
            if c <= 0.04045 {
                c / 12.92
            } else {
                ((c + 0.055) / 1.055).powf(2.4)
            }
        };
        for code in 0..=255u8 {
            let want = decode(f64::from(code) / 255.0);
            let got = f64::from(srgb8_to_linear(code));
            assert!(
                (got - want).abs() < 2e-6,
                "code {code}: {got} against {want}"
            );
            assert!(
                (f64::from(srgb_to_linear(f32::from(code) / 255.0)) - want).abs() < 2e-6,
                "code {code}"
            );
            // Every code survives the round trip.
            assert_eq!(linear_to_srgb8(srgb8_to_linear(code)), code);
        }
        assert!((f64::from(srgb8_to_linear(128)) - 0.215_861).abs() < 1e-6);
        assert_eq!(linear_to_srgb8(0.18), 118);
        assert_eq!(linear_to_srgb8(-1.0), 0);
        assert_eq!(linear_to_srgb8(2.0), 255);
        assert!((linear_to_srgb(0.5) - 0.735_357).abs() < 1e-5);
        // The f64 pair: inverse of each other, and equal to the f32 pair.
        for i in 0..=1000 {
            let l = f64::from(i) / 1000.0;
            assert!((srgb_to_linear_f64(linear_to_srgb_f64(l)) - l).abs() < 1e-12);
            assert!((linear_to_srgb_f64(l) - f64::from(linear_to_srgb(l as f32))).abs() < 1e-6);
        }
    }
    /// The hexcone HSV (Smith 1978) of the primaries and a mid grey, and
    /// back: red 0°, green 120°, blue 240°, each S = V = 1; grey S = 0
    /// (ecolor works in f32: within 1e-5).
    #[test]
    fn hsv_of_known_colours_and_back() {
        for (rgb, hsv) in [
            ([1.0, 0.0, 0.0], [0.0, 1.0, 1.0]),
            ([0.0, 1.0, 0.0], [120.0, 1.0, 1.0]),
            ([0.0, 0.0, 1.0], [240.0, 1.0, 1.0]),
            ([1.0, 1.0, 0.0], [60.0, 1.0, 1.0]),
            ([0.5, 0.5, 0.5], [0.0, 0.0, 0.5]),
            ([0.8, 0.4, 0.6], [330.0, 0.5, 0.8]),
        ] {
            let got = hsv_of(rgb);
            for c in 0..3 {
                assert!((got[c] - hsv[c]).abs() < 1e-4, "{rgb:?}: {got:?}");
            }
            let back = rgb_of_hsv(got);
            for c in 0..3 {
                assert!((back[c] - rgb[c]).abs() < 1e-5, "{rgb:?}: {back:?}");
            }
        }
    }

    #[test]
    fn hex_parses_as_artists_type_it_and_prints_back() {
        assert_eq!(parse_hex("#f59d8e"), Some([0xf5, 0x9d, 0x8e]));
        assert_eq!(parse_hex("F59D8E"), Some([0xf5, 0x9d, 0x8e]));
        assert_eq!(parse_hex(" #fa0 "), Some([0xff, 0xaa, 0x00]));
        assert_eq!(parse_hex("#f59d8"), None);
        assert_eq!(parse_hex("#zz9d8e"), None);
        assert_eq!(parse_hex("#f59d8eff"), None);
        assert_eq!(hex_of([0xf5, 0x9d, 0x8e]), "#f59d8e");
        assert_eq!(hex_of([0, 10, 255]), "#000aff");
    }
}
