//! `scatterlab export`: a look written for an engine or tool. The look is
//! a preset (`--preset`: its profile and rendering settings) or, as every
//! other command takes it, a profile from `--model` and its parameters
//! (with the default rendering settings).

use super::args::ModelArgs;
use anyhow::Result;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct ExportArgs {
    #[command(flatten)]
    pub model: ModelArgs,
    #[arg(long, value_enum)]
    pub format: crate::export::Format,
    #[arg(long, value_name = "PATH")]
    pub out: PathBuf,
}

impl ExportArgs {
    pub fn run(self) -> Result<()> {
        let p = match &self.model.preset {
            // The whole look: its name, notes and rendering settings too.
            Some(path) => {
                let p = crate::settings::Preset::load(path)?;
                // The flags describe no more than the file (`spec` says
                // which flags `--preset` takes).
                self.model.spec()?;
                p
            }
            // No flags: the default look, whole.
            None if self.model.model.is_none() => {
                self.model.spec()?;
                crate::settings::Preset::default_skin()
            }
            None => crate::settings::Preset {
                name: "look".into(),
                description: "Exported from scatterlab's command line.".into(),
                source: "scatterlab export --model".into(),
                profile: self.model.spec()?,
                ..Default::default()
            },
        };
        let source = self.model.preset.as_deref();
        for path in crate::export::export(&p, source, self.format, &self.out)? {
            println!("{}", path.display());
        }
        Ok(())
    }
}
