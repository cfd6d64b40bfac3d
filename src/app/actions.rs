//! `EditorApp::apply`: every [`Action`] a window, toolbar or menu returns
//! is performed here, in one place (issue 51), so that no window writes
//! the document or another window's state.

use super::windows::Action;
use super::*;

impl EditorApp {
    /// Performs `actions` in order.
    pub(super) fn apply(&mut self, actions: Vec<Action>) {
        for action in actions {
            match action {
                Action::SetView(v) => self.ui_state.view = v,
                Action::ApplyRig(rig) => {
                    if !rig.apply(&mut self.ui_state.view) {
                        // The HDR rig with no map loaded: ask for one; the
                        // map lights the head once it has loaded.
                        self.view.hdr_rig_pending = true;
                        self.open_dialog(DialogKind::Environment);
                    }
                }
                Action::ChooseEnvironmentFile => self.open_dialog(DialogKind::Environment),
                Action::LoadEnvironment(path) => self.load_environment(path),
                Action::OpenWindow(title) => {
                    self.windows.open(title);
                }
            }
        }
    }

    /// Draws the windows of [`windows::Windows`] and applies what they ask.
    pub(super) fn windows_ui(&mut self, ctx: &egui::Context) {
        let view = windows::WindowView {
            view: &self.ui_state.view,
            environment_file: self.ui_state.environment_file.as_deref(),
        };
        let actions = self.windows.show(ctx, &view);
        self.apply(actions);
    }
}
