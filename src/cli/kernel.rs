//! `scatterlab kernel`: the separable methods' 1D kernels.

use super::args::{parse_color, Color, ModelArgs};
use crate::model::jimenez::Jimenez2012;
use crate::model::separable::SeparableKernel;
use anyhow::Result;
use clap::Subcommand;
use serde_json::json;

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

impl KernelCommand {
    pub fn run(self) -> Result<()> {
        match self {
            KernelCommand::Jimenez {
                strength,
                falloff,
                taps,
                json,
            } => {
                let k = Jimenez2012::new(strength.0, falloff.0)?.kernel(taps)?;
                print_kernel(&k, json)
            }
            KernelCommand::Separable { model, taps, json } => {
                let p = model.spec()?.build()?;
                print_kernel(
                    &SeparableKernel::importance_sampled(p.as_ref(), taps)?,
                    json,
                )
            }
        }
    }
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
