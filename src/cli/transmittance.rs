//! `scatterlab transmittance`: the thin-slab transmittance
//! T(d) = ∫2πr R(√(r²+d²)) dr.

use super::args::{parse_list, ModelArgs, NumberList};
use super::{built, checked_list};
use crate::model::Rgb;
use anyhow::Result;
use serde_json::json;

#[derive(Debug, clap::Args)]
pub struct TransmittanceArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    /// Thicknesses (mm).
    #[arg(long, allow_hyphen_values = true, value_parser = parse_list, value_name = "D1,D2,…")]
    pub thickness: NumberList,
    #[arg(long)]
    pub json: bool,
}

impl TransmittanceArgs {
    pub fn run(self) -> Result<()> {
        transmittance(&self.model, &self.thickness.0, self.json)
    }
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
