//! Issue 52, what a new user still tripped on in the trial of 314eb75:
//! each test repeats one of the trial's steps and fails without its fix.

use super::*;

/// The tests' data and presets.
fn repo(path: &str) -> std::path::PathBuf {
    std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

/// Burley's albedo of the look open now.
fn albedo(h: &Harness<'_, EditorApp>) -> [f64; 3] {
    match &h.state().doc.preset.profile {
        ProfileSpec::Burley(b) => b.albedo,
        p => panic!("not a Burley look: {p:?}"),
    }
}

/// Imports HDRP's Skin profile (its albedo is the material's) over the
/// look open now and answers the material-albedo prompt with Enter.
fn import_hdrp_skin_with_enter(h: &mut Harness<'_, EditorApp>) {
    h.state_mut()
        .import_now(&repo("tests/data/hdrp/Skin Diffusion Profile.asset"));
    h.run_steps(2);
    assert!(
        h.query_by_label("Material albedo").is_some(),
        "no albedo prompt: {}",
        h.state().status()
    );
    h.key_press(Key::Enter);
    h.run_steps(2);
    assert!(
        h.query_by_label("Material albedo").is_none(),
        "the prompt stayed"
    );
}

/// Item 1: after Jade, HDRP's Skin imported with Enter was green skin (the
/// prompt's default was the look open before). On a head without a colour
/// map of its own the default is now the default skin's albedo, Unreal
/// Engine's default SurfaceAlbedo (0.91058, 0.338275, 0.2718: Unreal
/// Engine 4.27's `FSubsurfaceProfileStruct` defaults, as
/// presets/skin_default.ron cites them), not Jade's.
#[test]
fn an_hdrp_import_after_jade_is_skin_coloured_on_enter() {
    let mut h = harness(false);
    h.step();
    h.state_mut().open_now(&repo("presets/jade.ron"));
    h.run_steps(2);
    let jade = scatterlab::settings::albedo::look_albedo(&h.state().doc.preset);
    assert!(jade[1] > jade[0], "Jade is green: {jade:?}");
    import_hdrp_skin_with_enter(&mut h);
    let got = albedo(&h);
    let unreal = [0.91058, 0.338275, 0.2718];
    for c in 0..3 {
        assert!(
            (got[c] - unreal[c]).abs() < 1e-5,
            "imported albedo {got:?}, not Unreal's default SurfaceAlbedo {unreal:?} (Jade's is {jade:?})"
        );
    }
    assert!(
        h.state().status().contains("the default skin's"),
        "{}",
        h.state().status()
    );
}

/// Item 1 on the scan: with the head's colour map loaded, the default is
/// the map (the colour the engine's material takes from it), and the head
/// is drawn in the map's colour.
#[test]
fn an_hdrp_import_on_the_scan_takes_the_maps_colour_on_enter() {
    let scan = repo("assets/scan");
    let mesh = scan.join("LeePerrySmith.glb");
    let mut ui_state = UiState::default();
    let settings = ui_state.meshes.entry(mesh.clone()).or_default();
    settings.metres_per_unit = 0.0462;
    settings.maps[0].path = Some(scan.join("Map-COL.jpg"));
    settings.maps[0].flip_v = true;
    let jade = Preset::load(&repo("presets/jade.ron")).unwrap();
    let mut h = harness_of(
        EditorApp::new(None, ui_state, Some((jade, None)), true),
        [1500.0, 900.0],
    );
    h.state_mut().open_mesh(scatterlab::app::MeshArg {
        path: mesh,
        metres_per_unit: Some(0.0462),
    });
    step_until(&mut h, "the scan with its map", |a| {
        a.mesh_info().is_some_and(|i| i.colour_map_mean.is_some())
    });
    let mean = h.state().mesh_info().unwrap().colour_map_mean.unwrap();
    import_hdrp_skin_with_enter(&mut h);
    let got = albedo(&h);
    for c in 0..3 {
        assert!(
            (got[c] - mean[c] as f64).abs() < 1e-4,
            "imported albedo {got:?}, not the map's mean {mean:?}"
        );
    }
    assert_eq!(
        h.state().ui_state.map_colour,
        scatterlab::render::textures::MapColour::Map,
        "the head is drawn in its map's colour"
    );
}

/// Item 2: a text file renamed `.glb` replaced the loaded mesh with the
/// procedural head, and its error was posted twice. The mesh on screen
/// now stays (the frames after the error are still of it), and the error
/// is said once, naming the file and what is still shown.
#[test]
fn a_failed_mesh_load_keeps_the_mesh_on_screen_and_says_so_once() {
    let obj = repo("assets/head/head.obj");
    let mut h = harness(true);
    h.state_mut().open_mesh(scatterlab::app::MeshArg {
        path: obj.clone(),
        metres_per_unit: Some(0.01),
    });
    step_until(&mut h, "head.obj on screen", |a| {
        a.mesh_info().is_some_and(|i| i.metres_per_unit == 0.01) && a.viewport().idle()
    });
    let dir = std::env::temp_dir().join(format!("scatterlab-ui-badglb-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bad = dir.join("not_a_mesh.glb");
    std::fs::write(&bad, "These are notes, not a mesh.\n").unwrap();
    h.state_mut().open_mesh(scatterlab::app::MeshArg {
        path: bad.clone(),
        metres_per_unit: Some(0.01),
    });
    step_until(&mut h, "the error", |a| a.status().starts_with("Error"));
    // Frames keep coming of the mesh that was there.
    let n0 = h.state().viewport().frame().map_or(0, |f| f.1);
    h.state_mut().ui_state.view.orbit.camera_yaw_rad += 0.3;
    step_until(&mut h, "a frame after the error", |a| {
        a.viewport().idle() && a.viewport().frame().is_some_and(|f| f.1 > n0)
    });
    let status = h.state().status().to_string();
    assert!(status.contains("not_a_mesh.glb"), "{status}");
    assert!(status.contains("kept head.obj on screen"), "{status}");
    assert_eq!(h.state().mesh_path(), Some(obj.as_path()), "{status}");
    assert_eq!(h.state().mesh_info().unwrap().metres_per_unit, 0.01);
    let errors = h
        .state()
        .notices()
        .iter()
        .filter(|n| n.contains("not_a_mesh.glb"))
        .count();
    assert_eq!(errors, 1, "{:#?}", h.state().notices());
    std::fs::remove_dir_all(&dir).ok();
}
