//! Where the camera and the light are: one orbit around the mesh's centre,
//! shared by the editor (its remembered view), the renderer
//! ([`crate::render::RenderSettings::view`]) and the command line (which
//! takes degrees and converts at its edge, `cli::view`). Angles are
//! radians and named `*_rad`; lengths are metres.

use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct OrbitView {
    /// The camera's orbit about +y (0: in front of the face, +z).
    pub camera_yaw_rad: f32,
    /// The camera's elevation.
    pub camera_pitch_rad: f32,
    /// From the orbit's centre.
    pub camera_distance_m: f32,
    /// The orbit's target moved in the view plane (right, up).
    pub camera_pan_m: [f32; 2],
    /// Vertical field of view.
    pub fov_y_rad: f32,
    /// Direction towards the light: azimuth about +y (0 = +z) and
    /// elevation; a point light sits in that direction from the centre.
    pub light_azimuth_rad: f32,
    pub light_elevation_rad: f32,
    /// Irradiance at normal incidence (a point light's at its distance).
    pub light_intensity: f32,
    /// `None`: a directional light; else a point light this far from the
    /// centre, falling off with the inverse square.
    pub point_light_distance_m: Option<f32>,
    /// Multiplier before tonemapping.
    pub exposure: f32,
}

impl Default for OrbitView {
    fn default() -> Self {
        Self {
            camera_yaw_rad: 0.35,
            camera_pitch_rad: 0.05,
            camera_distance_m: 0.55,
            camera_pan_m: [0.0; 2],
            fov_y_rad: 30f32.to_radians(),
            light_azimuth_rad: 1.25,
            light_elevation_rad: 0.35,
            light_intensity: 3.2,
            point_light_distance_m: None,
            exposure: 1.0,
        }
    }
}
