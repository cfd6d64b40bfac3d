//! OBJ meshes (the same parser user meshes and the default head go
//! through): any text is a mesh with finite vertices or a named error.
#![no_main]

use libfuzzer_sys::fuzz_target;
use scatterlab::render::Mesh;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match Mesh::from_obj_text(text, "fuzz.obj", 0.01) {
        Ok(mesh) => {
            for v in &mesh.vertices {
                assert!(v.position.iter().all(|x| x.is_finite()));
                assert!(v.normal.iter().all(|x| x.is_finite()));
            }
            assert!(mesh
                .indices
                .iter()
                .all(|&i| (i as usize) < mesh.vertices.len()));
        }
        Err(e) => assert!(e.to_string().contains("fuzz.obj")),
    }
});
