//! Copies of GPU textures and buffers back to the CPU, and half floats.

use super::context::{GpuContext, GpuError};

/// Maps a 4 × u32 buffer (already copied and submitted).
pub(super) fn read_u32x4(ctx: &GpuContext, read: &wgpu::Buffer) -> Option<[u32; 4]> {
    let (tx, rx) = std::sync::mpsc::channel();
    read.slice(..).map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.device.poll(wgpu::PollType::wait_indefinitely()).ok()?;
    rx.recv().ok()?.ok()?;
    let data = read.slice(..).get_mapped_range().ok()?;
    let v: &[u32] = bytemuck::cast_slice(&data);
    let out = [v[0], v[1], v[2], v[3]];
    drop(data);
    read.unmap();
    Some(out)
}

/// Maps the first `n` u64 of a readback buffer (already copied and submitted).
pub(super) fn read_u64s(ctx: &GpuContext, read: &wgpu::Buffer, n: usize) -> Option<Vec<u64>> {
    let (tx, rx) = std::sync::mpsc::channel();
    let slice = read.slice(..8 * n as u64);
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.device.poll(wgpu::PollType::wait_indefinitely()).ok()?;
    rx.recv().ok()?.ok()?;
    let data = slice.get_mapped_range().ok()?;
    let out = bytemuck::cast_slice::<u8, u64>(&data).to_vec();
    drop(data);
    read.unmap();
    Some(out)
}

/// f32 → IEEE 754 binary16, round to nearest (for Rgba16Float uploads of
/// values well inside the half range; tiny values flush to zero).
pub fn f32_to_half(x: f32) -> u16 {
    let bits = x.to_bits();
    let sign = ((bits >> 16) & 0x8000) as u16;
    let exp = ((bits >> 23) & 0xff) as i32 - 127 + 15;
    let mant = bits & 0x7f_ffff;
    if x.is_nan() {
        return 0x7e00;
    }
    if exp >= 31 {
        return sign | 0x7c00;
    }
    if exp <= 0 {
        return sign;
    }
    let half = sign as u32 | ((exp as u32) << 10) | (mant >> 13);
    // Round to nearest on the dropped bits.
    (half + ((mant >> 12) & 1)) as u16
}

/// IEEE 754 binary16 → f32 (the HDR targets are Rgba16Float): a sign bit
/// over the same 5-bit-exponent float as RG11B10's, with 10 mantissa bits.
pub fn half_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    sign * small_float((h & 0x7fff) as u32, 10)
}

/// Copies each texture (with its bytes per pixel) into a buffer, submits
/// the frame, waits, and returns tightly packed rows for each.
pub(super) fn readback(
    ctx: &GpuContext,
    mut encoder: wgpu::CommandEncoder,
    textures: &[(&wgpu::Texture, u32)],
    w: u32,
    h: u32,
) -> Result<Vec<Vec<u8>>, GpuError> {
    let err = |e: String| GpuError::Readback(e);
    let buffers: Vec<(wgpu::Buffer, u32, u32)> = textures
        .iter()
        .map(|&(texture, bpp)| {
            let row = (bpp * w).div_ceil(256) * 256;
            let buffer = ctx.device.create_buffer(&wgpu::BufferDescriptor {
                label: Some("readback"),
                size: (row * h) as u64,
                usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
                mapped_at_creation: false,
            });
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &buffer,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(row),
                        rows_per_image: Some(h),
                    },
                },
                wgpu::Extent3d {
                    width: w,
                    height: h,
                    depth_or_array_layers: 1,
                },
            );
            (buffer, row, bpp)
        })
        .collect();
    ctx.queue.submit([encoder.finish()]);
    let (tx, rx) = std::sync::mpsc::channel();
    for (buffer, _, _) in &buffers {
        let tx = tx.clone();
        buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            let _ = tx.send(r);
        });
    }
    ctx.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| err(e.to_string()))?;
    for _ in &buffers {
        rx.recv()
            .map_err(|e| err(e.to_string()))?
            .map_err(|e| err(e.to_string()))?;
    }
    let mut out = Vec::new();
    for (buffer, row, bpp) in &buffers {
        let data = buffer
            .slice(..)
            .get_mapped_range()
            .map_err(|e| err(e.to_string()))?;
        let mut pixels = Vec::with_capacity((bpp * w * h) as usize);
        for y in 0..h as usize {
            let start = y * *row as usize;
            pixels.extend_from_slice(&data[start..start + (bpp * w) as usize]);
        }
        drop(data);
        buffer.unmap();
        out.push(pixels);
    }
    Ok(out)
}

/// An unsigned float of `mantissa_bits` and a 5-bit exponent (bias 15):
/// a half's magnitude (10 bits), or B10G11R11_UFLOAT's channels (6 and 5;
/// the Vulkan specification's "Unsigned 11-Bit Floating-Point Numbers" and
/// "10-Bit" sections: no sign bit, the exponent and mantissa as in a half).
fn small_float(bits: u32, mantissa_bits: u32) -> f32 {
    let exp = ((bits >> mantissa_bits) & 0x1f) as i32;
    let frac = (bits & ((1 << mantissa_bits) - 1)) as f32 / (1u32 << mantissa_bits) as f32;
    match exp {
        0 => frac * 2f32.powi(-14),
        31 => {
            if frac == 0.0 {
                f32::INFINITY
            } else {
                f32::NAN
            }
        }
        e => (1.0 + frac) * 2f32.powi(e - 15),
    }
}

/// Rows of Rg11b10Ufloat texels (4 bytes each: R in bits 0–10, G in
/// 11–21, B in 22–31) as f32 RGB.
pub(super) fn rg11b10(bytes: &[u8]) -> Vec<[f32; 3]> {
    bytes
        .chunks_exact(4)
        .map(|px| {
            let v = u32::from_le_bytes([px[0], px[1], px[2], px[3]]);
            [
                small_float(v & 0x7ff, 6),
                small_float((v >> 11) & 0x7ff, 6),
                small_float(v >> 22, 5),
            ]
        })
        .collect()
}

/// Rows of Rgba16Float texels (8 bytes each, little-endian halves) as f32 RGBA.
pub(super) fn rgba_halves(bytes: &[u8]) -> Vec<[f32; 4]> {
    bytes
        .chunks_exact(8)
        .map(|px| [0, 1, 2, 3].map(|k| half_to_f32(u16::from_le_bytes([px[2 * k], px[2 * k + 1]]))))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// B10G11R11_UFLOAT by the Vulkan specification's definitions (bias
    /// 15, no sign): 1.0, 2.0 and 0.5 exactly; the largest finite values
    /// the specification gives, 65024 (11 bits) and 64512 (10 bits); a
    /// mantissa's half; and the smallest denormal, 2⁻¹⁴/64.
    #[test]
    fn rg11b10_decodes_by_the_vulkan_definition() {
        let pack = |r: u32, g: u32, b: u32| (r | (g << 11) | (b << 22)).to_le_bytes();
        let px = rg11b10(&pack(15 << 6, 16 << 6, 14 << 5));
        assert_eq!(px, vec![[1.0, 2.0, 0.5]]);
        let px = rg11b10(&pack((30 << 6) | 63, (15 << 6) | 32, (30 << 5) | 31));
        assert_eq!(px, vec![[65024.0, 1.5, 64512.0]]);
        let px = rg11b10(&pack(1, 31 << 6, (14 << 5) | 16));
        assert_eq!(px[0][0], 2f32.powi(-14) / 64.0);
        assert!(px[0][1].is_infinite());
        assert_eq!(px[0][2], 0.75);
    }
}
