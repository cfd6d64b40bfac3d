//! What the plots show, computed from the profile core. Curves of closed-
//! form models are computed on the UI thread in the frame of the edit (well
//! under a millisecond); fits, kernel taps, table previews and layered
//! multipoles run on a background thread (`Background`), newest request wins.

use super::state::OverlayModel;
use crate::model::fit::{fit_artist, fit_burley, fit_gaussians, fit_jimenez};
use crate::model::lut::{Lut, LutLayout};
use crate::model::separable::{SeparableKernel, Tap};
use crate::model::{RadialProfile, Rgb, DEFAULT_ENERGY_FRACTION};
use crate::settings::ProfileSpec;
use std::sync::mpsc::{channel, Receiver, Sender};

/// Plot points per curve.
pub const CURVE_POINTS: usize = 241;

/// R(r) and r·R(r) on a radius grid, with the 0.997-energy radii.
#[derive(Debug, Clone, PartialEq)]
pub struct Curves {
    pub radius_mm: Vec<f64>,
    pub r: Vec<Rgb>,
    pub r_times_r: Vec<Rgb>,
    pub radius_997_mm: Rgb,
    pub total: Rgb,
}

/// The widest channel's 0.997 radius times 1.5: the plot's range.
pub fn plot_range_mm(radius_997: Rgb) -> f64 {
    radius_997.into_iter().fold(1e-3, f64::max)
}

/// Decades below the plot range's end that the radius grid reaches with
/// log-spaced points (the log radius axis starts there).
pub const LOG_RADIUS_DECADES: f64 = 3.0;

impl Curves {
    /// Curves on [0, `r_max`] (`None`: the widest 0.997 radius): evenly
    /// spaced points for the linear radius axis and log-spaced ones over
    /// the last [`LOG_RADIUS_DECADES`] for the log axis, merged.
    pub fn of(p: &dyn RadialProfile, r_max: Option<f64>) -> Self {
        let radius_997_mm = p.radius_for_energy(DEFAULT_ENERGY_FRACTION);
        let r_max = r_max.unwrap_or_else(|| plot_range_mm(radius_997_mm));
        let n = CURVE_POINTS - 1;
        let mut radius_mm: Vec<f64> = (0..=n)
            .map(|i| r_max * i as f64 / n as f64)
            .chain(
                (0..n)
                    .map(|i| r_max * 10f64.powf(LOG_RADIUS_DECADES * (i as f64 / n as f64 - 1.0))),
            )
            .collect();
        radius_mm.sort_by(f64::total_cmp);
        radius_mm.dedup();
        Self {
            r: radius_mm.iter().map(|&r| p.reflectance(r)).collect(),
            r_times_r: radius_mm.iter().map(|&r| p.r_reflectance(r)).collect(),
            radius_mm,
            radius_997_mm,
            total: p.total_reflectance(),
        }
    }
}

/// Whether building the model is too slow for the UI thread (stacks of
/// layers go through the FFTLog Hankel transform).
pub fn is_slow(spec: &ProfileSpec) -> bool {
    matches!(spec, ProfileSpec::Multipole(m) if m.layers.len() > 1)
}

#[derive(Debug, Clone, PartialEq)]
pub struct AnalysisKey {
    pub profile: ProfileSpec,
    pub taps: usize,
    pub overlay: OverlayModel,
    pub thickness_max_mm: f64,
}

/// A fitted model's curves, its shape error and what using it does to
/// the look's colour.
#[derive(Debug, Clone)]
pub struct Overlay {
    pub label: String,
    pub curves: Curves,
    /// Relative L2 error of the energy-normalised r·R(r) (the shape).
    pub error: Rgb,
    /// The colour the look would have with the fit (its surface albedo,
    /// `render::inputs::look_colour`) over the colour it has, minus 1: 0
    /// where the fit keeps the total reflectance; an energy-normalised
    /// kernel takes the default skin colour.
    pub energy_change: Rgb,
    /// The fitted model as a look, to apply with one click.
    pub spec: ProfileSpec,
}

/// The background results for one key.
#[derive(Debug, Clone)]
pub struct Analysis {
    pub key: AnalysisKey,
    /// Curves of slow models (fast ones are computed per frame).
    pub curves: Curves,
    pub overlay: Option<Result<Overlay, String>>,
    pub taps: Vec<Tap>,
    /// 64² preview of the pre-integrated table (linear D, sRGB-encoded for display).
    pub lut_preview: Vec<[u8; 3]>,
    pub lut_size: usize,
    /// T(d) at d = (i + ½)/N · thickness_max.
    pub transmittance: Vec<Rgb>,
    /// Burley parameters for the engine readouts of a non-Burley look:
    /// the fit and its largest relative L2 error.
    pub burley_fit: Option<Result<(crate::model::burley::Burley, f64), String>>,
    pub seconds: f64,
}

pub const LUT_PREVIEW: usize = 64;

fn fitted(
    look: &ProfileSpec,
    p: &dyn RadialProfile,
    which: OverlayModel,
    r_max: f64,
) -> Option<Result<Overlay, String>> {
    use crate::render::inputs::look_colour;
    use crate::settings::profile::*;
    let before = look_colour(look, p);
    let to_overlay = |label: &str, m: &dyn RadialProfile, error: Rgb, spec: ProfileSpec| {
        let after = look_colour(&spec, m);
        Overlay {
            label: label.into(),
            curves: Curves::of(m, Some(r_max)),
            error,
            energy_change: [0, 1, 2].map(|c| {
                if before[c] > 0.0 {
                    (after[c] / before[c]) as f64 - 1.0
                } else {
                    0.0
                }
            }),
            spec,
        }
    };
    let r = match which {
        OverlayModel::None => return None,
        OverlayModel::Burley => fit_burley(p).map(|f| {
            to_overlay(
                "Burley fit",
                &f.model,
                f.relative_l2_error,
                ProfileSpec::Burley(BurleySpec {
                    albedo: f.model.albedo(),
                    shape: BurleyShape::ScatteringDistance {
                        mm: f.model.scattering_distance_mm(),
                        multiplier: 1.0,
                    },
                }),
            )
        }),
        OverlayModel::Jimenez => fit_jimenez(p).map(|f| {
            to_overlay(
                "Jimenez 2012 fit",
                &f.model,
                f.relative_l2_error,
                ProfileSpec::Jimenez2012(Jimenez2012Spec {
                    strength: f.model.strength(),
                    falloff: f.model.falloff(),
                }),
            )
        }),
        OverlayModel::Artist => fit_artist(p).map(|f| {
            to_overlay(
                "artist two-Gaussian fit",
                &f.model,
                f.relative_l2_error,
                ProfileSpec::Artist(ArtistSpec {
                    sigma_near: f.model.sigma_near(),
                    sigma_far: f.model.sigma_far(),
                    weight: f.model.weight(),
                    scale_mm: f.model.scale_mm(),
                }),
            )
        }),
        OverlayModel::Gaussians4 => fit_gaussians(p, 4).map(|f| {
            let m = &f.model;
            let terms = (0..m.channel_terms(0).len())
                .map(|k| GaussianTerm {
                    variance_mm2: m.channel_terms(0)[k].variance_mm2,
                    weights: [0, 1, 2].map(|c| m.channel_terms(c)[k].weight),
                })
                .collect();
            to_overlay(
                "4-Gaussian fit",
                m,
                f.relative_l2_error,
                ProfileSpec::Gaussians(GaussiansSpec {
                    gaussians: terms,
                    dirac: m.dirac_weight(),
                }),
            )
        }),
    };
    Some(r.map_err(|e| e.to_string()))
}

/// Everything for `key` (runs on the background thread).
pub fn analyse(key: &AnalysisKey) -> Result<Analysis, String> {
    let t0 = std::time::Instant::now();
    let p = key.profile.build().map_err(|e| e.to_string())?;
    let p = p.as_ref();
    let curves = Curves::of(p, None);
    let r_max = *curves.radius_mm.last().unwrap_or(&1.0);
    let overlay = fitted(&key.profile, p, key.overlay, r_max);
    let taps = SeparableKernel::importance_sampled(p, key.taps)
        .map(|k| k.taps)
        .unwrap_or_default();
    let layout = LutLayout {
        width: LUT_PREVIEW,
        height: LUT_PREVIEW,
        ..LutLayout::default()
    };
    let lut_preview = Lut::bake(p, layout)
        .map(|l| l.d.iter().map(|d| d.map(linear_to_srgb8)).collect())
        .unwrap_or_default();
    let n = 64;
    let transmittance = (0..n)
        .map(|i| p.transmittance((i as f64 + 0.5) / n as f64 * key.thickness_max_mm))
        .collect();
    let burley_fit = match &key.profile {
        ProfileSpec::Burley(_) => None,
        _ => Some(
            fit_burley(p)
                .map(|f| {
                    let e = f.max_error();
                    (f.model, e)
                })
                .map_err(|e| e.to_string()),
        ),
    };
    Ok(Analysis {
        burley_fit,
        key: key.clone(),
        curves,
        overlay,
        taps,
        lut_preview,
        lut_size: LUT_PREVIEW,
        transmittance,
        seconds: t0.elapsed().as_secs_f64(),
    })
}

/// A background thread computing `f(key)` for the newest key sent. A
/// panic in `f` is caught: its key gets `failed(message)` as its value and
/// the thread goes on with the next key.
pub struct Background<K, V> {
    tx: Sender<K>,
    rx: Receiver<(K, V)>,
    sent: Option<K>,
    busy: bool,
    /// Set by a test to make the next computation panic.
    fault: std::sync::Arc<std::sync::atomic::AtomicBool>,
}

/// The calling thread yields the CPU to the viewport's: nice 10 for this
/// thread alone (on Linux a thread's nice value is its own,
/// setpriority(2), "BUGS"), so when the render thread, lavapipe's workers
/// and this thread all want the 2 cores the scheduler gives this one about
/// a tenth of their weight (1024 against 110 in Linux's CFS weights), and
/// all it wants when they wait. Elsewhere a no-op.
fn lower_priority() {
    #[cfg(target_os = "linux")]
    {
        let _ = rustix::process::setpriority_process(Some(rustix::thread::gettid()), 10);
    }
}

impl<K: Clone + PartialEq + Send + Sync + 'static, V: Send + 'static> Background<K, V> {
    pub fn start(
        name: &str,
        f: impl Fn(&K) -> V + Send + Sync + 'static,
        failed: impl Fn(String) -> V + Send + 'static,
        wake: impl Fn() + Send + 'static,
    ) -> Self {
        let (tx, krx) = channel::<K>();
        let (vtx, rx) = channel::<(K, V)>();
        let fault = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let their_fault = fault.clone();
        let thread = name.to_owned();
        let _ = std::thread::Builder::new()
            .name(name.into())
            .spawn(move || {
                lower_priority();
                // Its parallel work (the table preview's bake) on this
                // thread alone: in rayon's global pool it took both cores
                // for about a second after every edit, and the viewport's
                // refining frames then took 150–260 ms instead of 90–100
                // (with the nice value below; docs/rendering.md, "Live
                // while you work").
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(1)
                    .thread_name(|_| "scatterlab-analysis-pool".into())
                    .build()
                    .ok();
                while let Some(k) = super::wake::recv_newest(&krx) {
                    let run = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                        if their_fault.swap(false, std::sync::atomic::Ordering::Relaxed) {
                            panic!("a failure injected by a test");
                        }
                        match &pool {
                            Some(pool) => pool.install(|| f(&k)),
                            None => f(&k),
                        }
                    }));
                    let v = run.unwrap_or_else(|panic| {
                        let what = panic
                            .downcast_ref::<&str>()
                            .map(|s| s.to_string())
                            .or_else(|| panic.downcast_ref::<String>().cloned())
                            .unwrap_or_else(|| "no message".into());
                        failed(format!(
                            "the {thread} thread failed ({what}); it goes on with the next change, and the look is untouched"
                        ))
                    });
                    if vtx.send((k, v)).is_err() {
                        return;
                    }
                    wake();
                }
            });
        Self {
            tx,
            rx,
            sent: None,
            busy: false,
            fault,
        }
    }

    /// Makes the next computation panic (tests of the recovery; nothing
    /// in the editor calls it).
    #[doc(hidden)]
    pub fn inject_panic(&self) {
        self.fault.store(true, std::sync::atomic::Ordering::Relaxed);
    }

    /// Asks for `key` unless it was the last key asked for; true when it
    /// asked.
    pub fn request(&mut self, key: K) -> bool {
        if self.sent.as_ref() == Some(&key) {
            return false;
        }
        self.busy = self.tx.send(key.clone()).is_ok();
        self.sent = Some(key);
        true
    }

    /// The newest result that arrived, with its key, if any.
    pub fn poll(&mut self) -> Option<(K, V)> {
        let kv = self.rx.try_iter().last();
        if let Some((k, _)) = &kv {
            if self.sent.as_ref() == Some(k) {
                self.busy = false;
            }
        }
        kv
    }

    /// Whether the last request is still being computed.
    pub fn busy(&self) -> bool {
        self.busy
    }
}

/// Linear [0, 1] to an 8-bit sRGB code (display only).
pub fn linear_to_srgb8(v: f64) -> u8 {
    crate::model::colour::linear_to_srgb8(v as f32)
}
