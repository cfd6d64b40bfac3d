//! The editor's shell: eframe's window with its persistence and close
//! prompt, the command line's arguments, and the start-up (the state
//! remembered, the look, mesh, map and compare asked for).

use super::*;

/// eframe's wrapper: persistence and the close prompt.
struct EframeApp {
    app: EditorApp,
    /// Close once the viewport has shown a frame (smoke test).
    exit_after_first_frame: bool,
}

impl eframe::App for EframeApp {
    /// The panels' colour: they draw no fill of their own (see
    /// [`EditorApp::show`]).
    fn clear_color(&self, visuals: &egui::Visuals) -> [f32; 4] {
        visuals.panel_fill.to_normalized_gamma_f32()
    }

    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        let app = &mut self.app;
        if self.exit_after_first_frame && app.viewport().has_frame() {
            app.allow_close = true;
        }
        if ui.ctx().input(|i| i.viewport().close_requested())
            && app.doc.is_dirty()
            && !app.allow_close
        {
            ui.ctx()
                .send_viewport_cmd(egui::ViewportCommand::CancelClose);
            app.windows.unsaved.pending = Some(Pending::Quit);
        }
        if app.allow_close {
            ui.ctx().send_viewport_cmd(egui::ViewportCommand::Close);
        }
        app.show(ui);
    }

    /// A clean quit (the unsaved-changes prompt answered, or nothing
    /// unsaved): nothing is left to recover.
    fn on_exit(&mut self) {
        self.app.autosave_clear();
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        let mut s = self.app.ui_state.clone();
        s.last_preset = self.app.doc.path.clone();
        eframe::set_value(storage, STORAGE_KEY, &s);
    }
}

/// A mesh to open the editor on (`edit --mesh`), checked before a window
/// opens.
#[derive(Debug, Clone)]
pub struct MeshArg {
    /// Absolute, as the file dialog gives it (the units and maps are
    /// remembered by path).
    pub path: PathBuf,
    /// Metres per unit, if given; else the remembered units or the prompt.
    pub metres_per_unit: Option<f32>,
}

impl MeshArg {
    /// The longest and shortest metres per unit the units prompt takes.
    pub const METRES_PER_UNIT: std::ops::RangeInclusive<f32> = 1e-6..=1e3;

    /// `path` if it is a file the mesh loader reads, and `metres_per_unit`
    /// if it is in [`Self::METRES_PER_UNIT`]; an error naming the flag
    /// otherwise.
    pub fn check(path: PathBuf, metres_per_unit: Option<f32>) -> anyhow::Result<Self> {
        let ext = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        if !ext.is_some_and(|e| crate::render::mesh::Mesh::EXTENSIONS.contains(&e.as_str())) {
            anyhow::bail!(
                "--mesh {}: not a mesh the editor reads (.obj, .gltf, .glb)",
                path.display()
            );
        }
        let path = std::fs::canonicalize(&path)
            .map_err(|e| anyhow::anyhow!("--mesh {}: {e}", path.display()))?;
        if let Some(m) = metres_per_unit {
            if !Self::METRES_PER_UNIT.contains(&m) {
                anyhow::bail!(
                    "--metres-per-unit {m}: outside {}–{} m per unit",
                    Self::METRES_PER_UNIT.start(),
                    Self::METRES_PER_UNIT.end()
                );
            }
        }
        Ok(Self {
            path,
            metres_per_unit,
        })
    }
}

/// Opens the editor window on `preset` (else the last preset, else the
/// embedded default skin).
/// `compare`: open comparing in this mode, B the look with this method
/// (`None`: B as last time).
/// What `scatterlab edit` asks of the editor at start.
pub struct RunArgs {
    pub preset: Option<PathBuf>,
    pub exit_after_first_frame: bool,
    pub compare: Option<(CompareMode, Option<crate::settings::rendering::MethodId>)>,
    pub import: Option<PathBuf>,
    pub mesh: Option<MeshArg>,
    pub budget: Option<PathBuf>,
    /// B: a preset or engine file.
    pub compare_with: Option<PathBuf>,
    /// An HDR map to light the head with (and show behind it).
    pub environment: Option<PathBuf>,
    pub map_colour: Option<crate::render::textures::MapColour>,
    pub procedural_head: bool,
}

pub fn run(args: RunArgs) -> anyhow::Result<()> {
    let started = std::time::Instant::now();
    let initial = match &args.preset {
        Some(p) => Some((Preset::load(p)?, Some(p.clone()))),
        None => None,
    };
    // An engine file to open: refused here, with its one line, before a
    // window opens.
    if let Some(f) = &args.import {
        crate::export::import_file(f, &crate::export::ImportOptions::default())?;
    }
    // A budget report to compare: refused here too.
    let budget = match &args.budget {
        Some(dir) => Some(windows::budget::BudgetPairs::load(dir).map_err(anyhow::Error::msg)?),
        None => None,
    };
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_title("scatterlab")
            .with_app_id("scatterlab")
            .with_inner_size([1500.0, 900.0])
            .with_min_inner_size([900.0, 560.0])
            .with_drag_and_drop(true),
        persist_window: true,
        ..Default::default()
    };
    eframe::run_native(
        "scatterlab",
        options,
        Box::new(move |cc| {
            let exit_after_first_frame = args.exit_after_first_frame;
            let app = start_editor(cc, args, initial, budget, started);
            Ok(Box::new(EframeApp {
                app,
                exit_after_first_frame,
            }))
        }),
    )
    .map_err(|e| anyhow::anyhow!("cannot open the editor window: {e}"))
}

/// The UI state remembered from the last run, with what the command line
/// asks for over it (a compare mode and B, the map's colour, the
/// procedural head).
fn remembered_state(cc: &eframe::CreationContext<'_>, args: &RunArgs) -> UiState {
    let mut ui_state: UiState = cc
        .storage
        .and_then(|s| eframe::get_value(s, STORAGE_KEY))
        .unwrap_or_default();
    if let Some((mode, b)) = args.compare {
        ui_state.compare = mode;
        if let Some(m) = b {
            ui_state.compare_b = CompareB::Method(m);
        }
    }
    if let Some(m) = args.map_colour {
        ui_state.map_colour = m;
    }
    if args.procedural_head {
        ui_state.start_on_scan = false;
    }
    ui_state
}

/// The editor on `initial` (else the look open last time) with its
/// autosave, and the command line's import, mesh, budget, environment and
/// B.
fn start_editor(
    cc: &eframe::CreationContext<'_>,
    args: RunArgs,
    initial: Option<(Preset, Option<PathBuf>)>,
    budget: Option<windows::budget::BudgetPairs>,
    started: std::time::Instant,
) -> EditorApp {
    let ui_state = remembered_state(cc, &args);
    let initial = initial.or_else(|| {
        let p = ui_state.last_preset.clone()?;
        Preset::load(&p).ok().map(|preset| (preset, Some(p)))
    });
    widget_map::install(&cc.egui_ctx);
    let mut app = EditorApp::new(Some(&cc.egui_ctx), ui_state, initial, true);
    // The data folder eframe keeps its state in (XDG_DATA_HOME/scatterlab).
    if let Some(dir) = eframe::storage_dir("scatterlab") {
        app = app.with_autosave(&dir);
    }
    app.report.started = started;
    if let Some(f) = &args.import {
        app.import_now(f);
    }
    match args.mesh {
        Some(m) => app.open_mesh(m),
        None if app.ui_state.start_on_scan => {
            app.open_scanned_head();
        }
        None => {}
    }
    if let Some(b) = budget {
        app.open_budget(b);
    }
    if let Some(p) = args.environment {
        app.load_environment(p);
    }
    if let Some(p) = args.compare_with {
        match viewport::load_look(&p) {
            Ok(b) => {
                app.ui_state.compare_b = CompareB::Preset(p);
                app.ask_b_albedo(&b);
            }
            Err(e) => app.say(format!("Error: --compare-with: {e}")),
        }
    }
    app
}

/// The View menu's interface scale and theme, set on `ctx` where
/// changed (`applied_scale`: the scale set last frame).
pub(super) fn apply_interface(
    ctx: &egui::Context,
    ui_state: &mut state::UiState,
    applied_scale: &mut Option<f32>,
) {
    // The interface's scale and theme (View menu), where changed; a
    // zoom by keyboard (egui's Ctrl+plus/minus) is taken as the scale.
    if let Some(applied) = *applied_scale {
        if (ctx.zoom_factor() - applied).abs() > 1e-4 {
            ui_state.ui_scale = ctx.zoom_factor();
        }
    }
    let scale = ui_state
        .ui_scale
        .clamp(*state::UI_SCALE_RANGE.start(), *state::UI_SCALE_RANGE.end());
    if (ctx.zoom_factor() - scale).abs() > 1e-4 {
        ctx.set_zoom_factor(scale);
    }
    *applied_scale = Some(scale);
    let theme = if ui_state.light_theme {
        egui::Theme::Light
    } else {
        egui::Theme::Dark
    };
    if ctx.theme() != theme {
        ctx.set_theme(theme);
    }
}
