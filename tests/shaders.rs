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

fn parsed(module_name: &str) -> naga::Module {
    let sources = scatterlab::render::renderer::shader_sources();
    let src = &sources
        .iter()
        .find(|(n, _)| *n == module_name)
        .unwrap_or_else(|| panic!("no module {module_name}"))
        .1;
    naga::front::wgsl::parse_str(src).unwrap()
}

/// Every uniform and storage struct the Rust side uploads has the size of
/// its WGSL twin as naga lays it out (WGSL's alignment rules, not ours),
/// and the same fields, by name, in the same order, at the same byte
/// offsets: a field added, renamed or moved on one side only, or padded
/// differently, fails here before it garbles a frame.
#[test]
fn every_gpu_struct_matches_its_wgsl_twin() {
    use scatterlab::render::gpu_types::{
        BurleyUniforms, CloudNode, CloudUniforms, CompositeUniforms, GatherParams, GpuSample,
        GpuTap, SceneUniforms, SssUniforms, TextureSpaceUniforms, TreeLevel,
    };
    type Fields = &'static [(&'static str, usize, &'static str)];
    // (WGSL module, WGSL struct, Rust size, Rust fields)
    let twins: [(&str, &str, usize, Fields); 16] = [
        (
            "scene",
            "SceneUniforms",
            std::mem::size_of::<SceneUniforms>(),
            SceneUniforms::FIELDS,
        ),
        (
            "sss_burley",
            "SssUniforms",
            std::mem::size_of::<SssUniforms>(),
            SssUniforms::FIELDS,
        ),
        (
            "sss_burley",
            "BurleyUniforms",
            std::mem::size_of::<BurleyUniforms>(),
            BurleyUniforms::FIELDS,
        ),
        (
            "sss_burley",
            "Sample",
            std::mem::size_of::<GpuSample>(),
            GpuSample::FIELDS,
        ),
        (
            "sss_separable",
            "SssUniforms",
            std::mem::size_of::<SssUniforms>(),
            SssUniforms::FIELDS,
        ),
        (
            "sss_separable",
            "Tap",
            std::mem::size_of::<GpuTap>(),
            GpuTap::FIELDS,
        ),
        (
            "texture_space",
            "SceneUniforms",
            std::mem::size_of::<SceneUniforms>(),
            SceneUniforms::FIELDS,
        ),
        (
            "texture_space",
            "SssUniforms",
            std::mem::size_of::<SssUniforms>(),
            SssUniforms::FIELDS,
        ),
        (
            "texture_space",
            "Sample",
            std::mem::size_of::<GpuSample>(),
            GpuSample::FIELDS,
        ),
        (
            "texture_space",
            "TextureSpaceUniforms",
            std::mem::size_of::<TextureSpaceUniforms>(),
            TextureSpaceUniforms::FIELDS,
        ),
        (
            "texture_space_cloud",
            "CloudUniforms",
            std::mem::size_of::<CloudUniforms>(),
            CloudUniforms::FIELDS,
        ),
        (
            "texture_space_cloud",
            "Node",
            std::mem::size_of::<CloudNode>(),
            CloudNode::FIELDS,
        ),
        (
            "texture_space_tree",
            "Node",
            std::mem::size_of::<CloudNode>(),
            CloudNode::FIELDS,
        ),
        (
            "texture_space_tree",
            "TreeLevel",
            std::mem::size_of::<TreeLevel>(),
            TreeLevel::FIELDS,
        ),
        (
            "composite",
            "CompositeUniforms",
            std::mem::size_of::<CompositeUniforms>(),
            CompositeUniforms::FIELDS,
        ),
        (
            "ground_truth",
            "GatherParams",
            std::mem::size_of::<GatherParams>(),
            GatherParams::FIELDS,
        ),
    ];
    for (module_name, struct_name, rust_size, rust_fields) in twins {
        let module = parsed(module_name);
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let (handle, ty) = module
            .types
            .iter()
            .find(|(_, t)| t.name.as_deref() == Some(struct_name))
            .unwrap_or_else(|| panic!("{module_name}: no struct {struct_name}"));
        assert_eq!(
            layouter[handle].size as usize, rust_size,
            "{module_name}::{struct_name}: WGSL {} bytes, Rust twin {rust_size}",
            layouter[handle].size
        );
        let naga::TypeInner::Struct { members, .. } = &ty.inner else {
            panic!("{module_name}::{struct_name} is not a struct");
        };
        let wgsl: Vec<(String, usize, String)> = members
            .iter()
            .map(|m| {
                let ty = rust_spelling(&module, m.ty);
                (m.name.clone().unwrap_or_default(), m.offset as usize, ty)
            })
            .collect();
        let rust: Vec<(String, usize, String)> = rust_fields
            .iter()
            .map(|(n, o, t)| (n.to_string(), *o, t.replace(' ', "")))
            .collect();
        assert_eq!(
            wgsl, rust,
            "{module_name}::{struct_name}: WGSL fields (left) vs the Rust twin's (right)"
        );
    }
}

/// Every named WGSL `const` of each module equals its Rust twin; `literal`
/// reads the const's value if it is a literal of the kind `kind` names.
fn assert_constants_match<T: PartialEq + std::fmt::Debug + std::fmt::Display>(
    modules: &[(&str, &[(&str, T)])],
    kind: &str,
    literal: impl Fn(naga::Literal) -> Option<T>,
) {
    for (module_name, consts) in modules {
        let module = parsed(module_name);
        for (name, rust) in consts.iter() {
            let (_, c) = module
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(*name))
                .unwrap_or_else(|| panic!("{module_name}: no const {name}"));
            let wgsl = match module.global_expressions[c.init] {
                naga::Expression::Literal(l) => literal(l),
                _ => None,
            }
            .unwrap_or_else(|| {
                panic!(
                    "{module_name}::{name} is {:?}, not a {kind} literal",
                    module.global_expressions[c.init]
                )
            });
            assert_eq!(
                wgsl, *rust,
                "{module_name}::{name}: WGSL {wgsl}, Rust {rust}"
            );
        }
    }
}

/// How the Rust twin spells a WGSL member's type: `f32`, `u32`,
/// `[f32;N]` for a vector, `[[f32;4];4]` for a matrix, `[T;N]` for an
/// array (so an f32 on one side and a u32 on the other fails).
fn rust_spelling(module: &naga::Module, ty: naga::Handle<naga::Type>) -> String {
    let scalar = |s: naga::Scalar| match (s.kind, s.width) {
        (naga::ScalarKind::Float, 4) => "f32".to_owned(),
        (naga::ScalarKind::Uint, 4) => "u32".to_owned(),
        (naga::ScalarKind::Sint, 4) => "i32".to_owned(),
        other => format!("{other:?}"),
    };
    match &module.types[ty].inner {
        naga::TypeInner::Scalar(s) => scalar(*s),
        naga::TypeInner::Vector { size, scalar: s } => format!("[{};{}]", scalar(*s), *size as u8),
        naga::TypeInner::Matrix {
            columns,
            rows,
            scalar: s,
        } => {
            format!("[[{};{}];{}]", scalar(*s), *rows as u8, *columns as u8)
        }
        naga::TypeInner::Array {
            base,
            size: naga::ArraySize::Constant(n),
            ..
        } => {
            format!("[{};{n}]", rust_spelling(module, *base))
        }
        other => format!("{other:?}"),
    }
}

/// Every mode constant a shader compares against has the value of its
/// Rust twin in `render::gpu_types`, read from naga's constant arena.
#[test]
fn every_wgsl_mode_constant_matches_its_rust_twin() {
    use scatterlab::render::gpu_types as g;
    use scatterlab::render::tonemap as t;
    let twins: [(&str, &[(&str, u32)]); 3] = [
        (
            "scene",
            &[
                ("TRANSMISSION_OFF", g::TRANSMISSION_OFF),
                ("TRANSMISSION_THIN", g::TRANSMISSION_THIN),
                ("TRANSMISSION_THICK", g::TRANSMISSION_THICK),
                ("PATTERN_LIT", g::PATTERN_LIT),
                ("PATTERN_STEP", g::PATTERN_STEP),
                ("PATTERN_CHECKERBOARD", g::PATTERN_CHECKERBOARD),
                ("SPECULAR_DUAL_GGX", g::SPECULAR_DUAL_GGX),
                ("SPECULAR_KELEMEN", g::SPECULAR_KELEMEN),
                ("MAP_MODULATES", g::MAP_MODULATES),
                ("MAP_ABSOLUTE", g::MAP_ABSOLUTE),
                ("MAP_LOOK", g::MAP_LOOK),
            ],
        ),
        (
            "composite",
            &[
                ("TONE_ACES_FIT", t::TONE_ACES_FIT),
                ("TONE_ACES", t::TONE_ACES),
                ("TONE_AGX", t::TONE_AGX),
                ("TONE_PBR_NEUTRAL", t::TONE_PBR_NEUTRAL),
            ],
        ),
        (
            "sss_burley",
            &[
                ("SAMPLING_R2_ROTATION", g::SAMPLING_R2_ROTATION),
                ("SAMPLING_CENTRE_WEIGHT", g::SAMPLING_CENTRE_WEIGHT),
                ("SAMPLING_BILINEAR", g::SAMPLING_BILINEAR),
            ],
        ),
    ];
    assert_constants_match(&twins, "u32", |l| match l {
        naga::Literal::U32(v) => Some(v),
        _ => None,
    });
    // The diffuse target's alphas off the skin (f32 constants).
    let alphas: [(&str, &[(&str, f32)]); 3] = [
        (
            "scene",
            &[("DIFFUSE_ALPHA_NOT_SKIN", g::DIFFUSE_ALPHA_NOT_SKIN)],
        ),
        (
            "sss_burley",
            &[
                ("DIFFUSE_ALPHA_NOT_SKIN", g::DIFFUSE_ALPHA_NOT_SKIN),
                ("DIFFUSE_ALPHA_BACKGROUND", g::DIFFUSE_ALPHA_BACKGROUND),
            ],
        ),
        (
            "texture_space",
            &[
                ("DIFFUSE_ALPHA_NOT_SKIN", g::DIFFUSE_ALPHA_NOT_SKIN),
                ("ATLAS_EMPTY", g::DIFFUSE_ALPHA_BACKGROUND),
            ],
        ),
    ];
    assert_constants_match(&alphas, "f32", |l| match l {
        naga::Literal::F32(v) => Some(v),
        _ => None,
    });
    // The flags' bits are the ones BurleySampling packs.
    let all = scatterlab::render::BurleySampling {
        antithetic: false,
        mis: false,
        r2_rotation: true,
        bilinear: true,
        centre_weight: true,
    };
    assert_eq!(
        all.shader_flags(),
        g::SAMPLING_R2_ROTATION | g::SAMPLING_CENTRE_WEIGHT | g::SAMPLING_BILINEAR
    );
}
