#![allow(clippy::unwrap_used)]
//! Every WGSL module the renderer builds parses and validates with naga.

#[test]
fn every_shader_validates_with_naga() {
    let sources = scatterlab::render::renderer::shader_sources();
    assert!(sources.len() >= 4);
    for (name, src) in sources {
        let module = naga::front::wgsl::parse_str(&src)
            .unwrap_or_else(|e| panic!("{name}: {}", e.emit_to_string(&src)));
        naga::valid::Validator::new(
            naga::valid::ValidationFlags::all(),
            naga::valid::Capabilities::all(),
        )
        .validate(&module)
        .unwrap_or_else(|e| panic!("{name}: {e:?}"));
    }
}

/// Every uniform and storage struct the Rust side uploads has the size of
/// its WGSL twin as naga lays it out (WGSL's alignment rules, not ours):
/// a field added on one side only, or padded differently, fails here
/// before it garbles a frame.
#[test]
fn every_gpu_struct_matches_its_wgsl_twin() {
    use scatterlab::render::gpu_types::{
        CompositeUniforms, GpuSample, GpuTap, SceneUniforms, SssUniforms,
    };
    let sources = scatterlab::render::renderer::shader_sources();
    // (WGSL module, WGSL struct, Rust size)
    let twins = [
        (
            "scene",
            "SceneUniforms",
            std::mem::size_of::<SceneUniforms>(),
        ),
        (
            "sss_burley",
            "SssUniforms",
            std::mem::size_of::<SssUniforms>(),
        ),
        ("sss_burley", "Sample", std::mem::size_of::<GpuSample>()),
        (
            "sss_separable",
            "SssUniforms",
            std::mem::size_of::<SssUniforms>(),
        ),
        ("sss_separable", "Tap", std::mem::size_of::<GpuTap>()),
        (
            "composite",
            "CompositeUniforms",
            std::mem::size_of::<CompositeUniforms>(),
        ),
    ];
    for (module_name, struct_name, rust_size) in twins {
        let src = &sources
            .iter()
            .find(|(n, _)| *n == module_name)
            .unwrap_or_else(|| panic!("no module {module_name}"))
            .1;
        let module = naga::front::wgsl::parse_str(src).unwrap();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let (handle, _) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(struct_name))
            .unwrap_or_else(|| panic!("{module_name}: no struct {struct_name}"));
        assert_eq!(
            layouter[handle].size as usize, rust_size,
            "{module_name}::{struct_name}: WGSL {} bytes, Rust twin {rust_size}",
            layouter[handle].size
        );
    }
}
