//! Engine files drawn as the engine draws them, and a mesh's colour map
//! against the look's colour.
//!
//! HDRP keeps the albedo in the material: a diffusion profile's filter is
//! normalised and its file has no colour, so its import has albedo 1 and
//! draws a white head (`export/unity/read.rs` sets
//! `RenderingSpec::albedo_in_material`). Such a look is drawn and compared
//! with a *material albedo*: look A's (the default), the head's colour map
//! or a typed one. Opening one as the look asks once and writes the choice
//! into its albedo; as B the choice is the compare row's "B's albedo",
//! asked the first time.
//!
//! A mesh's own colour map is the surface colour as the engines draw it,
//! whatever the look's albedo; the Look panel says so and offers the map
//! tinted by the look's albedo, or the look's albedo alone
//! ([`MapColour`]).

use super::windows::albedo::{AlbedoPrompt, PromptFor};
use super::EditorApp;
use crate::model::Rgb;
use crate::settings::albedo::{b_as_drawn, resolve, set_albedo, MapColour, MaterialAlbedo};
use crate::settings::Preset;

impl EditorApp {
    /// Look A's albedo without building a slow model each frame: Burley's
    /// A, else the total reflectance of the curves the analysis thread
    /// computed for the look (clamped to [0, 1]; the kernels without a
    /// colour draw the default skin's, as `look_albedo` says), else
    /// [`look_albedo`] where the model is quick to build.
    pub(super) fn a_albedo(&self) -> Rgb {
        self.profile.a_albedo(&self.doc.preset)
    }

    /// The loaded mesh's colour map's mean colour, if it has one.
    pub(super) fn colour_map_mean(&self) -> Option<[f32; 3]> {
        self.meshes.colour_map_mean()
    }

    /// B as drawn ([`b_as_drawn`]) with the editor's choices.
    pub(super) fn b_drawn(&self, b: Preset) -> (Preset, MapColour, Option<String>) {
        b_as_drawn(
            b,
            self.a_albedo(),
            self.ui_state.b_material_albedo,
            self.ui_state.map_colour,
            self.meshes.colour_map_mean(),
        )
    }

    /// "drawn with A's albedo" when B's engine keeps the albedo in the
    /// material (the compare row and the difference readout say it).
    pub(super) fn b_albedo_note(&self) -> Option<String> {
        match &self.profile.b_look_cache {
            Some((_, _, Ok(b))) if b.rendering.albedo_in_material => self
                .b_drawn(b.clone())
                .2
                .map(|label| format!("drawn with {label} albedo")),
            _ => None,
        }
    }

    /// Asks for the document's material albedo if its engine keeps it in
    /// the material; `a_albedo` is the look open before it.
    pub(super) fn ask_document_albedo(&mut self, a_albedo: Rgb) {
        if !self.doc.preset.rendering.albedo_in_material {
            return;
        }
        self.windows.albedo.prompt = Some(AlbedoPrompt {
            target: PromptFor::Look,
            name: self.doc.preset.name.clone(),
            choice: MaterialAlbedo::LookA,
            typed: a_albedo.map(|c| c as f32),
            a_albedo,
        });
    }

    /// Asks, the first time, which material albedo B is drawn with when
    /// B's engine keeps it in the material.
    pub(super) fn ask_b_albedo(&mut self, b: &Preset) {
        if !b.rendering.albedo_in_material || self.ui_state.b_material_albedo_asked {
            return;
        }
        let a_albedo = self.a_albedo();
        self.windows.albedo.prompt = Some(AlbedoPrompt {
            target: PromptFor::CompareB,
            name: b.name.clone(),
            choice: self.ui_state.b_material_albedo,
            typed: match self.ui_state.b_material_albedo {
                MaterialAlbedo::Typed(c) => c.map(|v| v as f32),
                _ => a_albedo.map(|c| c as f32),
            },
            a_albedo,
        });
    }

    /// The prompt's other button: "Use A's for now" for B (A's, asked),
    /// "Keep albedo 1" for a document (said).
    pub(super) fn decline_albedo_prompt(&mut self, p: AlbedoPrompt) {
        if p.target == PromptFor::CompareB {
            self.ui_state.b_material_albedo = MaterialAlbedo::LookA;
            self.ui_state.b_material_albedo_asked = true;
        } else {
            self.say(format!(
                "\"{}\" keeps its file's albedo 1 (a white head): set Albedo to the material's",
                p.name
            ));
        }
    }

    /// Applies the prompt's answer.
    pub(super) fn answer_albedo_prompt(&mut self, p: AlbedoPrompt) {
        let map_mean = self.meshes.colour_map_mean();
        match p.target {
            PromptFor::CompareB => {
                self.ui_state.b_material_albedo = p.choice;
                self.ui_state.b_material_albedo_asked = true;
                self.say(format!(
                    "B \"{}\" is drawn with {} albedo (its engine keeps the albedo in the material); change it beside B",
                    p.name,
                    p.choice.label()
                ));
            }
            PromptFor::Look => {
                let rgb = resolve(p.choice, p.a_albedo, map_mean);
                let as_read = self.doc.preset.clone();
                let preset = &mut self.doc.preset;
                if !set_albedo(preset, rgb) {
                    return;
                }
                preset.rendering.albedo_in_material = false;
                let what = match (p.choice, map_mean) {
                    (MaterialAlbedo::LookA, _) => "the look open before it".to_string(),
                    (MaterialAlbedo::Map, Some(_)) => "the head's colour map's mean".to_string(),
                    (MaterialAlbedo::Map, None) => {
                        "the look open before it (no colour map)".to_string()
                    }
                    (MaterialAlbedo::Typed(_), _) => "typed at import".to_string(),
                };
                preset.description = format!(
                    "{} Albedo {:.4}/{:.4}/{:.4} from the material ({what}): its engine keeps the albedo in the material, and the file has none.",
                    preset.description, rgb[0], rgb[1], rgb[2]
                )
                .trim()
                .to_owned();
                if p.choice == MaterialAlbedo::Map && map_mean.is_some() {
                    self.ui_state.map_colour = MapColour::Map;
                }
                // An import (no file yet) starts as what was chosen; a
                // preset file that says "albedo in the material" keeps its
                // own as the undo step and shows as changed.
                let undo = if self.doc.path.is_none() {
                    self.doc = super::state::Document::new(self.doc.preset.clone(), None);
                    "Keep albedo 1 in the prompt draws the file's white"
                } else {
                    self.doc.commit();
                    "undo gives back the file's albedo 1"
                };
                // The Engines panel's readout of the file stays: this is
                // the look imported, with its material's albedo.
                if let Some((_, look)) = &mut self.profile.imported {
                    if look.preset == as_read {
                        look.preset = self.doc.preset.clone();
                    }
                }
                self.say(format!(
                    "\"{}\" drawn with albedo {:.3}/{:.3}/{:.3} ({what}); {undo}",
                    p.name, rgb[0], rgb[1], rgb[2]
                ));
            }
        }
    }

    /// The material-albedo prompt for B, on a typed colour ("a colour…"
    /// beside B).
    pub(super) fn ask_b_albedo_colour(&mut self) {
        let b = match &self.profile.b_look_cache {
            Some((_, _, Ok(b))) if b.rendering.albedo_in_material => b.clone(),
            _ => return,
        };
        self.ui_state.b_material_albedo_asked = false;
        self.ask_b_albedo(&b);
        if let Some(p) = self.windows.albedo.prompt.as_mut() {
            p.choice = MaterialAlbedo::Typed(p.typed.map(|c| c as f64));
        }
    }
}
