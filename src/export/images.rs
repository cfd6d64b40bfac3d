//! Table and profile images: PNG (with gAMA and tEXt chunks that state the
//! encoding) and float OpenEXR (the encoding in a header attribute).

use super::{write, ExportError, Provenance};
use crate::model::lut::{bake_shadow, Lut, LutEncoding, LutLayout, ShadowLayout};
use crate::model::{RadialProfile, Rgb, DEFAULT_ENERGY_FRACTION};
use crate::settings::Preset;
use std::path::Path;

/// The exported pre-integrated table: 256² texels, N·L from −1 to 1 across,
/// 1/c from 1/100 to 1/1 mm⁻¹ down (FaceWorks' layout).
pub const LUT_LAYOUT: LutLayout = LutLayout {
    width: 256,
    height: 256,
    curvature_radius_min_mm: 1.0,
    curvature_radius_max_mm: 100.0,
};

/// The exported shadow table (Penner's penumbra table).
pub const SHADOW_LAYOUT: ShadowLayout = ShadowLayout {
    width: 64,
    height: 64,
    penumbra_min_mm: 1.0,
    penumbra_max_mm: 100.0,
};

/// Texels of the 1D r·R(r) texture.
pub const PROFILE_TEXELS: usize = 256;
/// Texels of the transmittance strip.
pub const TRANSMITTANCE_TEXELS: usize = 64;

/// PNG bytes of 8- or 16-bit RGB `data` (big-endian for 16 bit), marked
/// linear (gAMA 1.0) with `Description` and `Software` text chunks.
fn png_bytes(
    path: &Path,
    (w, h): (usize, usize),
    sixteen: bool,
    data: &[u8],
    description: &str,
) -> Result<Vec<u8>, ExportError> {
    let err = |e: png::EncodingError| ExportError::Encode {
        path: path.to_owned(),
        message: e.to_string(),
    };
    let mut buf = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut buf, w as u32, h as u32);
        enc.set_color(png::ColorType::Rgb);
        enc.set_depth(if sixteen {
            png::BitDepth::Sixteen
        } else {
            png::BitDepth::Eight
        });
        // Linear values: gAMA of 1.0 so viewers do not treat them as sRGB.
        enc.set_source_gamma(png::ScaledFloat::new(1.0));
        enc.add_text_chunk("Description".into(), description.into())
            .map_err(err)?;
        enc.add_text_chunk(
            "Software".into(),
            format!("scatterlab {}", env!("CARGO_PKG_VERSION")),
        )
        .map_err(err)?;
        let mut writer = enc.write_header().map_err(err)?;
        writer.write_image_data(data).map_err(err)?;
        writer.finish().map_err(err)?;
    }
    Ok(buf)
}

/// Float RGB OpenEXR bytes (row-major, y down) with the description in the
/// image's `comments` attribute.
fn exr_bytes(
    path: &Path,
    (w, h): (usize, usize),
    pixels: &[Rgb],
    description: &str,
) -> Result<Vec<u8>, ExportError> {
    use exr::prelude::*;
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let p = pixels[y * w + x];
        (p[0] as f32, p[1] as f32, p[2] as f32)
    });
    let mut attributes = LayerAttributes::named("scatterlab");
    attributes.comments = Some(Text::from(description));
    attributes.software_name = Some(Text::from(
        format!("scatterlab {}", env!("CARGO_PKG_VERSION")).as_str(),
    ));
    let layer = Layer::new((w, h), attributes, Encoding::FAST_LOSSLESS, channels);
    let image = Image::from_layer(layer);
    let mut cursor = std::io::Cursor::new(Vec::new());
    image
        .write()
        .to_buffered(&mut cursor)
        .map_err(|e| ExportError::Encode {
            path: path.to_owned(),
            message: e.to_string(),
        })?;
    Ok(cursor.into_inner())
}

/// Float RGBA OpenEXR bytes (row-major, y down; alpha as given, colour
/// premultiplied by it as OpenEXR keeps colour) with `description` in the
/// `comments` attribute: the editor's stills.
pub fn rgba_exr_bytes(
    (w, h): (u32, u32),
    pixels: &[[f32; 4]],
    description: &str,
) -> Result<Vec<u8>, String> {
    use exr::prelude::*;
    let w = w as usize;
    let channels = SpecificChannels::rgba(|Vec2(x, y): Vec2<usize>| {
        let p = pixels[y * w + x];
        (p[0], p[1], p[2], p[3])
    });
    let mut attributes = LayerAttributes::named("");
    attributes.comments = Some(Text::from(description));
    attributes.software_name = Some(Text::from(
        format!("scatterlab {}", env!("CARGO_PKG_VERSION")).as_str(),
    ));
    let layer = Layer::new(
        (w, h as usize),
        attributes,
        Encoding::FAST_LOSSLESS,
        channels,
    );
    let mut cursor = std::io::Cursor::new(Vec::new());
    Image::from_layer(layer)
        .write()
        .to_buffered(&mut cursor)
        .map_err(|e| format!("OpenEXR: {e}"))?;
    Ok(cursor.into_inner())
}

fn write_image(
    path: &Path,
    size: (usize, usize),
    pixels: &[Rgb],
    exr: bool,
    png_encode: impl Fn(f64) -> u8,
    description: &str,
) -> Result<(), ExportError> {
    let bytes = if exr {
        exr_bytes(path, size, pixels, description)?
    } else {
        let data: Vec<u8> = pixels.iter().flat_map(|p| p.map(&png_encode)).collect();
        png_bytes(path, size, false, &data, description)?
    };
    write(path, &bytes)
}

/// Penner's pre-integrated table D(N·L, 1/c) and the shadow-penumbra
/// table. PNG: D is FaceWorks' delta encoding 2(D − sat(N·L)) + ½ (8-bit
/// linear), the shadow table linear; EXR: both linear floats.
pub fn write_luts(
    preset: &Preset,
    prov: &Provenance,
    exr: bool,
    out: &Path,
    shadow_out: &Path,
) -> Result<(), ExportError> {
    let profile = preset.build_profile()?;
    let lut = Lut::bake(profile.as_ref(), LUT_LAYOUT)?;
    let shadow = bake_shadow(profile.as_ref(), SHADOW_LAYOUT)?;
    let l = LUT_LAYOUT;
    let axes = format!(
        "x: N.L from -1 to 1 at texel centres; y: 1/curvature radius from 1/{} to 1/{} per mm, top to bottom",
        l.curvature_radius_max_mm, l.curvature_radius_min_mm
    );
    if exr {
        write_image(
            out,
            (l.width, l.height),
            &lut.d,
            true,
            |_| 0,
            &format!(
                "Pre-integrated skin D (Penner 2011), linear, not delta-encoded. {axes}. {}",
                prov.line()
            ),
        )?;
    } else {
        // Delta encoding needs each texel's N·L, so encode here.
        let data = lut.to_rgb8(LutEncoding::FaceWorksDelta);
        let bytes = png_bytes(
            out,
            (l.width, l.height),
            false,
            &data,
            &format!(
                "Pre-integrated skin D (Penner 2011), linear 8-bit, delta-encoded as FaceWorks: value = 2(D - saturate(N.L)) + 0.5, so D = (value - 0.5)/2 + saturate(N.L). {axes}. {}",
                prov.line()
            ),
        )?;
        write(out, &bytes)?;
    }
    let s = SHADOW_LAYOUT;
    write_image(
        shadow_out,
        (s.width, s.height),
        &shadow,
        exr,
        |v| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u8,
        &format!(
            "Penumbra table (Penner 2011), linear, not delta-encoded: x = unscattered shadow value at texel centres, y = 1/penumbra width from 1/{} to 1/{} per mm. {}",
            s.penumbra_max_mm, s.penumbra_min_mm, prov.line()
        ),
    )
}

/// r·R(r) sampled at texel centres r_i = (i + ½)/N · r_max, and the
/// thin-slab transmittance T(d) at d_i = (i + ½)/M · d_max.
pub fn profile_texels(profile: &dyn RadialProfile, d_max_mm: f64) -> (f64, Vec<Rgb>, Vec<Rgb>) {
    let r_max = profile
        .radius_for_energy(DEFAULT_ENERGY_FRACTION)
        .into_iter()
        .fold(1e-6, f64::max);
    let rr = (0..PROFILE_TEXELS)
        .map(|i| profile.r_reflectance((i as f64 + 0.5) / PROFILE_TEXELS as f64 * r_max))
        .collect();
    let t = (0..TRANSMITTANCE_TEXELS)
        .map(|i| profile.transmittance((i as f64 + 0.5) / TRANSMITTANCE_TEXELS as f64 * d_max_mm))
        .collect();
    (r_max, rr, t)
}

/// The 1D profile texture and the transmittance strip (N×1 each). EXR:
/// r·R(r) in 1/mm and T(d) as floats. PNG: 16-bit linear, r·R(r) divided
/// by its maximum (stated in the text chunk), T(d) as is (it is ≤ 1).
pub fn write_profile(
    preset: &Preset,
    prov: &Provenance,
    exr: bool,
    out: &Path,
    strip_out: &Path,
) -> Result<(), ExportError> {
    let profile = preset.build_profile()?;
    let d_max = preset.rendering.thickness_remap_mm.1.max(1e-3);
    let (r_max, rr, t) = profile_texels(profile.as_ref(), d_max);
    let peak = rr
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(*v))
        .max(1e-30);
    let layout = format!(
        "texel i of {PROFILE_TEXELS} holds r = (i + 0.5)/{PROFILE_TEXELS} * {r_max} mm (the 0.997-energy radius)"
    );
    let strip_layout = format!(
        "texel i of {TRANSMITTANCE_TEXELS} holds thickness d = (i + 0.5)/{TRANSMITTANCE_TEXELS} * {d_max} mm"
    );
    if exr {
        exr_image(
            out,
            &rr,
            &format!(
                "r*R(r) per channel in 1/mm, linear float; {layout}. {}",
                prov.line()
            ),
        )?;
        exr_image(
            strip_out,
            &t,
            &format!(
                "Thin-slab transmittance T(d), linear float; {strip_layout}. {}",
                prov.line()
            ),
        )?;
    } else {
        png16(out, &rr, 1.0 / peak, &format!("r*R(r) per channel, linear 16-bit, divided by its maximum {peak} 1/mm (value = r*R(r)/{peak}); {layout}. {}", prov.line()))?;
        png16(
            strip_out,
            &t,
            1.0,
            &format!(
                "Thin-slab transmittance T(d), linear 16-bit, not normalised; {strip_layout}. {}",
                prov.line()
            ),
        )?;
    }
    Ok(())
}

fn exr_image(path: &Path, row: &[Rgb], description: &str) -> Result<(), ExportError> {
    let bytes = exr_bytes(path, (row.len(), 1), row, description)?;
    write(path, &bytes)
}

fn png16(path: &Path, row: &[Rgb], scale: f64, description: &str) -> Result<(), ExportError> {
    let data: Vec<u8> = row
        .iter()
        .flat_map(|p| {
            p.map(|v| ((v * scale).clamp(0.0, 1.0) * 65535.0 + 0.5) as u16)
                .into_iter()
                .flat_map(u16::to_be_bytes)
        })
        .collect();
    let bytes = png_bytes(path, (row.len(), 1), true, &data, description)?;
    write(path, &bytes)
}

/// An image target: the tables (with the shadow table beside them) or the
/// profile texture (with the transmittance strip), PNG or EXR.
macro_rules! image_target {
    ($id:literal, $name:literal, $desc:literal, $ext:literal, $suffix:literal, $slow:literal, $writer:ident, $exr:literal) => {
        super::Target {
            id: $id,
            name: $name,
            description: $desc,
            extension: $ext,
            companion: Some(|out| super::companion(out, $suffix, $ext)),
            slow: $slow,
            write: |preset, prov, out, second, _| $writer(preset, prov, $exr, out, second),
            notes: super::no_notes,
            fidelity: super::no_fidelity,
            params: None,
            reader: None,
        }
    };
}

pub(super) const LUT_PNG: super::Target = image_target!(
    "lut-png",
    "Pre-integrated tables (PNG)",
    "pre-integrated and shadow tables, 8-bit (takes a few seconds)",
    "png",
    "_shadow",
    true,
    write_luts,
    false
);
pub(super) const LUT_EXR: super::Target = image_target!(
    "lut-exr",
    "Pre-integrated tables (OpenEXR)",
    "pre-integrated and shadow tables, float (takes a few seconds)",
    "exr",
    "_shadow",
    true,
    write_luts,
    true
);
pub(super) const PROFILE_EXR: super::Target = image_target!(
    "profile-exr",
    "Profile texture (OpenEXR)",
    "r·R(r) as a 1D float texture, and the transmittance strip",
    "exr",
    "_transmittance",
    false,
    write_profile,
    true
);
pub(super) const PROFILE_PNG: super::Target = image_target!(
    "profile-png",
    "Profile texture (PNG)",
    "r·R(r) as a 16-bit texture, and the transmittance strip",
    "png",
    "_transmittance",
    false,
    write_profile,
    false
);
