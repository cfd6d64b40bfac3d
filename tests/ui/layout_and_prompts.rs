//! The editor's layout at small windows, A/B flipping, panel edges, and
//! the dialogs and prompts that keep work from being lost.

use super::*;

/// Compare at 1280×720 and at the default window (1500×900), B the look
/// without SSS: in split, side by side and difference the viewport stays
/// between the side panels, inside the window; A and B are labelled on
/// their own halves; and both halves of the frame show the head (skin on
/// each side: before, at 1280×720 B was under the Profile panel).
#[test]
fn compare_fits_the_viewport_down_to_1280x720() {
    use scatterlab::app::state::{CompareB, CompareMode};
    use scatterlab::settings::rendering::MethodId;
    for size in [[1280.0, 720.0], [1500.0, 900.0]] {
        let mut h = harness_of(EditorApp::new(None, UiState::default(), None, true), size);
        h.step();
        step_until(&mut h, "the first frame", |a: &EditorApp| {
            a.viewport().has_frame()
        });
        h.state_mut().ui_state.compare_b = CompareB::Method(MethodId::None);
        for mode in [
            CompareMode::Split,
            CompareMode::SideBySide,
            CompareMode::Difference,
        ] {
            h.state_mut().ui_state.compare = mode;
            h.run_steps(2);
            step_until(&mut h, "the compared frame", |a| {
                a.viewport().idle()
                    && (mode != CompareMode::Difference
                        || a.viewport().frame_info().contains("heat map"))
            });
            let l = h.state().viewport_layout();
            let (vp, params, plots) = (l.viewport.unwrap(), l.params.unwrap(), l.plots.unwrap());
            let what = format!("{size:?} {mode:?}: viewport {vp:?}, panels {params:?} {plots:?}");
            assert!(vp.left() >= params.right() - 0.5, "{what}");
            assert!(vp.right() <= plots.left() + 0.5, "{what}");
            assert!(vp.right() <= size[0] && vp.bottom() <= size[1], "{what}");
            assert!(
                vp.width() > 0.3 * size[0],
                "{what}: the viewport is too narrow"
            );
            for (text, r) in &l.labels {
                assert!(vp.contains_rect(*r), "{what}: label {text} at {r:?}");
            }
            let (img, _) = h.state().viewport().frame().unwrap();
            assert!(
                (img.width() as f32 - vp.width()).abs() <= 1.5,
                "{what}: frame {}×{}",
                img.width(),
                img.height()
            );
            if mode == CompareMode::Difference {
                assert_eq!(l.labels.len(), 1, "{what}");
                assert!(l.labels[0].0.contains("A burley") && l.labels[0].0.contains("B none"));
                continue;
            }
            // A on the left half, B on the right (the split sits at 0.5).
            assert_eq!(l.labels.len(), 2, "{what}");
            let (a, b) = (&l.labels[0], &l.labels[1]);
            assert!(
                a.0.starts_with("A · burley") && b.0.starts_with("B · none"),
                "{what}"
            );
            assert!(a.1.right() <= vp.center().x + 0.5, "{what}: A at {:?}", a.1);
            assert!(b.1.left() >= vp.center().x - 0.5, "{what}: B at {:?}", b.1);
            // Skin (red well above blue) on both halves of the frame.
            let skin = |x0: u32, x1: u32| {
                let n = (x0..x1)
                    .flat_map(|x| (0..img.height()).map(move |y| (x, y)))
                    .filter(|&(x, y)| {
                        let p = img.get_pixel(x, y).0;
                        p[0] > 90 && p[0] as i32 - p[2] as i32 > 30
                    })
                    .count();
                n as f64 / ((x1 - x0) * img.height()) as f64
            };
            let half = img.width() / 2;
            let (left, right) = (skin(0, half), skin(half, img.width()));
            assert!(
                left > 0.1 && right > 0.1,
                "{what}: skin {left:.2} | {right:.2}"
            );
        }
    }
}

/// Space flips between B alone and A alone in every compare mode, and
/// Escape goes back to both (the labels say which). Before, side by side
/// cycled side by side → B → side by side and never showed A.
#[test]
fn space_flips_a_and_b_in_every_mode() {
    use scatterlab::app::state::CompareMode;
    use scatterlab::app::AbView;
    let mut h = harness(false);
    h.step();
    // Not comparing: Space does nothing.
    h.key_press(Key::Space);
    h.step();
    assert_eq!(h.state().viewport().ab(), AbView::Both);
    let shown = |h: &Harness<'_, EditorApp>| -> Vec<String> {
        let l = h.state().viewport_layout();
        l.labels.iter().map(|(t, _)| t[..1].to_string()).collect()
    };
    for mode in [
        CompareMode::Split,
        CompareMode::SideBySide,
        CompareMode::Difference,
    ] {
        h.state_mut().ui_state.compare = mode;
        h.run_steps(2);
        let both = shown(&h);
        for expected in [AbView::B, AbView::A, AbView::B, AbView::A] {
            h.key_press(Key::Space);
            h.run_steps(2);
            assert_eq!(h.state().viewport().ab(), expected, "{mode:?}");
            let tag = if expected == AbView::A { "A" } else { "B" };
            assert_eq!(shown(&h), vec![tag.to_string()], "{mode:?}");
        }
        h.key_press(Key::Escape);
        h.run_steps(2);
        assert_eq!(h.state().viewport().ab(), AbView::Both, "{mode:?}");
        assert_eq!(shown(&h), both, "{mode:?}");
    }
}

/// The side panels' edges stay grabbable: dragging the plots panel's left
/// edge 60 points left widens it by about that, and the params panel's
/// right edge likewise; the camera does not orbit (the viewport used to
/// take the drag).
#[test]
fn panel_edges_stay_grabbable() {
    let mut h = harness(false);
    h.run_steps(3);
    let yaw = h.state().ui_state.view.orbit.camera_yaw_rad;
    let drag = |h: &mut Harness<'_, EditorApp>, from: egui::Pos2, dx: f32| {
        h.hover_at(from);
        h.step();
        h.drag_at(from);
        h.step();
        for k in 1..=6 {
            h.hover_at(from + egui::vec2(dx * k as f32 / 6.0, 0.0));
            h.step();
        }
        h.drop_at(from + egui::vec2(dx, 0.0));
        h.run_steps(2);
    };
    let plots = h.state().viewport_layout().plots.unwrap();
    drag(&mut h, egui::pos2(plots.left(), plots.center().y), -60.0);
    let after = h.state().viewport_layout().plots.unwrap();
    assert!(
        after.width() > plots.width() + 40.0,
        "plots panel {} → {}",
        plots.width(),
        after.width()
    );
    let params = h.state().viewport_layout().params.unwrap();
    drag(&mut h, egui::pos2(params.right(), params.center().y), 40.0);
    let after = h.state().viewport_layout().params.unwrap();
    assert!(
        after.width() > params.width() + 25.0,
        "params panel {} → {}",
        params.width(),
        after.width()
    );
    assert_eq!(
        h.state().ui_state.view.orbit.camera_yaw_rad,
        yaw,
        "the viewport orbited"
    );
}

/// A file dialog opens in the folder of the current file of its kind (a
/// mesh dialog in the loaded mesh's folder), else where that kind was last
/// used, remembered in `UiState` across runs.
#[test]
fn file_dialogs_remember_their_folder() {
    let dir = std::env::temp_dir().join(format!("scatterlab-ui-folders-{}", std::process::id()));
    let meshes = dir.join("meshes");
    std::fs::create_dir_all(&meshes).unwrap();
    let mut h = harness(false);
    h.step();
    file_menu(&mut h, "Load mesh…");
    let start = h.state().dialog_folder_shown().unwrap();
    assert_ne!(start, meshes);
    // A file to click: Open acts on a file in the list.
    std::fs::write(meshes.join("head.obj"), "v 0 0 0\n").unwrap();
    choose(&mut h, &meshes.join("head.obj"));
    assert_eq!(
        h.state().dialog_folder_shown(),
        None,
        "{}",
        h.state().status()
    );
    file_menu(&mut h, "Load mesh…");
    assert_eq!(h.state().dialog_folder_shown().unwrap(), meshes);
    h.get_by_label("Cancel").click_accesskit();
    h.run_steps(2);
    // Remembered between runs: the stored state opens there too.
    let stored = ron::to_string(&h.state().ui_state).unwrap();
    let state: UiState = ron::from_str(&stored).unwrap();
    let mut h = harness_of(EditorApp::new(None, state, None, false), [1500.0, 900.0]);
    h.step();
    file_menu(&mut h, "Load mesh…");
    assert_eq!(h.state().dialog_folder_shown().unwrap(), meshes);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An export over an existing file asks first: Cancel leaves the file and
/// goes back to the dialog; Replace writes it. Save As asks the same.
#[test]
fn export_and_save_as_ask_before_replacing() {
    let dir = std::env::temp_dir().join(format!("scatterlab-ui-replace-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out = dir.join("look.asset");
    std::fs::write(&out, "old").unwrap();
    let mut h = harness(false);
    h.step();
    h.get_by_label("Export").click_accesskit();
    h.run_steps(3);
    h.get_by_label_contains("Unity HDRP diffusion profile")
        .click_accesskit();
    h.run_steps(5);
    choose(&mut h, &out);
    wait_for_label(&mut h, "Replace existing files?");
    h.get_by_label("Cancel").click_accesskit();
    h.run_steps(2);
    assert_eq!(std::fs::read_to_string(&out).unwrap(), "old");
    assert_eq!(h.state().dialog_folder_shown().unwrap(), dir);
    assert_eq!(name_field(&h).value().unwrap(), "look.asset");
    h.get_by_label("Save").click_accesskit();
    h.run_steps(4);
    h.get_by_label("Replace").click_accesskit();
    h.step();
    step_until(&mut h, "the export", |a| a.status().starts_with("Exported"));
    assert!(std::fs::read_to_string(&out)
        .unwrap()
        .contains("guid: b2686e09ec7aef44bad2843e4416f057"));

    let preset = dir.join("look.ron");
    std::fs::write(&preset, "old").unwrap();
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, Key::S);
    h.run_steps(2);
    choose(&mut h, &preset);
    wait_for_label(&mut h, "Replace existing files?");
    assert_eq!(std::fs::read_to_string(&preset).unwrap(), "old");
    h.get_by_label("Replace").click_accesskit();
    h.run_steps(2);
    assert_eq!(
        Preset::load(&preset).unwrap().name,
        h.state().doc.preset.name
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Whether the editor told the window to close this frame.
fn closing(h: &Harness<'_, EditorApp>) -> bool {
    h.output()
        .viewport_output
        .get(&egui::ViewportId::ROOT)
        .is_some_and(|v| v.commands.contains(&egui::ViewportCommand::Close))
}

/// Save in the quit prompt saves and closes the window (it saved and
/// stayed open); for a look without a file it asks where, saves, closes.
#[test]
fn save_in_the_quit_prompt_saves_and_quits() {
    let dir = std::env::temp_dir().join(format!("scatterlab-ui-quit-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("look.ron");
    Preset::default_skin().save(&path).unwrap();
    let app = EditorApp::new(
        None,
        UiState::default(),
        Some((Preset::load(&path).unwrap(), Some(path.clone()))),
        false,
    );
    let mut h = harness_of(app, [1500.0, 900.0]);
    h.step();
    h.state_mut().doc.preset.name = "Edited".into();
    h.run_steps(2);
    file_menu(&mut h, "Quit");
    assert!(h.query_by_label("Unsaved changes").is_some());
    assert!(!h.state().close_allowed());
    h.get_by_label("Save").click_accesskit();
    h.step();
    assert_eq!(Preset::load(&path).unwrap().name, "Edited");
    assert!(h.state().close_allowed() && closing(&h));

    // Untitled: Save asks where first.
    let mut h = harness(false);
    h.step();
    h.state_mut().doc.preset.name = "Untitled edit".into();
    h.run_steps(2);
    file_menu(&mut h, "Quit");
    h.get_by_label("Save").click_accesskit();
    h.run_steps(2);
    assert!(!h.state().close_allowed());
    let new = dir.join("new.ron");
    choose(&mut h, &new);
    h.step();
    assert_eq!(Preset::load(&new).unwrap().name, "Untitled edit");
    assert!(h.state().close_allowed() && closing(&h));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// While a prompt asks about the look, no key changes the look under it
/// (the soak found Ctrl+Z undoing behind an unsaved-changes prompt), and
/// Escape answers Cancel: the look stays as it was, unsaved, and the
/// editor carries on.
#[test]
fn keys_wait_for_a_prompt_and_escape_cancels_it() {
    let mut h = harness(false);
    h.step();
    h.state_mut().doc.preset.name = "Edited".into();
    h.run_steps(2);
    assert!(h.state().doc.can_undo());
    file_menu(&mut h, "Quit");
    wait_for_label(&mut h, "Unsaved changes");
    assert!(h.state().modal_prompt_open());
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_steps(2);
    assert_eq!(
        h.state().doc.preset.name,
        "Edited",
        "undone under the prompt"
    );
    h.key_press(Key::Escape);
    h.run_steps(3);
    assert!(!h.state().modal_prompt_open(), "Escape did not cancel");
    assert!(h.query_by_label("Unsaved changes").is_none());
    assert!(!h.state().close_allowed());
    assert_eq!(h.state().doc.preset.name, "Edited");
    assert!(h.state().doc.is_dirty());
    // With the prompt gone, Ctrl+Z undoes again.
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_steps(2);
    assert_ne!(h.state().doc.preset.name, "Edited");
}

/// The plot's legend: under the plot (never over the curves), R, G, B in
/// that order, then the fit by its name (the default overlay, "Jimenez
/// 2012 fit"). egui_plot's legend sat in the top right, alphabetical.
#[test]
fn legend_under_the_plot_in_rgb_order_naming_the_fit() {
    let mut h = harness(false);
    h.step();
    step_until(&mut h, "the overlay fit", |a| a.latest_analysis().is_some());
    h.run_steps(3);
    let plot = h.state().plot_rect().expect("the plot");
    let panel = h.state().viewport_layout().plots.unwrap();
    let under = |h: &Harness<'_, EditorApp>, label: &str| -> egui::Rect {
        let found: Vec<egui::Rect> = h
            .get_all_by_label(label)
            .map(|n| n.rect())
            .filter(|r| r.top() >= plot.bottom() && r.left() >= panel.left())
            .collect();
        let all: Vec<egui::Rect> = h.get_all_by_label(label).map(|n| n.rect()).collect();
        assert_eq!(
            found.len(),
            1,
            "legend entry {label}: {found:?} of {all:?} (plot {plot:?})"
        );
        found[0]
    };
    let (r, g, b) = (under(&h, "R"), under(&h, "G"), under(&h, "B"));
    assert!(
        r.left() < g.left() && g.left() < b.left(),
        "{r:?} {g:?} {b:?}"
    );
    under(&h, "Jimenez 2012 fit");
    under(&h, "99.7 % energy radius");
}

/// While the orbit is dragged the viewport shows reduced-resolution
/// previews; once released it renders the full size and refines it (burley
/// rotates its samples) until it reports "converged" after more than one
/// frame.
#[test]
fn the_viewport_previews_while_dragging_and_converges_after() {
    use scatterlab::app::viewport::Quality;
    let mut h = harness(true);
    h.step();
    step_until(&mut h, "the first converged frame", |a| {
        matches!(a.viewport().quality(), Some(Quality::Converged { .. }))
    });
    let vp = h.state().viewport_layout().viewport.unwrap();
    let full = h.state().viewport().frame().unwrap().0.width();
    let c = vp.center();
    h.hover_at(c);
    h.step();
    h.drag_at(c);
    h.step();
    let mut x = c.x;
    for _ in 0..3 {
        x += 10.0;
        h.hover_at(egui::pos2(x, c.y));
        h.step();
    }
    // Still held: previews until it is released.
    step_until(&mut h, "a preview", |a| {
        matches!(a.viewport().quality(), Some(Quality::Preview { .. }))
    });
    let preview = h.state().viewport().frame().unwrap().0.width();
    assert!(preview < full, "preview {preview} px wide, full {full}");
    h.drop_at(egui::pos2(x, c.y));
    h.step();
    step_until(&mut h, "convergence", |a| {
        matches!(a.viewport().quality(), Some(Quality::Converged { .. }))
    });
    let Some(Quality::Converged { frames, .. }) = h.state().viewport().quality() else {
        unreachable!()
    };
    assert!(frames > 1, "burley converged after {frames} frame(s)");
    assert_eq!(h.state().viewport().frame().unwrap().0.width(), full);
}

/// "Refine to the truth" (issues 23 and 38): the method's converged frame
/// stays on screen and the ground truth replaces it tile by tile at full
/// resolution (never a coarser frame over a converged one), the status
/// bar naming what is shown at every frame; going back to that view shows
/// its finished frame at once.
#[test]
fn refine_to_the_truth_fills_tiles_over_the_converged_frame_and_keeps_it() {
    use scatterlab::app::viewport::Quality;
    let state = UiState {
        refine_to_truth: true,
        ..UiState::default()
    };
    // A small window: the ground truth is a CPU frame.
    let mut h = harness_of(EditorApp::new(None, state, None, true), [900.0, 560.0]);
    h.step();
    // At this small window the plots panel is 104 points narrower once the
    // analysis has arrived, so the viewport grows and renders again: on a
    // loaded machine that may come after burley converged (the analysis
    // thread runs at a lower priority than the viewport's).
    step_until(&mut h, "the analysis", |a| a.analysis_done());
    step_until(&mut h, "the full ground truth", |a| {
        matches!(a.viewport().quality(), Some(Quality::Converged { .. }))
            && a.viewport().frame_info().starts_with("reference")
    });
    // Every frame after burley's converged one: its quality, size and
    // status line.
    let history: Vec<_> = h.state().viewport().history().cloned().collect();
    // The last converged frame of burley's: a resize before it starts a
    // new view.
    let start = history
        .iter()
        .rposition(|(q, _, info)| {
            matches!(q, Quality::Converged { .. }) && info.starts_with("burley")
        })
        .expect("burley converged first");
    let size = history[start].1;
    let seen = &history[start + 1..];
    for (q, s, info) in seen {
        eprintln!("{q:?} {s:?} {info}");
        assert_eq!(
            *s, size,
            "a frame of another size over the converged one: {info}"
        );
        assert!(
            !matches!(q, Quality::Coarse { .. }),
            "a coarse frame: {info}"
        );
    }
    let tiles: Vec<_> = seen
        .iter()
        .filter_map(|(q, _, _)| match q {
            Quality::Truth { done, tiles, .. } if *tiles > 0 => Some((*done, *tiles)),
            _ => None,
        })
        .collect();
    assert!(
        !tiles.is_empty(),
        "no frame of tiles came before the full truth"
    );
    assert!(
        tiles.windows(2).all(|w| w[0].0 <= w[1].0),
        "tiles went back: {tiles:?}"
    );
    // The status said the tiles were next before the first of them.
    assert!(seen
        .iter()
        .any(|(q, _, info)| matches!(q, Quality::Truth { tiles: 0, .. })
            && info.contains("burley's frame, the ground truth's tiles next")));
    let info = h.state().viewport().frame_info().to_string();
    assert!(
        info.contains("the ground truth, refined from burley"),
        "status: {info}"
    );
    let truth = h.state().viewport().frame().unwrap().0.clone();
    // Off: the method's own frame (another request).
    h.state_mut().ui_state.refine_to_truth = false;
    step_until(&mut h, "burley converged", |a| {
        matches!(a.viewport().quality(), Some(Quality::Converged { .. }))
            && a.viewport().frame_info().starts_with("burley")
    });
    // On again: the same view's finished ground truth, kept.
    h.state_mut().ui_state.refine_to_truth = true;
    step_until(&mut h, "the kept ground truth", |a| {
        a.viewport().frame_info().starts_with("reference")
            && a.viewport().frame_info().contains("kept from before")
    });
    assert_eq!(h.state().viewport().frame().unwrap().0, &truth);
}

/// File names and folders (issue 41):
/// - each export proposes a name no other format's files take: Blender
///   `<look>_blender.py`, Unreal `<look>_unreal.txt` (its script beside it
///   `<look>_unreal.py`), Unity `<look>.asset` as before;
/// - Save As on a look opened from the shipped presets' folder starts
///   elsewhere and proposes the file's own name;
/// - with nothing remembered and no file, a dialog starts in the
///   documents or home folder, not the process's working directory.
#[test]
fn export_names_and_dialog_folders_do_not_misplace_files() {
    let mut h = harness(false);
    h.step();
    let cwd = std::env::current_dir().unwrap();
    for (entry, name) in [
        ("Blender", "skin_default_blender.py"),
        ("Unreal subsurface profile", "skin_default_unreal.txt"),
        ("Unity HDRP diffusion profile", "skin_default.asset"),
    ] {
        h.get_by_label("Export").click_accesskit();
        h.run_steps(3);
        h.get_by_label_contains(entry).click_accesskit();
        h.run_steps(5);
        wait_for_file_dialog(&mut h);
        assert_eq!(name_field(&h).value().unwrap(), name, "{entry}");
        assert_ne!(h.state().dialog_folder_shown().unwrap(), cwd, "{entry}");
        h.get_by_label("Cancel").click_accesskit();
        h.run_steps(2);
    }
    let shipped = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("presets");
    let file = shipped.join("skin1_jensen2001.ron");
    let preset = Preset::load(&file).unwrap();
    let mut h = harness_of(
        EditorApp::new(None, UiState::default(), Some((preset, Some(file))), false),
        [1500.0, 900.0],
    );
    h.step();
    file_menu(&mut h, "Save as…  (Ctrl+Shift+S)");
    wait_for_file_dialog(&mut h);
    let folder = h.state().dialog_folder_shown().unwrap();
    assert_ne!(folder, shipped, "Save As opened the shipped presets");
    assert_ne!(folder, cwd);
    assert_eq!(name_field(&h).value().unwrap(), "skin1_jensen2001.ron");
}
