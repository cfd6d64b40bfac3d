#![allow(clippy::unwrap_used)]
//! The real editor window: `scatterlab edit` under Xvfb (winit, the eframe
//! wgpu surface on lavapipe, the render thread) opens, shows the head and
//! closes. `.ci/run` installs Xvfb; without it this test fails rather than
//! skips.

use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

struct Xvfb(Child);

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

#[test]
fn editor_window_opens_shows_the_head_and_closes() {
    // A display number of our own.
    let display = format!(":{}", 100 + std::process::id() % 800);
    let xvfb = Command::new("Xvfb")
        .args([
            display.as_str(),
            "-screen",
            "0",
            "1600x1000x24",
            "-nolisten",
            "tcp",
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("Xvfb is needed for the window test (apt-get install xvfb; .ci/run does)");
    let _xvfb = Xvfb(xvfb);
    std::thread::sleep(Duration::from_millis(1500));
    // A fresh home: no remembered window or preset.
    let home = std::env::temp_dir().join(format!("scatterlab-window-home-{}", std::process::id()));
    std::fs::create_dir_all(&home).unwrap();
    let runtime = home.join("runtime");
    std::fs::create_dir_all(&runtime).unwrap();
    let mut child = Command::new(env!("CARGO_BIN_EXE_scatterlab"))
        .args(["edit", "--exit-after-first-frame"])
        .env("DISPLAY", &display)
        .env("HOME", &home)
        .env("XDG_RUNTIME_DIR", &runtime)
        .env_remove("WAYLAND_DISPLAY")
        .env("SCATTERLAB_TIMINGS", "1")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if t0.elapsed() > Duration::from_secs(300) {
            let _ = child.kill();
            panic!("the editor did not show the head and close within 300 s");
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let out = child.wait_with_output().unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(status.success(), "editor exited with {status}: {stderr}");
    assert!(stderr.contains("timing: first UI frame"), "{stderr}");
    assert!(stderr.contains("timing: first viewport frame"), "{stderr}");
    // The first frame already has the head's skin maps (issue 25): they
    // bake before it, not after (they used to pop in a second later).
    let baked = stderr.find("timing: skin maps baked");
    let shown = stderr.find("timing: first viewport frame");
    assert!(
        matches!((baked, shown), (Some(b), Some(s)) if b < s),
        "the skin maps did not bake before the first viewport frame: {stderr}"
    );
    // The start-up figures, for the log (budgets are measured, not asserted).
    for line in stderr.lines().filter(|l| l.contains("first")) {
        eprintln!("{line}");
    }
    std::fs::remove_dir_all(&home).unwrap();
}
