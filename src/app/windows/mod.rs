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

pub mod help;
pub mod light;

use super::state;
use std::path::{Path, PathBuf};

/// A change of the editor's state that a window, toolbar or panel asks
/// for; [`super::EditorApp::apply`] performs it.
#[derive(Clone, Debug, PartialEq)]
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
}

/// What a window may read of the editor's state.
pub struct WindowView<'a> {
    pub view: &'a state::ViewState,
    /// The HDR map loaded last, if any.
    pub environment_file: Option<&'a Path>,
}

/// The menu bar's menu a window is opened from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Menu {
    View,
    Help,
}

/// A window: its title (also its egui id: Escape closes the topmost by
/// it), its menu item, its open flag and how it draws itself.
pub trait Window {
    fn title(&self) -> &'static str;
    /// The menu that opens it.
    fn menu(&self) -> Menu;
    /// Its item in that menu.
    fn menu_label(&self) -> String {
        format!("{}…", self.title())
    }
    fn is_open(&self) -> bool;
    fn set_open(&mut self, open: bool);
    /// Draws the window when it is open; what it wants changed.
    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action>;
}

/// Every window of this kind, listed once.
#[derive(Default)]
pub struct Windows {
    pub light: light::LightWindow,
    pub shortcuts: help::ShortcutsWindow,
    pub about: help::AboutWindow,
}

impl Windows {
    /// Each window, in drawing order.
    pub fn all_mut(&mut self) -> [&mut dyn Window; 3] {
        [&mut self.light, &mut self.shortcuts, &mut self.about]
    }

    pub fn all(&self) -> [&dyn Window; 3] {
        [&self.light, &self.shortcuts, &self.about]
    }

    /// The titles of the open windows.
    pub fn open_titles(&self) -> Vec<&'static str> {
        self.all()
            .into_iter()
            .filter(|w| w.is_open())
            .map(|w| w.title())
            .collect()
    }

    /// The items of `menu`: one a window, each opening it.
    pub fn menu_items_ui(&mut self, ui: &mut egui::Ui, menu: Menu) {
        for w in self.all_mut() {
            if w.menu() == menu && ui.button(w.menu_label()).clicked() {
                w.set_open(true);
                ui.close();
            }
        }
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
