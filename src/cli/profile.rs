//! `scatterlab profile`: R(r), r·R(r), the CDF, total reflectance and the
//! 99.7 % radius of a profile.

use super::args::{parse_list, ModelArgs, NumberList};
use super::{built, checked_list, rgb};
use crate::model::{Rgb, DEFAULT_ENERGY_FRACTION};
use anyhow::Result;
use serde_json::json;

#[derive(Debug, clap::Args)]
pub struct ProfileArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    /// Radii (mm); default: 24 radii up to twice the widest 99.7 % radius.
    #[arg(long, allow_hyphen_values = true, value_parser = parse_list, value_name = "R1,R2,…")]
    pub radii: Option<NumberList>,
    #[arg(long)]
    pub json: bool,
}

impl ProfileArgs {
    pub fn run(self) -> Result<()> {
        profile(&self.model, self.radii, self.json)
    }
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
