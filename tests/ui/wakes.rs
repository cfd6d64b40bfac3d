//! Issue 36: a background job's result reaches the screen with no input.
//! egui draws a frame only on input or when asked to, so each job's thread
//! must ask for one when it finishes, and a frame that changes what it
//! drew earlier (the status bar, drawn first) must ask for the next.
//!
//! Each test starts a job, draws the frames the editor asks for, and then
//! steps nothing: it waits for a repaint request from another thread
//! (egui's repaint observer sees every request; eframe's event loop wakes
//! on them), then draws only the frames egui asks for at once, as eframe
//! would with no input, and finds the result in the accessibility tree.

use super::*;
use std::sync::{Arc, Mutex};
use std::time::SystemTime;

/// Every repaint request egui gets from a thread other than the one that
/// draws the frames (a job's): when it came (both clocks: a file's time is
/// a `SystemTime`) and the delay asked for. The frames' own requests are
/// not logged, so nothing need be cleared after drawing them: clearing
/// them once also cleared the wake of a job that ended while they were
/// drawn (a uniform HDR map loads in milliseconds), and the test then
/// waited 60 s for a wake that had come.
#[derive(Clone, Default)]
struct Repaints(Arc<Mutex<Vec<(Instant, SystemTime, Duration)>>>);

impl Repaints {
    fn watch(h: &Harness<'_, EditorApp>) -> Self {
        let log = Self::default();
        let theirs = log.clone();
        let drawing = std::thread::current().id();
        h.ctx.set_repaint_observer(move |info| {
            if std::thread::current().id() == drawing {
                return;
            }
            if let Ok(mut v) = theirs.0.lock() {
                v.push((Instant::now(), SystemTime::now(), info.delay));
            }
        });
        log
    }

    fn clear(&self) {
        self.0.lock().unwrap().clear();
    }

    /// Waits, drawing nothing, until something asks for a frame within
    /// 0.5 s (eframe then draws one); when it asked.
    fn wait_for_wake(&self, what: &str, limit_s: u64) -> SystemTime {
        let t0 = Instant::now();
        loop {
            let woken = self
                .0
                .lock()
                .unwrap()
                .iter()
                .find(|(_, _, delay)| *delay <= Duration::from_millis(500))
                .map(|&(_, at, _)| at);
            if let Some(at) = woken {
                return at;
            }
            assert!(
                t0.elapsed() < Duration::from_secs(limit_s),
                "{what}: no frame was asked for within {limit_s} s (the result would wait for the next input)"
            );
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

/// The frames eframe draws with no input after a wake: one, then one more
/// for each that asks for another at once (at most ten).
fn frames_without_input(h: &mut Harness<'_, EditorApp>) {
    h.step();
    for _ in 0..10 {
        let asked = h
            .output()
            .viewport_output
            .get(&egui::ViewportId::ROOT)
            .map_or(Duration::MAX, |v| v.repaint_delay);
        if asked != Duration::ZERO {
            return;
        }
        h.step();
    }
}

/// Waits for wakes and draws their frames until `shown` holds of the
/// editor and of what is on screen, `limit_s` at most.
fn shown_without_input(
    h: &mut Harness<'_, EditorApp>,
    repaints: &Repaints,
    what: &str,
    limit_s: u64,
    shown: impl Fn(&Harness<'_, EditorApp>) -> bool,
) -> SystemTime {
    let t0 = Instant::now();
    if shown(h) {
        // Drawn by the frames the editor asked for after the start.
        return SystemTime::now();
    }
    loop {
        let left = limit_s.saturating_sub(t0.elapsed().as_secs()).max(1);
        let at = repaints.wait_for_wake(what, left);
        repaints.clear();
        frames_without_input(h);
        if shown(h) {
            return at;
        }
    }
}

/// Forgets the wakes so far, then draws the frames the editor asks for at
/// once. A wake that comes while they are drawn stays logged.
fn quiet(h: &mut Harness<'_, EditorApp>, repaints: &Repaints) {
    repaints.clear();
    frames_without_input(h);
}

fn status_shows(h: &Harness<'_, EditorApp>, text: &str) -> bool {
    h.query_by_label_contains(text).is_some()
}

/// The frame that showed `what` was asked for within 0.5 s of `file`'s
/// time (the job's end), not at some later input or timer.
fn woken_soon_after(woke: SystemTime, file: &std::path::Path, what: &str) {
    let written = std::fs::metadata(file).unwrap().modified().unwrap();
    let late = woke.duration_since(written).unwrap_or_default();
    eprintln!(
        "{what} written, frame asked for {:.0} ms later",
        late.as_secs_f64() * 1e3
    );
    assert!(
        late < Duration::from_millis(500),
        "{what}: the frame was asked for {late:?} after {}",
        file.display()
    );
}

/// An export's thread wakes the editor when its files are written: the
/// status bar says "Exported …" within 0.5 s of the file's time, with no
/// input. (Only wakes from other threads count: the status bar's spinner
/// asks for frames while an export or an environment load runs, and these
/// two passed with the wakes taken out while the spinner's requests were
/// counted. With the environment loader's wake taken out, its test now
/// fails after 60 s.)
#[test]
fn a_finished_export_is_shown_without_input() {
    let dir =
        std::env::temp_dir().join(format!("scatterlab-ui-wake-export-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = harness(false);
    let repaints = Repaints::watch(&h);
    step_until(&mut h, "the first analysis", EditorApp::analysis_done);
    quiet(&mut h, &repaints);
    // An export with the table bakes on its thread (seconds), so that the
    // frames below are drawn before it ends and the wake is its own.
    let format = *scatterlab::export::Format::all()
        .iter()
        .find(|f| f.is_slow())
        .expect("an export with table bakes");
    let out = dir.join(format!("look.{}", format.extension()));
    h.state_mut().export(format, out.clone());
    // The job has started: its wake may come while these are drawn.
    frames_without_input(&mut h);
    let woke = shown_without_input(&mut h, &repaints, "the export", 120, |h| {
        status_shows(h, "Exported")
    });
    woken_soon_after(woke, &out, "the export");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An HDR map loads on its own thread; the head is lit by it and the
/// status says so with no input.
#[test]
fn a_loaded_environment_is_shown_without_input() {
    let dir = std::env::temp_dir().join(format!("scatterlab-ui-wake-env-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let map = dir.join("uniform.hdr");
    uniform_hdr(&map, [0.5, 0.25, 0.125]);
    let mut h = harness(false);
    let repaints = Repaints::watch(&h);
    step_until(&mut h, "the first analysis", EditorApp::analysis_done);
    quiet(&mut h, &repaints);
    h.state_mut().load_environment(map.clone());
    // The job has started: its wake may come while these are drawn.
    frames_without_input(&mut h);
    shown_without_input(&mut h, &repaints, "the environment", 60, |h| {
        status_shows(h, &format!("Environment {}", map.display()))
    });
    assert!(h.state().ui_state.view.environment_map_sh.is_some());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A profile edit is analysed on the analysis thread (fits, taps, tables);
/// its result is taken in with no input.
#[test]
fn a_finished_analysis_is_shown_without_input() {
    let mut h = harness(false);
    let repaints = Repaints::watch(&h);
    step_until(&mut h, "the first analysis", EditorApp::analysis_done);
    quiet(&mut h, &repaints);
    h.get_by_label("R: mm").set_value_accesskit(2.5);
    // The job has started: its wake may come while these are drawn.
    frames_without_input(&mut h);
    shown_without_input(&mut h, &repaints, "the analysis", 120, |h| {
        h.state().analysis_done()
    });
}

/// File → Browse presets…: each thumbnail rendered on the browser's own
/// render thread wakes the editor.
#[test]
fn a_rendered_thumbnail_is_shown_without_input() {
    let cache =
        std::env::temp_dir().join(format!("scatterlab-ui-wake-thumbs-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&cache);
    let mut h = harness(false);
    let repaints = Repaints::watch(&h);
    h.step();
    h.state_mut().set_thumbnail_dir(cache.clone());
    // The wakes before the job (the first analysis) forgotten.
    repaints.clear();
    menu_item(&mut h, "File", "Browse presets…");
    // The job has started: its wake may come while these are drawn.
    frames_without_input(&mut h);
    shown_without_input(&mut h, &repaints, "a thumbnail", 180, |h| {
        h.state()
            .preset_browser()
            .is_some_and(|b| b.progress().0 >= 1)
    });
    drop(h);
    let _ = std::fs::remove_dir_all(&cache);
}

/// File → Save turntable…: the turntable's thread wakes the editor with
/// each frame and when the GIF is written, and "Saved turntable …" is on
/// screen within 0.5 s of the GIF's time. The window polls the job after
/// the status bar is drawn, so this also needs the frame that changed the
/// status to ask for the next.
#[test]
fn a_finished_turntable_is_shown_without_input() {
    let dir = std::env::temp_dir().join(format!("scatterlab-ui-wake-turn-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let mut h = viewport_harness([900.0, 560.0]);
    let repaints = Repaints::watch(&h);
    h.step();
    super::artist::settle(&mut h);
    menu_item(&mut h, "File", "Save turntable…");
    h.state_mut().ui_state.turntable.frames = 2;
    h.state_mut().ui_state.turntable.png_sequence = false;
    h.get_by_label("Save turntable as GIF…").click_accesskit();
    wait_for_file_dialog(&mut h);
    let out = dir.join("spin.gif");
    // The wakes before the job (the render thread's frames) forgotten.
    repaints.clear();
    choose(&mut h, &out);
    assert!(
        h.state().turntable_progress().is_some(),
        "{}",
        h.state().status()
    );
    // The job has started: its wake may come while these are drawn.
    frames_without_input(&mut h);
    let woke = shown_without_input(&mut h, &repaints, "the turntable", 300, |h| {
        status_shows(h, "Saved turntable")
    });
    woken_soon_after(woke, &out, "the turntable");
    std::fs::remove_dir_all(&dir).unwrap();
}
