//! Bind-group layouts, pipeline builders and the WGSL sources.

use super::gpu_types::Vertex;

/// Diffuse irradiance + SSS mask, and the SSS ping/pong targets.
pub(super) const HDR: wgpu::TextureFormat = wgpu::TextureFormat::Rgba16Float;

/// albedo^post (rgb) and coverage (a).
pub(super) const ALBEDO: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8Unorm;

/// The scene's depth buffer; its stencil marks the SSS pixels.
pub(super) const DEPTH_STENCIL: wgpu::TextureFormat = wgpu::TextureFormat::Depth24PlusStencil8;

pub(super) const OUTPUT: wgpu::TextureFormat = wgpu::TextureFormat::Rgba8UnormSrgb;

pub(super) fn texture_entry(binding: u32) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty: wgpu::BindingType::Texture {
            sample_type: wgpu::TextureSampleType::Float { filterable: false },
            view_dimension: wgpu::TextureViewDimension::D2,
            multisampled: false,
        },
        count: None,
    }
}

/// A buffer entry of any size (storage arrays).
pub(super) fn buffer_entry(
    binding: u32,
    ty: wgpu::BufferBindingType,
    stages: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    sized_buffer_entry(binding, ty, stages, None)
}

/// A uniform buffer entry whose binding must hold a `T` (its Rust twin):
/// wgpu checks every bind group against the size.
pub(super) fn uniform_entry<T>(
    binding: u32,
    stages: wgpu::ShaderStages,
) -> wgpu::BindGroupLayoutEntry {
    let size = wgpu::BufferSize::new(std::mem::size_of::<T>() as u64);
    sized_buffer_entry(binding, wgpu::BufferBindingType::Uniform, stages, size)
}

fn sized_buffer_entry(
    binding: u32,
    ty: wgpu::BufferBindingType,
    stages: wgpu::ShaderStages,
    min_binding_size: Option<wgpu::BufferSize>,
) -> wgpu::BindGroupLayoutEntry {
    wgpu::BindGroupLayoutEntry {
        binding,
        visibility: stages,
        ty: wgpu::BindingType::Buffer {
            ty,
            has_dynamic_offset: false,
            min_binding_size,
        },
        count: None,
    }
}

pub(super) const FULLSCREEN: &str = include_str!("../../shaders/fullscreen.wgsl");

/// `texture-space`'s module in [`shader_sources`].
pub(super) const TEXTURE_SPACE_MODULE: &str = "texture_space";

/// `texture-space`'s probe-ray gather in [`shader_sources`] (built only on
/// a device with ray queries).
pub(super) const TEXTURE_SPACE_RAYS_MODULE: &str = "texture_space_rays";

/// `texture-space --neighbours 3d`'s gather by 3D neighbourhood in
/// [`shader_sources`], and the compute pass that builds its tree.
pub(super) const TEXTURE_SPACE_CLOUD_MODULE: &str = "texture_space_cloud";
pub(super) const TEXTURE_SPACE_TREE_MODULE: &str = "texture_space_tree";

pub(super) const SSS_COMMON: &str = include_str!("../../shaders/sss_common.wgsl");

/// Every WGSL module the renderer builds, as (name, full source) pairs;
/// the tests validate each with naga.
pub fn shader_sources() -> Vec<(&'static str, String)> {
    vec![
        ("scene", include_str!("../../shaders/scene.wgsl").to_owned()),
        (
            "classify",
            format!(
                "{FULLSCREEN}\n{}",
                include_str!("../../shaders/classify.wgsl")
            ),
        ),
        (
            "composite",
            format!(
                "{FULLSCREEN}\n{}",
                include_str!("../../shaders/composite.wgsl")
            ),
        ),
    ]
    .into_iter()
    // `texture-space`'s passes draw the mesh with the scene's bindings
    // and its `shade`: scene.wgsl first.
    .chain([(
        TEXTURE_SPACE_MODULE,
        format!(
            "{}\n{}",
            include_str!("../../shaders/scene.wgsl"),
            include_str!("../../shaders/texture_space_scene.wgsl")
        ),
    )])
    // Its probe-ray gather: the same, with ray queries (naga's extension
    // first) and the gather's own group 2 after them.
    .chain([(
        TEXTURE_SPACE_RAYS_MODULE,
        format!(
            "enable wgpu_ray_query;\n{}\n{}\n{}",
            include_str!("../../shaders/scene.wgsl"),
            include_str!("../../shaders/texture_space_scene.wgsl"),
            include_str!("../../shaders/texture_space_rays.wgsl")
        ),
    )])
    // The gather by 3D neighbourhood: the same, with its tree's group 2
    // after them; and the tree's build, on its own.
    .chain([
        (
            TEXTURE_SPACE_CLOUD_MODULE,
            format!(
                "{}\n{}\n{}",
                include_str!("../../shaders/scene.wgsl"),
                include_str!("../../shaders/texture_space_scene.wgsl"),
                include_str!("../../shaders/texture_space_cloud.wgsl")
            ),
        ),
        (
            TEXTURE_SPACE_TREE_MODULE,
            include_str!("../../shaders/texture_space_tree.wgsl").to_owned(),
        ),
    ])
    // The GPU ground truth's gather as `reference --reference-gpu` builds
    // it: the scene's `shade` and the mesh's interpolation first (groups 0
    // and 1), the gather's own bindings after them.
    .chain([(
        "ground_truth",
        format!(
            "{}\n{}\n{}",
            include_str!("../../shaders/scene.wgsl"),
            include_str!("../../shaders/ground_truth_scene.wgsl"),
            include_str!("../../shaders/ground_truth.wgsl").replace("@group(0)", "@group(2)")
        ),
    )])
    // Each method's own pass (`MethodInfo::shader`), after the shared code.
    .chain(super::Method::all().iter().filter_map(|m| {
        m.sss()
            .shader
            .map(|(name, wgsl)| (name, format!("{FULLSCREEN}\n{SSS_COMMON}\n{wgsl}")))
    }))
    .collect()
}

pub(super) fn scene_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::BindGroupLayout,
    specular: wgpu::TextureFormat,
    linear_depth: wgpu::TextureFormat,
) -> wgpu::RenderPipeline {
    let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("scene"),
        bind_group_layouts: &[Some(layout)],
        ..Default::default()
    });
    let target = |format| {
        Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        })
    };
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("scene"),
        layout: Some(&pl),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_main"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32x2, 3 => Float32, 4 => Float32, 5 => Float32, 6 => Float32x4],
            })],
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some("fs_main"),
            compilation_options: Default::default(),
            targets: &[target(HDR), target(specular), target(ALBEDO), target(linear_depth)],
        }),
        // Back faces are culled: closed meshes shade each pixel about once
        // (halves the pass on lavapipe). glTF's default is single-sided too.
        primitive: wgpu::PrimitiveState { cull_mode: Some(wgpu::Face::Back), ..Default::default() },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_STENCIL,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: Default::default(),
        }),
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    })
}

pub(super) fn shadow_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    layout: &wgpu::BindGroupLayout,
) -> wgpu::RenderPipeline {
    let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("shadow"),
        bind_group_layouts: &[Some(layout)],
        ..Default::default()
    });
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some("shadow"),
        layout: Some(&pl),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_shadow"),
            compilation_options: Default::default(),
            buffers: &[Some(wgpu::VertexBufferLayout {
                array_stride: std::mem::size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3],
            })],
        },
        fragment: None,
        primitive: wgpu::PrimitiveState {
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: wgpu::TextureFormat::Depth32Float,
            depth_write_enabled: Some(true),
            depth_compare: Some(wgpu::CompareFunction::Less),
            stencil: Default::default(),
            bias: wgpu::DepthBiasState {
                constant: 2,
                slope_scale: 2.0,
                clamp: 0.0,
            },
        }),
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    })
}

/// How a fullscreen pass uses the scene's stencil.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Stencil {
    /// No depth-stencil attachment (composite).
    None,
    /// Writes 1 on every fragment that survives (classification).
    Mark,
    /// Shades only where the stencil is 1 (SSS passes).
    Test,
}

/// What a fullscreen pass writes: a colour format, optionally added to
/// the target's contents.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Output {
    /// No colour target (classification).
    Nothing,
    Replace(wgpu::TextureFormat),
    Add(wgpu::TextureFormat),
    /// Blended with the pass's blend constant c: c·new + (1 − c)·old
    /// (progressive refinement's running mean).
    Mean(wgpu::TextureFormat),
}

pub(super) fn fullscreen_pipeline(
    device: &wgpu::Device,
    module: &wgpu::ShaderModule,
    entry: &'static str,
    layout: &wgpu::BindGroupLayout,
    output: Output,
    stencil: Stencil,
) -> wgpu::RenderPipeline {
    let pl = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some(entry),
        bind_group_layouts: &[Some(layout)],
        ..Default::default()
    });
    let add = wgpu::BlendComponent {
        src_factor: wgpu::BlendFactor::One,
        dst_factor: wgpu::BlendFactor::One,
        operation: wgpu::BlendOperation::Add,
    };
    let target = match output {
        Output::Nothing => None,
        Output::Replace(format) => Some(wgpu::ColorTargetState {
            format,
            blend: None,
            write_mask: wgpu::ColorWrites::ALL,
        }),
        Output::Add(format) => Some(wgpu::ColorTargetState {
            format,
            blend: Some(wgpu::BlendState {
                color: add,
                alpha: add,
            }),
            write_mask: wgpu::ColorWrites::ALL,
        }),
        Output::Mean(format) => {
            let mean = wgpu::BlendComponent {
                src_factor: wgpu::BlendFactor::Constant,
                dst_factor: wgpu::BlendFactor::OneMinusConstant,
                operation: wgpu::BlendOperation::Add,
            };
            Some(wgpu::ColorTargetState {
                format,
                blend: Some(wgpu::BlendState {
                    color: mean,
                    alpha: mean,
                }),
                write_mask: wgpu::ColorWrites::ALL,
            })
        }
    };
    let face = |compare, pass_op| wgpu::StencilFaceState {
        compare,
        fail_op: wgpu::StencilOperation::Keep,
        depth_fail_op: wgpu::StencilOperation::Keep,
        pass_op,
    };
    let stencil_state = |compare, pass_op, write_mask| {
        Some(wgpu::DepthStencilState {
            format: DEPTH_STENCIL,
            depth_write_enabled: Some(false),
            depth_compare: Some(wgpu::CompareFunction::Always),
            stencil: wgpu::StencilState {
                front: face(compare, pass_op),
                back: face(compare, pass_op),
                read_mask: 0xff,
                write_mask,
            },
            bias: Default::default(),
        })
    };
    let depth_stencil = match stencil {
        Stencil::None => None,
        Stencil::Mark => stencil_state(
            wgpu::CompareFunction::Always,
            wgpu::StencilOperation::Replace,
            0xff,
        ),
        Stencil::Test => stencil_state(
            wgpu::CompareFunction::Equal,
            wgpu::StencilOperation::Keep,
            0,
        ),
    };
    let targets = [target];
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(entry),
        layout: Some(&pl),
        vertex: wgpu::VertexState {
            module,
            entry_point: Some("vs_fullscreen"),
            compilation_options: Default::default(),
            buffers: &[],
        },
        fragment: Some(wgpu::FragmentState {
            module,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            targets: if output == Output::Nothing {
                &[]
            } else {
                &targets
            },
        }),
        primitive: Default::default(),
        depth_stencil,
        multisample: Default::default(),
        multiview_mask: None,
        cache: None,
    })
}
