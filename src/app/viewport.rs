//! The live head: a render thread that owns the wgpu renderer and renders
//! only when the request changes; the UI shows its latest frame.
//!
//! The renderer runs on its own device on its own thread (not in
//! egui_wgpu's paint callback): a full frame with SSS takes 0.2–0.7 s on
//! lavapipe, and the UI thread must never wait for it. Requests are
//! coalesced: the thread renders the newest request and drops the rest.
//!
//! Live while the artist works, exact when they stop: a request made
//! while something is dragged ([`Request::interactive`]) renders at a
//! fraction of the resolution, chosen from the frames before so that one
//! takes about [`PREVIEW_BUDGET_MS`]; once input stops the thread renders
//! the full resolution and then, for the stochastic methods, keeps adding
//! frames with fresh sample rotations to a running mean
//! ([`crate::render::Progressive`]) until the image stops changing
//! ([`converged`]) or a new request arrives. docs/rendering.md has the
//! frame rates and times measured by `tools/measure_live.sh`.

use super::state::{CompareB, CompareMode, EnvironmentChoice, ViewState};
use crate::render::{
    FrameStats, GpuContext, Mesh, Method, ProfileInputs, Progressive, RenderSettings, Renderer,
    SceneLinear,
};
use crate::settings::rendering::MethodId;
use crate::settings::{Preset, ProfileSpec, RenderingSpec};
use std::path::PathBuf;
use std::sync::mpsc::{channel, Receiver, Sender};
use std::time::Instant;

/// d'Eon's 7-tap Gaussian kernel (the renderer's default).
mod framing;
mod thread;
mod worker;
pub use framing::side_by_side_zoom_out;
pub use thread::Fault;
use thread::*;
pub use worker::load_mesh;
use worker::*;

/// One side of a comparison: a look and the method it is rendered with.
#[derive(Debug, Clone, PartialEq)]
pub struct Look {
    pub profile: ProfileSpec,
    pub rendering: RenderingSpec,
    /// Where the surface colour comes from on a mesh with a colour map.
    pub map_colour: crate::render::textures::MapColour,
}

impl Look {
    /// `p`, on a colour map drawn in the map's colour.
    pub fn of(p: &Preset) -> Self {
        Self {
            profile: p.profile.clone(),
            rendering: p.rendering.clone(),
            map_colour: Default::default(),
        }
    }

    /// With the surface colour from `map_colour`.
    pub fn with_map_colour(self, map_colour: crate::render::textures::MapColour) -> Self {
        Self { map_colour, ..self }
    }
}

/// A loaded HDR map for the background, shared without copying: two are
/// the same when they are the same allocation (a request compares and
/// keys on it every frame).
#[derive(Clone)]
pub struct SharedMap(pub std::sync::Arc<crate::render::environment::BackgroundMap>);

impl PartialEq for SharedMap {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.0, &other.0)
    }
}

impl std::fmt::Debug for SharedMap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "SharedMap({}×{})", self.0.width, self.0.height)
    }
}

/// Everything a viewport frame depends on.
#[derive(Debug, Clone, PartialEq)]
pub struct Request {
    pub a: Look,
    /// B and how to show it (`None`: A alone).
    pub b: Option<(Look, CompareMode, f32)>,
    /// The difference view's white, |ΔL*| of CIE lightness (0–100);
    /// `None`: the frame's largest difference (auto-scaling).
    pub difference_scale: Option<f32>,
    /// Show B alone (the A/B toggle key).
    pub show_b: bool,
    pub view: ViewState,
    pub size: (u32, u32),
    pub mesh: Option<PathBuf>,
    /// Units and map slots of `mesh` (the default head knows its own).
    pub mesh_settings: super::state::MeshSettings,
    /// Made while the artist drags (a slider, the orbit, a panel): render
    /// a quick preview, not the converged frame.
    pub interactive: bool,
    /// Once the method's frame has converged, go on to the ground truth
    /// and make it the viewport's converged state (A alone, not while
    /// comparing: a comparison shows the two sides it names).
    pub refine_to_truth: bool,
    /// Set by [`Viewport::request`]: which request a frame answers.
    pub seq: u64,
    /// The HDR map to draw behind the head when `view.background.show`
    /// and the environment is the map.
    pub background_map: Option<SharedMap>,
    /// Read back the converged frame's scene-linear radiance and send it
    /// with the frame (the editor's probe and histogram, an EXR still):
    /// 28 bytes a pixel, so only where it is used (not thumbnails or
    /// turntables).
    pub want_radiance: bool,
}

impl Request {
    /// Whether A or B is drawn with the ground truth.
    fn has_truth(&self) -> bool {
        let b = self.b.as_ref().map(|b| &b.0);
        std::iter::once(&self.a)
            .chain(b)
            .any(|l| l.rendering.method.sss().ground_truth)
    }

    /// The request as a finished frame is kept under (its number and
    /// whether input was live do not change the frame).
    fn key(&self) -> Request {
        Request {
            seq: 0,
            interactive: false,
            ..self.clone()
        }
    }
}

/// A coarse ground truth first, at 1/this of the resolution per axis (a
/// comparison with the ground truth on one side; A alone gets tiles).
pub const COARSE_TRUTH_DIVISOR: f32 = 4.0;

/// The ground truth's tiles (px a side): 32 px hold up to 1,024 SSS
/// pixels of a face, about 75 ms of gathering on two cores (Mesa 25's
/// lavapipe, the scan at 1500×900). A frame gathers at least one tile:
/// 64 px tiles took about 300 ms each, and the first tiles came 0.56–0.58 s
/// after an orbit where 32 px ones came in 0.44–0.48 s, the full truth
/// the same within the machine's noise (docs/rendering.md).
pub const TRUTH_TILE_PX: u32 = 32;

/// What one frame of tiles may spend gathering (ms): the viewport shows
/// new tiles about three times a second and takes a newer request
/// between frames (one arriving during a frame stops its gather).
pub const TRUTH_TILES_BUDGET_MS: f64 = 300.0;

/// The first frame of tiles of a view gathers for this long (ms): the
/// first tiles show soon after the view stops, the later frames keep the
/// longer budget (fewer frames composed and sent for the same gather).
pub const FIRST_TRUTH_TILES_BUDGET_MS: f64 = 100.0;

/// Finished frames kept, per view, so that going back to one costs nothing.
const KEPT_FRAMES: usize = 8;

/// What a preview frame may take on the render thread (ms): 30 frames a
/// second with room left for the UI's own frames, which share the two
/// cores (a UI frame of the whole window costs lavapipe 10–20 ms of CPU).
/// At 50 ms an orbit drew 17–19 frames a second on Mesa 25; at 25 ms,
/// 36–39 (docs/rendering.md, "Live while you work").
pub const PREVIEW_BUDGET_MS: f64 = 25.0;

/// The preview's resolution divisors (per axis).
const PREVIEW_DIVISORS: [f32; 7] = [1.0, 1.25, 1.5, 2.0, 2.5, 3.0, MAX_PREVIEW_DIVISOR];

/// The coarsest preview: a quarter of the viewport's width and height
/// (176 px of the default window's 704); 5 and 6 were allowed before.
pub const MAX_PREVIEW_DIVISOR: f32 = 4.0;

/// Progressive refinement stops here even if pixels still change.
pub const MAX_REFINE_FRAMES: u32 = 64;

/// How far a frame has got.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Quality {
    /// While input goes on: 1/`divisor` of the viewport's resolution in
    /// each direction.
    Preview { divisor: f32 },
    /// The ground truth at 1/`divisor` of the resolution, the full frame
    /// next (a comparison with the ground truth in it).
    Coarse { divisor: f32 },
    /// The ground truth in full-resolution tiles over `under`'s frame
    /// (the artist's converged method, or a labelled preview): `done` of
    /// `tiles` finished, `left_s` the time left from the measured pace.
    Truth {
        done: u32,
        tiles: u32,
        left_s: Option<f64>,
        under: MethodId,
    },
    /// Full resolution; `frames` so far in the running mean, more to come.
    Refining { frames: u32 },
    /// Full resolution and final: the mean of `frames` stopped changing
    /// (1 for a method without random rotations), `ms` after input stopped.
    Converged { frames: u32, ms: f64 },
}

impl Quality {
    /// For the status bar.
    pub fn describe(&self) -> String {
        match self {
            Quality::Preview { divisor } if *divisor > 1.0 => {
                format!("preview at 1/{divisor:.1} resolution while you work")
            }
            Quality::Preview { .. } => "preview while you work".into(),
            Quality::Coarse { divisor } => {
                format!("coarse, 1/{divisor:.0} resolution: the full frame next")
            }
            Quality::Truth {
                tiles: 0, under, ..
            } => {
                format!("{}'s frame, the ground truth's tiles next", under.id())
            }
            Quality::Truth {
                done,
                tiles,
                left_s,
                under,
            } => format!(
                "ground truth: {done} of {tiles} tiles over {}'s frame{}",
                under.id(),
                left_s.map_or(String::new(), |s| format!(", {s:.0} s left"))
            ),
            Quality::Refining { frames } => format!("refining … {frames} frames"),
            Quality::Converged { frames: 1, ms } => format!("converged in {:.1} s", ms / 1e3),
            Quality::Converged { frames, ms } => {
                format!("converged in {:.1} s ({frames} frames)", ms / 1e3)
            }
        }
    }
}

/// Whether a running mean has stopped changing: from `prev` to `next`
/// (8-bit sRGB frames) no more than 1 pixel in 1000 moved by more than
/// one level in any channel. The mean's step is (x − mean)/(n + 1), so it
/// drops under a level once n exceeds the per-frame noise in levels.
pub fn converged(prev: &image::RgbaImage, next: &image::RgbaImage) -> bool {
    if prev.dimensions() != next.dimensions() {
        return false;
    }
    let moved = prev
        .pixels()
        .zip(next.pixels())
        .filter(|(a, b)| (0..3).any(|c| a.0[c].abs_diff(b.0[c]) > 1))
        .count();
    moved * 1000 <= prev.pixels().len()
}

/// A converged frame and its scene-linear radiance (one look alone).
pub type Converged = (image::RgbaImage, Option<std::sync::Arc<SceneLinear>>);

/// What the editor needs to frame and scale a loaded mesh.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeshInfo {
    /// Height and cranium in the file's units.
    pub size: crate::render::mesh::HeadSize,
    pub metres_per_unit: f32,
    /// Camera distance (m) at which the mesh fills the view.
    pub framing_distance_m: f32,
    /// The centre of the mesh's bounding box from the camera's focus (m):
    /// what F frames.
    pub bounds_centre_m: [f32; 3],
    /// The radius about that centre that holds every vertex (m).
    pub bounds_radius_m: f32,
    /// Which way the mesh faces as drawn (inside out: a dark disc).
    pub facing: crate::render::mesh::Facing,
    /// The mean linear colour of the mesh's own colour map
    /// ([`crate::render::textures::albedo_map_mean`]); `None` without one
    /// (the default head's map only modulates the look's colour).
    pub colour_map_mean: Option<[f32; 3]>,
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
        /// A difference view's scale: |ΔL*| shown white.
        difference_scale: Option<f32>,
        /// The request it answers.
        seq: u64,
        quality: Quality,
        /// The frame's scene-linear radiance (before exposure and the
        /// display transform): sent with a view's converged frame when the
        /// request wants it and it shows one look alone, else `None` (also
        /// on the method's converged frame that "to truth" goes on from).
        radiance: Option<std::sync::Arc<crate::render::SceneLinear>>,
    },
    Error(String),
    /// The mesh in the request was loaded (`None`: the default head).
    MeshLoaded(Option<PathBuf>, MeshInfo),
    /// The request's mesh or its maps failed to load: the mesh on screen
    /// (`kept`, `None`: the default head) stays, with the settings it was
    /// loaded with, and the frame is drawn with it.
    MeshFailed {
        /// The mesh the failed request asked for.
        asked: Option<PathBuf>,
        error: String,
        kept: Option<PathBuf>,
        kept_settings: crate::app::state::MeshSettings,
    },
    /// The render thread recovered from a failure of its own (a panic, a
    /// lost GPU device): what happened, for the artist. `resend`: the
    /// request in hand was lost with it and must be sent again.
    Recovered {
        message: String,
        resend: bool,
    },
}

/// How many times a request lost to a render-thread failure is sent again
/// before the viewport waits for the next one.
const MAX_RESENDS: u32 = 2;

pub struct Viewport {
    tx: Sender<Request>,
    rx: Receiver<Reply>,
    /// The last request sent, with `seq` 0 (to compare), and its number.
    last_sent: Option<Request>,
    seq: u64,
    pub busy_since: Option<Instant>,
    /// The render thread, joined on drop.
    thread: Option<std::thread::JoinHandle<()>>,
    /// Set with each new request: the render thread's renderer stops a
    /// ground truth computed for an older one (`Renderer::cancel_with`).
    cancel: std::sync::Arc<std::sync::atomic::AtomicBool>,
    /// Failures a test injects into the render thread.
    faults: std::sync::Arc<Faults>,
    /// The pointer over the viewport, for the ground truth's tiles.
    focus: Focus,
    /// Render-thread failures since the last frame: a request that fails
    /// every time is sent again only twice, not for ever.
    failures_in_a_row: u32,
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
        let cancel = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let theirs = cancel.clone();
        let faults = std::sync::Arc::new(Faults::default());
        let their_faults = faults.clone();
        let focus = Focus::default();
        let their_focus = focus.clone();
        let spawned = std::thread::Builder::new()
            .name("scatterlab-render".into())
            .spawn(move || {
                supervise(
                    &req_rx,
                    &reply_tx,
                    (&theirs, &their_focus),
                    &wake,
                    &their_faults,
                )
            });
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
            cancel,
            faults,
            focus,
            failures_in_a_row: 0,
        }
    }

    /// Where the pointer is over the viewport (fractions of its width and
    /// height; `None`: not over it): the ground truth's next tiles are the
    /// nearest to it, else to the centre. Read between frames; it changes
    /// no request.
    pub fn set_focus(&self, at: Option<[f32; 2]>) {
        if let Ok(mut f) = self.focus.lock() {
            *f = at;
        }
    }

    /// Makes the render thread fail on its next request, or the one after
    /// the faults already queued (tests of the recovery; nothing in the
    /// editor calls it).
    #[doc(hidden)]
    pub fn inject_fault(&self, fault: Fault) {
        self.faults.set(fault);
    }

    /// Sends `req` unless it shows what the last one sent showed (nothing
    /// changed: nothing is rendered). Dragging what does not change the
    /// frame (a scroll bar) sends nothing; the end of a drag that did
    /// change it sends the full-quality request.
    pub fn request(&mut self, req: Request) {
        let mut req = req;
        req.seq = 0;
        if let Some(last) = &self.last_sent {
            // Compared in place (a look can be a large layered stack: no
            // clone per UI frame just to compare).
            let interactive = req.interactive;
            req.interactive = last.interactive;
            let same_frame = req == *last;
            req.interactive = interactive;
            if same_frame && (interactive || !last.interactive) {
                return;
            }
        }
        self.last_sent = Some(req.clone());
        self.seq += 1;
        req.seq = self.seq;
        let interactive = req.interactive;
        // A ground truth being computed for an older request stops (the
        // render thread takes this one next).
        self.cancel
            .store(true, std::sync::atomic::Ordering::Relaxed);
        if self.tx.send(req).is_ok() {
            if interactive {
                self.busy_since.get_or_insert_with(Instant::now);
            } else {
                // The full frame is waited for from now, not from the start
                // of a drag whose previews kept the viewport busy.
                self.busy_since = Some(Instant::now());
            }
        }
    }

    /// The number of the last request sent (0 before the first).
    pub fn seq(&self) -> u64 {
        self.seq
    }

    /// The last request sent (its `seq` is 0).
    pub fn last_request(&self) -> Option<&Request> {
        self.last_sent.as_ref()
    }

    /// Stops a ground truth being computed for the last request.
    pub fn cancel_current(&self) {
        self.cancel
            .store(true, std::sync::atomic::Ordering::Relaxed);
    }

    /// Renders `req` until its frame converges, waiting on this thread
    /// (never the UI's: the turntable and the preset browser call it from
    /// their own). `Ok(None)` once `cancelled` says so; the error of a
    /// frame that failed.
    pub fn render_converged(
        &mut self,
        req: Request,
        cancelled: &dyn Fn() -> bool,
    ) -> Result<Option<image::RgbaImage>, String> {
        self.render_converged_with(req, cancelled, &|_, _| {})
            .map(|f| f.map(|(image, _)| image))
    }

    /// [`Viewport::render_converged`], telling `on_frame` each frame of the
    /// request that is not yet the last (its quality, and its render time
    /// in ms): a still's progress. With the frame, its scene-linear
    /// radiance where it shows one look alone.
    pub fn render_converged_with(
        &mut self,
        req: Request,
        cancelled: &dyn Fn() -> bool,
        on_frame: &dyn Fn(Quality, f64),
    ) -> Result<Option<Converged>, String> {
        self.request(req);
        let want = self.seq;
        loop {
            if cancelled() {
                self.cancel_current();
                return Ok(None);
            }
            for reply in self.poll() {
                match reply {
                    Reply::Frame {
                        image,
                        seq,
                        quality: Quality::Converged { .. },
                        radiance,
                        ..
                    } if seq == want => return Ok(Some((image, radiance))),
                    Reply::Frame {
                        seq,
                        quality,
                        wall_ms,
                        ..
                    } if seq == want => on_frame(quality, wall_ms),
                    Reply::Error(e) => return Err(e),
                    _ => {}
                }
            }
            std::thread::sleep(std::time::Duration::from_millis(5));
        }
    }

    /// Replies that arrived since the last call. A request the render
    /// thread lost in a failure it recovered from is sent again.
    pub fn poll(&mut self) -> Vec<Reply> {
        let mut replies: Vec<Reply> = self.rx.try_iter().collect();
        if replies.iter().any(|r| matches!(r, Reply::Frame { .. })) {
            self.failures_in_a_row = 0;
        }
        let mut gave_up = false;
        for r in &mut replies {
            if let Reply::Recovered {
                message,
                resend: true,
            } = r
            {
                self.failures_in_a_row += 1;
                if self.failures_in_a_row > MAX_RESENDS {
                    gave_up = true;
                    message.push_str(
                        "; it failed on this view every time, so it waits for the next change of look or view",
                    );
                }
            }
        }
        let resend = replies
            .iter()
            .any(|r| matches!(r, Reply::Recovered { resend: true, .. }));
        if resend && !gave_up {
            if let Some(last) = self.last_sent.take() {
                self.request(last);
            }
        }
        if gave_up {
            self.busy_since = None;
        }
        // Busy until the newest request is answered (a frame of an older
        // one, still on its way, does not count) or has failed.
        let done = replies.iter().any(|r| match r {
            Reply::Frame { seq, .. } => *seq == self.seq,
            Reply::Error(_) => true,
            Reply::MeshLoaded(..) | Reply::MeshFailed { .. } | Reply::Recovered { .. } => false,
        });
        if done {
            self.busy_since = None;
        }
        replies
    }
}

/// Renderer settings for a look and view ([`RenderSettings::for_look`]
/// with the view's environment).
pub fn render_settings(look: &Look, view: &ViewState, size: (u32, u32)) -> RenderSettings {
    let studio = RenderSettings::default().environment_sh;
    let env = match view.environment {
        EnvironmentChoice::Studio => studio,
        EnvironmentChoice::Black => [[0.0; 3]; 9],
        EnvironmentChoice::Map => view.environment_map_sh.unwrap_or(studio),
    }
    .map(|c| c.map(|v| v * view.environment_intensity));
    let on_map = view.environment == EnvironmentChoice::Map && view.environment_map_sh.is_some();
    let turn_rad = view.background.turn_deg.to_radians();
    let env = if on_map {
        crate::render::environment::rotate_sh_about_up(&env, turn_rad)
    } else {
        env
    };
    RenderSettings {
        map_colour: look.map_colour,
        tone_map: view.tone_map,
        background: (on_map && view.background.show).then_some(
            crate::render::settings::Background {
                blur: view.background.blur,
                turn_rad,
                intensity: view.environment_intensity,
            },
        ),
        ..RenderSettings::for_look(&look.rendering, view.orbit, env, size)
    }
}

/// The B side of a comparison.
pub fn b_look(a: &Preset, b: &CompareB) -> Result<Look, String> {
    match b {
        CompareB::Method(m) => {
            let mut look = Look::of(a);
            look.rendering.method = *m;
            Ok(look)
        }
        CompareB::Preset(path) => load_look(path).map(|p| Look::of(&p)),
    }
}

/// The look in `path`: a preset, or what the engine whose file it is will
/// draw from it (the first of several).
pub fn load_look(path: &std::path::Path) -> Result<Preset, String> {
    if crate::settings::is_preset_file(path) {
        return Preset::load(path).map_err(|e| e.to_string());
    }
    crate::export::import_file(path, &crate::export::ImportOptions::default())
        .map_err(|e| e.to_string())?
        .into_iter()
        .next()
        .map(|l| l.preset)
        .ok_or_else(|| format!("{}: no look in the file", path.display()))
}
