//! `scatterlab convert`: a profile in an engine's parameters (through a
//! Burley fit when needed).

use super::args::ModelArgs;
use super::built;
use crate::export::{import_file, Format, ImportOptions};
use anyhow::{bail, Context, Result};
use serde_json::{json, Value};
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct ConvertArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    /// Engine files to convert, or folders of them (batch): each look in
    /// each file is written in --to's format into --out, with a summary
    /// line per file. Without --from the model flags give the profile and
    /// its engine parameters are printed (--to unity, unreal or blender).
    #[arg(long, num_args = 1.., value_name = "FILE|DIR")]
    pub from: Vec<PathBuf>,
    #[arg(long, value_enum)]
    pub to: Format,
    /// The folder the converted files go into (with --from; created if
    /// missing).
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Unity: metres per unit (default 1). Unreal: World Unit Scale (default 0.1). Blender: metres per unit (default 1).
    #[arg(long, allow_hyphen_values = true)]
    pub world_scale: Option<f64>,
    /// With --from: metres per unit of files that do not state theirs.
    #[arg(long, allow_hyphen_values = true, value_name = "M")]
    pub metres_per_unit: Option<f64>,
    /// With --from: replace files that exist.
    #[arg(long)]
    pub force: bool,
    #[arg(long)]
    pub json: bool,
}

impl ConvertArgs {
    pub fn run(self) -> Result<()> {
        if !self.from.is_empty() {
            return convert_files(&self);
        }
        let Some(params) = self.to.target().params else {
            bail!(
                "--to {}: engine parameters are printed for {}; to write {} files give --from FILE… --out DIR",
                self.to.id(),
                Format::all()
                    .iter()
                    .filter(|f| f.target().params.is_some())
                    .map(|f| f.id())
                    .collect::<Vec<_>>()
                    .join(", "),
                self.to.id()
            );
        };
        convert(&self.model, self.to, params, self.world_scale, self.json)
    }
}

fn convert(
    model: &ModelArgs,
    to: Format,
    params_of: crate::export::EngineParams,
    world_scale: Option<f64>,
    as_json: bool,
) -> Result<()> {
    let (spec, _) = built(model)?;
    let (burley, fit_error) = crate::export::burley_of(&spec)?;
    let params = params_of(&burley, world_scale)?;
    if as_json {
        println!(
            "{}",
            json!({ "engine": to.id(), "burley_fit_relative_l2_error": fit_error, "params": params })
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

/// The importable files among `paths` (folders: their files, not deeper).
fn expand(paths: &[PathBuf]) -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut files: Vec<PathBuf> = std::fs::read_dir(p)
                .with_context(|| format!("{}: cannot list the folder", p.display()))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| {
                    f.is_file()
                        && f.extension().is_some_and(|x| {
                            crate::export::importable_extensions(true)
                                .contains(&x.to_string_lossy().to_ascii_lowercase().as_str())
                        })
                })
                .collect();
            files.sort();
            out.extend(files);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

/// `convert --from`: every look of every file written in `--to`'s format
/// into `--out`, a summary line per file; non-zero if any file failed.
fn convert_files(args: &ConvertArgs) -> Result<()> {
    let out = args
        .out
        .as_ref()
        .context("--from needs --out DIR: the folder the converted files go into")?;
    std::fs::create_dir_all(out)
        .with_context(|| format!("{}: cannot create the folder", out.display()))?;
    let options = ImportOptions {
        metres_per_unit: args.metres_per_unit,
    };
    let files = expand(&args.from)?;
    if files.is_empty() {
        bail!("--from: no engine files found");
    }
    let mut failed = 0;
    let mut summary = Vec::new();
    for file in &files {
        let line = (|| -> Result<Value> {
            let looks = import_file(file, &options)?;
            let stem = file
                .file_stem()
                .map(|s| s.to_string_lossy().into_owned())
                .unwrap_or_else(|| "look".into());
            let mut converted = Vec::new();
            for (i, l) in looks.iter().enumerate() {
                let name = if looks.len() == 1 {
                    stem.clone()
                } else {
                    format!(
                        "{stem}_{}",
                        crate::export::import::file_stem_of(&l.preset.name)
                    )
                };
                let _ = i;
                let target = out.join(format!("{name}.{}", args.to.extension()));
                let planned = crate::export::planned_paths(args.to, &target);
                if !args.force {
                    if let Some(p) = planned.iter().find(|p| p.exists()) {
                        bail!("{}: exists; pass --force to replace it", p.display());
                    }
                }
                let written = crate::export::export(&l.preset, Some(file), args.to, &target)?;
                converted.push(json!({
                    "look": l.preset.name,
                    "kind": l.kind,
                    "written": written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
                    "round_trip_relative_l2_error": (args.to.target().fidelity)(&l.preset),
                }));
            }
            Ok(json!({ "file": file.display().to_string(), "looks": converted }))
        })();
        match line {
            Ok(v) => {
                if !args.json {
                    for l in v["looks"].as_array().into_iter().flatten() {
                        let err = l["round_trip_relative_l2_error"]
                            .as_f64()
                            .map(|e| {
                                if e == 0.0 {
                                    "; the format holds the look exactly".to_owned()
                                } else {
                                    format!("; the engine draws it {e:.4} from the look (relative L2 error of r·R(r))")
                                }
                            })
                            .unwrap_or_default();
                        println!(
                            "{}: {} \"{}\" → {}{err}",
                            file.display(),
                            l["kind"].as_str().unwrap_or(""),
                            l["look"].as_str().unwrap_or(""),
                            l["written"]
                                .as_array()
                                .map(|w| w
                                    .iter()
                                    .filter_map(|p| p.as_str())
                                    .collect::<Vec<_>>()
                                    .join(", "))
                                .unwrap_or_default()
                        );
                    }
                }
                summary.push(v);
            }
            Err(e) => {
                failed += 1;
                if !args.json {
                    println!(
                        "{}: FAILED: {}",
                        file.display(),
                        one_line(&e.to_string(), file)
                    );
                }
                summary.push(json!({ "file": file.display().to_string(), "error": one_line(&e.to_string(), file) }));
            }
        }
    }
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({ "files": summary }))?
        );
    }
    if failed > 0 {
        bail!(
            "{failed} of {} file(s) could not be converted (see above)",
            files.len()
        );
    }
    Ok(())
}

/// An error without the file name it starts with.
fn one_line(message: &str, file: &std::path::Path) -> String {
    let prefix = format!("{}: ", file.display());
    message
        .strip_prefix(&prefix)
        .unwrap_or(message)
        .replace('\n', " ")
}
