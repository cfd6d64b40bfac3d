//! The recovery prompt: at start, a look an earlier editor left unsaved
//! (its autosave, `app/autosave.rs`) is offered back: Restore (Enter: it
//! opens as unsaved changes, with its view and compare), Discard (its file
//! goes) or Show file (its folder in the file manager; the prompt stays).
//! A modal; its answer is an [`Action::AnswerRecovery`].

use super::{Action, Window, WindowView};
use crate::app::autosave::{age_text, show_in_file_manager, unix_seconds, Found};

/// The recovery offered, until answered.
#[derive(Default)]
pub struct RecoveryWindow {
    pub found: Option<Found>,
}

/// Restore, Discard or Show file, if one was clicked.
fn buttons_ui(ui: &mut egui::Ui) -> Option<u8> {
    let mut answer = None;
    ui.horizontal(|ui| {
        if ui
            .button("Restore")
            .on_hover_text("Open the look as it was, with its view and compare, as unsaved changes (Enter)")
            .clicked()
        {
            answer = Some(0);
        }
        if ui
            .button("Discard")
            .on_hover_text("Delete the recovery file and keep the look opened now")
            .clicked()
        {
            answer = Some(1);
        }
        if ui
            .button("Show file")
            .on_hover_text("Open the folder that holds the recovery file (a RON file with the preset in it)")
            .clicked()
        {
            answer = Some(2);
        }
    });
    answer
}

impl Window for RecoveryWindow {
    fn title(&self) -> &'static str {
        "Recover unsaved work?"
    }
    /// Opened at start by an earlier editor's autosave.
    fn menu(&self) -> Option<super::Menu> {
        None
    }
    fn is_open(&self) -> bool {
        self.found.is_some()
    }
    fn set_open(&mut self, open: bool) {
        if !open {
            self.found = None;
        }
    }
    fn is_modal(&self) -> bool {
        true
    }

    fn show(&mut self, ctx: &egui::Context, _view: &WindowView) -> Vec<Action> {
        let Some(found) = &self.found else {
            return Vec::new();
        };
        let r = &found.recovery;
        let age_s = unix_seconds().saturating_sub(r.written_unix_s);
        let from = r
            .path
            .as_ref()
            .map_or("a look never saved".to_owned(), |p| p.display().to_string());
        let modal = egui::Modal::new(egui::Id::unique("scatterlab_recovery_prompt")).show(ctx, |ui| {
            ui.heading("Recover unsaved work?");
            ui.label(format!(
                "The editor stopped with unsaved changes to \"{}\" ({from}), autosaved {} ago.",
                r.preset.name,
                age_text(age_s)
            ));
            ui.label(format!("Recovery file: {}", found.file.display()));
            buttons_ui(ui)
        });
        // Enter restores (nothing is lost by it; Discard needs the mouse).
        let answer = modal
            .inner
            .or(ctx.input(|i| i.key_pressed(egui::Key::Enter)).then_some(0));
        match answer {
            Some(2) => {
                let dir = found.file.parent().unwrap_or(std::path::Path::new(".")).to_owned();
                if show_in_file_manager(&dir) {
                    Vec::new()
                } else {
                    vec![Action::Say(format!("Warning: no file manager to show {}", dir.display()))]
                }
            }
            restore => super::answered(&mut self.found, restore.map(|a| a == 0), |f, r| {
                Action::AnswerRecovery(Box::new(f), r)
            }),
        }
    }
}
