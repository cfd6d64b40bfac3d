//! Autosave and recovery. While the look has unsaved changes, it is
//! written with its view and compare state to the editor's data folder
//! (`<data>/autosave/<process id>.ron`, a temporary file renamed over the
//! last) at most [`AUTOSAVE_SECONDS`] after an edit, and only when something
//! changed. Saving, reverting to the file or a clean quit removes it, so
//! only a crash or a kill leaves one behind; the next start finds it and
//! offers it back (Restore / Discard / Show file).

use super::state::{
    CompareB, CompareMode, Document, History, MeshSettings, UiState, ViewState, HISTORY_BYTES,
};
use crate::settings::Preset;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The longest an edit waits to be written (the limit is 30 s).
pub const AUTOSAVE_SECONDS: u64 = 5;

/// What a crash would lose: the look, the file it came from, its undo
/// history, the mesh it was on, and how it was being looked at.
/// The look is read strictly (a preset's own rules); how it was viewed
/// falls back to defaults, so a file another version wrote still gives
/// the work back.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Recovery {
    pub preset: Preset,
    /// The preset file the look was opened from or last saved to.
    #[serde(default)]
    pub path: Option<PathBuf>,
    /// Undo and redo, at most [`HISTORY_BYTES`] of them, and the state
    /// last saved (files before issue 36 have none: one undo step back to
    /// the file, as they restored then).
    #[serde(default)]
    pub history: History,
    /// The mesh the look was on, with its units and maps (`None`: the
    /// default head).
    #[serde(default)]
    pub mesh: Option<RecoveredMesh>,
    #[serde(default)]
    pub view: ViewState,
    #[serde(default)]
    pub compare: CompareMode,
    #[serde(default)]
    pub compare_b: CompareB,
    #[serde(default = "half")]
    pub split: f32,
    /// When it was written (seconds since 1970).
    pub written_unix_s: u64,
}

/// A loaded mesh: its file and what the artist set for it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RecoveredMesh {
    pub path: PathBuf,
    #[serde(default)]
    pub settings: MeshSettings,
}

/// Everything of the editor an autosave holds, as [`Autosave::tick`]
/// reads it.
pub struct Snapshot<'a> {
    pub doc: &'a Document,
    pub ui: &'a UiState,
    pub mesh: Option<&'a Path>,
}

impl Snapshot<'_> {
    fn recovery(&self, history: History) -> Recovery {
        Recovery {
            preset: self.doc.preset.clone(),
            path: self.doc.path.clone(),
            history,
            mesh: self.mesh.map(|p| RecoveredMesh {
                path: p.to_owned(),
                settings: self.ui.meshes.get(p).cloned().unwrap_or_default(),
            }),
            view: self.ui.view,
            compare: self.ui.compare,
            compare_b: self.ui.compare_b.clone(),
            split: self.ui.split,
            written_unix_s: 0,
        }
    }
}

/// What a tick did, and when the editor must look again even if no input
/// comes (egui draws a frame only on input or a repaint request).
pub struct Ticked {
    /// An error to show, once.
    pub message: Option<String>,
    /// Ask for a frame after this long: something may be left to write
    /// (or a file to remove) at the next check.
    pub wake_in: Option<Duration>,
}

fn half() -> f32 {
    0.5
}

/// A recovery file another editor left behind.
#[derive(Debug, Clone)]
pub struct Found {
    pub file: PathBuf,
    pub recovery: Recovery,
}

/// This editor's autosave: where it writes, what it wrote last, and what
/// an earlier run left to recover.
pub struct Autosave {
    dir: PathBuf,
    file: PathBuf,
    /// The last content written (without its time and history) and the
    /// document's history revision then, to write only changes.
    last: Option<(String, u64)>,
    /// When the content was last checked or written.
    checked: Option<Instant>,
    /// An earlier run's recovery, offered until answered.
    pub found: Option<Found>,
    /// The last autosave error, said once.
    failed: Option<String>,
    /// Recovery files that could not be read, said at start (they stay
    /// where they are, for the artist to open by hand).
    pub unreadable: Vec<String>,
}

impl Autosave {
    /// Autosave under `data_dir` (the editor's data folder), and the
    /// newest recovery file an editor that is no longer running left there.
    pub fn new(data_dir: &Path) -> Self {
        let dir = data_dir.join("autosave");
        let file = dir.join(format!(
            "{}.{}",
            std::process::id(),
            crate::settings::PRESET_EXTENSION
        ));
        let (found, unreadable) = Self::find_left(&dir, &file);
        Self {
            dir,
            file,
            last: None,
            checked: None,
            found,
            failed: None,
            unreadable,
        }
    }

    /// The file this editor autosaves to.
    pub fn file(&self) -> &Path {
        &self.file
    }

    /// The newest readable recovery file in `dir` that is not `own` and
    /// whose editor is not running, and what could not be read there.
    fn find_left(dir: &Path, own: &Path) -> (Option<Found>, Vec<String>) {
        let Ok(entries) = std::fs::read_dir(dir) else {
            return (None, Vec::new());
        };
        let mut unreadable = Vec::new();
        let found = entries
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| p != own && crate::settings::is_preset_file(p))
            .filter(|p| !editor_running(p))
            .filter_map(|file| {
                let read = std::fs::read_to_string(&file)
                    .map_err(|e| e.to_string())
                    .and_then(|t| ron::from_str::<Recovery>(&t).map_err(|e| e.to_string()));
                match read {
                    Ok(recovery) => Some(Found { file, recovery }),
                    Err(e) => {
                        unreadable.push(format!("{}: {e}", file.display()));
                        None
                    }
                }
            })
            .max_by_key(|f| f.recovery.written_unix_s);
        (found, unreadable)
    }

    /// Writes the look if it has unsaved changes that were not written yet
    /// (checked once every [`AUTOSAVE_SECONDS`], or now with `force`);
    /// removes the file once nothing is unsaved. Between checks it says
    /// when to look again, so an edit with no input after it is still
    /// written (issue 36).
    pub fn tick(&mut self, now: Snapshot<'_>, force: bool) -> Ticked {
        let period = Duration::from_secs(AUTOSAVE_SECONDS);
        let since = self.checked.map(|t| t.elapsed());
        if !force && since.is_some_and(|s| s < period) {
            // Something changed this frame, or may have: look again at
            // the deadline while there is anything to write or remove.
            let pending = now.doc.is_dirty() || self.last.is_some();
            return Ticked {
                message: None,
                wake_in: pending.then(|| period - since.unwrap_or_default()),
            };
        }
        self.checked = Some(Instant::now());
        let message = self.write(&now);
        Ticked {
            message,
            wake_in: None,
        }
    }

    /// The check itself: writes what changed, removes the file once
    /// nothing is unsaved. An error to show, once.
    fn write(&mut self, now: &Snapshot<'_>) -> Option<String> {
        if !now.doc.is_dirty() {
            self.clear();
            return None;
        }
        // The history is compared by its revision, not by its text (up to
        // a megabyte of RON, serialised only when it changed).
        let content = ron::to_string(&now.recovery(History::default())).ok()?;
        let key = (content, now.doc.revision());
        if self.last.as_ref() == Some(&key) {
            return None;
        }
        let recovery = Recovery {
            written_unix_s: unix_seconds(),
            ..now.recovery(now.doc.history(HISTORY_BYTES))
        };
        // The look and its view one field a line (an artist may open the
        // file); the history's presets one a line, compact, so the file
        // holds about what `HISTORY_BYTES` counted (written pretty, 200
        // steps of the default skin were 1.8× their compact size).
        let layout = ron::ser::PrettyConfig::default().depth_limit(3);
        let text = ron::ser::to_string_pretty(&recovery, layout).ok()?;
        let written = std::fs::create_dir_all(&self.dir)
            .and_then(|()| crate::fsutil::write_atomic(&self.file, text.as_bytes()));
        match written {
            Ok(()) => {
                self.last = Some(key);
                self.failed = None;
                None
            }
            Err(e) => {
                let message = format!(
                    "Warning: autosave to {} failed ({e}): unsaved changes are not protected against a crash; save the look (Ctrl+S)",
                    self.file.display()
                );
                let new = self.failed.as_ref() != Some(&message);
                self.failed = Some(message.clone());
                new.then_some(message)
            }
        }
    }

    /// Removes this editor's autosave (saved, reverted or quit cleanly).
    pub fn clear(&mut self) {
        if self.last.take().is_some() || self.file.exists() {
            let _ = std::fs::remove_file(&self.file);
        }
    }
}

/// Whether the editor that wrote `file` (named by its process id) is still
/// running: where /proc exists, its entry; elsewhere, assumed not.
fn editor_running(file: &Path) -> bool {
    let Some(pid) = file
        .file_stem()
        .and_then(|s| s.to_str())
        .and_then(|s| s.parse::<u32>().ok())
    else {
        return false;
    };
    process_alive_and_ours(pid)
}

/// Whether process `pid` is running this program: it exists, is not a
/// zombie (killed but not yet reaped by its parent, state `Z` in
/// `/proc/<pid>/stat`, proc(5)) and has our command name (a recycled pid
/// belongs to some other program). Without `/proc` (not Linux) every
/// file counts as left behind.
fn process_alive_and_ours(pid: u32) -> bool {
    let dir = Path::new("/proc").join(pid.to_string());
    let Ok(stat) = std::fs::read_to_string(dir.join("stat")) else {
        return false;
    };
    // "pid (comm) state ...": the state follows the last ')'.
    let state = stat
        .rsplit_once(')')
        .and_then(|(_, rest)| rest.split_whitespace().next());
    if matches!(state, Some("Z" | "X" | "x")) {
        return false;
    }
    let comm = |d: &Path| std::fs::read_to_string(d.join("comm")).ok();
    comm(&dir) == comm(Path::new("/proc/self"))
}

pub(super) fn unix_seconds() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs())
}

/// Shows `dir` in the desktop's file manager; false if none could start.
pub fn show_in_file_manager(dir: &Path) -> bool {
    let opener = if cfg!(target_os = "macos") {
        "open"
    } else if cfg!(target_os = "windows") {
        "explorer"
    } else {
        "xdg-open"
    };
    std::process::Command::new(opener)
        .arg(dir)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .is_ok()
}

/// "42 s", "3 min", "2 h", "5 days".
pub(super) fn age_text(s: u64) -> String {
    match s {
        0..=89 => format!("{s} s"),
        90..=5399 => format!("{} min", (s + 30) / 60),
        5400..=172_799 => format!("{} h", (s + 1800) / 3600),
        _ => format!("{} days", (s + 43_200) / 86_400),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ages_read_naturally() {
        assert_eq!(age_text(42), "42 s");
        assert_eq!(age_text(180), "3 min");
        assert_eq!(age_text(7200), "2 h");
        assert_eq!(age_text(3 * 86_400), "3 days");
    }

    /// A file named by a running process (this one) is not offered; a
    /// dead one's is; unreadable files are skipped; the newest wins.
    #[test]
    fn finds_what_a_dead_editor_left() {
        let dir = std::env::temp_dir().join(format!("scatterlab-autosave-{}", std::process::id()));
        let auto = dir.join("autosave");
        std::fs::create_dir_all(&auto).unwrap();
        let recovery = |name: &str, t: u64| Recovery {
            preset: Preset {
                name: name.into(),
                ..Preset::default()
            },
            path: None,
            history: History::default(),
            mesh: None,
            view: ViewState::default(),
            compare: CompareMode::Off,
            compare_b: CompareB::default(),
            split: 0.5,
            written_unix_s: t,
        };
        let write = |file: &str, r: &Recovery| {
            std::fs::write(auto.join(file), ron::to_string(r).unwrap()).unwrap();
        };
        // Process ids above the kernel's pid_max (4194304) never run.
        write("999999901.ron", &recovery("older", 10));
        write("999999902.ron", &recovery("newer", 20));
        std::fs::write(auto.join("999999904.ron"), "not ron").unwrap();
        // This process is running: its file is its own autosave, never offered.
        write(
            &format!("{}.ron", std::process::id()),
            &recovery("mine", 40),
        );
        let a = Autosave::new(&dir);
        let found = a.found.as_ref().expect("a recovery");
        assert_eq!(found.recovery.preset.name, "newer");
        assert_eq!(a.unreadable.len(), 1, "{:?}", a.unreadable);
        assert!(a.unreadable[0].contains("999999904.ron"));
        // Written by another version with only the look and the time: how
        // it was viewed falls back to defaults, and the work comes back.
        let preset = ron::to_string(&Preset {
            name: "minimal".into(),
            ..Preset::default()
        })
        .unwrap();
        std::fs::write(
            auto.join("999999905.ron"),
            format!("(preset: {preset}, written_unix_s: 60)"),
        )
        .unwrap();
        let a = Autosave::new(&dir);
        assert_eq!(a.found.as_ref().unwrap().recovery.preset.name, "minimal");
        assert_eq!(a.found.as_ref().unwrap().recovery.split, 0.5);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// The file gives the history back as it was, and the history takes
    /// in it what its budget counted (compact RON, one preset a line), not
    /// the 1.8× of fully pretty RON.
    #[test]
    fn the_history_is_written_as_its_budget_counts_it() {
        let dir = std::env::temp_dir().join(format!("scatterlab-history-{}", std::process::id()));
        let mut doc = Document::new(Preset::default_skin(), None);
        for i in 0..40 {
            doc.preset.description = format!("step {i}");
            doc.commit();
        }
        let ui = UiState::default();
        let mut a = Autosave::new(&dir);
        let ticked = a.tick(
            Snapshot {
                doc: &doc,
                ui: &ui,
                mesh: None,
            },
            true,
        );
        assert!(ticked.message.is_none());
        let text = std::fs::read_to_string(a.file()).unwrap();
        let back: Recovery = ron::from_str(&text).unwrap();
        let history = doc.history(HISTORY_BYTES);
        assert_eq!(back.history, history);
        assert_eq!(back.preset, doc.preset);
        let counted: usize = history
            .undo
            .iter()
            .map(|p| ron::to_string(p).unwrap().len())
            .sum();
        let written = text.len() - ron::to_string(&back.preset).unwrap().len();
        eprintln!("history counted {counted} bytes; file without the look {written}");
        assert!(
            (written as f64) < 1.3 * counted as f64,
            "{written} bytes written for {counted} counted"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// A pid counts as a running editor only while its process lives and
    /// runs this program: not a zombie (killed, not yet reaped, which is
    /// how `kill -9` leaves a child until its parent waits) and not a
    /// recycled pid of another program (proc(5): /proc/<pid>/stat, comm).
    #[test]
    fn a_killed_or_foreign_process_is_not_a_running_editor() {
        assert!(process_alive_and_ours(std::process::id()));
        assert!(!process_alive_and_ours(999_999_901));
        if Path::new("/proc/1/comm").exists() {
            // Init runs, but it is not this program.
            assert!(!process_alive_and_ours(1));
            // A child that has exited and is not reaped yet: a zombie.
            let mut child = std::process::Command::new("true").spawn().unwrap();
            let pid = child.id();
            let stat = Path::new("/proc").join(pid.to_string()).join("stat");
            let t0 = Instant::now();
            while std::fs::read_to_string(&stat).is_ok_and(|s| !s.contains(") Z"))
                && t0.elapsed() < Duration::from_secs(10)
            {
                std::thread::sleep(Duration::from_millis(10));
            }
            assert!(std::fs::read_to_string(&stat).unwrap().contains(") Z"));
            assert!(!process_alive_and_ours(pid));
            child.wait().unwrap();
        }
    }
}
