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
    /// With --compare: B is the look in this preset or engine file (what
    /// that engine draws from it).
    #[arg(
        long,
        value_name = "FILE",
        requires = "compare",
        conflicts_with = "compare_b"
    )]
    pub compare_with: Option<PathBuf>,
    /// Light the head with this equirectangular HDR map, shown behind it.
    #[arg(long, value_name = "FILE.hdr")]
    pub environment: Option<PathBuf>,
    /// On a mesh with a colour map: the map's colour, the map tinted by the
    /// look's albedo, or the look's albedo alone.
    #[arg(long, value_enum)]
    pub map_colour: Option<crate::render::textures::MapColour>,
    /// Open on the procedural head instead of the head scan (remembered).
    #[arg(long, conflicts_with = "mesh")]
    pub procedural_head: bool,
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
        for (flag, p) in [
            ("--compare-with", &self.compare_with),
            ("--environment", &self.environment),
        ] {
            if let Some(p) = p.as_ref().filter(|p| !p.is_file()) {
                anyhow::bail!("{flag} {}: no such file", p.display());
            }
        }
        crate::app::run(crate::app::RunArgs {
            preset: self.preset,
            exit_after_first_frame: self.exit_after_first_frame,
            compare,
            import: self.import,
            mesh,
            budget: self.budget,
            compare_with: self.compare_with,
            environment: self.environment,
            map_colour: self.map_colour,
            procedural_head: self.procedural_head,
        })
    }
}
