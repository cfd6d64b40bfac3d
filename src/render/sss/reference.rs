//! `reference`: the ground truth, computed on the CPU (`render::ground_truth`
//! over `render::scene_cpu`'s twin of the scene pass). After the scene pass,
//! the frame reads back the diffuse target (its alpha: which pixels are
//! SSS), the linear depth (where each SSS pixel is on the surface) and the
//! shadow map (for the irradiance of points the camera does not see); the
//! cloud of irradiance cells is built once per light, look and profile and
//! kept while only the view changes; the gather's result goes into the ping
//! target, and the composite pass applies albedo^post and specular to it as
//! to every method's output.

use super::{Look, MethodInputs, ProfileInputs, Scattered, SssFrame, SssPipelines};
use crate::render::gpu_types::{SceneUniforms, SurfaceKind};
use crate::render::ground_truth::gpu::{scene_irradiance_wgsl, GpuCloud, MeshOnGpu};
use crate::render::ground_truth::{Cloud, GatherPoint, Probe};
use crate::render::mesh::Mesh;
use crate::render::passes::shadow::{ShadowPass, SHADOW_SIZE};
use crate::render::readback::{f32_to_half, half_to_f32, readback};
use crate::render::scene_cpu::{SceneIrradiance, ShadowMap, SurfaceMips};
use crate::render::targets::{HdrTarget, Targets};
use crate::render::settings::TruthProgress;
use crate::render::{GpuContext, GpuError, RenderSettings};
use glam::{Mat4, Vec3, Vec4};
use std::sync::Arc;
use std::time::Instant;

mod tiles;

/// `reference` in the registry (`sss::Method::sss`): computed on the CPU
/// into the ping target before the frame's composite ([`encode`]).
pub(in crate::render) static METHOD: super::MethodInfo = super::MethodInfo {
    id: "reference",
    label: "reference (exact, slow)",
    ground_truth: true,
    encode,
    ..super::MethodInfo::BASE
};

/// `reference`'s options (none on the command line).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::Args)]
#[group(skip)]
pub struct Options {
    /// With `--method reference`: gather N × N points of each pixel's
    /// surface, each read over its own footprint, and average them (1: the
    /// pixel's centre). 2 is the bench's check that one point is enough;
    /// `render` also gathers one point a pixel and prints how far it is
    /// from the N × N truth.
    #[arg(
        id = "supersample",
        long = "supersample",
        value_name = "N",
        default_value_t = 1,
        value_parser = clap::value_parser!(u32).range(1..=8)
    )]
    pub supersample: u32,
    /// Gather the ground truth on the GPU: a compute shader walks the same
    /// cells by the same rules, with the scene pass's own shading for the
    /// light it evaluates afresh (the CPU gather is the reference it is
    /// tested against).
    #[arg(id = "reference_gpu", long = "reference-gpu")]
    pub gpu: bool,
    /// The error bound of the ground truth: `final` (the yardstick's), or
    /// `loose` for a quicker first look (the same walk with the rule's τ
    /// four times larger; docs/rendering.md measures both).
    #[arg(long = "truth-bound", value_enum, default_value_t)]
    pub bound: crate::render::ground_truth::TruthBound,
}

impl Default for Options {
    fn default() -> Self {
        Self {
            supersample: 1,
            gpu: false,
            bound: Default::default(),
        }
    }
}

/// It has no pass and nothing on the GPU of its own.
pub(in crate::render) type Pipelines = ();
pub(in crate::render) type Buffers = ();

/// The ground truth's cells, kept while only the view changes.
pub(in crate::render) type State = Option<Cache>;

/// `reference`'s CPU input: the profile as the ground truth integrates it.
#[derive(Debug, Clone)]
pub struct Inputs {
    pub table: Arc<crate::render::ground_truth::ProfileTable>,
}

impl MethodInputs for Inputs {
    fn new(look: &Look<'_>, _bake: bool) -> Result<Self, crate::model::ModelError> {
        Ok(Self {
            table: Arc::new(crate::render::ground_truth::ProfileTable::with_bound(
                look.profile,
                look.options.reference.bound,
            )),
        })
    }

    fn fingerprint_into(&self, h: &mut impl std::hash::Hasher) {
        h.write(&self.table.fingerprint().to_le_bytes());
    }
}

/// Submits what the frame recorded so far (the scene pass must be on the
/// GPU before it is read back), then fills the ping target with the
/// ground truth ([`scatter`]).
fn encode(
    f: &mut crate::render::frame::FrameEncoder,
    _: &SssPipelines,
    io: &SssFrame,
    state: &mut super::State,
) -> Result<Scattered, GpuError> {
    let ctx = io.ctx;
    ctx.queue.submit([f.take().finish()]);
    let textures = Io::new(ctx, io.targets, io.shadow);
    let timing = scatter(
        ctx,
        io.mesh,
        &textures,
        (io.scene_bind, io.scene_layout),
        io.scene,
        io.view_from_world,
        io.settings,
        io.inputs,
        &mut state.reference,
        io.cancel,
    )?;
    Ok(Scattered {
        truth: Some(super::TruthFigures {
            cpu_ms: timing.build_ms.unwrap_or(0.0) + timing.gather_ms,
            build_ms: timing.build_ms,
            gpu_unfinished: timing.gpu_unfinished,
            tiles: timing.tiles,
        }),
        ..Scattered::in_target(HdrTarget::Ping, 0)
    })
}

/// Largest cell side of the ground truth's irradiance cloud (mm). The
/// gather splits cells further wherever its rule asks (within about
/// 1.4 mm of each shaded point for skin) and evaluates those pieces
/// afresh, so the samples near x stay under 0.5 mm apart; from 0.5 mm to
/// 1 mm the default head's cells went from 10.1 M to 2.5 M (build 1.5 →
/// 0.5 s, peak RSS of `render --method reference` at 640 × 360 497 →
/// 372 MB) and the frame's distance from a finer ground truth went from
/// 0.09 % to 0.06 % (issue 23; `render::ground_truth`'s module note).
pub const CELL_MM: f64 = 1.0;

/// The cells of the last frame and what they were built for, the clouds
/// of the profiles gathered over them, and the last frame.
pub(in crate::render) struct Cache {
    /// What the cells' irradiance depends on (`SceneIrradiance::key`).
    key: u64,
    shadow: Arc<ShadowMap>,
    mips: Arc<SurfaceMips>,
    /// The newest clouds over these cells, by their profile table's
    /// fingerprint (a look and its d → 0 twin share the cells).
    clouds: Vec<(u64, Arc<Cloud>)>,
    /// The last frame's ping texels and what they were for (cloud, view,
    /// size): showing the same view again (A/B toggles, compare modes)
    /// costs nothing.
    frame: Option<(u64, Vec<u8>)>,
    /// The GPU gather's mesh and the newest cloud on the GPU (by its
    /// profile's fingerprint), made on the first GPU frame.
    gpu: Option<(MeshOnGpu, Option<(u64, GpuCloud)>)>,
    /// The view being gathered in tiles, as far as it has got.
    partial: Option<tiles::Partial>,
}

impl Cache {
    /// The last frame's texels, if it was for these cells (`key`) and this
    /// frame (`frame_key`).
    fn frame_for(&self, key: u64, frame_key: u64) -> Option<&[u8]> {
        match &self.frame {
            Some((fk, bytes)) if self.key == key && *fk == frame_key => Some(bytes),
            _ => None,
        }
    }

    /// The cloud of `inputs`' profile over these cells (made and kept if
    /// new: bucketing the cells is a fraction of building them).
    fn cloud(&mut self, inputs: &ProfileInputs) -> Result<Arc<Cloud>, GpuError> {
        let fingerprint = inputs.methods.reference.table.fingerprint();
        if let Some((_, c)) = self.clouds.iter().find(|(f, _)| *f == fingerprint) {
            return Ok(c.clone());
        }
        let cells = self
            .clouds
            .first()
            .map(|(_, c)| c.cells().clone())
            .ok_or_else(|| GpuError::Readback("ground truth cells".into()))?;
        let cloud = Arc::new(Cloud::new(cells, (*inputs.methods.reference.table).clone()));
        self.clouds.insert(0, (fingerprint, cloud.clone()));
        self.clouds.truncate(3);
        Ok(cloud)
    }
}

/// What the ground truth cost (CPU wall time, ms).
struct Timing {
    pub build_ms: Option<f64>,
    pub gather_ms: f64,
    /// On the GPU: the points it did not finish (gathered on the CPU).
    pub gpu_unfinished: Option<u64>,
    /// In tiles: how far the view has got.
    pub tiles: Option<TruthProgress>,
}

/// The textures this pass reads and writes.
struct Io<'a> {
    pub diffuse: &'a wgpu::Texture,
    pub linear_depth: &'a wgpu::Texture,
    pub linear_depth_format: wgpu::TextureFormat,
    pub shadow_map: &'a wgpu::Texture,
    pub shadow_size: u32,
    pub ping: &'a wgpu::Texture,
}

impl<'a> Io<'a> {
    pub fn new(ctx: &GpuContext, t: &'a Targets, shadow: &'a ShadowPass) -> Self {
        Self {
            diffuse: t.texture(HdrTarget::Diffuse),
            linear_depth: &t.linear_depth_texture,
            linear_depth_format: ctx.linear_depth_format,
            shadow_map: &shadow.texture,
            shadow_size: SHADOW_SIZE,
            ping: t.texture(HdrTarget::Ping),
        }
    }
}

/// Fills the ping target with the ground truth's scattered diffuse on
/// every SSS pixel (alpha = the pixel's mask; 0 elsewhere). With
/// [`RenderSettings::truth_tiles`] (the editor) only the next tiles are
/// gathered, for about the budget, and the rest of the view is left for
/// the next frames of the same view ([`tiles`]).
#[allow(clippy::too_many_arguments)]
fn scatter(
    ctx: &GpuContext,
    mesh: &Mesh,
    io: &Io,
    scene_group: (&wgpu::BindGroup, &wgpu::BindGroupLayout),
    scene: &SceneUniforms,
    view: Mat4,
    s: &RenderSettings,
    inputs: &ProfileInputs,
    cache: &mut Option<Cache>,
    cancel: &std::sync::atomic::AtomicBool,
) -> Result<Timing, GpuError> {
    if !ctx.depth_copies {
        return Err(GpuError::NoGroundTruth {
            adapter: format!(
                "\"{}\" ({:?})",
                ctx.adapter_info.name, ctx.adapter_info.backend
            ),
        });
    }
    let (w, h) = (s.width, s.height);
    // The same cells, profile and view as the last frame: its texels,
    // before any readback (A/B toggles and compare modes ask for it again).
    let k = SceneIrradiance::key(scene);
    let frame_key = frame_key(k, scene, s, inputs);
    if let Some(bytes) = cache.as_ref().and_then(|c| c.frame_for(k, frame_key)) {
        write_ping(ctx, io.ping, bytes, w, h);
        return Ok(Timing {
            build_ms: None,
            gather_ms: 0.0,
            gpu_unfinished: None,
            tiles: s.truth_tiles.map(|t| tiles::finished(t, (w, h))),
        });
    }
    let gather = Gather {
        ctx,
        mesh,
        scene,
        scene_group,
        supersample: inputs.options.reference.supersample.max(1),
        on_gpu: inputs.options.reference.gpu,
        cancel,
    };
    if let Some(t) = s.truth_tiles {
        return tiles::scatter(&gather, io, (view, s, inputs), cache, (k, frame_key), t);
    }
    let t0 = Instant::now();
    let (pixels, points, build_ms) = prepare(&gather, io, (view, s, inputs), cache, k)?;
    let Some(c) = cache.as_mut() else {
        return Err(GpuError::Readback("ground truth cache".into()));
    };
    let cloud = c.cloud(inputs)?;
    let (scattered, gpu_unfinished) = gather.run(c, &cloud, &points, true)?;
    if std::env::var_os("SCATTERLAB_TIMINGS").is_some() {
        eprintln!(
            "timing: reference: {} cells, {} points, build {:?} ms, gather ({}) {:.0} ms",
            cloud.len(),
            points.len(),
            build_ms,
            if gather.on_gpu { "GPU" } else { "CPU" },
            t0.elapsed().as_secs_f64() * 1e3
        );
    }
    let gather_ms = t0.elapsed().as_secs_f64() * 1e3;
    let out = rgba_half_texels(pixels, scattered, (w, h));
    write_ping(ctx, io.ping, &out, w, h);
    c.frame = Some((frame_key, out));
    Ok(Timing {
        build_ms,
        gather_ms,
        gpu_unfinished,
        tiles: None,
    })
}

/// Each SSS pixel (its index and mask) with its probe, and the time the
/// cells took when they were built for this frame: the scene's diffuse
/// and depth read back, the cells made where the light, look or maps
/// changed (the cache keeps them otherwise).
type Prepared = (Vec<(usize, f32)>, Vec<Probe>, Option<f64>);

fn prepare(
    g: &Gather,
    io: &Io,
    (view, s, inputs): (Mat4, &RenderSettings, &ProfileInputs),
    cache: &mut Option<Cache>,
    k: u64,
) -> Result<Prepared, GpuError> {
    let ctx = g.ctx;
    let (w, h) = (s.width, s.height);
    let depth_bpp: u32 = match io.linear_depth_format {
        wgpu::TextureFormat::R32Float => 4,
        wgpu::TextureFormat::R16Float => 2,
        _ => 8,
    };
    let encoder = ctx
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("reference readback"),
        });
    let mut read = readback(
        ctx,
        encoder,
        &[(io.diffuse, 8), (io.linear_depth, depth_bpp)],
        w,
        h,
    )?;
    let depth_bytes = read.pop().unwrap_or_default();
    let diffuse_bytes = read.pop().unwrap_or_default();
    let half = |b: &[u8], k: usize| half_to_f32(u16::from_le_bytes([b[2 * k], b[2 * k + 1]]));
    let depth_at = |i: usize| -> f32 {
        let n = depth_bpp as usize;
        let b = &depth_bytes[i * n..(i + 1) * n];
        match depth_bpp {
            4 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]),
            _ => half(b, 0),
        }
    };
    let mut build_ms = None;
    if cache.as_ref().is_none_or(|c| c.key != k) {
        let t0 = Instant::now();
        let (cloud, shadow, mips) = build_cloud(ctx, g.mesh, io, g.scene, inputs)?;
        build_ms = Some(t0.elapsed().as_secs_f64() * 1e3);
        *cache = Some(Cache {
            key: k,
            clouds: vec![(inputs.methods.reference.table.fingerprint(), cloud)],
            shadow,
            mips,
            frame: None,
            gpu: None,
            partial: None,
        });
    }
    // Each SSS pixel's point on the surface, from its linear view depth.
    let (pixels, points) = surface_points(
        |i| half(&diffuse_bytes[8 * i..8 * i + 8], 3),
        depth_at,
        (w, h),
        view,
        s.view.fov_y_rad,
        1000.0 * g.mesh.metres_per_unit,
    );
    Ok((pixels, points, build_ms))
}

/// What a gather needs besides the cells and the probes.
struct Gather<'a> {
    ctx: &'a GpuContext,
    mesh: &'a Mesh,
    scene: &'a SceneUniforms,
    scene_group: (&'a wgpu::BindGroup, &'a wgpu::BindGroupLayout),
    /// k × k points a pixel (the floor's 2 × 2 check).
    supersample: u32,
    on_gpu: bool,
    cancel: &'a std::sync::atomic::AtomicBool,
}

impl Gather<'_> {
    /// The gather at `probes` on the CPU, or on the GPU with the points it
    /// does not finish gathered on the CPU (their number). `progress`:
    /// report it to [`crate::render::ground_truth::progress`] (the whole
    /// frame at once; a tile of it is reported by the frame's tiles).
    fn run(
        &self,
        c: &mut Cache,
        cloud: &Cloud,
        probes: &[Probe],
        progress: bool,
    ) -> Result<(Gathered, Option<u64>), GpuError> {
        if self.on_gpu {
            let (v, unfinished) = gather_on_gpu(
                self.ctx,
                (self.mesh, self.scene),
                c,
                cloud,
                self.scene_group,
                probes,
                self.supersample,
                self.cancel,
            )?;
            return Ok((v, Some(unfinished)));
        }
        let irr = SceneIrradiance::new(self.mesh, *self.scene, &c.shadow, &c.mips);
        let v = cloud
            .gather_all(probes, self.supersample, &irr, self.cancel, progress)
            .ok_or(GpuError::Cancelled)?;
        Ok((v, None))
    }
}

/// Each probe's scattered irradiance (`None`: not one surface under a
/// supersampled pixel).
type Gathered = Vec<Option<[f32; 3]>>;

/// The gather at every probe on the GPU (`ground_truth::gpu`): the
/// probes' points are found on the CPU as for the CPU gather
/// ([`Cloud::gather_points`]), the walk runs in a compute shader with the
/// scene pass's shading, and a pixel's k × k points are averaged here.
/// A point whose walk the GPU did not finish (the driver's loop limit;
/// see `shaders/ground_truth.wgsl`) is gathered on the CPU; their number
/// is returned with the values.
#[allow(clippy::too_many_arguments)]
fn gather_on_gpu(
    ctx: &GpuContext,
    (mesh, scene): (&Mesh, &SceneUniforms),
    c: &mut Cache,
    cloud: &Cloud,
    (scene_bind, scene_layout): (&wgpu::BindGroup, &wgpu::BindGroupLayout),
    probes: &[Probe],
    supersample: u32,
    cancel: &std::sync::atomic::AtomicBool,
) -> Result<(Gathered, u64), GpuError> {
    use rayon::prelude::*;
    if c.gpu.is_none() {
        c.gpu = Some((MeshOnGpu::new(ctx, mesh)?, None));
    }
    let Some((mesh_gpu, slot)) = c.gpu.as_mut() else {
        return Err(GpuError::Readback("ground truth GPU cache".into()));
    };
    let fingerprint = cloud.table().fingerprint();
    if slot.as_ref().is_none_or(|(f, _)| *f != fingerprint) {
        let source = scene_irradiance_wgsl();
        let t0 = Instant::now();
        let g = GpuCloud::new(ctx, cloud, &source, &[scene_layout, &mesh_gpu.layout])?;
        if std::env::var_os("SCATTERLAB_TIMINGS").is_some() {
            eprintln!(
                "timing: GPU gather: pipeline and upload {:.0} ms",
                t0.elapsed().as_secs_f64() * 1e3
            );
        }
        *slot = Some((fingerprint, g));
    }
    let Some((_, gpu)) = slot.as_ref() else {
        return Err(GpuError::Readback("ground truth GPU cloud".into()));
    };
    let per_probe: Vec<Option<Vec<GatherPoint>>> = probes
        .par_iter()
        .map(|p| cloud.gather_points(p, supersample))
        .collect();
    if cancel.load(std::sync::atomic::Ordering::Relaxed) {
        return Err(GpuError::Cancelled);
    }
    let flat: Vec<GatherPoint> = per_probe.iter().flatten().flatten().copied().collect();
    let mut got = gpu.gather(ctx, &flat, &[scene_bind, &mesh_gpu.bind])?;
    let unfinished: Vec<usize> = (0..got.len()).filter(|&i| got[i].is_none()).collect();
    if !unfinished.is_empty() {
        let irr = SceneIrradiance::new(mesh, *scene, &c.shadow, &c.mips);
        let again: Vec<GatherPoint> = unfinished.iter().map(|&i| flat[i]).collect();
        for (i, v) in unfinished.iter().zip(cloud.gather_at_points(&again, &irr)) {
            got[*i] = Some(v);
        }
    }
    let mut at = 0;
    let values = per_probe
        .iter()
        .map(|pts| {
            let pts = pts.as_ref()?;
            let mine = &got[at..at + pts.len()];
            at += pts.len();
            let mut acc = [0.0f64; 3];
            for v in mine {
                let v = (*v)?;
                for k in 0..3 {
                    acc[k] += v[k] as f64;
                }
            }
            Some(acc.map(|v| (v / pts.len() as f64) as f32))
        })
        .collect();
    Ok((values, unfinished.len() as u64))
}

/// What a finished frame is kept under: the cells, the profile, the scene
/// and the view.
fn frame_key(cells: u64, scene: &SceneUniforms, s: &RenderSettings, inputs: &ProfileInputs) -> u64 {
    use std::hash::{Hash, Hasher};
    let mut hs = std::collections::hash_map::DefaultHasher::new();
    cells.hash(&mut hs);
    inputs.methods.reference.table.fingerprint().hash(&mut hs);
    bytemuck::bytes_of(scene).hash(&mut hs);
    let view = (
        s.view.fov_y_rad.to_bits(),
        inputs.options.reference.supersample,
        inputs.options.reference.gpu,
    );
    (s.width, s.height, view).hash(&mut hs);
    hs.finish()
}

/// What a cloud is built from and kept with.
type Built = (Arc<Cloud>, Arc<ShadowMap>, Arc<SurfaceMips>);

/// The ground truth's irradiance cloud over the mesh's skin, lit as the
/// scene pass lights it (the shadow map read back), that shadow map and
/// the maps' mip chains.
fn build_cloud(
    ctx: &GpuContext,
    mesh: &Mesh,
    io: &Io,
    scene: &SceneUniforms,
    inputs: &ProfileInputs,
) -> Result<Built, GpuError> {
    let encoder = ctx
        .device
        .create_command_encoder(&wgpu::CommandEncoderDescriptor {
            label: Some("shadow readback"),
        });
    let n = io.shadow_size;
    let bytes = readback(ctx, encoder, &[(io.shadow_map, 4)], n, n)?
        .pop()
        .unwrap_or_default();
    let shadow = Arc::new(ShadowMap {
        size: n,
        depth: bytes
            .chunks_exact(4)
            .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
            .collect(),
    });
    let mips = Arc::new(SurfaceMips::new(mesh));
    let irr = SceneIrradiance::new(mesh, *scene, &shadow, &mips);
    let mm = 1000.0 * mesh.metres_per_unit;
    let positions: Vec<Vec3> = mesh
        .vertices
        .iter()
        .map(|v| Vec3::from(v.position) * mm)
        .collect();
    let triangles: Vec<[u32; 3]> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    // Every triangle with some skin: the scene pass decides skin per
    // fragment by the interpolated material, and so does the twin per
    // point (a triangle with one vertex on an eye is skin over part of it).
    let skin = |t: usize| {
        let m = &mesh.vertices;
        triangles[t]
            .iter()
            .any(|&i| SurfaceKind::of(m[i as usize].material) == SurfaceKind::Skin)
    };
    let cloud = Cloud::build(
        &positions,
        &triangles,
        skin,
        &irr,
        (*inputs.methods.reference.table).clone(),
        CELL_MM,
    );
    Ok((Arc::new(cloud), shadow, mips))
}

/// Each SSS pixel (index and mask) and its probe: its point on the surface
/// (mm), from its linear view depth, with the camera ray's differentials;
/// pixels whose mask exceeds 1/255.
fn surface_points(
    mask_at: impl Fn(usize) -> f32,
    depth_at: impl Fn(usize) -> f32,
    (w, h): (u32, u32),
    view: Mat4,
    fov_y_rad: f32,
    mm: f32,
) -> (Vec<(usize, f32)>, Vec<Probe>) {
    let world_from_view = view.inverse();
    let tan = (0.5 * fov_y_rad).tan();
    let aspect = w as f32 / h as f32;
    let camera_mm = world_from_view.transform_point3(Vec3::ZERO) * mm;
    // The ray at unit view depth, and its change per pixel.
    let ray_dx =
        world_from_view.transform_vector3(Vec3::new(2.0 * tan * aspect / w as f32, 0.0, 0.0));
    let ray_dy = world_from_view.transform_vector3(Vec3::new(0.0, -2.0 * tan / h as f32, 0.0));
    let mut pixels = Vec::new();
    let mut probes = Vec::new();
    // In 8 × 8 tiles, so that the gather's chunks (`MEMO_CHUNK`) are
    // neighbours that split the same cells.
    let (w_px, h_px) = (w as usize, h as usize);
    let tiles = (0..h_px.div_ceil(8)).flat_map(|ty| (0..w_px.div_ceil(8)).map(move |tx| (tx, ty)));
    let in_tile = |(tx, ty): (usize, usize)| {
        (8 * ty..(8 * ty + 8).min(h_px))
            .flat_map(move |py| (8 * tx..(8 * tx + 8).min(w_px)).map(move |px| (px, py)))
    };
    for (px, py) in tiles.flat_map(in_tile) {
        {
            let i = py * w_px + px;
            let alpha = mask_at(i);
            let z = depth_at(i);
            if alpha <= 1.0 / 255.0 || !(z > 0.0) {
                continue;
            }
            let x = ((px as f32 + 0.5) / w as f32 * 2.0 - 1.0) * tan * aspect;
            let y = (1.0 - (py as f32 + 0.5) / h as f32 * 2.0) * tan;
            let p = world_from_view * Vec4::new(x * z, y * z, -z, 1.0);
            pixels.push((i, alpha));
            probes.push(Probe {
                x_mm: p.truncate() * mm,
                camera_mm,
                ray: world_from_view.transform_vector3(Vec3::new(x, y, -1.0)),
                ray_dx,
                ray_dy,
                quad: glam::Vec2::new((px % 2) as f32, (py % 2) as f32),
                profile_scale: alpha.min(1.0),
            });
        }
    }
    (pixels, probes)
}

/// The scattered irradiance and mask of each pixel as Rgba16Float texels
/// (0 elsewhere). A supersampled frame (the floor check, never the
/// editor's) marks a pixel whose footprint is not one surface
/// (`Cloud::gather_supersampled`) with NaN irradiance, which the bench's
/// metrics leave out and the composite draws black.
fn rgba_half_texels(
    pixels: Vec<(usize, f32)>,
    scattered: Vec<Option<[f32; 3]>>,
    (w, h): (u32, u32),
) -> Vec<u8> {
    let mut out = vec![0u8; 8 * (w * h) as usize];
    for ((i, alpha), v) in pixels.into_iter().zip(scattered) {
        let v = v.unwrap_or([f32::NAN; 3]);
        for (k, x) in [v[0], v[1], v[2], alpha].into_iter().enumerate() {
            let b = f32_to_half(x).to_le_bytes();
            out[8 * i + 2 * k] = b[0];
            out[8 * i + 2 * k + 1] = b[1];
        }
    }
    out
}

fn write_ping(ctx: &GpuContext, ping: &wgpu::Texture, texels: &[u8], w: u32, h: u32) {
    ctx.queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture: ping,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        texels,
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(8 * w),
            rows_per_image: Some(h),
        },
        wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        },
    );
}
