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
    /// The key light's colour (linear RGB, multiplies its intensity;
    /// white in a view saved before lights had colours).
    pub light_colour: [f32; 3],
    /// The fill and rim lights beside the key (off in a view saved before
    /// there were any, and in every rig but the three-point one).
    pub fill: RigLight,
    pub rim: RigLight,
}

/// A light of the rig beside the key: directional and unshadowed (the one
/// shadow map is the key's, as a studio's soft fill casts none worth
/// seeing), lighting the surface and its highlights but not coming through
/// thin parts in the real-time methods (their transmission is the key's;
/// the ground truth, which integrates light on every surface cell, takes
/// it through the backs of ears too). Each adds to the key's light
/// (the renderer is linear in its lights:
/// `tests/render_physics.rs::rig_lights_add_and_follow_lambert`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct RigLight {
    /// Direction towards the light, as the key's: azimuth about +y (0 =
    /// +z) and elevation.
    pub azimuth_rad: f32,
    pub elevation_rad: f32,
    /// Irradiance at normal incidence; 0 = off.
    pub intensity: f32,
    /// Linear RGB, multiplies the intensity.
    pub colour: [f32; 3],
}

impl Default for RigLight {
    fn default() -> Self {
        Self {
            azimuth_rad: 0.0,
            elevation_rad: 0.0,
            intensity: 0.0,
            colour: [1.0; 3],
        }
    }
}

impl OrbitView {
    /// The view with its lights as the renderer can use them: a fill or
    /// rim whose intensity or direction is not a finite number (or is
    /// negative) is off, and a colour with a channel that is not a finite
    /// number ≥ 0 is white (a hand-edited or damaged state file would draw
    /// NaN). The editor's remembered view goes through it on load.
    pub fn with_usable_lights(mut self) -> Self {
        let usable = |c: [f32; 3]| {
            if c.iter().all(|v| v.is_finite() && *v >= 0.0) {
                c
            } else {
                [1.0; 3]
            }
        };
        self.light_colour = usable(self.light_colour);
        for l in [&mut self.fill, &mut self.rim] {
            let finite = [l.intensity, l.azimuth_rad, l.elevation_rad]
                .iter()
                .all(|v| v.is_finite());
            if !finite || l.intensity < 0.0 {
                *l = RigLight::default();
            }
            l.colour = usable(l.colour);
        }
        self
    }
}

impl RigLight {
    /// Unit direction towards the light (world, the orbit's axes).
    pub fn direction(&self) -> [f32; 3] {
        orbit(self.azimuth_rad, self.elevation_rad)
    }

    /// Irradiance at normal incidence per channel (intensity × colour).
    pub fn radiance(&self) -> [f32; 3] {
        self.colour.map(|c| c * self.intensity)
    }
}

impl OrbitView {
    /// The direction towards the light in the camera's frame: x right, y
    /// up, z towards the viewer (unit). The frame is the renderer's
    /// (`render::framing`: the eye along the orbit direction of yaw and
    /// pitch, right = +y × that direction, up = direction × right); the
    /// light's direction is the same orbit formula at its azimuth and
    /// elevation. Tested by `light_in_view_follows_the_camera`.
    pub fn light_in_view(&self) -> [f32; 3] {
        let (dir, right, up) = self.camera_frame();
        let light = orbit(self.light_azimuth_rad, self.light_elevation_rad);
        [dot(light, right), dot(light, up), dot(light, dir)]
    }

    /// The camera's frame (unit vectors): towards the eye from the
    /// target, right and up, as `render::framing` makes it.
    fn camera_frame(&self) -> ([f32; 3], [f32; 3], [f32; 3]) {
        let cross = |a: [f32; 3], b: [f32; 3]| {
            [
                a[1] * b[2] - a[2] * b[1],
                a[2] * b[0] - a[0] * b[2],
                a[0] * b[1] - a[1] * b[0],
            ]
        };
        let dir = orbit(self.camera_yaw_rad, self.camera_pitch_rad);
        let r = cross([0.0, 1.0, 0.0], dir);
        let n = dot(r, r).sqrt().max(1e-12);
        let right = r.map(|x| x / n);
        (dir, right, cross(dir, right))
    }

    /// This view moved to frame a mesh whole, from where the camera is (as
    /// Blender's View Selected does): the target on the centre of a sphere
    /// that holds the mesh (`centre_m` from the focus, `radius_m`), the
    /// camera just far enough for the sphere's outline to fit the
    /// narrower field of view of a viewport `aspect` wide (width / height),
    /// with [`FRAMING_ROOM`] to spare. The outline of a sphere of radius r
    /// seen from d is a cone of half angle asin(r / d), so d = r / sin(half
    /// angle). Direction, light and field of view are kept. Tested by
    /// `framing_whole_fits_a_sphere`.
    pub fn framing_whole(&self, centre_m: [f32; 3], radius_m: f32, aspect: f32) -> OrbitView {
        let (dir, right, up) = self.camera_frame();
        let half_y = 0.5 * self.fov_y_rad;
        let half_x = (aspect.max(1e-3) * half_y.tan()).atan();
        let half = half_y.min(half_x);
        OrbitView {
            camera_pan_m: [dot(centre_m, right), dot(centre_m, up)],
            // The sphere's centre lies off the target plane by c·dir.
            camera_distance_m: FRAMING_ROOM * radius_m.max(1e-4) / half.sin() + dot(centre_m, dir),
            ..*self
        }
    }
}

impl OrbitView {
    /// About how much of the framed mesh this view shows, 0–1, for a mesh
    /// that `framing_distance_m` frames whole: the view is a square window
    /// (half-width d·tan(fov/2), in the framing view's units of
    /// framing·tan(fov/2)) moved by the pan; the mesh fills the framing
    /// view's window; the fraction is the overlap's area over the mesh's.
    /// A start-up check (`EditorApp`: a remembered view under 0.2 is reset)
    /// and tested by `visible_fraction_of_views`.
    pub fn visible_fraction(&self, framing_distance_m: f32) -> f32 {
        let framing = framing_distance_m.max(1e-6);
        // The framing distance is worked out at the default field of view
        // (the render thread's `framing_distance_m`), whatever this view's.
        let half_mesh = framing * (0.5 * OrbitView::default().fov_y_rad).tan();
        let half_view = self.camera_distance_m.max(0.0) * (0.5 * self.fov_y_rad).tan();
        let overlap = |pan: f32| {
            let lo = (pan - half_view).max(-half_mesh);
            let hi = (pan + half_view).min(half_mesh);
            ((hi - lo) / (2.0 * half_mesh)).clamp(0.0, 1.0)
        };
        overlap(self.camera_pan_m[0]) * overlap(self.camera_pan_m[1])
    }
}

/// The height of the 35 mm full frame (36 × 24 mm) that the focal length
/// is given for: the field of view is vertical, so the lens is the one a
/// full-frame camera held in landscape would need for the same vertical
/// view (Blender's camera with Sensor Fit Vertical and a 24 mm sensor).
pub const FULL_FRAME_HEIGHT_MM: f32 = 24.0;

impl OrbitView {
    /// The focal length (mm) of the full-frame lens with this vertical
    /// field of view: a pinhole's f = (h / 2) / tan(fov / 2), h =
    /// [`FULL_FRAME_HEIGHT_MM`]. Tested by `focal_length_of_known_lenses`.
    pub fn focal_length_mm(&self) -> f32 {
        0.5 * FULL_FRAME_HEIGHT_MM / (0.5 * self.fov_y_rad).tan()
    }

    /// Sets the vertical field of view to that of a full-frame lens of
    /// `mm` (the inverse of [`OrbitView::focal_length_mm`]); the camera
    /// stays where it is, so a longer lens zooms in.
    pub fn set_focal_length_mm(&mut self, mm: f32) {
        self.fov_y_rad = 2.0 * (0.5 * FULL_FRAME_HEIGHT_MM / mm.max(1.0)).atan();
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
            light_colour: [1.0; 3],
            fill: RigLight::default(),
            rim: RigLight::default(),
        }
    }
}

/// How much farther than a tight fit [`OrbitView::framing_whole`] puts the
/// camera: the outline then spans about 1 / 1.08 = 93 % of the narrower
/// side, a margin as the DCC tools' "frame selected" leave.
pub const FRAMING_ROOM: f32 = 1.08;

/// The unit direction of an orbit's azimuth (about +y, 0 = +z) and
/// elevation.
fn orbit(az: f32, el: f32) -> [f32; 3] {
    [az.sin() * el.cos(), el.sin(), az.cos() * el.cos()]
}

fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
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

#[cfg(test)]
mod rig_tests {
    use super::{OrbitView, RigLight};

    /// A damaged state file's rig (NaN and negative numbers) is made
    /// usable: the fill and rim off and white colours, not NaN light;
    /// good lights are kept.
    #[test]
    fn damaged_rig_lights_are_turned_off() {
        let text = "(light_colour: (NaN, 1.0, 1.0), fill: (intensity: NaN), rim: (intensity: -2.0, colour: (0.5, -1.0, 0.5)))";
        let v = ron::from_str::<OrbitView>(text)
            .unwrap()
            .with_usable_lights();
        assert_eq!(v.light_colour, [1.0; 3]);
        assert_eq!(v.fill, RigLight::default());
        assert_eq!(v.rim, RigLight::default());
        let good = "(fill: (intensity: 0.5, azimuth_rad: 1.0, colour: (0.2, 0.3, 0.4)))";
        let v = ron::from_str::<OrbitView>(good)
            .unwrap()
            .with_usable_lights();
        assert_eq!((v.fill.intensity, v.fill.colour), (0.5, [0.2, 0.3, 0.4]));
    }

    /// A view saved before lights had colours (issue 52's rig) loads with
    /// a white key and the fill and rim off: its look is unchanged.
    #[test]
    fn a_view_saved_before_the_rig_loads_with_it_off() {
        let old = "(camera_yaw_rad: 0.5, light_intensity: 2.0, exposure: 1.5)";
        let v: OrbitView = ron::from_str(old).unwrap();
        assert_eq!(v.light_colour, [1.0; 3]);
        assert_eq!(v.fill.intensity, 0.0);
        assert_eq!(v.rim.intensity, 0.0);
        assert_eq!((v.camera_yaw_rad, v.light_intensity), (0.5, 2.0));
        // A fill saved with its intensity alone is white.
        let f: RigLight = ron::from_str("(intensity: 0.7)").unwrap();
        assert_eq!(f.radiance(), [0.7; 3]);
    }
}

#[cfg(test)]
mod framing_tests {
    use super::OrbitView;

    /// Framed: all of it; farther: still all; at 0.3 of the framing
    /// distance about 0.3² = 9 % (the view's side is 0.3 of the mesh's);
    /// panned a whole framing window away: none.
    #[test]
    fn visible_fraction_of_views() {
        let framing = 0.55;
        let at = |d: f32, pan: [f32; 2]| {
            OrbitView {
                camera_distance_m: d,
                camera_pan_m: pan,
                ..OrbitView::default()
            }
            .visible_fraction(framing)
        };
        assert!((at(framing, [0.0; 2]) - 1.0).abs() < 1e-6);
        assert!((at(2.0 * framing, [0.0; 2]) - 1.0).abs() < 1e-6);
        assert!((at(0.3 * framing, [0.0; 2]) - 0.09).abs() < 1e-4);
        let window = 2.0 * framing * (0.5 * OrbitView::default().fov_y_rad).tan();
        assert_eq!(at(framing, [window, 0.0]), 0.0);
        // Half a window across: half of it.
        assert!((at(framing, [0.5 * window, 0.0]) - 0.5).abs() < 1e-4);
    }
}

#[cfg(test)]
mod framing_whole_tests {
    use super::OrbitView;
    use glam::{Mat4, Vec3};

    /// Judged by glam's camera (the renderer's: `look_at_rh` from the eye
    /// along the orbit, `perspective_rh`): every point of the sphere lands
    /// inside the viewport and the outline touches its narrower edges, for
    /// a portrait and a landscape viewport, an off-centre sphere and an
    /// orbit from above.
    #[test]
    fn framing_whole_fits_a_sphere() {
        for (aspect, yaw, pitch, centre) in [
            (0.8f32, 0.35f32, 0.05f32, [0.0f32, -0.02, 0.0]),
            (1.6, -1.0, 0.6, [0.03, 0.05, -0.04]),
        ] {
            let radius = 0.09;
            let v = OrbitView {
                camera_yaw_rad: yaw,
                camera_pitch_rad: pitch,
                camera_pan_m: [0.2, -0.1],
                camera_distance_m: 0.05,
                ..OrbitView::default()
            }
            .framing_whole(centre, radius, aspect);
            let (dir, right, up) = v.camera_frame();
            let (dir, right, up) = (Vec3::from(dir), Vec3::from(right), Vec3::from(up));
            let target = right * v.camera_pan_m[0] + up * v.camera_pan_m[1];
            let eye = target + dir * v.camera_distance_m;
            let clip = Mat4::perspective_rh(v.fov_y_rad, aspect, 0.01, 100.0)
                * Mat4::look_at_rh(eye, target, Vec3::Y);
            let mut widest = [0.0f32; 2];
            for i in 0..64 {
                for j in 0..=32 {
                    let (a, b) = (
                        i as f32 / 64.0 * std::f32::consts::TAU,
                        j as f32 / 32.0 * std::f32::consts::PI,
                    );
                    let p = Vec3::from(centre)
                        + radius * Vec3::new(b.sin() * a.cos(), b.cos(), b.sin() * a.sin());
                    let ndc = clip.project_point3(p);
                    widest = [widest[0].max(ndc.x.abs()), widest[1].max(ndc.y.abs())];
                }
            }
            let narrow = if aspect < 1.0 { widest[0] } else { widest[1] };
            assert!(
                widest[0] <= 1.0 + 1e-3 && widest[1] <= 1.0 + 1e-3,
                "{widest:?}"
            );
            // sin(a) / 1.08 against sin(a) for the outline: 0.90–0.93 of
            // the narrower half-side.
            assert!(
                narrow > 0.88 && narrow < 0.95,
                "the outline should nearly touch the narrower edges: {widest:?}"
            );
        }
    }
}

#[cfg(test)]
mod focal_length_tests {
    use super::OrbitView;

    /// Published fields of view of full-frame lenses (vertical, 24 mm):
    /// 50 mm sees 27.0°, 24 mm 53.1°, 85 mm 16.1°, 200 mm 6.9° (e.g. Nikon's
    /// and Canon's lens tables, which give the diagonal 46.8°, 84°, 28.5°,
    /// 12.3°; the vertical figures are 2·atan(12/f), checked here against
    /// the diagonal ones through the 36 × 24 mm frame's 43.27 mm diagonal).
    #[test]
    fn focal_length_of_known_lenses() {
        for (mm, vertical_deg, diagonal_deg) in [
            (50.0f32, 27.0f32, 46.8f32),
            (24.0, 53.1, 84.0),
            (85.0, 16.1, 28.5),
            (200.0, 6.9, 12.3),
        ] {
            let mut v = OrbitView::default();
            v.set_focal_length_mm(mm);
            assert!(
                (v.fov_y_rad.to_degrees() - vertical_deg).abs() < 0.06,
                "{mm} mm: {}°",
                v.fov_y_rad.to_degrees()
            );
            // The same lens's diagonal view, from the same vertical one.
            let half_diag = (0.5 * v.fov_y_rad).tan() * (36.0f32.hypot(24.0) / 24.0);
            let diag = 2.0 * half_diag.atan().to_degrees();
            assert!(
                (diag - diagonal_deg).abs() < 0.15,
                "{mm} mm: {diag}° diagonal"
            );
            assert!((v.focal_length_mm() - mm).abs() < 1e-3);
        }
        // The default 30° view is a 44.8 mm lens.
        assert!((OrbitView::default().focal_length_mm() - 44.78).abs() < 0.01);
    }
}
