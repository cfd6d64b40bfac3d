//! View → Light & display (and the toolbar's "Light" menu): the light
//! rigs, the key, fill and rim lights, the exposure, the display transform
//! and the environment with its HDR map's turn and blur, in a window that
//! stays open while they are used. In a menu, the display transform's
//! combo box could not be opened with a pointer (the click that opens its
//! list lands outside the menu, and egui closes the menu), nor the map's
//! fields typed into (egui issues #4153, #7821; tests/pointer.rs).

use super::{Action, Window, WindowView};
use crate::app::state::{self, EnvironmentChoice, LightRig};

/// The window's title, and the menu item that opens it.
pub const TITLE: &str = "Light & display";

#[derive(Default)]
pub struct LightWindow {
    open: bool,
    /// The shipped HDR maps, listed once (not read from disk each frame).
    shipped: Option<Vec<std::path::PathBuf>>,
}

impl Window for LightWindow {
    fn title(&self) -> &'static str {
        TITLE
    }

    fn menu(&self) -> Option<super::Menu> {
        Some(super::Menu::View)
    }

    fn is_open(&self) -> bool {
        self.open
    }

    fn set_open(&mut self, open: bool) {
        self.open = open;
    }

    fn show(&mut self, ctx: &egui::Context, view: &WindowView) -> Vec<Action> {
        let mut actions = Vec::new();
        let mut v = *view.view;
        egui::Window::new(TITLE)
            .open(&mut self.open)
            .resizable(false)
            .collapsible(true)
            .default_pos(ctx.content_rect().right_top() + egui::vec2(-520.0, 90.0))
            .show(ctx, |ui| {
                rigs_ui(ui, &v, &mut actions);
                ui.separator();
                key_light_ui(ui, &mut v);
                ui.separator();
                let shipped = self.shipped.get_or_insert_with(state::shipped_hdr_maps);
                environment_ui(ui, &mut v, view, shipped, &mut actions);
            });
        if v != *view.view {
            actions.push(Action::SetView(v));
        }
        actions
    }
}

/// The rigs, one click each.
fn rigs_ui(ui: &mut egui::Ui, v: &state::ViewState, actions: &mut Vec<Action>) {
    let current = LightRig::current(v);
    ui.horizontal_wrapped(|ui| {
        ui.label("Rig");
        for rig in LightRig::ALL {
            if ui
                .selectable_label(current == Some(rig), rig.label())
                .on_hover_text(rig.tip())
                .clicked()
            {
                actions.push(Action::ApplyRig(rig));
            }
        }
    })
    .response
    .on_hover_text("Lighting set-ups that show scattering, each one click: the key light's direction is relative to the camera. Right-drag the view or drag the light gizmo (bottom right) to move the light.");
}

/// The key, fill and rim lights, the exposure, the camera's focal length
/// and the display transform.
fn key_light_ui(ui: &mut egui::Ui, v: &mut state::ViewState) {
    egui::Grid::new("light_display").num_columns(2).show(ui, |ui| {
        ui.label("Key light");
        ui.horizontal(|ui| {
            ui.add(
                egui::DragValue::new(&mut v.orbit.light_intensity)
                    .range(0.0..=50.0)
                    .speed(0.05)
                    .prefix("intensity "),
            )
            .on_hover_text("Irradiance of the key light at normal incidence (linear). It casts the shadow and comes through thin parts; right-drag the view or drag the light gizmo to move it.");
            light_colour_ui(ui, "key light", &mut v.orbit.light_colour);
        });
        ui.end_row();
        let yaw = v.orbit.camera_yaw_rad;
        rig_light_ui(ui, "Fill light", &mut v.orbit.fill, yaw);
        rig_light_ui(ui, "Rim light", &mut v.orbit.rim, yaw);
        ui.label("Exposure");
        // In stops (EV): the multiplier is 2^EV.
        let mut ev = v.orbit.exposure.max(1e-4).log2();
        if ui
            .add(
                egui::DragValue::new(&mut ev)
                    .range(-8.0..=8.0)
                    .speed(0.02)
                    .max_decimals(2)
                    .prefix("exposure ")
                    .suffix(" EV"),
            )
            .on_hover_text("Exposure in stops before the display transform: +1 EV doubles the light, 0 EV leaves it (the multiplier is 2^EV).")
            .changed()
        {
            v.orbit.exposure = ev.exp2();
        }
        ui.end_row();
        ui.label("Camera");
        let mut mm = v.orbit.focal_length_mm();
        if ui
            .add(
                egui::DragValue::new(&mut mm)
                    .range(12.0..=300.0)
                    // A remembered field of view outside the range is not
                    // rewritten by opening the window.
                    .clamp_existing_to_range(false)
                    .speed(0.2)
                    .max_decimals(1)
                    .prefix("focal length ")
                    .suffix(" mm"),
            )
            .on_hover_text(format!(
                "The lens, as a full-frame (36 × 24 mm) camera's: {:.1}° vertical field of view. A longer lens zooms in from where the camera is (F frames the mesh again); Reset view goes back to {:.1} mm.",
                v.orbit.fov_y_rad.to_degrees(),
                crate::settings::OrbitView::default().focal_length_mm()
            ))
            .changed()
        {
            v.orbit.set_focal_length_mm(mm);
        }
        ui.end_row();
        ui.label("Display");
        let current = v.tone_map.label();
        let combo = egui::ComboBox::from_id_salt("display")
            .selected_text(current)
            .show_ui(ui, |ui| {
                for t in crate::render::tonemap::ToneMap::ALL {
                    ui.selectable_value(&mut v.tone_map, t, t.label());
                }
            })
            .response;
        // Named for AccessKit (and the pointer test), as its row says.
        combo.widget_info(|| {
            let mut info = egui::WidgetInfo::labeled(egui::accesskit::Role::ComboBox, true, "display");
            info.current_text_value = Some(current.into());
            info
        });
        combo.on_hover_text("The display transform from scene light to the screen: ACES fit (Narkowicz 2015, scatterlab's former curve), ACES (Hill's RRT+ODT fit: desaturated highlights), AgX (Blender's default view) or Khronos PBR Neutral (base colours as authored up to 0.76). Saved images and turntables use it too.");
        ui.end_row();
    });
}

/// A light's colour: the swatch that opens the picker (linear RGB, 0–1),
/// named for AccessKit as "<name> colour".
fn light_colour_ui(ui: &mut egui::Ui, name: &str, colour: &mut [f32; 3]) {
    let mut rgb = colour.map(f64::from);
    if crate::app::colour_ui::colour_picker_ui(ui, name, &mut rgb, &(0.0..=1.0)) {
        *colour = rgb.map(|c| c as f32);
    }
}

/// A fill or rim light's row: intensity (0 = off), colour and direction
/// from the camera, as the rigs give it (the azimuth is kept in world
/// terms, so the light stays put while the camera orbits).
fn rig_light_ui(ui: &mut egui::Ui, label: &str, l: &mut crate::settings::RigLight, yaw: f32) {
    ui.label(label);
    let name = label.to_lowercase();
    ui.horizontal(|ui| {
        ui.add(
            egui::DragValue::new(&mut l.intensity)
                .range(0.0..=50.0)
                .speed(0.05)
                .max_decimals(3)
                .prefix(format!("{} ", name.trim_end_matches(" light"))),
        )
        .on_hover_text(format!("Intensity: irradiance of the {name} at normal incidence (linear); 0 turns it off. It casts no shadow (the one shadow map is the key's) and in the real-time methods does not come through thin parts (transmission is the key's; the ground truth, which lights every surface, takes it through the backs of ears too: judge transmission with the key alone); it adds to the key's light."));
        light_colour_ui(ui, &name, &mut l.colour);
        ui.add_enabled_ui(l.intensity > 0.0, |ui| {
            let turn = std::f32::consts::TAU;
            let mut az = ((l.azimuth_rad - yaw + std::f32::consts::PI).rem_euclid(turn)
                - std::f32::consts::PI)
                .to_degrees();
            if ui
                .add(
                    // Not clamped: dragged past ±180° it comes round.
                    egui::DragValue::new(&mut az)
                        .speed(0.5)
                        .max_decimals(1)
                        .prefix("azimuth ")
                        .suffix("°"),
                )
                .on_hover_text(format!("Where the {name} comes from, seen from the camera: 0° beside the camera, +90° from the right, −90° from the left, ±180° from behind the head."))
                .changed()
            {
                let wrapped = (az + 180.0).rem_euclid(360.0) - 180.0;
                l.azimuth_rad = yaw + wrapped.to_radians();
            }
            let mut el = l.elevation_rad.to_degrees();
            if ui
                .add(
                    egui::DragValue::new(&mut el)
                        .range(-90.0..=90.0)
                        .speed(0.5)
                        .max_decimals(1)
                        .prefix("elevation ")
                        .suffix("°"),
                )
                .on_hover_text(format!("How high the {name} is: 0° level with the head's centre, 90° straight above."))
                .changed()
            {
                l.elevation_rad = el.to_radians();
            }
        });
    });
    ui.end_row();
}

/// What lights the head besides the key, fill and rim, and the HDR map's
/// background, turn and blur.
fn environment_ui(
    ui: &mut egui::Ui,
    v: &mut state::ViewState,
    view: &WindowView,
    shipped: &[std::path::PathBuf],
    actions: &mut Vec<Action>,
) {
    ui.horizontal_wrapped(|ui| {
        ui.label("Environment");
        ui.selectable_value(&mut v.environment, EnvironmentChoice::Studio, "studio sky")
            .on_hover_text("The procedural studio sky.");
        ui.selectable_value(&mut v.environment, EnvironmentChoice::Black, "black")
            .on_hover_text("No environment light: the rig's lights alone.");
        if v.environment_map_sh.is_some() {
            let name = view
                .environment_file
                .and_then(|p| p.file_name())
                .map_or("HDR map".into(), |n| n.to_string_lossy().into_owned());
            let tip = view.environment_file.map_or("The last HDR map loaded.".into(), |p| {
                format!("{} (its irradiance, as order-2 spherical harmonics)", p.display())
            });
            ui.selectable_value(&mut v.environment, EnvironmentChoice::Map, name)
                .on_hover_text(tip);
        }
        if ui
            .button("HDR map…")
            .on_hover_text("Light the head with an equirectangular Radiance .hdr map (or drop one onto the window).")
            .clicked()
        {
            actions.push(Action::ChooseEnvironmentFile);
        }
    });
    ui.horizontal_wrapped(|ui| {
        ui.label("Shipped maps");
        for path in shipped {
            let name = path
                .file_stem()
                .map(|n| n.to_string_lossy().replace('_', " "))
                .unwrap_or_default();
            if ui
                .button(name)
                .on_hover_text(format!(
                    "{} (CC0, made by tools/make_hdri.py)",
                    path.display()
                ))
                .clicked()
            {
                actions.push(Action::LoadEnvironment(path.clone()));
            }
        }
    });
    ui.add_enabled_ui(v.environment == EnvironmentChoice::Map, |ui| {
        ui.checkbox(&mut v.background.show, "show behind the head")
            .on_hover_text("Draw the HDR map as the viewport's background (exposed and tone mapped as the head is).");
        ui.horizontal(|ui| {
            ui.add(
                egui::DragValue::new(&mut v.background.turn_deg)
                    .range(-180.0..=180.0)
                    .speed(0.5)
                    .max_decimals(1)
                    .prefix("turn ")
                    .suffix("°"),
            )
            .on_hover_text("Turn the map about the vertical axis: the background and the head's lighting turn together. Drag, or click and type.");
            ui.add(
                egui::DragValue::new(&mut v.background.blur)
                    .range(0.0..=1.0)
                    .speed(0.005)
                    .max_decimals(3)
                    .prefix("blur "),
            )
            .on_hover_text("0: the map sharp; 1: its coarsest level, a soft wash of its colours. Drag, or click and type.");
        });
    })
    .response
    .on_disabled_hover_text("With an HDR map as the environment.");
}
