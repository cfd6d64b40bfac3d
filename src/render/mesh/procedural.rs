//! The default head's textures, baked deterministically in UV space:
//! every texel is mapped back to its point on the mesh (through a texel →
//! triangle map, dilated past the UV islands' edges so filtering never
//! reads the background), and colour, roughness, mask and height are
//! functions of that 3D point. Landmarks are in the embedded head's units
//! (decimetres, recentred; see assets/head/).

use super::Mesh;
use crate::render::gpu_types::SurfaceKind;
use crate::render::textures::{AlbedoMode, MeshTextures, RoughnessMode, TextureImage};
use glam::{Vec2, Vec3};
use rayon::prelude::*;

/// Normal-map resolution; albedo, roughness and mask are baked at half.
/// The head covers 24 % of the hm08 atlas: about 0.47 mm per normal texel.
pub const NORMAL_SIZE: u32 = 2048;
/// Texels the UV islands are grown by.
const DILATE: usize = 6;
const EMPTY: u32 = u32::MAX;

/// A region weight in [0, 1]: 1 at `centre`, falling smoothly to 0 at the
/// ellipsoid of semi-axes `radii`.
fn blob(p: Vec3, centre: Vec3, radii: Vec3) -> f32 {
    let d = ((p - centre) / radii).length();
    let t = (1.0 - d).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// Mirror-symmetric region (both sides of the face).
fn blob2(p: Vec3, centre: Vec3, radii: Vec3) -> f32 {
    blob(Vec3::new(p.x.abs(), p.y, p.z), centre, radii)
}

struct Regions {
    lips: f32,
    nose: f32,
    cheeks: f32,
    brows: f32,
    under_eyes: f32,
    forehead: f32,
    ears: f32,
}

fn regions(p: Vec3) -> Regions {
    Regions {
        lips: blob(p, Vec3::new(0.0, -0.37, 0.93), Vec3::new(0.25, 0.085, 0.2)),
        nose: blob(p, Vec3::new(0.0, -0.02, 1.06), Vec3::new(0.15, 0.16, 0.16)),
        cheeks: blob2(p, Vec3::new(0.42, -0.06, 0.72), Vec3::new(0.22, 0.2, 0.25)),
        brows: (1.6 * blob2(p, Vec3::new(0.3, 0.55, 0.8), Vec3::new(0.26, 0.085, 0.3))).min(1.0),
        under_eyes: blob2(p, Vec3::new(0.3, 0.2, 0.8), Vec3::new(0.16, 0.06, 0.15)),
        forehead: blob(p, Vec3::new(0.0, 0.85, 0.8), Vec3::new(0.5, 0.26, 0.4)),
        ears: blob2(p, Vec3::new(0.78, 0.3, -0.05), Vec3::new(0.2, 0.35, 0.3)),
    }
}

fn hash3(i: [i32; 3], seed: u32) -> u32 {
    let mut h = seed
        ^ (i[0] as u32).wrapping_mul(0x8da6_b343)
        ^ (i[1] as u32).wrapping_mul(0xd816_3841)
        ^ (i[2] as u32).wrapping_mul(0xcb1a_b31f);
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^ (h >> 16)
}

fn unit(h: u32) -> f32 {
    (h >> 8) as f32 / (1u32 << 24) as f32
}

/// Smooth value noise in [0, 1] on a unit lattice.
fn value_noise(p: Vec3, seed: u32) -> f32 {
    let i = p.floor();
    let f = p - i;
    let s = f * f * (Vec3::splat(3.0) - 2.0 * f);
    let c = |dx: i32, dy: i32, dz: i32| {
        unit(hash3(
            [i.x as i32 + dx, i.y as i32 + dy, i.z as i32 + dz],
            seed,
        ))
    };
    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
    let x00 = lerp(c(0, 0, 0), c(1, 0, 0), s.x);
    let x10 = lerp(c(0, 1, 0), c(1, 1, 0), s.x);
    let x01 = lerp(c(0, 0, 1), c(1, 0, 1), s.x);
    let x11 = lerp(c(0, 1, 1), c(1, 1, 1), s.x);
    lerp(lerp(x00, x10, s.y), lerp(x01, x11, s.y), s.z)
}

/// Distance to the nearest jittered lattice point (Worley F1), lattice units.
fn worley(p: Vec3, seed: u32) -> f32 {
    let i = p.floor();
    let mut best = f32::MAX;
    for dz in -1..=1 {
        for dy in -1..=1 {
            for dx in -1..=1 {
                let cell = [i.x as i32 + dx, i.y as i32 + dy, i.z as i32 + dz];
                let h = hash3(cell, seed);
                let jitter = Vec3::new(
                    unit(h),
                    unit(h.wrapping_mul(0x9e37_79b9)),
                    unit(h.wrapping_mul(0x85eb_ca6b)),
                );
                let q = Vec3::new(cell[0] as f32, cell[1] as f32, cell[2] as f32) + jitter;
                best = best.min((q - p).length_squared());
            }
        }
    }
    best.sqrt()
}

/// Linear albedo multiplier (1 = the preset's colour), roughness
/// multiplier and SSS mask at point `p` (units) with `mm` = p in mm.
fn surface(p: Vec3, mm: Vec3) -> ([f32; 3], f32, f32) {
    let r = regions(p);
    let mut a = Vec3::ONE;
    let tint = |a: Vec3, w: f32, c: Vec3| a * Vec3::ONE.lerp(c, w);
    a = tint(a, r.lips, Vec3::new(0.95, 0.62, 0.66));
    a = tint(a, r.cheeks, Vec3::new(1.03, 0.9, 0.9));
    a = tint(a, r.nose, Vec3::new(1.03, 0.9, 0.9));
    a = tint(a, r.ears, Vec3::new(1.02, 0.9, 0.9));
    a = tint(a, r.under_eyes, Vec3::new(0.92, 0.88, 0.94));
    // Mottling (±5 %, ~8 mm blotches) and sparse freckles (~2 mm).
    let blotch = value_noise(mm / 8.0, 11) - 0.5;
    a *= Vec3::new(1.0 + 0.06 * blotch, 1.0 + 0.1 * blotch, 1.0 + 0.1 * blotch);
    let freckle = (1.0 - worley(mm / 2.5, 23) / 0.22).clamp(0.0, 1.0) * 0.25;
    a *= Vec3::ONE - freckle * Vec3::new(0.25, 0.35, 0.45) * (1.0 - r.lips);
    // Brow hair: dark strands along x.
    let strands = value_noise(mm * Vec3::new(0.8, 6.0, 6.0), 31);
    let hair = (r.brows * (0.6 + 0.8 * strands)).clamp(0.0, 1.0);
    a = a.lerp(Vec3::new(0.16, 0.11, 0.09), hair * 0.85);
    // T-zone and lips shinier, cheeks rougher; pores add grain.
    let rough =
        1.0 - 0.18 * r.forehead - 0.22 * r.nose - 0.2 * r.lips + 0.12 * r.cheeks + 0.3 * hair;
    // Brow hair does not scatter like skin.
    let mask = 1.0 - (hair * 1.4).clamp(0.0, 1.0);
    (a.into(), rough, mask)
}

/// Surface height (mm): pores, forehead lines, lip creases. Real pores
/// (0.1–0.3 mm) are below the 0.47 mm texel of this atlas, so the bake
/// draws them at the scale it can resolve: pits ~1.4 mm apart.
fn height(p: Vec3, mm: Vec3) -> f32 {
    let r = regions(p);
    // Pores, larger on nose and cheeks, none on lips and brows.
    let scale = 1.4 * (1.0 + 0.3 * r.nose + 0.15 * r.cheeks);
    let f1 = worley(mm / scale, 7);
    let pit = (1.0 - f1 / 0.45).clamp(0.0, 1.0);
    let pores = -0.08 * pit * pit * (1.0 - r.lips) * (1.0 - r.brows);
    // Fine skin grain.
    let grain = 0.05 * (value_noise(mm / 1.1, 3) - 0.5);
    // Forehead lines (~7 mm apart, wavy) and vertical lip creases (~1.8 mm).
    let wave = 2.0 * value_noise(mm / 12.0, 5);
    let line = |u: f32| {
        let s = (u * std::f32::consts::PI).sin().abs();
        (1.0 - s).powi(4)
    };
    let forehead = -0.15 * r.forehead * line(mm.y / 7.0 + wave);
    let lips = -0.08 * r.lips * line(mm.x / 1.8 + 0.5 * wave);
    pores + grain + forehead + lips
}

/// Texel → skin triangle map at `size`², grown `DILATE` texels past the
/// islands, and each texel's barycentric coordinates in its triangle.
fn texel_triangles(mesh: &Mesh, size: u32) -> Vec<u32> {
    let n = size as usize;
    let mut map = vec![EMPTY; n * n];
    let uv = |i: u32| Vec2::from(mesh.vertices[i as usize].uv) * size as f32;
    for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
        if SurfaceKind::of(mesh.vertices[tri[0] as usize].material) != SurfaceKind::Skin {
            continue;
        }
        let [a, b, c] = [uv(tri[0]), uv(tri[1]), uv(tri[2])];
        let lo = a.min(b).min(c).floor().max(Vec2::ZERO);
        let hi = a.max(b).max(c).ceil().min(Vec2::splat(size as f32 - 1.0));
        for y in lo.y as usize..=hi.y as usize {
            for x in lo.x as usize..=hi.x as usize {
                let q = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
                let w = barycentric(q, a, b, c);
                if w.min_element() >= -1e-4 {
                    map[y * n + x] = t as u32;
                }
            }
        }
    }
    for _ in 0..DILATE {
        let prev = map.clone();
        for y in 0..n {
            for x in 0..n {
                if prev[y * n + x] != EMPTY {
                    continue;
                }
                let nb = [
                    (x.wrapping_sub(1), y),
                    (x + 1, y),
                    (x, y.wrapping_sub(1)),
                    (x, y + 1),
                ];
                if let Some(&t) = nb
                    .iter()
                    .filter(|(i, j)| *i < n && *j < n)
                    .map(|(i, j)| &prev[j * n + i])
                    .find(|t| **t != EMPTY)
                {
                    map[y * n + x] = t;
                }
            }
        }
    }
    map
}

fn barycentric(q: Vec2, a: Vec2, b: Vec2, c: Vec2) -> Vec3 {
    let d = (b - a).perp_dot(c - a);
    if d.abs() < 1e-12 {
        return Vec3::new(1.0, 0.0, 0.0);
    }
    let wb = (q - a).perp_dot(c - a) / d;
    let wc = (b - a).perp_dot(q - a) / d;
    Vec3::new(1.0 - wb - wc, wb, wc)
}

/// Bakes the default head's albedo variation, normal, roughness and mask.
pub fn bake(mesh: &Mesh) -> MeshTextures {
    let size = NORMAL_SIZE;
    let n = size as usize;
    let map = texel_triangles(mesh, size);
    let mm_per_unit = mesh.metres_per_unit * 1000.0;
    let vert = |i: u32| &mesh.vertices[i as usize];
    // Per texel: (point, height) from its triangle, or None off the islands.
    let point = |x: usize, y: usize| -> Option<(Vec3, u32)> {
        let t = map[y * n + x];
        if t == EMPTY {
            return None;
        }
        let tri = &mesh.indices[3 * t as usize..3 * t as usize + 3];
        let uv = |i: u32| Vec2::from(vert(i).uv) * size as f32;
        let q = Vec2::new(x as f32 + 0.5, y as f32 + 0.5);
        // Dilated texels extrapolate their triangle's plane.
        let w = barycentric(q, uv(tri[0]), uv(tri[1]), uv(tri[2]));
        let p = w.x * Vec3::from(vert(tri[0]).position)
            + w.y * Vec3::from(vert(tri[1]).position)
            + w.z * Vec3::from(vert(tri[2]).position);
        Some((p, t))
    };
    let heights: Vec<f32> = (0..n * n)
        .into_par_iter()
        .map(|i| point(i % n, i / n).map_or(0.0, |(p, _)| height(p, p * mm_per_unit)))
        .collect();
    // mm of surface per unit of u and of v, per triangle.
    let scale = |t: u32| -> (f32, f32) {
        let tri = &mesh.indices[3 * t as usize..3 * t as usize + 3];
        let p = |i: u32| Vec3::from(vert(i).position) * mm_per_unit;
        let uv = |i: u32| Vec2::from(vert(i).uv);
        let (e1, e2) = (p(tri[1]) - p(tri[0]), p(tri[2]) - p(tri[0]));
        let (d1, d2) = (uv(tri[1]) - uv(tri[0]), uv(tri[2]) - uv(tri[0]));
        let det = d1.perp_dot(d2);
        if det.abs() < 1e-12 {
            return (1.0, 1.0);
        }
        let dpdu = (e1 * d2.y - e2 * d1.y) / det;
        let dpdv = (e2 * d1.x - e1 * d2.x) / det;
        (dpdu.length().max(1e-6), dpdv.length().max(1e-6))
    };
    let normal: Vec<u8> = (0..n * n)
        .into_par_iter()
        .flat_map_iter(|i| {
            let (x, y) = (i % n, i / n);
            let t = map[i];
            let enc = |v: f32| ((v * 0.5 + 0.5) * 255.0).round().clamp(0.0, 255.0) as u8;
            if t == EMPTY {
                return [128, 128, 255, 255];
            }
            let h = |x: usize, y: usize| heights[y.min(n - 1) * n + x.min(n - 1)];
            let texel = 1.0 / size as f32;
            let dh_du = (h(x + 1, y) - h(x.saturating_sub(1), y)) / (2.0 * texel);
            // +v is up in the image: opposite to the row index.
            let dh_dv = -(h(x, y + 1) - h(x, y.saturating_sub(1))) / (2.0 * texel);
            let (su, sv) = scale(t);
            let nrm = Vec3::new(-dh_du / su, -dh_dv / sv, 1.0).normalize();
            [enc(nrm.x), enc(nrm.y), enc(nrm.z), 255]
        })
        .collect();
    // Albedo, roughness and mask at half resolution: the full-size bake
    // box-filtered once.
    let full: Vec<([f32; 3], f32, f32)> = (0..n * n)
        .into_par_iter()
        .map(|i| {
            point(i % n, i / n).map_or(([1.0; 3], 1.0, 1.0), |(p, _)| surface(p, p * mm_per_unit))
        })
        .collect();
    let srgb = crate::model::colour::linear_to_srgb8;
    let mut albedo = Vec::with_capacity(n * n * 4);
    let mut rough = Vec::with_capacity(n * n);
    let mut mask = Vec::with_capacity(n * n);
    for (a, r, m) in &full {
        // Stored as sRGB of multiplier / 2, so 0.5 (linear) is the preset.
        albedo.extend(a.map(|c| srgb(0.5 * c)));
        albedo.push(255);
        rough.push((0.5 * r * 255.0).round().clamp(0.0, 255.0) as u8);
        mask.push((m * 255.0).round().clamp(0.0, 255.0) as u8);
    }
    let image = |channels: u32, texels: Vec<u8>| TextureImage {
        width: size,
        height: size,
        channels,
        texels,
    };
    MeshTextures {
        albedo: image(4, albedo).half(),
        albedo_mode: AlbedoMode::Modulate,
        normal: image(4, normal),
        roughness: image(1, rough).half(),
        roughness_mode: RoughnessMode::Scale,
        mask: image(1, mask).half(),
        thickness: None,
    }
}
