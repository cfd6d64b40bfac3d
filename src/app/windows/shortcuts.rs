//! Help → Shortcuts (F1): every key the editor takes, in a window that
//! stays until closed.

use super::{Action, Window, WindowView};

/// Help → Shortcuts, F1.
#[derive(Default)]
pub struct ShortcutsWindow {
    open: bool,
}

impl Window for ShortcutsWindow {
    fn title(&self) -> &'static str {
        "Shortcuts"
    }

    fn menu(&self) -> Option<super::Menu> {
        Some(super::Menu::Help)
    }

    fn menu_label(&self) -> String {
        "Shortcuts  (F1)".into()
    }

    fn is_open(&self) -> bool {
        self.open
    }

    fn set_open(&mut self, open: bool) {
        self.open = open;
    }

    fn show(&mut self, ctx: &egui::Context, _view: &WindowView) -> Vec<Action> {
        egui::Window::new(self.title())
            .open(&mut self.open)
            .resizable(false)
            .collapsible(false)
            .show(ctx, |ui| {
                egui::Grid::new("shortcuts").striped(true).show(ui, |ui| {
                    for (keys, what) in SHORTCUTS {
                        ui.monospace(*keys);
                        ui.label(*what);
                        ui.end_row();
                    }
                });
            });
        Vec::new()
    }
}

/// Every shortcut, as Help → Shortcuts (F1) lists them. The keys are
/// read in `app/keys.rs` (Escape's topmost window in `EditorApp::keys`),
/// the mouse in `ViewportPanel::input`.
pub const SHORTCUTS: &[(&str, &str)] = &[
    ("F1", "this list"),
    ("Ctrl+O", "open a preset"),
    ("Ctrl+S", "save"),
    ("Ctrl+Shift+S", "save as"),
    ("F12", "save the viewport image (PNG)"),
    ("Ctrl+Z", "undo"),
    ("Ctrl+Shift+Z, Ctrl+Y", "redo"),
    (
        "F",
        "frame the whole mesh from where the camera is",
    ),
    ("\\", "flicker: the look before the last edit, and back"),
    (
        "Esc",
        "close the topmost window; while comparing, back to the mode's view",
    ),
    ("Space", "while comparing: A alone / B alone"),
    ("left drag", "orbit the camera"),
    (
        "right or Shift+left drag",
        "move the light (or drag the light gizmo)",
    ),
    ("middle drag", "pan"),
    ("wheel", "zoom"),
    ("drop a file", "open a preset, mesh, HDR map or engine file"),
];
