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
