//! Issue 25, what an artist reaches for first: light rigs and the light
//! gizmo, colour pickers on the RGB fields.

use super::*;
use scatterlab::app::state::EnvironmentChoice;

/// The light gizmo's direction text ("… from the camera, … up, in front").
fn gizmo(h: &Harness<'_, EditorApp>) -> String {
    h.get_by_label("Light direction")
        .value()
        .expect("the light gizmo states the light's direction")
}

/// Steps until the viewport has converged and stays so: the analysis done
/// (it can change the panels' widths, and so the viewport's size) and no
/// new frame over a few more steps. Under parallel tests a first converged
/// frame can still be at a provisional size.
pub(super) fn settle(h: &mut Harness<'_, EditorApp>) {
    step_until(h, "the analysis", EditorApp::analysis_done);
    loop {
        step_until(h, "a converged frame", |a| {
            a.viewport().idle()
                && matches!(
                    a.viewport().quality(),
                    Some(scatterlab::app::viewport::Quality::Converged { .. })
                )
        });
        let n = h.state().viewport().frame().map(|f| f.1);
        for _ in 0..5 {
            std::thread::sleep(std::time::Duration::from_millis(50));
            h.step();
        }
        if h.state().viewport().frame().map(|f| f.1) == n && h.state().viewport().idle() {
            return;
        }
    }
}

/// Each rig is one click from the view toolbar and puts the key light
/// where its tooltip says, relative to the camera (the side light at 90°,
/// the back light at 135° from the camera's azimuth), with its environment;
/// the menu names the rig in use and "custom" once the light is dragged;
/// the gizmo reads the light from the camera's frame (in front or behind);
/// the HDR rig with no map loaded asks for one.
#[test]
fn light_rigs_are_one_click_and_the_gizmo_shows_the_light() {
    let mut h = harness(false);
    h.step();
    // The default view is no rig: 51.6° from the camera, 20° up.
    assert!(h.query_by_label("Light: custom").is_some());
    assert_eq!(gizmo(&h), "52° from the camera, 20° up, in front");
    menu_item(&mut h, "Light: custom", "side");
    let v = h.state().ui_state.view;
    let rel = (v.orbit.light_azimuth_rad - v.orbit.camera_yaw_rad).to_degrees();
    assert!((rel - 90.0).abs() < 1e-3, "{rel}");
    assert!((v.orbit.light_elevation_rad.to_degrees() - 10.0).abs() < 1e-3);
    assert_eq!(v.environment, EnvironmentChoice::Black);
    assert_eq!(gizmo(&h), "90° from the camera, 10° up, in front");
    menu_item(&mut h, "Light: side", "back, through the ear");
    assert_eq!(gizmo(&h), "135° from the camera, 10° up, behind");
    assert!(h.query_by_label("Light: back, through the ear").is_some());
    // Orbiting keeps the light where it is in the world: no longer the rig.
    h.state_mut().ui_state.view.orbit.camera_yaw_rad += 0.5;
    h.run_steps(2);
    assert!(h.query_by_label("Light: custom").is_some());
    assert_eq!(gizmo(&h), "106° from the camera, 10° up, behind");
    // Front, from the new camera: beside it.
    menu_item(&mut h, "Light: custom", "front");
    assert_eq!(gizmo(&h), "0° from the camera, 20° up, in front");
    assert_eq!(
        h.state().ui_state.view.environment,
        EnvironmentChoice::Studio
    );
    // No map loaded: the HDR rig opens the environment dialog, lighting
    // nothing yet.
    menu_item(&mut h, "Light: front", "HDR map");
    assert!(h.query_by_label_contains("Environment map").is_some());
    assert_eq!(
        h.state().ui_state.view.environment,
        EnvironmentChoice::Studio
    );
}

/// The albedo's swatch opens a colour picker whose numbers are linear (the
/// same numbers as the fields); the scattering distance's picker edits its
/// colour and keeps its multiplier (the largest channel), as HDRP's
/// inspector splits colour × multiplier.
#[test]
fn colour_pickers_edit_linear_colours_and_distance_colour_times_multiplier() {
    let mut h = harness(false);
    h.step();
    let albedo = |app: &EditorApp| match &app.doc.preset.profile {
        ProfileSpec::Burley(b) => b.albedo,
        other => panic!("{other:?}"),
    };
    let a0 = albedo(h.state());
    h.get_by_label("Albedo colour").click_accesskit();
    h.run_steps(2);
    // Opening the picker is no edit (its f32/HSV round trip once was).
    assert!(!h.state().doc.is_dirty());
    assert_eq!(albedo(h.state()), a0);
    // Egui's picker in linear mode: its R field ("R 0.911") shows the
    // albedo's red.
    let red = picker_field(&h, "R");
    let shown: f64 = red
        .value()
        .and_then(|v| v.trim_start_matches("R ").parse().ok())
        .expect("the picker's red value");
    assert!((shown - a0[0]).abs() < 5e-4, "{shown} vs {a0:?}");
    red.set_value_accesskit(0.25);
    h.run_steps(2);
    let a1 = albedo(h.state());
    assert!((a1[0] - 0.25).abs() < 1e-3, "{a1:?}");
    assert!(
        (a1[1] - a0[1]).abs() < 1e-3 && (a1[2] - a0[2]).abs() < 1e-3,
        "{a1:?}"
    );
    h.key_press(Key::Escape);
    h.run_steps(2);
    let d0: [f64; 3] = match &h.state().doc.preset.profile {
        ProfileSpec::Burley(b) => match b.shape {
            BurleyShape::ScatteringDistance { mm, .. } => mm,
            ref other => panic!("{other:?}"),
        },
        other => panic!("{other:?}"),
    };
    let m = d0.iter().cloned().fold(0.0, f64::max);
    h.get_by_label("Scattering distance colour")
        .click_accesskit();
    h.run_steps(2);
    picker_field(&h, "G").set_value_accesskit(0.5);
    h.run_steps(2);
    let g = scattering_distance(h.state());
    assert!((g[1] - 0.5 * m).abs() < 1e-3, "{g:?} from {d0:?}");
    assert!(
        (g[0] - d0[0]).abs() < 1e-3 && (g[2] - d0[2]).abs() < 1e-3,
        "{g:?} from {d0:?}"
    );
    // One undo step takes the picker's edit back.
    h.key_press(Key::Escape);
    h.run_steps(2);
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_steps(2);
    assert_eq!(scattering_distance(h.state()), d0);
}

fn scattering_distance(app: &EditorApp) -> [f64; 3] {
    match &app.doc.preset.profile {
        ProfileSpec::Burley(b) => match b.shape {
            BurleyShape::ScatteringDistance { mm, .. } => mm,
            ref other => panic!("{other:?}"),
        },
        other => panic!("{other:?}"),
    }
}

/// The open colour picker's number field for `channel` ("R", "G", "B"):
/// its value reads "R 0.911" (the panel's own fields read "R: 0.91058").
pub(crate) fn picker_field<'h>(
    h: &'h Harness<'_, EditorApp>,
    channel: &str,
) -> egui_kittest::Node<'h> {
    h.get_all_by_role(egui::accesskit::Role::SpinButton)
        .find(|n| {
            n.value()
                .is_some_and(|v| v.starts_with(&format!("{channel} ")))
        })
        .unwrap_or_else(|| panic!("no colour picker field {channel}"))
}

/// F12 saves the viewport's frame as you see it: the dialog (egui_file)
/// proposes a clean name (the look's words and the method, no "__"), lists
/// folders before files, keeps the typed name while a folder is clicked,
/// opens a folder typed as the file name instead of offering to replace
/// it (the old dialog offered to "Replace" one and failed), and the PNG
/// written is the frame shown, pixel for pixel.
#[test]
fn f12_saves_the_frame_shown_and_a_folder_is_never_a_file() {
    let dir = std::env::temp_dir().join(format!("scatterlab-ui-image-{}", std::process::id()));
    let sub = dir.join("renders");
    std::fs::create_dir_all(&sub).unwrap();
    std::fs::write(dir.join("a_first.png"), b"not read").unwrap();
    let mut h = viewport_harness([900.0, 560.0]);
    h.step();
    settle(&mut h);
    h.key_press(Key::F12);
    h.run_steps(2);
    assert!(h
        .query_by_label_contains("Save the viewport image")
        .is_some());
    assert_eq!(name_field(&h).value().unwrap(), "skin_default_burley.png");
    // In `dir`: the folder is listed before the file, though "a_first"
    // sorts first by name.
    assert!(h.state_mut().dialog_goto(&dir));
    h.run_steps(2);
    let folder = h.get_by_label("\u{1f5c0} renders").rect();
    let file = h.get_by_label("\u{1f5cb} a_first.png").rect();
    assert!(folder.top() < file.top(), "{folder:?} {file:?}");
    // The folder's name as the file to write: it is opened, not replaced.
    name_field(&h).set_text_value_accesskit("renders");
    h.run_steps(2);
    h.get_by_label("Save").click_accesskit();
    h.run_steps(3);
    assert!(h.query_by_label("Replace existing files?").is_none());
    assert_eq!(h.state().dialog_folder_shown().unwrap(), sub);
    assert!(sub.is_dir());
    // Back up; type a name, click the folder, open it: the name stays.
    h.get_by_label("\u{2b06}").click_accesskit();
    h.run_steps(2);
    assert_eq!(h.state().dialog_folder_shown().unwrap(), dir);
    name_field(&h).set_text_value_accesskit("head.png");
    h.run_steps(2);
    h.get_by_label("\u{1f5c0} renders").click_accesskit();
    h.run_steps(2);
    assert_eq!(name_field(&h).value().unwrap(), "head.png");
    h.get_by_label("Open").click_accesskit();
    h.run_steps(2);
    assert_eq!(h.state().dialog_folder_shown().unwrap(), sub);
    assert_eq!(name_field(&h).value().unwrap(), "head.png");
    // Save there under the typed name.
    h.get_by_label("Save").click_accesskit();
    h.run_steps(3);
    let out = sub.join("head.png");
    assert!(
        h.state().status().starts_with("Saved image"),
        "{}",
        h.state().status()
    );
    let saved = image::open(&out).unwrap().to_rgba8();
    let (shown, _) = h.state().viewport().frame().unwrap();
    assert_eq!(saved.dimensions(), shown.dimensions());
    assert!(
        saved.as_raw() == shown.as_raw(),
        "the PNG is not the frame shown"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Mean absolute difference of two equally sized images (8-bit, RGB).
fn mean_difference(a: &image::RgbaImage, b: &image::RgbaImage) -> f64 {
    assert_eq!(a.dimensions(), b.dimensions());
    let sum: u64 = a
        .pixels()
        .zip(b.pixels())
        .map(|(p, q)| {
            (0..3)
                .map(|c| (p[c] as i64 - q[c] as i64).unsigned_abs())
                .sum::<u64>()
        })
        .sum();
    sum as f64 / (3 * a.width() * a.height()) as f64
}

/// File → Save turntable… renders N converged frames around the head and
/// writes them as a looping GIF and a PNG per frame; the first frame is the
/// viewport's own view, the half turn shows the back of the head. Read
/// back with `image`'s GIF decoder (another code path than the encoder).
/// Cancel stops a long one and writes nothing.
#[test]
fn turntable_writes_a_gif_and_pngs_and_cancel_writes_nothing() {
    use image::AnimationDecoder;
    let dir = std::env::temp_dir().join(format!("scatterlab-ui-turntable-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = viewport_harness([900.0, 560.0]);
    h.step();
    settle(&mut h);
    menu_item(&mut h, "File", "Save turntable…");
    assert!(h.query_by_label("Save turntable as GIF…").is_some());
    h.state_mut().ui_state.turntable.frames = 4;
    h.get_by_label("Save turntable as GIF…").click_accesskit();
    wait_for_file_dialog(&mut h);
    assert_eq!(
        name_field(&h).value().unwrap(),
        "skin_default_burley_turntable.gif"
    );
    let out = dir.join("spin.gif");
    choose(&mut h, &out);
    assert!(
        h.state().turntable_progress().is_some(),
        "{}",
        h.state().status()
    );
    step_until(&mut h, "the turntable", |a| {
        a.turntable_progress().is_none()
    });
    assert!(
        h.state().status().starts_with("Saved turntable"),
        "{}",
        h.state().status()
    );
    let gif = image::codecs::gif::GifDecoder::new(std::io::BufReader::new(
        std::fs::File::open(&out).unwrap(),
    ))
    .unwrap();
    let frames = gif.into_frames().collect_frames().unwrap();
    assert_eq!(frames.len(), 4);
    let (shown, _) = h.state().viewport().frame().unwrap();
    let first = frames[0].buffer();
    assert_eq!(first.dimensions(), shown.dimensions());
    // GIF's 256-colour palette costs a little; the view is the viewport's.
    let d0 = mean_difference(first, shown);
    let d_half = mean_difference(frames[2].buffer(), shown);
    assert!(d0 < 3.0, "frame 0 vs the viewport: {d0:.2}");
    assert!(
        d_half > 4.0 * d0.max(1.0),
        "the half turn is the same view: {d_half:.2}"
    );
    let pngs: Vec<_> = (0..4)
        .map(|k| dir.join("spin_frames").join(format!("spin_{k:03}.png")))
        .collect();
    for p in &pngs {
        assert!(p.is_file(), "{} missing", p.display());
    }
    let png0 = image::open(&pngs[0]).unwrap().to_rgba8();
    let dp = mean_difference(&png0, shown);
    assert!(dp < 0.5, "PNG frame 0 vs the viewport: {dp:.3}");
    // The APNG beside it: its chunks by the APNG 1.0 specification
    // (acTL: 4 frames, 0 = loop forever; an fcTL per frame, delay 1000 ms
    // over 4 = 250/1000 s), read here byte by byte; decoded by the image
    // crate's APNG reader, each frame is its PNG exactly (lossless, where
    // the GIF is not).
    let apng_path = dir.join("spin.png");
    let bytes = std::fs::read(&apng_path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let mut at = 8;
    let (mut actl, mut fctl) = (None, Vec::new());
    while at + 8 <= bytes.len() {
        let len = u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
        let kind = &bytes[at + 4..at + 8];
        let data = &bytes[at + 8..at + 8 + len];
        let be = |o: usize| u32::from_be_bytes(data[o..o + 4].try_into().unwrap());
        match kind {
            b"acTL" => actl = Some((be(0), be(4))),
            // delay_num, delay_den at bytes 20..24 of the 26-byte fcTL.
            b"fcTL" => fctl.push((
                u16::from_be_bytes([data[20], data[21]]),
                u16::from_be_bytes([data[22], data[23]]),
            )),
            _ => {}
        }
        at += 12 + len;
    }
    assert_eq!(actl, Some((4, 0)), "acTL (frames, plays)");
    assert_eq!(fctl, vec![(1000, 1000); 4], "fcTL delays");
    let apng = image::codecs::png::PngDecoder::new(std::io::BufReader::new(
        std::fs::File::open(&apng_path).unwrap(),
    ))
    .unwrap()
    .apng()
    .unwrap()
    .into_frames()
    .collect_frames()
    .unwrap();
    assert_eq!(apng.len(), 4);
    for (f, p) in apng.iter().zip(&pngs) {
        let png = image::open(p).unwrap().to_rgba8();
        assert_eq!(
            f.buffer().as_raw(),
            png.as_raw(),
            "APNG frame vs {}",
            p.display()
        );
    }

    // A long one, cancelled after its first frame: nothing written.
    h.state_mut().ui_state.turntable.frames = 72;
    h.get_by_label("Save turntable as GIF…").click_accesskit();
    h.run_steps(2);
    let long = dir.join("long.gif");
    choose(&mut h, &long);
    step_until(&mut h, "a first turntable frame", |a| {
        a.turntable_progress().is_some_and(|(done, _)| done >= 1)
    });
    h.get_by_label("Cancel turntable").click_accesskit();
    step_until(&mut h, "the cancel", |a| a.turntable_progress().is_none());
    assert!(
        h.state().status().contains("cancelled"),
        "{}",
        h.state().status()
    );
    assert!(!long.exists() && !dir.join("long_frames").exists() && !dir.join("long.png").exists());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// F1 lists the shortcuts (each one the editor handles, F12 among them);
/// Help → About gives the version and the bundled assets' licences.
#[test]
fn f1_lists_the_shortcuts_and_about_names_the_licences() {
    let mut h = harness(false);
    h.step();
    assert!(h.query_by_label("save the viewport image (PNG)").is_none());
    h.key_press(Key::F1);
    h.run_steps(2);
    assert!(h.query_by_label("save the viewport image (PNG)").is_some());
    assert!(h.query_by_label("F12").is_some());
    h.key_press(Key::F1);
    h.run_steps(2);
    assert!(h.query_by_label("save the viewport image (PNG)").is_none());
    // Escape closes it too (the topmost window).
    h.key_press(Key::F1);
    h.run_steps(2);
    assert!(h.query_by_label("save the viewport image (PNG)").is_some());
    h.key_press(Key::Escape);
    h.run_steps(2);
    assert!(h.query_by_label("save the viewport image (PNG)").is_none());
    h.get_by_label("Help").click_accesskit();
    h.run_steps(2);
    h.get_by_label("About scatterlab").click_accesskit();
    h.run_steps(2);
    assert!(h
        .query_by_label(&format!("scatterlab {}", env!("CARGO_PKG_VERSION")))
        .is_some());
    // The procedural head and the HDR maps are CC0, the scan CC BY.
    assert_eq!(h.query_all_by_label_contains("CC0 1.0").count(), 2);
    assert!(h.query_by_label_contains("MakeHuman").is_some());
    assert!(h.query_by_label_contains("make_hdri.py").is_some());
    assert!(h.query_by_label_contains("CC BY 3.0").is_some());
    // With Shortcuts opened over About, Escape closes Shortcuts, then
    // About.
    h.key_press(Key::F1);
    h.run_steps(2);
    h.key_press(Key::Escape);
    h.run_steps(2);
    assert!(h.query_by_label("save the viewport image (PNG)").is_none());
    assert!(h.query_by_label_contains("MakeHuman").is_some());
    h.key_press(Key::Escape);
    h.run_steps(2);
    assert!(h.query_by_label_contains("MakeHuman").is_none());
}

/// F frames the mesh as Blender, Maya and Substance do: the camera's
/// distance and pan go back to what frames it, its direction stays; the
/// shortcut list says so, and that Backslash is the before/after flicker.
#[test]
fn f_frames_the_mesh_and_keeps_the_direction() {
    let mut h = harness(false);
    h.step();
    let framing = h.state().ui_state.view.orbit.camera_distance_m;
    {
        let o = &mut h.state_mut().ui_state.view.orbit;
        o.camera_distance_m = framing * 3.0;
        o.camera_pan_m = [0.05, -0.02];
        o.camera_yaw_rad = 0.7;
    }
    h.run_steps(2);
    h.key_press(Key::F);
    h.run_steps(2);
    let o = h.state().ui_state.view.orbit;
    assert_eq!(o.camera_distance_m, framing);
    assert_eq!(
        o.camera_pan_m,
        scatterlab::settings::OrbitView::default().camera_pan_m
    );
    assert_eq!(o.camera_yaw_rad, 0.7);
    h.key_press(Key::F1);
    h.run_steps(2);
    assert!(h.query_by_label_contains("frame the whole mesh").is_some());
    assert!(h.query_by_label_contains("flicker").is_some());
}

/// An error is a notification that stays until dismissed, not only red
/// text in the status bar that the next message replaces.
#[test]
fn errors_stay_as_notifications_until_dismissed() {
    let mut h = harness(false);
    h.step();
    assert!(h.state().notices().is_empty());
    // No viewport in this editor: saving its image is an error.
    let out =
        std::env::temp_dir().join(format!("scatterlab-ui-noframe-{}.png", std::process::id()));
    h.key_press(Key::F12);
    h.run_steps(2);
    choose(&mut h, &out);
    h.run_steps(3);
    assert!(!out.exists());
    let notices = h.state().notices().to_vec();
    assert_eq!(notices.len(), 1, "{notices:?}");
    assert!(notices[0].contains("no viewport frame"), "{notices:?}");
    // A later message replaces the status line, not the notification.
    let saved =
        std::env::temp_dir().join(format!("scatterlab-ui-notice-{}.ron", std::process::id()));
    h.state_mut().save_as(&saved);
    h.run_steps(3);
    assert!(
        h.state().status().starts_with("Saved"),
        "{}",
        h.state().status()
    );
    assert_eq!(h.state().notices().len(), 1);
    assert!(h
        .query_by_label_contains("no viewport frame to save yet")
        .is_some());
    h.get_by_label("Dismiss notification").click_accesskit();
    h.run_steps(2);
    assert!(h.state().notices().is_empty());
    assert!(h
        .query_by_label_contains("no viewport frame to save yet")
        .is_none());
    std::fs::remove_file(&saved).unwrap();
}

/// A restart into a remembered extreme close-up (a pore, panned off the
/// face) frames the head instead, keeping the angles; a remembered view
/// that shows the head is kept as it was.
#[test]
fn a_restart_never_opens_on_a_sliver_of_the_head() {
    let mut state = UiState::default();
    let o = &mut state.view.orbit;
    o.camera_distance_m = 0.06;
    o.camera_pan_m = [0.05, 0.02];
    o.camera_yaw_rad = 1.0;
    let mut h = harness_of(EditorApp::new(None, state, None, true), [900.0, 560.0]);
    h.step();
    step_until(&mut h, "the head", |a| a.mesh_info().is_some());
    let framing = h.state().mesh_info().unwrap().framing_distance_m;
    let o = h.state().ui_state.view.orbit;
    assert_eq!(o.camera_distance_m, framing);
    assert_eq!(o.camera_pan_m, [0.0; 2]);
    assert_eq!(o.camera_yaw_rad, 1.0);
    assert!(
        h.state().status().contains("remembered view showed about"),
        "{}",
        h.state().status()
    );
    // A close view of the face (0.6 of the framing distance, 36 %) stays.
    let mut state = UiState::default();
    state.view.orbit.camera_distance_m = 0.6 * framing;
    let mut h = harness_of(EditorApp::new(None, state, None, true), [900.0, 560.0]);
    h.step();
    step_until(&mut h, "the head", |a| a.mesh_info().is_some());
    assert_eq!(
        h.state().ui_state.view.orbit.camera_distance_m,
        0.6 * framing
    );
}

/// The plot's radius axis: the default skin's r·R(r) (blue halves within
/// 0.2 mm of a 12.5 mm range) is a spike at zero on a linear axis, so the
/// axis is logarithmic by itself; one wide Gaussian (variance 4 mm²: half
/// its peak past 4 mm of 6.8) stays linear; the checkbox overrides the
/// automatic choice and a right-click gives it back.
#[test]
fn the_radius_axis_goes_log_where_linear_would_be_a_spike() {
    use scatterlab::settings::profile::{GaussianTerm, GaussiansSpec};
    let mut h = harness(false);
    h.step();
    h.step();
    assert!(h.state().plot_log_radius());
    // The range ends at the widest 99.7 % radius (red's, 12.5 mm).
    let last = h.state().plot_series().unwrap()[0].last().unwrap()[0];
    assert!((last - 12.54).abs() < 0.01, "{last}");
    h.get_by_label("log r (auto)").click_accesskit();
    h.run_steps(2);
    assert!(!h.state().plot_log_radius());
    assert_eq!(h.state().ui_state.log_radius, Some(false));
    assert!(h.query_by_label("log r").is_some());
    h.state_mut().ui_state.log_radius = None;
    // The look's own curves decide here (an overlay's would too).
    h.state_mut().ui_state.overlay = scatterlab::app::state::OverlayModel::None;
    h.state_mut().doc.preset.profile = ProfileSpec::Gaussians(GaussiansSpec {
        gaussians: vec![GaussianTerm {
            variance_mm2: 4.0,
            weights: [0.8, 0.5, 0.3],
        }],
        dirac: [0.0; 3],
    });
    h.run_steps(3);
    assert!(!h.state().plot_log_radius());
    assert!(h.query_by_label("log r (auto)").is_some());
}

/// The automatic radius axis looks at every curve drawn (issue 41): one
/// wide Gaussian alone stays linear, but beside B, the default skin (a
/// spike at 0 on a linear axis), it goes logarithmic, and back when the
/// comparison is off.
#[test]
fn the_radius_axis_decides_on_every_curve_shown() {
    use scatterlab::app::state::{CompareB, CompareMode, OverlayModel};
    use scatterlab::settings::profile::{GaussianTerm, GaussiansSpec};
    let dir = std::env::temp_dir().join(format!("scatterlab-ui-logaxis-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let b = dir.join("skin.ron");
    Preset::default_skin().save(&b).unwrap();
    let mut h = harness(false);
    h.step();
    h.state_mut().ui_state.overlay = OverlayModel::None;
    h.state_mut().doc.preset.profile = ProfileSpec::Gaussians(GaussiansSpec {
        gaussians: vec![GaussianTerm {
            variance_mm2: 4.0,
            weights: [0.8, 0.5, 0.3],
        }],
        dirac: [0.0; 3],
    });
    step_until(&mut h, "the Gaussian's analysis", EditorApp::analysis_done);
    assert!(!h.state().plot_log_radius());
    h.state_mut().ui_state.compare = CompareMode::SideBySide;
    h.state_mut().ui_state.compare_b = CompareB::Preset(b);
    h.run_steps(3);
    assert!(
        h.state().plot_log_radius(),
        "B's spike at 0 did not turn the axis log"
    );
    h.state_mut().ui_state.compare = CompareMode::Off;
    h.run_steps(2);
    assert!(!h.state().plot_log_radius());
}

/// An overlay fit whose numbers are not sane is named and not drawn
/// (issue 41: Ketchup opened on a Jimenez fit, "colour changes R +455.8 %");
/// a Burley fit of it is drawn, and "Use fit" gives the look a description
/// of what it now is and what it was fitted to.
#[test]
fn overlays_are_drawn_where_sane_and_a_used_fit_says_what_it_is() {
    use scatterlab::app::state::OverlayModel;
    let ketchup = scatterlab::settings::library::load("ketchup_jensen2001.ron").unwrap();
    let old_description = ketchup.description.clone();
    let state = UiState {
        overlay: OverlayModel::Jimenez,
        ..Default::default()
    };
    let mut h = harness_of(
        EditorApp::new(None, state, Some((ketchup, None)), false),
        [1500.0, 900.0],
    );
    step_until(&mut h, "Ketchup's Jimenez fit", EditorApp::analysis_done);
    assert!(h
        .query_by_label_contains("cannot hold this look: not drawn")
        .is_some());
    h.state_mut().ui_state.overlay = OverlayModel::Burley;
    h.step();
    step_until(&mut h, "Ketchup's Burley fit", EditorApp::analysis_done);
    assert!(h.query_by_label_contains("cannot hold this look").is_none());
    h.get_by_label("Use fit").click_accesskit();
    h.run_steps(2);
    let d = &h.state().doc.preset.description;
    assert!(d.starts_with("A Burley fit"), "{d}");
    assert!(
        d.contains("Before the fit:") && d.contains(old_description.trim()),
        "{d}"
    );
    assert!(matches!(
        h.state().doc.preset.profile,
        ProfileSpec::Burley(_)
    ));
}

/// At 1280×720 each viewport toolbar is one row: the compare modes with
/// "SSS only", then environment, light (exposure inside), Reset view and
/// "to truth" (they wrapped onto 3–4 rows before).
#[test]
fn the_toolbars_are_one_row_each_at_1280x720() {
    let mut h = harness_of(
        EditorApp::new(None, UiState::default(), None, false),
        [1280.0, 720.0],
    );
    h.run_steps(3);
    let top = |label: &str| h.get_by_label(label).rect().center().y;
    let compare = top("off");
    assert!((top("difference") - compare).abs() < 2.0);
    assert!((top("SSS only") - compare).abs() < 2.0);
    let view = top("Light: custom");
    assert!(view > compare + 10.0, "{view} vs {compare}");
    assert!((top("Reset view") - view).abs() < 2.0, "Reset view wrapped");
    assert!((top("to truth") - view).abs() < 2.0);
    let env = h
        .get_all_by_role(egui::accesskit::Role::ComboBox)
        .map(|n| n.rect().center().y)
        .fold(f32::INFINITY, |a, y| {
            if (y - view).abs() < (a - view).abs() {
                y
            } else {
                a
            }
        });
    assert!(
        (env - view).abs() < 2.0,
        "the environment menu is not on the light's row"
    );
    // A mesh loaded and compare on: its units and maps are one menu on
    // the same row (Units… and Maps… had wrapped to a third row).
    let scan = std::path::Path::new(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/scan/LeePerrySmith.glb"
    ));
    h.state_mut().open_mesh(scatterlab::app::MeshArg {
        path: scan.to_path_buf(),
        metres_per_unit: Some(0.0462),
    });
    h.state_mut().ui_state.compare = scatterlab::app::state::CompareMode::SideBySide;
    h.run_steps(3);
    let top = |label: &str| h.get_by_label(label).rect().center().y;
    let view = top("Light: custom");
    assert!((top("Mesh") - view).abs() < 2.0, "the Mesh menu wrapped");
    assert!((top("to truth") - view).abs() < 2.0, "to truth wrapped");
}

/// "SSS only" is the difference view against the same look without
/// scattering (B = none), on the fixed scale the colour bar's numbers give
/// (5 ΔL* by default, the same for another pair); "auto" scales each view
/// to its own largest difference instead.
#[test]
fn sss_only_shows_what_scattering_adds_on_a_fixed_labelled_scale() {
    use scatterlab::app::state::{CompareB, CompareMode};
    use scatterlab::settings::rendering::MethodId;
    let mut h = viewport_harness([900.0, 560.0]);
    h.step();
    h.get_by_label("SSS only").click_accesskit();
    h.run_steps(2);
    assert_eq!(h.state().ui_state.compare, CompareMode::Difference);
    assert_eq!(
        h.state().ui_state.compare_b,
        CompareB::Method(MethodId::None)
    );
    step_until(&mut h, "the difference view", |a| {
        a.viewport().difference_scale_shown().is_some() && a.viewport().idle()
    });
    assert_eq!(h.state().viewport().difference_scale_shown(), Some(5.0));
    // Another pair, the same scale.
    h.state_mut().ui_state.compare_b = CompareB::Method(MethodId::Separable);
    h.run_steps(2);
    step_until(&mut h, "the second pair", |a| a.viewport().idle());
    assert_eq!(h.state().viewport().difference_scale_shown(), Some(5.0));
    h.get_by_label("auto").click_accesskit();
    h.run_steps(2);
    step_until(&mut h, "the auto-scaled view", |a| {
        a.viewport().idle() && a.viewport().difference_scale_shown() != Some(5.0)
    });
    let auto = h.state().viewport().difference_scale_shown().unwrap();
    assert!(auto > 0.0 && auto <= 100.0, "{auto}");
    // Clicked again, SSS only goes back to no comparison.
    h.state_mut().ui_state.compare_b = CompareB::Method(MethodId::None);
    h.run_steps(2);
    h.get_by_label("SSS only").click_accesskit();
    h.run_steps(2);
    assert_eq!(h.state().ui_state.compare, CompareMode::Off);
}

/// Side by side at 1280×720, each half (242 px of a 484 px viewport) shows
/// the whole head: in the upper 60 % of the frame (the head, above the
/// shoulders) no skin touches a half's left or right edge. Before, each
/// half was a crop of one camera that cut off an eye and the ears.
#[test]
fn side_by_side_frames_the_whole_head_in_each_half() {
    use scatterlab::app::state::CompareMode;
    let state = UiState {
        compare: CompareMode::SideBySide,
        ..UiState::default()
    };
    let mut h = harness_of(EditorApp::new(None, state, None, true), [1280.0, 720.0]);
    h.step();
    step_until(&mut h, "the side-by-side frame", |a| {
        a.viewport().idle() && a.viewport().frame().is_some()
    });
    let (frame, _) = h.state().viewport().frame().unwrap();
    let (w, fh) = frame.dimensions();
    let half = w / 2;
    // Skin: warm and bright, unlike the grey-blue background.
    let skin = |x: u32, y: u32| {
        let p = frame.get_pixel(x, y).0;
        p[0] as i32 > p[2] as i32 + 25 && p[0] > 90
    };
    let rows = (fh * 6 / 10) as usize;
    for (side, x0) in [("A", 0), ("B", half)] {
        let mut total = 0;
        for x in [x0, x0 + 1, x0 + half - 2, x0 + half - 1] {
            let touching = (0..rows as u32).filter(|&y| skin(x, y)).count();
            assert!(
                touching == 0,
                "{side}: skin on column {x} in {touching} rows"
            );
        }
        for x in x0..x0 + half {
            total += (0..rows as u32).filter(|&y| skin(x, y)).count();
        }
        // And the head is there: a good part of the half is skin.
        assert!(
            total > half as usize * rows / 10,
            "{side}: {total} skin pixels"
        );
    }
}

/// "before" (and Backslash, Lightroom's before/after key; F frames the
/// mesh) flickers the viewport to the look before the last
/// edit and back: the frame rendered is the old look's (within the
/// refinement's noise of the frame before the edit, far from the edited
/// one); with no edit yet it is off.
#[test]
fn before_flickers_to_the_look_before_the_last_edit() {
    let mut h = viewport_harness([900.0, 560.0]);
    h.step();
    settle(&mut h);
    let original = h.state().viewport().frame().unwrap().0.clone();
    h.key_press(Key::Backslash);
    h.run_steps(2);
    assert!(
        !h.state().viewport().show_before(),
        "no edit yet: nothing to flicker to"
    );
    // An edit: red scattering distance 3 mm.
    h.get_by_label("R: mm").set_value_accesskit(3.0);
    h.run_steps(2);
    settle(&mut h);
    let edited = h.state().viewport().frame().unwrap().0.clone();
    assert!(edited != original, "the edit changed nothing on screen");
    h.key_press(Key::Backslash);
    h.run_steps(2);
    assert!(h.state().viewport().show_before());
    settle(&mut h);
    // With a tolerance (the refinement's noise may differ when the frame
    // is rendered again rather than kept): far nearer the old frame than
    // the edited one is.
    let mean_diff = |a: &image::RgbaImage, b: &image::RgbaImage| -> f64 {
        assert_eq!(a.dimensions(), b.dimensions());
        a.as_raw()
            .iter()
            .zip(b.as_raw())
            .map(|(x, y)| (*x as f64 - *y as f64).abs())
            .sum::<f64>()
            / a.as_raw().len() as f64
    };
    let shown = h.state().viewport().frame().unwrap().0.clone();
    let (to_old, edit) = (mean_diff(&shown, &original), mean_diff(&edited, &original));
    eprintln!("before vs original {to_old:.3}, edited vs original {edit:.3} (8-bit levels)");
    assert!(
        to_old < 0.25 * edit && to_old < 1.0,
        "before is not the old look: {to_old} vs {edit}"
    );
    // The look being edited is untouched.
    assert_eq!(scattering_distance(h.state())[0], 3.0);
    h.get_by_label("before").click_accesskit();
    h.run_steps(2);
    assert!(!h.state().viewport().show_before());
}

/// File → Browse presets… shows every shipped preset as a thumbnail that
/// our renderer drew of the head (ketchup's red differs from skin's),
/// cached on disk: a second editor over the same cache renders none. A
/// click starts a new look from that preset.
#[test]
fn preset_browser_renders_thumbnails_once_and_opens_a_preset() {
    let cache = std::env::temp_dir().join(format!("scatterlab-ui-thumbs-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&cache);
    let browse = |h: &mut Harness<'_, EditorApp>| {
        h.state_mut().set_thumbnail_dir(cache.clone());
        menu_item(h, "File", "Browse presets…");
        step_until(h, "every thumbnail", |a| {
            a.preset_browser()
                .is_some_and(|b| b.progress().0 == b.progress().1)
        });
    };
    let mut h = harness(false);
    h.step();
    browse(&mut h);
    let b = h.state().preset_browser().unwrap();
    let all = b.progress().1;
    assert_eq!(all, scatterlab::settings::library::PRESETS.len());
    assert_eq!(b.rendered, all);
    let stored = std::fs::read_dir(&cache).unwrap().count();
    assert_eq!(stored, all, "one cached PNG a preset");
    let skin = b.thumbnail("Skin (default)").unwrap().clone();
    let ketchup = b.thumbnail("Ketchup (Jensen 2001)").unwrap().clone();
    assert_eq!(skin.dimensions(), scatterlab::app::windows::browser::THUMB);
    // The head fills the middle; ketchup is far redder than skin there.
    let centre = |img: &image::RgbaImage| {
        let p = img.get_pixel(img.width() / 2, img.height() / 2);
        (p[0] as f64, p[1] as f64)
    };
    let (skin_r, skin_g) = centre(&skin);
    let (ketchup_r, ketchup_g) = centre(&ketchup);
    assert!(
        ketchup_r / ketchup_g.max(1.0) > 1.5 * skin_r / skin_g.max(1.0),
        "ketchup {ketchup_r}/{ketchup_g} vs skin {skin_r}/{skin_g}"
    );

    // A second editor over the same cache renders nothing.
    let mut h2 = harness(false);
    h2.step();
    browse(&mut h2);
    assert_eq!(h2.state().preset_browser().unwrap().rendered, 0);
    assert_eq!(
        h2.state()
            .preset_browser()
            .unwrap()
            .thumbnail("Ketchup (Jensen 2001)"),
        Some(&ketchup)
    );
    h2.get_by_label("Ketchup (Jensen 2001)").click_accesskit();
    h2.run_steps(2);
    assert_eq!(h2.state().doc.preset.name, "Ketchup (Jensen 2001)");
    assert!(h2.state().preset_browser().is_none());
    std::fs::remove_dir_all(&cache).unwrap();
}

/// The colour entry behind a colour field's "#" (issue 41): sRGB 0–255
/// and HSV numbers edit the field (linear, as the field holds it: 255 red
/// is 1.0), and the colour left behind is offered among the recent ones,
/// one click bringing it back.
#[test]
fn colours_take_srgb_bytes_hsv_and_recent_colours() {
    let mut h = harness(false);
    h.step();
    let before = match &h.state().doc.preset.profile {
        ProfileSpec::Burley(b) => b.albedo,
        _ => unreachable!(),
    };
    h.get_all_by_label("#").next().unwrap().click_accesskit();
    h.run_steps(2);
    h.get_by_label("R /255").set_value_accesskit(255.0);
    h.run_steps(2);
    let albedo = |h: &egui_kittest::Harness<'_, EditorApp>| match &h.state().doc.preset.profile {
        ProfileSpec::Burley(b) => b.albedo,
        _ => unreachable!(),
    };
    assert!((albedo(&h)[0] - 1.0).abs() < 1e-9, "{:?}", albedo(&h));
    assert_eq!(albedo(&h)[1], before[1]);
    // V 50 %: the brightest sRGB channel at half (linear 0.214).
    h.get_by_label("V %").set_value_accesskit(50.0);
    h.run_steps(2);
    let a = albedo(&h);
    let max = a.iter().cloned().fold(0.0, f64::max);
    assert!((max - 0.214).abs() < 0.002, "{a:?}");
    // The first colour (the look's own) is among the recent ones.
    h.get_by_label("recent colour 2").click_accesskit();
    h.run_steps(2);
    let back = albedo(&h);
    for c in 0..3 {
        assert!((back[c] - before[c]).abs() < 1e-9, "{back:?} vs {before:?}");
    }
}

/// CIE L* of an sRGB pixel, derived here from the standards (IEC 61966-2-1
/// decoding, Rec. 709 luminance, CIE 15:2004 eq. 8.1), not the editor's.
fn cie_lightness(p: &image::Rgba<u8>) -> f64 {
    let lin = |v: u8| {
        let c = v as f64 / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let y = 0.2126 * lin(p[0]) + 0.7152 * lin(p[1]) + 0.0722 * lin(p[2]);
    if y > (6.0f64 / 29.0).powi(3) {
        116.0 * y.cbrt() - 16.0
    } else {
        116.0 * (y / (3.0 * (6.0f64 / 29.0).powi(2)) + 4.0 / 29.0) - 16.0
    }
}

/// The pixel probe reads the frame under the pointer (its L* as the CIE
/// formula gives it), side by side it reads both sides and their ΔL*, and
/// the difference view states the mean and largest ΔL* over the head.
#[test]
fn the_probe_reads_the_pixel_and_both_sides() {
    use scatterlab::app::state::CompareMode;
    let mut h = viewport_harness([1500.0, 900.0]);
    step_until(&mut h, "the head", |a: &EditorApp| a.viewport().has_frame());
    settle(&mut h);
    let rect = h.state().viewport_layout().viewport.unwrap();
    let at = rect.center();
    h.input_mut().events.push(egui::Event::PointerMoved(at));
    h.run_steps(2);
    let text = h
        .state()
        .probe_text()
        .expect("no probe over the head")
        .to_owned();
    let img = h.state().viewport().frame().unwrap().0.clone();
    let x = ((at.x - rect.left()) / rect.width() * img.width() as f32) as u32;
    let y = ((at.y - rect.top()) / rect.height() * img.height() as f32) as u32;
    let p = img.get_pixel(x, y);
    let want = format!("sRGB {} {} {}", p[0], p[1], p[2]);
    assert!(text.contains(&want), "{text} (want {want})");
    let l = cie_lightness(p);
    assert!(
        text.contains(&format!("L* {l:.1}")),
        "{text} (want L* {l:.1})"
    );
    // Side by side: both sides' L* and ΔL*.
    h.state_mut().ui_state.compare = CompareMode::SideBySide;
    let n0 = h.state().viewport().frame().map_or(0, |f| f.1);
    step_until(&mut h, "the side-by-side frame", |a| {
        a.viewport().idle() && a.viewport().frame().is_some_and(|f| f.1 > n0)
    });
    h.input_mut().events.push(egui::Event::PointerMoved(
        rect.center() - egui::vec2(rect.width() / 4.0, 0.0),
    ));
    h.run_steps(2);
    let text = h.state().probe_text().unwrap().to_owned();
    assert!(
        text.starts_with("A sRGB") && text.contains("B L*") && text.contains("ΔL*"),
        "{text}"
    );
    // The difference view's note: mean and max ΔL* over the head.
    h.state_mut().ui_state.compare = CompareMode::Difference;
    let n1 = h.state().viewport().frame().map_or(0, |f| f.1);
    step_until(&mut h, "the difference frame", |a| {
        a.viewport().idle() && a.viewport().frame().is_some_and(|f| f.1 > n1)
    });
    h.run_steps(2);
    assert!(
        h.query_by_label_contains("over the head").is_some(),
        "no mean and max ΔL*: {}",
        h.state().status()
    );
    let text = h.state().probe_text().unwrap_or_default().to_owned();
    assert!(text.starts_with("|ΔL*|"), "{text}");
}

/// File → Save image at size renders offscreen at the size asked, not the
/// window's: 320×200 at 1× and 2× supersampling are that size, show the
/// head, agree but for edge pixels, and 2× smooths the edges (more
/// in-between values). The file name proposed names the size.
#[test]
fn save_image_at_size_renders_offscreen_at_that_size() {
    let dir = std::env::temp_dir().join(format!("scatterlab-ui-still-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = viewport_harness([900.0, 560.0]);
    h.step();
    settle(&mut h);
    menu_item(&mut h, "File", "Save image at size…");
    let mut saved = Vec::new();
    for k in [1u32, 2] {
        h.state_mut().ui_state.still = scatterlab::app::state::StillSettings {
            width: 320,
            height: 200,
            supersample: k,
            ..Default::default()
        };
        h.run_steps(2);
        h.get_by_label("Save image (PNG or EXR)…").click_accesskit();
        wait_for_file_dialog(&mut h);
        assert_eq!(
            name_field(&h).value().unwrap(),
            "skin_default_burley_320x200.png"
        );
        let out = dir.join(format!("still_{k}.png"));
        choose(&mut h, &out);
        step_until(&mut h, "the still", |a| !a.still_running());
        assert!(
            h.state().status().starts_with("Saved image"),
            "{}",
            h.state().status()
        );
        let img = image::open(&out).unwrap().to_rgba8();
        assert_eq!(img.dimensions(), (320, 200));
        saved.push(img);
    }
    let bg = *saved[0].get_pixel(0, 0);
    let centre = *saved[0].get_pixel(160, 100);
    assert!(
        (0..3).any(|c| centre[c].abs_diff(bg[c]) > 30),
        "no head at the centre: {centre:?}"
    );
    let d = mean_difference(&saved[0], &saved[1]);
    assert!(d < 3.0, "1× and 2× differ by {d:.2} on average");
    // Edge pixels between head and background: 2× has more distinct values.
    let distinct = |img: &image::RgbaImage| {
        let mut v: Vec<[u8; 4]> = img.pixels().map(|p| p.0).collect();
        v.sort_unstable();
        v.dedup();
        v.len()
    };
    assert!(
        distinct(&saved[1]) > distinct(&saved[0]),
        "2× did not smooth anything"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// The artist's own preset folders in the browser: a folder's presets are
/// listed after the shipped ones (a broken file is named, not listed), a
/// click opens the file itself; the folder is remembered. View → the
/// interface scale and theme reach egui (zoom factor, light visuals).
#[test]
fn own_preset_folders_and_the_interface_scale_and_theme() {
    let dir =
        std::env::temp_dir().join(format!("scatterlab-ui-own-presets-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut mine = scatterlab::settings::Preset::default_skin();
    mine.name = "My pale skin".into();
    let file = dir.join("my_pale_skin.ron");
    mine.save(&file).unwrap();
    std::fs::write(dir.join("broken.ron"), "(format_version: 2, name: ").unwrap();
    let state = UiState {
        preset_folders: vec![dir.clone()],
        ..Default::default()
    };
    let mut h = harness_of(EditorApp::new(None, state, None, false), [1500.0, 900.0]);
    h.state_mut().set_thumbnail_dir(dir.join("thumbs"));
    menu_item(&mut h, "File", "Browse presets…");
    h.run_steps(2);
    let b = h.state().preset_browser().unwrap();
    assert_eq!(b.own_presets(), vec![file.as_path()]);
    assert!(
        b.skipped.len() == 1 && b.skipped[0].contains("broken.ron"),
        "{:?}",
        b.skipped
    );
    assert!(h.query_by_label_contains("Not listed:").is_some());
    h.get_by_label("My pale skin").click_accesskit();
    h.run_steps(3);
    assert_eq!(h.state().doc.path.as_deref(), Some(file.as_path()));
    assert_eq!(h.state().doc.preset.name, "My pale skin");

    h.state_mut().ui_state.ui_scale = 1.5;
    h.state_mut().ui_state.light_theme = true;
    h.run_steps(3);
    assert!((h.ctx.zoom_factor() - 1.5).abs() < 1e-4);
    assert_eq!(h.ctx.theme(), egui::Theme::Light);
    assert!(!h.ctx.global_style().visuals.dark_mode);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// File → Reference image: the photo opens in its window, a click on it
/// writes the 5×5 linear mean under the pointer into the look's albedo
/// (sRGB (200, 120, 90) decoded by IEC 61966-2-1 in this test), undo gives
/// the albedo back, and "over the render" draws it on the viewport.
#[test]
fn the_reference_image_eyedropper_picks_into_the_albedo() {
    let dir = std::env::temp_dir().join(format!("scatterlab-ui-reference-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let photo = dir.join("photo.png");
    image::RgbaImage::from_pixel(64, 48, image::Rgba([200, 120, 90, 255]))
        .save(&photo)
        .unwrap();
    let mut h = harness(false);
    h.step();
    let before = match &h.state().doc.preset.profile {
        ProfileSpec::Burley(b) => b.albedo,
        _ => unreachable!(),
    };
    menu_item(&mut h, "File", "Reference image…");
    wait_for_file_dialog(&mut h);
    choose(&mut h, &photo);
    h.run_steps(3);
    assert_eq!(h.state().reference_path(), Some(photo.as_path()));
    let image = h
        .get_all_by_role(egui::accesskit::Role::Image)
        .last()
        .expect("no reference image shown");
    image.click();
    h.run_steps(3);
    let lin = |v: f64| ((v / 255.0 + 0.055) / 1.055).powf(2.4);
    let want = [lin(200.0), lin(120.0), lin(90.0)];
    match &h.state().doc.preset.profile {
        ProfileSpec::Burley(b) => {
            for c in 0..3 {
                assert!(
                    (b.albedo[c] - want[c]).abs() < 1e-5,
                    "{:?} against {want:?}",
                    b.albedo
                );
            }
        }
        p => panic!("{p:?}"),
    }
    assert!(
        h.state().status().starts_with("Albedo picked:"),
        "{}",
        h.state().status()
    );
    h.key_press_modifiers(Modifiers::COMMAND, Key::Z);
    h.run_steps(2);
    match &h.state().doc.preset.profile {
        ProfileSpec::Burley(b) => assert_eq!(b.albedo, before),
        p => panic!("{p:?}"),
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
