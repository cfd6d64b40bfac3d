//! The render thread's renderer and what it was last given: the inputs
//! per look and method, the kept sides, the preview's divisor and the last
//! finished frames; one frame rendered per call.

use super::*;

/// The renderer and what it was last given, on the render thread.
pub(super) struct Worker {
    pub(super) renderer: Option<Renderer>,
    pub(super) mesh_path: Option<PathBuf>,
    pub(super) mesh_settings: crate::app::state::MeshSettings,
    pub(super) mesh_info: Option<MeshInfo>,
    /// The last reload changed the mesh or its units (not only its maps):
    /// the editor frames it anew.
    pub(super) reframed: bool,
    /// Inputs per (look, method) of the last frame (A and B).
    pub(super) cache: Vec<((ProfileSpec, usize, usize, Method), ProfileInputs)>,
    /// The default head whose surface maps are still to bake (after its
    /// first frame).
    pub(super) pending_maps: Option<Mesh>,
    /// The background map the renderer holds (a new renderer holds none).
    pub(super) background: Option<SharedMap>,
    /// Sides (A, B) without random rotations, kept through refinement.
    pub(super) kept: [Option<Side>; 2],
    /// The preview's resolution divisor, adapted frame by frame.
    pub(super) divisor: Option<f32>,
    /// What the last full-resolution first frame took (ms).
    pub(super) full_frame_ms: Option<f64>,
    /// The last finished frames, newest first, by [`Request::key`].
    pub(super) finished: Vec<(Request, Finished)>,
    /// Shared with the [`Viewport`] and every renderer made here.
    pub(super) cancel: std::sync::Arc<std::sync::atomic::AtomicBool>,
    /// Where the pointer is over the viewport, set by the UI: the ground
    /// truth's tiles nearest it first.
    pub(super) focus: Focus,
}

/// The pointer over the viewport (fractions of its width and height),
/// shared by the UI and the render thread.
pub(super) type Focus = std::sync::Arc<std::sync::Mutex<Option<[f32; 2]>>>;

/// A finished frame as it was sent.
#[derive(Clone)]
pub(super) struct Finished {
    pub(super) image: image::RgbaImage,
    pub(super) stats: FrameStats,
    pub(super) note: Option<String>,
    pub(super) difference_scale: Option<f32>,
    /// Its scene-linear radiance, where it shows one look alone.
    pub(super) radiance: Option<std::sync::Arc<SceneLinear>>,
}

pub(super) fn timings_on() -> bool {
    std::env::var_os("SCATTERLAB_TIMINGS").is_some()
}

impl Worker {
    /// The pointer over the viewport, else its centre.
    pub(super) fn focus(&self) -> [f32; 2] {
        self.focus
            .lock()
            .ok()
            .and_then(|f| *f)
            .unwrap_or([0.5, 0.5])
    }

    pub(super) fn inputs(&mut self, look: &Look, m: Method) -> Result<ProfileInputs, String> {
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
        let inputs = ProfileInputs::for_method(
            &look.profile,
            profile.as_ref(),
            m,
            (look.rendering.samples, look.rendering.taps),
            // The editor draws each method with its default options.
            &Default::default(),
        )
        .map_err(|e| e.to_string())?;
        self.cache.insert(0, (key, inputs.clone()));
        self.cache.truncate(4);
        Ok(inputs)
    }

    pub(super) fn ensure_renderer(
        &mut self,
        mesh: &Option<PathBuf>,
        settings: &crate::app::state::MeshSettings,
        thickness_range_mm: f32,
    ) -> Result<bool, String> {
        let same_settings = mesh.is_none() || self.mesh_settings == *settings;
        if self.renderer.is_some() && self.mesh_path == *mesh && same_settings {
            return Ok(false);
        }
        let t = Instant::now();
        // The GPU context starts while the mesh loads; the default head's
        // surface maps (about a second) are left to `apply_pending_maps`,
        // which the render thread runs before the first frame.
        let bake_later = mesh.is_none() && !Mesh::default_head_maps_baked();
        let (mesh_data, ctx) = std::thread::scope(|s| {
            let ctx = s.spawn(GpuContext::new_headless);
            let mesh_data = match mesh {
                Some(p) => load_mesh(p, settings, thickness_range_mm),
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
        let mut renderer = Renderer::new(ctx, &mesh_data).map_err(|e| e.to_string())?;
        renderer.cancel_with(self.cancel.clone());
        self.background = None;
        self.renderer = Some(renderer);
        self.reframed = self.mesh_path != *mesh
            || self.mesh_settings.metres_per_unit != settings.metres_per_unit;
        self.mesh_path = mesh.clone();
        self.mesh_settings = settings.clone();
        self.mesh_info = Some(MeshInfo {
            size: mesh_data.head_size(),
            metres_per_unit: mesh_data.metres_per_unit,
            framing_distance_m: mesh_data
                .framing_distance_m(crate::settings::OrbitView::default().fov_y_rad),
            facing: mesh_data.facing(),
            bounds_centre_m: mesh_data.bounds_sphere_m().0,
            bounds_radius_m: mesh_data.bounds_sphere_m().1,
            colour_map_mean: (mesh_data.textures.albedo_mode
                == crate::render::textures::AlbedoMode::Absolute)
                .then(|| crate::render::textures::albedo_map_mean(&mesh_data.textures.albedo))
                .flatten(),
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
    pub(super) fn apply_pending_maps(&mut self) -> Result<bool, String> {
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

    /// Renders `req` at the quality `pass` asks for: A alone, or A and B
    /// composed as the compare mode shows them. Returns the image, A's
    /// statistics, a note for the status bar, and whether any side is
    /// stochastic (more refinement frames would change it).
    pub(super) fn frame(&mut self, req: &Request, pass: Pass) -> Result<Rendered, String> {
        if self.background != req.background_map {
            if let Some(r) = self.renderer.as_mut() {
                r.set_background(req.background_map.as_ref().map(|m| &*m.0));
                self.background = req.background_map.clone();
            }
        }
        let (full_w, full_h) = req.size;
        let (w, h) = match pass {
            Pass::Preview(d) | Pass::Coarse(d) => (
                ((full_w as f32 / d).round() as u32).max(16),
                ((full_h as f32 / d).round() as u32).max(16),
            ),
            Pass::Refine(_) | Pass::Tiles(_) => (full_w, full_h),
        };
        let mut notes: Vec<String> = Vec::new();
        // The ground truth takes seconds to minutes: while the artist
        // works, `burley` stands in for it (and says so).
        let settings = |look: &Look, size: (u32, u32), notes: &mut Vec<String>| {
            let mut s = render_settings(look, &req.view, size);
            if matches!(pass, Pass::Preview(_)) && s.method.preview() != s.method {
                s.method = s.method.preview();
                notes.push(format!(
                    "{} while you work, the ground truth when you stop",
                    s.method.id()
                ));
            }
            s
        };
        let a_look = if req.show_b {
            req.b.as_ref().map(|b| &b.0).unwrap_or(&req.a)
        } else {
            &req.a
        };
        let b = match &req.b {
            Some((look, mode, split)) if !req.show_b && *mode != CompareMode::Off => {
                Some((look, *mode, *split))
            }
            _ => None,
        };
        let side_size = match b {
            Some((_, CompareMode::SideBySide, _)) => ((w / 2).max(16), h),
            _ => (w, h),
        };
        // Side by side, each half zooms out to keep the head whole.
        let zoom = match b {
            Some((_, CompareMode::SideBySide, _)) => side_by_side_zoom_out(side_size),
            _ => 1.0,
        };
        let mut a_settings = settings(a_look, side_size, &mut notes);
        a_settings.view.camera_distance_m *= zoom;
        let a = self.render_side(0, a_look, a_settings, pass)?;
        let Some((b_look, mode, split)) = b else {
            notes.dedup();
            return Ok(Rendered {
                difference_scale: None,
                image: a.image.clone(),
                sides: vec![a.image],
                stats: a.stats,
                note: (!notes.is_empty()).then(|| notes.join(" · ")),
                stochastic: a.stochastic,
            });
        };
        let mut b_settings = settings(b_look, side_size, &mut notes);
        b_settings.view.camera_distance_m *= zoom;
        let bside = self.render_side(1, b_look, b_settings, pass)?;
        let (image, difference_scale) =
            compose(req, &a.image, &bside.image, mode, split, &mut notes);
        notes.dedup();
        Ok(Rendered {
            difference_scale,
            image,
            sides: vec![a.image, bside.image],
            stats: a.stats,
            note: (!notes.is_empty()).then(|| notes.join(" · ")),
            stochastic: a.stochastic || bside.stochastic,
        })
    }

    /// One side (`slot` 0: A, 1: B) of a frame. Refinement frames past the
    /// first join the side's running mean; a side without random
    /// rotations is rendered once and kept.
    pub(super) fn render_side(
        &mut self,
        slot: usize,
        look: &Look,
        settings: RenderSettings,
        pass: Pass,
    ) -> Result<Side, String> {
        let stochastic = crate::render::sss::is_stochastic(&settings, &Default::default());
        if let (Pass::Refine(frame), false, Some(kept)) = (pass, stochastic, &self.kept[slot]) {
            if frame > 0 {
                return Ok(kept.clone());
            }
        }
        let inputs = self.inputs(look, settings.method)?;
        let settings = RenderSettings {
            progressive: match pass {
                Pass::Refine(frame) => Some(Progressive { slot, frame }),
                Pass::Preview(_) | Pass::Coarse(_) | Pass::Tiles(_) => None,
            },
            truth_tiles: match pass {
                Pass::Tiles(budget_ms) if settings.method.sss().ground_truth => {
                    Some(crate::render::TruthTiles {
                        tile_px: TRUTH_TILE_PX,
                        focus: self.focus(),
                        budget_ms,
                    })
                }
                _ => None,
            },
            ..settings
        };
        let renderer = self.renderer.as_mut().ok_or("no renderer")?;
        let (image, stats) = renderer
            .render(&inputs, &settings)
            .map_err(|e| e.to_string())?;
        let side = Side {
            image,
            stats,
            stochastic,
        };
        self.kept[slot] = (!stochastic && matches!(pass, Pass::Refine(_))).then(|| side.clone());
        if matches!(pass, Pass::Coarse(_) | Pass::Tiles(_)) {
            self.kept[slot] = None;
        }
        Ok(side)
    }
}

/// What a request is rendered as.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Pass {
    /// A preview at 1/divisor of the resolution.
    Preview(f32),
    /// The first frame of a view with the ground truth in it: every side
    /// as it will be (the ground truth too) at 1/divisor of the resolution.
    Coarse(f32),
    /// Full resolution, frame n of the running mean.
    Refine(u32),
    /// The ground truth's next tiles at full resolution (A alone), nearest
    /// the focus first ([`crate::render::TruthTiles`]), gathering for
    /// about this many ms.
    Tiles(f64),
}

/// One side of a frame.
#[derive(Clone)]
pub(super) struct Side {
    pub(super) image: image::RgbaImage,
    pub(super) stats: FrameStats,
    pub(super) stochastic: bool,
}

/// A composed frame.
pub(super) struct Rendered {
    pub(super) image: image::RgbaImage,
    /// A difference view's scale (white).
    pub(super) difference_scale: Option<f32>,
    /// Each side's own frame (A, and B when comparing): convergence is
    /// judged on these, not on a difference view that magnifies noise.
    pub(super) sides: Vec<image::RgbaImage>,
    pub(super) stats: FrameStats,
    pub(super) note: Option<String>,
    pub(super) stochastic: bool,
}

/// A and B in one frame as `mode` shows them (split at `split`, their
/// difference as a heat map, or side by side), and the heat map's scale
/// (white, ΔL*) where it is one; the heat map's note goes into `notes`.
fn compose(
    req: &Request,
    a: &image::RgbaImage,
    b: &image::RgbaImage,
    mode: CompareMode,
    split: f32,
    notes: &mut Vec<String>,
) -> (image::RgbaImage, Option<f32>) {
    use crate::render::compare;
    match mode {
        CompareMode::Split => (compare::split_view(a, b, split), None),
        CompareMode::Difference => {
            let (d, scale) = compare::difference_view(a, b, req.difference_scale);
            let plain = !(req.view.background.show
                && req.view.environment == EnvironmentChoice::Map
                && req.background_map.is_some());
            let stats = compare::difference_stats(a, b, plain);
            notes.push(format!(
                "|A − B| heat map: white = {scale:.1} ΔL*{} · mean {:.2}, max {:.1} ΔL* over {}",
                if req.difference_scale.is_none() {
                    " (auto)"
                } else {
                    ""
                },
                stats.mean,
                stats.max,
                if plain {
                    "the head"
                } else {
                    "the pixels that differ"
                }
            ));
            (d, Some(scale))
        }
        _ => {
            let mut out = image::RgbaImage::new(a.width() * 2, a.height());
            image::imageops::replace(&mut out, a, 0, 0);
            image::imageops::replace(&mut out, b, a.width() as i64, 0);
            (out, None)
        }
    }
}

/// Sets up the default head before a request for it is drawn (an error
/// here recurs, and is reported, at that request); the editor learns the
/// head's framing from it (Reset view, zoom limits, and the start-up check
/// of a remembered view). Its skin maps (curvature, thickness: about a
/// second) bake now, before the first frame, so that frame already has
/// them (they used to pop in a second or two after it).
pub(super) fn default_head(w: &mut Worker, tx: &Sender<Reply>) {
    if let (Ok(true), Some(info)) = (
        w.ensure_renderer(&None, &Default::default(), 1.0),
        w.mesh_info,
    ) {
        let _ = tx.send(Reply::MeshLoaded(None, info));
    }
    if let Err(e) = w.apply_pending_maps() {
        let _ = tx.send(Reply::Error(e));
    }
}

/// The scene-linear radiance of the frame just drawn, when the viewport
/// shows one look alone (side by side, split or a difference, the targets
/// hold B's last side): the pixel probe's and the histogram's. `None`
/// where it cannot be read (said nowhere: the probe then says it has
/// none).
pub(super) fn last_radiance(w: &mut Worker, req: &Request) -> Option<std::sync::Arc<SceneLinear>> {
    if !req.want_radiance {
        return None;
    }
    let alone = match &req.b {
        Some((_, mode, _)) => req.show_b || *mode == CompareMode::Off,
        None => true,
    };
    if !alone {
        return None;
    }
    let read = w.renderer.as_mut()?.read_last_radiance();
    read.ok().map(std::sync::Arc::new)
}

/// The artist's mesh at `path` as the viewport draws it: at its units,
/// turned outward where asked, with the maps its slots name (the render
/// thread's, and the glTF export's of the mesh on screen).
pub fn load_mesh(
    path: &std::path::Path,
    settings: &crate::app::state::MeshSettings,
    thickness_range_mm: f32,
) -> Result<Mesh, String> {
    let mut m = Mesh::load(path, settings.metres_per_unit).map_err(|e| e.to_string())?;
    if settings.turn_outward {
        m.turn_outward();
    }
    crate::render::textures::apply_slots(
        std::sync::Arc::make_mut(&mut m.textures),
        &settings.maps,
        thickness_range_mm,
    )
    .map_err(|e| e.to_string())?;
    Ok(m)
}
