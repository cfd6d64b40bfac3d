//! The render's view and look flags, and the one place where the command
//! line's degrees become the [`OrbitView`]'s radians.

use super::args::{parse_color, Color};
use crate::render::MethodOptions;
use crate::settings::rendering::{MethodId, TexturingId, TransmissionId};
use crate::settings::{OrbitView, RenderingSpec};
use anyhow::Result;
use std::path::PathBuf;

/// Camera, light, mesh and maps of a render. Angles are degrees here and
/// converted once, in [`ViewArgs::orbit`].
#[derive(Debug, Clone, clap::Args)]
pub struct ViewArgs {
    /// Camera orbit angle around the head (degrees; 0 = front).
    #[arg(long, allow_hyphen_values = true, default_value_t = 20.0)]
    pub camera_yaw: f32,
    /// Direction to the light: azimuth (degrees; 0 = from the camera's front, 180 = behind the head).
    #[arg(long, allow_hyphen_values = true, default_value_t = 72.0)]
    pub light_azimuth: f32,
    /// Direction to the light: elevation (degrees).
    #[arg(long, allow_hyphen_values = true, default_value_t = 20.0)]
    pub light_elevation: f32,
    /// Camera elevation above the head's centre (degrees; default 2.9).
    #[arg(long, allow_hyphen_values = true)]
    pub camera_pitch: Option<f32>,
    /// Vertical field of view (degrees; default 30).
    #[arg(long, allow_negative_numbers = true)]
    pub fov: Option<f32>,
    /// Irradiance of the key light at normal incidence (default 3.2).
    #[arg(long, allow_hyphen_values = true)]
    pub light_intensity: Option<f32>,
    /// The key light's colour, linear R,G,B (multiplies its intensity;
    /// default 1,1,1).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub light_colour: Option<Color>,
    /// A fill light beside the key: INTENSITY,AZIMUTH,ELEVATION
    /// (irradiance at normal incidence; degrees as --light-azimuth and
    /// --light-elevation: the head's own azimuth, not from the camera).
    /// Directional and unshadowed; light through thin parts is the key's
    /// alone in the real-time methods (the ground truth lights every
    /// surface, the backs of ears included).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_rig_light, value_name = "I,AZ,EL")]
    pub fill_light: Option<RigLightArg>,
    /// The fill light's colour, linear R,G,B (default 1,1,1).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub fill_colour: Option<Color>,
    /// A rim light: INTENSITY,AZIMUTH,ELEVATION, as --fill-light.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_rig_light, value_name = "I,AZ,EL")]
    pub rim_light: Option<RigLightArg>,
    /// The rim light's colour, linear R,G,B (default 1,1,1).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub rim_colour: Option<Color>,
    /// Exposure multiplier before tonemapping (default 1).
    #[arg(long, allow_hyphen_values = true)]
    pub exposure: Option<f32>,
    /// The display transform after exposure (`render::tonemap`).
    #[arg(long, value_enum, default_value_t = crate::render::tonemap::ToneMap::AcesFit)]
    pub tone_map: crate::render::tonemap::ToneMap,
    /// Camera distance from the face (m); default: the distance at which
    /// the mesh's height fills the view (0.574 m for the default head).
    #[arg(long, value_name = "M")]
    pub camera_distance: Option<f32>,
    /// Render this mesh (OBJ, glTF .gltf or .glb) instead of the default
    /// head. It needs UVs; OBJ groups named `eyes`/`teeth` are kept out of
    /// the scattering; glTF textures come from its first material.
    #[arg(long, value_name = "FILE")]
    pub mesh: Option<PathBuf>,
    /// Scale of --mesh: metres per unit (Unity's worldScale convention).
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub metres_per_unit: f32,
    /// Albedo (colour) map, sRGB PNG/JPEG; replaces the mesh's.
    #[arg(long = "albedo", id = "albedo_map", value_name = "IMG")]
    pub albedo: Option<PathBuf>,
    /// Where the surface colour comes from on a mesh with a colour map
    /// (--albedo, or a glTF's base colour texture): the map as the engines
    /// draw it, the map tinted so that its mean is the look's albedo, or
    /// the look's albedo alone. The default head's map modulates the
    /// look's colour whatever this says.
    #[arg(long, value_enum, default_value_t = crate::render::textures::MapColour::Map)]
    pub map_colour: crate::render::textures::MapColour,
    /// Tangent-space normal map (OpenGL convention: green up).
    #[arg(long, value_name = "IMG")]
    pub normal: Option<PathBuf>,
    /// Roughness map (grey, or the red channel), roughness of the first lobe.
    #[arg(long, value_name = "IMG")]
    pub roughness: Option<PathBuf>,
    /// SSS mask (grey): black keeps texels out of every SSS pass.
    #[arg(long, value_name = "IMG")]
    pub mask: Option<PathBuf>,
    /// Thickness map (grey): white = --thickness-range-mm, for transmission.
    #[arg(long, value_name = "IMG")]
    pub thickness: Option<PathBuf>,
    /// Environment light: an equirectangular map (Radiance .hdr, or PNG/JPEG
    /// as sRGB), projected to spherical harmonics; default: a studio sky.
    #[arg(long, value_name = "FILE.hdr")]
    pub environment: Option<PathBuf>,
    /// Multiplier of the environment's radiance.
    #[arg(long, default_value_t = 1.0, allow_negative_numbers = true)]
    pub environment_intensity: f32,
    /// A point light at this distance (m) from the head's centre, in the
    /// --light-azimuth/--light-elevation direction, instead of a
    /// directional light; it delivers the usual irradiance at that distance
    /// and falls off with the inverse square (perspective shadow map).
    #[arg(long, value_name = "M", allow_negative_numbers = true)]
    pub point_light: Option<f32>,
    /// Each method's own flags (`render::sss::MethodOptions`: declared in
    /// the method's file).
    #[command(flatten)]
    pub methods: MethodOptions,
    /// Render this many identical frames and report the last one's stats:
    /// the steady state of the editor, where the shadow map and the
    /// profile's tables are reused.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1000))]
    pub frames: u32,
    /// Flip the maps given with --albedo/--normal/--roughness/--mask/
    /// --thickness vertically (v → 1 − v): for maps made with V up
    /// (OpenGL's bottom-left origin) on a glTF, or the other way round.
    #[arg(long)]
    pub flip_v: bool,
    /// Turn a mesh exported inside out (its triangles clockwise seen from
    /// outside, or its normals pointing in: it draws dark) outward.
    #[arg(long)]
    pub turn_outward: bool,
    /// Thickness (mm) that a white texel of --thickness stands for
    /// (default: the look's `rendering.thickness_remap_mm`, 5 mm).
    #[arg(long, allow_negative_numbers = true)]
    pub thickness_range_mm: Option<f32>,
}

impl ViewArgs {
    /// The mesh to render, with any textures named on the command line.
    /// `thickness_range_mm`: what a white texel of a thickness map stands
    /// for when --thickness-range-mm is not given.
    pub fn load_mesh(&self, thickness_range_mm: f32) -> anyhow::Result<crate::render::Mesh> {
        use crate::render::textures::{self, AlbedoMode, RoughnessMode, TextureSlot};
        use crate::render::Mesh;
        crate::model::check_range(
            "metres_per_unit",
            self.metres_per_unit as f64,
            1e-6,
            1e3,
            " m/unit",
        )?;
        // Checked where it is given or used (a preset's remap may be 0
        // when the look has no thickness map).
        let thickness_range_mm = self.thickness_range_mm.unwrap_or(thickness_range_mm);
        if self.thickness_range_mm.is_some() || self.thickness.is_some() {
            crate::model::check_range(
                "thickness_range_mm",
                thickness_range_mm as f64,
                1e-3,
                1e4,
                " mm",
            )?;
        }
        let mut mesh = match &self.mesh {
            Some(path) => {
                let mut mesh = Mesh::load(path, self.metres_per_unit)?;
                if let Some(w) = mesh.head_size().scale_warning(self.metres_per_unit) {
                    eprintln!("warning: {}: {w}", path.display());
                }
                if self.turn_outward {
                    mesh.turn_outward();
                } else if let Some(what) = mesh.facing().describe() {
                    eprintln!(
                        "warning: {}: the file is inside out ({what} point inward), so it draws dark: add --turn-outward",
                        path.display()
                    );
                }
                mesh
            }
            None => Mesh::default_head()?,
        };
        let flip = self.flip_v;
        let load = |p: &std::path::Path, slot| -> anyhow::Result<textures::TextureImage> {
            let mut t = textures::load(p, slot)?;
            if flip {
                t.flip_v();
            }
            Ok(t)
        };
        let maps = std::sync::Arc::make_mut(&mut mesh.textures);
        if let Some(p) = &self.albedo {
            maps.albedo = load(p, TextureSlot::Albedo)?;
            maps.albedo_mode = AlbedoMode::Absolute;
        }
        if let Some(p) = &self.normal {
            maps.normal = load(p, TextureSlot::Normal)?;
        }
        if let Some(p) = &self.roughness {
            maps.roughness = load(p, TextureSlot::Roughness)?;
            maps.roughness_mode = RoughnessMode::Absolute;
        }
        if let Some(p) = &self.mask {
            maps.mask = load(p, TextureSlot::Mask)?;
        }
        if let Some(p) = &self.thickness {
            maps.thickness = Some((load(p, TextureSlot::Thickness)?, thickness_range_mm));
        }
        Ok(mesh)
    }
}

impl ViewArgs {
    /// The view these flags describe: degrees to radians here and nowhere
    /// else; `framing_distance_m` when no --camera-distance is given.
    pub fn orbit(&self, framing_distance_m: impl FnOnce(f32) -> f32) -> Result<OrbitView> {
        let d = OrbitView::default();
        let fov_y_rad = self.fov.map_or(d.fov_y_rad, f32::to_radians);
        if let Some(fov) = self.fov {
            crate::model::check_range("fov", fov as f64, 1.0, 170.0, "°")?;
        }
        if let Some(d) = self.camera_distance {
            crate::model::check_range("camera_distance", d as f64, 0.05, 1000.0, " m")?;
        }
        if let Some(d) = self.point_light {
            crate::model::check_range("point_light", d as f64, 1e-3, 1e4, " m")?;
        }
        if let Some(v) = self.light_intensity {
            crate::model::check_range("light_intensity", v as f64, 0.0, 1e4, "")?;
        }
        if let Some(v) = self.exposure {
            crate::model::check_range("exposure", v as f64, 1e-4, 1e4, "")?;
        }
        // Angles: any turn, but finite (a NaN yaw draws an empty frame).
        crate::model::check_range("camera_yaw", self.camera_yaw as f64, -1e4, 1e4, "°")?;
        crate::model::check_range("light_azimuth", self.light_azimuth as f64, -1e4, 1e4, "°")?;
        crate::model::check_range(
            "light_elevation",
            self.light_elevation as f64,
            -90.0,
            90.0,
            "°",
        )?;
        if let Some(v) = self.camera_pitch {
            crate::model::check_range("camera_pitch", v as f64, -89.0, 89.0, "°")?;
        }
        let light_colour = checked_colour("light_colour", self.light_colour)?;
        let fill = rig_light("fill", self.fill_light, self.fill_colour)?;
        let rim = rig_light("rim", self.rim_light, self.rim_colour)?;
        Ok(OrbitView {
            camera_yaw_rad: self.camera_yaw.to_radians(),
            camera_pitch_rad: self
                .camera_pitch
                .map_or(d.camera_pitch_rad, f32::to_radians),
            camera_distance_m: match self.camera_distance {
                Some(m) => m,
                None => framing_distance_m(fov_y_rad),
            },
            camera_pan_m: d.camera_pan_m,
            fov_y_rad,
            light_azimuth_rad: self.light_azimuth.to_radians(),
            light_elevation_rad: self.light_elevation.to_radians(),
            light_intensity: self.light_intensity.unwrap_or(d.light_intensity),
            point_light_distance_m: self.point_light,
            exposure: self.exposure.unwrap_or(d.exposure),
            light_colour,
            fill,
            rim,
        })
    }
}

/// `--fill-light`/`--rim-light`: intensity, azimuth and elevation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigLightArg(pub [f32; 3]);

fn parse_rig_light(s: &str) -> Result<RigLightArg, String> {
    let v = super::args::parse_list(s)?.0;
    match v.as_slice() {
        [i, az, el] => Ok(RigLightArg([*i as f32, *az as f32, *el as f32])),
        _ => Err(format!(
            "expected INTENSITY,AZIMUTH,ELEVATION (three numbers), got {} number(s) in `{s}`",
            v.len()
        )),
    }
}

/// A light's colour from the command line, white when not given; each
/// channel finite and 0–1e4 (the error names `field`).
fn checked_colour(field: &str, c: Option<Color>) -> Result<[f32; 3]> {
    let c = c.map_or([1.0; 3], |c| c.0);
    for (channel, v) in ["r", "g", "b"].iter().zip(c) {
        crate::model::check_range(&format!("{field}.{channel}"), v, 0.0, 1e4, "")?;
    }
    Ok(c.map(|v| v as f32))
}

/// The fill or rim light from `--<name>-light` and `--<name>-colour`
/// (off when no light is given; a colour alone is refused, as it would
/// light nothing).
fn rig_light(
    name: &str,
    light: Option<RigLightArg>,
    colour: Option<Color>,
) -> Result<crate::settings::RigLight> {
    let Some(RigLightArg([intensity, az, el])) = light else {
        if colour.is_some() {
            anyhow::bail!("--{name}-colour needs --{name}-light INTENSITY,AZIMUTH,ELEVATION");
        }
        return Ok(crate::settings::RigLight::default());
    };
    let check = crate::model::check_range;
    check(
        &format!("{name}_light intensity"),
        intensity as f64,
        0.0,
        1e4,
        "",
    )?;
    check(&format!("{name}_light azimuth"), az as f64, -1e4, 1e4, "°")?;
    check(
        &format!("{name}_light elevation"),
        el as f64,
        -90.0,
        90.0,
        "°",
    )?;
    Ok(crate::settings::RigLight {
        azimuth_rad: az.to_radians(),
        elevation_rad: el.to_radians(),
        intensity,
        colour: checked_colour(&format!("{name}_colour"), colour)?,
    })
}

/// The look's rendering settings (`RenderingSpec`, a preset's `rendering`
/// section): each flag overrides the preset's value (the defaults without
/// --preset), so that every field of a look can be set here.
#[derive(Debug, Clone, Default, clap::Args)]
pub struct LookArgs {
    /// SSS method (default: the preset's, else burley).
    #[arg(long, value_enum)]
    pub method: Option<MethodId>,
    /// Burley disk samples (default: the preset's, else 21).
    #[arg(long)]
    pub samples: Option<usize>,
    /// Separable kernel taps, odd (default: the preset's, else 17).
    #[arg(long)]
    pub taps: Option<usize>,
    /// Turn off the levels of detail: Burley's discrete LOD and the mesh's
    /// coarse level (always the finest mesh, as `reference` draws).
    #[arg(long)]
    pub no_lod: bool,
    /// Transmission (default: the preset's, else thin).
    #[arg(long, value_enum)]
    pub transmission: Option<TransmissionId>,
    /// Linear RGB multiplier of transmitted light (default: the preset's, else 1,1,1).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B")]
    pub transmission_tint: Option<Color>,
    /// Texturing mode (default: the preset's, else pre-and-post).
    #[arg(long, value_enum)]
    pub texturing: Option<TexturingId>,
    /// Index of refraction of the surface, 1–2: the specular F0 (default:
    /// the preset's, else 1.4).
    #[arg(long, allow_negative_numbers = true)]
    pub ior: Option<f64>,
    /// The dual-lobe specular's material roughness, 0–1 (default: the
    /// preset's, else 0.55).
    #[arg(long, allow_negative_numbers = true)]
    pub specular_roughness: Option<f64>,
    /// Multiplier of the sharper lobe's roughness, 0–2 (Unreal's
    /// Roughness0; default: the preset's, else 0.75).
    #[arg(long, allow_negative_numbers = true)]
    pub lobe0_roughness_multiplier: Option<f64>,
    /// Multiplier of the broader lobe's roughness, 0–2 (Unreal's
    /// Roughness1; default: the preset's, else 1.30).
    #[arg(long, allow_negative_numbers = true)]
    pub lobe1_roughness_multiplier: Option<f64>,
    /// Weight of the broader lobe, 0–1 (Unreal's LobeMix; default: the
    /// preset's, else 0.85).
    #[arg(long, allow_negative_numbers = true)]
    pub lobe_mix: Option<f64>,
    /// Metres per scene unit the look's engine exports assume (Unity's
    /// world scale; default: the preset's, else 1). A field of the look
    /// for exports: it does not change this render (--metres-per-unit
    /// gives the mesh's units).
    #[arg(long, allow_negative_numbers = true)]
    pub world_scale: Option<f64>,
}

impl LookArgs {
    /// `base` (the preset's rendering settings) with every given flag
    /// applied, validated (errors name the field under `rendering.`).
    pub fn apply(&self, base: RenderingSpec) -> Result<RenderingSpec> {
        let RenderingSpec {
            method,
            samples,
            taps,
            lod,
            texturing,
            transmission,
            thickness_remap_mm,
            transmission_tint,
            ior,
            world_scale_m_per_unit,
            specular,
            albedo_in_material,
        } = base;
        let r = RenderingSpec {
            method: self.method.unwrap_or(method),
            samples: self.samples.unwrap_or(samples),
            taps: self.taps.unwrap_or(taps),
            lod: lod && !self.no_lod,
            texturing: self.texturing.unwrap_or(texturing),
            transmission: self.transmission.unwrap_or(transmission),
            // Set with --thickness-range-mm where a thickness map is given.
            thickness_remap_mm,
            transmission_tint: self.transmission_tint.map_or(transmission_tint, |c| c.0),
            ior: self.ior.unwrap_or(ior),
            world_scale_m_per_unit: self.world_scale.unwrap_or(world_scale_m_per_unit),
            specular: crate::settings::rendering::DualLobeSpec {
                roughness: self.specular_roughness.unwrap_or(specular.roughness),
                lobe0_roughness_multiplier: self
                    .lobe0_roughness_multiplier
                    .unwrap_or(specular.lobe0_roughness_multiplier),
                lobe1_roughness_multiplier: self
                    .lobe1_roughness_multiplier
                    .unwrap_or(specular.lobe1_roughness_multiplier),
                lobe_mix: self.lobe_mix.unwrap_or(specular.lobe_mix),
            },
            albedo_in_material,
        };
        r.validate()?;
        Ok(r)
    }
}
