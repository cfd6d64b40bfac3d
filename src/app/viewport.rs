//! The live head: a render thread that owns the wgpu renderer and renders
//! only when the request changes; the UI shows its latest frame.
//!
//! The renderer runs on its own device on its own thread (not in
//! egui_wgpu's paint callback): a frame with SSS takes 30–150 ms on
//! lavapipe, and the UI thread must never wait for it. Requests are
//! coalesced: the thread renders the newest request and drops the rest.

use super::state::{CompareB, CompareMode, EnvironmentChoice, ViewState};
use crate::render::{
    FrameStats, GpuContext, Mesh, Method, ProfileInputs, RenderSettings, Renderer, Specular,
    TexturingMode, Transmission,
};
use crate::settings::rendering::{MethodId, TexturingId, TransmissionId};
use crate::settings::{Preset, ProfileSpec, RenderingSpec};
use std::path::PathBuf;
use std::sync::mpsc::{channel, Receiver, Sender};
use std::time::Instant;

/// d'Eon's 7-tap Gaussian kernel (the renderer's default).
const GAUSSIAN_TAPS: usize = crate::render::inputs::GAUSSIAN_TAPS;

pub fn method(id: MethodId) -> Method {
    match id {
        MethodId::None => Method::None,
        MethodId::Burley => Method::Burley,
        MethodId::Separable => Method::Separable,
        MethodId::Gaussians => Method::Gaussians,
        MethodId::Preintegrated => Method::Preintegrated,
        MethodId::Reference => Method::Reference,
    }
}

/// One side of a comparison: a look and the method it is rendered with.
#[derive(Debug, Clone, PartialEq)]
pub struct Look {
    pub profile: ProfileSpec,
    pub rendering: RenderingSpec,
}

impl Look {
    pub fn of(p: &Preset) -> Self {
        Self {
            profile: p.profile.clone(),
            rendering: p.rendering.clone(),
        }
    }
}

/// Everything a viewport frame depends on.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    pub a: Look,
    /// B and how to show it (`None`: A alone).
    pub b: Option<(Look, CompareMode, f32)>,
    /// Show B alone (the A/B toggle key).
    pub show_b: bool,
    pub view: ViewState,
    pub size: (u32, u32),
    pub mesh: Option<PathBuf>,
    /// Units and map slots of `mesh` (the default head knows its own).
    pub mesh_settings: super::state::MeshSettings,
    /// Set by [`Viewport::request`]: which request a frame answers.
    pub seq: u64,
}

/// What the editor needs to frame and scale a loaded mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshInfo {
    /// Height and cranium in the file's units.
    pub size: crate::render::mesh::HeadSize,
    pub metres_per_unit: f32,
    /// Camera distance (m) at which the mesh fills the view.
    pub framing_distance_m: f32,
}

/// What the thread sends back.
pub enum Reply {
    Frame {
        image: image::RgbaImage,
        stats: Box<FrameStats>,
        /// Wall time of the request on the render thread (ms).
        wall_ms: f64,
        /// Note for the status bar (difference scale).
        note: Option<String>,
        /// The request it answers.
        seq: u64,
    },
    Error(String),
    /// The mesh in the request was loaded (`None`: the default head).
    MeshLoaded(Option<PathBuf>, MeshInfo),
}

pub struct Viewport {
    tx: Sender<Request>,
    rx: Receiver<Reply>,
    /// The last request sent, with `seq` 0 (to compare), and its number.
    last_sent: Option<Request>,
    seq: u64,
    pub busy_since: Option<Instant>,
    /// The render thread, joined on drop.
    thread: Option<std::thread::JoinHandle<()>>,
}

impl Drop for Viewport {
    /// Closes the request channel (the render thread's loop ends after its
    /// current frame) and waits for the thread, so its GPU device is torn
    /// down before the process exits: leaving it running into exit aborted
    /// a test process once in lavapipe's teardown ("malloc_consolidate():
    /// unaligned fastbin chunk detected").
    fn drop(&mut self) {
        let (closed, _) = channel::<Request>();
        drop(std::mem::replace(&mut self.tx, closed));
        if let Some(t) = self.thread.take() {
            let _ = t.join();
        }
    }
}

impl Viewport {
    /// Starts the render thread; `wake` is called after each reply.
    pub fn start(wake: impl Fn() + Send + 'static) -> Self {
        let (tx, req_rx) = channel::<Request>();
        let (reply_tx, rx) = channel::<Reply>();
        let spawned = std::thread::Builder::new()
            .name("scatterlab-render".into())
            .spawn(move || worker(req_rx, reply_tx, wake));
        let thread = match spawned {
            Ok(t) => Some(t),
            Err(e) => {
                // The UI still works without the viewport.
                eprintln!("error: cannot start the render thread: {e}");
                None
            }
        };
        Self {
            tx,
            rx,
            last_sent: None,
            seq: 0,
            busy_since: None,
            thread,
        }
    }

    /// Sends `req` unless it equals the last one sent (nothing changed:
    /// nothing is rendered).
    pub fn request(&mut self, req: Request) {
        let mut req = req;
        req.seq = 0;
        if self.last_sent.as_ref() == Some(&req) {
            return;
        }
        self.last_sent = Some(req.clone());
        self.seq += 1;
        req.seq = self.seq;
        if self.tx.send(req).is_ok() {
            self.busy_since.get_or_insert_with(Instant::now);
        }
    }

    /// Replies that arrived since the last call.
    pub fn poll(&mut self) -> Vec<Reply> {
        let replies: Vec<Reply> = self.rx.try_iter().collect();
        // Busy until the newest request is answered (a frame of an older
        // one, still on its way, does not count) or has failed.
        let done = replies.iter().any(|r| match r {
            Reply::Frame { seq, .. } => *seq == self.seq,
            Reply::Error(_) => true,
            Reply::MeshLoaded(..) => false,
        });
        if done {
            self.busy_since = None;
        }
        replies
    }
}

/// Renderer settings for a look and view.
pub fn render_settings(look: &Look, view: &ViewState, (w, h): (u32, u32)) -> RenderSettings {
    let r = &look.rendering;
    let base = RenderSettings::default();
    let env = match view.environment {
        EnvironmentChoice::Studio => base.environment_sh,
        EnvironmentChoice::Black => [[0.0; 3]; 9],
        EnvironmentChoice::Map => view.environment_map_sh.unwrap_or(base.environment_sh),
    }
    .map(|c| c.map(|v| v * view.environment_intensity));
    let sp = &r.specular;
    RenderSettings {
        width: w,
        height: h,
        method: method(r.method),
        texturing: match r.texturing {
            TexturingId::PreAndPostScatter => TexturingMode::PreAndPostScatter,
            TexturingId::PostScatter => TexturingMode::PostScatter,
        },
        camera_yaw: view.camera_yaw,
        camera_pitch: view.camera_pitch,
        camera_distance_m: view.camera_distance_m,
        camera_pan_m: view.pan_m,
        light_azimuth: view.light_azimuth,
        light_elevation: view.light_elevation,
        light_intensity: view.light_intensity,
        exposure: view.exposure,
        transmission: match r.transmission {
            TransmissionId::Off => Transmission::Off,
            TransmissionId::ThinObject => Transmission::ThinObject,
            TransmissionId::ThickObject => Transmission::ThickObject,
        },
        transmission_tint: r.transmission_tint.map(|v| v as f32),
        lod: r.lod,
        specular: Specular::DualGgx {
            roughness0: (sp.roughness * sp.lobe0_roughness_multiplier).min(1.0) as f32,
            roughness1: (sp.roughness * sp.lobe1_roughness_multiplier).min(1.0) as f32,
            lobe_mix: sp.lobe_mix as f32,
        },
        specular_f0: r.f0() as f32,
        environment_sh: env,
        ..base
    }
}

/// The renderer and what it was last given, on the render thread.
struct Worker {
    renderer: Option<Renderer>,
    mesh_path: Option<PathBuf>,
    mesh_settings: super::state::MeshSettings,
    mesh_info: Option<MeshInfo>,
    /// The last reload changed the mesh or its units (not only its maps):
    /// the editor frames it anew.
    reframed: bool,
    /// Inputs per (look, method) of the last frame (A and B).
    cache: Vec<((ProfileSpec, usize, usize, Method), ProfileInputs)>,
    /// The default head whose surface maps are still to bake (after its
    /// first frame).
    pending_maps: Option<Mesh>,
}

fn timings_on() -> bool {
    std::env::var_os("SCATTERLAB_TIMINGS").is_some()
}

impl Worker {
    fn inputs(&mut self, look: &Look, m: Method) -> Result<ProfileInputs, String> {
        let key = (
            look.profile.clone(),
            look.rendering.samples,
            look.rendering.taps,
            m,
        );
        if let Some((_, i)) = self.cache.iter().find(|(k, _)| *k == key) {
            return Ok(i.clone());
        }
        let profile = look.profile.build().map_err(|e| e.to_string())?;
        let inputs = ProfileInputs::for_look(
            &look.profile,
            profile.as_ref(),
            m,
            (look.rendering.samples, look.rendering.taps),
            GAUSSIAN_TAPS,
        )
        .map_err(|e| e.to_string())?;
        self.cache.insert(0, (key, inputs.clone()));
        self.cache.truncate(4);
        Ok(inputs)
    }

    fn ensure_renderer(
        &mut self,
        mesh: &Option<PathBuf>,
        settings: &super::state::MeshSettings,
        thickness_range_mm: f32,
    ) -> Result<bool, String> {
        let same_settings = mesh.is_none() || self.mesh_settings == *settings;
        if self.renderer.is_some() && self.mesh_path == *mesh && same_settings {
            return Ok(false);
        }
        let mpu = settings.metres_per_unit;
        let t = Instant::now();
        // The GPU context starts while the mesh loads; the default head's
        // surface maps (about a second) bake after its first frame, so the
        // head shows first with neutral maps.
        let bake_later = mesh.is_none() && !Mesh::default_head_maps_baked();
        let (mesh_data, ctx) = std::thread::scope(|s| {
            let ctx = s.spawn(GpuContext::new_headless);
            let mesh_data = match mesh {
                Some(p) => Mesh::load(p, mpu)
                    .map_err(|e| e.to_string())
                    .and_then(|mut m| {
                        crate::render::textures::apply_slots(
                            std::sync::Arc::make_mut(&mut m.textures),
                            &settings.maps,
                            thickness_range_mm,
                        )
                        .map_err(|e| e.to_string())?;
                        Ok(m)
                    }),
                None if bake_later => Mesh::default_head_without_maps().map_err(|e| e.to_string()),
                None => Mesh::default_head().map_err(|e| e.to_string()),
            };
            (mesh_data, ctx.join())
        });
        let mesh_data = mesh_data?;
        let ctx = ctx
            .map_err(|_| "the GPU set-up thread panicked".to_string())?
            .map_err(|e| e.to_string())?;
        let t_setup = t.elapsed();
        self.renderer = Some(Renderer::new(ctx, &mesh_data).map_err(|e| e.to_string())?);
        self.reframed = self.mesh_path != *mesh
            || self.mesh_settings.metres_per_unit != settings.metres_per_unit;
        self.mesh_path = mesh.clone();
        self.mesh_settings = settings.clone();
        self.mesh_info = Some(MeshInfo {
            size: mesh_data.head_size(),
            metres_per_unit: mesh_data.metres_per_unit,
            framing_distance_m: mesh_data.framing_distance_m(RenderSettings::default().fov_y),
        });
        self.pending_maps = bake_later.then_some(mesh_data);
        if timings_on() {
            eprintln!(
                "timing: mesh and GPU context {:.2} s, renderer {:.2} s",
                t_setup.as_secs_f64(),
                (t.elapsed() - t_setup).as_secs_f64()
            );
        }
        Ok(true)
    }

    /// Bakes the default head's maps left by [`Worker::ensure_renderer`]
    /// (about a second; requests arriving meanwhile coalesce) and swaps them
    /// in. Returns whether there were maps to apply.
    fn apply_pending_maps(&mut self) -> Result<bool, String> {
        let Some(head) = self.pending_maps.take() else {
            return Ok(false);
        };
        let t = Instant::now();
        let maps = Mesh::default_head_maps(&head);
        if timings_on() {
            eprintln!(
                "timing: skin maps baked in {:.2} s",
                t.elapsed().as_secs_f64()
            );
        }
        let renderer = self.renderer.as_mut().ok_or("no renderer")?;
        renderer
            .set_surface_maps(&maps)
            .map_err(|e| e.to_string())?;
        Ok(true)
    }

    fn frame(
        &mut self,
        req: &Request,
    ) -> Result<(image::RgbaImage, FrameStats, Option<String>), String> {
        let (w, h) = req.size;
        let a_look = if req.show_b {
            req.b.as_ref().map(|b| &b.0).unwrap_or(&req.a)
        } else {
            &req.a
        };
        let a_settings = render_settings(a_look, &req.view, (w, h));
        let a_inputs = self.inputs(a_look, a_settings.method)?;
        let b = match (&req.b, req.show_b) {
            (Some((look, mode, split)), false) if *mode != CompareMode::Off => {
                let size = if *mode == CompareMode::SideBySide {
                    ((w / 2).max(16), h)
                } else {
                    (w, h)
                };
                let s = render_settings(look, &req.view, size);
                Some((self.inputs(look, s.method)?, s, *mode, *split))
            }
            _ => None,
        };
        let renderer = self.renderer.as_mut().ok_or("no renderer")?;
        let Some((b_inputs, b_settings, mode, split)) = b else {
            let (img, stats) = renderer
                .render(&a_inputs, &a_settings)
                .map_err(|e| e.to_string())?;
            return Ok((img, stats, None));
        };
        let a_settings = RenderSettings {
            width: b_settings.width,
            ..a_settings
        };
        let (a_img, stats) = renderer
            .render(&a_inputs, &a_settings)
            .map_err(|e| e.to_string())?;
        let (b_img, _) = renderer
            .render(&b_inputs, &b_settings)
            .map_err(|e| e.to_string())?;
        use crate::render::compare;
        Ok(match mode {
            CompareMode::Split => (compare::split_view(&a_img, &b_img, split), stats, None),
            CompareMode::Difference => {
                let (d, scale) = compare::difference_view(&a_img, &b_img, None);
                (
                    d,
                    stats,
                    Some(format!("|A − B| heat map: white = {scale:.3}")),
                )
            }
            _ => {
                let mut out = image::RgbaImage::new(a_img.width() * 2, a_img.height());
                image::imageops::replace(&mut out, &a_img, 0, 0);
                image::imageops::replace(&mut out, &b_img, a_img.width() as i64, 0);
                (out, stats, None)
            }
        })
    }
}

fn worker(rx: Receiver<Request>, tx: Sender<Reply>, wake: impl Fn()) {
    let mut w = Worker {
        renderer: None,
        mesh_path: None,
        mesh_settings: Default::default(),
        mesh_info: None,
        reframed: false,
        cache: Vec::new(),
        pending_maps: None,
    };
    // Set up the default head before the UI's first request arrives (an
    // error here recurs, and is reported, at that request).
    let _ = w.ensure_renderer(&None, &Default::default(), 1.0);
    // Coalesce: render only the newest request.
    while let Some(mut req) = super::analysis::recv_newest(&rx) {
        let t0 = Instant::now();
        let range = req.a.rendering.thickness_remap_mm.1 as f32;
        match w.ensure_renderer(&req.mesh, &req.mesh_settings, range) {
            Err(e) => {
                // Fall back to the head so the viewport keeps working.
                let _ = tx.send(Reply::Error(e));
                if req.mesh.is_some() {
                    req.mesh = None;
                    let _ = w.ensure_renderer(&None, &Default::default(), 1.0);
                    if let Some(info) = w.mesh_info {
                        let _ = tx.send(Reply::MeshLoaded(None, info));
                    }
                }
                if w.renderer.is_none() {
                    wake();
                    continue;
                }
            }
            Ok(true) => {
                if let Some(info) = w.mesh_info {
                    let _ = tx.send(Reply::MeshLoaded(req.mesh.clone(), info));
                    // The editor frames a new mesh (or new units) when this
                    // reply arrives; frame this first frame the same way,
                    // so a stale camera never shows. A change of maps
                    // alone keeps the artist's view.
                    if w.reframed {
                        req.view.camera_distance_m = info.framing_distance_m;
                        req.view.pan_m = [0.0; 2];
                    }
                }
            }
            Ok(false) => {}
        }
        let maps_pending = w.pending_maps.is_some();
        if !send_frame(&mut w, &req, t0, maps_pending, &tx) {
            return;
        }
        wake();
        // The head is on screen; now the same view with its skin maps.
        match w.apply_pending_maps() {
            Ok(false) => {}
            Ok(true) => {
                if !send_frame(&mut w, &req, Instant::now(), false, &tx) {
                    return;
                }
                wake();
            }
            Err(e) => {
                let _ = tx.send(Reply::Error(e));
                wake();
            }
        }
    }
}

/// Renders `req` and sends the frame (or the error); false when the UI has
/// gone.
fn send_frame(
    w: &mut Worker,
    req: &Request,
    t0: Instant,
    maps_pending: bool,
    tx: &Sender<Reply>,
) -> bool {
    let t1 = Instant::now();
    let frame = w.frame(req);
    if timings_on() {
        eprintln!(
            "timing: render thread frame {:.2} s ({:.2} s since the request)",
            t1.elapsed().as_secs_f64(),
            t0.elapsed().as_secs_f64()
        );
    }
    let reply = match frame {
        Ok((image, stats, note)) => Reply::Frame {
            image,
            stats: Box::new(stats),
            wall_ms: t0.elapsed().as_secs_f64() * 1e3,
            note: note.or_else(|| maps_pending.then(|| "baking the head's skin maps…".into())),
            seq: req.seq,
        },
        Err(e) => Reply::Error(e),
    };
    tx.send(reply).is_ok()
}

/// The B side of a comparison.
pub fn b_look(a: &Preset, b: &CompareB) -> Result<Look, String> {
    match b {
        CompareB::Method(m) => {
            let mut look = Look::of(a);
            look.rendering.method = *m;
            Ok(look)
        }
        CompareB::Preset(path) => Preset::load(path)
            .map(|p| Look::of(&p))
            .map_err(|e| e.to_string()),
    }
}
