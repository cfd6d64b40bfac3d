//! `scatterlab bench`: run time against error of every SSS method
//! (`crate::bench`).

use anyhow::Result;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Smaller frames and one timed frame per configuration (a few
    /// minutes on 2 cores; what CI runs).
    #[arg(long)]
    pub quick: bool,
    /// The look to measure (default: the embedded skin preset).
    #[arg(long, value_name = "FILE.ron")]
    pub preset: Option<PathBuf>,
    /// Only redraw the charts and accuracy.md from --out's results.csv
    /// and skip.csv (no rendering).
    #[arg(long)]
    pub replot: bool,
    /// Also gather each scene's ground truth on the GPU (`truth.csv`,
    /// `render --reference-gpu`): its time and its distance from the CPU's.
    #[arg(long)]
    pub reference_gpu: bool,
}

impl BenchArgs {
    pub fn run(self) -> Result<()> {
        if self.replot {
            crate::bench::replot(&self.out, self.quick)
        } else {
            crate::bench::run_cli(
                &self.out,
                self.quick,
                self.preset.as_deref(),
                self.reference_gpu,
            )
        }
    }
}
