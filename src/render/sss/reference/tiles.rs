//! The ground truth in tiles, for the editor ([`RenderSettings::truth_tiles`]):
//! a view's SSS pixels in square tiles, gathered nearest the focus first
//! for about a budget a frame. The next frame of the same view (the same
//! `frame_key`: cells, profile, view and size) goes on where the last one
//! stopped, so the editor can show each frame's finished tiles over the
//! artist's converged frame, as Cycles fills a frame, and stay responsive:
//! a newer request is taken between frames, and one arriving during a
//! frame stops its gather (`cancel`) with the tiles finished so far kept.
//! The finished view is the frame a whole gather gives (the same probes,
//! the same walk), and it is kept as the cache's frame.

use super::*;
use crate::render::settings::{TruthProgress, TruthTiles};

/// The pixels a batch of tiles holds at least: enough for both cores'
/// chunks of 64 neighbours (`MEMO_CHUNK`), few enough that a batch ends
/// well inside a frame's budget (about 0.1 s at 0.17 ms a pixel a core).
const BATCH_PIXELS: usize = 1024;

/// A view being gathered tile by tile.
pub(in crate::render) struct Partial {
    /// The frame it is for ([`frame_key`]) and its cells ([`Cache::key`]).
    frame_key: u64,
    cells_key: u64,
    size: (u32, u32),
    tile_px: u32,
    columns: u32,
    rows: u32,
    /// Each SSS pixel (its index and mask) and its probe.
    pixels: Vec<(usize, f32)>,
    probes: Vec<Probe>,
    /// Each tile's pixels (indices into `pixels`), row by row.
    members: Vec<Vec<u32>>,
    done: Vec<bool>,
    /// Each pixel's gathered value once its tile is done (the inner
    /// `None`: not one surface under a supersampled pixel).
    values: Vec<Option<Option<[f32; 3]>>>,
    pixels_done: u64,
    gather_ms: f64,
    gpu_unfinished: Option<u64>,
}

impl Partial {
    fn new(
        (frame_key, cells_key): (u64, u64),
        size: (u32, u32),
        tile_px: u32,
        pixels: Vec<(usize, f32)>,
        probes: Vec<Probe>,
    ) -> Self {
        let tile_px = tile_px.max(8);
        let (columns, rows) = (size.0.div_ceil(tile_px), size.1.div_ceil(tile_px));
        let mut members = vec![Vec::new(); (columns * rows) as usize];
        for (k, (i, _)) in pixels.iter().enumerate() {
            let (x, y) = ((*i as u32) % size.0, (*i as u32) / size.0);
            members[((y / tile_px) * columns + x / tile_px) as usize].push(k as u32);
        }
        // A tile with no SSS pixel has nothing to gather.
        let done = members.iter().map(Vec::is_empty).collect();
        Self {
            frame_key,
            cells_key,
            size,
            tile_px,
            columns,
            rows,
            values: vec![None; pixels.len()],
            pixels,
            probes,
            members,
            done,
            pixels_done: 0,
            gather_ms: 0.0,
            gpu_unfinished: None,
        }
    }

    /// The next tiles to gather: those not done nearest `focus`
    /// (fractions of the frame), until they hold [`BATCH_PIXELS`].
    fn next_batch(&self, focus: [f32; 2]) -> Vec<usize> {
        let (fx, fy) = (
            focus[0].clamp(0.0, 1.0) * self.size.0 as f32,
            focus[1].clamp(0.0, 1.0) * self.size.1 as f32,
        );
        let distance = |t: usize| {
            let (c, r) = ((t as u32 % self.columns) as f32, (t as u32 / self.columns) as f32);
            let half = 0.5 * self.tile_px as f32;
            let (x, y) = (c * self.tile_px as f32 + half, r * self.tile_px as f32 + half);
            (x - fx).powi(2) + (y - fy).powi(2)
        };
        let mut left: Vec<usize> = (0..self.done.len()).filter(|t| !self.done[*t]).collect();
        left.sort_by(|a, b| distance(*a).total_cmp(&distance(*b)));
        let mut batch = Vec::new();
        let mut pixels = 0;
        for t in left {
            if pixels >= BATCH_PIXELS {
                break;
            }
            pixels += self.members[t].len();
            batch.push(t);
        }
        batch
    }

    fn progress(&self) -> TruthProgress {
        let skin = |t: &usize| !self.members[*t].is_empty();
        TruthProgress {
            tile_px: self.tile_px,
            columns: self.columns,
            rows: self.rows,
            done: self.done.clone(),
            skin_tiles: (0..self.done.len()).filter(skin).count() as u32,
            skin_tiles_done: (0..self.done.len())
                .filter(|t| skin(t) && self.done[*t])
                .count() as u32,
            pixels_done: self.pixels_done,
            pixels_total: self.pixels.len() as u64,
            gather_ms: self.gather_ms,
        }
    }

    fn finished(&self) -> bool {
        self.done.iter().all(|d| *d)
    }

    /// The ping texels: each finished pixel's value; a pixel still to
    /// gather is left black (the editor draws the artist's frame there).
    fn texels(&self) -> Vec<u8> {
        let values = self
            .values
            .iter()
            .map(|v| v.unwrap_or(Some([0.0; 3])))
            .collect();
        rgba_half_texels(self.pixels.clone(), values, self.size)
    }
}

/// The progress of a view found finished in the cache.
pub(super) fn finished(t: TruthTiles, (w, h): (u32, u32)) -> TruthProgress {
    let tile_px = t.tile_px.max(8);
    let (columns, rows) = (w.div_ceil(tile_px), h.div_ceil(tile_px));
    TruthProgress {
        tile_px,
        columns,
        rows,
        done: vec![true; (columns * rows) as usize],
        skin_tiles: 0,
        skin_tiles_done: 0,
        pixels_done: 0,
        pixels_total: 0,
        gather_ms: 0.0,
    }
}

/// Gathers the view's next tiles for about `t.budget_ms` (at least one
/// batch), writes what is done into the ping target and, once every tile
/// is done, keeps the frame as the cache's.
pub(super) fn scatter(
    g: &Gather,
    io: &Io,
    (view, s, inputs): (Mat4, &RenderSettings, &ProfileInputs),
    cache: &mut Option<Cache>,
    (k, frame_key): (u64, u64),
    t: TruthTiles,
) -> Result<Timing, GpuError> {
    let (w, h) = (s.width, s.height);
    let resumes = cache.as_ref().is_some_and(|c| {
        c.key == k
            && c.partial.as_ref().is_some_and(|p| {
                p.frame_key == frame_key
                    && p.cells_key == k
                    && p.size == (w, h)
                    && p.tile_px == t.tile_px.max(8)
            })
    });
    let mut build_ms = None;
    if !resumes {
        let (pixels, probes, built) = prepare(g, io, (view, s, inputs), cache, k)?;
        build_ms = built;
        if let Some(c) = cache.as_mut() {
            c.partial = Some(Partial::new(
                (frame_key, k),
                (w, h),
                t.tile_px,
                pixels,
                probes,
            ));
        }
    }
    let Some(c) = cache.as_mut() else {
        return Err(GpuError::Readback("ground truth cache".into()));
    };
    let cloud = c.cloud(inputs)?;
    let Some(mut partial) = c.partial.take() else {
        return Err(GpuError::Readback("ground truth tiles".into()));
    };
    let t0 = Instant::now();
    let gathered = loop {
        let batch = partial.next_batch(t.focus);
        if batch.is_empty() {
            break Ok(());
        }
        let index: Vec<u32> = batch
            .iter()
            .flat_map(|t| partial.members[*t].iter().copied())
            .collect();
        let probes: Vec<Probe> = index
            .iter()
            .map(|k| partial.probes[*k as usize])
            .collect();
        match g.run(c, &cloud, &probes, false) {
            Ok((values, unfinished)) => {
                for (k, v) in index.iter().zip(values) {
                    partial.values[*k as usize] = Some(v);
                }
                for tile in batch {
                    partial.done[tile] = true;
                }
                partial.pixels_done += index.len() as u64;
                if let Some(n) = unfinished {
                    *partial.gpu_unfinished.get_or_insert(0) += n;
                }
            }
            Err(e) => break Err(e),
        }
        if t0.elapsed().as_secs_f64() * 1e3 >= t.budget_ms {
            break Ok(());
        }
    };
    let gather_ms = t0.elapsed().as_secs_f64() * 1e3;
    partial.gather_ms += gather_ms;
    if let Err(e) = gathered {
        // A newer request: the tiles done so far are kept for this view.
        c.partial = Some(partial);
        return Err(e);
    }
    let texels = partial.texels();
    write_ping(g.ctx, io.ping, &texels, w, h);
    let progress = partial.progress();
    let gpu_unfinished = partial.gpu_unfinished;
    if partial.finished() {
        c.frame = Some((frame_key, texels));
    } else {
        c.partial = Some(partial);
    }
    if std::env::var_os("SCATTERLAB_TIMINGS").is_some() {
        eprintln!(
            "timing: reference tiles: {} of {} done, {} of {} pixels, build {:?} ms, gather {:.0} ms",
            progress.tiles_done(),
            progress.done.len(),
            progress.pixels_done,
            progress.pixels_total,
            build_ms,
            gather_ms
        );
    }
    Ok(Timing {
        build_ms,
        gather_ms,
        gpu_unfinished,
        tiles: Some(progress),
    })
}
