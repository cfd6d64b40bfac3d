//! The render thread's loop: the newest request first, a quick preview
//! while input lasts, then refinement to the converged frame (and the
//! ground truth after it where asked), each frame sent back as it lands.

use super::*;

/// The request being refined once input stopped.
pub(super) struct Refine {
    pub(super) req: Request,
    /// Frames in the running mean so far.
    pub(super) frames: u32,
    /// The sides of the last frame (to see whether the means still change).
    pub(super) prev: Option<Vec<image::RgbaImage>>,
    /// When the request arrived (input stopped).
    pub(super) since: Instant,
    /// The coarse ground truth has been shown.
    pub(super) coarse_done: bool,
    /// The request as the artist made it, when `req` is its ground truth
    /// ("refine to the truth"), with the method it was refined from.
    pub(super) truth_of: Option<(Request, MethodId)>,
    /// The ground truth in tiles: the frame under the tiles not yet done
    /// (the method's converged frame, or a preview) and how fast the
    /// tiles have come.
    pub(super) tiles: TilesState,
}

/// A ground truth in tiles as the render thread follows it.
#[derive(Default)]
pub(super) struct TilesState {
    /// The frame shown where tiles are not done, and its method.
    under: Option<(image::RgbaImage, MethodId)>,
    /// Frames of tiles so far.
    frames: u32,
    /// Wall time and SSS pixels of the frames after the first (the first
    /// may also build the cells): the pace of the time left.
    paced_ms: f64,
    paced_pixels: u64,
    pixels_done: u64,
}

impl TilesState {
    /// Under the tiles: `image`, the converged frame of `method`.
    pub(super) fn over(image: image::RgbaImage, method: MethodId) -> Self {
        Self {
            under: Some((image, method)),
            ..Self::default()
        }
    }
}

/// The newest request waiting, without blocking; `Err` when the UI has
/// gone.
pub(super) fn try_newest(rx: &Receiver<Request>) -> Result<Option<Request>, ()> {
    let mut newest = None;
    loop {
        match rx.try_recv() {
            Ok(r) => newest = Some(r),
            Err(std::sync::mpsc::TryRecvError::Empty) => return Ok(newest),
            Err(std::sync::mpsc::TryRecvError::Disconnected) => {
                return newest.map(Some).ok_or(());
            }
        }
    }
}

/// A failure a test can make the render thread have on its next request
/// ([`Viewport::inject_fault`]); nothing else turns these on.
#[doc(hidden)]
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Fault {
    /// The render thread panics.
    Panic,
    /// The GPU device is destroyed under the renderer (`Device::destroy`).
    DeviceLoss,
}

/// The faults waiting for the render thread's next requests, in order.
#[derive(Default)]
pub(super) struct Faults(std::sync::Mutex<std::collections::VecDeque<Fault>>);

impl Faults {
    pub(super) fn set(&self, f: Fault) {
        if let Ok(mut queue) = self.0.lock() {
            queue.push_back(f);
        }
    }

    pub(super) fn take(&self) -> Option<Fault> {
        self.0.lock().ok().and_then(|mut queue| queue.pop_front())
    }
}

/// Runs [`worker`] until the UI goes. A panic in it is caught and said,
/// and a fresh worker (a new renderer) takes the next request; the viewport
/// sends the request in hand again (`Reply::Recovered`). The document and
/// its undo history live on the UI thread and are never touched.
pub(super) fn supervise(
    rx: &Receiver<Request>,
    tx: &Sender<Reply>,
    (cancel, focus): (&std::sync::Arc<std::sync::atomic::AtomicBool>, &Focus),
    wake: &impl Fn(),
    faults: &Faults,
) {
    loop {
        let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            worker(rx, tx, (cancel.clone(), focus.clone()), wake, faults)
        }));
        let Err(panic) = run else {
            return;
        };
        let what = panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_else(|| "no message".into());
        let message = format!(
            "the render thread failed ({what}) and was restarted with a new renderer; the look and its undo history are untouched"
        );
        if tx
            .send(Reply::Recovered {
                message,
                resend: true,
            })
            .is_err()
        {
            return;
        }
        wake();
    }
}

pub(super) fn worker(
    rx: &Receiver<Request>,
    tx: &Sender<Reply>,
    (cancel, focus): (std::sync::Arc<std::sync::atomic::AtomicBool>, Focus),
    wake: &impl Fn(),
    faults: &Faults,
) {
    let mut w = Worker::new(cancel, focus);
    // The UI's first request comes with its first frame (a tenth of a
    // second): with a mesh of its own (the head scan the editor opens on),
    // the default head is not set up first, which took more than a second
    // before the scan's first frame (its renderer and its baked maps).
    let mut pending = match rx.recv_timeout(FIRST_REQUEST_WAIT) {
        Ok(first) => Some(newest_after(rx, first)),
        Err(std::sync::mpsc::RecvTimeoutError::Timeout) => None,
        Err(std::sync::mpsc::RecvTimeoutError::Disconnected) => return,
    };
    if pending.as_ref().is_none_or(|r| r.mesh.is_none()) {
        default_head(&mut w, tx);
    }
    let mut refine: Option<Refine> = None;
    loop {
        // Refining: take a new request if there is one, else add a frame.
        // Otherwise wait for the next request. Either way only the newest.
        let next = match (pending.take(), &refine) {
            (Some(first), _) => Some(first),
            (None, Some(_)) => match try_newest(rx) {
                Ok(r) => r,
                Err(()) => return,
            },
            (None, None) => match crate::app::wake::recv_newest(rx) {
                Some(r) => Some(r),
                None => return,
            },
        };
        let Some(req) = next else {
            if let Some(r) = refine.as_mut() {
                if !refine_step(&mut w, r, tx) {
                    refine = None;
                }
                wake();
            }
            continue;
        };
        refine = match take_request(&mut w, req, tx, wake, faults) {
            Next::Quit => return,
            Next::Wait => None,
            Next::Refine(r) => Some(*r),
        };
        wake();
    }
}

/// How long the render thread waits for its first request before it sets
/// up the default head anyway.
const FIRST_REQUEST_WAIT: std::time::Duration = std::time::Duration::from_secs(1);

/// `first`, or the newest request queued behind it.
fn newest_after(rx: &Receiver<Request>, first: Request) -> Request {
    let mut newest = first;
    while let Ok(newer) = rx.try_recv() {
        newest = newer;
    }
    newest
}

/// What the render loop does after a new request: stop (the UI has
/// gone), wait for the next, or refine this one.
enum Next {
    Quit,
    Wait,
    Refine(Box<Refine>),
}

/// A new request taken: its mesh made ready, then its preview (while
/// input lasts), its kept frame (a view finished before), or its first
/// refining step.
fn take_request(
    w: &mut Worker,
    mut req: Request,
    tx: &Sender<Reply>,
    wake: &impl Fn(),
    faults: &Faults,
) -> Next {
    // The newest request is taken: a cancel set before now was for the
    // requests it replaces (one sent from here on cancels its work).
    w.cancel.store(false, std::sync::atomic::Ordering::Relaxed);
    let t0 = Instant::now();
    if !prepare_mesh(w, &mut req, tx, faults) {
        return Next::Wait;
    }
    if req.interactive && w.pending_maps.is_none() {
        if !send_preview(w, &req, t0, tx) {
            return Next::Quit;
        }
        return Next::Wait;
    }
    // A view finished before: shown again at once.
    if w.pending_maps.is_none() {
        match send_kept(w, &req, t0, tx) {
            Some(false) => return Next::Quit,
            Some(true) => return Next::Wait,
            None => {}
        }
    }
    let mut r = Refine {
        req,
        frames: 0,
        prev: None,
        since: t0,
        coarse_done: false,
        truth_of: None,
        tiles: TilesState::default(),
    };
    if w.pending_maps.is_some() {
        // The head first, with neutral maps; then the same view with
        // its skin maps, refined from there. The ground truth of a head
        // about to change would be seconds thrown away: a preview.
        let sent = if r.req.has_truth() {
            send_frame(w, &r.req, Pass::Preview(1.0), t0, tx, |_| {
                Quality::Preview { divisor: 1.0 }
            })
        } else {
            send_frame(w, &r.req, Pass::Refine(0), t0, tx, |_| Quality::Refining {
                frames: 1,
            })
        };
        if !sent {
            return Next::Quit;
        }
        wake();
        if let Err(e) = w.apply_pending_maps() {
            let _ = tx.send(Reply::Error(e));
            return Next::Wait;
        }
    }
    if refine_step(w, &mut r, tx) {
        Next::Refine(Box::new(r))
    } else {
        Next::Wait
    }
}

impl Worker {
    /// A worker with no renderer yet, cancelled through `cancel`.
    fn new(cancel: std::sync::Arc<std::sync::atomic::AtomicBool>, focus: Focus) -> Self {
        Worker {
            renderer: None,
            mesh_path: None,
            mesh_settings: Default::default(),
            mesh_info: None,
            reframed: false,
            cache: Vec::new(),
            pending_maps: None,
            background: None,
            kept: [None, None],
            divisor: None,
            full_frame_ms: None,
            finished: Vec::new(),
            cancel,
            focus,
        }
    }
}

/// Loads the request's mesh and maps if they changed (replying with the
/// mesh's framing). On an error the mesh on screen stays and draws this
/// request (`Reply::MeshFailed`, said once); with none yet, the default
/// head stands in so the viewport keeps working. False when there is no
/// renderer to draw with.
fn prepare_mesh(w: &mut Worker, req: &mut Request, tx: &Sender<Reply>, faults: &Faults) -> bool {
    match faults.take() {
        Some(Fault::Panic) => panic!("a failure injected by a test"),
        Some(Fault::DeviceLoss) => {
            if let Some(r) = &w.renderer {
                r.context().destroy_device();
            }
        }
        None => {}
    }
    // A lost device (wgpu's callback said so): everything made on it is
    // gone; a new renderer on a new device draws this request.
    if let Some(why) = w.renderer.as_ref().and_then(|r| r.device_lost()) {
        w.renderer = None;
        let message = format!(
            "the GPU device was lost ({why}): the renderer was rebuilt on a new device and the view redrawn; nothing of the look was lost"
        );
        let _ = tx.send(Reply::Recovered {
            message,
            resend: false,
        });
    }
    let range = req.a.rendering.thickness_remap_mm.1 as f32;
    match w.ensure_renderer(&req.mesh, &req.mesh_settings, range) {
        // A file that is not a mesh, or a map that will not load: the
        // artist's mesh on screen is kept, not thrown away.
        Err(error) if w.renderer.is_some() => {
            let asked = std::mem::replace(&mut req.mesh, w.mesh_path.clone());
            req.mesh_settings = w.mesh_settings.clone();
            let _ = tx.send(Reply::MeshFailed {
                asked,
                error,
                kept: req.mesh.clone(),
                kept_settings: req.mesh_settings.clone(),
            });
        }
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
                return false;
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
                    req.view.orbit.camera_distance_m = info.framing_distance_m;
                    req.view.orbit.camera_pan_m = [0.0; 2];
                }
            }
        }
        Ok(false) => {}
    }
    true
}

/// Sends the frame of a view finished before, if `req`'s is among them:
/// `None` when it is not, else whether the reply was sent.
fn send_kept(w: &mut Worker, req: &Request, t0: Instant, tx: &Sender<Reply>) -> Option<bool> {
    let key = req.key();
    let i = w.finished.iter().position(|(k, _)| *k == key)?;
    let kept = w.finished.remove(i);
    let f = kept.1.clone();
    w.finished.insert(0, kept);
    let note = Some(f.note.map_or("kept from before".into(), |n| {
        format!("{n} · kept from before")
    }));
    let reply = Reply::Frame {
        difference_scale: f.difference_scale,
        image: f.image,
        stats: Box::new(f.stats),
        wall_ms: t0.elapsed().as_secs_f64() * 1e3,
        note,
        seq: req.seq,
        quality: Quality::Converged { frames: 1, ms: 0.0 },
        radiance: f.radiance,
    };
    Some(tx.send(reply).is_ok())
}

/// Renders a preview of `req` at the divisor that keeps a frame near
/// [`PREVIEW_BUDGET_MS`], and adapts the divisor to what it took. False
/// when the UI has gone.
pub(super) fn send_preview(w: &mut Worker, req: &Request, t0: Instant, tx: &Sender<Reply>) -> bool {
    // The first preview guesses from the last full frame: its time scales
    // with the pixel count, so with the divisor squared.
    let estimate = w.divisor.unwrap_or_else(|| {
        w.full_frame_ms
            .map_or(2.0, |ms| (ms / PREVIEW_BUDGET_MS).sqrt() as f32)
            .clamp(1.0, MAX_PREVIEW_DIVISOR)
    });
    // A few fixed steps, so that the preview's render targets keep their
    // size from frame to frame instead of being made anew for each.
    let divisor = PREVIEW_DIVISORS
        .into_iter()
        .min_by(|a, b| (a - estimate).abs().total_cmp(&(b - estimate).abs()))
        .unwrap_or(estimate);
    let t1 = Instant::now();
    let sent = send_frame(w, req, Pass::Preview(divisor), t0, tx, |_| {
        Quality::Preview { divisor }
    });
    let ms = t1.elapsed().as_secs_f64() * 1e3;
    // Halfway towards the divisor that would have met the budget.
    let ideal = divisor * (ms / PREVIEW_BUDGET_MS).sqrt() as f32;
    w.divisor = Some((0.5 * (estimate + ideal)).clamp(1.0, MAX_PREVIEW_DIVISOR));
    sent
}

/// Renders the next refinement frame of `r` and sends it. Returns whether
/// more frames would still change the image (false: converged, failed, or
/// the UI has gone).
pub(super) fn refine_step(w: &mut Worker, r: &mut Refine, tx: &Sender<Reply>) -> bool {
    if r.req.has_truth() && r.req.b.is_none() {
        return truth_tiles_step(w, r, tx);
    }
    // A comparison with the ground truth takes seconds: a coarse one over
    // the whole view first (a new request in between is taken before the
    // full frame).
    if r.frames == 0 && !r.coarse_done && r.req.has_truth() {
        return coarse_truth_step(w, r, tx);
    }
    let frame = r.frames;
    let t1 = Instant::now();
    let rendered = w.frame(&r.req, Pass::Refine(frame));
    if frame == 0 {
        w.full_frame_ms = Some(t1.elapsed().as_secs_f64() * 1e3);
    }
    let rendered = match rendered {
        Ok(x) => x,
        // A newer request is waiting: nothing to report.
        Err(e) if is_cancelled(&e) => return false,
        Err(e) => {
            let _ = tx.send(Reply::Error(e));
            return false;
        }
    };
    r.frames += 1;
    let done = !rendered.stochastic
        || r.frames >= MAX_REFINE_FRAMES
        || r.prev.as_ref().is_some_and(|p| {
            r.frames >= 3
                && p.len() == rendered.sides.len()
                && p.iter().zip(&rendered.sides).all(|(a, b)| converged(a, b))
        });
    let quality = if done {
        Quality::Converged {
            frames: r.frames,
            ms: r.since.elapsed().as_secs_f64() * 1e3,
        }
    } else {
        Quality::Refining { frames: r.frames }
    };
    if !done {
        r.prev = Some(rendered.sides);
    }
    let note = with_truth_note(&r.truth_of, rendered.note);
    // "Refine to the truth": the method's converged frame is shown, and
    // the ground truth of the same view follows in tiles over it, kept as
    // the view's finished frame.
    let to_truth = done
        && r.req.refine_to_truth
        && r.truth_of.is_none()
        && !r.req.has_truth()
        && r.req.b.is_none();
    let radiance = (done && !to_truth)
        .then(|| last_radiance(w, &r.req))
        .flatten();
    if done && !to_truth {
        keep_finished(
            w,
            r,
            Finished {
                image: rendered.image.clone(),
                stats: rendered.stats.clone(),
                note: note.clone(),
                difference_scale: rendered.difference_scale,
                radiance: radiance.clone(),
            },
        );
    }
    let under = to_truth.then(|| (rendered.image.clone(), rendered.stats.clone()));
    let reply = Reply::Frame {
        difference_scale: rendered.difference_scale,
        image: rendered.image,
        stats: Box::new(rendered.stats),
        wall_ms: t1.elapsed().as_secs_f64() * 1e3,
        note,
        seq: r.req.seq,
        quality,
        radiance,
    };
    let sent = tx.send(reply).is_ok();
    if sent && to_truth {
        return start_truth_tiles(r, under, tx);
    }
    sent && !done
}

/// The coarse ground truth over the whole view, shown before the full
/// frame of a comparison with it; false when the thread should wait.
fn coarse_truth_step(w: &mut Worker, r: &mut Refine, tx: &Sender<Reply>) -> bool {
    r.coarse_done = true;
    let divisor = COARSE_TRUTH_DIVISOR;
    let reply = match w.frame(&r.req, Pass::Coarse(divisor)) {
        Ok(rendered) => Reply::Frame {
            difference_scale: rendered.difference_scale,
            image: rendered.image,
            stats: Box::new(rendered.stats),
            wall_ms: r.since.elapsed().as_secs_f64() * 1e3,
            note: with_truth_note(&r.truth_of, rendered.note),
            seq: r.req.seq,
            quality: Quality::Coarse { divisor },
            radiance: None,
        },
        Err(e) if is_cancelled(&e) => return true,
        Err(e) => {
            let _ = tx.send(Reply::Error(e));
            return false;
        }
    };
    tx.send(reply).is_ok()
}

/// Keeps a converged frame as its view's finished frame (the view the
/// artist asked for, when it is that view's ground truth), newest first.
fn keep_finished(w: &mut Worker, r: &Refine, frame: Finished) {
    let key = r
        .truth_of
        .as_ref()
        .map_or_else(|| r.req.key(), |(k, _)| k.key());
    w.finished.retain(|(k, _)| *k != key);
    // The radiance (28 bytes a pixel) is kept for the newest view alone:
    // a view gone back to shows its kept frame, and the probe says it has
    // no scene-linear reading until that view is drawn again.
    for (_, older) in &mut w.finished {
        older.radiance = None;
    }
    w.finished.insert(0, (key, frame));
    w.finished.truncate(KEPT_FRAMES);
}

/// "Refine to the truth": the request becomes its ground truth, which
/// follows in tiles over `under` (the method's converged frame and its
/// statistics), said at once; false when the UI has gone.
fn start_truth_tiles(
    r: &mut Refine,
    under: Option<(image::RgbaImage, FrameStats)>,
    tx: &Sender<Reply>,
) -> bool {
    let from = r.req.a.rendering.method;
    let mut truth = r.req.clone();
    truth.a.rendering.method = MethodId::ground_truth();
    truth.show_b = false;
    r.truth_of = Some((r.req.clone(), from));
    r.req = truth;
    r.frames = 0;
    r.prev = None;
    r.coarse_done = false;
    // Said at once: the converged frame stays, the tiles come next.
    if let Some((image, stats)) = &under {
        let next = Reply::Frame {
            difference_scale: None,
            image: image.clone(),
            stats: Box::new(stats.clone()),
            wall_ms: 0.0,
            note: with_truth_note(&r.truth_of, None),
            seq: r.req.seq,
            quality: Quality::Truth {
                done: 0,
                tiles: 0,
                left_s: None,
                under: from,
            },
            radiance: None,
        };
        if tx.send(next).is_err() {
            return false;
        }
    }
    r.tiles = under.map_or_else(TilesState::default, |(i, _)| TilesState::over(i, from));
    true
}

/// One step of the ground truth in tiles (A alone): first, where there is
/// no converged frame of the artist's method to show under the tiles, the
/// preview method's full-resolution frame, labelled; then each step a
/// frame of the next tiles composed over it, the finished tiles the
/// ground truth's, until every tile is done. Returns whether more steps
/// follow (false: finished, failed, a newer request, or the UI has gone).
fn truth_tiles_step(w: &mut Worker, r: &mut Refine, tx: &Sender<Reply>) -> bool {
    let t1 = Instant::now();
    let Some((under, under_method)) = &r.tiles.under else {
        return truth_stand_in_step(w, r, tx);
    };
    let (under, under_method) = (under.clone(), *under_method);
    let budget_ms = match r.tiles.frames {
        0 => FIRST_TRUTH_TILES_BUDGET_MS,
        _ => TRUTH_TILES_BUDGET_MS,
    };
    let rendered = match w.frame(&r.req, Pass::Tiles(budget_ms)) {
        Ok(x) => x,
        Err(e) if is_cancelled(&e) => return false,
        Err(e) => {
            let _ = tx.send(Reply::Error(e));
            return false;
        }
    };
    let Some(progress) = rendered.stats.truth_tiles.clone() else {
        let _ = tx.send(Reply::Error(
            "the ground truth's frame reported no tiles".into(),
        ));
        return false;
    };
    let mut image = rendered.image;
    let finished = progress.finished();
    if !finished && under.dimensions() == image.dimensions() {
        for (x, y, p) in image.enumerate_pixels_mut() {
            if !progress.is_done(x, y) {
                *p = *under.get_pixel(x, y);
            }
        }
    }
    // The pace of the frames after the first (which may build the cells).
    let t = &mut r.tiles;
    if t.frames > 0 {
        t.paced_ms += t1.elapsed().as_secs_f64() * 1e3;
        t.paced_pixels += progress.pixels_done.saturating_sub(t.pixels_done);
    }
    t.frames += 1;
    t.pixels_done = progress.pixels_done;
    let left = progress.pixels_total.saturating_sub(progress.pixels_done);
    let left_s =
        (t.paced_pixels > 0).then(|| t.paced_ms / t.paced_pixels as f64 * left as f64 / 1e3);
    let quality = if finished {
        Quality::Converged {
            frames: 1,
            ms: r.since.elapsed().as_secs_f64() * 1e3,
        }
    } else {
        Quality::Truth {
            done: progress.skin_tiles_done,
            tiles: progress.skin_tiles,
            left_s,
            under: under_method,
        }
    };
    let note = with_truth_note(&r.truth_of, rendered.note);
    let radiance = finished.then(|| last_radiance(w, &r.req)).flatten();
    if finished {
        keep_finished(
            w,
            r,
            Finished {
                image: image.clone(),
                stats: rendered.stats.clone(),
                note: note.clone(),
                difference_scale: None,
                radiance: radiance.clone(),
            },
        );
    }
    let reply = Reply::Frame {
        difference_scale: None,
        image,
        stats: Box::new(rendered.stats),
        wall_ms: t1.elapsed().as_secs_f64() * 1e3,
        note,
        seq: r.req.seq,
        quality,
        radiance,
    };
    tx.send(reply).is_ok() && !finished
}

/// The first step of a ground truth in tiles with nothing under them: the
/// method's preview at full size stands in where tiles are not done.
fn truth_stand_in_step(w: &mut Worker, r: &mut Refine, tx: &Sender<Reply>) -> bool {
    let t1 = Instant::now();
    let method = r.req.a.rendering.method.preview();
    let rendered = match w.frame(&r.req, Pass::Preview(1.0)) {
        Ok(x) => x,
        Err(e) if is_cancelled(&e) => return false,
        Err(e) => {
            let _ = tx.send(Reply::Error(e));
            return false;
        }
    };
    r.tiles = TilesState::over(rendered.image.clone(), method);
    let reply = Reply::Frame {
        difference_scale: None,
        image: rendered.image,
        stats: Box::new(rendered.stats),
        wall_ms: t1.elapsed().as_secs_f64() * 1e3,
        note: Some(format!(
            "{} stands in where the ground truth's tiles are not done",
            method.id()
        )),
        seq: r.req.seq,
        quality: Quality::Truth {
            done: 0,
            tiles: 0,
            left_s: None,
            under: method,
        },
        radiance: None,
    };
    tx.send(reply).is_ok()
}

/// A frame's note, led by "the ground truth, refined from …" when it is
/// the ground truth the artist asked to refine to.
pub(super) fn with_truth_note(
    truth_of: &Option<(Request, MethodId)>,
    note: Option<String>,
) -> Option<String> {
    match (truth_of, note) {
        (Some((_, m)), n) => {
            let lead = format!("the ground truth, refined from {}", m.id());
            Some(n.map_or(lead.clone(), |n| format!("{lead} · {n}")))
        }
        (None, n) => n,
    }
}

/// Renders `req` as `pass` and sends the frame (or the error); false when
/// the UI has gone.
pub(super) fn send_frame(
    w: &mut Worker,
    req: &Request,
    pass: Pass,
    t0: Instant,
    tx: &Sender<Reply>,
    quality: impl Fn(&Rendered) -> Quality,
) -> bool {
    let t1 = Instant::now();
    let frame = w.frame(req, pass);
    if timings_on() {
        eprintln!(
            "timing: render thread frame {:.2} s ({:.2} s since the request)",
            t1.elapsed().as_secs_f64(),
            t0.elapsed().as_secs_f64()
        );
    }
    let reply = match frame {
        Ok(r) => Reply::Frame {
            difference_scale: r.difference_scale,
            quality: quality(&r),
            image: r.image,
            stats: Box::new(r.stats),
            wall_ms: t0.elapsed().as_secs_f64() * 1e3,
            note: r.note,
            seq: req.seq,
            radiance: None,
        },
        Err(e) if is_cancelled(&e) => return true,
        Err(e) => Reply::Error(e),
    };
    tx.send(reply).is_ok()
}

/// Whether a frame's error is the ground truth stopping for a newer
/// request.
pub(super) fn is_cancelled(e: &str) -> bool {
    e == crate::render::GpuError::Cancelled.to_string()
}
