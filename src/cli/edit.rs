//! `scatterlab edit` (and no subcommand): the editor.

use crate::settings::rendering::MethodId;
use anyhow::Result;
use clap::ValueEnum;
use std::path::PathBuf;

#[derive(Debug, Default, clap::Args)]
pub struct EditArgs {
    /// The preset (.ron) to open; default: the last one, else the embedded skin.
    #[arg(long, value_name = "FILE.ron")]
    pub preset: Option<PathBuf>,
    /// An engine's file to open as a new look (Unity .asset, Unreal text
    /// or .py, MaterialX .mtlx, Godot .tres, Blender .py): what that
    /// engine draws from it.
    #[arg(long, value_name = "FILE", conflicts_with = "preset")]
    pub import: Option<PathBuf>,
    /// Open on this mesh (OBJ, glTF or GLB) instead of the default head,
    /// with the units and maps remembered for it, else the units prompt.
    #[arg(long, value_name = "FILE")]
    pub mesh: Option<PathBuf>,
    /// With --mesh: metres per unit of the file (0.01 for centimetres),
    /// instead of the remembered units or the prompt.
    #[arg(long, value_name = "M", requires = "mesh")]
    pub metres_per_unit: Option<f32>,
    /// Close the window once the head has been shown (start-up smoke
    /// test; with SCATTERLAB_TIMINGS=1 it prints the start-up times).
    #[arg(long, hide = true)]
    pub exit_after_first_frame: bool,
    /// Open comparing the look (A) with B in this view.
    #[arg(long, value_enum)]
    pub compare: Option<CompareArg>,
    /// With --compare: B is the look rendered with this method
    /// (default: what B was last time).
    #[arg(long, value_enum, requires = "compare")]
    pub compare_b: Option<MethodId>,
    /// A `scatterlab budget` report's folder: its merges in a window, each
    /// profile comparable with its merge side by side.
    #[arg(long, value_name = "DIR")]
    pub budget: Option<PathBuf>,
}

/// The editor's compare views (`edit --compare`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum CompareArg {
    Split,
    SideBySide,
    Difference,
}

impl EditArgs {
    pub fn run(self) -> Result<()> {
        use crate::app::state::CompareMode;
        let compare = self.compare.map(|c| {
            let mode = match c {
                CompareArg::Split => CompareMode::Split,
                CompareArg::SideBySide => CompareMode::SideBySide,
                CompareArg::Difference => CompareMode::Difference,
            };
            (mode, self.compare_b)
        });
        let mesh = match self.mesh {
            Some(path) => Some(crate::app::MeshArg::check(path, self.metres_per_unit)?),
            None => None,
        };
        crate::app::run(
            self.preset,
            self.exit_after_first_frame,
            compare,
            self.import,
            mesh,
            self.budget,
        )
    }
}
