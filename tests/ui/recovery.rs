//! Issue 27: the editor survives its own failures with the artist's work
//! intact. A panic injected into the render thread or the analysis thread
//! and a GPU device destroyed under the renderer (`Device::destroy`, as a
//! driver reset) are each said once, the thread or renderer starts again,
//! the view is redrawn, and the document and its undo history are as they
//! were. An editor killed with unsaved changes leaves its autosave behind
//! (`tests/window.rs` kills a real one); the next editor offers it back.

use super::*;
use scatterlab::app::viewport::Fault;

/// An edit the undo history holds: the look renamed, committed.
fn edited(h: &mut Harness<'static, EditorApp>) -> Preset {
    h.state_mut().doc.preset.name = "Edited before the failure".into();
    h.run_steps(2);
    assert!(h.state().doc.can_undo());
    h.state().doc.preset.clone()
}

/// The document is the edited one and one undo step takes it back.
fn work_intact(h: &mut Harness<'static, EditorApp>, edit: &Preset) {
    assert_eq!(&h.state().doc.preset, edit);
    assert!(h.state().doc.is_dirty());
    h.state_mut().doc.undo();
    assert_ne!(h.state().doc.preset.name, edit.name);
    h.state_mut().doc.redo();
    assert_eq!(&h.state().doc.preset, edit);
}

/// Injects `fault`, turns the head a little (a new request for the render
/// thread to fail on), and waits for the notice with `said` and a new
/// frame after it.
fn survive(fault: Fault, said: &str) {
    let mut h = viewport_harness([1000.0, 640.0]);
    step_until(&mut h, "the first frame", |a: &EditorApp| {
        a.viewport().has_frame()
    });
    step_until(&mut h, "a settled view", |a: &EditorApp| {
        a.viewport().idle()
    });
    let edit = edited(&mut h);
    let frames = h.state().viewport().frame().map_or(0, |f| f.1);
    h.state().viewport().inject_fault(fault);
    h.state_mut().ui_state.view.orbit.camera_yaw_rad += 0.2;
    step_until(&mut h, said, |a| {
        a.notices().iter().any(|n| n.contains(said))
    });
    let notice = h
        .state()
        .notices()
        .iter()
        .find(|n| n.contains(said))
        .cloned();
    step_until(&mut h, "a frame after the failure", |a| {
        a.viewport().idle() && a.viewport().frame().is_some_and(|f| f.1 > frames)
    });
    // The frame is the head, not an empty one.
    let (image, _) = h.state().viewport().frame().unwrap();
    let lit = image.pixels().filter(|p| p.0[0] > 40).count();
    assert!(
        lit * 20 > image.pixels().len(),
        "{lit} lit pixels after {notice:?}"
    );
    assert!(
        !h.state().status().starts_with("Error"),
        "{}",
        h.state().status()
    );
    work_intact(&mut h, &edit);
}

#[test]
fn a_render_thread_panic_is_survived() {
    survive(Fault::Panic, "render thread failed");
}

#[test]
fn a_lost_gpu_device_is_rebuilt() {
    survive(Fault::DeviceLoss, "GPU device was lost");
}

/// A view the render thread fails on every time (three panics queued) is
/// sent again twice, then the viewport stops asking and says so; the next
/// change of view renders, and the look is untouched.
#[test]
fn a_view_that_always_fails_is_not_retried_for_ever() {
    let mut h = viewport_harness([1000.0, 640.0]);
    step_until(&mut h, "the first frame", |a: &EditorApp| {
        a.viewport().has_frame()
    });
    step_until(&mut h, "a settled view", |a: &EditorApp| {
        a.viewport().idle()
    });
    let edit = edited(&mut h);
    for _ in 0..3 {
        h.state().viewport().inject_fault(Fault::Panic);
    }
    h.state_mut().ui_state.view.orbit.camera_yaw_rad += 0.2;
    let said = "failed on this view every time";
    step_until(&mut h, said, |a| {
        a.notices().iter().any(|n| n.contains(said))
    });
    step_until(&mut h, "an idle viewport", |a: &EditorApp| {
        a.viewport().idle()
    });
    let frames = h.state().viewport().frame().map_or(0, |f| f.1);
    h.state_mut().ui_state.view.orbit.camera_yaw_rad += 0.2;
    step_until(&mut h, "a frame of the next view", |a| {
        a.viewport().idle() && a.viewport().frame().is_some_and(|f| f.1 > frames)
    });
    work_intact(&mut h, &edit);
}

#[test]
fn an_analysis_panic_is_survived() {
    let mut h = harness(false);
    step_until(&mut h, "the first analysis", EditorApp::analysis_done);
    let edit = edited(&mut h);
    h.state().inject_analysis_panic();
    // A profile edit: the analysis runs again, and fails.
    let spec = &mut h.state_mut().doc.preset.profile;
    if let ProfileSpec::Burley(b) = spec {
        b.albedo[0] *= 0.9;
    }
    h.run_steps(2);
    let edit2 = h.state().doc.preset.clone();
    assert_ne!(edit2, edit);
    let said = "analysis thread failed";
    step_until(&mut h, said, |a| {
        a.notices().iter().any(|n| n.contains(said))
    });
    // The thread is alive: the next edit is analysed.
    if let ProfileSpec::Burley(b) = &mut h.state_mut().doc.preset.profile {
        b.albedo[0] *= 0.9;
    }
    step_until(
        &mut h,
        "the analysis after the failure",
        EditorApp::analysis_done,
    );
    assert!(h.state().latest_analysis().is_some());
    assert!(h.state().doc.can_undo());
    h.state_mut().doc.undo();
    assert_eq!(h.state().doc.preset, edit2);
}

/// What a killed editor left (written here by an editor that is dropped
/// without quitting, as a kill leaves it) is offered at the next start;
/// Restore brings back the look, unsaved, with its view and compare, its
/// undo history (issue 36: two steps here, and a third undone into redo)
/// and the mesh it was on with its units and maps.
#[test]
fn the_next_start_restores_unsaved_work() {
    use scatterlab::app::MeshArg;
    let data = std::env::temp_dir().join(format!("scatterlab-restore-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&data);
    let scan = std::path::Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scan"));
    let mesh = MeshArg::check(scan.join("LeePerrySmith.glb"), Some(0.0462)).unwrap();
    let original = Preset::default_skin().name;
    let (file, settings) = {
        let app = EditorApp::new(None, UiState::default(), None, false).with_autosave(&data);
        let mut h = harness_of(app, [1200.0, 800.0]);
        h.step();
        h.state_mut().open_mesh(mesh.clone());
        let m = h.state_mut().ui_state.meshes.get_mut(&mesh.path).unwrap();
        m.maps[0].path = Some(scan.join("Map-COL.jpg"));
        m.maps[0].flip_v = true;
        let settings = m.clone();
        h.state_mut().doc.preset.description = "step one".into();
        h.run_steps(2);
        h.state_mut().doc.preset.description = "step two".into();
        h.run_steps(2);
        h.state_mut().doc.preset.description = "step three".into();
        h.run_steps(2);
        h.state_mut().doc.undo();
        let _ = edited(&mut h);
        h.state_mut().ui_state.view.orbit.camera_yaw_rad = 1.25;
        h.state_mut().ui_state.compare = scatterlab::app::state::CompareMode::Split;
        h.state_mut().autosave_now();
        (h.state().autosave_file().unwrap(), settings)
    };
    assert!(file.exists(), "no autosave at {}", file.display());
    // That file is named by this (running) process: as if its editor had
    // died, rename it to a process id that never runs.
    let dead = file.with_file_name("999999999.ron");
    std::fs::rename(&file, &dead).unwrap();
    let app = EditorApp::new(None, UiState::default(), None, false).with_autosave(&data);
    let mut h = harness_of(app, [1200.0, 800.0]);
    h.run_steps(2);
    wait_for_label(&mut h, "Restore");
    assert!(h
        .query_by_label_contains("Edited before the failure")
        .is_some());
    h.get_by_label("Restore").click_accesskit();
    h.run_steps(3);
    let a = h.state();
    assert_eq!(a.doc.preset.name, "Edited before the failure");
    assert!(a.doc.is_dirty(), "a restored look is unsaved");
    assert_eq!(a.ui_state.view.orbit.camera_yaw_rad, 1.25);
    assert_eq!(
        a.ui_state.compare,
        scatterlab::app::state::CompareMode::Split
    );
    assert_eq!(a.mesh_path(), Some(mesh.path.as_path()));
    assert_eq!(a.ui_state.meshes.get(&mesh.path), Some(&settings));
    assert!(!dead.exists(), "the recovered file was not removed");
    assert!(h.query_by_label("Restore").is_none());
    // The history as it was: the rename, then "step two" (the undo of
    // "step three" is in redo, and the rename cleared it), then one, then
    // the look as it was saved, which is not unsaved.
    let steps = |h: &mut Harness<'static, EditorApp>, key: egui::Modifiers| {
        h.key_press_modifiers(key, egui::Key::Z);
        h.run_steps(2);
        (
            h.state().doc.preset.name.clone(),
            h.state().doc.preset.description.clone(),
        )
    };
    let undo = egui::Modifiers::COMMAND;
    assert_eq!(steps(&mut h, undo).1, "step two");
    assert_eq!(steps(&mut h, undo).1, "step one");
    let (name, _) = steps(&mut h, undo);
    assert_eq!(name, original);
    assert!(!h.state().doc.is_dirty(), "undone to the look as saved");
    assert!(!h.state().doc.can_undo());
    let redo = egui::Modifiers::COMMAND | egui::Modifiers::SHIFT;
    assert_eq!(steps(&mut h, redo).1, "step one");
    let _ = std::fs::remove_dir_all(&data);
}

/// A recovery file written before issue 36 (no history, no mesh) still
/// restores: the look with one undo step back to the default, on the
/// default head.
#[test]
fn a_recovery_file_without_history_restores_one_step() {
    let data = std::env::temp_dir().join(format!("scatterlab-restore-old-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&data);
    let dir = data.join("autosave");
    std::fs::create_dir_all(&dir).unwrap();
    let preset = ron::to_string(&Preset {
        name: "From an older editor".into(),
        ..Preset::default_skin()
    })
    .unwrap();
    std::fs::write(
        dir.join("999999998.ron"),
        format!("(preset: {preset}, path: None, written_unix_s: 60)"),
    )
    .unwrap();
    let app = EditorApp::new(None, UiState::default(), None, false).with_autosave(&data);
    let mut h = harness_of(app, [1200.0, 800.0]);
    h.run_steps(2);
    wait_for_label(&mut h, "Restore");
    h.get_by_label("Restore").click_accesskit();
    h.run_steps(3);
    assert_eq!(h.state().doc.preset.name, "From an older editor");
    assert!(h.state().doc.is_dirty());
    assert_eq!(h.state().mesh_path(), None);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Z);
    h.run_steps(2);
    assert_eq!(h.state().doc.preset, Preset::default());
    assert!(!h.state().doc.can_undo());
    let _ = std::fs::remove_dir_all(&data);
}

/// Saving removes the autosave (nothing unsaved is left to recover), and
/// so does answering the quit prompt with Discard: a clean quit leaves
/// nothing behind.
#[test]
fn saving_or_quitting_cleanly_leaves_nothing_to_recover() {
    let data = std::env::temp_dir().join(format!("scatterlab-clean-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&data);
    let app = EditorApp::new(None, UiState::default(), None, false).with_autosave(&data);
    let mut h = harness_of(app, [1200.0, 800.0]);
    h.step();
    let _ = edited(&mut h);
    h.state_mut().autosave_now();
    let file = h.state().autosave_file().unwrap();
    assert!(file.exists());
    let saved = data.join("saved.ron");
    h.state_mut().doc.save_as(&saved).unwrap();
    h.state_mut().autosave_now();
    assert!(!file.exists(), "an autosave outlived the save");
    // Unsaved again, then File → Quit → Discard.
    let _ = edited(&mut h);
    h.state_mut().doc.preset.description = "changed again".into();
    h.run_steps(2);
    h.state_mut().autosave_now();
    assert!(file.exists());
    file_menu(&mut h, "Quit");
    wait_for_label(&mut h, "Discard changes");
    h.get_by_label("Discard changes").click_accesskit();
    h.run_steps(3);
    assert!(!file.exists(), "a clean quit left an autosave");
    let _ = std::fs::remove_dir_all(&data);
}
