//! The scripting interface: subcommands that print the same numbers the
//! editor shows. `--json` prints exactly the documented keys; bad input
//! exits non-zero with a one-line error on stderr.

pub mod args;

use crate::model::burley::{sample_radius_checked, sample_radius_halley, Burley};
use crate::model::fit::{fit_artist, fit_burley, fit_gaussians, fit_jimenez};
use crate::model::jimenez::Jimenez2012;
use crate::model::lut::{self, LutEncoding, LutLayout, ShadowLayout};
use crate::model::sampling::{AngleSequence, SamplePattern};
use crate::model::separable::SeparableKernel;
use crate::model::units::{
    BlenderSubsurface, UnityProfile, UnrealProfile, UNREAL_DEFAULT_WORLD_UNIT_SCALE,
};
use crate::model::{check_radius, RadialProfile, Rgb, DEFAULT_ENERGY_FRACTION};
use crate::settings::rendering::{MethodId, TexturingId, TransmissionId};
use crate::settings::ProfileSpec;
use anyhow::{bail, Context, Result};
use args::{parse_color, parse_list, Color, ModelArgs, NumberList};
use clap::{Parser, Subcommand, ValueEnum};
use serde_json::{json, Value};
use std::path::PathBuf;

#[derive(Debug, Parser)]
#[command(name = "scatterlab", version, about = "Author subsurface-scattering diffusion profiles.", long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

#[derive(Debug, Subcommand)]
#[allow(clippy::large_enum_variant)] // parsed once per process
pub enum Command {
    /// Open the editor (the default with no subcommand), optionally on a preset.
    Edit {
        /// The preset (.ron) to open; default: the last one, else the embedded skin.
        #[arg(long, value_name = "FILE.ron")]
        preset: Option<PathBuf>,
        /// Close the window once the head has been shown (start-up smoke
        /// test; with SCATTERLAB_TIMINGS=1 it prints the start-up times).
        #[arg(long, hide = true)]
        exit_after_first_frame: bool,
        /// Open comparing the look (A) with B in this view.
        #[arg(long, value_enum)]
        compare: Option<CompareArg>,
        /// With --compare: B is the look rendered with this method
        /// (default: what B was last time).
        #[arg(long, value_enum, requires = "compare")]
        compare_b: Option<MethodId>,
    },
    /// R(r), r·R(r), CDF, total reflectance and 99.7 % radius of a profile.
    Profile {
        #[command(flatten)]
        model: ModelArgs,
        /// Radii (mm); default: 24 radii up to twice the widest 99.7 % radius.
        #[arg(long, allow_hyphen_values = true, value_parser = parse_list, value_name = "R1,R2,…")]
        radii: Option<NumberList>,
        #[arg(long)]
        json: bool,
    },
    /// Sample radii and patterns.
    #[command(subcommand)]
    Sample(SampleCommand),
    /// 1D separable kernels.
    #[command(subcommand)]
    Kernel(KernelCommand),
    /// Lookup tables.
    #[command(subcommand)]
    Lut(LutCommand),
    /// Thin-slab transmittance T(d) = ∫2πr R(√(r²+d²)) dr.
    Transmittance {
        #[command(flatten)]
        model: ModelArgs,
        /// Thicknesses (mm).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_list, value_name = "D1,D2,…")]
        thickness: NumberList,
        #[arg(long)]
        json: bool,
    },
    /// Fit another model to a profile; the error is the relative L2 error of r·R(r) to the 99.7 % radius.
    Fit {
        #[command(flatten)]
        model: ModelArgs,
        /// burley, jimenez, artist or gaussians:N.
        #[arg(long, value_name = "MODEL")]
        to: String,
        #[arg(long)]
        json: bool,
    },
    /// Render the head offscreen with an SSS method and write a PNG.
    /// (`--albedo` is the albedo map here; the Burley volume albedo of
    /// `--model burley` is `--volume-albedo`.)
    #[command(mut_arg("albedo", |a| a.long("volume-albedo")))]
    Render {
        #[command(flatten)]
        model: ModelArgs,
        #[arg(long, value_enum, default_value = "burley")]
        method: MethodId,
        #[arg(long, default_value_t = 512)]
        width: u32,
        #[arg(long, default_value_t = 512)]
        height: u32,
        /// Burley disk samples.
        #[arg(long, default_value_t = 21)]
        samples: usize,
        /// Separable kernel taps (odd).
        #[arg(long, default_value_t = 17)]
        taps: usize,
        /// Turn off the per-pixel random rotation (reproducible images).
        #[arg(long)]
        deterministic: bool,
        #[arg(long, value_name = "FILE.png")]
        out: PathBuf,
        /// Also write per-frame statistics as JSON.
        #[arg(long, value_name = "FILE.json")]
        stats: Option<PathBuf>,
        #[command(flatten)]
        view: ViewArgs,
        /// Render a second method and show both, split at --split.
        #[arg(long, value_enum)]
        compare: Option<MethodId>,
        /// Divider position for --compare (0–1 of the width).
        #[arg(long, default_value_t = 0.5)]
        split: f32,
        /// With --compare: write the |A − B| heat map instead of the split
        /// (against `reference` when no --compare is given).
        #[arg(long)]
        diff: bool,
        /// With --diff: the |ΔL| (linear luminance) at the top of the colour
        /// bar, so that several heat maps share one scale; default: the
        /// frame's largest difference.
        #[arg(long, value_name = "ΔL")]
        diff_scale: Option<f32>,
    },
    /// Write a preset for an engine or tool. Files are written atomically;
    /// formats with comments or metadata record the scatterlab version and
    /// the preset. Some formats write a companion file beside --out
    /// (unreal: .py; lut-*: _shadow; profile-*: _transmittance).
    Export {
        /// The preset (.ron).
        #[arg(long, value_name = "FILE.ron")]
        preset: PathBuf,
        #[arg(long, value_enum)]
        format: crate::export::Format,
        #[arg(long, value_name = "PATH")]
        out: PathBuf,
    },
    /// Run-time against error of every SSS method and count on fixed
    /// scenes, against `reference`; writes results.csv, skip.csv, one chart
    /// per scene and accuracy.md into --out.
    Bench {
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Smaller frames and one timed frame per configuration (a few
        /// minutes on 2 cores; what CI runs).
        #[arg(long)]
        quick: bool,
        /// The look to measure (default: the embedded skin preset).
        #[arg(long, value_name = "FILE.ron")]
        preset: Option<PathBuf>,
        /// Only redraw the charts and accuracy.md from --out's results.csv
        /// and skip.csv (no rendering).
        #[arg(long)]
        replot: bool,
    },
    /// Sweep every model across its documented parameter range against
    /// independent references: worst relative errors of R, the CDF and the
    /// inverse CDF, kernel normalisation, and the count of NaN/Inf.
    Stress {
        /// Random parameter sets per model (multipole slabs get 1/6 of
        /// them, layered stacks 1/24, at least 2); edges are drawn one time
        /// in five. The default takes about two minutes on 2 cores.
        #[arg(long, default_value_t = crate::model::stress::DEFAULT_CASES, conflicts_with = "long")]
        cases: usize,
        /// The long sweep: 400 cases per model (about 20 CPU-minutes).
        #[arg(long)]
        long: bool,
        #[arg(long, default_value_t = 2026)]
        seed: u64,
        /// Only this model (burley, gaussians, jimenez2012, artist, dipole,
        /// measured, multipole-slab, multipole-stack).
        #[arg(long)]
        model: Option<String>,
        #[arg(long)]
        json: bool,
    },
    /// Express a profile in an engine's parameters (via a Burley fit when needed).
    Convert {
        #[command(flatten)]
        model: ModelArgs,
        #[arg(long, value_enum)]
        to: Engine,
        /// Unity: metres per unit (default 1). Unreal: World Unit Scale (default 0.1). Blender: metres per unit (default 1).
        #[arg(long, allow_hyphen_values = true)]
        world_scale: Option<f64>,
        #[arg(long)]
        json: bool,
    },
}

/// Camera, light and transmission of a render.
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
    #[arg(long, value_enum, default_value = "thin")]
    pub transmission: TransmissionId,
    /// Texturing mode.
    #[arg(long, value_enum, default_value = "pre-and-post")]
    pub texturing: TexturingId,
    /// Camera distance from the face (m); default: the distance at which
    /// the mesh's height fills the view (0.574 m for the default head).
    #[arg(long, value_name = "M")]
    pub camera_distance: Option<f32>,
    /// Turn off the levels of detail: Burley's discrete LOD and the mesh's
    /// coarse level (always the finest mesh, as `reference` draws).
    #[arg(long)]
    pub no_lod: bool,
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
    /// `separable`: rotate the blur axes per pixel (Jimenez 2015 §6).
    #[arg(long)]
    pub separable_rotation: bool,
    /// `burley` sampling: `improved` (MIS across the channels, R2
    /// rotations, an exact centre weight) or `golubev` (Golubev 2018 as
    /// published); `bench` measures both.
    #[arg(long, value_enum, default_value = "improved")]
    pub burley_sampling: SamplingArg,
    /// Taps of each 1D Gaussian pass of `gaussians` (odd; 7 is d'Eon 2007's
    /// kernel, 13 follows edges more closely at about twice the cost).
    #[arg(long, default_value_t = 7)]
    pub gaussian_taps: usize,
    /// Render this many identical frames and report the last one's stats:
    /// the steady state of the editor, where the shadow map and the
    /// profile's tables are reused.
    #[arg(long, default_value_t = 1)]
    pub frames: u32,
    /// Flip the maps given with --albedo/--normal/--roughness/--mask/
    /// --thickness vertically (v → 1 − v): for maps made with V up
    /// (OpenGL's bottom-left origin) on a glTF, or the other way round.
    #[arg(long)]
    pub flip_v: bool,
    /// Thickness (mm) that a white texel of --thickness stands for.
    #[arg(long, default_value_t = 20.0, allow_negative_numbers = true)]
    pub thickness_range_mm: f32,
}

impl ViewArgs {
    /// The mesh to render, with any textures named on the command line.
    pub fn load_mesh(&self) -> anyhow::Result<crate::render::Mesh> {
        use crate::render::textures::{self, AlbedoMode, RoughnessMode, TextureSlot};
        use crate::render::Mesh;
        crate::model::check_range(
            "metres_per_unit",
            self.metres_per_unit as f64,
            1e-6,
            1e3,
            " m/unit",
        )?;
        crate::model::check_range(
            "thickness_range_mm",
            self.thickness_range_mm as f64,
            1e-3,
            1e4,
            " mm",
        )?;
        let mut mesh = match &self.mesh {
            Some(path) => {
                let mesh = Mesh::load(path, self.metres_per_unit)?;
                if let Some(w) = mesh.head_size().scale_warning(self.metres_per_unit) {
                    eprintln!("warning: {}: {w}", path.display());
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
            maps.thickness = Some((load(p, TextureSlot::Thickness)?, self.thickness_range_mm));
        }
        Ok(mesh)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SamplingArg {
    Improved,
    Golubev,
}

/// The editor's compare views (`edit --compare`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CompareArg {
    Split,
    SideBySide,
    Difference,
}

#[cfg(test)]
mod tests {
    /// clap's own consistency checks over every subcommand (duplicate
    /// names, conflicts) — these otherwise panic at parse time.
    #[test]
    fn command_line_definition_is_consistent() {
        use clap::CommandFactory;
        super::Cli::command().debug_assert();
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Engine {
    Unity,
    Unreal,
    Blender,
}

#[derive(Debug, Subcommand)]
#[allow(clippy::large_enum_variant)]
pub enum SampleCommand {
    /// Burley radii for given ξ by the inverse CDF (closed form or Halley).
    Burley {
        /// Shape s = 1/d (1/mm).
        #[arg(long, allow_hyphen_values = true)]
        shape: f64,
        /// CDF values ξ in [0, 1).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_list, value_name = "X1,X2,…")]
        xi: NumberList,
        #[arg(long, value_enum, default_value = "closed-form")]
        method: InverseMethod,
        #[arg(long)]
        json: bool,
    },
    /// Golubev 2018 disk sample pattern for a profile.
    Pattern {
        #[command(flatten)]
        model: ModelArgs,
        #[arg(long, default_value_t = 21)]
        samples: usize,
        #[arg(long, value_enum, default_value = "golden-angle")]
        angles: AnglesArg,
        #[arg(long)]
        json: bool,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum InverseMethod {
    ClosedForm,
    Halley,
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum AnglesArg {
    GoldenAngle,
    Hammersley,
}

// Parsed once per run; boxing the larger variant would buy nothing.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Subcommand)]
pub enum KernelCommand {
    /// The Jimenez 2012 demo kernel (centre tap first).
    Jimenez {
        #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B", default_value = "0.48,0.41,0.28")]
        strength: Color,
        #[arg(long, allow_hyphen_values = true, value_parser = parse_color, value_name = "R,G,B", default_value = "1,0.37,0.3")]
        falloff: Color,
        #[arg(long, default_value_t = 17)]
        taps: usize,
        #[arg(long)]
        json: bool,
    },
    /// Importance-sampled taps of the pre-integrated kernel (Jimenez 2015) of any profile.
    Separable {
        #[command(flatten)]
        model: ModelArgs,
        #[arg(long, default_value_t = 7)]
        taps: usize,
        #[arg(long)]
        json: bool,
    },
}

#[derive(Debug, Subcommand)]
pub enum LutCommand {
    /// Penner's pre-integrated D(θ, curvature radius).
    Preintegrated {
        #[command(flatten)]
        model: ModelArgs,
        /// Angles between N and L (radians).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_list, value_name = "T1,T2,…")]
        theta: Option<NumberList>,
        /// Curvature radii (mm).
        #[arg(long, allow_hyphen_values = true, value_parser = parse_list, value_name = "C1,C2,…")]
        curvature_radius: Option<NumberList>,
        /// Write the table as a PNG (θ or N·L across, curvature down).
        #[arg(long, value_name = "FILE.png")]
        out: Option<PathBuf>,
        /// PNG encoding: linear D or FaceWorks' delta from saturate(N·L).
        #[arg(long, value_enum, default_value = "linear")]
        encoding: EncodingArg,
        /// Baked table size when no --theta/--curvature-radius lists are given.
        #[arg(long, default_value_t = 256)]
        size: usize,
        #[arg(long)]
        json: bool,
    },
    /// Penner's shadow-penumbra table (linear PNG).
    Shadow {
        #[command(flatten)]
        model: ModelArgs,
        #[arg(long, value_name = "FILE.png")]
        out: PathBuf,
        #[arg(long, default_value_t = 64)]
        size: usize,
    },
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum EncodingArg {
    Linear,
    FaceworksDelta,
}

/// Runs a parsed command; `None` prints the default profile.
pub fn run(cli: Cli) -> Result<()> {
    let Some(command) = cli.command else {
        return crate::app::run(None, false, None);
    };
    match command {
        Command::Edit {
            preset,
            exit_after_first_frame,
            compare,
            compare_b,
        } => {
            use crate::app::state::CompareMode;
            let compare = compare.map(|c| {
                let mode = match c {
                    CompareArg::Split => CompareMode::Split,
                    CompareArg::SideBySide => CompareMode::SideBySide,
                    CompareArg::Difference => CompareMode::Difference,
                };
                (mode, compare_b)
            });
            crate::app::run(preset, exit_after_first_frame, compare)
        }
        Command::Profile { model, radii, json } => profile(&model, radii, json),
        Command::Sample(SampleCommand::Burley {
            shape,
            xi,
            method,
            json,
        }) => sample_burley(shape, &xi.0, method, json),
        Command::Sample(SampleCommand::Pattern {
            model,
            samples,
            angles,
            json,
        }) => pattern(&model, samples, angles, json),
        Command::Kernel(KernelCommand::Jimenez {
            strength,
            falloff,
            taps,
            json,
        }) => {
            let k = Jimenez2012::new(strength.0, falloff.0)?.kernel(taps)?;
            print_kernel(&k, json)
        }
        Command::Kernel(KernelCommand::Separable { model, taps, json }) => {
            let p = model.spec()?.build()?;
            print_kernel(
                &SeparableKernel::importance_sampled(p.as_ref(), taps)?,
                json,
            )
        }
        Command::Lut(LutCommand::Preintegrated {
            model,
            theta,
            curvature_radius,
            out,
            encoding,
            size,
            json,
        }) => lut_preintegrated(&model, theta, curvature_radius, out, encoding, size, json),
        Command::Lut(LutCommand::Shadow { model, out, size }) => lut_shadow(&model, &out, size),
        Command::Transmittance {
            model,
            thickness,
            json,
        } => transmittance(&model, &thickness.0, json),
        Command::Fit { model, to, json } => fit(&model, &to, json),
        Command::Render {
            model,
            method,
            width,
            height,
            samples,
            taps,
            deterministic,
            out,
            stats,
            view,
            compare,
            split,
            diff,
            diff_scale,
        } => render(
            &model,
            method,
            (width, height),
            (samples, taps),
            deterministic,
            &out,
            stats.as_deref(),
            &view,
            (compare, split, diff, diff_scale),
        ),
        Command::Convert {
            model,
            to,
            world_scale,
            json,
        } => convert(&model, to, world_scale, json),
        Command::Bench {
            out,
            quick,
            preset,
            replot,
        } => {
            if replot {
                crate::bench::replot(&out, quick)
            } else {
                crate::bench::run_cli(&out, quick, preset.as_deref())
            }
        }
        Command::Stress {
            cases,
            long,
            seed,
            model,
            json,
        } => {
            let cases = if long {
                crate::model::stress::LONG_CASES
            } else {
                cases
            };
            stress(cases, seed, model.as_deref(), json)
        }
        Command::Export {
            preset,
            format,
            out,
        } => {
            let p = crate::settings::Preset::load(&preset)?;
            for path in crate::export::export(&p, Some(&preset), format, &out)? {
                println!("{}", path.display());
            }
            Ok(())
        }
    }
}

fn built(model: &ModelArgs) -> Result<(ProfileSpec, Box<dyn RadialProfile>)> {
    let spec = model.spec()?;
    let p = spec.build()?;
    Ok((spec, p))
}

fn checked_list(field: &str, values: &[f64]) -> Result<()> {
    for (i, v) in values.iter().enumerate() {
        check_radius(&format!("{field}[{i}]"), *v)?;
    }
    Ok(())
}

fn rgb(v: Rgb) -> Value {
    json!(v)
}

fn profile(model: &ModelArgs, radii: Option<NumberList>, as_json: bool) -> Result<()> {
    let (spec, p) = built(model)?;
    let r997 = p.radius_for_energy(DEFAULT_ENERGY_FRACTION);
    let radii = match radii {
        Some(l) => l.0,
        None => {
            let max = 2.0 * r997.into_iter().fold(0.0, f64::max);
            (0..24).map(|i| max * i as f64 / 23.0).collect()
        }
    };
    checked_list("radii", &radii)?;
    let rows: Vec<(Rgb, Rgb, Rgb)> = radii
        .iter()
        .map(|&r| (p.reflectance(r), p.r_reflectance(r), p.cdf(r)))
        .collect();
    let total = p.total_reflectance();
    if as_json {
        let out = json!({
            "radii_mm": radii,
            "R": rows.iter().map(|r| rgb(r.0)).collect::<Vec<_>>(),
            "rR": rows.iter().map(|r| rgb(r.1)).collect::<Vec<_>>(),
            "cdf": rows.iter().map(|r| rgb(r.2)).collect::<Vec<_>>(),
            "total_reflectance": rgb(total),
            "radius_997_mm": rgb(r997),
        });
        println!("{out}");
        return Ok(());
    }
    println!("model: {}", spec.model_name());
    println!(
        "total diffuse reflectance (R, G, B): {:.6} {:.6} {:.6}",
        total[0], total[1], total[2]
    );
    println!(
        "radius holding 99.7 % of the energy (mm): {:.6} {:.6} {:.6}",
        r997[0], r997[1], r997[2]
    );
    println!(
        "{:>10}  {:>36}  {:>36}  {:>26}",
        "r (mm)", "R(r) R G B (1/mm²)", "r·R(r) R G B (1/mm)", "CDF R G B"
    );
    for (r, (a, b, c)) in radii.iter().zip(&rows) {
        println!(
            "{r:>10.4}  {:>11.4e} {:>11.4e} {:>11.4e}  {:>11.4e} {:>11.4e} {:>11.4e}  {:>8.5} {:>8.5} {:>8.5}",
            a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2]
        );
    }
    Ok(())
}

fn sample_burley(shape: f64, xi: &[f64], method: InverseMethod, as_json: bool) -> Result<()> {
    crate::model::check_range("shape", shape, 1e-3, 1e4, " 1/mm")?;
    let mut radii = Vec::with_capacity(xi.len());
    for (i, &x) in xi.iter().enumerate() {
        let r = sample_radius_checked(x, shape).with_context(|| format!("xi[{i}]"))?;
        radii.push(match method {
            InverseMethod::ClosedForm => r,
            InverseMethod::Halley => sample_radius_halley(x, shape),
        });
    }
    if as_json {
        println!("{}", json!({ "xi": xi, "radius_mm": radii }));
    } else {
        println!("{:>12}  {:>14}", "xi", "radius (mm)");
        for (x, r) in xi.iter().zip(&radii) {
            println!("{x:>12.6}  {r:>14.8}");
        }
    }
    Ok(())
}

fn pattern(model: &ModelArgs, n: usize, angles: AnglesArg, as_json: bool) -> Result<()> {
    let (_, p) = built(model)?;
    let seq = match angles {
        AnglesArg::GoldenAngle => AngleSequence::GoldenAngle,
        AnglesArg::Hammersley => AngleSequence::Hammersley,
    };
    let pat = SamplePattern::new(p.as_ref(), n, seq)?;
    if as_json {
        let samples: Vec<Value> = pat
            .samples
            .iter()
            .map(|s| json!({ "radius_mm": s.radius_mm, "angle_rad": s.angle_rad, "weight": rgb(s.weight) }))
            .collect();
        println!(
            "{}",
            json!({ "sampled_channel": pat.sampled_channel, "angles": seq.id(), "samples": samples })
        );
    } else {
        println!(
            "sampled channel: {} ({} angles)",
            ["R", "G", "B"][pat.sampled_channel],
            seq.id()
        );
        println!(
            "{:>12}  {:>10}  {:>36}",
            "radius (mm)", "angle", "weight R G B"
        );
        for s in &pat.samples {
            println!(
                "{:>12.6}  {:>10.6}  {:>11.4e} {:>11.4e} {:>11.4e}",
                s.radius_mm, s.angle_rad, s.weight[0], s.weight[1], s.weight[2]
            );
        }
    }
    Ok(())
}

fn print_kernel(k: &SeparableKernel, as_json: bool) -> Result<()> {
    if as_json {
        let rows: Vec<[f64; 4]> = k
            .taps
            .iter()
            .map(|t| [t.weight[0], t.weight[1], t.weight[2], t.offset_mm])
            .collect();
        println!("{}", json!({ "kernel": rows }));
    } else {
        println!(
            "{:>12} {:>12} {:>12}  {:>12}",
            "weight R", "weight G", "weight B", "offset (mm)"
        );
        for t in &k.taps {
            println!(
                "{:>12.6e} {:>12.6e} {:>12.6e}  {:>12.6}",
                t.weight[0], t.weight[1], t.weight[2], t.offset_mm
            );
        }
    }
    Ok(())
}

#[allow(clippy::too_many_arguments)]
fn lut_preintegrated(
    model: &ModelArgs,
    theta: Option<NumberList>,
    radii: Option<NumberList>,
    out: Option<PathBuf>,
    encoding: EncodingArg,
    size: usize,
    as_json: bool,
) -> Result<()> {
    let (_, p) = built(model)?;
    let enc = match encoding {
        EncodingArg::Linear => LutEncoding::Linear,
        EncodingArg::FaceworksDelta => LutEncoding::FaceWorksDelta,
    };
    match (theta, radii) {
        (Some(t), Some(c)) => {
            for &th in &t.0 {
                for &cr in &c.0 {
                    lut::check_lut_inputs(th, cr)?;
                }
            }
            let d: Vec<Vec<Rgb>> =
                t.0.iter()
                    .map(|&th| {
                        c.0.iter()
                            .map(|&cr| lut::preintegrated_d(p.as_ref(), th, cr))
                            .collect()
                    })
                    .collect();
            if let Some(path) = &out {
                let (w, h) = (t.0.len(), c.0.len());
                let mut px = Vec::with_capacity(w * h * 3);
                for j in 0..h {
                    for (i, th) in t.0.iter().enumerate() {
                        px.extend(d[i][j].map(|v| {
                            (enc.encode(v, th.cos()).clamp(0.0, 1.0) * 255.0 + 0.5) as u8
                        }));
                    }
                }
                write_png(path, w, h, px)?;
            }
            if as_json {
                println!("{}", json!({ "D": d }));
            } else if out.is_none() {
                for (th, row) in t.0.iter().zip(&d) {
                    for (cr, v) in c.0.iter().zip(row) {
                        println!(
                            "theta {th:.6} rad, curvature radius {cr:.4} mm: D = {:.6} {:.6} {:.6}",
                            v[0], v[1], v[2]
                        );
                    }
                }
            }
            Ok(())
        }
        (None, None) => {
            let Some(path) = out else {
                bail!(
                    "give --theta and --curvature-radius lists, or --out FILE.png to bake a table"
                )
            };
            if as_json {
                bail!("--json needs --theta and --curvature-radius lists");
            }
            let layout = LutLayout {
                width: size,
                height: size,
                ..LutLayout::default()
            };
            let table = lut::Lut::bake(p.as_ref(), layout)?;
            write_png(&path, size, size, table.to_rgb8(enc))?;
            println!(
                "wrote {} ({size}×{size}, x: N·L −1→1, y: 1/c from 1/{} to 1/{} mm⁻¹, {:?}, linear 8-bit)",
                path.display(),
                layout.curvature_radius_max_mm,
                layout.curvature_radius_min_mm,
                enc
            );
            Ok(())
        }
        _ => bail!("--theta and --curvature-radius go together"),
    }
}

fn lut_shadow(model: &ModelArgs, out: &std::path::Path, size: usize) -> Result<()> {
    let (_, p) = built(model)?;
    let layout = ShadowLayout {
        width: size,
        height: size,
        ..ShadowLayout::default()
    };
    let t = lut::bake_shadow(p.as_ref(), layout)?;
    let px: Vec<u8> = t
        .iter()
        .flat_map(|v| v.map(|x| (x.clamp(0.0, 1.0) * 255.0 + 0.5) as u8))
        .collect();
    write_png(out, size, size, px)?;
    println!(
        "wrote {} ({size}×{size}, x: unscattered shadow 0→1, y: 1/penumbra width from 1/{} to 1/{} mm⁻¹, linear 8-bit)",
        out.display(),
        layout.penumbra_max_mm,
        layout.penumbra_min_mm
    );
    Ok(())
}

fn write_png(path: &std::path::Path, w: usize, h: usize, rgb8: Vec<u8>) -> Result<()> {
    let img = image::RgbImage::from_raw(w as u32, h as u32, rgb8)
        .context("internal: image size mismatch")?;
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )?;
    crate::fsutil::write_atomic(path, &bytes)
        .with_context(|| format!("{}: cannot write", path.display()))
}

#[allow(clippy::too_many_arguments)]
fn render(
    model: &ModelArgs,
    method: MethodId,
    (width, height): (u32, u32),
    (samples, taps): (usize, usize),
    deterministic: bool,
    out: &std::path::Path,
    stats_path: Option<&std::path::Path>,
    view: &ViewArgs,
    (compare, split, diff, fixed_scale): (Option<MethodId>, f32, bool, Option<f32>),
) -> Result<()> {
    use crate::render::{GpuContext, ProfileInputs, RenderSettings, Renderer};
    crate::model::check_range("width", width as f64, 16.0, 8192.0, " px")?;
    crate::model::check_range("height", height as f64, 16.0, 8192.0, " px")?;
    if let Some(d) = view.camera_distance {
        crate::model::check_range("camera_distance", d as f64, 0.05, 1000.0, " m")?;
    }
    // The shared model flags name the volume albedo `--albedo`; here that
    // flag is `--volume-albedo` (`--albedo` is the albedo map).
    let (spec, p) = built(model)
        .map_err(|e| anyhow::anyhow!(format!("{e:#}").replace("--albedo", "--volume-albedo")))?;
    crate::model::check_range("gaussian_taps", view.gaussian_taps as f64, 3.0, 63.0, "")?;
    if view.gaussian_taps.is_multiple_of(2) {
        anyhow::bail!("gaussian_taps = {} must be odd", view.gaussian_taps);
    }
    let mut inputs = ProfileInputs::for_look(
        &spec,
        p.as_ref(),
        method,
        (samples, taps),
        view.gaussian_taps,
    )?;
    if view.burley_sampling == SamplingArg::Golubev {
        inputs.set_burley(p.as_ref(), samples, crate::render::BurleySampling::GOLUBEV)?;
    }
    let mesh = view.load_mesh()?;
    crate::model::check_range(
        "environment_intensity",
        view.environment_intensity as f64,
        0.0,
        1e4,
        "",
    )?;
    if let Some(d) = view.point_light {
        crate::model::check_range("point_light", d as f64, 1e-3, 1e4, " m")?;
    }
    let environment = match &view.environment {
        Some(path) => crate::render::environment::Environment::load(path)?,
        None => Default::default(),
    };
    let environment_sh = environment
        .irradiance_sh()
        .map(|c| c.map(|v| v * view.environment_intensity));
    let mut renderer = Renderer::new(GpuContext::new_headless()?, &mesh)?;
    let settings = RenderSettings {
        width,
        height,
        method,
        deterministic,
        camera_yaw: view.camera_yaw.to_radians(),
        camera_distance_m: view
            .camera_distance
            .unwrap_or_else(|| mesh.framing_distance_m(RenderSettings::default().fov_y)),
        lod: !view.no_lod,
        mesh_lod: !view.no_lod,
        light_azimuth: view.light_azimuth.to_radians(),
        light_elevation: view.light_elevation.to_radians(),
        transmission: view.transmission,
        texturing: view.texturing,
        environment_sh,
        separable_rotation: view.separable_rotation,
        point_light_distance_m: view.point_light,
        ..RenderSettings::default()
    };
    crate::model::check_range("frames", view.frames as f64, 1.0, 1000.0, "")?;
    let (mut image, mut stats) = renderer.render(&inputs, &settings)?;
    for _ in 1..view.frames {
        (image, stats) = renderer.render(&inputs, &settings)?;
    }
    let other = match (compare, diff) {
        (Some(m), _) => Some(m),
        (None, true) => Some(MethodId::Reference),
        (None, false) => None,
    };
    let mut diff_scale = None;
    if let Some(m) = other {
        crate::model::check_range("split", split as f64, 0.0, 1.0, "")?;
        let b_settings = RenderSettings {
            method: m,
            ..settings.clone()
        };
        let (b, _) = renderer.render(&inputs, &b_settings)?;
        if diff {
            if let Some(v) = fixed_scale {
                crate::model::check_range("diff_scale", v as f64, 1e-6, 1e6, "")?;
            }
            let (d, scale) = crate::render::compare::difference_view(&image, &b, fixed_scale);
            image = d;
            diff_scale = Some(scale);
        } else {
            image = crate::render::compare::split_view(&image, &b, split);
        }
    }
    let mut bytes = Vec::new();
    image.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )?;
    crate::fsutil::write_atomic(out, &bytes)
        .with_context(|| format!("{}: cannot write", out.display()))?;
    if let Some(path) = stats_path {
        crate::fsutil::write_atomic(path, serde_json::to_string_pretty(&stats)?.as_bytes())
            .with_context(|| format!("{}: cannot write", path.display()))?;
    }
    println!(
        "wrote {} ({}×{}, {}, passes: {})",
        out.display(),
        width,
        height,
        stats.adapter,
        stats
            .passes
            .iter()
            .map(|p| p.name)
            .collect::<Vec<_>>()
            .join(", ")
    );
    if let Some(scale) = diff_scale {
        println!("difference heat map: top of the colour bar = |ΔL| {scale:.5} (linear luminance)");
    }
    Ok(())
}

fn transmittance(model: &ModelArgs, thickness: &[f64], as_json: bool) -> Result<()> {
    let (_, p) = built(model)?;
    checked_list("thickness", thickness)?;
    let t: Vec<Rgb> = thickness.iter().map(|&d| p.transmittance(d)).collect();
    if as_json {
        println!("{}", json!({ "thickness_mm": thickness, "T": t }));
    } else {
        println!(
            "{:>12}  {:>12} {:>12} {:>12}",
            "d (mm)", "T R", "T G", "T B"
        );
        for (d, v) in thickness.iter().zip(&t) {
            println!("{d:>12.5}  {:>12.6e} {:>12.6e} {:>12.6e}", v[0], v[1], v[2]);
        }
    }
    Ok(())
}

fn fit(model: &ModelArgs, to: &str, as_json: bool) -> Result<()> {
    let (_, p) = built(model)?;
    let target = p.as_ref();
    let (params, err) = match to {
        "burley" => {
            let f = fit_burley(target)?;
            (
                json!({ "albedo": rgb(f.model.albedo()), "scattering_distance_mm": rgb(f.model.scattering_distance_mm()) }),
                f.max_error(),
            )
        }
        "jimenez" | "jimenez2012" => {
            let f = fit_jimenez(target)?;
            (
                json!({ "strength": rgb(f.model.strength()), "falloff": rgb(f.model.falloff()) }),
                f.max_error(),
            )
        }
        "artist" => {
            let f = fit_artist(target)?;
            let m = &f.model;
            (
                json!({ "sigma_near": rgb(m.sigma_near()), "sigma_far": rgb(m.sigma_far()), "weight": m.weight(), "scale_mm": m.scale_mm() }),
                f.max_error(),
            )
        }
        other => {
            let Some(n) = other.strip_prefix("gaussians:") else {
                bail!("--to must be burley, jimenez, artist or gaussians:N (got `{other}`)");
            };
            let n: usize = n.parse().map_err(|_| {
                anyhow::anyhow!("--to gaussians:N needs a whole number N (got `{n}`)")
            })?;
            let f = fit_gaussians(target, n)?;
            let terms: Vec<Value> = (0..n)
                .map(|k| {
                    let t: Vec<_> = (0..3).map(|c| f.model.channel_terms(c)[k]).collect();
                    json!({ "variance_mm2": t[0].variance_mm2, "weights": [t[0].weight, t[1].weight, t[2].weight] })
                })
                .collect();
            (json!({ "gaussians": terms }), f.max_error())
        }
    };
    if as_json {
        println!("{}", json!({ "params": params, "relative_l2_error": err }));
    } else {
        println!("fitted {to}: {}", serde_json::to_string_pretty(&params)?);
        println!("relative L2 error of r·R(r) to the 99.7 % radius (worst channel): {err:.6}");
    }
    Ok(())
}

fn convert(model: &ModelArgs, to: Engine, world_scale: Option<f64>, as_json: bool) -> Result<()> {
    let (spec, p) = built(model)?;
    let (burley, fit_error) = match &spec {
        ProfileSpec::Burley(b) => (b.build()?, 0.0),
        _ => {
            let f = fit_burley(p.as_ref())?;
            let e = f.max_error();
            (f.model, e)
        }
    };
    let params = engine_params(&burley, to, world_scale)?;
    if as_json {
        println!(
            "{}",
            json!({ "engine": format!("{to:?}").to_lowercase(), "burley_fit_relative_l2_error": fit_error, "params": params })
        );
    } else {
        if fit_error > 0.0 {
            println!(
                "(converted through a Burley fit; relative L2 error of r·R(r): {fit_error:.6})"
            );
        }
        println!("{}", serde_json::to_string_pretty(&params)?);
    }
    Ok(())
}

/// Engine parameters of a Burley profile as JSON, with units in the keys.
pub fn engine_params(b: &Burley, to: Engine, world_scale: Option<f64>) -> Result<Value> {
    Ok(match to {
        Engine::Unity => {
            let u = UnityProfile::from_burley(b, world_scale.unwrap_or(1.0))?;
            json!({
                "scattering_distance_color": rgb(u.scattering_distance_color),
                "scattering_distance_multiplier": u.scattering_distance_multiplier,
                "world_scale_m_per_unit": u.world_scale_m_per_unit,
                "albedo_for_material": rgb(b.albedo()),
            })
        }
        Engine::Unreal => {
            let u = UnrealProfile::from_burley(
                b,
                world_scale.unwrap_or(UNREAL_DEFAULT_WORLD_UNIT_SCALE),
            )?;
            json!({
                "surface_albedo": rgb(u.surface_albedo),
                "mean_free_path_color": rgb(u.mean_free_path_color),
                "mean_free_path_distance_cm": u.mean_free_path_distance_cm,
                "world_unit_scale": u.world_unit_scale,
                "struct_text": u.to_struct_text(),
            })
        }
        Engine::Blender => {
            let u = BlenderSubsurface::from_burley(b, world_scale.unwrap_or(1.0))?;
            json!({
                "base_color": rgb(u.base_color),
                "subsurface_radius": rgb(u.subsurface_radius),
                "subsurface_scale": u.subsurface_scale,
                "metres_per_unit": u.metres_per_unit,
                "subsurface_method": "Christensen-Burley",
            })
        }
    })
}

/// A Burley profile (used by tests and exporters).
pub fn burley_from(spec: &ProfileSpec) -> Option<Burley> {
    match spec {
        ProfileSpec::Burley(b) => b.build().ok(),
        _ => None,
    }
}

fn stress(cases: usize, seed: u64, model: Option<&str>, json: bool) -> Result<()> {
    crate::model::check_range("cases", cases as f64, 2.0, 1e6, "")?;
    let names = crate::model::stress::model_names();
    if let Some(m) = model.filter(|m| !names.contains(m)) {
        bail!("--model {m}: unknown; known: {}", names.join(", "));
    }
    // Progress on stderr, about every 5 %: the sweep takes minutes.
    let started = std::time::Instant::now();
    let last = std::sync::Mutex::new(0usize);
    let report = crate::model::stress::run_with_progress(cases, seed, model, |done, total| {
        let step = (total / 20).max(1);
        let Ok(mut last) = last.lock() else {
            return;
        };
        if done == total || done >= *last + step {
            *last = done;
            eprintln!(
                "stress: {done}/{total} cases, {:.0} s",
                started.elapsed().as_secs_f64()
            );
        }
    });
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "{:<16} {:>6} {:>10} {:>9} {:>10} {:>10} {:>10} {:>10}",
            "model", "cases", "values", "NaN/Inf", "R rel", "CDF rel", "inv rel", "kernel"
        );
        for m in &report.models {
            println!(
                "{:<16} {:>6} {:>10} {:>9} {:>10.2e} {:>10.2e} {:>10.2e} {:>10.2e}",
                m.model,
                m.cases,
                m.evaluations,
                m.non_finite,
                m.worst_r_rel,
                m.worst_cdf_rel,
                m.worst_inverse_rel,
                m.worst_kernel_norm
            );
        }
        for m in report.models.iter().filter(|m| m.non_finite > 0) {
            println!("{}: first NaN/Inf: {}", m.model, m.non_finite_at);
        }
    }
    if report.total_non_finite() > 0 {
        bail!("{} NaN or Inf values", report.total_non_finite());
    }
    Ok(())
}
