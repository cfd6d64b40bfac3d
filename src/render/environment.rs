//! The environment light: a procedural sky or an equirectangular HDR map,
//! projected to order-2 spherical harmonics and convolved with the clamped
//! cosine (Ramamoorthi & Hanrahan 2001), so the scene shader evaluates the
//! diffuse irradiance E(n) with nine coefficients.

use glam::Vec3;
use std::path::Path;

/// Radiance over the sphere of directions.
#[derive(Debug, Clone, PartialEq)]
pub enum Environment {
    /// Zenith and horizon colours above the horizon (blended by
    /// elevation), and a uniform ground below; linear radiance.
    Sky {
        zenith: [f32; 3],
        horizon: [f32; 3],
        ground: [f32; 3],
    },
    /// An equirectangular (latitude-longitude) radiance map: row 0 looks
    /// up, the centre column looks down −z (towards the default head's
    /// back), u runs with the azimuth. Linear RGB, row-major.
    Map {
        width: usize,
        height: usize,
        texels: Vec<[f32; 3]>,
    },
}

impl Default for Environment {
    /// A studio sky as fill: cool zenith, neutral horizon, warm dark
    /// floor. Its irradiance on a face is about 15 % of the key light's
    /// (π·0.15 against 3.2), a 6:1 key-to-fill ratio, inside the 4:1–8:1
    /// of portrait lighting, so the side away from the key (and the eye
    /// there) stays readable; at a third of this (20:1) that eye read as
    /// a hole.
    fn default() -> Self {
        Environment::Sky {
            zenith: [0.15, 0.174, 0.216],
            horizon: [0.126, 0.132, 0.144],
            ground: [0.06, 0.054, 0.048],
        }
    }
}

/// Largest accepted texel value: the sun in a real HDR capture is ~10⁵–10⁶;
/// RGBE can encode ~10³⁸, which overflowed the SH projection to ∞ (found by
/// fuzzing).
pub const MAX_RADIANCE: f32 = 1e9;

#[derive(Debug, thiserror::Error)]
pub enum EnvironmentError {
    #[error("{path}: cannot read the environment map: {message}")]
    Load { path: String, message: String },
    #[error("{path}: the environment map has a non-finite, negative or absurd (> {MAX_RADIANCE:e}) texel at ({x}, {y})")]
    BadTexel { path: String, x: usize, y: usize },
}

/// The sRGB transfer function inverted (IEC 61966-2-1): an encoded value
/// in [0, 1] to linear.
pub(crate) fn srgb_to_linear(c: f32) -> f32 {
    crate::model::colour::srgb_to_linear(c)
}

impl Environment {
    /// Loads a Radiance .hdr (or any image; LDR images are decoded as sRGB
    /// and linearised) as an equirectangular map.
    pub fn load(path: &Path) -> Result<Self, EnvironmentError> {
        let origin = path.display().to_string();
        let img = super::textures::decode_bounded(path).map_err(|e| EnvironmentError::Load {
            path: origin.clone(),
            message: e.to_string(),
        })?;
        let (width, height) = (img.width() as usize, img.height() as usize);
        // An 8-bit image (most LDR maps): sRGB decoded through a table
        // of its 256 codes (IEC 61966-2-1 inverse transfer), straight from
        // the bytes. The float path below costs three copies and a powf a
        // channel: a 61-megapixel JPEG the fuzzer made took 2.1 s and
        // 2 GB there (docs/robustness.md).
        if let image::DynamicImage::ImageRgb8(_)
        | image::DynamicImage::ImageRgba8(_)
        | image::DynamicImage::ImageLuma8(_)
        | image::DynamicImage::ImageLumaA8(_) = img
        {
            let table: [f32; 256] = std::array::from_fn(|code| srgb_to_linear(code as f32 / 255.0));
            let rgb = img.into_rgb8();
            let texels = rgb
                .pixels()
                .map(|p| p.0.map(|c| table[c as usize]))
                .collect();
            return Ok(Environment::Map {
                width,
                height,
                texels,
            });
        }
        let hdr = matches!(
            img,
            image::DynamicImage::ImageRgb32F(_) | image::DynamicImage::ImageRgba32F(_)
        );
        let rgb = img.into_rgb32f();
        let lin = |c: f32| if hdr { c } else { srgb_to_linear(c) };
        let mut texels = Vec::with_capacity(width * height);
        for (i, p) in rgb.pixels().enumerate() {
            if p.0
                .iter()
                .any(|c| !c.is_finite() || *c < 0.0 || *c > MAX_RADIANCE)
            {
                return Err(EnvironmentError::BadTexel {
                    path: origin,
                    x: i % width,
                    y: i / width,
                });
            }
            texels.push(p.0.map(lin));
        }
        Ok(Environment::Map {
            width,
            height,
            texels,
        })
    }

    /// Radiance arriving from direction `d` (unit).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        match self {
            Environment::Sky {
                zenith,
                horizon,
                ground,
            } => {
                if d.y < 0.0 {
                    Vec3::from(*ground)
                } else {
                    Vec3::from(*horizon).lerp(Vec3::from(*zenith), d.y.sqrt())
                }
            }
            Environment::Map {
                width,
                height,
                texels,
            } => {
                let (u, v) = direction_to_equirect(d);
                let x = ((u * *width as f32) as usize).min(width - 1);
                let y = ((v * *height as f32) as usize).min(height - 1);
                Vec3::from(texels[y * width + x])
            }
        }
    }

    /// Nine SH coefficients of the irradiance divided by π, E(n)/π =
    /// Σ c_i Y_i(n): what a white Lambertian surface reflects. Integrated
    /// over a 128 × 256 latitude-longitude grid (or the map's own texels).
    pub fn irradiance_sh(&self) -> [[f32; 3]; 9] {
        let (rows, cols) = match self {
            Environment::Map { width, height, .. } => (*height, *width),
            Environment::Sky { .. } => (128, 256),
        };
        let mut l = [Vec3::ZERO; 9];
        for j in 0..rows {
            let theta = std::f32::consts::PI * (j as f32 + 0.5) / rows as f32;
            let d_omega = std::f32::consts::PI / rows as f32 * std::f32::consts::TAU / cols as f32
                * theta.sin();
            for i in 0..cols {
                let u = (i as f32 + 0.5) / cols as f32;
                let d = equirect_to_direction(u, (j as f32 + 0.5) / rows as f32);
                let radiance = self.radiance(d);
                for (k, y) in sh9(d).iter().enumerate() {
                    l[k] += radiance * (*y * d_omega);
                }
            }
        }
        // Clamped-cosine convolution: Â_0 = π, Â_1 = 2π/3, Â_2 = π/4; ÷ π.
        let band = [
            1.0,
            2.0 / 3.0,
            2.0 / 3.0,
            2.0 / 3.0,
            0.25,
            0.25,
            0.25,
            0.25,
            0.25,
        ];
        std::array::from_fn(|k| (l[k] * band[k]).into())
    }
}

/// An environment map as the viewport's background: linear RGB at most
/// `max_width` wide (2×2 box means down from the map), row-major, the
/// equirectangular layout of [`Environment::Map`].
#[derive(Debug, Clone, PartialEq)]
pub struct BackgroundMap {
    pub width: u32,
    pub height: u32,
    pub texels: Vec<[f32; 3]>,
}

impl BackgroundMap {
    /// `env`'s map (none for the procedural sky), halved until it is at
    /// most `max_width` wide and high.
    pub fn of(env: &Environment, max_width: usize) -> Option<Self> {
        let Environment::Map {
            width,
            height,
            texels,
        } = env
        else {
            return None;
        };
        let mut m = Self {
            width: *width as u32,
            height: *height as u32,
            texels: texels.clone(),
        };
        while m.width as usize > max_width.max(2) || m.height as usize > max_width.max(2) {
            m = m.half();
        }
        Some(m)
    }

    /// The next level down: each output texel the mean of a 2×2 block
    /// (odd edges clamp).
    pub fn half(&self) -> Self {
        let (w, h) = ((self.width / 2).max(1), (self.height / 2).max(1));
        let at = |x: u32, y: u32| {
            let (x, y) = (x.min(self.width - 1), y.min(self.height - 1));
            self.texels[(y * self.width + x) as usize]
        };
        let texels = (0..h)
            .flat_map(|y| (0..w).map(move |x| (x, y)))
            .map(|(x, y)| {
                let q = [
                    at(2 * x, 2 * y),
                    at(2 * x + 1, 2 * y),
                    at(2 * x, 2 * y + 1),
                    at(2 * x + 1, 2 * y + 1),
                ];
                std::array::from_fn(|c| q.iter().map(|t| t[c]).sum::<f32>() / 4.0)
            })
            .collect();
        Self {
            width: w,
            height: h,
            texels,
        }
    }
}

/// The irradiance SH `sh` ([`Environment::irradiance_sh`]) of an
/// environment turned by `angle_rad` about the up axis (y), so that what
/// was seen along u is seen along u + angle/2π: the coefficients of
/// E(R⁻¹ n) projected back on the basis. The projection is exact (up to
/// rounding): E∘R⁻¹ lies in bands 0–2, a product of two such functions is
/// a polynomial of degree 4, and Gauss–Legendre in cos θ with 4 nodes
/// (exact to degree 7) times 12 equal azimuths (exact for frequencies
/// under 12) integrates it exactly.
pub fn rotate_sh_about_up(sh: &[[f32; 3]; 9], angle_rad: f32) -> [[f32; 3]; 9] {
    if angle_rad == 0.0 {
        return *sh;
    }
    // Gauss–Legendre nodes and weights on [−1, 1], n = 4.
    const NODES: [(f64, f64); 4] = [
        (-0.861_136_311_594_053, 0.347_854_845_137_454),
        (-0.339_981_043_584_856, 0.652_145_154_862_546),
        (0.339_981_043_584_856, 0.652_145_154_862_546),
        (0.861_136_311_594_053, 0.347_854_845_137_454),
    ];
    const AZIMUTHS: usize = 12;
    let (s, c) = (angle_rad as f64).sin_cos();
    let mut out = [[0.0f64; 3]; 9];
    for (y, wy) in NODES {
        let r = (1.0 - y * y).sqrt();
        for k in 0..AZIMUTHS {
            let phi = std::f64::consts::TAU * (k as f64 + 0.5) / AZIMUTHS as f64;
            let d = Vec3::new((r * phi.sin()) as f32, y as f32, (-r * phi.cos()) as f32);
            // R⁻¹ d: turned back by the angle about y (the azimuth of
            // `equirect_to_direction`, atan2(x, −z), goes down by it).
            let back = Vec3::new(
                (d.x as f64 * c + d.z as f64 * s) as f32,
                d.y,
                (-(d.x as f64) * s + d.z as f64 * c) as f32,
            );
            let basis_back = sh9(back);
            let basis = sh9(d);
            let w = wy * std::f64::consts::TAU / AZIMUTHS as f64;
            for ch in 0..3 {
                let f: f64 = (0..9)
                    .map(|j| sh[j][ch] as f64 * basis_back[j] as f64)
                    .sum();
                for (i, b) in basis.iter().enumerate() {
                    out[i][ch] += w * f * *b as f64;
                }
            }
        }
    }
    out.map(|c| c.map(|v| v as f32))
}

/// Real SH basis up to l = 2 (Ramamoorthi & Hanrahan's constants), in the
/// order the scene shader uses.
pub fn sh9(d: Vec3) -> [f32; 9] {
    [
        0.282_095,
        0.488_603 * d.y,
        0.488_603 * d.z,
        0.488_603 * d.x,
        1.092_548 * d.x * d.y,
        1.092_548 * d.y * d.z,
        0.315_392 * (3.0 * d.z * d.z - 1.0),
        1.092_548 * d.x * d.z,
        0.546_274 * (d.x * d.x - d.y * d.y),
    ]
}

fn direction_to_equirect(d: Vec3) -> (f32, f32) {
    let u = 0.5 + d.x.atan2(-d.z) / std::f32::consts::TAU;
    let v = d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI;
    (u.rem_euclid(1.0), v)
}

fn equirect_to_direction(u: f32, v: f32) -> Vec3 {
    let phi = (u - 0.5) * std::f32::consts::TAU;
    let theta = v * std::f32::consts::PI;
    Vec3::new(
        theta.sin() * phi.sin(),
        theta.cos(),
        -theta.sin() * phi.cos(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An 8-bit map is linearised by the sRGB curve (IEC 61966-2-1):
    /// code 128 is 0.21586 linear and code 10 is 10/255/12.92 (the linear
    /// toe), as published tables give them; 255 is 1 and 0 is 0.
    #[test]
    fn eight_bit_maps_are_linearised_by_the_srgb_curve() {
        let path = std::env::temp_dir().join(format!("scatterlab-env8-{}.png", std::process::id()));
        image::RgbImage::from_raw(2, 1, vec![10, 128, 255, 0, 0, 0])
            .unwrap()
            .save(&path)
            .unwrap();
        let Environment::Map { width, texels, .. } = Environment::load(&path).unwrap() else {
            panic!("not a map");
        };
        std::fs::remove_file(&path).unwrap();
        assert_eq!((width, texels.len()), (2, 2));
        let [toe, mid, one] = texels[0];
        assert!((toe - 10.0 / 255.0 / 12.92).abs() < 1e-7, "{toe}");
        assert!((mid - 0.215_86).abs() < 1e-5, "{mid}");
        assert_eq!(one, 1.0);
        assert_eq!(texels[1], [0.0; 3]);
    }

    /// A Radiance file whose RGBE texels decode to ~10³⁸ (the fuzzer's
    /// find: its SH projection overflowed to ∞) is refused by name.
    #[test]
    fn absurd_radiance_is_refused() {
        let hex = "233f52414449414e43450a462f4f726762895022470d0a1a0a0000950a0a2d592032202b5820340a808080ffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffffff80808180808081";
        let bytes: Vec<u8> = (0..hex.len() / 2)
            .map(|i| u8::from_str_radix(&hex[2 * i..2 * i + 2], 16).unwrap())
            .collect();
        let path =
            std::env::temp_dir().join(format!("scatterlab-absurd-{}.hdr", std::process::id()));
        std::fs::write(&path, bytes).unwrap();
        let e = Environment::load(&path)
            .map(|_| ())
            .unwrap_err()
            .to_string();
        std::fs::remove_file(&path).unwrap();
        assert!(
            e.contains("scatterlab-absurd-") && e.contains("absurd"),
            "{e}"
        );
    }

    fn eval(c: &[[f32; 3]; 9], n: Vec3) -> Vec3 {
        sh9(n).iter().zip(c).map(|(y, c)| Vec3::from(*c) * *y).sum()
    }

    /// L(ω) = a + b·ω_y is linear, so order-2 SH are exact:
    /// E(n)/π = a + (2/3)·b·n_y (∫ max(cos θ, 0)(a + b ω·ŷ) dω / π).
    #[test]
    fn linear_radiance_gives_the_closed_form_irradiance() {
        let (a, b) = (0.7f32, 0.3f32);
        let w = 256;
        let h = 128;
        let texels = (0..h)
            .flat_map(|j| {
                (0..w).map(move |i| {
                    let d = equirect_to_direction(
                        (i as f32 + 0.5) / w as f32,
                        (j as f32 + 0.5) / h as f32,
                    );
                    [a + b * d.y; 3]
                })
            })
            .collect();
        let env = Environment::Map {
            width: w,
            height: h,
            texels,
        };
        let c = env.irradiance_sh();
        for n in [
            Vec3::Y,
            -Vec3::Y,
            Vec3::X,
            Vec3::new(0.3, 0.5, -0.8).normalize(),
        ] {
            let want = a + 2.0 / 3.0 * b * n.y;
            let got = eval(&c, n);
            assert!((got.x - want).abs() < 2e-3, "n={n}: {got} vs {want}");
        }
    }

    /// A sky over a ground: E/π = sky·(1 + n_y)/2 + ground·(1 − n_y)/2
    /// exactly; order-2 SH follow it within 6 % of the sky at every normal
    /// (the cosine lobe's band limit; Ramamoorthi & Hanrahan 2001).
    #[test]
    fn two_hemispheres_match_the_exact_irradiance() {
        let env = Environment::Sky {
            zenith: [1.0; 3],
            horizon: [1.0; 3],
            ground: [0.0; 3],
        };
        let c = env.irradiance_sh();
        for k in 0..=20 {
            let ny = -1.0 + k as f32 / 10.0;
            let n = Vec3::new((1.0 - ny * ny).max(0.0).sqrt(), ny, 0.0);
            let got = eval(&c, n).x;
            let want = 0.5 * (1.0 + ny);
            assert!((got - want).abs() < 0.06, "n_y={ny}: {got} vs {want}");
        }
    }

    #[test]
    fn equirect_round_trips() {
        for d in [
            Vec3::X,
            Vec3::Y * 0.999,
            -Vec3::Z,
            Vec3::new(0.2, -0.4, 0.6).normalize(),
        ] {
            let (u, v) = direction_to_equirect(d.normalize());
            assert!((equirect_to_direction(u, v) - d.normalize()).length() < 1e-4);
        }
    }

    #[test]
    fn bad_maps_are_refused_with_the_path() {
        let e = Environment::load(Path::new("/no/such/sky.hdr")).unwrap_err();
        assert!(e.to_string().contains("/no/such/sky.hdr"));
    }
}

#[cfg(test)]
mod rotation_tests {
    use super::*;

    /// Turning the SH by a quarter turn gives the SH of the map with its
    /// columns moved a quarter along u (projected independently, texel by
    /// texel); turning back gives the original.
    #[test]
    fn turned_sh_is_the_sh_of_the_turned_map() {
        let (w, h) = (64, 32);
        let texels: Vec<[f32; 3]> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                let u = x as f32 / w as f32;
                [
                    1.0 + (std::f32::consts::TAU * u).sin(),
                    0.5 + 0.5 * (y as f32 / h as f32),
                    (2.0 * std::f32::consts::TAU * u).cos().abs(),
                ]
            })
            .collect();
        let shifted: Vec<[f32; 3]> = (0..w * h)
            .map(|i| {
                let (x, y) = (i % w, i / w);
                texels[y * w + (x + w - w / 4) % w]
            })
            .collect();
        let sh = Environment::Map {
            width: w,
            height: h,
            texels,
        }
        .irradiance_sh();
        let want = Environment::Map {
            width: w,
            height: h,
            texels: shifted,
        }
        .irradiance_sh();
        let got = rotate_sh_about_up(&sh, std::f32::consts::FRAC_PI_2);
        for k in 0..9 {
            for c in 0..3 {
                assert!(
                    (got[k][c] - want[k][c]).abs() < 2e-3,
                    "coefficient {k}: {} against {}",
                    got[k][c],
                    want[k][c]
                );
            }
        }
        let back = rotate_sh_about_up(&got, -std::f32::consts::FRAC_PI_2);
        for k in 0..9 {
            for c in 0..3 {
                assert!((back[k][c] - sh[k][c]).abs() < 1e-4);
            }
        }
    }
}
