//! Where the mesh sits and how the camera and light orbit it: the view,
//! projection and light transforms every pass and the ground truth share.

use super::settings::{CameraRecord, RenderSettings};
use glam::{Mat4, Vec3};

/// The mesh's placement: what the camera and light orbit, and the scale
/// from its units to metres.
pub(super) struct Framing {
    /// The point the camera orbits (world units; [`super::Mesh::focus`]).
    pub centre: Vec3,
    /// Bounding-sphere radius (world units).
    pub radius: f32,
    pub metres_per_unit: f32,
    /// The eyeballs ([`super::Mesh::eyeballs`]).
    pub eyes: [[f32; 4]; 2],
}

/// A point light: position, distance from the centre, shadow near and far
/// planes (world units).
pub(super) struct PointLight {
    pub position: Vec3,
    pub distance: f32,
    pub near: f32,
    pub far: f32,
}

/// The camera and light of one frame.
pub(super) struct CameraLight {
    pub eye: Vec3,
    /// The point the camera looks at (world units).
    pub target: Vec3,
    pub view: Mat4,
    pub projection: Mat4,
    /// Towards a directional light (unit).
    pub light: Vec3,
    /// The shadow map's clip transform.
    pub light_clip: Mat4,
}

impl Framing {
    /// The camera (eye, view, projection) and the light's direction and
    /// clip transform around the mesh's bounding sphere.
    pub fn camera_and_light(&self, s: &RenderSettings) -> CameraLight {
        let aspect = s.width as f32 / s.height as f32;
        let v = &s.view;
        let dist = v.camera_distance_m / self.metres_per_unit;
        let dir = orbit_direction(v.camera_yaw_rad, v.camera_pitch_rad);
        let right = Vec3::Y.cross(dir).normalize_or_zero();
        let up = dir.cross(right);
        let target = self.centre
            + (right * v.camera_pan_m[0] + up * v.camera_pan_m[1]) / self.metres_per_unit;
        let eye = target + dist * dir;
        let view = Mat4::look_at_rh(eye, target, Vec3::Y);
        let projection = Mat4::perspective_rh(v.fov_y_rad, aspect, 0.05 * dist, 10.0 * dist);
        let light = orbit_direction(v.light_azimuth_rad, v.light_elevation_rad);
        let rad = self.radius;
        let up = if light.y.abs() > 0.99 {
            Vec3::Z
        } else {
            Vec3::Y
        };
        let light_clip = match self.point_light(s) {
            // A perspective map from the light, just wide enough for the
            // bounding sphere.
            Some(p) => {
                let half = (rad / p.distance).clamp(1e-4, 0.99).asin() * 1.05;
                Mat4::perspective_rh(2.0 * half, 1.0, p.near, p.far)
                    * Mat4::look_at_rh(p.position, self.centre, up)
            }
            None => {
                let light_view = Mat4::look_at_rh(self.centre + light * 2.0 * rad, self.centre, up);
                Mat4::orthographic_rh(-rad, rad, -rad, rad, 0.01 * rad, 4.0 * rad) * light_view
            }
        };
        CameraLight {
            eye,
            target,
            view,
            projection,
            light,
            light_clip,
        }
    }

    /// The point light, or `None` for a directional light.
    pub fn point_light(&self, s: &RenderSettings) -> Option<PointLight> {
        let metres = s.view.point_light_distance_m?;
        let rad = self.radius;
        // At least just outside the bounding sphere.
        let distance = (metres / self.metres_per_unit).max(1.05 * rad);
        let dir = orbit_direction(s.view.light_azimuth_rad, s.view.light_elevation_rad);
        Some(PointLight {
            position: self.centre + dir * distance,
            distance,
            near: (distance - rad).max(0.01 * rad),
            far: distance + rad,
        })
    }

    /// The frame's camera and key light in metres, for another renderer
    /// to set up the same shot ([`CameraRecord`]).
    pub fn record(&self, camera: &CameraLight, s: &RenderSettings) -> CameraRecord {
        let m = |p: Vec3| (p * self.metres_per_unit).to_array();
        let v = &s.view;
        CameraRecord {
            eye_m: m(camera.eye),
            target_m: m(camera.target),
            up: [0.0, 1.0, 0.0],
            fov_y_deg: v.fov_y_rad.to_degrees(),
            width: s.width,
            height: s.height,
            toward_light: camera.light.to_array(),
            light_irradiance: v.light_colour.map(|c| c * v.light_intensity),
            point_light_m: self.point_light(s).map(|p| m(p.position)),
            metres_per_unit: self.metres_per_unit,
            unrecorded: [
                ("fill light", v.fill.intensity > 0.0),
                ("rim light", v.rim.intensity > 0.0),
                (
                    "environment",
                    s.environment_sh.iter().flatten().any(|c| *c != 0.0),
                ),
                ("specular", s.specular_f0 > 0.0),
                (
                    "transmission",
                    s.transmission != super::settings::Transmission::Off,
                ),
            ]
            .into_iter()
            .filter_map(|(name, on)| on.then_some(name))
            .collect(),
        }
    }

    /// Pixels per world unit at the orbit's centre.
    pub fn pixels_per_unit(&self, s: &RenderSettings) -> f32 {
        let dist = s.view.camera_distance_m / self.metres_per_unit;
        s.height as f32 / (2.0 * (0.5 * s.view.fov_y_rad).tan() * dist)
    }
}

/// Unit vector for an azimuth about +y (0 = +z) and an elevation (radians).
pub(super) fn orbit_direction(azimuth: f32, elevation: f32) -> Vec3 {
    Vec3::new(
        azimuth.sin() * elevation.cos(),
        elevation.sin(),
        azimuth.cos() * elevation.cos(),
    )
}
