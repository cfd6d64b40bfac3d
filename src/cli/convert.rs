//! `scatterlab convert`: a profile in an engine's parameters (through a
//! Burley fit when needed).

use super::args::ModelArgs;
use super::{built, rgb};
use crate::model::burley::Burley;
use crate::model::fit::fit_burley;
use crate::model::units::{
    BlenderSubsurface, UnityProfile, UnrealProfile, UNREAL_DEFAULT_WORLD_UNIT_SCALE,
};
use crate::settings::ProfileSpec;
use anyhow::Result;
use clap::ValueEnum;
use serde_json::{json, Value};

#[derive(Debug, clap::Args)]
pub struct ConvertArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[arg(long, value_enum)]
    pub to: Engine,
    /// Unity: metres per unit (default 1). Unreal: World Unit Scale (default 0.1). Blender: metres per unit (default 1).
    #[arg(long, allow_hyphen_values = true)]
    pub world_scale: Option<f64>,
    #[arg(long)]
    pub json: bool,
}

impl ConvertArgs {
    pub fn run(self) -> Result<()> {
        convert(&self.model, self.to, self.world_scale, self.json)
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum Engine {
    Unity,
    Unreal,
    Blender,
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
