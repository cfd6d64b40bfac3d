//! Surface textures: albedo, tangent-space normal, roughness, SSS mask and
//! thickness. Each comes from the mesh file, the command line, or (for the
//! default head) the deterministic bake in `procedural.rs`; a missing one
//! is a 1×1 neutral texture, so the shader always samples all five.

use std::path::Path;

/// How the shader reads the albedo texture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AlbedoMode {
    /// Linear value × 2 multiplies the preset's skin albedo (the default
    /// head's variation map: 0.5 leaves the preset's colour unchanged).
    Modulate,
    /// The texture is the albedo (sRGB), as a scan's colour map is.
    Absolute,
}

pub use crate::settings::albedo::MapColour;

/// The mean linear colour of a colour map over its used texels (alpha
/// over ½ and not black: a scan's unused atlas space is black or
/// transparent), per channel; `None` when no texel is used.
pub fn albedo_map_mean(map: &TextureImage) -> Option<[f32; 3]> {
    if map.channels != 4 {
        return None;
    }
    let lut: Vec<f64> = (0..=255u8)
        .map(|v| super::compare::srgb_to_linear(v) as f64)
        .collect();
    let mut sum = [0.0f64; 3];
    let mut n = 0u64;
    for t in map.texels.chunks_exact(4) {
        if t[3] < 128 || (t[0] | t[1] | t[2]) < 3 {
            continue;
        }
        for c in 0..3 {
            sum[c] += lut[t[c] as usize];
        }
        n += 1;
    }
    (n > 0).then(|| sum.map(|s| (s / n as f64) as f32))
}

/// How the shader reads the roughness texture.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RoughnessMode {
    /// Value × 2 scales the settings' roughness (0.5 leaves it unchanged).
    Scale,
    /// The texture is the roughness of the first lobe.
    Absolute,
}

/// One texture's texels, top-left origin, with `channels` bytes per texel.
#[derive(Debug, Clone, PartialEq)]
pub struct TextureImage {
    pub width: u32,
    pub height: u32,
    /// 4 (RGBA) or 1 (a single channel).
    pub channels: u32,
    pub texels: Vec<u8>,
}

impl TextureImage {
    /// Mirrors the rows: sampling the result at v is sampling the original
    /// at 1 − v, for maps made with V pointing up (OpenGL's bottom-left
    /// origin, as some scanners and bakers write them) on a mesh whose UVs
    /// follow glTF's top-left origin, or the other way round.
    pub fn flip_v(&mut self) {
        let row = (self.width * self.channels) as usize;
        if row == 0 {
            return;
        }
        let rows: Vec<&[u8]> = self.texels.chunks(row).rev().collect();
        self.texels = rows.concat();
    }

    /// A 1×1 texture of one value.
    pub fn solid(value: &[u8]) -> Self {
        Self {
            width: 1,
            height: 1,
            channels: value.len() as u32,
            texels: value.to_vec(),
        }
    }

    /// The next mip level: 2×2 box filter (odd edges clamp).
    pub fn half(&self) -> Self {
        let (w, h, c) = (
            (self.width / 2).max(1),
            (self.height / 2).max(1),
            self.channels as usize,
        );
        let at = |x: u32, y: u32, k: usize| {
            let (x, y) = (x.min(self.width - 1), y.min(self.height - 1));
            self.texels[(y * self.width + x) as usize * c + k] as u32
        };
        let mut texels = Vec::with_capacity((w * h) as usize * c);
        for y in 0..h {
            for x in 0..w {
                for k in 0..c {
                    let s = at(2 * x, 2 * y, k)
                        + at(2 * x + 1, 2 * y, k)
                        + at(2 * x, 2 * y + 1, k)
                        + at(2 * x + 1, 2 * y + 1, k);
                    texels.push(((s + 2) / 4) as u8);
                }
            }
        }
        Self {
            width: w,
            height: h,
            channels: self.channels,
            texels,
        }
    }

    /// This image and its mip chain down to 1×1.
    pub fn mip_chain(&self) -> Vec<TextureImage> {
        let mut chain = vec![self.clone()];
        while let Some(last) = chain.last().filter(|m| m.width > 1 || m.height > 1) {
            let next = last.half();
            chain.push(next);
        }
        chain
    }
}

/// The five textures of a mesh and how to read them.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshTextures {
    pub albedo: TextureImage,
    pub albedo_mode: AlbedoMode,
    /// Tangent-space normal, OpenGL convention (green = +v, up in the image).
    pub normal: TextureImage,
    pub roughness: TextureImage,
    pub roughness_mode: RoughnessMode,
    /// SSS mask: 0 keeps a texel out of every SSS pass.
    pub mask: TextureImage,
    /// Thickness for transmission: value × `thickness_range_mm`; `None`
    /// uses the per-vertex ray-cast bake.
    pub thickness: Option<(TextureImage, f32)>,
}

impl Default for MeshTextures {
    /// Neutral: the preset's albedo and roughness, a flat normal, all skin.
    fn default() -> Self {
        Self {
            albedo: TextureImage::solid(&[188, 188, 188, 255]),
            albedo_mode: AlbedoMode::Modulate,
            normal: TextureImage::solid(&[128, 128, 255, 255]),
            roughness: TextureImage::solid(&[128]),
            roughness_mode: RoughnessMode::Scale,
            mask: TextureImage::solid(&[255]),
            thickness: None,
        }
    }
}

/// Which texture a file is for (names it in errors).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureSlot {
    Albedo,
    Normal,
    Roughness,
    Mask,
    Thickness,
}

impl TextureSlot {
    pub fn name(self) -> &'static str {
        match self {
            TextureSlot::Albedo => "albedo",
            TextureSlot::Normal => "normal",
            TextureSlot::Roughness => "roughness",
            TextureSlot::Mask => "mask",
            TextureSlot::Thickness => "thickness",
        }
    }

    fn channels(self) -> u32 {
        match self {
            TextureSlot::Albedo | TextureSlot::Normal => 4,
            _ => 1,
        }
    }
}

#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    #[error("{path}: cannot read the {slot} texture: {message}")]
    Load {
        path: String,
        slot: &'static str,
        message: String,
    },
    #[error(
        "{path}: the {slot} texture is {width}×{height}; textures must be 1–16384 texels a side"
    )]
    Size {
        path: String,
        slot: &'static str,
        width: u32,
        height: u32,
    },
}

/// Converts a decoded image into the slot's layout (RGBA, or the first
/// channel of a grey image / the luminance-free red channel otherwise).
pub fn from_dynamic(
    img: image::DynamicImage,
    slot: TextureSlot,
    origin: &str,
) -> Result<TextureImage, TextureError> {
    let (width, height) = (img.width(), img.height());
    if width == 0 || height == 0 || width > 16384 || height > 16384 {
        return Err(TextureError::Size {
            path: origin.into(),
            slot: slot.name(),
            width,
            height,
        });
    }
    let texels = if slot.channels() == 4 {
        img.to_rgba8().into_raw()
    } else {
        // Grey maps: the first channel (grey, or red of an RGB export).
        img.to_rgba8().pixels().map(|p| p.0[0]).collect()
    };
    Ok(TextureImage {
        width,
        height,
        channels: slot.channels(),
        texels,
    })
}

/// Why an image file was not decoded ([`decode_bounded`]); its callers
/// add the file and what it was for.
#[derive(Debug, thiserror::Error)]
pub enum DecodeError {
    #[error("{0}")]
    Read(#[from] std::io::Error),
    /// Shorter than any image format's signature ("0 bytes: the file is
    /// empty").
    #[error("{0}")]
    TooShort(String),
    #[error("{width}×{height} is over the limit of {MAX_SIDE} pixels a side")]
    TooWide { width: u32, height: u32 },
    #[error("{width}×{height} is over the 64-megapixel limit")]
    TooLarge { width: u32, height: u32 },
    /// The pixels stop before the image its header names is complete (a
    /// download cut short): said in the file's terms, not the I/O call's
    /// ("failed to fill whole buffer").
    #[error("ends early: its {len} bytes stop before the {width}×{height} pixels its header names are all there (cut short: download or copy it again)")]
    EndsEarly { len: u64, width: u32, height: u32 },
    #[error("{0}")]
    Image(#[from] image::ImageError),
}

/// The most pixels a side [`decode_bounded`] takes.
pub const MAX_SIDE: u32 = 16384;

/// Decodes an image file with bounded memory: at most 16384 pixels a side
/// and 512 MiB per allocation (the image crate refuses more), and at most
/// 64 megapixels, so later conversions (RGBA8, RGB32F) stay bounded too. A
/// header claiming a huge image ran the fuzzer out of memory.
pub fn decode_bounded(path: &Path) -> Result<image::DynamicImage, DecodeError> {
    const MAX_PIXELS: u64 = 64 << 20;
    let len = crate::fsutil::file_len(path)?;
    // Shorter than any image format's signature (PNG's is 8 bytes).
    if let Some(problem) = crate::fsutil::too_short(len, 8, "an image") {
        return Err(DecodeError::TooShort(problem));
    }
    // The header's size first (no pixel decoded), said in numbers when it
    // is over a limit (the image crate says only "Image size exceeds
    // limit").
    let reader = image::ImageReader::open(path)?.with_guessed_format()?;
    let (width, height) = reader.into_dimensions()?;
    if width > MAX_SIDE || height > MAX_SIDE {
        return Err(DecodeError::TooWide { width, height });
    }
    if width as u64 * height as u64 > MAX_PIXELS {
        return Err(DecodeError::TooLarge { width, height });
    }
    let mut reader = image::ImageReader::open(path)?.with_guessed_format()?;
    reader.limits(bounded_limits());
    reader.decode().map_err(|e| match e {
        image::ImageError::IoError(io) if io.kind() == std::io::ErrorKind::UnexpectedEof => {
            DecodeError::EndsEarly { len, width, height }
        }
        e => e.into(),
    })
}

fn bounded_limits() -> image::Limits {
    let mut limits = image::Limits::default();
    limits.max_image_width = Some(MAX_SIDE);
    limits.max_image_height = Some(MAX_SIDE);
    limits.max_alloc = Some(512 << 20);
    limits
}

/// Loads an image file (PNG or JPEG) for `slot`.
pub fn load(path: &Path, slot: TextureSlot) -> Result<TextureImage, TextureError> {
    let origin = path.display().to_string();
    let img = decode_bounded(path).map_err(|e| TextureError::Load {
        path: origin.clone(),
        slot: slot.name(),
        message: e.to_string(),
    })?;
    from_dynamic(img, slot, &origin)
}

/// Uploads a texture with its mip chain.
#[cfg(feature = "gpu")]
pub(super) fn upload(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    img: &TextureImage,
    format: wgpu::TextureFormat,
    label: &'static str,
) -> wgpu::TextureView {
    let chain = img.mip_chain();
    let data: Vec<u8> = chain
        .iter()
        .flat_map(|m| m.texels.iter().copied())
        .collect();
    sampled_texture(
        device,
        queue,
        label,
        (img.width, img.height, chain.len() as u32),
        format,
        &data,
    )
}

/// A 2D texture for sampling, filled with `data` (every mip level in
/// turn, as wgpu's `LayerMajor` order reads it): `(width, height, mips)`.
#[cfg(feature = "gpu")]
pub(super) fn sampled_texture(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    (width, height, mip_level_count): (u32, u32, u32),
    format: wgpu::TextureFormat,
    data: &[u8],
) -> wgpu::TextureView {
    use wgpu::util::DeviceExt;
    device
        .create_texture_with_data(
            queue,
            &wgpu::TextureDescriptor {
                label: Some(label),
                size: wgpu::Extent3d {
                    width,
                    height,
                    depth_or_array_layers: 1,
                },
                mip_level_count,
                sample_count: 1,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage: wgpu::TextureUsages::TEXTURE_BINDING,
                view_formats: &[],
            },
            wgpu::util::TextureDataOrder::LayerMajor,
            data,
        )
        .create_view(&Default::default())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mip_chain_averages_and_ends_at_one_texel() {
        let img = TextureImage {
            width: 4,
            height: 2,
            channels: 1,
            texels: vec![0, 4, 8, 12, 4, 8, 12, 16],
        };
        let chain = img.mip_chain();
        let dims: Vec<_> = chain.iter().map(|m| (m.width, m.height)).collect();
        assert_eq!(dims, vec![(4, 2), (2, 1), (1, 1)]);
        // (0+4+4+8)/4 = 4, (8+12+12+16)/4 = 12, then (4+12)/2 = 8 (clamped edge).
        assert_eq!(chain[1].texels, vec![4, 12]);
        assert_eq!(chain[2].texels, vec![8]);
    }

    #[test]
    fn corrupt_image_names_the_file_and_slot() {
        let dir = std::env::temp_dir().join("scatterlab-texture-test");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("broken.png");
        std::fs::write(&path, b"\x89PNG\r\n\x1a\nnot really").unwrap();
        let e = load(&path, TextureSlot::Normal).unwrap_err().to_string();
        assert!(e.contains("broken.png") && e.contains("normal"), "{e}");
        let e = load(&dir.join("missing.png"), TextureSlot::Mask)
            .unwrap_err()
            .to_string();
        assert!(e.contains("missing.png") && e.contains("mask"), "{e}");
    }
}

#[cfg(test)]
mod flip_tests {
    use super::TextureImage;

    /// A 2×3 single-channel image: rows (1 2), (3 4), (5 6) become
    /// (5 6), (3 4), (1 2); twice is the identity.
    #[test]
    fn flip_v_mirrors_rows() {
        let mut t = TextureImage {
            width: 2,
            height: 3,
            channels: 1,
            texels: vec![1, 2, 3, 4, 5, 6],
        };
        t.flip_v();
        assert_eq!(t.texels, vec![5, 6, 3, 4, 1, 2]);
        t.flip_v();
        assert_eq!(t.texels, vec![1, 2, 3, 4, 5, 6]);
    }
}

/// One surface-map slot of a user mesh, as the artist set it: a file that
/// replaces the mesh's own map (`None` keeps the mesh's), whether its V
/// runs up (flipped on load), and whether its texels are sRGB-encoded.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[serde(default)]
pub struct MapSlot {
    pub path: Option<std::path::PathBuf>,
    pub flip_v: bool,
    /// Texels are sRGB-encoded (colour maps usually are; normal,
    /// roughness, mask and thickness maps usually are not).
    pub srgb: bool,
}

impl MapSlot {
    /// The usual encoding of a slot: sRGB for colour, linear for data.
    pub fn default_for(slot: TextureSlot) -> Self {
        Self {
            path: None,
            flip_v: false,
            srgb: slot == TextureSlot::Albedo,
        }
    }
}

impl Default for MapSlot {
    fn default() -> Self {
        Self::default_for(TextureSlot::Normal)
    }
}

/// The five slots in [`MeshTextures`]' order.
pub const SLOTS: [TextureSlot; 5] = [
    TextureSlot::Albedo,
    TextureSlot::Normal,
    TextureSlot::Roughness,
    TextureSlot::Mask,
    TextureSlot::Thickness,
];

impl TextureImage {
    /// Re-encodes 8-bit texels between sRGB and linear (IEC 61966-2-1):
    /// `to_srgb` true encodes linear values, false decodes sRGB ones.
    /// The alpha of RGBA images is left alone.
    pub fn recode(&mut self, to_srgb: bool) {
        let lut: Vec<u8> = (0..256)
            .map(|i| {
                let x = i as f32 / 255.0;
                let y = if to_srgb {
                    crate::model::colour::linear_to_srgb(x)
                } else {
                    crate::model::colour::srgb_to_linear(x)
                };
                (y * 255.0).round().clamp(0.0, 255.0) as u8
            })
            .collect();
        let c = self.channels as usize;
        for (i, t) in self.texels.iter_mut().enumerate() {
            if c == 4 && i % 4 == 3 {
                continue;
            }
            *t = lut[*t as usize];
        }
    }
}

/// Applies the artist's map slots to a mesh's textures: loads the files
/// that replace maps, flips V and re-encodes where asked. The albedo
/// texture is sampled as sRGB and the others as linear, so a slot whose
/// encoding differs is converted on load. A replaced albedo is the albedo
/// as it is (`AlbedoMode::Absolute`), a replaced roughness likewise.
pub fn apply_slots(
    maps: &mut MeshTextures,
    slots: &[MapSlot; 5],
    thickness_range_mm: f32,
) -> Result<(), TextureError> {
    for (slot, set) in SLOTS.into_iter().zip(slots) {
        let mut img = match &set.path {
            Some(p) => Some(load(p, slot)?),
            None => None,
        };
        let replaced = img.is_some();
        let target: Option<&mut TextureImage> = match slot {
            TextureSlot::Albedo => Some(&mut maps.albedo),
            TextureSlot::Normal => Some(&mut maps.normal),
            TextureSlot::Roughness => Some(&mut maps.roughness),
            TextureSlot::Mask => Some(&mut maps.mask),
            TextureSlot::Thickness => maps.thickness.as_mut().map(|t| &mut t.0),
        };
        let t = match (img.take(), target) {
            (Some(new), Some(t)) => {
                *t = new;
                t
            }
            (Some(new), None) => {
                maps.thickness = Some((new, thickness_range_mm));
                match maps.thickness.as_mut() {
                    Some(t) => &mut t.0,
                    None => continue,
                }
            }
            (None, Some(t)) if set.flip_v || set.srgb != MapSlot::default_for(slot).srgb => t,
            _ => continue,
        };
        if set.flip_v {
            t.flip_v();
        }
        // The GPU decodes the albedo as sRGB and reads the rest as linear.
        let gpu_srgb = slot == TextureSlot::Albedo;
        if set.srgb != gpu_srgb {
            t.recode(gpu_srgb);
        }
        if replaced {
            match slot {
                TextureSlot::Albedo => maps.albedo_mode = AlbedoMode::Absolute,
                TextureSlot::Roughness => maps.roughness_mode = RoughnessMode::Absolute,
                _ => {}
            }
        }
    }
    Ok(())
}

#[cfg(test)]
mod slot_tests {
    use super::*;

    /// sRGB 188 is linear 0.5029 → 128 (IEC 61966-2-1), and back.
    #[test]
    fn recode_round_trips_mid_grey() {
        let mut t = TextureImage {
            width: 1,
            height: 1,
            channels: 4,
            texels: vec![188, 188, 188, 7],
        };
        t.recode(false);
        assert_eq!(t.texels, vec![128, 128, 128, 7]);
        t.recode(true);
        assert_eq!(t.texels, vec![188, 188, 188, 7]);
    }

    /// A linear-encoded albedo map is converted for the sRGB sampler; a
    /// flipped normal slot mirrors the mesh's own map; untouched slots stay.
    #[test]
    fn slots_flip_and_recode_the_meshs_maps() {
        let mut maps = MeshTextures {
            normal: TextureImage {
                width: 1,
                height: 2,
                channels: 4,
                texels: vec![1, 2, 3, 4, 5, 6, 7, 8],
            },
            ..MeshTextures::default()
        };
        let mut slots: [MapSlot; 5] = SLOTS.map(MapSlot::default_for);
        slots[0].srgb = false;
        slots[1].flip_v = true;
        let before_mask = maps.mask.clone();
        apply_slots(&mut maps, &slots, 20.0).unwrap();
        assert_eq!(maps.normal.texels, vec![5, 6, 7, 8, 1, 2, 3, 4]);
        // 188 read as linear 0.737 is sRGB 0.874 → 223.
        assert_eq!(maps.albedo.texels[0], 223);
        assert_eq!(maps.mask.texels, before_mask.texels);
    }
}

#[cfg(test)]
mod map_mean_tests {
    use super::*;

    /// The mean is over used texels only: transparent and black texels
    /// (a scan's unused atlas space) are left out; sRGB bytes are decoded
    /// (188 → 0.5029, IEC 61966-2-1).
    #[test]
    fn the_mean_leaves_out_unused_texels_and_is_linear() {
        let map = TextureImage {
            width: 4,
            height: 1,
            channels: 4,
            texels: vec![
                255, 0, 188, 255, // used
                188, 188, 188, 255, // used
                0, 0, 0, 255, // black: unused
                255, 255, 255, 0, // transparent: unused
            ],
        };
        let m = albedo_map_mean(&map).unwrap();
        let g = ((188.0f64 / 255.0 + 0.055) / 1.055).powf(2.4) as f32;
        assert!((m[0] - (1.0 + g) / 2.0).abs() < 1e-6, "{m:?}");
        assert!((m[1] - g / 2.0).abs() < 1e-6, "{m:?}");
        assert!((m[2] - g).abs() < 1e-6, "{m:?}");
        let empty = TextureImage::solid(&[0, 0, 0, 255]);
        assert_eq!(albedo_map_mean(&empty), None);
    }
}
