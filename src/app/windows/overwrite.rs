//! The overwrite prompt: a Save As, an export, an image or a turntable
//! would replace files that exist. Replace, or Cancel back to the file
//! dialog (Escape or a click outside is Cancel). A modal; its answer is an
//! [`Action::AnswerOverwrite`].

use super::{Action, Window, WindowView};
use crate::app::Overwrite;

/// The write waiting for the answer, while the prompt is up.
#[derive(Default)]
pub struct OverwriteWindow {
    pub write: Option<Overwrite>,
}

impl Window for OverwriteWindow {
    fn title(&self) -> &'static str {
        "Replace existing files?"
    }
    /// Opened by a write that would replace files.
    fn menu(&self) -> Option<super::Menu> {
        None
    }
    fn is_open(&self) -> bool {
        self.write.is_some()
    }
    fn set_open(&mut self, open: bool) {
        if !open {
            self.write = None;
        }
    }
    fn is_modal(&self) -> bool {
        true
    }

    fn show(&mut self, ctx: &egui::Context, _view: &WindowView) -> Vec<Action> {
        let Some(o) = &self.write else {
            return Vec::new();
        };
        let modal = egui::Modal::new(egui::Id::unique("scatterlab_overwrite_prompt")).show(ctx, |ui| {
            ui.heading("Replace existing files?");
            for p in &o.existing {
                ui.label(format!("{} exists.", p.display()));
            }
            let mut choice = None;
            ui.horizontal(|ui| {
                if ui.button("Replace").clicked() {
                    choice = Some(true);
                }
                if ui.button("Cancel").clicked() {
                    choice = Some(false);
                }
            });
            choice
        });
        // Escape or a click outside is Cancel: back to the dialog.
        let choice = match modal.inner {
            None if modal.should_close() => Some(false),
            c => c,
        };
        super::answered(&mut self.write, choice, Action::AnswerOverwrite)
    }
}
