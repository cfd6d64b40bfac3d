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

impl OrbitView {
    /// The direction towards the light in the camera's frame: x right, y
    /// up, z towards the viewer (unit). The frame is the renderer's
    /// (`render::framing`: the eye along the orbit direction of yaw and
    /// pitch, right = +y × that direction, up = direction × right); the
    /// light's direction is the same orbit formula at its azimuth and
    /// elevation. Tested by `light_in_view_follows_the_camera`.
    pub fn light_in_view(&self) -> [f32; 3] {
        let orbit = |az: f32, el: f32| [az.sin() * el.cos(), el.sin(), az.cos() * el.cos()];
        let cross = |a: [f32; 3], b: [f32; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let dot = |a: [f32; 3], b: [f32; 3]| a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
        let dir = orbit(self.camera_yaw_rad, self.camera_pitch_rad);
        let r = cross([0.0, 1.0, 0.0], dir);
        let n = dot(r, r).sqrt().max(1e-12);
        let right = r.map(|x| x / n);
        let up = cross(dir, right);
        let light = orbit(self.light_azimuth_rad, self.light_elevation_rad);
        [dot(light, right), dot(light, up), dot(light, dir)]
    }
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

#[cfg(test)]
mod light_tests {
    use super::OrbitView;

    /// A light where the camera is points at the viewer; 90° more azimuth
    /// puts it on the viewer's right (the camera at yaw 0 looks down −z
    /// with +x to its right, as `Mat4::look_at_rh` makes it); straight up
    /// is up on screen for a level camera, whatever the yaw.
    #[test]
    fn light_in_view_follows_the_camera() {
        let close = |a: [f32; 3], b: [f32; 3]| a.iter().zip(b).all(|(x, y)| (x - y).abs() < 1e-5);
        for yaw in [0.0f32, 0.35, 2.0, -1.0] {
            let mut v = OrbitView {
                camera_yaw_rad: yaw,
                camera_pitch_rad: 0.0,
                light_azimuth_rad: yaw,
                light_elevation_rad: 0.0,
                ..OrbitView::default()
            };
            assert!(close(v.light_in_view(), [0.0, 0.0, 1.0]), "{yaw}");
            v.light_azimuth_rad = yaw + std::f32::consts::FRAC_PI_2;
            assert!(close(v.light_in_view(), [1.0, 0.0, 0.0]), "{yaw}");
            v.light_elevation_rad = std::f32::consts::FRAC_PI_2;
            assert!(close(v.light_in_view(), [0.0, 1.0, 0.0]), "{yaw}");
        }
    }
}
