//! The document being edited: a preset, its file, what was last saved
//! there, and its undo history.

use super::*;

/// Undo steps kept.
pub const HISTORY_LIMIT: usize = 200;
/// The most of the undo history an autosave carries (its presets as RON,
/// newest first): about 1 MB, a few hundred steps of a typical look.
pub const HISTORY_BYTES: usize = 1 << 20;

/// A preset, where it lives, and what was last saved there.
#[derive(Debug, Clone)]
pub struct Document {
    pub preset: Preset,
    pub path: Option<PathBuf>,
    /// The preset as last loaded or saved (the unsaved-changes check).
    saved: Preset,
    /// The state the next undo step returns to (edits since are one step).
    committed: Preset,
    undo: Vec<Preset>,
    redo: Vec<Preset>,
    /// Counts the changes of the undo history and of `saved` (their only
    /// writers are this type's methods), so the autosave can tell that
    /// nothing in them changed without comparing them.
    revision: u64,
}

/// A document's undo history as the autosave carries it: what undo and
/// redo go back to (oldest first, as [`Document`] keeps them) and the
/// preset as last saved, which decides what counts as unsaved.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct History {
    pub undo: Vec<Preset>,
    pub redo: Vec<Preset>,
    /// `None`: as the preset file says (a recovery another version wrote).
    pub saved: Option<Preset>,
}

impl Document {
    pub fn new(preset: Preset, path: Option<PathBuf>) -> Self {
        Self {
            saved: preset.clone(),
            committed: preset.clone(),
            preset,
            path,
            undo: Vec::new(),
            redo: Vec::new(),
            revision: 0,
        }
    }

    /// The document as it was: `preset` (its edits since the last commit
    /// included), its file, and its history. Without a saved state in
    /// `history`, what is saved is the file at `path` (else the default
    /// preset), so the recovered look shows as unsaved.
    pub fn restored(preset: Preset, path: Option<PathBuf>, history: History) -> Self {
        let saved = history.saved.unwrap_or_else(|| {
            path.as_deref()
                .and_then(|p| Preset::load(p).ok())
                .unwrap_or_default()
        });
        Self {
            saved,
            committed: preset.clone(),
            preset,
            path,
            undo: history.undo,
            redo: history.redo,
            revision: 0,
        }
    }

    /// The undo history for an autosave, within `budget_bytes` of RON:
    /// the newest undo steps first (an edit not yet committed counts as
    /// one, as [`Document::commit`] would make it), then the newest redo
    /// steps; older steps that do not fit are left out.
    pub fn history(&self, budget_bytes: usize) -> History {
        let mut undo: Vec<&Preset> = self.undo.iter().collect();
        if self.preset != self.committed {
            undo.push(&self.committed);
        }
        let mut left = budget_bytes;
        let mut fits = |p: &Preset| {
            let n = ron::to_string(p).map_or(usize::MAX, |t| t.len());
            let ok = n <= left;
            if ok {
                left -= n;
            }
            ok
        };
        let keep_undo = undo.iter().rev().take_while(|p| fits(p)).count();
        let keep_redo = self.redo.iter().rev().take_while(|p| fits(p)).count();
        History {
            undo: undo[undo.len() - keep_undo..]
                .iter()
                .map(|p| (*p).clone())
                .collect(),
            redo: self.redo[self.redo.len() - keep_redo..].to_vec(),
            saved: Some(self.saved.clone()),
        }
    }

    /// Changes whenever the undo history or the saved state changes.
    pub fn revision(&self) -> u64 {
        self.revision
    }

    pub fn is_dirty(&self) -> bool {
        self.preset != self.saved
    }

    /// Ends an edit: if the preset changed since the last commit, the old
    /// state becomes an undo step. Called once per frame while no pointer
    /// button is held, so a slider drag is one step.
    pub fn commit(&mut self) {
        if self.preset != self.committed {
            let before = std::mem::replace(&mut self.committed, self.preset.clone());
            self.undo.push(before);
            if self.undo.len() > HISTORY_LIMIT {
                self.undo.remove(0);
            }
            self.redo.clear();
            self.revision += 1;
        }
    }

    pub fn can_undo(&self) -> bool {
        !self.undo.is_empty() || self.preset != self.committed
    }

    /// The look before the last edit (the one in progress, else the last
    /// undo step): what the viewport's "before" flicker shows.
    pub fn before_last_edit(&self) -> Option<&Preset> {
        if self.preset != self.committed {
            Some(&self.committed)
        } else {
            self.undo.last()
        }
    }

    pub fn can_redo(&self) -> bool {
        !self.redo.is_empty()
    }

    pub fn undo(&mut self) {
        self.commit();
        if let Some(prev) = self.undo.pop() {
            self.redo.push(std::mem::replace(&mut self.preset, prev));
            self.committed = self.preset.clone();
            self.revision += 1;
        }
    }

    pub fn redo(&mut self) {
        if let Some(next) = self.redo.pop() {
            self.undo.push(std::mem::replace(&mut self.preset, next));
            self.committed = self.preset.clone();
            self.revision += 1;
        }
    }

    /// Replaces the preset as one undoable edit (applying a fit, picking a
    /// material from a list).
    pub fn replace(&mut self, preset: Preset) {
        self.commit();
        self.preset = preset;
        self.commit();
    }

    /// Saves to `path` (atomically) and remembers it as the document's file.
    pub fn save_as(&mut self, path: &Path) -> Result<(), crate::settings::PresetError> {
        self.preset.save(path)?;
        self.path = Some(path.to_owned());
        self.saved = self.preset.clone();
        self.revision += 1;
        Ok(())
    }

    pub fn title(&self) -> String {
        let file = self
            .path
            .as_ref()
            .and_then(|p| p.file_name())
            .map(|f| f.to_string_lossy().into_owned())
            .unwrap_or_else(|| "untitled".into());
        format!(
            "{}{} — {} — scatterlab",
            if self.is_dirty() { "* " } else { "" },
            file,
            self.preset.name
        )
    }
}
