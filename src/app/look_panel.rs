//! The look's panel (the left one): its name, model and parameters, the
//! rendering settings, the surface colour's source on a mesh with a colour
//! map, and what each engine reads of the look. A type as Rerun's panels
//! are: it edits a copy of the look and returns it as an [`Action`]; the
//! editor applies it, and commits an undo step once the gesture ends.

use super::params_ui;
use super::parts::ProfileState;
use super::windows::Action;
use crate::settings::albedo::MapColour;
use crate::settings::Preset;

/// What the look's panel draws and edits.
pub(super) struct LookPanel<'a> {
    /// The look as it stands (the panel edits a copy).
    pub(super) preset: &'a Preset,
    /// The model's last build and analysis (its error, the fits the
    /// engines' readouts go through) and the file the look came from.
    pub(super) profile: &'a ProfileState,
    /// The head's surface colour with a colour map: the map tinted, or
    /// the look's albedo alone (UI state, not the look).
    pub(super) map_colour: &'a mut MapColour,
    /// The loaded mesh's colour map's mean, if it has one.
    pub(super) colour_map_mean: Option<[f32; 3]>,
}

impl LookPanel<'_> {
    /// Draws the panel over a copy of the look; the copy, when an edit
    /// changed it ([`Action::EditLook`]).
    pub(super) fn ui(mut self, ui: &mut egui::Ui) -> Vec<Action> {
        let mut edited = self.preset.clone();
        let p = &mut edited;
        ui.heading("Look");
        ui.horizontal(|ui| {
            ui.label("Name");
            ui.text_edit_singleline(&mut p.name).on_hover_text(
                "The look's name, used in exports (Unity m_Name, Unreal asset name).",
            );
        });
        ui.separator();
        params_ui::model_picker_ui(ui, &mut p.profile);
        params_ui::model_params_ui(ui, &mut p.profile);
        self.map_colour_ui(ui);
        // The model's error, from the last build (never rebuilt per frame:
        // layered stacks take seconds).
        if let Some(Err(e)) = &self.profile.curves {
            ui.colored_label(ui.visuals().error_fg_color, e);
        }
        if let Err(e) = p.rendering.validate() {
            ui.colored_label(ui.visuals().error_fg_color, e.to_string());
        }
        ui.separator();
        egui::CollapsingHeader::new("Rendering")
            .default_open(true)
            .show(ui, |ui| params_ui::rendering_ui(ui, &mut p.rendering));
        ui.separator();
        egui::CollapsingHeader::new("Engines (live)")
            .default_open(true)
            .show(ui, |ui| self.engine_readouts_ui(ui, &edited));
        if edited != *self.preset {
            vec![Action::EditLook(Box::new(edited))]
        } else {
            Vec::new()
        }
    }

    /// Under the look's parameters, with a colour map on the mesh: that
    /// the map sets the surface colour, and the choice of the map tinted
    /// by the look's albedo or the look's albedo alone.
    fn map_colour_ui(&mut self, ui: &mut egui::Ui) {
        let Some(mean) = self.colour_map_mean else {
            return;
        };
        let mc = &mut *self.map_colour;
        if *mc == MapColour::Map {
            ui.colored_label(
                ui.visuals().warn_fg_color,
                "The mesh's colour map sets the surface colour: the Albedo above changes the profile's shape, not the head's colour.",
            );
        }
        ui.horizontal(|ui| {
            ui.label("Surface colour");
            egui::ComboBox::from_id_salt("map_colour")
                .selected_text(mc.label())
                .show_ui(ui, |ui| {
                    for m in MapColour::ALL {
                        ui.selectable_value(mc, m, m.label());
                    }
                })
                .response
                .on_hover_text(format!(
                    "The map's colour: as engines draw a material whose base colour is the map. Tinted: the map's detail with its mean (linear {:.3} / {:.3} / {:.3}) scaled to the look's albedo, albedo = A · map / mean, so that looks compared on a scan differ as their albedos do. The look's albedo: the map's colour not used.",
                    mean[0], mean[1], mean[2]
                ));
        });
    }

    /// What each engine reads of the look now (`p`): the file it was
    /// imported from, as that engine wrote it, and Unity's and Unreal's
    /// fields through the Burley fit.
    fn engine_readouts_ui(&self, ui: &mut egui::Ui, p: &Preset) {
        use crate::model::units::{UnityProfile, UnrealProfile, UNREAL_DEFAULT_WORLD_UNIT_SCALE};
        // The file the look came from, as that engine wrote it (while the
        // look is still the one imported).
        if let Some((path, look)) = &self.profile.imported {
            if look.preset == *p {
                let name = path.file_name().map_or_else(
                    || path.display().to_string(),
                    |n| n.to_string_lossy().into_owned(),
                );
                ui.label(format!("Imported from {name} ({})", look.kind))
                    .on_hover_text(path.display().to_string());
                let width = look
                    .fields
                    .iter()
                    .map(|(k, _)| k.chars().count())
                    .max()
                    .unwrap_or(0);
                let text: String = look
                    .fields
                    .iter()
                    .map(|(k, v)| format!("{k:width$}  {v}\n"))
                    .collect();
                ui.monospace(text.trim_end());
                for n in &look.notes {
                    ui.label(egui::RichText::new(format!("• {n}")).small());
                }
                ui.separator();
            }
        }
        let burley = match &p.profile {
            crate::settings::ProfileSpec::Burley(b) => {
                b.build().map(|b| (b, 0.0)).map_err(|e| e.to_string())
            }
            _ => match self
                .profile
                .latest
                .as_ref()
                .filter(|a| a.key.profile == p.profile)
            {
                Some(a) => a.burley_fit.clone().unwrap_or_else(|| Err("no fit".into())),
                None => {
                    ui.horizontal(|ui| {
                        super::report::spinner(ui);
                        ui.label("fitting Burley …");
                    });
                    return;
                }
            },
        };
        let (b, err) = match burley {
            Ok(x) => x,
            Err(e) => {
                ui.colored_label(ui.visuals().error_fg_color, e);
                return;
            }
        };
        if err > 0.0 {
            ui.label(format!(
                "Through a Burley fit (relative L2 error of r·R(r): {:.2} %)",
                100.0 * err
            ));
        }
        let f3 = |v: [f64; 3]| format!("({:.4}, {:.4}, {:.4})", v[0], v[1], v[2]);
        if let Ok(u) = UnityProfile::from_burley(&b, p.rendering.world_scale_m_per_unit) {
            ui.label("Unity HDRP")
                .on_hover_text("DiffusionProfileSettings fields");
            ui.monospace(format!(
                "scatteringDistance  {}\nmultiplier          {:.4}\nworldScale          {:.4} m/unit\nalbedo (material)   {}",
                f3(u.scattering_distance_color),
                u.scattering_distance_multiplier,
                u.world_scale_m_per_unit,
                f3(b.albedo())
            ));
        }
        if let Ok(u) = UnrealProfile::from_burley(&b, UNREAL_DEFAULT_WORLD_UNIT_SCALE) {
            ui.label("Unreal")
                .on_hover_text("SubsurfaceProfile (Burley, mean free path)");
            ui.monospace(format!(
                "SurfaceAlbedo         {}\nMeanFreePathColor     {}\nMeanFreePathDistance  {:.4} cm\nWorldUnitScale        {:.2}",
                f3(u.surface_albedo),
                f3(u.mean_free_path_color),
                u.mean_free_path_distance_cm,
                u.world_unit_scale
            ));
        }
    }
}
