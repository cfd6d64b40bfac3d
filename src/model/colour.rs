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
}
