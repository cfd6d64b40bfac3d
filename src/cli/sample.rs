//! `scatterlab sample`: Burley radii by the inverse CDF, and disk sample
//! patterns.

use super::args::{parse_list, ModelArgs, NumberList};
use super::{built, rgb};
use crate::model::burley::{sample_radius_checked, sample_radius_halley};
use crate::model::sampling::{AngleSequence, SamplePattern};
use anyhow::{Context, Result};
use clap::{Subcommand, ValueEnum};
use serde_json::{json, Value};

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

impl SampleCommand {
    pub fn run(self) -> Result<()> {
        match self {
            SampleCommand::Burley {
                shape,
                xi,
                method,
                json,
            } => sample_burley(shape, &xi.0, method, json),
            SampleCommand::Pattern {
                model,
                samples,
                angles,
                json,
            } => pattern(&model, samples, angles, json),
        }
    }
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
