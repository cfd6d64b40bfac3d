//! The fixed scenes and the method configurations `bench` measures.

use crate::render::{IrradiancePattern, Knob, Method, Quality, RenderSettings, Transmission};
use crate::settings::OrbitView;

/// What a scene renders.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// The default head.
    Head,
    /// Lee Perry-Smith's head scan with its colour and normal maps, as the
    /// editor opens it ([`scan_mesh`]).
    Scan,
    /// A 200 mm square plane, 1 mm per unit, facing the camera.
    Plane,
}

/// One fixed scene.
#[derive(Debug, Clone)]
pub struct Scene {
    pub id: &'static str,
    pub description: &'static str,
    pub stage: Stage,
    /// Whether the sampling target (21 vs 55 samples) is judged on it.
    pub head_shot: bool,
    pub settings: RenderSettings,
}

/// Field of view of the plane scenes and the width of plane they show.
const PLANE_SPAN_MM: f32 = 40.0;

/// Settings of a plane scene: the camera square on, `PLANE_SPAN_MM` across.
pub fn plane_settings(size: (u32, u32), pattern: IrradiancePattern) -> RenderSettings {
    let fov_y = 30f32.to_radians();
    let aspect = size.0 as f32 / size.1 as f32;
    let half_height_mm = 0.5 * PLANE_SPAN_MM / aspect;
    RenderSettings {
        width: size.0,
        height: size.1,
        view: OrbitView {
            camera_yaw_rad: 0.0,
            camera_pitch_rad: 0.0,
            camera_distance_m: half_height_mm / (0.5 * fov_y).tan() / 1000.0,
            fov_y_rad: fov_y,
            light_intensity: std::f32::consts::PI,
            ..OrbitView::default()
        },
        pattern,
        transmission: Transmission::Off,
        // Every method on the surface the ground truth integrates.
        mesh_lod: false,
        ..RenderSettings::default()
    }
}

fn head(size: (u32, u32), yaw_deg: f32, distance_m: f32, light: (f32, f32)) -> RenderSettings {
    RenderSettings {
        width: size.0,
        height: size.1,
        view: OrbitView {
            camera_yaw_rad: yaw_deg.to_radians(),
            camera_distance_m: distance_m,
            light_azimuth_rad: light.0.to_radians(),
            light_elevation_rad: light.1.to_radians(),
            ..OrbitView::default()
        },
        // Every method on the surface the ground truth integrates.
        mesh_lod: false,
        ..RenderSettings::default()
    }
}

/// The scan's scale: its glTF is in units of 0.0462 m, as the editor
/// opens it (`app::state::scanned_head`) and the yardstick's tests load it
/// (tests/common/scan.rs).
pub const SCAN_METRES_PER_UNIT: f32 = 0.0462;

/// Lee Perry-Smith's head scan (assets/scan, CC BY 3.0) with its colour
/// map drawn as the map (the editor's "the map's colour") and its
/// tangent-space normal map, both V-flipped as the scan's tool wrote them.
pub fn scan_mesh() -> anyhow::Result<crate::render::Mesh> {
    use crate::render::textures::{self, AlbedoMode, TextureSlot};
    use anyhow::Context;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scan");
    let glb = root.join("LeePerrySmith.glb");
    let mut mesh = crate::render::Mesh::load(&glb, SCAN_METRES_PER_UNIT)
        .with_context(|| format!("the bench's head scan {}", glb.display()))?;
    let maps = std::sync::Arc::make_mut(&mut mesh.textures);
    let load = |name: &str, slot| {
        let path = root.join(name);
        textures::load(&path, slot).with_context(|| format!("the scan's map {}", path.display()))
    };
    let mut albedo = load("Map-COL.jpg", TextureSlot::Albedo)?;
    albedo.flip_v();
    maps.albedo = albedo;
    maps.albedo_mode = AlbedoMode::Absolute;
    let mut normal = load(
        "Infinite-Level_02_Tangent_SmoothUV.jpg",
        TextureSlot::Normal,
    )?;
    normal.flip_v();
    maps.normal = normal;
    Ok(mesh)
}

/// The scan's camera distance: the face about as large in the frame as
/// the default head's at 0.55 m, the crown inside a 16:9 frame.
const SCAN_DISTANCE_M: f32 = 0.6;

/// The six scenes of issue 5, the thick-transmission ear and the scan's
/// front-lit and back-lit-ear shots (issue 53) at `size` pixels.
pub fn scenes(size: (u32, u32)) -> Vec<Scene> {
    vec![
        Scene {
            id: "head_front",
            description: "default head, front-left key light with the nose's hard shadow (camera yaw 20°, light azimuth 50°, elevation 25°, 0.55 m)",
            stage: Stage::Head,
            head_shot: true,
            settings: head(size, 20.0, 0.55, (50.0, 25.0)),
        },
        Scene {
            id: "head_backlit_ear",
            description: "the head back-lit through the ear, thin-object transmission (the light's path through the part from the shadow map; camera yaw 65°, light azimuth 200°, elevation 10°)",
            stage: Stage::Head,
            head_shot: true,
            settings: RenderSettings {
                transmission: Transmission::ThinObject,
                ..head(size, 65.0, 0.55, (200.0, 10.0))
            },
        },
        Scene {
            id: "head_backlit_ear_thick",
            description: "the back-lit ear of head_backlit_ear with thick-object transmission (the distance through the shadow map, unshadowed; Golubev 2018)",
            stage: Stage::Head,
            head_shot: true,
            settings: RenderSettings {
                transmission: Transmission::ThickObject,
                ..head(size, 65.0, 0.55, (200.0, 10.0))
            },
        },
        Scene {
            id: "head_closeup",
            description: "close-up of nose and cheek, side light (0.32 m, yaw 25°, light azimuth 75°, elevation 20°)",
            stage: Stage::Head,
            head_shot: true,
            settings: head(size, 25.0, 0.32, (75.0, 20.0)),
        },
        Scene {
            id: "scan_front",
            description: "Lee Perry-Smith's scan with its colour and normal maps, front-left key light (camera yaw 20°, light azimuth 50°, elevation 25°, 0.6 m)",
            stage: Stage::Scan,
            head_shot: true,
            settings: head(size, 20.0, SCAN_DISTANCE_M, (50.0, 25.0)),
        },
        Scene {
            id: "scan_backlit_ear",
            description: "the scan back-lit through the ear, thin-object transmission (camera yaw 65°, light azimuth 200°, elevation 10°, 0.6 m)",
            stage: Stage::Scan,
            head_shot: true,
            settings: RenderSettings {
                transmission: Transmission::ThinObject,
                ..head(size, 65.0, SCAN_DISTANCE_M, (200.0, 10.0))
            },
        },
        Scene {
            id: "head_far",
            description: "far shot (3 m): the head is a few dozen pixels tall and Burley's LOD takes the short pattern or none",
            stage: Stage::Head,
            head_shot: false,
            settings: head(size, 20.0, 3.0, (50.0, 25.0)),
        },
        Scene {
            id: "plane_edge",
            description: "flat plane with a straight shadow edge (unit irradiance on x > 0), 40 mm across",
            stage: Stage::Plane,
            head_shot: false,
            settings: plane_settings(size, IrradiancePattern::Step),
        },
        Scene {
            id: "plane_checker",
            description: "flat plane under a 4 mm checkerboard of irradiance, 40 mm across",
            stage: Stage::Plane,
            head_shot: false,
            settings: plane_settings(size, IrradiancePattern::Checkerboard { period_mm: 4.0 }),
        },
    ]
}

/// One method at one of its bench configurations ([`Knob`], declared by
/// the method: `MethodInfo::bench`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Config {
    pub method: Method,
    pub knob: Knob,
}

impl Config {
    /// A method's one configuration.
    pub fn fixed(method: Method) -> Self {
        Self {
            method,
            knob: Knob::FIXED,
        }
    }

    /// The ground truth, every scene's yardstick.
    pub fn reference() -> Self {
        Self::fixed(Method::ground_truth())
    }

    /// The baseline that scatters nothing.
    pub fn none() -> Self {
        Self::fixed(Method::baseline())
    }

    /// `method`'s bench configuration `variant` at `count`, if it has one.
    pub fn of(method: Method, variant: &str, count: usize) -> Option<Self> {
        (method.sss().bench)()
            .into_iter()
            .find(|k| k.variant == variant && k.count == count)
            .map(|knob| Self { method, knob })
    }

    pub fn method(self) -> Method {
        self.method
    }

    /// The CSV's `variant` column.
    pub fn variant(self) -> &'static str {
        self.knob.variant
    }

    /// Samples or taps, else 0.
    pub fn count(self) -> usize {
        self.knob.count
    }

    /// `method/variant/count`, for labels.
    pub fn label(self) -> String {
        let v = self.variant();
        match (v.is_empty(), self.count()) {
            (true, _) => self.method().id().to_string(),
            (false, 0) => format!("{} {v}", self.method().id()),
            (false, n) => format!("{} {v} {n}", self.method().id()),
        }
    }
}

/// Every configuration measured on every scene (the reference is rendered
/// first and separately): each method's own list (`MethodInfo::bench`),
/// the methods of fixed quality first, then those set by taps, then by
/// samples, each group in the registry's order.
pub fn configs() -> Vec<Config> {
    let rank = |m: &Method| match m.sss().quality {
        Quality::Fixed => 0,
        Quality::Taps => 1,
        Quality::Samples => 2,
    };
    let mut methods: Vec<Method> = Method::all()
        .iter()
        .copied()
        .filter(|m| !m.sss().ground_truth)
        .collect();
    methods.sort_by_key(rank);
    methods
        .into_iter()
        .flat_map(|method| {
            (method.sss().bench)()
                .into_iter()
                .map(move |knob| Config { method, knob })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every configuration has its own label, every method but the
    /// ground truth is measured, each at every configuration it declares
    /// and no other (counted from the registry, so a new method's rows
    /// cannot be left out).
    #[test]
    fn every_method_is_benched_at_each_of_its_configs() {
        let c = configs();
        let mut labels: Vec<String> = c.iter().map(|c| c.label()).collect();
        labels.sort();
        labels.dedup();
        assert_eq!(labels.len(), c.len(), "{labels:?}");
        for &m in Method::all() {
            let rows = c.iter().filter(|c| c.method == m).count();
            let declared = (m.sss().bench)().len();
            let want = if m.sss().ground_truth { 0 } else { declared };
            assert_eq!(rows, want, "{}", m.id());
        }
    }
}
