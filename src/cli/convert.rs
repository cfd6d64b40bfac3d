//! `scatterlab convert`: a profile in an engine's parameters (through a
//! Burley fit when needed).

use super::args::ModelArgs;
use super::built;
use crate::export::{import_file, Format, ImportOptions};
use anyhow::{bail, Context, Result};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

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

/// The files `--from` names: a file as given, and a folder's files with
/// an importable extension, in its subfolders too (sorted; hidden files
/// and folders, such as `.git`, and links to folders are not followed).
/// Each with whether it was found in a folder: a folder's file that is no
/// engine profile (a README, a material, binary data) is skipped, where a
/// file named on its own is refused.
pub(super) fn expand(paths: &[PathBuf]) -> Result<Vec<(PathBuf, bool)>> {
    let extensions = crate::export::importable_extensions(true);
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let mut files = Vec::new();
            walk(p, &extensions, &mut files)?;
            files.sort();
            out.extend(files.into_iter().map(|f| (f, true)));
        } else {
            out.push((p.clone(), false));
        }
    }
    Ok(out)
}

/// The files under `dir` with one of `extensions`, depth first.
fn walk(dir: &Path, extensions: &[&str], out: &mut Vec<PathBuf>) -> Result<()> {
    let entries = std::fs::read_dir(dir)
        .with_context(|| format!("{}: cannot list the folder", dir.display()))?;
    for entry in entries {
        let entry = entry.with_context(|| format!("{}: cannot list the folder", dir.display()))?;
        let path = entry.path();
        if entry.file_name().to_string_lossy().starts_with('.') {
            continue;
        }
        let Ok(kind) = entry.file_type() else {
            continue;
        };
        if kind.is_dir() {
            walk(&path, extensions, out)?;
        } else if (kind.is_file() || kind.is_symlink() && path.is_file())
            && path.extension().is_some_and(|x| {
                extensions.contains(&x.to_string_lossy().to_ascii_lowercase().as_str())
            })
        {
            out.push(path);
        }
    }
    Ok(())
}

/// Every file of a batch read: each file's looks (or why it failed), the
/// folders' files that are no engine profile (skipped, with why), and which
/// looks to write: a look met in several files is kept once, from the file
/// with the fewest looks (a profile's own asset rather than a list that
/// names it).
pub(super) struct Batch {
    pub read: Vec<(PathBuf, Result<Vec<crate::export::ImportedLook>>)>,
    pub skipped: Vec<(PathBuf, String)>,
    /// Per file, per look: whether it is written.
    pub keep: Vec<Vec<bool>>,
    /// Per file: its looks written from other files.
    pub repeated: Vec<usize>,
}

/// Reads `files` (from [`expand`]) as [`Batch`] says.
pub(super) fn read_all(files: &[(PathBuf, bool)], options: &ImportOptions) -> Batch {
    let mut read: Vec<(PathBuf, Result<Vec<crate::export::ImportedLook>>)> = Vec::new();
    let mut skipped: Vec<(PathBuf, String)> = Vec::new();
    for (file, in_folder) in files {
        match import_file(file, options) {
            Err(e) if *in_folder && e.is_not_engine() => {
                skipped.push((file.clone(), one_line(&e.to_string(), file)));
            }
            r => read.push((file.clone(), r.map_err(anyhow::Error::from))),
        }
    }
    let mut order: Vec<usize> = (0..read.len()).collect();
    order.sort_by_key(|&i| read[i].1.as_ref().map_or(0, Vec::len));
    let mut seen: Vec<crate::settings::Preset> = Vec::new();
    let mut repeated = vec![0usize; read.len()];
    let mut keep: Vec<Vec<bool>> = read
        .iter()
        .map(|(_, r)| vec![true; r.as_ref().map_or(0, Vec::len)])
        .collect();
    for i in order {
        if let Ok(looks) = &read[i].1 {
            for (k, l) in looks.iter().enumerate() {
                if seen.contains(&l.preset) {
                    keep[i][k] = false;
                    repeated[i] += 1;
                } else {
                    seen.push(l.preset.clone());
                }
            }
        }
    }
    Batch {
        read,
        skipped,
        keep,
        repeated,
    }
}

/// The last line of a batch: files converted, failed and skipped (the
/// first five skipped named).
pub(super) fn counts_line(
    verb: &str,
    done: usize,
    failed: usize,
    skipped: &[(PathBuf, String)],
) -> String {
    format!(
        "{done} file(s) {verb}, {failed} failed, {} skipped (not engine profiles{})",
        skipped.len(),
        if skipped.is_empty() {
            String::new()
        } else {
            let shown: Vec<String> = skipped
                .iter()
                .take(5)
                .map(|(f, _)| f.display().to_string())
                .collect();
            let more = skipped.len().saturating_sub(shown.len());
            format!(
                ": {}{}",
                shown.join(", "),
                if more > 0 {
                    format!(" and {more} more; --json lists each with why")
                } else {
                    String::new()
                }
            )
        }
    )
}

/// `convert --from`: every look of every file written in `--to`'s format
/// into `--out`, a summary line per file; non-zero if any file failed.
/// Found in folders, files that are no engine profile are skipped and
/// counted, and a look read twice (a Unity profile list beside the
/// profiles it names) is written once, from the file with the fewest
/// looks (the profile's own).
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
        bail!(
            "--from: no engine files found (looked for {} files, in subfolders too)",
            crate::export::importable_extensions(true)
                .iter()
                .map(|e| format!(".{e}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
    }
    let Batch {
        read,
        skipped,
        keep,
        repeated,
    } = read_all(&files, &options);
    if read.is_empty() {
        bail!(
            "--from: no engine profile found; {}",
            counts_line("converted", 0, 0, &skipped)
        );
    }
    let mut failed = 0;
    let mut summary = Vec::new();
    for (i, (file, looks)) in read.iter().enumerate() {
        let line = looks
            .as_ref()
            .map_err(|e| anyhow::anyhow!("{e:#}"))
            .and_then(|looks| convert_file(args, out, (file, looks), &keep[i], repeated[i]));
        match line {
            Ok(v) => {
                if !args.json {
                    print_converted(file, &v, repeated[i]);
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
    let converted = read.len() - failed;
    if args.json {
        println!(
            "{}",
            serde_json::to_string_pretty(&json!({
                "files": summary,
                "skipped": skipped
                    .iter()
                    .map(|(f, why)| json!({ "file": f.display().to_string(), "why": why }))
                    .collect::<Vec<_>>(),
                "converted_files": converted,
                "failed_files": failed,
            }))?
        );
    } else {
        println!("{}", counts_line("converted", converted, failed, &skipped));
    }
    if failed > 0 {
        bail!(
            "{failed} of {} file(s) could not be converted (see above)",
            read.len()
        );
    }
    Ok(())
}

/// Converts the looks of one engine `file` that `keep` marks (the others
/// were written from their own files: `repeated` of them) into `out`, as
/// `args.to`; what was written, for the summary.
fn convert_file(
    args: &ConvertArgs,
    out: &std::path::Path,
    (file, looks): (&std::path::Path, &Vec<crate::export::ImportedLook>),
    keep: &[bool],
    repeated: usize,
) -> Result<Value> {
    let stem = file
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "look".into());
    let mut converted = Vec::new();
    for (k, l) in looks.iter().enumerate() {
        if !keep[k] {
            continue;
        }
        let name = if looks.len() == 1 {
            stem.clone()
        } else {
            format!(
                "{stem}_{}",
                crate::export::import::file_stem_of(&l.preset.name)
            )
        };
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
    Ok(json!({
        "file": file.display().to_string(),
        "looks": converted,
        "looks_read_from_other_files": repeated,
    }))
}

/// The lines printed for a file converted: each look, what it was written
/// to and how far the engine draws it from the look.
fn print_converted(file: &std::path::Path, v: &Value, repeated: usize) {
    for l in v["looks"].as_array().into_iter().flatten() {
        let err = l["round_trip_relative_l2_error"]
            .as_f64()
            .map(|e| {
                if e == 0.0 {
                    "; the format holds the look exactly".to_owned()
                } else {
                    format!(
                        "; the engine draws it {e:.4} from the look (relative L2 error of r·R(r))"
                    )
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
    if repeated > 0 {
        println!(
            "{}: {} look(s) it names were written from their own files",
            file.display(),
            repeated
        );
    }
}

/// An error without the file name it starts with.
pub(super) fn one_line(message: &str, file: &std::path::Path) -> String {
    let prefix = format!("{}: ", file.display());
    message
        .strip_prefix(&prefix)
        .unwrap_or(message)
        .replace('\n', " ")
}
