//! The editor's windows as types (issue 51): each is a struct in its own
//! file that owns its open flag and its state, draws itself with one
//! [`Window::show`] from what it may read ([`WindowView`]) and returns what
//! it wants changed as [`Action`]s, which [`super::EditorApp::apply`]
//! performs in one place (`app/actions.rs`). No window writes the document
//! or another window's state. The list [`Windows`] is the one place a
//! window is named: the menus, the dialog loop and Escape go over it.
//!
//! The pattern is egui_demo_lib's `Demo`/`View` (a window is a value with
//! `show(ctx, &mut open)`) and Rerun's panels (a view returns commands to
//! the app rather than writing its state).

use super::state;
use std::path::{Path, PathBuf};

/// A change of the editor's state that a window, toolbar or panel asks
/// for; [`super::EditorApp::apply`] performs it.
#[derive(Clone, Debug)]
pub enum Action {
    /// The view's settings (light, exposure, display transform,
    /// environment) as the control left them.
    SetView(state::ViewState),
    /// A light rig, one click; one that needs an HDR map asks for a map
    /// and takes effect once it has loaded.
    ApplyRig(state::LightRig),
    /// The HDR map's file dialog.
    ChooseEnvironmentFile,
    /// An HDR map from a file (the shipped ones).
    LoadEnvironment(PathBuf),
    /// Opens the window of this title (a menu item).
    OpenWindow(&'static str),
    /// A line for the status bar (and a notification when it is an
    /// error or a warning).
    Say(String),
    /// The file dialog of this kind.
    OpenDialog(super::DialogKind),
    /// Save image at size's settings as its window left them.
    SetStill(still::StillSettings),
    /// Save turntable's settings as its window left them.
    SetTurntable(turntable::TurntableSettings),
    /// File → Browse presets: lists the presets (the artist's folders
    /// too) and opens the browser.
    BrowsePresets,
    /// The artist's preset folders as the browser left them (it lists
    /// them again).
    SetPresetFolders(Vec<PathBuf>),
    /// Opens this preset file (asking first about unsaved changes).
    OpenPreset(PathBuf),
    /// Starts a new look from this one (asking first about unsaved
    /// changes).
    NewLook(Box<crate::settings::Preset>),
    /// The look as an edit left it, one undo step (a fit applied).
    SetLook(Box<crate::settings::Preset>),
    /// The look as a control being used left it: the undo step is
    /// committed when the gesture ends (no button held, no field typed in).
    EditLook(Box<crate::settings::Preset>),
    /// A mesh's units and maps as a window left them (remembered for the
    /// file; the mesh reloads with them).
    SetMeshSettings(PathBuf, state::MeshSettings),
    /// Opens the first preset as the look (asking first about unsaved
    /// changes) and compares it side by side with the second as B.
    ComparePair([PathBuf; 2]),
    /// Undo and redo the look's last edit.
    Undo,
    Redo,
    /// Saves the look (Save As where it has no file yet).
    Save,
    /// The shipped head scan, or the procedural head, as the mesh.
    ScannedHead,
    ProceduralHead,
    /// Quits (asking first about unsaved changes).
    Quit,
    /// The interface's scale and theme (light: true).
    SetInterface {
        scale: f32,
        light_theme: bool,
    },
    /// Open on the head scan when no mesh is asked for.
    SetStartOnScan(bool),
    /// The compare toolbar's settings as it left them.
    SetCompare(super::compare::CompareSettings),
    /// The material-albedo prompt for B, on a typed colour.
    AskBAlbedoColour,
    /// "to truth": the viewport refines to the ground truth.
    SetRefineToTruth(bool),
    /// The unsaved-changes prompt's answer for what waited on it.
    AnswerUnsaved(super::Pending, unsaved::Unsaved),
    /// The overwrite prompt's answer: replace (true) or back to the dialog.
    AnswerOverwrite(super::Overwrite, bool),
    /// The recovery prompt's answer: restore (true) or discard the look
    /// an earlier editor left.
    AnswerRecovery(Box<super::autosave::Found>, bool),
    /// The material-albedo prompt's answer: OK (true) or the other button.
    AnswerAlbedo(albedo::AlbedoPrompt, bool),
    /// Imports an engine's file as a new, unsaved look (a file dropped).
    Import(PathBuf),
    /// Loads this mesh (a file dropped).
    LoadMesh(PathBuf),
    /// Opens the window of this title when closed, closes it when open
    /// (F1: Shortcuts).
    ToggleWindow(&'static str),
    /// Frames the mesh: the camera's distance and pan reset, its
    /// direction kept (F).
    FrameMesh,
    /// Shows the look before the last edit, or the look again (Backslash).
    ToggleBefore,
    /// What the viewport shows while comparing (Space, Escape).
    SetAb(super::AbView),
    /// A line in the frame log (`Report::log_line`).
    Log(String),
    /// The render thread loaded a mesh (`None`: the default head).
    MeshLoaded(Option<PathBuf>, super::viewport::MeshInfo),
    /// A mesh or its maps failed to load on the render thread, which kept
    /// the mesh on screen (`None`: the default head) with its settings.
    MeshFailed {
        asked: Option<PathBuf>,
        error: String,
        kept: Option<PathBuf>,
        kept_settings: state::MeshSettings,
    },
    /// The reference image's eyedropper: a linear colour into a field of
    /// the look, as an undoable edit.
    PickColour([f64; 3], reference::PickInto),
}

/// What a window may read of the editor's state.
pub struct WindowView<'a> {
    pub view: &'a state::ViewState,
    /// The HDR map loaded last, if any.
    pub environment_file: Option<&'a Path>,
    pub still: &'a still::StillSettings,
    pub turntable: &'a turntable::TurntableSettings,
    /// The artist's preset folders.
    pub preset_folders: &'a [PathBuf],
    /// The open look's file, if it has one.
    pub doc_path: Option<&'a Path>,
    /// The loaded mesh (none: the default head), its size once loaded,
    /// and every mesh's remembered units and maps.
    pub mesh: Option<&'a Path>,
    pub mesh_info: Option<super::viewport::MeshInfo>,
    pub meshes: &'a std::collections::BTreeMap<PathBuf, state::MeshSettings>,
    /// Wakes the UI from a window's own thread.
    pub waker: &'a super::wake::Waker,
    /// The look's name.
    pub look_name: &'a str,
    /// The mean colour of the head's colour map, when it has one.
    pub colour_map_mean: Option<[f32; 3]>,
    /// Where the viewport was drawn last frame.
    pub viewport_rect: Option<egui::Rect>,
    /// Where the Profile panel (the plots, right) was drawn last frame.
    pub profile_panel_rect: Option<egui::Rect>,
    /// The last frame's scene-linear radiance (a settled view of one look).
    pub radiance: Option<&'a std::sync::Arc<crate::render::SceneLinear>>,
}

impl WindowView<'_> {
    /// Where a window that works with the viewport and the Look panel
    /// (the budget's pairs, the reference's eyedropper) first opens: over
    /// the Profile panel, as wide as it, so that neither the render nor
    /// the fields it picks into are covered, `down` below the panel's top
    /// (two such windows open at once stay apart); its place and width.
    pub fn over_profile_panel(&self, width: f32, down: f32) -> (egui::Pos2, f32) {
        match self.profile_panel_rect {
            Some(r) => (
                r.left_top() + egui::vec2(4.0, down),
                (r.width() - 8.0).min(width),
            ),
            None => (egui::pos2(860.0, 96.0), width),
        }
    }

    /// A window's first place: inside the viewport's top left, `down`
    /// below its top (clear of the Look panel), or near the top left
    /// before the viewport was drawn.
    pub fn pos_in_viewport(&self, down: f32) -> egui::Pos2 {
        self.viewport_rect.map_or(egui::pos2(330.0, 96.0), |r| {
            r.left_top() + egui::vec2(8.0, down)
        })
    }
}

/// The menu bar's menu a window is opened from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Menu {
    /// The File menu's first items, with the presets.
    FilePresets,
    /// The File menu's images (after the viewport's PNG and the reference).
    FileImages,
    /// The view toolbar's Mesh menu (with a mesh loaded).
    Mesh,
    View,
    Help,
}

/// A window: its title (also its egui id: Escape closes the topmost by
/// it), its menu item, its open flag and how it draws itself.
pub trait Window {
    fn title(&self) -> &'static str;
    /// The menu that opens it (none: opened another way).
    fn menu(&self) -> Option<Menu>;
    /// Its item in that menu.
    fn menu_label(&self) -> String {
        format!("{}…", self.title())
    }
    /// Its menu item's tooltip.
    fn menu_tooltip(&self) -> &'static str {
        ""
    }
    /// Whether its menu item is listed now.
    fn in_menu(&self) -> bool {
        true
    }
    fn is_open(&self) -> bool;
    /// What its menu item asks for, where opening needs more than the
    /// open flag (none: the item opens it).
    fn opens_with(&self) -> Option<Action> {
        None
    }
    fn set_open(&mut self, open: bool);
    /// A modal prompt: it answers Escape itself, and no key reaches the
    /// look while it is up.
    fn is_modal(&self) -> bool {
        false
    }
    /// Draws the window when it is open; what it wants changed.
    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action>;
}

/// A modal prompt's answer: what waited on it, taken out, given to
/// `action` with the answer; nothing while unanswered (it stays).
pub fn answered<T, A>(
    waiting: &mut Option<T>,
    answer: Option<A>,
    action: impl FnOnce(T, A) -> Action,
) -> Vec<Action> {
    match answer {
        Some(a) => waiting.take().map(|t| action(t, a)).into_iter().collect(),
        None => Vec::new(),
    }
}

/// A menu's item for a window: its label, tooltip and what it asks for.
#[derive(Clone, Debug)]
pub struct MenuItem {
    pub label: String,
    pub tooltip: String,
    pub action: Action,
}

/// `items` as menu buttons; what the one clicked asks for (the menu
/// closes).
pub fn items_ui(ui: &mut egui::Ui, items: &[MenuItem]) -> Vec<Action> {
    let mut actions = Vec::new();
    for item in items {
        let mut button = ui.button(&item.label);
        if !item.tooltip.is_empty() {
            button = button.on_hover_text(&item.tooltip);
        }
        if button.clicked() {
            actions.push(item.action.clone());
            ui.close();
        }
    }
    actions
}

/// The registry of windows, as `render/sss`'s `methods!` is of methods:
/// each entry is a window's file (`mod`) and its type, in drawing order,
/// and makes the module, the [`Windows`] field of that name and its place
/// in [`Windows::all`]. A new window is its file and one line here.
macro_rules! windows {
    ($($m:ident: $window:ident),* $(,)?) => {
        $(pub mod $m;)*

        /// Every window, listed once.
        #[derive(Default)]
        pub struct Windows {
            $(pub $m: $m::$window,)*
        }

        impl Windows {
            /// Each window, in drawing order.
            pub fn all_mut(&mut self) -> Vec<&mut dyn Window> {
                vec![$(&mut self.$m,)*]
            }

            /// Each window, in drawing order.
            pub fn all(&self) -> Vec<&dyn Window> {
                vec![$(&self.$m,)*]
            }
        }
    };
}

windows! {
    recovery: RecoveryWindow,
    unsaved: UnsavedWindow,
    overwrite: OverwriteWindow,
    albedo: AlbedoWindow,
    browser: BrowserWindow,
    budget: BudgetWindow,
    still: StillWindow,
    turntable: TurntableWindow,
    units: UnitsWindow,
    maps: MapsWindow,
    reference: ReferenceWindow,
    light: LightWindow,
    histogram: HistogramWindow,
    shortcuts: ShortcutsWindow,
    about: AboutWindow,
}

impl Windows {
    /// The titles of the open windows (not the modal prompts: they take
    /// Escape themselves).
    pub fn open_titles(&self) -> Vec<&'static str> {
        self.all()
            .into_iter()
            .filter(|w| w.is_open() && !w.is_modal())
            .map(|w| w.title())
            .collect()
    }

    /// Whether a modal prompt is up.
    pub fn modal_open(&self) -> bool {
        self.all().into_iter().any(|w| w.is_open() && w.is_modal())
    }

    /// The items of `menu`, one a window listed now.
    pub fn items(&self, menu: Menu) -> Vec<MenuItem> {
        self.all()
            .into_iter()
            .filter(|w| w.menu() == Some(menu) && w.in_menu())
            .map(|w| MenuItem {
                label: w.menu_label(),
                tooltip: w.menu_tooltip().into(),
                action: w.opens_with().unwrap_or(Action::OpenWindow(w.title())),
            })
            .collect()
    }

    /// Opens the window titled `title`; whether there is one.
    pub fn open(&mut self, title: &str) -> bool {
        for w in self.all_mut() {
            if w.title() == title {
                w.set_open(true);
                return true;
            }
        }
        false
    }

    /// Closes the window titled `title`; whether one was.
    pub fn close(&mut self, title: &str) -> bool {
        for w in self.all_mut() {
            if w.title() == title && w.is_open() {
                w.set_open(false);
                return true;
            }
        }
        false
    }

    /// Draws the open windows; what they want changed.
    pub fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        self.all_mut()
            .into_iter()
            .flat_map(|w| w.show(ctx, view))
            .collect()
    }
}
