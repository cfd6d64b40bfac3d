//! Work on other threads that the editor waits on: exports (table bakes
//! take seconds) and an HDR environment map loading (decoding and
//! projecting a large map takes a while). Each thread wakes the UI when it
//! finishes; `EditorApp::poll_workers` takes in what finished.

use super::*;

/// The widest background image kept of an HDR map (texels): a 1024 × 512
/// map is 4 texels a degree of a 60° view of 1000 px, soft but not blocky,
/// in 4 MB of half floats.
const BACKGROUND_WIDTH: usize = 1024;

/// A finished export, reported by its thread.
pub(super) type ExportResult = Result<Vec<PathBuf>, String>;

/// A loaded HDR map: its file, irradiance SH and background image, or why
/// not.
pub(super) type EnvironmentResult = Result<
    (
        PathBuf,
        [[f32; 3]; 9],
        Option<crate::render::environment::BackgroundMap>,
    ),
    String,
>;

/// The exports under way, and an HDR map loading.
#[derive(Default)]
pub(super) struct Jobs {
    exports: Vec<std::sync::mpsc::Receiver<ExportResult>>,
    /// An HDR environment map loading on its own thread, and the
    /// environment chosen before it, when that choice is to be kept (the
    /// remembered map read again at start-up for its picture).
    environment: Option<(
        std::sync::mpsc::Receiver<EnvironmentResult>,
        Option<state::EnvironmentChoice>,
    )>,
}

/// An environment map's load, finished.
pub(super) struct LoadedEnvironment {
    pub(super) result: EnvironmentResult,
    /// The choice to keep (the map is then the background only), if any.
    pub(super) keep: Option<state::EnvironmentChoice>,
}

impl Jobs {
    /// Exports `preset` (from the file `source`) as `format` to `out` on
    /// its own thread.
    pub(super) fn export(
        &mut self,
        (preset, source): (Preset, Option<PathBuf>),
        format: Format,
        out: PathBuf,
        on_mesh: Option<OnMesh>,
        waker: &wake::Waker,
    ) {
        let (tx, rx) = std::sync::mpsc::channel();
        let waker = waker.clone();
        std::thread::spawn(move || {
            let r = export_on(&preset, source.as_deref(), format, &out, on_mesh);
            let _ = tx.send(r);
            waker.wake();
        });
        self.exports.push(rx);
    }

    /// Loads the equirectangular HDR map at `path` on its own thread: its
    /// irradiance and its background picture. `keep`: the environment
    /// chosen now stays when it arrives.
    pub(super) fn load_environment(
        &mut self,
        path: PathBuf,
        keep: Option<state::EnvironmentChoice>,
        waker: &wake::Waker,
    ) {
        let (tx, rx) = std::sync::mpsc::channel();
        let waker = waker.clone();
        std::thread::spawn(move || {
            let r = crate::render::environment::Environment::load(&path)
                .map(|e| {
                    let bg = crate::render::environment::BackgroundMap::of(&e, BACKGROUND_WIDTH);
                    (path, e.irradiance_sh(), bg)
                })
                .map_err(|e| e.to_string());
            let _ = tx.send(r);
            waker.wake();
        });
        self.environment = Some((rx, keep));
    }

    /// An environment map is loading.
    pub(super) fn loading_environment(&self) -> bool {
        self.environment.is_some()
    }

    /// Whether anything is under way (the status bar's spinner).
    pub(super) fn busy(&self) -> bool {
        !self.exports.is_empty() || self.environment.is_some()
    }

    /// The exports that finished since the last call.
    pub(super) fn finished_exports(&mut self) -> Vec<ExportResult> {
        let mut done = Vec::new();
        self.exports.retain(|rx| match rx.try_recv() {
            Ok(r) => {
                done.push(r);
                false
            }
            Err(std::sync::mpsc::TryRecvError::Empty) => true,
            Err(_) => false,
        });
        done
    }

    /// The environment map's load, once it finished (a thread that died
    /// is forgotten).
    pub(super) fn finished_environment(&mut self) -> Option<LoadedEnvironment> {
        let (rx, _) = self.environment.as_ref()?;
        match rx.try_recv() {
            Ok(result) => {
                let (_, keep) = self.environment.take()?;
                Some(LoadedEnvironment { result, keep })
            }
            Err(std::sync::mpsc::TryRecvError::Empty) => None,
            Err(_) => {
                self.environment = None;
                None
            }
        }
    }
}

/// The mesh on screen for a glTF export: its file, its units and maps, and
/// how the look draws its colour map.
pub(super) type OnMesh = (
    PathBuf,
    state::MeshSettings,
    crate::render::textures::MapColour,
);

/// An export; a glTF one on the mesh on screen (`on_mesh`), loaded here as
/// the viewport draws it.
fn export_on(
    preset: &Preset,
    source: Option<&std::path::Path>,
    format: Format,
    out: &std::path::Path,
    on_mesh: Option<OnMesh>,
) -> Result<Vec<PathBuf>, String> {
    let mut options = crate::export::ExportOptions::default();
    if let (Format::Gltf, Some((path, settings, map_colour))) = (format, on_mesh) {
        let range = preset.rendering.thickness_remap_mm.1 as f32;
        let mesh = super::viewport::load_mesh(&path, &settings, range)
            .map_err(|e| format!("{}: {e}", path.display()))?;
        options.gltf_on_mesh = Some(crate::export::GltfOnMesh {
            mesh: std::sync::Arc::new(mesh),
            name: path
                .file_stem()
                .map_or("mesh".into(), |s| s.to_string_lossy().into_owned()),
            map_colour,
        });
    }
    crate::export::export_with(preset, source, format, out, &options).map_err(|e| e.to_string())
}
