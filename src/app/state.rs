//! The document being edited (a preset and its file), its undo history,
//! and the UI state remembered between runs. No egui here.

pub use crate::settings::albedo::MaterialAlbedo;
use crate::settings::Preset;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

mod document;
pub use document::{Document, History, HISTORY_BYTES, HISTORY_LIMIT};

/// Recent files listed.
pub const RECENT_LIMIT: usize = 10;
/// The difference view's default white: 5 ΔL*, a few just-noticeable
/// differences (about 0.05 of display luminance at mid grey, the scale
/// the editor used in ΔY).
pub const DEFAULT_DIFFERENCE_SCALE: f32 = 5.0;

/// Which environment lights the head.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum EnvironmentChoice {
    /// The procedural studio sky.
    #[default]
    Studio,
    /// No environment: the lights alone.
    Black,
    /// An equirectangular HDR map loaded by the user
    /// ([`ViewState::environment_map_sh`]).
    Map,
}

/// One-click lighting set-ups that show what scattering does: the key
/// light's direction relative to the camera (so a rig lights what is in
/// view, wherever the orbit is) and the environment. The side light puts
/// the terminator down the middle of the face, where scattering softens it
/// most; the back light comes through the ear from behind (the bench's
/// back-lit ear: 135° from the camera, 10° up); the three-point rig is the
/// portrait photographer's warm key, cool fill and rim (the fill and rim
/// are off in every other rig).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LightRig {
    Front,
    ThreeQuarter,
    Side,
    Back,
    Rim,
    ThreePoint,
    Hdr,
}

/// A rig's lights: each direction as (azimuth from the camera's,
/// elevation) in degrees, with its intensity and colour.
struct RigSetUp {
    key: (f32, f32, f32, [f32; 3]),
    fill: (f32, f32, f32, [f32; 3]),
    rim: (f32, f32, f32, [f32; 3]),
    environment: EnvironmentChoice,
}

/// The three-point rig's colours (linear RGB): a key a little warm (as a
/// tungsten-balanced key reads under a daylight-balanced camera), a cool
/// fill (sky light from the shadow side) and a white rim.
pub const THREE_POINT_KEY_COLOUR: [f32; 3] = [1.0, 0.93, 0.84];
pub const THREE_POINT_FILL_COLOUR: [f32; 3] = [0.78, 0.88, 1.0];

impl LightRig {
    pub const ALL: [LightRig; 7] = [
        LightRig::Front,
        LightRig::ThreeQuarter,
        LightRig::Side,
        LightRig::Back,
        LightRig::Rim,
        LightRig::ThreePoint,
        LightRig::Hdr,
    ];

    pub fn label(self) -> &'static str {
        match self {
            LightRig::Front => "front",
            LightRig::ThreeQuarter => "three-quarter",
            LightRig::Side => "side",
            LightRig::Back => "back, through the ear",
            LightRig::Rim => "rim",
            LightRig::ThreePoint => "three-point",
            LightRig::Hdr => "HDR map",
        }
    }

    pub fn tip(self) -> &'static str {
        match self {
            LightRig::Front => "Key light beside the camera, 20° up, studio sky: flat, as engines' previews light it; scattering shows least.",
            LightRig::ThreeQuarter => "Key light 45° to the camera's right, 25° up, studio sky: the classic portrait light.",
            LightRig::Side => "Key light 90° to the right, 10° up, no environment: the terminator runs down the face, where scattering's softening and colour show most.",
            LightRig::Back => "Key light behind the head, 135° from the camera and 10° up, no environment: light through the ear shows transmission.",
            LightRig::Rim => "Key light almost behind, 170° from the camera and 20° up, no environment: a rim on the outline and thin parts.",
            LightRig::ThreePoint => "Key, fill and rim, no environment: a warm key 45° to the right and 25° up; a cool fill a third as bright, 60° to the left and 10° up; a white rim behind on the left, 150° from the camera and 30° up. Each light's colour and strength are set below.",
            LightRig::Hdr => "The loaded HDR map alone (key light off); asks for a map if none is loaded.",
        }
    }

    fn set_up(self) -> RigSetUp {
        let key = crate::settings::OrbitView::default().light_intensity;
        let white = [1.0; 3];
        let off = (0.0, 0.0, 0.0, white);
        let lone = |az: f32, el: f32, env| RigSetUp {
            key: (az, el, key, white),
            fill: off,
            rim: off,
            environment: env,
        };
        match self {
            LightRig::Front => lone(0.0, 20.0, EnvironmentChoice::Studio),
            LightRig::ThreeQuarter => lone(45.0, 25.0, EnvironmentChoice::Studio),
            LightRig::Side => lone(90.0, 10.0, EnvironmentChoice::Black),
            LightRig::Back => lone(135.0, 10.0, EnvironmentChoice::Black),
            LightRig::Rim => lone(170.0, 20.0, EnvironmentChoice::Black),
            LightRig::ThreePoint => RigSetUp {
                key: (45.0, 25.0, key, THREE_POINT_KEY_COLOUR),
                fill: (-60.0, 10.0, key / 3.0, THREE_POINT_FILL_COLOUR),
                rim: (-150.0, 30.0, key, white),
                environment: EnvironmentChoice::Black,
            },
            LightRig::Hdr => RigSetUp {
                key: (45.0, 25.0, 0.0, white),
                ..lone(0.0, 0.0, EnvironmentChoice::Map)
            },
        }
    }

    /// Puts the rig's lights into `view`. Returns false for the HDR rig
    /// when no map is loaded (nothing changed: the caller asks for one).
    pub fn apply(self, view: &mut ViewState) -> bool {
        let r = self.set_up();
        if r.environment == EnvironmentChoice::Map && view.environment_map_sh.is_none() {
            return false;
        }
        let o = &mut view.orbit;
        let yaw = o.camera_yaw_rad;
        let (az, el, intensity, colour) = r.key;
        o.light_azimuth_rad = yaw + az.to_radians();
        o.light_elevation_rad = el.to_radians();
        o.light_intensity = intensity;
        o.light_colour = colour;
        let rig_light =
            |(az, el, intensity, colour): (f32, f32, f32, [f32; 3])| crate::settings::RigLight {
                azimuth_rad: yaw + f32::to_radians(az),
                elevation_rad: f32::to_radians(el),
                intensity,
                colour,
            };
        o.fill = rig_light(r.fill);
        o.rim = rig_light(r.rim);
        view.environment = r.environment;
        true
    }

    /// The rig `view` is lit by now, if any (a light dragged or edited or
    /// the environment changed since: none).
    pub fn current(view: &ViewState) -> Option<LightRig> {
        let o = &view.orbit;
        let turn = std::f32::consts::TAU;
        let same_azimuth = |rad: f32, deg: f32| {
            let d = (rad - o.camera_yaw_rad - deg.to_radians()).rem_euclid(turn);
            d < 1e-3 || turn - d < 1e-3
        };
        // Within what the fields show (the fill's third of the key is
        // 1.067 once its field has been clicked into and left: egui writes
        // the text it shows back).
        let near = |a: f32, b: f32| (a - b).abs() <= 1e-3 * b.abs().max(1.0);
        let same = |az_rad: f32,
                    el_rad: f32,
                    i: f32,
                    c: [f32; 3],
                    (az, el, intensity, colour): (f32, f32, f32, [f32; 3])| {
            // An unlit light's direction does not matter.
            near(i, intensity)
                && (i == 0.0
                    || (same_azimuth(az_rad, az)
                        && (el_rad - f32::to_radians(el)).abs() < 1e-3
                        && (0..3).all(|k| near(c[k], colour[k]))))
        };
        LightRig::ALL.into_iter().find(|r| {
            let r = r.set_up();
            same(
                o.light_azimuth_rad,
                o.light_elevation_rad,
                o.light_intensity,
                o.light_colour,
                r.key,
            ) && same(
                o.fill.azimuth_rad,
                o.fill.elevation_rad,
                o.fill.intensity,
                o.fill.colour,
                r.fill,
            ) && same(
                o.rim.azimuth_rad,
                o.rim.elevation_rad,
                o.rim.intensity,
                o.rim.colour,
                r.rim,
            ) && view.environment == r.environment
        })
    }
}

/// How the viewport shows A and B.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum CompareMode {
    #[default]
    Off,
    Split,
    SideBySide,
    Difference,
}

/// What B is.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum CompareB {
    /// The same profile with another method.
    Method(crate::settings::rendering::MethodId),
    /// Another preset file with its own method.
    Preset(PathBuf),
}

impl Default for CompareB {
    fn default() -> Self {
        CompareB::Method(crate::render::Method::compare_partner())
    }
}

/// Camera and light, as the viewport's mouse controls change them.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(from = "StoredViewState")]
pub struct ViewState {
    /// Camera, the lights (key, fill, rim) and exposure (radians and
    /// metres), as the renderer and the command line take them.
    pub orbit: crate::settings::OrbitView,
    pub environment: EnvironmentChoice,
    /// The loaded HDR map's irradiance as order-2 SH (kept, so a restart
    /// lights the head the same way without the file).
    pub environment_map_sh: Option<[[f32; 3]; 9]>,
    pub environment_intensity: f32,
    /// The display transform after exposure.
    pub tone_map: crate::render::tonemap::ToneMap,
    /// The HDR map drawn behind the head, and its turn (the lighting
    /// turns with it).
    pub background: BackgroundView,
}

/// How the loaded HDR map is shown behind the head.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct BackgroundView {
    /// Draw the map behind the head (with the map as the environment).
    pub show: bool,
    /// 0 sharp … 1 its coarsest level.
    pub blur: f32,
    /// The map's turn about the up axis (degrees); the head's lighting
    /// turns with it.
    pub turn_deg: f32,
}

impl Default for BackgroundView {
    fn default() -> Self {
        Self {
            show: true,
            blur: 0.0,
            turn_deg: 0.0,
        }
    }
}

impl Default for ViewState {
    fn default() -> Self {
        Self {
            orbit: Default::default(),
            environment: EnvironmentChoice::Studio,
            environment_map_sh: None,
            environment_intensity: 1.0,
            tone_map: Default::default(),
            background: Default::default(),
        }
    }
}

/// A remembered [`ViewState`] as any version stored it: before the view
/// became an [`crate::settings::OrbitView`] its fields sat here flat, in
/// radians under names without `_rad` (`camera_yaw`, …, `pan_m`), and a
/// state saved then still restores its camera and light.
#[derive(Deserialize)]
#[serde(default)]
struct StoredViewState {
    orbit: crate::settings::OrbitView,
    environment: EnvironmentChoice,
    environment_map_sh: Option<[[f32; 3]; 9]>,
    environment_intensity: f32,
    tone_map: crate::render::tonemap::ToneMap,
    background: BackgroundView,
    #[serde(deserialize_with = "present")]
    camera_yaw: Option<f32>,
    #[serde(deserialize_with = "present")]
    camera_pitch: Option<f32>,
    #[serde(deserialize_with = "present")]
    camera_distance_m: Option<f32>,
    #[serde(deserialize_with = "present")]
    pan_m: Option<[f32; 2]>,
    #[serde(deserialize_with = "present")]
    light_azimuth: Option<f32>,
    #[serde(deserialize_with = "present")]
    light_elevation: Option<f32>,
    #[serde(deserialize_with = "present")]
    light_intensity: Option<f32>,
    #[serde(deserialize_with = "present")]
    exposure: Option<f32>,
}

/// A field the old format wrote as a plain value (RON would want `Some(…)`
/// for an `Option`); absent fields take the container's default, `None`.
fn present<'de, D: serde::Deserializer<'de>, T: Deserialize<'de>>(
    d: D,
) -> Result<Option<T>, D::Error> {
    T::deserialize(d).map(Some)
}

impl Default for StoredViewState {
    fn default() -> Self {
        let v = ViewState::default();
        Self {
            orbit: v.orbit,
            environment: v.environment,
            environment_map_sh: v.environment_map_sh,
            environment_intensity: v.environment_intensity,
            tone_map: v.tone_map,
            background: v.background,
            camera_yaw: None,
            camera_pitch: None,
            camera_distance_m: None,
            pan_m: None,
            light_azimuth: None,
            light_elevation: None,
            light_intensity: None,
            exposure: None,
        }
    }
}

impl From<StoredViewState> for ViewState {
    fn from(s: StoredViewState) -> Self {
        let legacy = [
            s.camera_yaw,
            s.camera_pitch,
            s.camera_distance_m,
            s.light_azimuth,
            s.light_elevation,
            s.light_intensity,
            s.exposure,
        ]
        .iter()
        .any(Option::is_some)
            || s.pan_m.is_some();
        let d = s.orbit;
        let orbit = if !legacy {
            s.orbit
        } else {
            crate::settings::OrbitView {
                camera_yaw_rad: s.camera_yaw.unwrap_or(d.camera_yaw_rad),
                camera_pitch_rad: s.camera_pitch.unwrap_or(d.camera_pitch_rad),
                camera_distance_m: s.camera_distance_m.unwrap_or(d.camera_distance_m),
                camera_pan_m: s.pan_m.unwrap_or(d.camera_pan_m),
                light_azimuth_rad: s.light_azimuth.unwrap_or(d.light_azimuth_rad),
                light_elevation_rad: s.light_elevation.unwrap_or(d.light_elevation_rad),
                light_intensity: s.light_intensity.unwrap_or(d.light_intensity),
                exposure: s.exposure.unwrap_or(d.exposure),
                ..d
            }
        };
        Self {
            orbit: orbit.with_usable_lights(),
            environment: s.environment,
            environment_map_sh: s.environment_map_sh,
            environment_intensity: s.environment_intensity,
            tone_map: s.tone_map,
            background: s.background,
        }
    }
}

/// What the plots show.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum PlotQuantity {
    /// r·R(r), the radial energy density (mm⁻¹).
    #[default]
    RTimesR,
    /// R(r) (mm⁻²).
    R,
}

/// The model fitted to the current profile for the overlay.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
pub enum OverlayModel {
    None,
    Burley,
    #[default]
    Jimenez,
    Artist,
    Gaussians4,
}

/// What the artist set for one of their meshes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct MeshSettings {
    /// Metres per unit of the file.
    pub metres_per_unit: f32,
    /// Albedo, normal, roughness, SSS mask and thickness
    /// (`render::textures::SLOTS` order).
    pub maps: [crate::render::textures::MapSlot; 5],
    /// The file is inside out: turn its faces and normals outward on
    /// load (`Mesh::turn_outward`).
    pub turn_outward: bool,
}

impl Default for MeshSettings {
    fn default() -> Self {
        Self {
            metres_per_unit: 1.0,
            maps: crate::render::textures::SLOTS.map(crate::render::textures::MapSlot::default_for),
            turn_outward: false,
        }
    }
}

/// What the artist set for turntables (remembered in `UiState`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct TurntableSettings {
    /// Frames in one turn.
    pub frames: u32,
    /// One turn's length in the GIF (s).
    pub seconds: f32,
    /// The lights (key, fill, rim) turn with the camera (the head spins
    /// under them).
    pub light_follows: bool,
    /// Also write each frame as a PNG, in `<name>_frames/`.
    pub png_sequence: bool,
    /// Also write the turn as an animated PNG (full colour, lossless),
    /// `<name>.png` beside the GIF.
    pub apng: bool,
}

impl Default for TurntableSettings {
    fn default() -> Self {
        Self {
            frames: 36,
            seconds: 4.0,
            light_follows: true,
            png_sequence: true,
            apng: true,
        }
    }
}

/// File → Save image at size's settings (remembered in `UiState`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(default)]
pub struct StillSettings {
    pub width: u32,
    pub height: u32,
    /// Rendered pixels a side per saved pixel (a k×k box filter).
    pub supersample: u32,
    /// Also write the subsurface layer (the light through the skin, no
    /// specular, the background transparent) as its own file.
    pub subsurface_file: bool,
}

impl Default for StillSettings {
    fn default() -> Self {
        Self {
            width: 2048,
            height: 2048,
            supersample: 2,
            subsurface_file: false,
        }
    }
}

/// UI state remembered between runs (eframe storage, RON).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct UiState {
    pub view: ViewState,
    pub compare: CompareMode,
    pub compare_b: CompareB,
    pub split: f32,
    pub plot_quantity: PlotQuantity,
    pub log_y: bool,
    /// The difference view's white, |ΔL*| (CIE lightness, 0–100), the same
    /// for every compare unless `difference_auto`. Stored under a new name:
    /// states before 2026-12 kept a ΔY (0–1) under `difference_scale`,
    /// which is not read as a ΔL*.
    #[serde(rename = "difference_scale_lstar")]
    pub difference_scale: f32,
    /// Scale each difference view to its own largest difference.
    pub difference_auto: bool,
    /// A log radius axis; `None`: automatic (`plots::auto_log_radius`).
    pub log_radius: Option<bool>,
    pub overlay: OverlayModel,
    pub show_taps: bool,
    pub recent: Vec<PathBuf>,
    /// The preset open when the editor was closed.
    pub last_preset: Option<PathBuf>,
    /// The HDR map behind `view.environment_map_sh`.
    pub environment_file: Option<PathBuf>,
    /// Units and map slots of each mesh the artist has loaded, by path.
    pub meshes: std::collections::BTreeMap<PathBuf, MeshSettings>,
    /// The folder each kind of file dialog was last used in ("preset",
    /// "export", "mesh", "environment", "map"): it opens there again.
    pub folders: std::collections::BTreeMap<String, PathBuf>,
    /// Go on from the method's converged frame to the ground truth.
    pub refine_to_truth: bool,
    /// File → Save turntable's settings.
    pub turntable: TurntableSettings,
    /// The material albedo a B whose engine keeps the albedo in the
    /// material is drawn with, and whether the artist has been asked.
    pub b_material_albedo: MaterialAlbedo,
    pub b_material_albedo_asked: bool,
    /// On a mesh with a colour map: the map's colour, tinted by the
    /// look's albedo, or the look's albedo alone.
    pub map_colour: crate::render::textures::MapColour,
    /// File → Save image at size's settings.
    pub still: StillSettings,
    /// Open on the shipped head scan (with its maps, units and flip) when
    /// no mesh is asked for; off: the procedural head.
    pub start_on_scan: bool,
    /// The mesh the remembered view was framed for (`Some(None)`: the
    /// procedural head; `None`: not known, states before 2026-12-06). A
    /// start on another mesh frames it rather than keep a view of this one.
    pub view_framed_for: Option<Option<std::path::PathBuf>>,
    /// The interface's scale (egui's zoom factor: 1 = 100 %).
    pub ui_scale: f32,
    /// A light interface instead of the dark one.
    pub light_theme: bool,
    /// The artist's own preset folders, listed in the preset browser
    /// after the shipped presets.
    pub preset_folders: Vec<PathBuf>,
}

/// The interface scales offered (View → Interface scale).
pub const UI_SCALE_RANGE: std::ops::RangeInclusive<f32> = 0.75..=2.0;

impl Default for UiState {
    fn default() -> Self {
        Self {
            view: ViewState::default(),
            compare: CompareMode::Off,
            compare_b: CompareB::default(),
            split: 0.5,
            plot_quantity: PlotQuantity::RTimesR,
            log_y: false,
            log_radius: None,
            difference_scale: DEFAULT_DIFFERENCE_SCALE,
            difference_auto: false,
            overlay: OverlayModel::Jimenez,
            show_taps: true,
            recent: Vec::new(),
            last_preset: None,
            environment_file: None,
            meshes: Default::default(),
            folders: Default::default(),
            refine_to_truth: false,
            turntable: Default::default(),
            b_material_albedo: MaterialAlbedo::LookA,
            b_material_albedo_asked: false,
            map_colour: Default::default(),
            still: Default::default(),
            start_on_scan: true,
            view_framed_for: None,
            ui_scale: 1.0,
            light_theme: false,
            preset_folders: Vec::new(),
        }
    }
}

impl UiState {
    pub fn add_recent(&mut self, path: &Path) {
        let path = path.to_owned();
        self.recent.retain(|p| *p != path);
        self.recent.insert(0, path);
        self.recent.truncate(RECENT_LIMIT);
    }
}

/// The environment maps shipped in assets/hdri/ (CC0), by name.
pub fn shipped_hdr_maps() -> Vec<std::path::PathBuf> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/hdri");
    let mut maps: Vec<std::path::PathBuf> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(Result::ok)
                .map(|e| e.path())
                .filter(|p| p.extension().is_some_and(|x| x == "hdr"))
                .collect()
        })
        .unwrap_or_default();
    maps.sort();
    maps
}

/// The shipped head scan and its settings (`EditorApp::open_scanned_head`).
pub fn scanned_head() -> Option<(PathBuf, MeshSettings)> {
    use crate::render::textures::MapSlot;
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scan");
    let mesh = dir.join("LeePerrySmith.glb");
    let (colour, normal) = (
        dir.join("Map-COL.jpg"),
        dir.join("Infinite-Level_02_Tangent_SmoothUV.jpg"),
    );
    if !(mesh.is_file() && colour.is_file() && normal.is_file()) {
        return None;
    }
    let mut settings = MeshSettings {
        metres_per_unit: 0.0462,
        ..Default::default()
    };
    settings.maps[0] = MapSlot {
        path: Some(colour),
        flip_v: true,
        srgb: true,
    };
    settings.maps[1] = MapSlot {
        path: Some(normal),
        flip_v: true,
        srgb: false,
    };
    Some((mesh, settings))
}

#[cfg(test)]
mod tests {

    use super::*;

    /// A view remembered before the camera and light became an OrbitView
    /// (flat fields, radians, as 1169852 wrote them) restores its camera
    /// and light; one written now round-trips.
    #[test]
    fn a_view_saved_by_an_older_version_restores() {
        let old = "(view: (camera_yaw: 1.5, camera_pitch: -0.25, camera_distance_m: 0.8, \
                   pan_m: (0.01, -0.02), light_azimuth: 2.0, light_elevation: 0.5, \
                   light_intensity: 4.0, environment: Black, environment_map_sh: None, \
                   environment_intensity: 0.5, exposure: 1.25))";
        let state: UiState = ron::from_str(old).unwrap();
        let o = state.view.orbit;
        assert_eq!(
            (o.camera_yaw_rad, o.camera_pitch_rad, o.camera_distance_m),
            (1.5, -0.25, 0.8)
        );
        assert_eq!(o.camera_pan_m, [0.01, -0.02]);
        assert_eq!(
            (
                o.light_azimuth_rad,
                o.light_elevation_rad,
                o.light_intensity
            ),
            (2.0, 0.5, 4.0)
        );
        assert_eq!(o.exposure, 1.25);
        assert_eq!(state.view.environment, EnvironmentChoice::Black);
        assert_eq!(state.view.environment_intensity, 0.5);
        assert_eq!(o.fov_y_rad, crate::settings::OrbitView::default().fov_y_rad);
        let again: UiState = ron::from_str(&ron::to_string(&state).unwrap()).unwrap();
        assert_eq!(again.view, state.view);
        let empty: UiState = ron::from_str("()").unwrap();
        assert_eq!(empty.view, ViewState::default());
    }

    fn with_name(name: &str) -> Preset {
        Preset {
            name: name.into(),
            ..Preset::default_skin()
        }
    }

    #[test]
    fn edits_between_commits_are_one_undo_step() {
        let mut d = Document::new(with_name("a"), None);
        d.preset.name = "ab".into();
        d.preset.name = "abc".into();
        d.commit();
        d.preset.name = "abcd".into();
        d.commit();
        assert!(d.is_dirty());
        d.undo();
        assert_eq!(d.preset.name, "abc");
        d.undo();
        assert_eq!(d.preset.name, "a");
        assert!(!d.is_dirty());
        assert!(!d.can_undo());
        d.redo();
        d.redo();
        assert_eq!(d.preset.name, "abcd");
        // A new edit clears redo.
        d.undo();
        d.preset.name = "x".into();
        d.commit();
        assert!(!d.can_redo());
    }

    /// Undo without an explicit commit still undoes the pending edit.
    #[test]
    fn undo_commits_a_pending_edit_first() {
        let mut d = Document::new(with_name("a"), None);
        d.preset.name = "b".into();
        assert!(d.can_undo());
        d.undo();
        assert_eq!(d.preset.name, "a");
        d.redo();
        assert_eq!(d.preset.name, "b");
    }

    /// The autosave's history (issue 36): a restored document undoes and
    /// redoes as the original did, an edit not yet committed is one more
    /// step, and a history over the budget keeps its newest steps whole.
    #[test]
    fn history_restores_undo_and_redo_within_its_budget() {
        let mut d = Document::new(with_name("a"), None);
        for n in ["b", "c", "d"] {
            d.preset.name = n.into();
            d.commit();
        }
        d.undo();
        // Uncommitted: "e" (typed, the field still focused).
        d.preset.name = "e".into();
        let h = d.history(HISTORY_BYTES);
        let names = |v: &[Preset]| v.iter().map(|p| p.name.clone()).collect::<Vec<_>>();
        // Undo: a, b, then c (where the uncommitted edit started); the
        // edit clears redo ("d") once committed, as it does here.
        assert_eq!(names(&h.undo), ["a", "b", "c"]);
        assert_eq!(names(&h.redo), ["d"]);
        assert_eq!(h.saved.as_ref().map(|p| p.name.as_str()), Some("a"));
        let mut r = Document::restored(d.preset.clone(), None, h);
        assert!(r.is_dirty());
        r.undo();
        assert_eq!(r.preset.name, "c");
        r.undo();
        r.undo();
        assert_eq!(r.preset.name, "a");
        assert!(!r.is_dirty(), "undone to the saved state");
        r.redo();
        assert_eq!(r.preset.name, "b");

        // A budget of about two presets keeps the two newest undo steps.
        let one = ron::to_string(&with_name("b")).unwrap().len();
        let h = d.history(2 * one + one / 2);
        assert_eq!(names(&h.undo), ["b", "c"]);
        assert!(h.redo.is_empty());
        let bytes: usize = h
            .undo
            .iter()
            .map(|p| ron::to_string(p).unwrap().len())
            .sum();
        assert!(bytes <= 2 * one + one / 2);
    }

    /// The revision the autosave compares moves with every change of the
    /// history or the saved state, and not with edits in between.
    #[test]
    fn the_history_revision_moves_with_the_history() {
        let mut d = Document::new(with_name("a"), None);
        let r0 = d.revision();
        d.preset.name = "b".into();
        assert_eq!(d.revision(), r0, "an edit is not yet history");
        d.commit();
        let r1 = d.revision();
        assert_ne!(r1, r0);
        d.commit();
        assert_eq!(d.revision(), r1, "a commit of nothing");
        d.undo();
        assert_ne!(d.revision(), r1);
        let r2 = d.revision();
        d.redo();
        assert_ne!(d.revision(), r2);
    }

    #[test]
    fn recent_files_are_unique_and_bounded() {
        let mut u = UiState::default();
        for i in 0..15 {
            u.add_recent(Path::new(&format!("/p/{i}.ron")));
        }
        u.add_recent(Path::new("/p/3.ron"));
        assert_eq!(u.recent.len(), RECENT_LIMIT);
        assert_eq!(u.recent[0], Path::new("/p/3.ron"));
        assert_eq!(u.recent.iter().filter(|p| p.ends_with("3.ron")).count(), 1);
    }
}
