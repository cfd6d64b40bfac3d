#![allow(clippy::unwrap_used)]
//! Every input the fuzzers crashed on (fuzz/regressions/<target>/) goes
//! through the same loader again: it must now be refused with an error that
//! names the file, without a panic or a hang.

use scatterlab::render::environment::Environment;
use scatterlab::render::textures::{load, TextureSlot};
use scatterlab::render::Mesh;
use std::path::{Path, PathBuf};

fn inputs(target: &str) -> Vec<PathBuf> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fuzz/regressions")
        .join(target);
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    files.sort();
    assert!(!files.is_empty(), "no regression inputs for {target}");
    files
}

#[test]
fn obj_crashes_are_refused() {
    for path in inputs("mesh_obj") {
        let text = std::fs::read_to_string(&path).unwrap();
        let e = Mesh::from_obj_text(&text, "regression.obj", 0.01)
            .map(|_| ())
            .unwrap_err();
        assert!(
            e.to_string().contains("regression.obj"),
            "{}: {e}",
            path.display()
        );
    }
}

#[test]
fn gltf_crashes_are_refused() {
    for path in inputs("mesh_gltf") {
        // The loader picks the format by extension, as `--mesh` does.
        let copy =
            std::env::temp_dir().join(format!("scatterlab-regression-{}.glb", std::process::id()));
        std::fs::copy(&path, &copy).unwrap();
        let result = Mesh::load(&copy, 1.0).map(|_| ());
        std::fs::remove_file(&copy).unwrap();
        let e = result.unwrap_err().to_string();
        assert!(
            e.contains("scatterlab-regression-"),
            "{}: {e}",
            path.display()
        );
    }
}

#[test]
fn image_crashes_are_refused() {
    for path in inputs("image") {
        let env = Environment::load(&path).map(|_| ());
        let e = env.unwrap_err().to_string();
        assert!(e.contains(&path.display().to_string()), "{e}");
        // As a surface map it is an 8-bit image or a named error, never a panic.
        if let Err(e) = load(&path, TextureSlot::Albedo) {
            assert!(e.to_string().contains(&path.display().to_string()), "{e}");
        }
    }
}

/// Engine files the importer fuzzers crashed on: refused with one line
/// that names the file (an Unreal struct text once put its own newline
/// into the error).
#[test]
fn import_crashes_are_refused_on_one_line() {
    for path in inputs("unreal_text") {
        let text = String::from_utf8_lossy(&std::fs::read(&path).unwrap()).into_owned();
        let e = scatterlab::export::import_text(
            &text,
            Path::new("regression.txt"),
            &scatterlab::export::ImportOptions::default(),
        )
        .map(|_| ())
        .unwrap_err()
        .to_string();
        assert!(e.contains("regression.txt"), "{}: {e}", path.display());
        assert_eq!(e.lines().count(), 1, "{}: {e}", path.display());
    }
}
