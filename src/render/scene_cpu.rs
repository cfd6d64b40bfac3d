//! The scene pass's diffuse target evaluated on the CPU at any point of
//! the mesh, seen by the camera or not: what the ground truth
//! (`render::ground_truth`) integrates. A twin of `fs_main` in
//! `shaders/scene.wgsl` for the SSS surface, line for line: the light
//! (directional or point, `light_at`), its PCF shadow from the same shadow
//! map read back from the GPU (`shadow_factor`: 3×3 bilinear comparison
//! taps, LessEqual, clamp to edge), the SH environment
//! (`environment_irradiance`), the tangent-space normal map, the irradiance
//! test patterns, and albedo^pre of the texturing mode. Textures are read
//! at their full resolution (the GPU picks a mip level from the screen
//! footprint; a point unseen by the camera has none). Transmission is not
//! added: light through thin parts reaches the ground truth as irradiance
//! on the far side's cells. Eyes and teeth (material ≠ 0) and texels
//! outside the SSS mask (mask ≤ 1/255) are not SSS surface and give 0.
//! Checked against the GPU's own diffuse target on the visible pixels:
//! `scene_twin_matches_the_scene_pass` in tests/render_physics.rs.

use super::gpu_types::{SceneUniforms, MAP_ABSOLUTE, PATTERN_CHECKERBOARD, PATTERN_STEP};
use super::ground_truth::SurfaceIrradiance;
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

/// The scene's lighting and surface, for [`SurfaceIrradiance`].
pub struct SceneIrradiance<'a> {
    mesh: &'a Mesh,
    u: SceneUniforms,
    light_clip: Mat4,
    shadow: &'a ShadowMap,
}

impl<'a> SceneIrradiance<'a> {
    pub fn new(mesh: &'a Mesh, u: SceneUniforms, shadow: &'a ShadowMap) -> Self {
        Self {
            mesh,
            light_clip: Mat4::from_cols_array_2d(&u.light_clip_from_world),
            u,
            shadow,
        }
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
            let v = t.texels.get(k + c.min(ch - 1)).copied().unwrap_or(0) as f32 / 255.0;
            if srgb && c < 3 {
                if v <= 0.04045 {
                    v / 12.92
                } else {
                    ((v + 0.055) / 1.055).powf(2.4)
                }
            } else {
                v
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
    fn at(&self, triangle: usize, b: Vec3) -> [f32; 3] {
        let m = self.mesh;
        let idx = &m.indices[3 * triangle..3 * triangle + 3];
        let v = [0, 1, 2].map(|k| &m.vertices[idx[k] as usize]);
        let w = [b.x, b.y, b.z];
        let mix3 = |f: &dyn Fn(usize) -> Vec3| f(0) * w[0] + f(1) * w[1] + f(2) * w[2];
        let material = v[0].material * w[0] + v[1].material * w[1] + v[2].material * w[2];
        if material > 0.5 {
            return [0.0; 3];
        }
        let world = mix3(&|k| Vec3::from(v[k].position));
        let uv =
            Vec2::from(v[0].uv) * w[0] + Vec2::from(v[1].uv) * w[1] + Vec2::from(v[2].uv) * w[2];
        let maps = &m.textures;
        let mask = sample(&maps.mask, uv, false).x.clamp(0.0, 1.0);
        if mask <= 1.0 / 255.0 {
            return [0.0; 3];
        }
        let u = &self.u;
        let ng = mix3(&|k| Vec3::from(v[k].normal)).normalize_or_zero();
        let tangent = Vec4::from(v[0].tangent) * w[0]
            + Vec4::from(v[1].tangent) * w[1]
            + Vec4::from(v[2].tangent) * w[2];
        let mut n = ng;
        let t_raw = tangent.truncate() - ng * ng.dot(tangent.truncate());
        if t_raw.length_squared() > 1e-12 && u.detail_normal_strength > 0.0 {
            let nt = sample(&maps.normal, uv, false).truncate() * 2.0 - Vec3::ONE;
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
            radiance * (nl * shadow) / pi + self.environment(n)
        };
        let pre = u.pre_scatter_exponent;
        if pre > 0.0 {
            let tex = sample(&maps.albedo, uv, true).truncate();
            let albedo = if u.albedo_map_mode == MAP_ABSOLUTE {
                tex
            } else {
                Vec3::new(
                    u.surface_albedo[0],
                    u.surface_albedo[1],
                    u.surface_albedo[2],
                ) * 2.0
                    * tex
            };
            irradiance *= albedo.max(Vec3::ZERO).powf(pre);
        }
        irradiance.into()
    }
}
