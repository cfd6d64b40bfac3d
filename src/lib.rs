#![cfg_attr(test, allow(clippy::unwrap_used))]
// `!(x > 0.0)` is deliberate throughout: it is true for NaN as well.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Per-channel numerics index several arrays with one channel index.
#![allow(clippy::needless_range_loop)]
//! scatterlab: author subsurface-scattering diffusion profiles.
//!
//! Layering (see ARCHITECTURE.md): `model` is pure math (profiles, kernels,
//! sampling, lookup tables, fits, unit conversions) tested against
//! independent references; `settings` holds the serde types of a look and
//! its RON presets; `cli` drives them without a window. The renderer
//! (`render`, wgpu) and the editor (`app`, egui) build on these; `export`
//! writes engine assets and images; `bench` measures every method's run
//! time against its error and proves that unused work is skipped.

#[cfg(feature = "gpu")]
pub mod app;
#[cfg(feature = "gpu")]
pub mod bench;
#[cfg(feature = "gpu")]
pub mod cli;
pub mod export;
pub mod fsutil;
pub mod model;
pub mod render;
pub mod settings;

/// ARCHITECTURE.md's layering, checked on the source: `model` imports
/// neither `render`, `settings`' callers (`app`, `cli`, `bench`, `export`)
/// nor a GPU or UI crate; `render` imports neither egui/eframe nor `app`,
/// `cli` or `bench`. Comments are skipped (they may name what is absent).
#[cfg(test)]
mod layering {
    fn sources(dir: &str) -> Vec<(std::path::PathBuf, String)> {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("src")
            .join(dir);
        let mut out = Vec::new();
        let mut stack = vec![root];
        while let Some(d) = stack.pop() {
            for e in std::fs::read_dir(&d).unwrap().flatten() {
                let p = e.path();
                if p.is_dir() {
                    stack.push(p);
                } else if p.extension().is_some_and(|x| x == "rs") {
                    // Code only: line comments and doc comments removed.
                    let text = std::fs::read_to_string(&p).unwrap();
                    let code: String = text
                        .lines()
                        .map(|l| l.split("//").next().unwrap_or(""))
                        .collect::<Vec<_>>()
                        .join("\n");
                    out.push((p, code));
                }
            }
        }
        assert!(!out.is_empty(), "no sources under src/{dir}");
        out
    }

    fn forbid(dir: &str, names: &[&str]) {
        for (path, code) in sources(dir) {
            for name in names {
                assert!(
                    !code.contains(name),
                    "{} uses `{name}`: ARCHITECTURE.md keeps {dir} free of it",
                    path.display()
                );
            }
        }
    }

    #[test]
    fn model_is_pure_math() {
        forbid(
            "model",
            &[
                "crate::render",
                "crate::app",
                "crate::cli",
                "crate::bench",
                "crate::export",
                "egui",
                "eframe",
                "wgpu",
            ],
        );
    }

    #[test]
    fn render_never_uses_the_ui() {
        forbid(
            "render",
            &["egui", "eframe", "crate::app", "crate::cli", "crate::bench"],
        );
    }

    /// The check itself can fail: it finds egui in the editor.
    #[test]
    fn the_check_sees_an_import() {
        assert!(sources("app").iter().any(|(_, c)| c.contains("egui")));
    }
}
