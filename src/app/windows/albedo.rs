//! The material-albedo prompt: a look from an engine that keeps the
//! albedo in the material (HDRP: the profile's file has none) opened as
//! the look or as B asks once what to draw it with: look A's albedo (the
//! default), the head's colour map or a typed colour. A modal: it decides
//! what the next frame draws. Its answer is an [`Action::AnswerAlbedo`],
//! which `EditorApp::apply` writes into the look or B's choice.
//!
//! HDRP keeps the albedo in the material: a diffusion profile's filter is
//! normalised and its file has no colour, so its import has albedo 1 and
//! draws a white head (`export/unity/read.rs` sets
//! `RenderingSpec::albedo_in_material`). Such a look is drawn and compared
//! with a *material albedo*: look A's (the default), the head's colour map
//! or a typed one. Opening one as the look asks once and writes the choice
//! into its albedo; as B the choice is the compare row's "B's albedo",
//! asked the first time.

use super::{Action, Window, WindowView};
use crate::model::Rgb;
use crate::settings::albedo::MaterialAlbedo;

/// What the prompt is for.
#[derive(Debug, Clone, PartialEq)]
pub enum PromptFor {
    /// The look just opened or imported (its albedo is set).
    Look,
    /// B, a file of such an engine (`UiState::b_material_albedo`).
    CompareB,
}

/// The open prompt's question and the choice so far.
#[derive(Debug, Clone, PartialEq)]
pub struct AlbedoPrompt {
    pub target: PromptFor,
    /// The look's name and the engine's file kind, for the text.
    pub name: String,
    pub choice: MaterialAlbedo,
    /// The colour the "typed" choice edits (linear).
    pub typed: [f32; 3],
    /// Look A's albedo when the prompt opened (for a document: the look
    /// open before it).
    pub a_albedo: Rgb,
    /// The choice is still the default the prompt opened with (a look's:
    /// it turns to the head's map when the map arrives after the prompt,
    /// as when a file is imported at start-up, before the scan is in).
    pub by_default: bool,
}

/// The prompt, while it is asking.
#[derive(Default)]
pub struct AlbedoWindow {
    pub prompt: Option<AlbedoPrompt>,
    /// The prompt has been drawn: Enter and Escape are its from the next
    /// frame on (the Enter that confirmed a file dialog in the frame the
    /// prompt opened is not its OK).
    drawn: bool,
}

impl AlbedoWindow {
    /// Asks for the look's material albedo if its engine keeps it in the
    /// material; `a_albedo` is the look open before it, `map_mean` the
    /// head's colour map's mean colour if it has one. The safe answer is
    /// the default: the head's map where there is one (the colour the
    /// engine's material takes from it), else the default skin's albedo,
    /// never the look open before, which may be jade or ketchup.
    pub fn ask_look(
        &mut self,
        look: &crate::settings::Preset,
        a_albedo: Rgb,
        map_mean: Option<[f32; 3]>,
    ) {
        if !look.rendering.albedo_in_material {
            return;
        }
        self.prompt = Some(AlbedoPrompt {
            target: PromptFor::Look,
            name: look.name.clone(),
            choice: match map_mean {
                Some(_) => MaterialAlbedo::Map,
                None => MaterialAlbedo::DefaultSkin,
            },
            typed: a_albedo.map(|c| c as f32),
            a_albedo,
            by_default: true,
        });
    }

    /// Asks which material albedo B is drawn with when B's engine keeps it
    /// in the material, `current` being the choice so far (the typed
    /// colour starts from it).
    pub fn ask_b(&mut self, b: &crate::settings::Preset, current: MaterialAlbedo, a_albedo: Rgb) {
        if !b.rendering.albedo_in_material {
            return;
        }
        self.prompt = Some(AlbedoPrompt {
            target: PromptFor::CompareB,
            name: b.name.clone(),
            choice: current,
            typed: match current {
                MaterialAlbedo::Typed(c) => c.map(|v| v as f32),
                _ => a_albedo.map(|c| c as f32),
            },
            a_albedo,
            by_default: false,
        });
    }
}

impl AlbedoPrompt {
    /// The four choices: A's albedo, the head's map, the default skin's, a
    /// typed colour.
    fn choices_ui(&mut self, ui: &mut egui::Ui, has_map: bool) {
        let a = self.a_albedo;
        let before = if self.target == PromptFor::Look {
            ": the look open before it"
        } else {
            ""
        };
        ui.radio_value(
            &mut self.choice,
            MaterialAlbedo::LookA,
            format!("A's albedo ({:.3} / {:.3} / {:.3}){before}", a[0], a[1], a[2]),
        )
        .on_hover_text("The colour held equal, so that only the profile's shape differs: how far this engine's profile is from the look.");
        ui.add_enabled_ui(has_map, |ui| {
            ui.radio_value(&mut self.choice, MaterialAlbedo::Map, "the head's colour map")
                .on_hover_text("The loaded mesh's colour map as the engine's material uses it (its mean colour in the plots).")
                .on_disabled_hover_text("The head has no colour map of its own (the default head's map only varies the look's colour): load a mesh with one.");
        });
        let skin = crate::settings::albedo::KERNEL_SURFACE_ALBEDO;
        ui.radio_value(
            &mut self.choice,
            MaterialAlbedo::DefaultSkin,
            format!(
                "the default skin's ({:.3} / {:.3} / {:.3})",
                skin[0], skin[1], skin[2]
            ),
        )
        .on_hover_text("Unreal Engine's default SurfaceAlbedo, the default skin's: a skin colour whatever look was open.");
        ui.horizontal(|ui| {
            let typed = matches!(self.choice, MaterialAlbedo::Typed(_));
            if ui.radio(typed, "this colour").clicked() || typed {
                self.choice = MaterialAlbedo::Typed(self.typed.map(|c| c as f64));
            }
            if egui::color_picker::color_edit_button_rgb(ui, &mut self.typed)
                .on_hover_text("Linear RGB, the material's base colour")
                .changed()
            {
                self.choice = MaterialAlbedo::Typed(self.typed.map(|c| c as f64));
            }
            let t = self.typed;
            ui.label(format!("{:.3} / {:.3} / {:.3}", t[0], t[1], t[2]));
        });
    }

    /// OK (true) and the other answer (false), if one was clicked.
    fn buttons_ui(&self, ui: &mut egui::Ui) -> Option<bool> {
        let mut answer = None;
        ui.horizontal(|ui| {
            if ui.button("OK").clicked() {
                answer = Some(true);
            }
            let other = if self.target == PromptFor::Look {
                "Keep albedo 1 (white)"
            } else {
                "Use A's for now"
            };
            if ui.button(other).clicked() {
                answer = Some(false);
            }
        });
        answer
    }
}

impl Window for AlbedoWindow {
    fn title(&self) -> &'static str {
        "Material albedo"
    }
    /// Opened by an engine file whose albedo is the material's.
    fn menu(&self) -> Option<super::Menu> {
        None
    }
    fn is_open(&self) -> bool {
        self.prompt.is_some()
    }
    fn set_open(&mut self, open: bool) {
        if !open {
            self.prompt = None;
        }
    }
    fn is_modal(&self) -> bool {
        true
    }

    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        let Some(p) = self.prompt.as_mut() else {
            self.drawn = false;
            return Vec::new();
        };
        let keys_are_ours = std::mem::replace(&mut self.drawn, true);
        let modal = egui::Modal::new(egui::Id::unique("scatterlab_albedo_prompt")).show(ctx, |ui| {
            ui.set_max_width(460.0);
            ui.heading("Material albedo");
            ui.label(format!(
                "\"{}\" comes from an engine that keeps the albedo in the material (HDRP): its file has no colour, so as it is it draws a white head. Draw {} with:",
                p.name,
                if p.target == PromptFor::Look { "it" } else { "B" }
            ));
            let has_map = view.colour_map_mean.is_some();
            if p.by_default && has_map && p.target == PromptFor::Look {
                p.choice = MaterialAlbedo::Map;
            }
            let before = p.choice;
            p.choices_ui(ui, has_map);
            // Any click in the prompt is the artist's choice, even of the
            // default already shown.
            p.by_default &= p.choice == before && !ui.input(|i| i.pointer.any_pressed());
            ui.separator();
            p.buttons_ui(ui)
        });
        // Enter answers OK, Escape the other button (as the prompt's keys
        // elsewhere).
        let (enter, escape) = ctx.input(|i| {
            (i.key_pressed(egui::Key::Enter), i.key_pressed(egui::Key::Escape))
        });
        let (enter, escape) = (enter && keys_are_ours, escape && keys_are_ours);
        let answer = modal
            .inner
            .or(enter.then_some(true))
            .or(escape.then_some(false));
        if answer.is_some() {
            self.drawn = false;
        }
        super::answered(&mut self.prompt, answer, Action::AnswerAlbedo)
    }
}
