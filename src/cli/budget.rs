//! `scatterlab budget PROJECT --slots 15 --out DIR`: the shell over the
//! budget's use case (`export::unity_budget_run`): its flags, and what it
//! says.

use crate::export::unity_budget_run::BudgetOptions;
use crate::export::unity_project::HDRP_LIST_SLOTS;
use anyhow::Result;
use std::path::PathBuf;

#[derive(Debug, clap::Args)]
pub struct BudgetArgs {
    /// The Unity project (its folder, or its Assets folder).
    #[arg(value_name = "PROJECT")]
    pub project: PathBuf,
    /// How many profiles the list may hold (HDRP: 15, its 16 slots less
    /// the neutral profile).
    #[arg(long, default_value_t = HDRP_LIST_SLOTS)]
    pub slots: usize,
    /// Where the merged profiles, the Diffusion Profile List, the remap
    /// table and the report are written.
    #[arg(long, value_name = "DIR")]
    pub out: PathBuf,
    /// Also change the project: copy the merged profiles and the list into
    /// Assets/scatterlab_budget/ and point each remapped material at its new
    /// profile, after copying every file it rewrites to DIR/backup/.
    #[arg(long)]
    pub apply: bool,
    /// Replace an earlier report in DIR.
    #[arg(long)]
    pub force: bool,
    /// Leave out the head renders (old beside new, with ΔL*), which take a
    /// few seconds a profile on a CPU renderer.
    #[arg(long)]
    pub no_renders: bool,
    /// Side of each head render, in pixels.
    #[arg(long, default_value_t = 256)]
    pub render_size: u32,
}

impl BudgetArgs {
    pub fn run(self) -> Result<()> {
        let said = BudgetOptions {
            project: self.project,
            slots: self.slots,
            out: self.out,
            apply: self.apply,
            force: self.force,
            no_renders: self.no_renders,
            render_size: self.render_size,
        }
        .run()?;
        println!("{said}");
        Ok(())
    }
}
