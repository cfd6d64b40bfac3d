use super::*;

/// tan(15°) = 0.267949: a 0.308 m head at 30° is framed from
/// 0.154 / 0.267949 = 0.5747 m; the default head (0.3077 m tall) lands
/// within 5 % of the 0.55 m its views used before framing existed.
#[test]
fn framing_by_hand_and_the_default_head() {
    let d = framing_distance_m(0.308, 30f32.to_radians());
    assert!((d - 0.5747).abs() < 1e-3, "{d}");
    let head = Mesh::default_head().unwrap();
    let d = head.framing_distance_m(30f32.to_radians());
    assert!(
        (d / 0.55 - 1.0).abs() < 0.05,
        "{d} m (height {} m)",
        head.height_m()
    );
}

/// The default head's eyeballs (MakeHuman's low-poly eyes): two spheres
/// at x = ±0.308 dm, y 0.342, z 0.654 (the mean of each group's 282
/// vertices, computed from head.obj by a separate script), radius about
/// 0.147 dm (z from 0.507 to 0.801): 1.2–1.5 cm, an eyeball's size.
#[test]
fn default_head_eyeballs() {
    let e = Mesh::default_head().unwrap().eyeballs();
    for (k, x) in [(0, -0.308f32), (1, 0.308)] {
        let [cx, cy, cz, r] = e[k];
        assert!((cx - x).abs() < 0.01 && (cy - 0.342).abs() < 0.01, "{e:?}");
        assert!((cz - 0.654).abs() < 0.01, "{e:?}");
        assert!((r - 0.147).abs() < 0.01, "{e:?}");
    }
}

/// A card 9 units tall in 1/40 m units is 0.225 m: no warning; read
/// as metres it is 9 m and the warning suggests 0.25/9 = 0.0278 m/unit,
/// within −28 %/+60 % of which lies the inch.
#[test]
fn scale_warning_names_the_fix() {
    let card = [
        Vec3::ZERO,
        Vec3::new(9.0, 0.0, 0.0),
        Vec3::new(0.0, 9.0, 0.0),
    ];
    let size = HeadSize::measure(card.into_iter());
    assert_eq!(size.cranium_units, None);
    assert!(size.scale_warning(0.025).is_none());
    let w = size.scale_warning(1.0).unwrap();
    assert!(
        w.contains("--metres-per-unit 0.0254 would make it 0.23 m"),
        "{w}"
    );
}

/// Height-only suggestions (no cranium): a 7-unit card (0.25/7 =
/// 0.0357; 7 inches would be 17.8 cm), 9.2 units reads as inches
/// (23.4 cm), 24 as cm, 3.08 as dm; a flat or huge mesh still gets a
/// loadable value.
#[test]
fn suggestions_from_the_height() {
    let s = |h: f32| {
        HeadSize {
            height_units: h,
            cranium_units: None,
        }
        .suggest_metres_per_unit()
    };
    assert!((s(7.0) - 0.0357).abs() < 1e-6);
    assert_eq!(s(9.2), 0.0254);
    assert_eq!(s(24.0), 0.01);
    assert_eq!(s(3.08), 0.1);
    assert_eq!(s(0.0), 1e3);
    assert_eq!(s(1e12), 1e-6);
}

/// The cranium of the default head (MakeHuman hm08, decimetres): a
/// separate numpy script over head.obj's vertices found 1.751 dm
/// wide and 1.964 dm deep above the neck, so the mean is 1.857 dm, and the
/// suggestion is the decimetre. Lee Perry-Smith's scan
/// (assets/scan/, a bust to the shoulders, 7.945 units tall): the same
/// script found 3.620 wide and 4.428 deep, mean 4.024 (the crown to the
/// chin is 4.6 units, so at 0.0462 m/unit 21 cm: an adult's), and the old
/// height rule's 25 cm for the whole bust made that head 15 cm from
/// crown to chin. A sphere (a ball, not a head with a neck) has no
/// neck: the walk stops where it narrows past its equator, 2 units
/// wide and deep.
#[test]
fn head_size_of_the_default_head_and_a_scan() {
    let head = Mesh::default_head().unwrap().head_size();
    let c = head.cranium_units.unwrap();
    assert!((c - 1.857).abs() < 0.005, "{head:?}");
    assert_eq!(head.suggest_metres_per_unit(), 0.1);
    assert!(head.scale_warning(0.1).is_none());
    let scan = Mesh::load(
        std::path::Path::new(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/assets/scan/LeePerrySmith.glb"
        )),
        1.0,
    )
    .unwrap()
    .head_size();
    let c = scan.cranium_units.unwrap();
    assert!((c - 4.024).abs() < 0.005, "{scan:?}");
    let mpu = scan.suggest_metres_per_unit();
    assert!((mpu - 0.0462).abs() < 1e-6, "{mpu}");
    assert!(scan.scale_warning(mpu).is_none());
    // 1/40 m/unit, "about right" by the bust's height (19.9 cm), is a
    // 10 cm head.
    let w = scan.scale_warning(0.025).unwrap();
    assert!(w.contains("10.1 cm across"), "{w}");
    let sphere: Vec<Vec3> = (0..400)
        .map(|k| {
            let (t, p) = (k as f32 * 0.7, k as f32 / 399.0 * std::f32::consts::PI);
            Vec3::new(p.sin() * t.cos(), p.cos(), p.sin() * t.sin())
        })
        .collect();
    let ball = HeadSize::measure(sphere.into_iter());
    assert!((ball.cranium_units.unwrap() - 2.0).abs() < 0.05, "{ball:?}");
}
