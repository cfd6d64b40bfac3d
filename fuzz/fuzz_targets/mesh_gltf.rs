//! Binary glTF (.glb), through the loader `--mesh` uses (a file on disk,
//! as users give it): a mesh with finite vertices, or a named error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use scatterlab::render::Mesh;

fuzz_target!(|data: &[u8]| {
    // One file per process, so parallel fuzzers (-jobs) do not race.
    let path =
        std::env::temp_dir().join(format!("scatterlab-fuzz-mesh-{}.glb", std::process::id()));
    if std::fs::write(&path, data).is_err() {
        return;
    }
    match Mesh::load(&path, 1.0) {
        Ok(mesh) => {
            for v in &mesh.vertices {
                assert!(v.position.iter().all(|x| x.is_finite()));
            }
            assert!(mesh
                .indices
                .iter()
                .all(|&i| (i as usize) < mesh.vertices.len()));
        }
        Err(e) => assert!(e.to_string().contains("scatterlab-fuzz-")),
    }
});
