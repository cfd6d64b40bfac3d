//! `texture-space` (d'Eon & Luebke 2007, GPU Gems 3 ch. 14: texture-space
//! diffusion): the light is gathered over the mesh's UV atlas, where every
//! triangle has its texels whether the camera sees it or not, so the light
//! that reaches a visible pixel from the lid margin or the back of the ear
//! is there to be gathered; the screen-space methods only see the pixels
//! on screen. Two passes, both drawing the mesh and both timed as SSS
//! (`shaders/texture_space_scene.wgsl`, after scene.wgsl):
//!
//! 1. **irradiance**: the mesh drawn at its UVs into an `N × N` atlas
//!    (`--atlas-size`, capped by the frame: [`atlas_side`]), each texel
//!    shaded by the scene pass's own `shade` (light, shadow map,
//!    environment, maps, transmission) and given its surface position;
//! 2. **gather**: the mesh drawn again with the scene pass's vertex shader
//!    at its depth (compare Equal) on the SSS pixels. Each pixel gathers
//!    burley's importance-sampled disk (Golubev 2018; its samples and
//!    profile table, `sss::burley`): samples under `--near-field-mm` on
//!    screen as `burley` reads them, the rest on the surface's tangent
//!    plane, carried into UV by the triangle's own surface-to-UV map (the
//!    rasteriser's derivatives: d'Eon's stretch map, anisotropic and exact
//!    per triangle) and weighted by R(ρ) at the 3D distance between the
//!    surface points, so that a sample crossing a UV seam weighs next to
//!    nothing. d'Eon sums six separable Gaussians blurred over the whole
//!    atlas instead; one radial profile keeps the method exact for any
//!    look, and gathering at the pixels on screen costs 35–47 ms on
//!    lavapipe at 640 × 360 where blurring a 1024² atlas cost 78 ms
//!    (docs/accuracy.md).
//!
//! With `--neighbours 3d` ([`cloud`]) the second pass gathers by 3D
//! distance over the atlas's texels as a point cloud instead (Jensen &
//! Buhler 2002), after a 4× coverage atlas and a compute pass that builds
//! the cloud's tree; with `--probe-rays on` ([`rays`]) it adds the skin
//! that probe rays find far in UV.
//!
//! What it needs of a mesh: UVs that do not overlap (the default head's
//! and the Lee Perry-Smith scan's do not); overlapping islands take the
//! light of whichever triangle was drawn last.

use super::{Knob, Look, MethodInputs, Scattered, SssFrame, SssPipelines};
use crate::model::ModelError;
use crate::render::context::GpuError;
use crate::render::frame::{buf, color_attachment, tex, FrameEncoder};
use crate::render::gpu_types::{SssUniforms, TextureSpaceUniforms};
use crate::render::pipelines::{
    TEXTURE_SPACE_CLOUD_MODULE, TEXTURE_SPACE_MODULE, TEXTURE_SPACE_RAYS_MODULE,
    TEXTURE_SPACE_TREE_MODULE,
};
use crate::render::sss::burley::LUT_SIZE;
use crate::render::targets::HdrTarget;

mod cloud;
mod passes;
mod rays;

use passes::{Atlas, MeshPasses};

/// `texture-space` in the registry (`sss::Method::sss`).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "texture-space",
    label: "texture-space (d'Eon 2007)",
    quality: super::Quality::Samples,
    stochastic: |_| true,
    colour: [227, 119, 194],
    bench,
    encode,
    ..super::MethodInfo::BASE
};

/// `bench`'s configurations: the default (a 1024² atlas with the 1 mm
/// near field on screen), every sample in the atlas, and the gather by 3D
/// neighbourhood (`--neighbours 3d`, issue 53), at burley's default count
/// (21). (2048² was measured in the full bench of
/// 2026-12-05 within 2 points of 1024² for 1.6–2.3× the time,
/// docs/accuracy.md; at the quick bench's 320 × 180 [`atlas_side`] caps it
/// to 1024².)
fn bench() -> Vec<Knob> {
    let knob = |variant, series| Knob {
        variant,
        count: 21,
        series,
        shipped: true,
    };
    vec![
        knob("atlas1024", (" 1024²", None)),
        knob("atlas1024-only", (" 1024², atlas only", Some([247, 182, 210]))),
        knob("atlas1024-3d", (" 1024², 3D neighbours", Some([148, 52, 110]))),
    ]
}

/// `texture-space`'s command-line options.
#[derive(Debug, Clone, Copy, PartialEq, clap::Args)]
#[group(skip)]
pub struct Options {
    /// `texture-space`: the side of its irradiance atlas in texels. On the
    /// default head a texel is about 0.95 mm of skin at 1024 and 0.47 mm
    /// at 2048 (its UV islands cover 24 % of the square). A frame never
    /// draws more than the power of two at or above twice its longer side
    /// (at least 256): small frames and drag previews take a smaller atlas.
    #[arg(
        id = "atlas_size",
        long = "atlas-size",
        value_name = "TEXELS",
        default_value_t = DEFAULT_ATLAS,
        value_parser = clap::value_parser!(u32).range(64..=4096)
    )]
    pub atlas_size: u32,
    /// `texture-space`: samples nearer than this (mm) are read on screen
    /// at pixel resolution, the rest in the atlas (0: all in the atlas).
    #[arg(
        id = "near_field_mm",
        long = "near-field-mm",
        value_name = "MM",
        default_value_t = DEFAULT_NEAR_FIELD_MM,
        value_parser = near_field_parser
    )]
    pub near_field_mm: f32,
    /// `texture-space`: also gather the skin that is near in 3D but far
    /// in UV by probe rays through the mesh (the adapter's ray queries;
    /// an error, saying why, where it has none). Off by default: it gains
    /// 4–10 points on three of the bench's four head views, gives 1 back
    /// on the fourth, and takes 11–40 × the time on lavapipe
    /// (docs/accuracy.md).
    #[arg(
        id = "probe_rays",
        long = "probe-rays",
        value_name = "ON_OFF",
        value_enum,
        default_value_t = ProbeRays::Off
    )]
    pub probe_rays: ProbeRays,
    /// `texture-space`: how a pixel finds its neighbours in the atlas:
    /// along the surface through the UV layout (`uv`), or by 3D distance
    /// over the atlas's texels as a point cloud (`3d`: every sheet within
    /// reach, closed lids and lips and the far side of the ear included).
    /// `3d` removed 76–83 % of `none`'s error on every head view of the
    /// bench (the UV gather 25–55 %) at 28–37 × its time on lavapipe
    /// (docs/accuracy.md, "The gather by 3D neighbourhood"); it takes the
    /// atlas's side up to a power of two, and cannot be combined with
    /// `--probe-rays on`.
    #[arg(
        id = "neighbours",
        long = "neighbours",
        value_name = "UV_3D",
        value_enum,
        default_value_t = Neighbours::Uv
    )]
    pub neighbours: Neighbours,
}

/// How `texture-space` finds a pixel's neighbours in the atlas.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum Neighbours {
    /// Along the surface, through the UV layout.
    Uv,
    /// By 3D distance, over the atlas's texels as a point cloud
    /// (Jensen & Buhler 2002; [`cloud`]).
    #[value(name = "3d")]
    ThreeD,
}

/// Whether `texture-space` gathers by probe rays too ([`rays`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, clap::ValueEnum)]
pub enum ProbeRays {
    /// The UV layout's gather alone.
    Off,
    /// Probe rays too: an error where the adapter has no ray queries
    /// (`GpuContext::ray_queries` says why).
    On,
}

/// `--near-field-mm`: finite, 0 to 100 mm.
fn near_field_parser(s: &str) -> Result<f32, String> {
    let v: f32 = s.parse().map_err(|e| format!("{s:?}: {e}"))?;
    if v.is_finite() && (0.0..=100.0).contains(&v) {
        Ok(v)
    } else {
        Err(format!("{v} mm: the near field must be 0 to 100 mm"))
    }
}

/// The default near field (mm): on the default head and the scan it
/// measured best of 0, 0.5, 1 and 2 mm (docs/accuracy.md).
pub const DEFAULT_NEAR_FIELD_MM: f32 = 1.0;

/// The default atlas side (texels).
pub const DEFAULT_ATLAS: u32 = 1024;

impl Default for Options {
    fn default() -> Self {
        Self {
            atlas_size: DEFAULT_ATLAS,
            near_field_mm: DEFAULT_NEAR_FIELD_MM,
            probe_rays: ProbeRays::Off,
            neighbours: Neighbours::Uv,
        }
    }
}

/// `texture-space`'s CPU inputs: the atlas size and near field (its
/// samples and table are burley's, read through `burley::Buffers::disk`).
#[derive(Debug, Clone)]
pub struct Inputs {
    pub atlas_size: u32,
    /// Samples nearer (mm) are read on screen.
    pub near_field_mm: f32,
    pub probe_rays: ProbeRays,
    pub neighbours: Neighbours,
    /// `--neighbours 3d`'s opening ratio θ ([`cloud::DEFAULT_THETA`]).
    pub theta: f32,
}

impl MethodInputs for Inputs {
    fn new(look: &Look<'_>, _bake: bool) -> Result<Self, ModelError> {
        let o = &look.options.texture_space;
        if (o.neighbours, o.probe_rays) == (Neighbours::ThreeD, ProbeRays::On) {
            return Err(ModelError::invalid(
                "texture-space --neighbours 3d with --probe-rays on",
                "the gather by 3D neighbourhood already finds every sheet within reach, and the probe rays add to the UV layout's gather: pick one (--probe-rays off, or --neighbours uv)",
            ));
        }
        Ok(Self {
            atlas_size: o.atlas_size,
            near_field_mm: o.near_field_mm,
            probe_rays: o.probe_rays,
            neighbours: o.neighbours,
            theta: cloud::DEFAULT_THETA,
        })
    }

    /// `variant` is `atlas<N>` (the default near field), `atlas<N>-only`
    /// (no near field: every sample in the atlas), both through the UV
    /// layout alone (probe rays off: the bench tool
    /// `texture_space_on_the_scan` measures them), or `atlas<N>-3d` (the
    /// gather by 3D neighbourhood, the default near field).
    fn bench(&mut self, _: &Look<'_>, knob: &Knob) -> Result<(), ModelError> {
        let bad = || ModelError::invalid("texture-space bench variant", format!("{:?}", knob.variant));
        let rest = knob.variant.strip_prefix("atlas").ok_or_else(bad)?;
        let (size, only, by_3d) = match (rest.strip_suffix("-only"), rest.strip_suffix("-3d")) {
            (Some(size), _) => (size, true, false),
            (_, Some(size)) => (size, false, true),
            _ => (rest, false, false),
        };
        self.atlas_size = size.parse().map_err(|_| bad())?;
        self.near_field_mm = if only { 0.0 } else { DEFAULT_NEAR_FIELD_MM };
        self.probe_rays = ProbeRays::Off;
        self.neighbours = if by_3d { Neighbours::ThreeD } else { Neighbours::Uv };
        self.theta = cloud::DEFAULT_THETA;
        Ok(())
    }

    fn fingerprint_into(&self, h: &mut impl std::hash::Hasher) {
        h.write_u32(self.atlas_size);
        h.write_u32(self.near_field_mm.to_bits());
        h.write_u8(self.probe_rays as u8);
        h.write_u8(self.neighbours as u8);
        h.write_u32(self.theta.to_bits());
    }
}

/// Nothing of its own on the GPU per profile: it gathers burley's disk
/// through burley's table (`burley::Disk`), the one table both read.
pub(in crate::render) type Buffers = ();

/// The module of its two passes (scene.wgsl, then
/// `shaders/texture_space_scene.wgsl`: `pipelines::shader_sources`) and,
/// on a device with ray queries, of the probe-ray gather; their
/// pipelines need the scene's bind-group layout and are built with the
/// [`State`].
pub(in crate::render) struct Pipelines {
    module: wgpu::ShaderModule,
    rays: Option<wgpu::ShaderModule>,
    /// The gather by 3D neighbourhood's module, and its tree's build's
    /// (whose compute pipeline is made the first time a frame asks for
    /// it: a device without compute shaders renders everything else).
    cloud: wgpu::ShaderModule,
    tree_module: wgpu::ShaderModule,
}

impl super::MethodPipelines for Pipelines {
    fn new(device: &wgpu::Device, module: &dyn Fn(&'static str) -> wgpu::ShaderModule) -> Self {
        let rays = device
            .features()
            .contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY)
            .then(|| module(TEXTURE_SPACE_RAYS_MODULE));
        Self {
            module: module(TEXTURE_SPACE_MODULE),
            rays,
            cloud: module(TEXTURE_SPACE_CLOUD_MODULE),
            tree_module: module(TEXTURE_SPACE_TREE_MODULE),
        }
    }
}

/// Kept between frames: the mesh passes (built on first use, with the
/// scene's layout) and the atlas's textures (for one size).
#[derive(Default)]
pub(in crate::render) struct State {
    passes: Option<MeshPasses>,
    atlas: Option<Atlas>,
    /// The probe rays' acceleration structures, by mesh ([`probe_rays`];
    /// `None`: that mesh has no skin).
    rays: Vec<(u64, Option<rays::RayScene>)>,
    /// `--neighbours 3d`'s tree, for the atlas's size, and its build's
    /// pipelines (made on first use).
    tree: Option<cloud::Tree>,
    tree_pipelines: Option<cloud::Pipelines>,
}

/// The atlas side a frame of `frame` pixels draws: `--atlas-size`, but
/// never more than the power of two at or above twice the frame's longer
/// side (and never under 256). The atlas costs the same at any frame size
/// (48–54 ms at 1024² on lavapipe), so without the cap the editor's drag
/// previews (about 120–200 px a side) paid for texels four to eight times
/// finer than their pixels and ran at 6–7.5 frames a second
/// (docs/accuracy.md); the bench's frames (320 and 640 px wide) and the
/// editor's full frames keep the full atlas.
pub fn atlas_side(atlas_size: u32, (width, height): (u32, u32)) -> u32 {
    let cap = (2 * width.max(height)).next_power_of_two().max(MIN_ATLAS);
    atlas_size.min(cap)
}

/// The smallest atlas side [`atlas_side`] picks.
pub const MIN_ATLAS: u32 = 256;

fn encode(
    f: &mut FrameEncoder,
    p: &SssPipelines,
    io: &SssFrame,
    state: &mut super::State,
) -> Result<Scattered, GpuError> {
    let state = &mut state.texture_space;
    let inputs = &io.inputs.methods.texture_space;
    let by_3d = inputs.neighbours == Neighbours::ThreeD;
    // The point cloud's tree halves the atlas down to one node: a power of
    // two a side (a side of 1000 gathers over a 1024² atlas).
    let side = atlas_side(inputs.atlas_size, io.targets.size);
    let size = if by_3d { side.next_power_of_two() } else { side };
    let device = f.device;
    let passes = state
        .passes
        .get_or_insert_with(|| MeshPasses::new(device, &p.texture_space.module, io.scene_layout));
    let tree_pipelines = by_3d.then(|| cloud_pipelines(&mut state.tree_pipelines, passes, p, io));
    let scene = probe_rays(io, &mut state.rays)?;
    let passes = passes.with_rays(scene.is_some(), p, io);
    let rays = scene.zip(passes.rays.as_ref());
    if state.atlas.as_ref().map(|a| a.size) != Some(size) {
        state.atlas = None;
        state.atlas = Some(Atlas::new(device, size));
    }
    let Some(atlas) = state.atlas.as_ref() else {
        return Err(GpuError::Readback("texture-space: no atlas".into()));
    };
    // 1. The irradiance atlas: every triangle at its UVs.
    match (by_3d, &passes.cloud) {
        (true, Some(cloud)) => atlas.draw(f, io, &cloud.atlas),
        _ => atlas.draw(f, io, &passes.atlas),
    }
    // 1b. With --neighbours 3d, the point cloud's tree over it.
    let tree = match (tree_pipelines, &passes.cloud) {
        (Some(tp), Some(c)) => Some((built_tree(f, tp, io, (&mut state.tree, &c.coverage), atlas)?, tp)),
        (Some(_), None) => return Err(GpuError::Readback("texture-space: no cloud passes".into())),
        (None, _) => None,
    };
    // 2. The gather at each SSS pixel, into the ping target.
    // burley's disk and table (texture-space has none of its own).
    let disk = io.profile.methods.burley.disk();
    let n = disk.count;
    let label = "sss texture-space gather";
    let t = io.targets;
    let uniforms = SssUniforms {
        lut_radius_mm: disk.lut_radius_mm,
        lut_entries: LUT_SIZE as u32,
        ..io.uniforms(n)
    };
    let u = f.uniform("sss uniforms", bytemuck::bytes_of(&uniforms));
    let near = f.uniform(
        "texture-space uniforms",
        bytemuck::bytes_of(&TextureSpaceUniforms {
            near_field_mm: inputs.near_field_mm,
            pad0: 0.0,
            pad1: 0.0,
            pad2: 0.0,
        }),
    );
    let gather_bg = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout: &passes.gather_layout,
        entries: &[
            buf(0, &u),
            tex(1, &atlas.irradiance),
            tex(2, &atlas.position),
            tex(3, &atlas.position_lo),
            tex(4, t.view(HdrTarget::Diffuse)),
            buf(5, disk.samples),
            buf(6, disk.profile_lut),
            tex(7, &t.linear_depth),
            buf(8, &near),
        ],
    });
    let cloud_bg = tree.map(|(tree, tp)| {
        let uniforms = tree.uniforms(inputs.theta, inputs.near_field_mm);
        tree.bind_group(f, &tp.gather_layout, &uniforms)
    });
    let colour = [Some(color_attachment(t.view(HdrTarget::Ping), false))];
    let mut pass = f.encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &colour,
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view: &t.depth_stencil,
            depth_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: Some(wgpu::Operations {
                load: wgpu::LoadOp::Load,
                store: wgpu::StoreOp::Store,
            }),
        }),
        timestamp_writes: f.timer.render(label, io.sss_pixels, io.sss_pixels * n as u64),
        ..Default::default()
    });
    pass.set_stencil_reference(1);
    let cloud = passes.cloud.as_ref().map(|c| &c.gather);
    match (rays, cloud_bg.as_ref().zip(cloud)) {
        (_, Some((cloud_bg, pipeline))) => {
            io.drawn
                .draw_with(&mut pass, pipeline, &[io.scene_bind, &gather_bg, cloud_bg]);
        }
        (Some((scene, (pipeline, layout))), None) => {
            let rays_bg = scene.bind_group(device, layout);
            io.drawn
                .draw_with(&mut pass, pipeline, &[io.scene_bind, &gather_bg, &rays_bg]);
        }
        (None, None) => io
            .drawn
            .draw_with(&mut pass, &passes.gather, &[io.scene_bind, &gather_bg]),
    }
    drop(pass);
    Ok(Scattered::in_target(HdrTarget::Ping, n))
}

/// `--neighbours 3d`'s tree build (made on first use) and its passes that
/// draw the mesh (built into `passes` on first use).
fn cloud_pipelines<'s>(
    slot: &'s mut Option<cloud::Pipelines>,
    passes: &mut MeshPasses,
    p: &SssPipelines,
    io: &SssFrame,
) -> &'s cloud::Pipelines {
    let device = &io.ctx.device;
    let tp = slot.get_or_insert_with(|| cloud::Pipelines::new(device, &p.texture_space.tree_module));
    passes.build_cloud(device, &p.texture_space, (io.scene_layout, &tp.gather_layout));
    tp
}

/// `--neighbours 3d`'s tree for `atlas` (made for its size, kept while the
/// size is the same), built over this frame's atlas.
fn built_tree<'s>(
    f: &mut FrameEncoder,
    pipelines: &cloud::Pipelines,
    io: &SssFrame,
    (slot, coverage): (&'s mut Option<cloud::Tree>, &wgpu::RenderPipeline),
    atlas: &Atlas,
) -> Result<&'s cloud::Tree, GpuError> {
    if slot.as_ref().map(cloud::Tree::size) != Some(atlas.size) {
        *slot = None;
        *slot = Some(cloud::Tree::new(f.device, atlas.size)?);
    }
    let tree = slot
        .as_mut()
        .ok_or_else(|| GpuError::Readback("texture-space: no tree".into()))?;
    tree.set_mesh(drawn_mesh(io));
    tree.draw_coverage(f, io, coverage);
    tree.build(f, pipelines, atlas.views());
    Ok(tree)
}

/// The probe rays' scene where this frame gathers by them too
/// (`--probe-rays on`), built and submitted when the drawn mesh is new to
/// the cache (which keeps the last [`RAY_SCENES`], so that switching
/// between the levels of detail does not rebuild them); `None` where it
/// gathers through the UV layout alone (off, or a mesh with no skin).
fn probe_rays<'s>(
    io: &SssFrame,
    cache: &'s mut Vec<(u64, Option<rays::RayScene>)>,
) -> Result<Option<&'s rays::RayScene>, GpuError> {
    use crate::render::context::RayQueries;
    match (io.inputs.methods.texture_space.probe_rays, &io.ctx.ray_queries) {
        (ProbeRays::Off, _) => return Ok(None),
        (ProbeRays::On, RayQueries::Missing(why)) => {
            return Err(GpuError::NoRayQueries(why.clone()))
        }
        (ProbeRays::On, RayQueries::Available) => {}
    }
    // The level of detail the scene pass drew: the pixels' surface points
    // lie on it, and a ray through a finer one would find them up to its
    // deviation away.
    let mesh = drawn_mesh(io);
    let key = rays::mesh_key(mesh);
    let at = match cache.iter().position(|(k, _)| *k == key) {
        Some(at) => at,
        None => {
            if cache.len() >= RAY_SCENES {
                cache.remove(0);
            }
            let scene = rays::RayScene::new(&io.ctx.device, &io.ctx.queue, mesh);
            cache.push((key, scene));
            cache.len() - 1
        }
    };
    Ok(cache[at].1.as_ref())
}

/// The level of detail the scene pass drew this frame.
fn drawn_mesh<'m>(io: &SssFrame<'m>) -> &'m crate::render::mesh::Mesh {
    let mut mesh = io.mesh;
    while mesh.indices.len() as u32 != io.drawn.index_count {
        match &mesh.coarse {
            Some(coarse) => mesh = coarse,
            None => return io.mesh,
        }
    }
    mesh
}

/// How many meshes' probe-ray scenes are kept (a mesh and its coarser
/// level of detail).
const RAY_SCENES: usize = 2;

#[cfg(test)]
mod tests {
    use super::*;

    /// The cap by hand: 2 × 176 = 352 → 512; 2 × 640 = 1280 → 2048,
    /// above the asked 1024; 2 × 40 = 80 → 128, under the floor.
    #[test]
    fn the_atlas_is_capped_by_the_frame() {
        assert_eq!(atlas_side(1024, (176, 197)), 512);
        assert_eq!(atlas_side(1024, (640, 360)), 1024);
        assert_eq!(atlas_side(2048, (640, 360)), 2048);
        assert_eq!(atlas_side(2048, (320, 180)), 1024);
        assert_eq!(atlas_side(1024, (40, 40)), MIN_ATLAS);
        assert_eq!(atlas_side(128, (40, 40)), 128);
    }
}
