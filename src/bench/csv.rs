//! The one reader of the CSV files `bench` writes (`results.csv`,
//! `floor.csv`, `skip.csv`), for `--replot`: the header checked, each
//! line split into fields, numbers read with the file and line named.

use anyhow::{Context as _, Result};
use std::path::Path;

/// One data line of a bench CSV.
pub struct Record {
    pub fields: Vec<String>,
    /// "FILE line N", for messages.
    pub at: String,
}

impl Record {
    /// Fails unless the line has one of `counts` fields.
    pub fn expect_fields(&self, counts: &[usize]) -> Result<()> {
        anyhow::ensure!(
            counts.contains(&self.fields.len()),
            "{}: {} fields, expected {}",
            self.at,
            self.fields.len(),
            counts.last().copied().unwrap_or(0)
        );
        Ok(())
    }

    /// Field `k` as text.
    pub fn text(&self, k: usize) -> &str {
        self.fields.get(k).map_or("", String::as_str)
    }

    /// Field `k` as a finite number.
    pub fn num(&self, k: usize) -> Result<f64> {
        self.text(k)
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .with_context(|| {
                format!(
                    "{}: field {} = {:?} is not a finite number",
                    self.at,
                    k + 1,
                    self.text(k)
                )
            })
    }

    /// Field `k` as a finite number, or `None` where it is empty.
    pub fn opt_num(&self, k: usize) -> Result<Option<f64>> {
        if self.text(k).is_empty() {
            return Ok(None);
        }
        self.num(k).map(Some)
    }

    /// Field `k`, which must be one of `list`.
    pub fn one_of(&self, k: usize, list: &[&'static str]) -> Result<&'static str> {
        list.iter()
            .copied()
            .find(|x| *x == self.text(k))
            .with_context(|| format!("{}: unknown {}", self.at, self.text(k)))
    }
}

/// The data lines of a CSV `bench` wrote at `path`, after checking its
/// header; each split at commas into at most `max_fields` fields (the last
/// keeps any commas of its own).
pub fn read(path: &Path, header: &str, max_fields: usize) -> Result<Vec<Record>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut lines = text.lines();
    anyhow::ensure!(
        lines.next() == Some(header),
        "{}: not a file `bench` wrote (the header differs)",
        path.display()
    );
    Ok(lines
        .enumerate()
        .map(|(i, line)| Record {
            fields: line.splitn(max_fields, ',').map(str::to_string).collect(),
            at: format!("{} line {}", path.display(), i + 2),
        })
        .collect())
}
