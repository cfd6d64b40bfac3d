//! The scene pass's diffuse target evaluated on the CPU at any point of
//! the mesh, seen by the camera or not: what the ground truth
//! (`render::ground_truth`) integrates. A twin of `fs_main` in
//! `shaders/scene.wgsl` for the SSS surface, line for line: the light
//! (directional or point, `light_at`) and the rig's unshadowed fill and
//! rim, the key's PCF shadow from the same shadow
//! map read back from the GPU (`shadow_factor`: 3×3 bilinear comparison
//! taps, LessEqual, clamp to edge), the SH environment
//! (`environment_irradiance`), the tangent-space normal map, the irradiance
//! test patterns, and albedo^pre of the texturing mode. The maps are read
//! as the GPU reads them: trilinear over the same mip chain, at the level
//! of detail of the region the value stands for ([`Footprint`]: a pixel's
//! two steps on the surface, Vulkan's ρ_max, where a pixel sees it; the
//! width of a cell of the cloud elsewhere). Reading level 0 where the GPU
//! filtered left a speckle of normal-map detail on every pixel, as large as
//! the errors the ground truth ranks (issue 22). Transmission is not
//! added: light through thin parts reaches the ground truth as irradiance
//! on the far side's cells. Eyes and teeth (material ≠ 0) are not SSS
//! surface and give 0; skin outside the SSS mask (brows) is skin that
//! scatters under its hair, and gives its light. Checked against the GPU's
//! own diffuse target on the visible pixels: `scene_twin_matches_the_scene_pass`
//! and the d → 0 limit in tests/render_physics.rs.

use super::gpu_types::{
    SceneUniforms, SurfaceKind, MAP_ABSOLUTE, MAP_LOOK, PATTERN_CHECKERBOARD, PATTERN_STEP,
};
use super::ground_truth::{Footprint, SurfaceIrradiance};
use super::mesh::Mesh;
use super::textures::TextureImage;
use glam::{Mat4, Vec2, Vec3, Vec4};

/// The light's depth map as the scene pass samples it (row 0 at v = 0).
#[derive(Debug, Clone)]
pub struct ShadowMap {
    pub size: u32,
    pub depth: Vec<f32>,
}

impl ShadowMap {
    /// `textureSampleCompareLevel` with a linear comparison sampler:
    /// each of the four nearest texels passes when `reference` ≤ its
    /// depth, and the passes are weighted bilinearly.
    fn compare(&self, uv: Vec2, reference: f32) -> f32 {
        let n = self.size as i32;
        let t = uv * self.size as f32 - Vec2::splat(0.5);
        let (i0, j0) = (t.x.floor() as i32, t.y.floor() as i32);
        let (fx, fy) = (t.x - i0 as f32, t.y - j0 as f32);
        let pass = |i: i32, j: i32| {
            let (i, j) = (i.clamp(0, n - 1), j.clamp(0, n - 1));
            if reference <= self.depth[(j * n + i) as usize] {
                1.0
            } else {
                0.0
            }
        };
        let top = pass(i0, j0) * (1.0 - fx) + pass(i0 + 1, j0) * fx;
        let bottom = pass(i0, j0 + 1) * (1.0 - fx) + pass(i0 + 1, j0 + 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

/// A surface map and its mip chain, sampled as the scene pass's sampler
/// does: trilinear, repeating (`surface_sampler` in `passes/scene.rs`:
/// linear min/mag/mip filters, no anisotropy), over the same 2×2 box
/// chain the GPU is given (`TextureImage::mip_chain`).
#[derive(Debug, Clone)]
pub struct MipMap {
    levels: Vec<TextureImage>,
}

impl MipMap {
    pub fn new(t: &TextureImage) -> Self {
        Self {
            levels: t.mip_chain(),
        }
    }

    pub fn width(&self) -> u32 {
        self.levels[0].width
    }

    pub fn height(&self) -> u32 {
        self.levels[0].height
    }

    /// Trilinear at level of detail `lod` (Vulkan §16.6: level ⌊λ⌋ and
    /// ⌊λ⌋ + 1 blended by the fraction, λ clamped to the chain).
    pub fn sample(&self, uv: Vec2, lod: f32, srgb: bool) -> Vec4 {
        let last = (self.levels.len() - 1) as f32;
        let lod = if lod.is_finite() {
            lod.clamp(0.0, last)
        } else {
            0.0
        };
        let base = lod.floor();
        let f = lod - base;
        let a = sample(&self.levels[base as usize], uv, srgb);
        if f <= 0.0 {
            return a;
        }
        let b = sample(
            &self.levels[(base as usize + 1).min(last as usize)],
            uv,
            srgb,
        );
        a * (1.0 - f) + b * f
    }
}

/// The maps the twin reads, with their mip chains (built once per mesh
/// and kept with the ground truth's cloud).
#[derive(Debug, Clone)]
pub struct SurfaceMips {
    pub albedo: MipMap,
    pub normal: MipMap,
}

impl SurfaceMips {
    pub fn new(mesh: &Mesh) -> Self {
        Self {
            albedo: MipMap::new(&mesh.textures.albedo),
            normal: MipMap::new(&mesh.textures.normal),
        }
    }
}

/// How a triangle's texture coordinates change across its plane:
/// J = ∂(u, v)/∂(surface mm) in the orthonormal basis (t1, t2) of the
/// plane, as its columns j1, j2 (UV per mm along t1 and t2).
struct UvJacobian {
    t1: Vec3,
    t2: Vec3,
    j1: Vec2,
    j2: Vec2,
}

impl UvJacobian {
    /// From the corners `p` (mm) and texture coordinates `uv`; `None` for
    /// a degenerate triangle.
    fn new(p: [Vec3; 3], uv: [Vec2; 3]) -> Option<Self> {
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let l1 = e1.length();
        let t1 = e1 / l1.max(1e-30);
        let t2 = (e2 - t1 * e2.dot(t1)).normalize_or_zero();
        // The edges in the plane's basis: e1 = (a, 0), e2 = (b, c).
        let (a, b, c) = (l1, e2.dot(t1), e2.dot(t2));
        if a <= 0.0 || c.abs() <= 0.0 {
            return None;
        }
        // J = [Δuv₁ Δuv₂] · [[a, b], [0, c]]⁻¹.
        let j1 = (uv[1] - uv[0]) / a;
        let j2 = ((uv[2] - uv[0]) - j1 * b) / c;
        Some(Self { t1, t2, j1, j2 })
    }

    /// The level of detail at which the GPU reads a map `size` texels
    /// across over `footprint`: λ = log₂ ρ with ρ the larger of the texel
    /// lengths of the pixel's two steps (Vulkan §16.6.2's ρ_max), and at
    /// least the texels the footprint's width spans along the map's most
    /// stretched direction (the larger singular value of J in texels).
    fn level_of_detail(&self, (w, h): (u32, u32), footprint: &Footprint) -> f32 {
        let scale = Vec2::new(w as f32, h as f32);
        let (j1, j2) = (self.j1 * scale, self.j2 * scale);
        let texels = |d: Vec3| (j1 * d.dot(self.t1) + j2 * d.dot(self.t2)).length();
        let frob = j1.length_squared() + j2.length_squared();
        let det = j1.x * j2.y - j1.y * j2.x;
        let stretch = (0.5 * (frob + (frob * frob - 4.0 * det * det).max(0.0).sqrt())).sqrt();
        let rho = texels(footprint.pixel_dx_mm)
            .max(texels(footprint.pixel_dy_mm))
            .max(stretch * footprint.width_mm);
        rho.log2()
    }
}

/// sRGB-encoded byte → linear (IEC 61966-2-1), tabulated once.
fn srgb_to_linear(byte: u8) -> f32 {
    static TABLE: std::sync::OnceLock<[f32; 256]> = std::sync::OnceLock::new();
    TABLE.get_or_init(|| std::array::from_fn(|i| super::compare::srgb_to_linear(i as u8)))
        [byte as usize]
}

/// The scene's lighting and surface, for [`SurfaceIrradiance`].
pub struct SceneIrradiance<'a> {
    mesh: &'a Mesh,
    u: SceneUniforms,
    light_clip: Mat4,
    shadow: &'a ShadowMap,
    mips: &'a SurfaceMips,
}

impl<'a> SceneIrradiance<'a> {
    pub fn new(
        mesh: &'a Mesh,
        u: SceneUniforms,
        shadow: &'a ShadowMap,
        mips: &'a SurfaceMips,
    ) -> Self {
        Self {
            mesh,
            light_clip: Mat4::from_cols_array_2d(&u.light_clip_from_world),
            u,
            shadow,
            mips,
        }
    }

    /// A hash of every scene uniform the twin reads (and so of the
    /// irradiance it gives): the ground truth keeps its cells while this
    /// stays the same (the camera, the profile's tables and the methods'
    /// fields can change).
    pub fn key(u: &SceneUniforms) -> u64 {
        use std::hash::{Hash, Hasher};
        let mut h = std::collections::hash_map::DefaultHasher::new();
        let SceneUniforms {
            light_clip_from_world,
            light_direction,
            light_radiance,
            rig_direction,
            rig_radiance,
            surface_albedo,
            environment_sh,
            pre_scatter_exponent,
            pattern,
            pattern_period,
            shadow_texel,
            shadow_depth_bias,
            shadow_normal_offset,
            light_reference_distance,
            mm_per_unit,
            albedo_map_mode,
            detail_normal_strength,
            ..
        } = u;
        for m in light_clip_from_world {
            m.map(f32::to_bits).hash(&mut h);
        }
        for v in [light_direction, light_radiance, surface_albedo] {
            v.map(f32::to_bits).hash(&mut h);
        }
        for v in rig_direction.iter().chain(rig_radiance) {
            v.map(f32::to_bits).hash(&mut h);
        }
        for v in environment_sh {
            v.map(f32::to_bits).hash(&mut h);
        }
        [
            *pre_scatter_exponent,
            *pattern_period,
            *shadow_texel,
            *shadow_depth_bias,
            *shadow_normal_offset,
            *light_reference_distance,
            *mm_per_unit,
            *detail_normal_strength,
        ]
        .map(f32::to_bits)
        .hash(&mut h);
        (*pattern, *albedo_map_mode).hash(&mut h);
        h.finish()
    }

    fn v4(a: [f32; 4]) -> Vec4 {
        Vec4::from(a)
    }

    /// Direction towards the light (unit) and the radiance factor.
    fn light_at(&self, world: Vec3) -> (Vec3, f32) {
        let l = Self::v4(self.u.light_direction);
        if l.w < 0.5 {
            return (l.truncate(), 1.0);
        }
        let d = l.truncate() - world;
        let r2 = d.length_squared().max(1e-8);
        let z = self.u.light_reference_distance;
        (d / r2.sqrt(), z * z / r2)
    }

    fn light_space(&self, p: Vec4) -> Vec3 {
        let w = if self.u.light_direction[3] > 0.5 {
            p.w
        } else {
            1.0
        };
        let q = p.truncate() / w;
        Vec3::new(q.x * 0.5 + 0.5, 0.5 - q.y * 0.5, q.z)
    }

    fn shadow_factor(&self, world: Vec3, n: Vec3) -> f32 {
        let u = &self.u;
        let q =
            self.light_space(self.light_clip * (world + n * u.shadow_normal_offset).extend(1.0));
        let uv = Vec2::new(q.x, q.y);
        if uv.x <= 0.0 || uv.x >= 1.0 || uv.y <= 0.0 || uv.y >= 1.0 {
            return 1.0;
        }
        let depth = q.z - u.shadow_depth_bias;
        let mut lit = 0.0;
        for y in -1..=1 {
            for x in -1..=1 {
                let o = Vec2::new(x as f32, y as f32) * u.shadow_texel;
                lit += self.shadow.compare(uv + o, depth);
            }
        }
        lit / 9.0
    }

    fn environment(&self, n: Vec3) -> Vec3 {
        // (Called for every cell: no allocation.)
        let c = self.u.environment_sh.map(|v| Vec3::new(v[0], v[1], v[2]));
        let mut e = c[0] * 0.282095;
        e += c[1] * (0.488603 * n.y) + c[2] * (0.488603 * n.z) + c[3] * (0.488603 * n.x);
        e += c[4] * (1.092548 * n.x * n.y) + c[5] * (1.092548 * n.y * n.z);
        e += c[6] * (0.315392 * (3.0 * n.z * n.z - 1.0)) + c[7] * (1.092548 * n.x * n.z);
        e += c[8] * (0.546274 * (n.x * n.x - n.y * n.y));
        e.max(Vec3::ZERO)
    }
}

/// Bilinear, repeating, at mip 0; channels as stored (0–1), optionally
/// decoded from sRGB per texel first (as an sRGB texture is filtered).
pub fn sample(t: &TextureImage, uv: Vec2, srgb: bool) -> Vec4 {
    let (w, h) = (t.width.max(1) as i64, t.height.max(1) as i64);
    let p = Vec2::new(uv.x * w as f32 - 0.5, uv.y * h as f32 - 0.5);
    let (i0, j0) = (p.x.floor() as i64, p.y.floor() as i64);
    let (fx, fy) = (p.x - i0 as f32, p.y - j0 as f32);
    let ch = t.channels.max(1) as usize;
    let texel = |i: i64, j: i64| -> Vec4 {
        let (i, j) = (i.rem_euclid(w) as usize, j.rem_euclid(h) as usize);
        let k = (j * w as usize + i) * ch;
        let get = |c: usize| -> f32 {
            let byte = t.texels.get(k + c.min(ch - 1)).copied().unwrap_or(0);
            if srgb && c < 3 {
                srgb_to_linear(byte)
            } else {
                byte as f32 / 255.0
            }
        };
        if ch == 1 {
            Vec4::new(get(0), 0.0, 0.0, 1.0)
        } else {
            Vec4::new(get(0), get(1), get(2), if ch > 3 { get(3) } else { 1.0 })
        }
    };
    let top = texel(i0, j0) * (1.0 - fx) + texel(i0 + 1, j0) * fx;
    let bottom = texel(i0, j0 + 1) * (1.0 - fx) + texel(i0 + 1, j0 + 1) * fx;
    top * (1.0 - fy) + bottom * fy
}

impl SurfaceIrradiance for SceneIrradiance<'_> {
    fn at(&self, triangle: usize, b: Vec3, footprint: Footprint) -> [f32; 3] {
        let m = self.mesh;
        let idx = &m.indices[3 * triangle..3 * triangle + 3];
        let v = [0, 1, 2].map(|k| &m.vertices[idx[k] as usize]);
        let w = [b.x, b.y, b.z];
        let mix3 = |f: &dyn Fn(usize) -> Vec3| f(0) * w[0] + f(1) * w[1] + f(2) * w[2];
        let material = v[0].material * w[0] + v[1].material * w[1] + v[2].material * w[2];
        if SurfaceKind::of(material) != SurfaceKind::Skin {
            return [0.0; 3];
        }
        let world = mix3(&|k| Vec3::from(v[k].position));
        let uv =
            Vec2::from(v[0].uv) * w[0] + Vec2::from(v[1].uv) * w[1] + Vec2::from(v[2].uv) * w[2];
        // The level of detail of each map over the footprint.
        let corners = [0, 1, 2].map(|k| Vec3::from(v[k].position) * self.u.mm_per_unit);
        let uvs = [0, 1, 2].map(|k| Vec2::from(v[k].uv));
        let jacobian = UvJacobian::new(corners, uvs);
        let lod = |map: &MipMap| {
            jacobian.as_ref().map_or(0.0, |j| {
                j.level_of_detail((map.width(), map.height()), &footprint)
            })
        };
        let u = &self.u;
        let ng = mix3(&|k| Vec3::from(v[k].normal)).normalize_or_zero();
        let tangent = Vec4::from(v[0].tangent) * w[0]
            + Vec4::from(v[1].tangent) * w[1]
            + Vec4::from(v[2].tangent) * w[2];
        let mut n = ng;
        let t_raw = tangent.truncate() - ng * ng.dot(tangent.truncate());
        if t_raw.length_squared() > 1e-12 && u.detail_normal_strength > 0.0 {
            let nt = self
                .mips
                .normal
                .sample(uv, lod(&self.mips.normal), false)
                .truncate()
                * 2.0
                - Vec3::ONE;
            let t = t_raw.normalize();
            let bt = ng.cross(t) * if tangent.w < 0.0 { -1.0 } else { 1.0 };
            let strength = u.detail_normal_strength;
            let d = Vec3::new(nt.x * strength, nt.y * strength, nt.z.max(1e-3));
            n = (t * d.x + bt * d.y + ng * d.z).normalize_or_zero();
        }
        let (l, falloff) = self.light_at(world);
        let radiance = Vec3::new(
            u.light_radiance[0],
            u.light_radiance[1],
            u.light_radiance[2],
        ) * falloff;
        let pi = std::f32::consts::PI;
        let mut irradiance = if u.pattern == PATTERN_STEP {
            if world.x > 0.0 {
                radiance / pi
            } else {
                Vec3::ZERO
            }
        } else if u.pattern == PATTERN_CHECKERBOARD {
            let cell = (Vec2::new(world.x, world.y) / u.pattern_period).floor();
            if (cell.x as i32 + cell.y as i32) % 2 == 0 {
                radiance / pi
            } else {
                Vec3::ZERO
            }
        } else {
            let nl = n.dot(l).max(0.0);
            let shadow = if nl > 0.0 {
                self.shadow_factor(world, ng)
            } else {
                0.0
            };
            // The fill and rim: unshadowed N·L each (`shade`).
            let rig: Vec3 = (0..2)
                .map(|k| {
                    let l = Self::v4(u.rig_direction[k]).truncate();
                    Self::v4(u.rig_radiance[k]).truncate() * n.dot(l).max(0.0)
                })
                .sum();
            (radiance * (nl * shadow) + rig) / pi + self.environment(n)
        };
        let pre = u.pre_scatter_exponent;
        if pre > 0.0 {
            let tex = self
                .mips
                .albedo
                .sample(uv, lod(&self.mips.albedo), true)
                .truncate();
            let look = Vec3::new(
                u.surface_albedo[0],
                u.surface_albedo[1],
                u.surface_albedo[2],
            );
            // `shade` in shaders/scene.wgsl.
            let albedo = match u.albedo_map_mode {
                MAP_ABSOLUTE => tex,
                MAP_LOOK => look,
                _ => look * 2.0 * tex,
            };
            // Pre-and-post texturing is √albedo (pre = ½): sqrt, not powf.
            let a = albedo.max(Vec3::ZERO);
            irradiance *= if pre == 0.5 {
                Vec3::new(a.x.sqrt(), a.y.sqrt(), a.z.sqrt())
            } else {
                a.powf(pre)
            };
        }
        irradiance.into()
    }
}
