use super::*;
use crate::model::burley::Burley;
use crate::model::quad;
use crate::model::RadialProfile;

/// A square of side `size_mm` in z = 0 cut into 2·n² triangles.
pub(super) fn plane(size_mm: f32, n: usize) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            p.push(Vec3::new(
                (i as f32 / n as f32 - 0.5) * size_mm,
                (j as f32 / n as f32 - 0.5) * size_mm,
                0.0,
            ));
        }
    }
    let mut t = Vec::new();
    let id = |i: usize, j: usize| (j * (n + 1) + i) as u32;
    for j in 0..n {
        for i in 0..n {
            t.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
            t.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
        }
    }
    (p, t)
}

/// Irradiance from a function of the position (mm).
pub(super) struct ByPosition<'a> {
    pub(super) p: &'a [Vec3],
    pub(super) t: &'a [[u32; 3]],
    pub(super) f: &'a (dyn Fn(Vec3) -> [f32; 3] + Sync),
}

impl SurfaceIrradiance for ByPosition<'_> {
    fn at(&self, tri: usize, b: Vec3, _footprint: Footprint) -> [f32; 3] {
        let [i, j, k] = self.t[tri];
        (self.f)(self.p[i as usize] * b.x + self.p[j as usize] * b.y + self.p[k as usize] * b.z)
    }
}

pub(super) fn skin() -> Burley {
    Burley::from_scattering_distance([0.8; 3], [1.0, 0.5, 0.25]).unwrap()
}

/// Across a straight irradiance edge the exact 2D convolution is the
/// strip CDF Φ(x) (Jimenez 2015 §4), a closed form for Burley (Ki₁):
/// every point of a line across the edge within 0.002 of it (measured
/// 0.0010, 0.0008, 0.0012).
#[test]
fn straight_edge_follows_the_strip_cdf() {
    let profile = skin();
    let (p, t) = plane(80.0, 40);
    let f = |q: Vec3| if q.x > 0.0 { [1.0; 3] } else { [0.0; 3] };
    let irr = ByPosition {
        p: &p,
        t: &t,
        f: &f,
    };
    let cloud = Cloud::build(&p, &t, |_| true, &irr, ProfileTable::new(&profile), 0.5);
    let mut worst = [0.0f64; 3];
    for k in 0..=60 {
        let x = -3.0 + 0.1 * k as f64 + 0.013;
        let got = cloud.gather(&Probe::point(Vec3::new(x as f32, 0.37, 0.0)), &irr);
        let want = profile.strip_cdf(x);
        for c in 0..3 {
            worst[c] = worst[c].max((got[c] as f64 - want[c]).abs());
        }
    }
    eprintln!("worst |M − Φ| per channel {worst:?}");
    assert!(worst.iter().all(|w| *w < 0.002), "worst |M − Φ| {worst:?}");
}

/// The gather at `points` on a uniformly lit 80 mm plane.
fn on_a_uniformly_lit_plane(profile: &dyn RadialProfile, points: &[Vec3]) -> Vec<[f32; 3]> {
    let (p, t) = plane(80.0, 20);
    let f = |_: Vec3| [1.0; 3];
    let irr = ByPosition {
        p: &p,
        t: &t,
        f: &f,
    };
    let cloud = Cloud::build(&p, &t, |_| true, &irr, ProfileTable::new(profile), 0.5);
    points
        .iter()
        .map(|x| cloud.gather(&Probe::point(*x), &irr))
        .collect()
}

/// Uniform light on a plane: the sum holds each channel's energy up to
/// the stated truncation (≥ 99.9 %, ≤ 100.05 % with the quadrature).
#[test]
fn uniformly_lit_plane_keeps_its_energy() {
    let points = [Vec3::new(0.11, -0.27, 0.0), Vec3::new(1.3, 2.9, 0.0)];
    for (x, got) in points
        .iter()
        .zip(on_a_uniformly_lit_plane(&skin(), &points))
    {
        eprintln!("uniform plane at {x}: {got:?}");
        for c in 0..3 {
            assert!(
                (0.998..1.0005).contains(&got[c]),
                "channel {c}: {} at {x}",
                got[c]
            );
        }
    }
}

/// The exact near field at points beside, on and at the corners of cell
/// edges, with a profile far narrower than the cells (d = 5 µm in 0.5 mm
/// cells, the yardstick's d → 0 limit): uniform light must come back as
/// the plane's energy, 1 − (the truncation's 0.1 %) at most. Before the
/// angle about the edge's foot was the variable (`edge_fan`), 8 nodes
/// along an edge 1 µm from x returned −0.07 to 1.7 here.
#[test]
fn polar_weight_is_exact_beside_an_edge() {
    let profile = Burley::from_scattering_distance([0.8; 3], [0.005; 3]).unwrap();
    // The 80 mm plane of 20 × 20 squares: cells are 4 mm / 2^3 = 0.5 mm,
    // and the cell edges run along x = k/2 mm, y = k/2 mm and the diagonals.
    let mut points = Vec::new();
    for off in [0.0f32, 1e-4, 1e-3, 3e-3, 1e-2] {
        points.push(Vec3::new(0.5 + off, 0.31, 0.0)); // beside a vertical edge
        points.push(Vec3::new(0.27, 1.0 - off, 0.0)); // beside a horizontal edge
        points.push(Vec3::new(1.5 + off, 1.5 + off, 0.0)); // at a corner
        points.push(Vec3::new(0.3 + off, 0.3, 0.0)); // beside a diagonal
    }
    for (x, got) in points
        .iter()
        .zip(on_a_uniformly_lit_plane(&profile, &points))
    {
        for c in 0..3 {
            assert!(
                (0.998..1.0005).contains(&got[c]),
                "channel {c}: {} at {x}",
                got[c]
            );
        }
    }
}

/// A Jimenez 2012 look keeps 1 − strength of its energy as a Dirac at
/// r = 0 (the demo's lerp towards the centre): on a uniformly lit plane
/// it must still hold its energy when the shaded point sits 0.1 µm off
/// the surface, as f32 depth reconstruction leaves it (the Dirac was
/// lost there before: half of the demo skin's energy).
#[test]
fn a_dirac_part_survives_depth_noise() {
    let profile =
        crate::model::jimenez::Jimenez2012::new([0.48, 0.41, 0.28], [1.0, 0.37, 0.3]).unwrap();
    let points = [Vec3::new(0.11, -0.27, 0.0), Vec3::new(0.11, -0.27, 1e-4)];
    for (x, got) in points
        .iter()
        .zip(on_a_uniformly_lit_plane(&profile, &points))
    {
        eprintln!("Jimenez demo skin at {x}: {got:?}");
        for c in 0..3 {
            // Measured 0.9965 / 0.9997 / 0.9998 at both heights: the
            // truncation and 0.25 % of quadrature on the widest Gaussians.
            assert!(
                (0.995..1.0005).contains(&got[c]),
                "{x} channel {c}: {}",
                got[c]
            );
        }
    }
}

/// An 80 mm slab 1 mm thick: the plane z = 0 facing +z and its copy at
/// z = −1 facing −z.
pub(super) fn slab() -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let (mut p, mut t) = plane(80.0, 20);
    let n = p.len() as u32;
    let back: Vec<Vec3> = p.iter().map(|q| *q - Vec3::Z).collect();
    p.extend(back);
    let tris: Vec<[u32; 3]> = t.iter().map(|[a, b, c]| [a + n, c + n, b + n]).collect();
    t.extend(tris);
    (p, t)
}

/// The slab's light: its back face only.
pub(super) fn slab_light(q: Vec3) -> [f32; 3] {
    if q.z < -0.5 {
        [1.0; 3]
    } else {
        [0.0; 3]
    }
}

/// A slab t = 1 mm thick lit on its back face only: on the front face
/// the sum is the thin-slab transmittance T(t) = A/4 (e^(−t/d) +
/// 3e^(−t/3d)) (Burley's closed form, typed here) over the total A.
#[test]
fn back_lit_slab_transmits_t_of_t() {
    let profile = skin();
    let (p, t) = slab();
    let f = slab_light;
    let irr = ByPosition {
        p: &p,
        t: &t,
        f: &f,
    };
    let cloud = Cloud::build(&p, &t, |_| true, &irr, ProfileTable::new(&profile), 0.5);
    let got = cloud.gather(&Probe::point(Vec3::new(0.21, 0.34, 0.0)), &irr);
    for (c, d) in [1.0f64, 0.5, 0.25].into_iter().enumerate() {
        let want = 0.25 * ((-1.0 / d).exp() + 3.0 * (-1.0 / (3.0 * d)).exp());
        eprintln!("slab channel {c}: {} vs T(t)/A {want:.5}", got[c]);
        assert!(
            (got[c] as f64 / want - 1.0).abs() < 0.005,
            "channel {c}: {} vs {want}",
            got[c]
        );
    }
}

/// A UV sphere of radius `a` (mm) with `nu` × `nv` quads split in two.
pub(super) fn uv_sphere(a: f64, (nu, nv): (usize, usize)) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let mut p = Vec::new();
    for j in 0..=nv {
        let th = std::f64::consts::PI * j as f64 / nv as f64;
        for i in 0..nu {
            let ph = 2.0 * std::f64::consts::PI * i as f64 / nu as f64;
            p.push(Vec3::new(
                (a * th.sin() * ph.cos()) as f32,
                (a * th.sin() * ph.sin()) as f32,
                (a * th.cos()) as f32,
            ));
        }
    }
    let mut t = Vec::new();
    let id = |i: usize, j: usize| (j * nu + i % nu) as u32;
    for j in 0..nv {
        for i in 0..nu {
            t.push([id(i, j), id(i, j + 1), id(i + 1, j + 1)]);
            t.push([id(i, j), id(i + 1, j + 1), id(i + 1, j)]);
        }
    }
    (p, t)
}

/// The scattered light at polar angle `theta0` on a sphere of radius `a`
/// under a directional light along +z (E = max(n·z, 0)), channel `c`, by
/// nested adaptive quadrature (polar angle γ about the point, then
/// azimuth): M = ∫∫ ρ(2a sin(γ/2)) E(y) a² sin γ dγ dφ, with the chord
/// 2a sin(γ/2).
pub(super) fn sphere_by_quadrature(
    profile: &dyn RadialProfile,
    a: f64,
    theta0: f64,
    c: usize,
) -> f64 {
    let total = profile.total_reflectance();
    // y at angle γ from x (azimuth φ about x): its z coordinate.
    let inner = |g: f64| {
        let rho = profile.reflectance(2.0 * a * (0.5 * g).sin())[c] / total[c];
        let ring = |ph: f64| {
            let z = g.cos() * theta0.cos() - g.sin() * ph.cos() * theta0.sin();
            z.max(0.0)
        };
        let e = quad::integrate(&ring, 0.0, 2.0 * std::f64::consts::PI, 1e-12, 1e-10);
        rho * e * a * a * g.sin()
    };
    quad::integrate(&inner, 0.0, std::f64::consts::PI, 1e-10, 1e-8)
}

/// A sphere of radius 5 mm under a directional light along +z, E =
/// max(n·z, 0): at the pole facing the light, on the terminator and at
/// the dark pole, against the integral over the sphere by nested
/// adaptive quadrature ([`sphere_by_quadrature`]).
#[test]
fn sphere_lit_from_one_side_matches_quadrature() {
    let profile = Burley::from_scattering_distance([0.8; 3], [2.0, 1.0, 0.5]).unwrap();
    let a = 5.0f64;
    // A UV sphere, fine enough that its flat facets sit within 1 µm.
    let (p, t) = uv_sphere(a, (720, 360));
    let f = |q: Vec3| [(q.z / a as f32).max(0.0); 3];
    let irr = ByPosition {
        p: &p,
        t: &t,
        f: &f,
    };
    let cloud = Cloud::build(&p, &t, |_| true, &irr, ProfileTable::new(&profile), 0.5);
    for theta0 in [0.0f64, 0.5 * std::f64::consts::PI, std::f64::consts::PI] {
        let x = Vec3::new((a * theta0.sin()) as f32, 0.0, (a * theta0.cos()) as f32);
        let got = cloud.gather(&Probe::point(x), &irr);
        for c in 0..3 {
            let want = sphere_by_quadrature(&profile, a, theta0, c);
            eprintln!("sphere θ0 {theta0:.3} channel {c}: {} vs {want:.5}", got[c]);
            assert!(
                (got[c] as f64 - want).abs() < 0.003 + 0.005 * want,
                "θ0 {theta0:.3} channel {c}: {} vs {want}",
                got[c]
            );
        }
    }
}

/// Penner's table against the ground truth on the same sphere: a UV
/// sphere of radius c under a directional light along +z, E = max(n·z, 0),
/// gathered at 45°, 90° and 110° from the light, must give Penner's
/// D(θ, c) × CDF(2c) (the table is normalised by the energy that fits on
/// the sphere; the ground truth sums what lands on it) on 3 mm and 10 mm
/// spheres, for the default skin: measured within 3·10⁻⁴ (the 0.1 %
/// truncation on the 10 mm sphere), held to 10⁻³ (issue 22 asks 0.01). The
/// two share no code: the table is a 1D ring integral with the ring's
/// closed-form mean (model::lut), the ground truth a cloud of cells.
#[test]
fn penners_table_is_the_ground_truths_sphere() {
    use crate::model::lut::preintegrated_d;
    let profile =
        Burley::from_scattering_distance([0.91058, 0.338275, 0.2718], [0.7568628, 0.32156864, 0.2])
            .unwrap();
    for c in [3.0f64, 10.0] {
        let (p, t) = uv_sphere(c, (720, 360));
        let f = |q: Vec3| [(q.z / c as f32).max(0.0); 3];
        let irr = ByPosition {
            p: &p,
            t: &t,
            f: &f,
        };
        let cloud = Cloud::build(&p, &t, |_| true, &irr, ProfileTable::new(&profile), 0.5);
        let cdf = profile.cdf(2.0 * c);
        for deg in [45.0f64, 90.0, 110.0] {
            let th = deg.to_radians();
            // Off the UV grid's meridians, on the sphere.
            let (ph, thf) = (0.0123f64, th);
            let x = Vec3::new(
                (c * thf.sin() * ph.cos()) as f32,
                (c * thf.sin() * ph.sin()) as f32,
                (c * thf.cos()) as f32,
            );
            let got = cloud.gather(&Probe::point(x), &irr);
            let d = preintegrated_d(&profile, th, c);
            for ch in 0..3 {
                let want = d[ch] * cdf[ch];
                eprintln!(
                    "c {c} θ {deg}° channel {ch}: ground truth {:.5} vs D·CDF {want:.5}",
                    got[ch]
                );
                assert!(
                    (got[ch] as f64 - want).abs() < 1e-3,
                    "c {c} θ {deg}° {ch}: {} vs {want}",
                    got[ch]
                );
            }
        }
    }
}

/// The table's index log against std's f64 ln (the judge), from the
/// smallest radius a table holds to beyond the largest, across every
/// mantissa: within 4e-6 absolute, f32's rounding of ln x up to |ln x| = 21
/// (a table step is ln(range)/2047, about 0.008, so the index moves by
/// under 1e-3 of a step).
#[test]
fn fast_ln_matches_ln() {
    let mut worst = 0.0f64;
    let mut x = 1e-9f64;
    while x < 1e6 {
        let got = super::table::fast_ln(x as f32) as f64;
        let want = (x as f32 as f64).ln();
        worst = worst.max((got - want).abs());
        x *= 1.0007;
    }
    eprintln!("worst |fast_ln − ln| {worst:e}");
    assert!(worst < 4e-6, "worst {worst:e}");
}
