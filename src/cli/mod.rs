//! The scripting interface: subcommands that print the same numbers the
//! editor shows. `--json` prints exactly the documented keys; bad input
//! exits non-zero with a one-line error on stderr.

pub mod args;
pub mod bench;
pub mod budget;
pub mod convert;
pub mod edit;
pub mod export;
pub mod fit;
pub mod import;
pub mod kernel;
pub mod lut;
pub mod profile;
pub mod render;
pub mod sample;
pub mod stress;
pub mod transmittance;
pub mod view;

use crate::model::{check_radius, RadialProfile, Rgb};
use crate::settings::ProfileSpec;
use anyhow::Result;
use args::ModelArgs;
use clap::{Parser, Subcommand};
use serde_json::{json, Value};

#[derive(Debug, Parser)]
#[command(name = "scatterlab", version, about = "Author subsurface-scattering diffusion profiles.", long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// One variant per subcommand, each with its own `Args` struct and file
/// (`cli/<name>.rs`) whose `run` does the work.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Open the editor (the default with no subcommand), optionally on a preset.
    Edit(edit::EditArgs),
    /// R(r), r·R(r), CDF, total reflectance and 99.7 % radius of a profile.
    Profile(profile::ProfileArgs),
    /// Sample radii and patterns.
    #[command(subcommand)]
    Sample(sample::SampleCommand),
    /// 1D separable kernels.
    #[command(subcommand)]
    Kernel(kernel::KernelCommand),
    /// Lookup tables.
    #[command(subcommand)]
    Lut(lut::LutCommand),
    /// Thin-slab transmittance T(d) = ∫2πr R(√(r²+d²)) dr.
    Transmittance(transmittance::TransmittanceArgs),
    /// Fit another model to a profile; the error is the relative L2 error of r·R(r) to the 99.7 % radius.
    Fit(fit::FitArgs),
    /// Render the head offscreen with an SSS method and write a PNG.
    /// (`--albedo` is the albedo map here; the Burley volume albedo of
    /// `--model burley` is `--volume-albedo`.) The look is the preset's
    /// (`--preset`) or the default skin, with any of its rendering
    /// settings overridden by the flags.
    #[command(mut_arg("albedo", |a| a.long("volume-albedo")))]
    Render(Box<render::RenderArgs>),
    /// Write a look for an engine or tool: a preset (--preset), or a
    /// profile from --model and its flags as every command takes one (with
    /// the default rendering settings; no flags: the default skin). Files
    /// are written atomically; formats with comments or metadata record
    /// the scatterlab version and the preset. Some formats write a
    /// companion file beside --out (unreal: .py; lut-*: _shadow; profile-*:
    /// _transmittance).
    Export(export::ExportArgs),
    /// Run-time against error of every SSS method and count on fixed
    /// scenes, against `reference`; writes results.csv, skip.csv, one chart
    /// per scene and accuracy.md into --out.
    Bench(bench::BenchArgs),
    /// Sweep every model across its documented parameter range against
    /// independent references: worst relative errors of R, the CDF and the
    /// inverse CDF, kernel normalisation, and the count of NaN/Inf.
    Stress(stress::StressArgs),
    /// Express a profile in an engine's parameters (via a Burley fit when needed).
    Convert(convert::ConvertArgs),
    /// Read an engine's file (Unity HDRP .asset, Unreal, MaterialX, Godot,
    /// Blender) back into looks: the look the engine renders from it, the
    /// file's own fields and what had to be assumed; --out writes presets.
    Import(import::ImportArgs),
    /// Fit a Unity project's HDRP diffusion profiles into the list's slots
    /// (15): which to merge, what each merge costs the materials that use
    /// it (shape error, tint ΔE, head renders with ΔL*), the merged
    /// profiles, a Diffusion Profile List, a remap table and a report;
    /// with --apply, into the project (with a backup).
    Budget(budget::BudgetArgs),
}

/// Runs a parsed command; no subcommand opens the editor.
pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        None => edit::EditArgs::default().run(),
        Some(Command::Edit(a)) => a.run(),
        Some(Command::Profile(a)) => a.run(),
        Some(Command::Sample(a)) => a.run(),
        Some(Command::Kernel(a)) => a.run(),
        Some(Command::Lut(a)) => a.run(),
        Some(Command::Transmittance(a)) => a.run(),
        Some(Command::Fit(a)) => a.run(),
        Some(Command::Render(a)) => a.run(),
        Some(Command::Export(a)) => a.run(),
        Some(Command::Bench(a)) => a.run(),
        Some(Command::Stress(a)) => a.run(),
        Some(Command::Convert(a)) => a.run(),
        Some(Command::Import(a)) => a.run(),
        Some(Command::Budget(a)) => a.run(),
    }
}

/// The profile the model flags describe, and its model.
fn built(model: &ModelArgs) -> Result<(ProfileSpec, Box<dyn RadialProfile>)> {
    let spec = model.spec()?;
    let p = spec.build()?;
    Ok((spec, p))
}

/// Every value a valid radius, named `field[i]`.
fn checked_list(field: &str, values: &[f64]) -> Result<()> {
    for (i, v) in values.iter().enumerate() {
        check_radius(&format!("{field}[{i}]"), *v)?;
    }
    Ok(())
}

fn rgb(v: Rgb) -> Value {
    json!(v)
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
