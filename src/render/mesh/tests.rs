/// A negative (relative) face index before the first normal (the
/// fuzzer's find: tobj overflowed on it) is refused by line.
#[test]
fn relative_indices_before_the_start_are_refused() {
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//-41 2//1 3//1\n";
    let e = Mesh::from_obj_text(obj, "rel.obj", 0.01)
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("rel.obj") && e.contains("line 5"), "{e}");
    let ok = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\nf -3/-3 -2/-2 -1/-1\n";
    assert!(Mesh::from_obj_text(ok, "ok.obj", 0.01).is_ok());
}

/// A normal index of 8.9·10¹⁸ (the fuzzer's find: 3 × index overflowed in
/// tobj) is refused by line, naming the file's one normal; a face that
/// names a vertex defined after it (OBJ allows it) still loads.
#[test]
fn indices_beyond_the_file_are_refused() {
    let obj =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\nf 1/1/1 2/1/1 3/1/8888888888888888882\n";
    let e = Mesh::from_obj_text(obj, "far.obj", 0.01)
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("far.obj") && e.contains("line 6") && e.contains("1 normal"),
        "{e}"
    );
    let forward = "vt 0 0\nvt 1 0\nvt 0 1\nf 1/1 2/2 3/3\nv 0 0 0\nv 1 0 0\nv 0 1 0\n";
    assert!(Mesh::from_obj_text(forward, "forward.obj", 0.01).is_ok());
}

/// A vertex at 4.4·10²¹ units (the fuzzer's find: the squared extent
/// overflowed and the thickness bake never ended) is refused by name.
#[test]
fn far_vertices_are_refused() {
    let obj = "v -0.5 -0.5 0\nv 0.5 -0.5 0\nv 0.5 0.5 4444444444444444444440\nvt 0 0\nvt 1 0\nvt 1 1\nf 1/1 2/2 3/3\n";
    let e = Mesh::from_obj_text(obj, "far.obj", 0.01)
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("far.obj") && e.contains("vertex 3"), "{e}");
}

use super::*;

#[test]
fn default_head_loads_with_three_materials() {
    let m = Mesh::default_head().unwrap();
    assert!(
        m.indices.len() / 3 > 8000,
        "{} triangles",
        m.indices.len() / 3
    );
    let (lo, hi) = m.bounds();
    // About 31 cm from collar to crown at 0.1 m per unit.
    assert!((hi.y - lo.y) * m.metres_per_unit > 0.25 && (hi.y - lo.y) * m.metres_per_unit < 0.35);
    for mat in [0.0, 1.0, 2.0] {
        assert!(
            m.vertices.iter().any(|v| v.material == mat),
            "material {mat}"
        );
    }
    assert!(m
        .vertices
        .iter()
        .all(|v| (Vec3::from(v.normal).length() - 1.0).abs() < 1e-3));
}

/// An OBJ of a (nu × nv)-quad grid closed in u (a band: sphere, cylinder),
/// its vertex at grid point (i, j) at `point(i/nu, j/nv)` with that UV; the
/// quads wound (a, b, b + nu, a + nu), or the other way with `flip`.
fn wrapped_grid_obj(
    (nu, nv): (u32, u32),
    flip: bool,
    point: impl Fn(f32, f32) -> [f32; 3],
) -> String {
    let mut obj = String::new();
    for j in 0..=nv {
        for i in 0..nu {
            let (u, v) = (i as f32 / nu as f32, j as f32 / nv as f32);
            let p = point(u, v);
            obj += &format!("v {} {} {}\nvt {u} {v}\n", p[0], p[1], p[2]);
        }
    }
    for j in 0..nv {
        for i in 0..nu {
            let a = j * nu + i + 1;
            let b = j * nu + (i + 1) % nu + 1;
            let (c, d) = (b + nu, a + nu);
            obj += &if flip {
                format!("f {d}/{d} {c}/{c} {b}/{b} {a}/{a}\n")
            } else {
                format!("f {a}/{a} {b}/{b} {c}/{c} {d}/{d}\n")
            };
        }
    }
    obj
}

/// A UV sphere of radius 5 units (48 × 24), its faces wound outwards, or
/// inwards with `inside` (the surface seen from within: a hollow).
fn sphere_obj(inside: bool) -> String {
    wrapped_grid_obj((48, 24), inside, |u, v| {
        let (th, ph) = (std::f32::consts::PI * v, std::f32::consts::TAU * u);
        [
            5.0 * th.sin() * ph.cos(),
            5.0 * th.cos(),
            5.0 * th.sin() * ph.sin(),
        ]
    })
}

/// A sphere of radius ρ has mean curvature 1/ρ everywhere (away from the
/// poles), and thickness 2ρ.
#[test]
fn sphere_curvature_is_one_over_radius() {
    let obj = sphere_obj(false);
    // 5 units at 0.01 m per unit: radius 50 mm.
    let m = Mesh::from_obj_text(&obj, "sphere", 0.01).unwrap();
    // Inward rays cross the sphere: thickness is its diameter, 100 mm
    // (within the chord error of a 48×24 tessellation).
    for v in m.vertices.iter().filter(|v| v.position[1].abs() < 3.0) {
        assert!(
            (v.thickness_mm - 100.0).abs() < 1.5,
            "thickness {}",
            v.thickness_mm
        );
    }
    for v in m.vertices.iter().filter(|v| v.position[1].abs() < 3.0) {
        assert!(
            (v.curvature_per_mm - 1.0 / 50.0).abs() < 0.002,
            "{}",
            v.curvature_per_mm
        );
    }
}

/// The same sphere seen from inside (faces wound inwards, so its normals
/// point to the centre) is hollow: H = −1/ρ, and Penner's table takes a
/// hollow as flat (0).
#[test]
fn hollow_curvature_is_flat() {
    let m = Mesh::from_obj_text(&sphere_obj(true), "hollow", 0.01).unwrap();
    let centre_ward = m
        .vertices
        .iter()
        .filter(|v| v.position[1].abs() < 3.0)
        .all(|v| Vec3::from(v.normal).dot(Vec3::from(v.position)) < 0.0);
    assert!(
        centre_ward,
        "the normals of the inward-wound sphere point out"
    );
    for v in &m.vertices {
        assert_eq!(v.curvature_per_mm, 0.0);
    }
}

/// An open cylinder of radius ρ = 50 mm: mean curvature (0 + 1/ρ)/2 =
/// 1/(2ρ) away from its two cut ends (do Carmo 1976, §3-3: H is the mean of
/// the principal curvatures), and its boundary rows take their inner
/// neighbours' value.
#[test]
fn cylinder_curvature_is_half_over_radius() {
    // Radius 5 units, 10 units tall.
    let obj = wrapped_grid_obj((64, 20), false, |u, v| {
        let ph = std::f32::consts::TAU * u;
        [5.0 * ph.cos(), 10.0 * v, -5.0 * ph.sin()]
    });
    let m = Mesh::from_obj_text(&obj, "cylinder", 0.01).unwrap();
    let outward = m.vertices.iter().all(|v| {
        let radial = Vec3::new(v.position[0], 0.0, v.position[2]);
        Vec3::from(v.normal).dot(radial) > 0.0
    });
    assert!(
        outward,
        "the cylinder's normals point inwards: wind it the other way"
    );
    for v in &m.vertices {
        assert!(
            (v.curvature_per_mm - 1.0 / 100.0).abs() < 0.0005,
            "at y {}: {}",
            v.position[1],
            v.curvature_per_mm
        );
    }
}

/// MikkTSpace tangents on a plane unwrapped with u along +x and v (up the
/// image) along +y: T = +x, and B = w N × T = +y needs w = +1; mirroring
/// u flips T and w.
#[test]
fn tangents_follow_the_uv_layout() {
    let quad = |u0: f32, u1: f32| {
        format!(
            "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt {u0} 0\nvt {u1} 0\nvt {u1} 1\nvt {u0} 1\nf 1/1 2/2 3/3 4/4\n"
        )
    };
    let m = Mesh::from_obj_text(&quad(0.0, 1.0), "quad", 1.0).unwrap();
    for v in &m.vertices {
        let t = Vec3::from_slice(&v.tangent[..3]);
        assert!((t - Vec3::X).length() < 1e-5, "{:?}", v.tangent);
        assert_eq!(v.tangent[3], 1.0);
        let b = Vec3::from(v.normal).cross(t) * v.tangent[3];
        assert!((b - Vec3::Y).length() < 1e-5);
    }
    let mirrored = Mesh::from_obj_text(&quad(1.0, 0.0), "quad", 1.0).unwrap();
    for v in &mirrored.vertices {
        let t = Vec3::from_slice(&v.tangent[..3]);
        assert!((t + Vec3::X).length() < 1e-5, "{:?}", v.tangent);
        assert_eq!(v.tangent[3], -1.0, "B must still point up the image");
    }
}

#[test]
fn meshes_without_usable_uvs_are_refused() {
    let e = Mesh::from_obj_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "bare.obj", 1.0)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("bare.obj") && e.contains("no texture coordinates"),
        "{e}"
    );
    let nan = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt nan 1\nf 1/1 2/2 3/3\n";
    let e = Mesh::from_obj_text(nan, "nan_uv.obj", 1.0)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("nan_uv.obj") && e.contains("non-finite UV"),
        "{e}"
    );
    let flat = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.5 0.5\nf 1/1 2/1 3/1\n";
    let e = Mesh::from_obj_text(flat, "flat.obj", 1.0)
        .unwrap_err()
        .to_string();
    assert!(e.contains("flat.obj") && e.contains("zero area"), "{e}");
}

#[test]
fn bad_obj_is_an_error() {
    assert!(Mesh::from_obj_text("v 0 0 0\n", "empty.obj", 1.0).is_err());
    assert!(Mesh::load_obj(Path::new("/no/such.obj"), 1.0)
        .unwrap_err()
        .to_string()
        .contains("/no/such.obj"));
}
