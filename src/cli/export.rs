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
    /// glTF only: the mesh the material is put on.
    #[arg(long, value_enum, default_value_t = crate::export::GltfMesh::Head)]
    pub gltf_mesh: crate::export::GltfMesh,
    /// glTF only: also write KHR_materials_volume_scatter, a draft
    /// extension (KhronosGroup/glTF PR #2453) that carries the albedo of
    /// the volume; readers that know it draw the look's scattering.
    #[arg(long)]
    pub gltf_volume_scatter: bool,
    /// Unreal only: the script's Substrate Slab uses its own mean free path
    /// (type Diffusion, `SSS MFP` in cm, `SSS MFP Scale` 1) instead of the
    /// SubsurfaceProfile it sets.
    #[arg(long)]
    pub substrate_diffusion: bool,
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
        let gltf_flag =
            self.gltf_volume_scatter || self.gltf_mesh != crate::export::GltfMesh::default();
        if gltf_flag && self.format != crate::export::Format::Gltf {
            anyhow::bail!(
                "--gltf-mesh and --gltf-volume-scatter are for --format gltf, not {}",
                self.format.id()
            );
        }
        if self.substrate_diffusion && self.format != crate::export::Format::Unreal {
            anyhow::bail!(
                "--substrate-diffusion is for --format unreal, not {}",
                self.format.id()
            );
        }
        let options = crate::export::ExportOptions {
            gltf_mesh: self.gltf_mesh,
            gltf_on_mesh: None,
            gltf_volume_scatter: self.gltf_volume_scatter,
            unreal_substrate_diffusion: self.substrate_diffusion,
        };
        for path in crate::export::export_with(&p, source, self.format, &self.out, &options)? {
            println!("{}", path.display());
        }
        Ok(())
    }
}
