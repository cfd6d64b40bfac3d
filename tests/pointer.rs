#![allow(clippy::unwrap_used)]
//! Issue 51: what a test drives through AccessKit a user must reach with a
//! pointer. The real editor (`scatterlab edit` under Xvfb, on lavapipe) is
//! driven by `xdotool`, at 1500×900 and 1280×720. Controls are found by
//! what they are, their AccessKit role and label, in the editor's widget
//! map (`SCATTERLAB_WIDGET_MAP`, `app/widget_map.rs`), never by window
//! coordinates; each is clicked or typed into at its centre, and the test
//! checks what it did in the frame log (the requests the render thread was
//! sent) or in the control's own value.
//!
//! A combo box or a text field inside a menu cannot be used this way: the
//! click that opens the combo's list lands outside the menu, and egui
//! closes the menu with the combo in it (egui issues #4153, #7821).

use std::path::PathBuf;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant, SystemTime};

/// A control in the widget map: role, label, value and its rectangle in
/// window pixels.
#[derive(Clone, Debug)]
struct Widget {
    role: String,
    label: String,
    value: String,
    rect: [f32; 4],
}

impl Widget {
    fn centre(&self) -> (i32, i32) {
        (
            ((self.rect[0] + self.rect[2]) / 2.0).round() as i32,
            ((self.rect[1] + self.rect[3]) / 2.0).round() as i32,
        )
    }
}

/// Xvfb, the editor in it, and where its map and log are.
struct Session {
    display: String,
    size: (u32, u32),
    dir: PathBuf,
    wid: String,
    editor: Child,
    /// Dropped after the editor (fields drop in order).
    _xvfb: Xvfb,
}

impl Drop for Session {
    fn drop(&mut self) {
        let _ = self.editor.kill();
        let _ = self.editor.wait();
        // The editor's files stay for a failure's message, not after.
        if !std::thread::panicking() {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

/// Xvfb, stopped (TERM, so it removes its lock file) however the test ends.
struct Xvfb(Child);

impl Drop for Xvfb {
    fn drop(&mut self) {
        let _ = Command::new("kill").arg(self.0.id().to_string()).status();
        let _ = self.0.wait();
    }
}

impl Session {
    /// The editor with fresh state at `w`×`h` on a display of its own.
    fn start(name: &str, w: u32, h: u32) -> Self {
        let dir = std::env::temp_dir().join(format!(
            "scatterlab-pointer-{name}-{w}x{h}-{}",
            std::process::id()
        ));
        let _ = std::fs::remove_dir_all(&dir);
        for d in ["data", "config", "runtime"] {
            std::fs::create_dir_all(dir.join(d)).unwrap();
        }
        // A display of our own: Xvfb picks a free number and writes it to
        // the pipe (-displayfd), so tests running at once never share one.
        let xvfb = Command::new("Xvfb")
            .args([
                "-displayfd",
                "1",
                "-screen",
                "0",
                &format!("{w}x{h}x24"),
                "-nolisten",
                "tcp",
            ])
            .stdout(Stdio::piped())
            .stderr(Stdio::null())
            .spawn()
            .expect("Xvfb is needed for the pointer test (apt-get install xvfb; .ci/run does)");
        let mut xvfb = Xvfb(xvfb);
        let mut number = String::new();
        {
            use std::io::BufRead;
            let out = xvfb.0.stdout.take().unwrap();
            std::io::BufReader::new(out).read_line(&mut number).unwrap();
        }
        let display = format!(":{}", number.trim());
        assert!(display.len() > 1, "Xvfb named no display");
        let editor = Command::new(env!("CARGO_BIN_EXE_scatterlab"))
            .args(["edit", "--procedural-head"])
            .env("DISPLAY", &display)
            .env("XDG_DATA_HOME", dir.join("data"))
            .env("XDG_CONFIG_HOME", dir.join("config"))
            .env("XDG_RUNTIME_DIR", dir.join("runtime"))
            .env_remove("WAYLAND_DISPLAY")
            .env("SCATTERLAB_FRAME_LOG", dir.join("frames.log"))
            .env("SCATTERLAB_WIDGET_MAP", dir.join("widgets.tsv"))
            .stdout(Stdio::null())
            .stderr(Stdio::from(
                std::fs::File::create(dir.join("editor.err")).unwrap(),
            ))
            .spawn()
            .unwrap();
        let mut s = Session {
            display,
            size: (w, h),
            dir,
            wid: String::new(),
            editor,
            _xvfb: xvfb,
        };
        let t0 = Instant::now();
        while s.wid.is_empty() {
            assert!(
                t0.elapsed() < Duration::from_secs(180),
                "the editor's window did not open: {}",
                s.editor_err()
            );
            std::thread::sleep(Duration::from_millis(200));
            s.wid = s
                .xdotool(&["search", "--name", "scatterlab"])
                .lines()
                .next()
                .unwrap_or("")
                .to_owned();
        }
        let wid = s.wid.clone();
        s.xdotool(&["windowmove", &wid, "0", "0"]);
        s.xdotool(&["windowsize", &wid, &w.to_string(), &h.to_string()]);
        s.xdotool(&["windowfocus", "--sync", &wid]);
        // The first frame of the head: start-up work done.
        s.wait_log("a converged frame", 300, |l| {
            l.contains(" frame converged ")
        });
        s
    }

    fn editor_err(&self) -> String {
        std::fs::read_to_string(self.dir.join("editor.err")).unwrap_or_default()
    }

    fn xdotool(&self, args: &[&str]) -> String {
        let out = Command::new("xdotool")
            .args(args)
            .env("DISPLAY", &self.display)
            .output()
            .expect(
                "xdotool is needed for the pointer test (apt-get install xdotool; .ci/run does)",
            );
        String::from_utf8_lossy(&out.stdout).trim().to_owned()
    }

    /// The widget map written after `since`, if one is. The editor
    /// rewrites its map only when it changed, so once `settled` an older
    /// one is taken too.
    fn widgets_since(&self, since: SystemTime, settled: bool) -> Option<Vec<Widget>> {
        let path = self.dir.join("widgets.tsv");
        let modified = std::fs::metadata(&path).ok()?.modified().ok()?;
        if modified <= since && !settled {
            return None;
        }
        let text = std::fs::read_to_string(&path).ok()?;
        Some(
            text.lines()
                .filter(|l| !l.starts_with('#'))
                .filter_map(|l| {
                    let f: Vec<&str> = l.split('\t').collect();
                    let r: Vec<f32> = f
                        .get(3)?
                        .split(' ')
                        .filter_map(|v| v.parse().ok())
                        .collect();
                    (f.len() == 4 && r.len() == 4).then(|| Widget {
                        role: f[0].into(),
                        label: f[1].into(),
                        value: f[2].into(),
                        rect: [r[0], r[1], r[2], r[3]],
                    })
                })
                .collect(),
        )
    }

    /// The one control `pick` chooses from a map written after this call,
    /// on screen; within 15 s (the pointer wiggles over the window's
    /// corner meanwhile: the editor writes its map on frames).
    fn find(&self, what: &str, pick: impl Fn(&Widget) -> bool) -> Widget {
        let since = SystemTime::now();
        let t0 = Instant::now();
        let mut last = Vec::new();
        while t0.elapsed() < Duration::from_secs(15) {
            if let Some(ws) = self.widgets_since(since, t0.elapsed() > Duration::from_secs(1)) {
                let hits: Vec<Widget> = ws
                    .iter()
                    .filter(|w| pick(w))
                    .filter(|w| {
                        let (x, y) = w.centre();
                        w.rect[2] - w.rect[0] >= 4.0
                            && w.rect[3] - w.rect[1] >= 4.0
                            && (0..self.size.0 as i32).contains(&x)
                            && (0..self.size.1 as i32).contains(&y)
                    })
                    .cloned()
                    .collect();
                if hits.len() == 1 {
                    return hits[0].clone();
                }
                last = ws;
            }
            let wid = self.wid.clone();
            self.xdotool(&["mousemove", "--window", &wid, "1", "1"]);
            self.xdotool(&["mousemove", "--window", &wid, "2", "2"]);
            std::thread::sleep(Duration::from_millis(150));
        }
        let shown: Vec<String> = last
            .iter()
            .map(|w| format!("{} '{}' = '{}' at {:?}", w.role, w.label, w.value, w.rect))
            .collect();
        let shot = self.screenshot(what);
        panic!(
            "at {}×{}: cannot reach {what} (not on screen as one control); screenshot {}; the controls on screen:\n{}",
            self.size.0,
            self.size.1,
            shot.display(),
            shown.join("\n")
        );
    }

    /// Waits until no control `pick` chooses is on screen (15 s).
    fn gone(&self, what: &str, pick: impl Fn(&Widget) -> bool) {
        let since = SystemTime::now();
        let t0 = Instant::now();
        while t0.elapsed() < Duration::from_secs(15) {
            if let Some(ws) = self.widgets_since(since, t0.elapsed() > Duration::from_secs(1)) {
                if !ws.iter().any(&pick) {
                    return;
                }
            }
            let wid = self.wid.clone();
            self.xdotool(&["mousemove", "--window", &wid, "1", "1"]);
            self.xdotool(&["mousemove", "--window", &wid, "2", "2"]);
            std::thread::sleep(Duration::from_millis(150));
        }
        let shot = self.screenshot(what);
        panic!(
            "at {}×{}: {what} is still on screen; screenshot {}",
            self.size.0,
            self.size.1,
            shot.display()
        );
    }

    /// A picture of the screen, for a failure's message.
    fn screenshot(&self, what: &str) -> PathBuf {
        let name: String = what
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!(
            "pointer-{}x{}-{name}.png",
            self.size.0, self.size.1
        ));
        let _ = Command::new("import")
            .args(["-window", "root", out.to_str().unwrap()])
            .env("DISPLAY", &self.display)
            .status();
        out
    }

    /// Moves to the control's centre and clicks it.
    fn click(&self, w: &Widget) {
        let (x, y) = w.centre();
        let wid = self.wid.clone();
        self.xdotool(&[
            "mousemove",
            "--window",
            &wid,
            &x.to_string(),
            &y.to_string(),
        ]);
        std::thread::sleep(Duration::from_millis(150));
        self.xdotool(&["click", "1"]);
        std::thread::sleep(Duration::from_millis(300));
    }

    /// Types `text` into the focused field, all of its old text replaced,
    /// and presses Enter.
    fn type_into_focused(&self, text: &str) {
        // X's keyboard focus on the window first (with no window manager
        // nothing gives it; tests/window.rs saw keys lost without it).
        let wid = self.wid.clone();
        self.xdotool(&["windowfocus", "--sync", &wid]);
        self.xdotool(&["key", "ctrl+a"]);
        self.xdotool(&["type", "--delay", "30", text]);
        self.xdotool(&["key", "Return"]);
        std::thread::sleep(Duration::from_millis(300));
    }

    /// Waits for a frame-log line `ok` accepts.
    fn wait_log(&self, what: &str, limit_s: u64, ok: impl Fn(&str) -> bool) -> String {
        let t0 = Instant::now();
        loop {
            let log = std::fs::read_to_string(self.dir.join("frames.log")).unwrap_or_default();
            if let Some(l) = log.lines().find(|l| ok(l)) {
                return l.to_owned();
            }
            assert!(
                t0.elapsed() < Duration::from_secs(limit_s),
                "at {}×{}: no {what} in the frame log within {limit_s} s; the editor said:\n{}",
                self.size.0,
                self.size.1,
                self.editor_err()
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }
}

const SIZES: [(u32, u32); 2] = [(1500, 900), (1280, 720)];

/// The display transform, chosen with a pointer: the light settings
/// opened, the display combo box opened, AgX clicked; the render thread is
/// then asked for frames with AgX.
#[test]
fn the_display_transform_is_chosen_with_a_pointer() {
    for (w, h) in SIZES {
        let s = Session::start("display", w, h);
        let light = s.find("the Light menu", |c| {
            c.role == "Button" && c.label.starts_with("Light:")
        });
        s.click(&light);
        let window = s.find("Light & display… in the Light menu", |c| {
            c.role == "Button" && c.label == "Light & display…"
        });
        s.click(&window);
        // Labelled "display", or (egui's ComboBox::from_label names only
        // the label beside it) the combo showing the default transform.
        let combo = s.find("the display combo box", |c| {
            c.role == "ComboBox" && (c.label == "display" || c.value == "ACES fit (Narkowicz)")
        });
        s.click(&combo);
        let agx = s.find("AgX in the display list", |c| {
            c.label == "AgX" && c.role != "ComboBox"
        });
        s.click(&agx);
        s.wait_log("request with AgX", 30, |l| {
            l.contains(" request ") && l.ends_with("display=AgX")
        });
        // The window stays open, showing what was chosen.
        s.find("the display combo box showing AgX", |c| {
            c.role == "ComboBox" && c.label == "display" && c.value == "AgX"
        });
    }
}

/// The HDR map's turn, typed in with the keyboard after a pointer click
/// (View → Light & display, a shipped map chosen there, the turn field
/// clicked, 45 typed, Enter): the field shows 45° and the render thread
/// is asked for a new frame.
#[test]
fn the_hdr_maps_turn_is_typed_into_with_a_pointer_and_keys() {
    for (w, h) in SIZES {
        let s = Session::start("turn", w, h);
        let view = s.find("the View menu", |c| c.role == "Button" && c.label == "View");
        s.click(&view);
        let item = s.find("Light & display… in the View menu", |c| {
            c.role == "Button" && c.label == "Light & display…"
        });
        s.click(&item);
        let map = s.find("a shipped HDR map", |c| {
            c.role == "Button" && c.label == "studio softboxes"
        });
        s.click(&map);
        // Loaded (not "Loading environment …"): the turn field is enabled.
        s.wait_log("the map's environment", 120, |l| {
            l.contains(" status Environment ") && l.contains(".hdr")
        });
        let field = s.find("the turn field", |c| {
            c.role == "SpinButton" && c.label == "turn °"
        });
        s.click(&field);
        // Typed only once the field is a text edit (its value without the
        // prefix): keys in the frame of the click are lost.
        s.find("the turn field as a text edit", |c| {
            c.role == "SpinButton" && c.label == "turn °" && !c.value.starts_with("turn")
        });
        s.type_into_focused("45");
        // Read until the map shows the field out of its text edit again.
        s.find("the turn field showing 45°", |c| {
            c.role == "SpinButton" && c.label == "turn °" && c.value.starts_with("turn 45")
        });
        // The render thread is asked for the view with the map turned.
        s.wait_log("a request with the map turned 45°", 30, |l| {
            l.contains(" request ") && l.contains(" turn=45 ")
        });
    }
}

/// Every window of the View and Help menus opens with a pointer (the
/// menu, then its item: the window's title is on screen) and Escape closes
/// it again.
#[test]
fn the_view_and_help_menus_open_their_windows_with_a_pointer() {
    let items = [
        ("View", "Light & display…", "Light & display"),
        ("Help", "Shortcuts  (F1)", "Shortcuts"),
        ("Help", "About scatterlab", "About scatterlab"),
    ];
    for (w, h) in SIZES {
        let s = Session::start("menus", w, h);
        for (menu, item, title) in items {
            let m = s.find(&format!("the {menu} menu"), |c| {
                c.role == "Button" && c.label == menu
            });
            s.click(&m);
            let i = s.find(&format!("{item} in {menu}"), |c| {
                c.role == "Button" && c.label == item
            });
            s.click(&i);
            s.find(&format!("the {title} window's title"), |c| {
                c.role == "Window" && c.label == title
            });
            let wid = s.wid.clone();
            s.xdotool(&["windowfocus", "--sync", &wid]);
            s.xdotool(&["key", "Escape"]);
            s.gone(&format!("the {title} window, after Escape"), |c| {
                c.role == "Window" && c.label == title
            });
        }
    }
}
