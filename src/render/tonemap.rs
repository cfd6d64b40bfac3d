//! Display transforms from exposed scene-linear Rec. 709 to display-linear
//! values the sRGB output target encodes (`shaders/composite.wgsl`,
//! `tone_map`). These are the CPU twins of the shader's functions, each
//! checked against its source below; `tests/render.rs` checks that the
//! GPU draws what they compute.
// The constants are kept digit for digit as their sources print them.
#![allow(clippy::excessive_precision)]

/// Which curve maps exposed scene light to the display.
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Hash,
    Default,
    serde::Serialize,
    serde::Deserialize,
    clap::ValueEnum,
)]
pub enum ToneMap {
    /// Narkowicz's 2015 fit of ACES' filmic curve, per channel (scatterlab's
    /// curve before there was a choice).
    #[default]
    AcesFit,
    /// Hill's fit of the ACES 1.0 RRT and sRGB ODT (BakingLab's ACES.hlsl):
    /// the AP1 round trip desaturates highlights as ACES does.
    Aces,
    /// Sobotka's AgX (Blender 4's default view), through Wrensch's 2024
    /// minimal fit of its base contrast.
    Agx,
    /// Khronos PBR Neutral (2024): colours under 0.76 untouched but for a
    /// small offset, so a product's base colour reads as authored.
    PbrNeutral,
}

impl ToneMap {
    pub const ALL: [ToneMap; 4] = [
        ToneMap::AcesFit,
        ToneMap::Aces,
        ToneMap::Agx,
        ToneMap::PbrNeutral,
    ];

    pub fn label(self) -> &'static str {
        match self {
            ToneMap::AcesFit => "ACES fit (Narkowicz)",
            ToneMap::Aces => "ACES (Hill RRT+ODT)",
            ToneMap::Agx => "AgX",
            ToneMap::PbrNeutral => "Khronos PBR Neutral",
        }
    }

    /// `TONE_*` in `shaders/composite.wgsl`.
    pub fn shader_id(self) -> u32 {
        match self {
            ToneMap::AcesFit => TONE_ACES_FIT,
            ToneMap::Aces => TONE_ACES,
            ToneMap::Agx => TONE_AGX,
            ToneMap::PbrNeutral => TONE_PBR_NEUTRAL,
        }
    }

    /// The display-linear colour (in [0, 1], before sRGB encoding) of the
    /// exposed scene-linear colour `c`.
    pub fn apply(self, c: [f32; 3]) -> [f32; 3] {
        let c = c.map(|v| v.max(0.0));
        let out = match self {
            ToneMap::AcesFit => c.map(aces_fit),
            ToneMap::Aces => aces_hill(c),
            ToneMap::Agx => agx(c),
            ToneMap::PbrNeutral => pbr_neutral(c),
        };
        out.map(|v| v.clamp(0.0, 1.0))
    }
}

/// `TONE_*` in `shaders/composite.wgsl`.
pub const TONE_ACES_FIT: u32 = 0;
pub const TONE_ACES: u32 = 1;
pub const TONE_AGX: u32 = 2;
pub const TONE_PBR_NEUTRAL: u32 = 3;

/// Narkowicz 2015, "ACES Filmic Tone Mapping Curve":
/// x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14).
fn aces_fit(x: f32) -> f32 {
    (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14)
}

/// `m` (rows) times `v`.
fn mul(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    m.map(|r| r[0] * v[0] + r[1] * v[1] + r[2] * v[2])
}

/// Hill's ACES fit (MJP & Neubelt, BakingLab `ACES.hlsl`, MIT): sRGB → AP1
/// with the RRT's saturation, the RRT+ODT rational fit per channel, back
/// with the ODT's saturation. Each matrix's rows sum to 1, so a grey stays
/// grey.
fn aces_hill(c: [f32; 3]) -> [f32; 3] {
    const INPUT: [[f32; 3]; 3] = [
        [0.59719, 0.35458, 0.04823],
        [0.07600, 0.90834, 0.01566],
        [0.02840, 0.13383, 0.83777],
    ];
    const OUTPUT: [[f32; 3]; 3] = [
        [1.60475, -0.53108, -0.07367],
        [-0.10208, 1.10813, -0.00605],
        [-0.00327, -0.07276, 1.07602],
    ];
    let v = mul(&INPUT, c).map(|v| {
        let a = v * (v + 0.0245786) - 0.000090537;
        let b = v * (0.983729 * v + 0.4329510) + 0.238081;
        a / b
    });
    mul(&OUTPUT, v)
}

/// AgX's log encoding: log2 exposure from −12.47393 to +4.026069 stops
/// around 0.18 (Sobotka's AgX OCIO config; Wrensch 2024).
pub const AGX_MIN_EV: f32 = -12.47393;
pub const AGX_MAX_EV: f32 = 4.026069;

/// Sobotka's AgX through Wrensch's 2024 minimal implementation
/// (iolite-engine.com, "Minimal AgX implementation", MIT): the inset
/// matrix, log2 encoding over [`AGX_MIN_EV`, `AGX_MAX_EV`], the 6th-order
/// fit of the default contrast curve (display-encoded, mean squared error
/// 3.7e-6), the outset matrix, then decoded by sRGB's curve so that the
/// sRGB target writes the curve's value.
fn agx(c: [f32; 3]) -> [f32; 3] {
    // The inset matrix, as rows (Wrensch's GLSL lists it by columns).
    const INSET: [[f32; 3]; 3] = [
        [0.842479062253094, 0.0784335999999992, 0.0792237451477643],
        [0.0423282422610123, 0.878468636469772, 0.0791661274605434],
        [0.0423756549057051, 0.0784336, 0.879142973793104],
    ];
    const OUTSET: [[f32; 3]; 3] = [
        [1.19687900512017, -0.0980208811401368, -0.0990297440797205],
        [-0.0528968517574562, 1.15190312990417, -0.0989611768448433],
        [-0.0529716355144438, -0.0980434501171241, 1.15107367264116],
    ];
    let v = mul(&INSET, c).map(|v| {
        let e = v.max(1e-10).log2().clamp(AGX_MIN_EV, AGX_MAX_EV);
        agx_contrast((e - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV))
    });
    mul(&OUTSET, v).map(|v| super::environment::srgb_to_linear(v.clamp(0.0, 1.0)))
}

/// Wrensch's 6th-order polynomial of AgX's default contrast curve.
pub fn agx_contrast(x: f32) -> f32 {
    let x2 = x * x;
    let x4 = x2 * x2;
    15.5 * x4 * x2 - 40.14 * x4 * x + 31.96 * x4 - 6.868 * x2 * x + 0.4298 * x2 + 0.1191 * x
        - 0.00232
}

/// Khronos PBR Neutral, by its specification (KhronosGroup/ToneMapping,
/// `PBR_Neutral/README.md`): F90 = 0.04, Ks = 0.8 − F90, Kd = 0.15;
/// f = x − x²/(4·F90) for x = min(R,G,B) ≤ 2·F90, else F90; p = max(c − f);
/// above Ks the peak is compressed to pn = 1 − (1 − Ks)²/(p + 1 − 2Ks) and
/// the colour mixed towards [pn, pn, pn] by 1 − g, g = 1/(Kd(p − pn) + 1).
/// (A copy of the repository's `pbrNeutral.glsl` found while writing
/// this mixes towards white instead of [pn, pn, pn]; the README's
/// equation is followed here, as three.js and Filament do.)
fn pbr_neutral(c: [f32; 3]) -> [f32; 3] {
    const F90: f32 = 0.04;
    const KS: f32 = 0.8 - F90;
    const KD: f32 = 0.15;
    let x = c[0].min(c[1]).min(c[2]);
    let f = if x <= 2.0 * F90 {
        x - x * x / (4.0 * F90)
    } else {
        F90
    };
    let c = c.map(|v| v - f);
    let p = c[0].max(c[1]).max(c[2]);
    if p <= KS {
        return c;
    }
    let pn = 1.0 - (1.0 - KS) * (1.0 - KS) / (p + 1.0 - 2.0 * KS);
    let g = 1.0 / (KD * (p - pn) + 1.0);
    c.map(|v| v * pn / p * g + pn * (1.0 - g))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// AgX maps scene grey 0.18 to display 0.18^(1/2.4) = 0.4894: the
    /// pivot of EaryChow's AgX (Blender's), `y_pivot` in allenwp's
    /// AgX-GLSL-Shaders. Wrensch's curve is a fit, so within 0.01; 0.18
    /// sits at (log2 0.18 + 12.47393)/16.5 = 0.6061 of the log range
    /// (`x_pivot` there).
    #[test]
    fn agx_puts_grey_at_blenders_pivot() {
        let x = (0.18f32.log2() - AGX_MIN_EV) / (AGX_MAX_EV - AGX_MIN_EV);
        assert!((x - 0.60606).abs() < 1e-3, "{x}");
        let y = agx_contrast(x);
        assert!((y - 0.18f32.powf(1.0 / 2.4)).abs() < 0.01, "{y}");
        let out = ToneMap::Agx.apply([0.18; 3]);
        let encoded = ((out[0].powf(1.0 / 2.4)) * 1.055) - 0.055;
        assert!((encoded - 0.4894).abs() < 0.012, "{out:?}");
        // Grey stays grey.
        assert!((out[0] - out[1]).abs() < 1e-3 && (out[1] - out[2]).abs() < 1e-3);
    }

    /// PBR Neutral by the README's cases: under Ks a colour only loses the
    /// offset f (0.04 for min > 0.08; x − x²/0.16 below), and above it the
    /// peak goes to pn; the result stays within [0, 1] and is continuous
    /// at p = Ks.
    #[test]
    fn pbr_neutral_follows_its_specification() {
        let c = [0.5, 0.3, 0.1];
        let out = ToneMap::PbrNeutral.apply(c);
        for k in 0..3 {
            assert!((out[k] - (c[k] - 0.04)).abs() < 1e-6, "{out:?}");
        }
        let dark = ToneMap::PbrNeutral.apply([0.05, 0.2, 0.3]);
        let f = 0.05 - 0.05 * 0.05 / 0.16;
        assert!((dark[1] - (0.2 - f)).abs() < 1e-6, "{dark:?}");
        // Continuity at the knee (peak p = Ks = 0.76 after the offset).
        let below = ToneMap::PbrNeutral.apply([0.7999, 0.5, 0.5]);
        let above = ToneMap::PbrNeutral.apply([0.8001, 0.5, 0.5]);
        assert!((below[0] - above[0]).abs() < 1e-3);
        // A bright grey's peak: pn = 1 − 0.24²/(p + 1 − 1.52), p = 9.96.
        let grey = ToneMap::PbrNeutral.apply([10.0; 3]);
        let pn = 1.0 - 0.24 * 0.24 / (9.96 + 1.0 - 1.52);
        assert!((grey[0] - pn).abs() < 1e-5, "{grey:?} against {pn}");
    }

    /// Hill's ACES keeps greys grey (each matrix's rows sum to 1), is
    /// monotonic, black stays black and bright light reaches white.
    #[test]
    fn hill_aces_keeps_greys_and_rises() {
        let mut last = -1.0;
        for i in 0..200 {
            let x = 0.001 * 1.06f32.powi(i);
            let o = ToneMap::Aces.apply([x; 3]);
            assert!(
                (o[0] - o[1]).abs() < 2e-3 && (o[1] - o[2]).abs() < 2e-3,
                "{x}: {o:?}"
            );
            assert!(o[0] >= last, "not monotonic at {x}");
            last = o[0];
        }
        assert_eq!(ToneMap::Aces.apply([0.0; 3]), [0.0; 3]);
        assert!(ToneMap::Aces.apply([100.0; 3])[0] > 0.99);
        // Narkowicz's fit: 0 → 0, and its limit 2.51/2.43 > 1 clamps to 1.
        assert_eq!(ToneMap::AcesFit.apply([0.0; 3]), [0.0; 3]);
        assert_eq!(ToneMap::AcesFit.apply([1e4; 3]), [1.0; 3]);
    }
}
