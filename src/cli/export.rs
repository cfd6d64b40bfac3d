//! `scatterlab export`: a preset written for an engine or tool.

use anyhow::Result;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    /// The preset (.ron).
    #[arg(long, value_name = "FILE.ron")]
    pub preset: PathBuf,
    #[arg(long, value_enum)]
    pub format: crate::export::Format,
    #[arg(long, value_name = "PATH")]
    pub out: PathBuf,
}

impl ExportArgs {
    pub fn run(self) -> Result<()> {
        let p = crate::settings::Preset::load(&self.preset)?;
        for path in crate::export::export(&p, Some(&self.preset), self.format, &self.out)? {
            println!("{}", path.display());
        }
        Ok(())
    }
}
