//! `scatterlab stress`: every model swept across its documented parameter
//! range against independent references, in parallel, with progress.

use anyhow::{bail, Result};

#[derive(Debug, clap::Args)]
pub struct StressArgs {
    /// Random parameter sets per model (multipole slabs get 1/6 of
    /// them, layered stacks 1/24, at least 2); edges are drawn one time
    /// in five. The default takes about two minutes on 2 cores.
    #[arg(long, default_value_t = crate::model::stress::DEFAULT_CASES, conflicts_with = "long")]
    pub cases: usize,
    /// The long sweep: 400 cases per model (about 20 CPU-minutes).
    #[arg(long)]
    pub long: bool,
    #[arg(long, default_value_t = 2026)]
    pub seed: u64,
    /// Only this model (burley, gaussians, jimenez2012, artist, dipole,
    /// measured, multipole-slab, multipole-stack).
    #[arg(long)]
    pub model: Option<String>,
    #[arg(long)]
    pub json: bool,
}

impl StressArgs {
    pub fn run(self) -> Result<()> {
        let cases = if self.long {
            crate::model::stress::LONG_CASES
        } else {
            self.cases
        };
        stress(cases, self.seed, self.model.as_deref(), self.json)
    }
}

fn stress(cases: usize, seed: u64, model: Option<&str>, json: bool) -> Result<()> {
    crate::model::check_range("cases", cases as f64, 2.0, 1e6, "")?;
    let names = crate::model::stress::model_names();
    if let Some(m) = model.filter(|m| !names.contains(m)) {
        bail!("--model {m}: unknown; known: {}", names.join(", "));
    }
    // Progress on stderr, about every 5 %: the sweep takes minutes.
    let started = std::time::Instant::now();
    let last = std::sync::Mutex::new(0usize);
    let report = crate::model::stress::run_with_progress(cases, seed, model, |done, total| {
        let step = (total / 20).max(1);
        let Ok(mut last) = last.lock() else {
            return;
        };
        if done == total || done >= *last + step {
            *last = done;
            eprintln!(
                "stress: {done}/{total} cases, {:.0} s",
                started.elapsed().as_secs_f64()
            );
        }
    });
    if json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "{:<16} {:>6} {:>10} {:>9} {:>10} {:>10} {:>10} {:>10}",
            "model", "cases", "values", "NaN/Inf", "R rel", "CDF rel", "inv rel", "kernel"
        );
        for m in &report.models {
            println!(
                "{:<16} {:>6} {:>10} {:>9} {:>10.2e} {:>10.2e} {:>10.2e} {:>10.2e}",
                m.model,
                m.cases,
                m.evaluations,
                m.non_finite,
                m.worst_r_rel,
                m.worst_cdf_rel,
                m.worst_inverse_rel,
                m.worst_kernel_norm
            );
        }
        for m in report.models.iter().filter(|m| m.non_finite > 0) {
            println!("{}: first NaN/Inf: {}", m.model, m.non_finite_at);
        }
    }
    if report.total_non_finite() > 0 {
        bail!("{} NaN or Inf values", report.total_non_finite());
    }
    Ok(())
}
