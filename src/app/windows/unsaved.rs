//! The unsaved-changes prompt: an open, a new look or quitting waits while
//! the look has changes that are not saved. Save (Save As first for a
//! look without a file), Discard changes or Cancel; Escape or a click
//! outside is Cancel, which loses nothing. A modal; its answer is an
//! [`Action::AnswerUnsaved`].

use super::{Action, Window, WindowView};
use crate::app::Pending;

/// The prompt's answers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Unsaved {
    Save,
    Discard,
    Cancel,
}

/// What waits for the answer, while the prompt is up.
#[derive(Default)]
pub struct UnsavedWindow {
    pub pending: Option<Pending>,
}

impl Window for UnsavedWindow {
    fn title(&self) -> &'static str {
        "Unsaved changes"
    }
    /// Opened by an open, a new look or quitting with changes.
    fn menu(&self) -> Option<super::Menu> {
        None
    }
    fn is_open(&self) -> bool {
        self.pending.is_some()
    }
    fn set_open(&mut self, open: bool) {
        if !open {
            self.pending = None;
        }
    }
    fn is_modal(&self) -> bool {
        true
    }

    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        if self.pending.is_none() {
            return Vec::new();
        }
        let modal = egui::Modal::new(egui::Id::unique("scatterlab_unsaved_prompt")).show(ctx, |ui| {
            ui.heading("Unsaved changes");
            ui.label(format!("\"{}\" has changes that are not saved.", view.look_name));
            let mut choice = None;
            ui.horizontal(|ui| {
                for (label, answer) in [
                    ("Save", Unsaved::Save),
                    ("Discard changes", Unsaved::Discard),
                    ("Cancel", Unsaved::Cancel),
                ] {
                    if ui.button(label).clicked() {
                        choice = Some(answer);
                    }
                }
            });
            choice
        });
        // Escape or a click outside is Cancel (nothing is lost by it).
        let choice = match modal.inner {
            None if modal.should_close() => Some(Unsaved::Cancel),
            c => c,
        };
        super::answered(&mut self.pending, choice, Action::AnswerUnsaved)
    }
}
