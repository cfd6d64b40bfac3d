//! The keyboard's shortcuts and the files dropped on the window, read as
//! [`Action`]s that `EditorApp::apply` performs (issue 51). Escape's
//! topmost window is `dialogs.rs`'s: which window is on top is egui's.

use super::windows::Action;
use super::{AbView, DialogKind};
use std::path::PathBuf;

/// What the keys' meaning depends on.
pub(super) struct KeysView {
    /// The look has a state before its last edit (Backslash shows it).
    pub has_before: bool,
    /// A compare mode is on (Space and Escape switch what is shown).
    pub comparing: bool,
    /// What the viewport shows while comparing.
    pub ab: AbView,
    /// This frame's Escape closed a window (it goes no further).
    pub escape_taken: bool,
}

/// The shortcuts pressed this frame: Ctrl+Z / Ctrl+Shift+Z / Ctrl+Y undo
/// and redo, Ctrl+S / Ctrl+Shift+S save, Ctrl+O open, F12 save the image,
/// F1 the shortcuts window; and the viewport's keys (not while typing in
/// a field): F frames the mesh (as Blender, Maya and Substance do: the
/// camera's distance and pan reset, its direction kept), Backslash
/// flickers to the look before the last edit (Lightroom's before/after
/// key), and while comparing Space flips between B alone and A alone
/// (from the mode's own view it shows B first) and Escape goes back to
/// the mode's view. The caller reads none while a modal prompt is up: it
/// asked about the look as it is.
pub(super) fn shortcuts(ctx: &egui::Context, view: &KeysView) -> Vec<Action> {
    use egui::{Key, KeyboardShortcut, Modifiers};
    let cmd_shift = Modifiers::COMMAND | Modifiers::SHIFT;
    let shortcut = |m, k| ctx.input_mut(|i| i.consume_shortcut(&KeyboardShortcut::new(m, k)));
    let (redo, undo, redo_y) = (
        shortcut(cmd_shift, Key::Z),
        shortcut(Modifiers::COMMAND, Key::Z),
        shortcut(Modifiers::COMMAND, Key::Y),
    );
    let (save_as, save, open) = (
        shortcut(cmd_shift, Key::S),
        shortcut(Modifiers::COMMAND, Key::S),
        shortcut(Modifiers::COMMAND, Key::O),
    );
    let key = |k| ctx.input_mut(|i| i.consume_key(Modifiers::NONE, k));
    let (toggle, image, help) = (
        ctx.input(|i| i.key_pressed(Key::Space)),
        key(Key::F12),
        key(Key::F1),
    );
    let mut actions = Vec::new();
    let mut push = |on: bool, a: Action| {
        if on {
            actions.push(a)
        }
    };
    push(help, Action::ToggleWindow("Shortcuts"));
    push(image, Action::OpenDialog(DialogKind::SaveImage));
    push(redo || redo_y, Action::Redo);
    push(undo && !(redo || redo_y), Action::Undo);
    push(save_as, Action::OpenDialog(DialogKind::SaveAs));
    push(save && !save_as, Action::Save);
    push(open, Action::OpenDialog(DialogKind::Open));
    // The viewport's keys, not while a field is typed into.
    let free = ctx.memory(|m| m.focused().is_none());
    push(free && key(Key::F), Action::FrameMesh);
    push(
        free && key(Key::Backslash) && view.has_before,
        Action::ToggleBefore,
    );
    if free && view.comparing && !view.escape_taken {
        if toggle {
            actions.push(Action::SetAb(match view.ab {
                AbView::B => AbView::A,
                AbView::Both | AbView::A => AbView::B,
            }));
        } else if ctx.input(|i| i.key_pressed(Key::Escape)) {
            actions.push(Action::SetAb(AbView::Both));
        }
    }
    actions
}

/// The files dropped on the window this frame, each opened as what its
/// extension says: a preset, an engine's file (a look), a mesh or an HDR
/// map; anything else is an error naming the file and what is read.
pub(super) fn dropped(ctx: &egui::Context) -> Vec<Action> {
    let dropped: Vec<PathBuf> = ctx.input(|i| {
        i.raw
            .dropped_files
            .iter()
            .map(|f| f.path().to_path_buf())
            .filter(|p| !p.as_os_str().is_empty())
            .collect()
    });
    let engines = crate::export::importable_extensions(false);
    let meshes = crate::render::mesh::Mesh::EXTENSIONS;
    dropped
        .into_iter()
        .map(|path| {
            let ext = path
                .extension()
                .and_then(|e| e.to_str())
                .unwrap_or("")
                .to_ascii_lowercase();
            match ext.as_str() {
                e if e == crate::settings::PRESET_EXTENSION => Action::OpenPreset(path),
                // A .gltf is a look when a material has the volume
                // extension (the glTF export), and otherwise a mesh.
                e if engines.contains(&e)
                    && (!meshes.contains(&e) || crate::export::gltf_has_volume(&path)) =>
                {
                    Action::Import(path)
                }
                e if meshes.contains(&e) => Action::LoadMesh(path),
                "hdr" => Action::LoadEnvironment(path),
                _ => Action::Say(format!(
                    "Error: {}: not a preset (.ron), engine file (.{}), mesh (.{}) or environment (.hdr)",
                    path.display(),
                    engines.join(", ."),
                    meshes.join(", ."),
                )),
            }
        })
        .collect()
}
