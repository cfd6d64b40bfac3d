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

/// IEEE 754 binary16 → f32 (the HDR targets are Rgba16Float).
pub fn half_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exp = ((h >> 10) & 0x1f) as i32;
    let frac = (h & 0x3ff) as f32;
    sign * match exp {
        0 => frac * 2f32.powi(-24),
        31 => {
            if frac == 0.0 {
                f32::INFINITY
            } else {
                f32::NAN
            }
        }
        e => (1.0 + frac / 1024.0) * 2f32.powi(e - 15),
    }
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

/// Rows of Rgba16Float texels (8 bytes each, little-endian halves) as f32 RGBA.
pub(super) fn rgba_halves(bytes: &[u8]) -> Vec<[f32; 4]> {
    bytes
        .chunks_exact(8)
        .map(|px| [0, 1, 2, 3].map(|k| half_to_f32(u16::from_le_bytes([px[2 * k], px[2 * k + 1]]))))
        .collect()
}
