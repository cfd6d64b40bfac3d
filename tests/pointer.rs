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
    /// The editor's files stay after it (a crash whose autosave the next
    /// editor recovers).
    keep: bool,
    /// Dropped after the editor (fields drop in order).
    _xvfb: Xvfb,
}

impl Drop for Session {
    fn drop(&mut self) {
        let _ = self.editor.kill();
        let _ = self.editor.wait();
        // The editor's files stay for a failure's message, not after.
        if !std::thread::panicking() && !self.keep {
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
    /// The editor on the procedural head with fresh state at `w`×`h` on
    /// a display of its own.
    fn start(name: &str, w: u32, h: u32) -> Self {
        Self::start_with(name, w, h, &["--procedural-head"])
    }

    /// The editor with `args` after `edit` (none: the head scan).
    fn start_with(name: &str, w: u32, h: u32, args: &[&str]) -> Self {
        Self::start_in(name, w, h, args, true)
    }

    /// The editor with `args`; `fresh`: with no state of an earlier
    /// editor of the same `name` (else its data and config stay, its frame
    /// log and widget map do not).
    fn start_in(name: &str, w: u32, h: u32, args: &[&str], fresh: bool) -> Self {
        let dir = std::env::temp_dir().join(format!(
            "scatterlab-pointer-{name}-{w}x{h}-{}",
            std::process::id()
        ));
        if fresh {
            let _ = std::fs::remove_dir_all(&dir);
        }
        for f in ["frames.log", "widgets.tsv"] {
            let _ = std::fs::remove_file(dir.join(f));
        }
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
            .arg("edit")
            .args(args)
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
            keep: false,
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
            shot,
            shown.join("\n")
        );
    }

    /// The one control `pick` chooses inside the window titled `title`
    /// (its title bar's rectangle down to the window's last control).
    fn find_in(&self, title: &str, what: &str, pick: impl Fn(&Widget) -> bool) -> Widget {
        let window = self.find(&format!("the {title} window"), |c| {
            c.role == "Window" && c.label == title
        });
        let [x0, y0, x1, y1] = window.rect;
        self.find(&format!("{what} in {title}"), |c| {
            let (x, y) = c.centre();
            pick(c) && (x0 as i32..=x1 as i32).contains(&x) && (y0 as i32..=y1 as i32).contains(&y)
        })
    }

    /// Opens `item` of the menu labelled `menu` with two clicks.
    fn menu_item(&self, menu: &str, item: &str) {
        let m = self.find(&format!("the {menu} menu"), |c| {
            c.role == "Button" && c.label == menu
        });
        self.click(&m);
        let i = self.find(&format!("{item} in {menu}"), |c| {
            c.role == "Button" && c.label == item
        });
        self.click(&i);
    }

    /// Escape, with X's keyboard focus on the window first.
    fn escape(&self) {
        let wid = self.wid.clone();
        self.xdotool(&["windowfocus", "--sync", &wid]);
        self.xdotool(&["key", "Escape"]);
    }

    /// The drag value `pick` chooses in `title` clicked, `text` typed
    /// into it and Enter; the field (found again where it was: its value
    /// changes while it is a text edit) as it shows the value afterwards.
    fn type_into_field(
        &self,
        title: &str,
        what: &str,
        pick: impl Fn(&Widget) -> bool,
        text: &str,
    ) -> Widget {
        let field = self.find_in(title, what, pick);
        let here = |c: &Widget| {
            c.role == field.role
                && (c.rect[0] - field.rect[0]).abs() < 3.0
                && (c.rect[1] - field.rect[1]).abs() < 3.0
        };
        self.click(&field);
        // Typed only once the field is a text edit (keys in the frame of
        // the click are lost).
        self.find_in(title, &format!("{what} as a text edit"), |c| {
            here(c) && c.value != field.value
        });
        self.type_into_focused(text);
        self.find_in(title, &format!("{what} showing {text}"), |c| {
            here(c) && c.value.contains(text) && c.value != text
        })
    }

    /// The number of requests sent to the render thread so far.
    fn requests(&self) -> usize {
        std::fs::read_to_string(self.dir.join("frames.log"))
            .unwrap_or_default()
            .lines()
            .filter(|l| l.contains(" request "))
            .count()
    }

    /// Waits for a request to the render thread past the first `n`.
    fn wait_request_after(&self, what: &str, n: usize) {
        let t0 = Instant::now();
        while self.requests() <= n {
            assert!(
                t0.elapsed() < Duration::from_secs(60),
                "at {}×{}: {what} sent the render thread no request",
                self.size.0,
                self.size.1
            );
            std::thread::sleep(Duration::from_millis(100));
        }
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
            self.size.0, self.size.1, shot
        );
    }

    /// A picture of the screen for a failure's message: where it is, or
    /// why there is none.
    fn screenshot(&self, what: &str) -> String {
        let name: String = what
            .chars()
            .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
            .collect();
        let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!(
            "pointer-{}x{}-{name}.png",
            self.size.0, self.size.1
        ));
        let took = Command::new("import")
            .args(["-window", "root", out.to_str().unwrap()])
            .env("DISPLAY", &self.display)
            .status()
            .is_ok_and(|s| s.success());
        if took && out.is_file() {
            out.display().to_string()
        } else {
            "none (ImageMagick's import is missing: apt-get install imagemagick)".into()
        }
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

/// One editor at a time: five editors drawing on lavapipe at once on two
/// cores made frames so slow that egui took a click's press and release
/// for a long press (over its 0.8 s) now and then, and the click was lost.
/// A test holds this for its whole run.
static ONE_AT_A_TIME: std::sync::Mutex<()> = std::sync::Mutex::new(());

fn one_at_a_time() -> std::sync::MutexGuard<'static, ()> {
    ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner())
}

/// The display transform, chosen with a pointer: the light settings
/// opened, the display combo box opened, AgX clicked; the render thread is
/// then asked for frames with AgX.
#[test]
fn the_display_transform_is_chosen_with_a_pointer() {
    let _one = one_at_a_time();
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
/// is asked for a new frame. In the same window, the focal length typed,
/// the three-point rig clicked, the fill's intensity typed and the rim's
/// colour picker opened (issue 52).
#[test]
fn the_hdr_maps_turn_is_typed_into_with_a_pointer_and_keys() {
    let _one = one_at_a_time();
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
        // Issue 52: the camera's focal length, typed in the same window.
        let lens = |c: &Widget| c.role == "SpinButton" && c.value.starts_with("focal length ");
        let field = s.find("the focal length field", lens);
        s.click(&field);
        // As a text edit it shows the number alone: 44.8 (mm, the default).
        s.find("the focal length field as a text edit", |c| {
            c.role == "SpinButton" && c.value.trim() == "44.8"
        });
        s.type_into_focused("85");
        s.find("the focal length field showing 85 mm", |c| {
            c.role == "SpinButton" && c.value == "focal length 85.0 mm"
        });
        // Issue 52: the key + fill + rim rig, one click, then the fill's
        // intensity typed and the rim's colour picker opened.
        let rig = s.find("the three-point rig", |c| {
            c.role == "Button" && c.label == "three-point"
        });
        s.click(&rig);
        s.find("the toolbar naming the three-point rig", |c| {
            c.role == "Button" && c.label == "Light: three-point"
        });
        let fill = |c: &Widget| c.role == "SpinButton" && c.label == "fill";
        let shown = s.type_into_field("Light & display", "the fill light's intensity", fill, "2");
        assert!(shown.value.starts_with("fill 2.0"), "{}", shown.value);
        s.wait_log("a request with the fill at 2", 30, |l| {
            l.contains(" request ") && l.contains(" fill=2 ")
        });
        let well = s.find("the rim light's colour", |c| {
            c.role == "ColorWell" && c.label == "rim light colour"
        });
        s.click(&well);
        s.find("the rim colour's picker (its blue field)", |c| {
            c.role == "SpinButton" && c.value.starts_with("B ")
        });
    }
}

/// Every window of the View and Help menus (issue 52's Histogram among
/// them) opens with a pointer (the menu, then its item: the window's title
/// is on screen) and Escape closes it again.
#[test]
fn the_view_and_help_menus_open_their_windows_with_a_pointer() {
    let _one = one_at_a_time();
    let items = [
        ("View", "Light & display…", "Light & display"),
        ("View", "Histogram…", "Histogram"),
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

/// The File menu's windows used with a pointer, each kind of control in
/// them: Save image at size (a preset button, the width typed into its
/// drag value, a supersampling radio button, the subsurface layer's
/// checkbox), Save turntable (a checkbox, the frame count typed) and
/// Browse presets (a folder typed into its text field and refused by name,
/// the folder dialog opened and cancelled, then a preset's button, which
/// opens it: the window's title names it).
#[test]
fn the_file_menus_windows_are_used_with_a_pointer() {
    let _one = one_at_a_time();
    for (w, h) in SIZES {
        let s = Session::start("file", w, h);
        let still = "Save image at size";
        s.menu_item("File", "Save image at size…");
        let preset = s.find_in(still, "the 3840×2160 button", |c| {
            c.role == "Button" && c.label == "3840×2160"
        });
        s.click(&preset);
        s.find_in(still, "the width at 3840", |c| {
            c.role == "SpinButton" && c.value == "3840 px"
        });
        let px = |c: &Widget| c.role == "SpinButton" && c.value.ends_with(" px");
        let width = s.find_in(still, "the width", |c| px(c) && c.value == "3840 px");
        let _ = width;
        s.type_into_field(
            still,
            "the width",
            |c| px(c) && !c.value.starts_with("2160"),
            "640",
        );
        // 3×: 2160 × 3 is within the 8192 rendered a side (4× is not,
        // and is disabled).
        let three = s.find_in(still, "the 3× radio button", |c| {
            c.role == "RadioButton" && c.label == "3×"
        });
        s.click(&three);
        s.find_in(still, "3× checked", |c| {
            c.role == "RadioButton" && c.label == "3×" && c.value == "checked"
        });
        s.find_in(still, "the size rendered at 640×2160, 3×", |c| {
            c.role == "Label" && c.value.starts_with("Renders 1920×6480 ")
        });
        // Issue 52: the subsurface layer as its own file.
        let layer = "Subsurface layer as its own file";
        let sss = s.find_in(still, "the subsurface layer's checkbox", |c| {
            c.role == "CheckBox" && c.label == layer && c.value == "unchecked"
        });
        s.click(&sss);
        s.find_in(still, "the subsurface layer's checkbox checked", |c| {
            c.role == "CheckBox" && c.label == layer && c.value == "checked"
        });
        s.escape();
        s.gone("Save image at size after Escape", |c| {
            c.role == "Window" && c.label == still
        });

        let tt = "Save turntable";
        s.menu_item("File", "Save turntable…");
        let pngs = s.find_in(tt, "the PNG-per-frame checkbox", |c| {
            c.role == "CheckBox" && c.label == "Also a PNG per frame"
        });
        assert_eq!(pngs.value, "checked", "a PNG per frame is on by default");
        s.click(&pngs);
        s.find_in(tt, "the PNG-per-frame checkbox unchecked", |c| {
            c.role == "CheckBox" && c.label == "Also a PNG per frame" && c.value == "unchecked"
        });
        s.type_into_field(
            tt,
            "the frame count",
            |c| c.role == "SpinButton" && c.value.ends_with(" frames"),
            "12",
        );
        s.escape();
        s.gone("Save turntable after Escape", |c| {
            c.role == "Window" && c.label == tt
        });

        let presets = "Presets";
        s.menu_item("File", "Browse presets…");
        let field = s.find_in(presets, "the folder field", |c| {
            c.role == "TextInput" && c.label == "Your folders:"
        });
        s.click(&field);
        s.type_into_focused("/no/such/folder");
        s.find_in(presets, "the typed folder refused by name", |c| {
            c.role == "Label" && c.value == "Not listed: /no/such/folder: not a folder"
        });
        // The grid settles once every thumbnail is in (an image button is
        // taller than the spinner it replaces, and the rows below it move):
        // a click before that once landed on the thumbnail under the name.
        let t0 = Instant::now();
        let rendering = |c: &Widget| {
            c.value.starts_with("rendering thumbnails")
                || c.label.starts_with("rendering thumbnails")
        };
        while s
            .widgets_since(SystemTime::UNIX_EPOCH, true)
            .is_none_or(|ws| ws.iter().any(rendering))
        {
            assert!(
                t0.elapsed() < Duration::from_secs(180),
                "at {w}×{h}: the thumbnails did not all come in within 180 s"
            );
            // A frame to write the map on.
            let wid = s.wid.clone();
            s.xdotool(&["mousemove", "--window", &wid, "1", "1"]);
            s.xdotool(&["mousemove", "--window", &wid, "2", "2"]);
            std::thread::sleep(Duration::from_millis(500));
        }
        // Issue 52: a folder chosen in a folder dialog, not typed (once
        // the thumbnails are in: the window widens as they come, and its
        // text above the button rewraps).
        let choose = s.find_in(presets, "the choose-folder button", |c| {
            c.role == "Button" && c.label == "+ choose folder…"
        });
        s.click(&choose);
        let dialog = "Add a folder of your presets (.ron)";
        // egui_file puts a folder glyph before the title.
        s.find("the folder dialog's title", |c| {
            c.role == "Window" && c.label.ends_with(dialog)
        });
        let cancel = s.find("the folder dialog's Cancel", |c| {
            c.role == "Button" && c.label == "Cancel"
        });
        s.click(&cancel);
        s.gone("the folder dialog after Cancel", |c| {
            c.role == "Window" && c.label.ends_with(dialog)
        });
        let jade = s.find_in(presets, "Jade's button", |c| {
            c.role == "Button" && c.label == "Jade"
        });
        s.click(&jade);
        s.gone("the preset browser after a preset was chosen", |c| {
            c.role == "Window" && c.label == presets
        });
        let t0 = Instant::now();
        loop {
            let wid = s.wid.clone();
            let title = s.xdotool(&["getwindowname", &wid]);
            if title.contains("Jade") {
                break;
            }
            assert!(
                t0.elapsed() < Duration::from_secs(15),
                "at {w}×{h}: the window's title is '{title}' after Jade was chosen"
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }
}

/// The Mesh menu's windows on the head scan: Mesh units (a unit's
/// selectable, the field showing it, OK) and Mesh maps (a flip-V
/// checkbox and a colour-space combo box); each change sends the render
/// thread a new request (the mesh reloads with it).
#[test]
fn the_mesh_menus_windows_are_used_with_a_pointer() {
    let _one = one_at_a_time();
    for (w, h) in SIZES {
        let s = Session::start_with("mesh", w, h, &[]);
        let units = "Mesh units";
        s.menu_item("Mesh", "Units…");
        let cm = s.find_in(units, "the cm choice", |c| c.label == "cm");
        let n = s.requests();
        s.click(&cm);
        s.find_in(units, "the units field at 0.01 m/unit", |c| {
            c.role == "SpinButton" && c.value.starts_with("0.01") && c.value.ends_with(" m/unit")
        });
        s.wait_request_after("centimetres", n);
        let ok = s.find_in(units, "OK", |c| c.role == "Button" && c.label == "OK");
        s.click(&ok);
        s.gone("Mesh units after OK", |c| {
            c.role == "Window" && c.label == units
        });

        let maps = "Mesh maps";
        s.menu_item("Mesh", "Maps…");
        let flip = s.find_in(maps, "the normal map's flip V", |c| {
            c.role == "CheckBox" && c.label == "Normal: flip V"
        });
        let n = s.requests();
        s.click(&flip);
        s.find_in(maps, "the normal map's flip V changed", |c| {
            c.role == "CheckBox" && c.label == "Normal: flip V" && c.value != flip.value
        });
        s.wait_request_after("the flip", n);
        // The second slot's colour space (the normal map's, linear).
        let combos =
            |c: &Widget| c.role == "ComboBox" && (c.value == "linear" || c.value == "sRGB");
        let combo = s.find_in(maps, "the normal map's colour space", |c| {
            combos(c) && c.value == "linear"
        });
        s.click(&combo);
        let srgb = s.find("sRGB in the colour-space list", |c| {
            c.label == "sRGB" && c.role != "ComboBox"
        });
        let n = s.requests();
        s.click(&srgb);
        s.wait_request_after("the colour space", n);
        s.escape();
        s.gone("Mesh maps after Escape", |c| {
            c.role == "Window" && c.label == maps
        });
    }
}

impl Session {
    /// The window's title, as X has it.
    fn title(&self) -> String {
        let wid = self.wid.clone();
        self.xdotool(&["getwindowname", &wid])
    }

    /// Waits for the window's title to satisfy `ok` (15 s).
    fn wait_title(&self, what: &str, ok: impl Fn(&str) -> bool) {
        let t0 = Instant::now();
        loop {
            let title = self.title();
            if ok(&title) {
                return;
            }
            assert!(
                t0.elapsed() < Duration::from_secs(15),
                "at {}×{}: the window's title is '{title}', not {what}",
                self.size.0,
                self.size.1
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }
}

/// The Edit menu and the unsaved-changes prompt with a pointer: the red
/// scattering distance typed into (the title says the look is changed),
/// Edit → Undo (the field shows its old value again), typed into again,
/// then File → New from preset → Jade, which asks first; "Discard
/// changes" opens Jade.
#[test]
fn the_edit_menu_and_the_unsaved_prompt_are_used_with_a_pointer() {
    let _one = one_at_a_time();
    for (w, h) in SIZES {
        let s = Session::start("edit", w, h);
        let red = |c: &Widget| c.role == "SpinButton" && c.label == "R: mm";
        let field = s.find("the red scattering distance", red);
        let was = field.value.clone();
        let type_distance = |mm: &str| {
            let f = s.find("the red scattering distance", red);
            s.click(&f);
            s.find("the red scattering distance as a text edit", |c| {
                red(c) && !c.value.starts_with("R:")
            });
            s.type_into_focused(mm);
            s.find(&format!("the red scattering distance at {mm} mm"), |c| {
                red(c) && c.value.starts_with(&format!("R: {mm}"))
            });
        };
        type_distance("2.5");
        s.wait_title("changed ('* ')", |t| t.starts_with("* "));
        s.menu_item("Edit", "Undo  (Ctrl+Z)");
        s.find("the red scattering distance back as it was", |c| {
            red(c) && c.value == was
        });
        s.wait_title("unchanged", |t| !t.starts_with("* "));
        type_distance("3");
        let file = s.find("the File menu", |c| c.role == "Button" && c.label == "File");
        s.click(&file);
        let new = s.find("New from preset in File", |c| {
            c.role == "Button" && c.label == "New from preset"
        });
        s.click(&new);
        let jade = s.find("Jade in New from preset", |c| {
            c.role == "Button" && c.label == "Jade"
        });
        s.click(&jade);
        let discard = s.find("the unsaved-changes prompt's Discard changes", |c| {
            c.role == "Button" && c.label == "Discard changes"
        });
        s.click(&discard);
        s.wait_title("Jade's", |t| t.contains("Jade"));
    }
}

/// The Export menu: a format's item opens the file dialog, whose file
/// field takes the path typed (all of it: egui_file joins the folder and
/// the name, and an absolute name replaces the folder) and Enter; the look
/// is written there and the status line says so. The same again asks
/// before replacing the file (the overwrite prompt, answered by a click).
#[test]
fn an_export_goes_through_the_file_dialog_with_a_pointer() {
    let _one = one_at_a_time();
    for (w, h) in SIZES {
        let s = Session::start("export", w, h);
        let m = s.find("the Export menu", |c| {
            c.role == "Button" && c.label == "Export"
        });
        s.click(&m);
        let gltf = s.find("glTF 2.0 in Export", |c| {
            c.role == "Button" && c.label.starts_with("glTF 2.0 (volume extensions)")
        });
        s.click(&gltf);
        let title = "💾  Export: glTF 2.0 (volume extensions) (.gltf)";
        let field = s.find_in(title, "the file name field", |c| {
            c.role == "TextInput" && c.value.ends_with(".gltf")
        });
        s.click(&field);
        let out = s.dir.join("look.gltf");
        s.type_into_focused(out.to_str().unwrap());
        s.wait_log("the export's status line", 60, |l| {
            l.contains(" status Exported ") && l.contains("look.gltf")
        });
        let text = std::fs::read_to_string(&out).unwrap();
        assert!(
            text.contains("KHR_materials_volume"),
            "at {w}×{h}: {} is not the look's glTF",
            out.display()
        );
        s.gone("the file dialog after its Enter", |c| {
            c.role == "Window" && c.label == title
        });
        // Again to the same file: the overwrite prompt, answered Replace
        // with a click, and a second export.
        s.click(&s.find("the Export menu", |c| {
            c.role == "Button" && c.label == "Export"
        }));
        s.click(&s.find("glTF 2.0 in Export", |c| {
            c.role == "Button" && c.label.starts_with("glTF 2.0 (volume extensions)")
        }));
        let field = s.find_in(title, "the file name field", |c| {
            c.role == "TextInput" && c.value.ends_with(".gltf")
        });
        s.click(&field);
        let first = std::fs::metadata(&out).unwrap().modified().unwrap();
        s.type_into_focused(out.to_str().unwrap());
        // A modal (egui's Modal: no title bar), asking by the file's name.
        s.find("the prompt naming the file", |c| {
            c.role == "Label" && c.value.ends_with("look.gltf exists.")
        });
        let replace = s.find("the prompt's Replace button", |c| {
            c.role == "Button" && c.label == "Replace"
        });
        s.click(&replace);
        // The file written again (the status line reads the same after
        // both exports, and the frame log writes a line only when it
        // changes: "Exporting" may come and go between two frames).
        let t0 = Instant::now();
        while std::fs::metadata(&out).unwrap().modified().unwrap() == first {
            assert!(
                t0.elapsed() < Duration::from_secs(60),
                "at {w}×{h}: no second export after Replace"
            );
            std::thread::sleep(Duration::from_millis(200));
        }
    }
}

/// File → Reference image…: a photo chosen in the file dialog (its path
/// typed into the file field, Enter) opens the Reference window; there the
/// "over the render" checkbox is ticked, the eyedropper's combo box set to
/// the transmission tint, and a click on the photo picks its colour into
/// the look: the status line gives the linear value, which is the photo's
/// sRGB (200, 100, 50) through IEC 61966-2-1's decoding, and the look is
/// unsaved.
#[test]
fn a_reference_photo_is_opened_and_picked_from_with_a_pointer() {
    let _one = one_at_a_time();
    let linear = |c: f64| {
        let c = c / 255.0;
        if c <= 0.04045 {
            c / 12.92
        } else {
            ((c + 0.055) / 1.055).powf(2.4)
        }
    };
    let said = format!(
        "Transmission tint picked: {:.4} / {:.4} / {:.4}",
        linear(200.0),
        linear(100.0),
        linear(50.0)
    );
    for (w, h) in SIZES {
        let s = Session::start("reference", w, h);
        let photo = s.dir.join("photo.png");
        image::RgbImage::from_pixel(64, 48, image::Rgb([200, 100, 50]))
            .save(&photo)
            .unwrap();
        s.menu_item("File", "Reference image…");
        let dialog = "📂  Reference image (.png, .jpg)";
        let field = s.find_in(dialog, "the file name field", |c| c.role == "TextInput");
        s.click(&field);
        s.type_into_focused(photo.to_str().unwrap());
        let reference = "Reference";
        let over = s.find_in(reference, "the over-the-render checkbox", |c| {
            c.role == "CheckBox" && c.label == "over the render"
        });
        let was = over.value.clone();
        s.click(&over);
        s.find_in(reference, "the over-the-render checkbox toggled", |c| {
            c.role == "CheckBox" && c.label == "over the render" && c.value != was
        });
        let combo = s.find_in(reference, "the pick-into combo box", |c| {
            c.role == "ComboBox" && c.value == "Albedo"
        });
        s.click(&combo);
        let tint = s.find("Transmission tint in the list", |c| {
            c.label == "Transmission tint" && c.role != "ComboBox"
        });
        s.click(&tint);
        s.find_in(reference, "the combo box showing the tint", |c| {
            c.role == "ComboBox" && c.value == "Transmission tint"
        });
        let picture = s.find_in(reference, "the photo", |c| c.role == "Image");
        s.click(&picture);
        s.wait_log("the picked colour's status line", 30, |l| {
            l.contains(" status ") && l.contains(&said)
        });
        s.wait_title("unsaved (\"* \")", |t| t.starts_with("* "));
    }
}

/// File → Import engine file…: an HDRP diffusion profile (its engine
/// keeps the albedo in the material, and the file has none) typed into
/// the file dialog opens the material-albedo prompt; its "this colour"
/// radio button clicked and OK, the look is drawn with the colour shown
/// beside it, as the status line says: the look open before's albedo,
/// Unreal's default SurfaceAlbedo.
#[test]
fn the_material_albedo_prompt_is_answered_with_a_pointer() {
    let _one = one_at_a_time();
    let asset = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/hdrp/Skin Diffusion Profile.asset");
    for (w, h) in SIZES {
        let s = Session::start("albedo", w, h);
        s.menu_item("File", "Import engine file…");
        let dialog = "📂  Import an engine's file";
        let field = s.find_in(dialog, "the file name field", |c| c.role == "TextInput");
        s.click(&field);
        s.type_into_focused(asset.to_str().unwrap());
        let typed = s.find("the prompt's 'this colour' radio button", |c| {
            c.role == "RadioButton" && c.label == "this colour"
        });
        assert_eq!(
            typed.value, "unchecked",
            "the map or the default skin is the default"
        );
        s.click(&typed);
        s.find("'this colour' checked", |c| {
            c.role == "RadioButton" && c.label == "this colour" && c.value == "checked"
        });
        // The colour beside the radio button, as the prompt shows it.
        let shown = s.find("the typed colour's numbers", |c| {
            c.role == "Label" && c.value.matches(" / ").count() == 2 && !c.value.contains('(')
        });
        let ok = s.find("the prompt's OK", |c| c.role == "Button" && c.label == "OK");
        s.click(&ok);
        let said = s.wait_log("the answer's status line", 30, |l| {
            l.contains(" status ") && l.contains("(typed at import)")
        });
        assert!(
            said.contains(&format!(
                "drawn with albedo {}",
                shown.value.replace(" / ", "/")
            )),
            "at {w}×{h}: the prompt showed {} and the editor said: {said}",
            shown.value
        );
        // The colour offered is the look open before: the default skin's
        // albedo, Unreal Engine's default SurfaceAlbedo (0.91058, 0.338275,
        // 0.2718; presets/skin_default.ron cites it), to three places.
        assert!(
            said.contains("drawn with albedo 0.911/0.338/0.272"),
            "at {w}×{h}: not Unreal's default SurfaceAlbedo: {said}"
        );
        s.gone("the prompt after OK", |c| {
            c.role == "RadioButton" && c.label == "this colour"
        });
    }
}

/// `edit --budget DIR`: the Budget merges window, opened with the report
/// that `scatterlab budget` wrote for the test project; the first
/// profile's "A | B" clicked opens that profile as the look (the title
/// names it) to compare with its merge.
#[test]
fn the_budget_merges_window_is_used_with_a_pointer() {
    let _one = one_at_a_time();
    let report = std::env::temp_dir().join(format!(
        "scatterlab-pointer-budget-report-{}",
        std::process::id()
    ));
    let _ = std::fs::remove_dir_all(&report);
    let project = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/unity_budget/project");
    let made = Command::new(env!("CARGO_BIN_EXE_scatterlab"))
        .args(["budget", "--no-renders", "--slots", "4", "--out"])
        .arg(&report)
        .arg(&project)
        .output()
        .unwrap();
    assert!(
        made.status.success(),
        "{}",
        String::from_utf8_lossy(&made.stderr)
    );
    for (w, h) in SIZES {
        let s = Session::start_with(
            "budget",
            w,
            h,
            &["--procedural-head", "--budget", report.to_str().unwrap()],
        );
        let window = "Budget merges";
        let ab = |c: &Widget| c.role == "Button" && c.label == "A | B";
        // The topmost "A | B" and the profile named on its row.
        let first = s.find_in(window, "the first A | B", |c| {
            ab(c) && c.rect[1] <= 1.0 + s.lowest_y(ab)
        });
        let row = (first.rect[1] + first.rect[3]) / 2.0;
        let name = s
            .find_in(window, "the first row's profile", |c| {
                // The row's one word that is not a figure or "—".
                c.role == "Label"
                    && ((c.rect[1] + c.rect[3]) / 2.0 - row).abs() < 4.0
                    && c.value.starts_with(|ch: char| ch.is_alphabetic())
            })
            .value;
        s.click(&first);
        s.wait_title(&format!("{name}'s"), |t| {
            t.contains(&format!(" — {name} — "))
        });
    }
    let _ = std::fs::remove_dir_all(&report);
}

impl Session {
    /// The top edge of the highest control `pick` chooses in the map now.
    fn lowest_y(&self, pick: impl Fn(&Widget) -> bool) -> f32 {
        self.widgets_since(SystemTime::UNIX_EPOCH, true)
            .unwrap_or_default()
            .iter()
            .filter(|c| pick(c))
            .map(|c| c.rect[1])
            .fold(f32::INFINITY, f32::min)
    }
}

/// An editor killed (SIGKILL) with unsaved work: the next editor's
/// recovery prompt offers it, and its Restore, clicked, brings back the
/// red scattering distance typed before the kill, unsaved ("* ").
#[test]
fn unsaved_work_is_recovered_after_a_kill_with_a_pointer() {
    let _one = one_at_a_time();
    let red = |c: &Widget| c.role == "SpinButton" && c.label == "R: mm";
    for (w, h) in SIZES {
        let mut s = Session::start("recovery", w, h);
        let field = s.find("the red scattering distance", red);
        s.click(&field);
        s.find("the red scattering distance as a text edit", |c| {
            red(c) && !c.value.starts_with("R:")
        });
        s.type_into_focused("2.5");
        s.find("the red scattering distance at 2.5 mm", |c| {
            red(c) && c.value.starts_with("R: 2.5")
        });
        s.wait_title("changed ('* ')", |t| t.starts_with("* "));
        // The autosave (within 5 s of a change) holds the edit: its
        // `<pid>.ron`, not the temporary file written before the rename
        // (`fsutil::write_atomic`'s `.<name>.<pid>.tmp`; a kill between
        // the two, on a busy machine, left no autosave to recover).
        let autosave = s.dir.join("data/scatterlab/autosave");
        let t0 = Instant::now();
        while !std::fs::read_dir(&autosave).is_ok_and(|d| {
            d.flatten().any(|f| {
                f.path().extension().is_some_and(|e| e == "ron")
                    && std::fs::read_to_string(f.path()).is_ok_and(|t| t.contains("2.5"))
            })
        }) {
            assert!(
                t0.elapsed() < Duration::from_secs(20),
                "at {w}×{h}: no autosave with the edit in {}",
                autosave.display()
            );
            std::thread::sleep(Duration::from_millis(200));
        }
        s.keep = true;
        drop(s);
        let s = Session::start_in("recovery", w, h, &["--procedural-head"], false);
        let restore = s.find("the recovery prompt's Restore", |c| {
            c.role == "Button" && c.label == "Restore"
        });
        s.click(&restore);
        s.find("the red scattering distance restored at 2.5 mm", |c| {
            red(c) && c.value.starts_with("R: 2.5")
        });
        s.wait_title("unsaved ('* ')", |t| t.starts_with("* "));
    }
}

/// Issue 52 item 5: the View menu's interface scale, dragged to 130 % with
/// a pointer. It rescaled under the pointer on the way (the menu grows with
/// the interface), so aiming at 130 % gave 95 %; it now applies when the
/// button is let go. Pressed where 130 % is on the rail (egui's slider maps
/// its range linearly between the handle's radius from each end), moved a
/// few pixels and back, released: the slider reads 1.3.
#[test]
fn the_interface_scale_is_dragged_to_where_the_pointer_lets_go() {
    let _one = one_at_a_time();
    for (w, h) in SIZES {
        let s = Session::start("scale", w, h);
        let view = s.find("the View menu", |c| c.role == "Button" && c.label == "View");
        s.click(&view);
        let slider = s.find("the interface scale slider", |c| {
            c.role == "Slider" && c.value == "1"
        });
        let [x0, y0, x1, y1] = slider.rect;
        let radius = (y1 - y0) / 2.5;
        let f = (1.3 - 0.75) / (2.0 - 0.75);
        let x = (x0 + radius + f * (x1 - x0 - 2.0 * radius)).round() as i32;
        let y = ((y0 + y1) / 2.0).round() as i32;
        let wid = s.wid.clone();
        let at = |dx: i32| {
            s.xdotool(&[
                "mousemove",
                "--window",
                &wid,
                &(x + dx).to_string(),
                &y.to_string(),
            ]);
            std::thread::sleep(Duration::from_millis(120));
        };
        at(0);
        s.xdotool(&["mousedown", "1"]);
        std::thread::sleep(Duration::from_millis(200));
        for dx in [3, 6, 3, 0] {
            at(dx);
        }
        s.xdotool(&["mouseup", "1"]);
        std::thread::sleep(Duration::from_millis(500));
        // The menu closes as the interface rescales: open it again.
        if !s
            .widgets_since(SystemTime::UNIX_EPOCH, true)
            .unwrap_or_default()
            .iter()
            .any(|c| c.role == "Slider" && c.label == slider.label)
        {
            let view = s.find("the View menu, rescaled", |c| {
                c.role == "Button" && c.label == "View"
            });
            s.click(&view);
        }
        let after = s.find("the slider after the drag", |c| {
            c.role == "Slider" && c.label == slider.label && c.value != "1"
        });
        let v: f32 = after.value.parse().unwrap_or(f32::NAN);
        assert!(
            (v - 1.3).abs() < 0.026,
            "at {w}×{h}: let go at 130 %, the scale is {} ({after:?}; screenshot {})",
            after.value,
            s.screenshot("scale")
        );
    }
}
