//! `scatterlab import`: an engine's file read back into looks.

use crate::export::{import_file, ImportOptions, ImportedLook};
use anyhow::{bail, Context, Result};
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

#[derive(Debug, clap::Args)]
pub struct ImportArgs {
    /// The engine's file: Unity HDRP .asset, Unreal struct text or .py,
    /// MaterialX .mtlx, Godot .tres, Blender .py or a preset .ron. Or a
    /// folder (a Unity project): every profile in it and its subfolders,
    /// skipping what is no engine profile, with a count.
    #[arg(value_name = "FILE|DIR")]
    pub file: PathBuf,
    /// Where the look goes (.ron). A file that holds several profiles, or
    /// a folder, writes one preset each into this folder instead.
    #[arg(long, value_name = "LOOK.ron")]
    pub out: Option<PathBuf>,
    /// Metres per unit of the file's distances where the file does not
    /// say (MaterialX without units, Godot, Blender's scene).
    #[arg(long, value_name = "M", allow_hyphen_values = true)]
    pub metres_per_unit: Option<f64>,
    /// Print the looks (profile, rendering fields, the file's own fields,
    /// notes) as JSON.
    #[arg(long)]
    pub json: bool,
    /// Replace files that exist.
    #[arg(long)]
    pub force: bool,
}

impl ImportArgs {
    pub fn run(self) -> Result<()> {
        if let Some(m) = self.metres_per_unit {
            crate::model::check_range("--metres-per-unit", m, 1e-6, 1e6, " m/unit")?;
        }
        let options = ImportOptions {
            metres_per_unit: self.metres_per_unit,
        };
        if self.file.is_dir() {
            return self.import_folder(&options);
        }
        let looks = import_file(&self.file, &options)?;
        let written = match &self.out {
            Some(out) => write_looks(&looks, out, self.force)?,
            None => Vec::new(),
        };
        if self.json {
            let v: Vec<Value> = looks
                .iter()
                .zip(written.iter().map(Some).chain(std::iter::repeat(None)))
                .map(|(l, w)| look_json(l, w.map(PathBuf::as_path)))
                .collect();
            println!(
                "{}",
                serde_json::to_string_pretty(
                    &json!({ "file": self.file.display().to_string(), "looks": v })
                )?
            );
        } else {
            let mut text = String::new();
            for (i, l) in looks.iter().enumerate() {
                text += &format!(
                    "{}: {} \"{}\"\n",
                    self.file.display(),
                    l.kind,
                    l.preset.name
                );
                for (k, v) in &l.fields {
                    text += &format!("  {k}: {v}\n");
                }
                for n in &l.notes {
                    text += &format!("  note: {n}\n");
                }
                if let Some(w) = written.get(i) {
                    text += &format!("  wrote {}\n", w.display());
                }
            }
            // A closed pipe (`| head`) is not an error of the import.
            use std::io::Write;
            let _ = std::io::stdout().lock().write_all(text.as_bytes());
        }
        Ok(())
    }
}

impl ImportArgs {
    /// `import DIR`: every look of every profile under the folder (as
    /// `convert --from` reads a folder: subfolders, non-profiles skipped
    /// and counted, a look a list names once), printed a line each and,
    /// with `--out`, written one preset each into that folder. Non-zero if
    /// a profile failed; the others are still read and written.
    fn import_folder(&self, options: &ImportOptions) -> Result<()> {
        use super::convert::{counts_line, expand, one_line, read_all};
        let files = expand(std::slice::from_ref(&self.file))?;
        let batch = read_all(&files, options);
        let mut looks: Vec<ImportedLook> = Vec::new();
        let mut sources: Vec<&Path> = Vec::new();
        let mut failed: Vec<(&Path, String)> = Vec::new();
        for (i, (file, read)) in batch.read.iter().enumerate() {
            match read {
                Ok(ls) => {
                    for (k, l) in ls.iter().enumerate() {
                        if batch.keep[i][k] {
                            looks.push(l.clone());
                            sources.push(file);
                        }
                    }
                }
                Err(e) => failed.push((file, one_line(&format!("{e:#}"), file))),
            }
        }
        if looks.is_empty() && failed.is_empty() {
            bail!(
                "{}: no engine profile in the folder or its subfolders ({} file(s) skipped: not engine profiles)",
                self.file.display(),
                batch.skipped.len()
            );
        }
        let written = match &self.out {
            Some(out) if !looks.is_empty() => {
                if out.exists() && !out.is_dir() {
                    bail!(
                        "{}: importing a folder writes one preset per look; --out must be a folder",
                        out.display()
                    );
                }
                std::fs::create_dir_all(out)
                    .with_context(|| format!("{}: cannot create the folder", out.display()))?;
                write_looks(&looks, out, self.force)?
            }
            _ => Vec::new(),
        };
        let done = batch.read.len() - failed.len();
        if self.json {
            let v: Vec<Value> = looks
                .iter()
                .zip(&sources)
                .enumerate()
                .map(|(i, (l, f))| {
                    let mut j = look_json(l, written.get(i).map(PathBuf::as_path));
                    j["file"] = Value::String(f.display().to_string());
                    j
                })
                .collect();
            println!(
                "{}",
                serde_json::to_string_pretty(&json!({
                    "folder": self.file.display().to_string(),
                    "looks": v,
                    "failed": failed.iter().map(|(f, e)| json!({ "file": f.display().to_string(), "error": e })).collect::<Vec<_>>(),
                    "skipped": batch.skipped.iter().map(|(f, why)| json!({ "file": f.display().to_string(), "why": why })).collect::<Vec<_>>(),
                }))?
            );
        } else {
            let mut text = String::new();
            for (i, (l, f)) in looks.iter().zip(&sources).enumerate() {
                text += &format!("{}: {} \"{}\"", f.display(), l.kind, l.preset.name);
                if let Some(w) = written.get(i) {
                    text += &format!(" → {}", w.display());
                }
                text += "\n";
            }
            for (f, e) in &failed {
                text += &format!("{}: FAILED: {e}\n", f.display());
            }
            text += &counts_line("read", done, failed.len(), &batch.skipped);
            text += "\n";
            use std::io::Write;
            let _ = std::io::stdout().lock().write_all(text.as_bytes());
        }
        if !failed.is_empty() {
            bail!(
                "{} of {} file(s) could not be read (see above)",
                failed.len(),
                batch.read.len()
            );
        }
        Ok(())
    }
}

/// Writes one look to `out`, or several into the folder `out`, refusing
/// to replace a file unless `force`.
fn write_looks(looks: &[ImportedLook], out: &Path, force: bool) -> Result<Vec<PathBuf>> {
    let paths: Vec<PathBuf> = if looks.len() == 1 && !out.is_dir() {
        vec![out.to_owned()]
    } else {
        if out.exists() && !out.is_dir() {
            bail!(
                "{}: the file holds {} profiles; --out must be a folder to hold one preset each",
                out.display(),
                looks.len()
            );
        }
        std::fs::create_dir_all(out)
            .with_context(|| format!("{}: cannot create the folder", out.display()))?;
        let mut used = std::collections::HashSet::new();
        looks
            .iter()
            .map(|l| {
                let stem = crate::export::import::file_stem_of(&l.preset.name);
                let mut name = format!("{stem}.ron");
                let mut k = 2;
                while !used.insert(name.clone()) {
                    name = format!("{stem}_{k}.ron");
                    k += 1;
                }
                out.join(name)
            })
            .collect()
    };
    if !force {
        if let Some(p) = paths.iter().find(|p| p.exists()) {
            bail!("{}: exists; pass --force to replace it", p.display());
        }
    }
    for (l, p) in looks.iter().zip(&paths) {
        l.preset.save(p)?;
    }
    Ok(paths)
}

fn look_json(l: &ImportedLook, written: Option<&Path>) -> Value {
    let fields: serde_json::Map<String, Value> = l
        .fields
        .iter()
        .map(|(k, v)| (k.clone(), Value::String(v.clone())))
        .collect();
    json!({
        "kind": l.kind,
        "name": l.preset.name,
        "preset": serde_json::to_value(&l.preset).unwrap_or(Value::Null),
        "fields": fields,
        "notes": l.notes,
        "written": written.map(|p| p.display().to_string()),
    })
}
