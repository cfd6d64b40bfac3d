//! `scatterlab fit`: another model fitted to a profile.

use super::args::ModelArgs;
use super::{built, rgb};
use crate::model::fit::{fit_artist, fit_burley, fit_gaussians, fit_jimenez};
use anyhow::{bail, Result};
use serde_json::{json, Value};

#[derive(Debug, clap::Args)]
pub struct FitArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    /// burley, jimenez, artist or gaussians:N.
    #[arg(long, value_name = "MODEL")]
    pub to: String,
    #[arg(long)]
    pub json: bool,
}

impl FitArgs {
    pub fn run(self) -> Result<()> {
        fit(&self.model, &self.to, self.json)
    }
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
