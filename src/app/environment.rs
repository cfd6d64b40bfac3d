//! The environment map: loaded on a thread, its irradiance (SH) for the
//! lighting and its picture for the background, and the remembered map's
//! picture read again at start-up.

use super::*;

/// The widest background image kept of an HDR map (texels): a 1024 × 512
/// map is 4 texels a degree of a 60° view of 1000 px, soft but not blocky,
/// in 4 MB of half floats.
const BACKGROUND_WIDTH: usize = 1024;

impl EditorApp {
    /// The HDR map remembered from the last run, for its background: its
    /// lighting is remembered (SH), its picture is read again, quietly.
    pub(super) fn reload_background(&mut self) {
        if self.view.background_map.is_none() && self.jobs.environment_load.is_none() {
            if let Some(p) = self
                .ui_state
                .environment_file
                .clone()
                .filter(|p| p.is_file())
            {
                let env = self.ui_state.view.environment;
                self.load_environment(p);
                // Loading makes the map the environment: keep the choice.
                self.view.keep_environment = Some(env);
            }
        }
    }

    pub fn load_environment(&mut self, path: PathBuf) {
        // A map asked for now becomes the lighting (`reload_background`
        // sets this again after calling here).
        self.view.keep_environment = None;
        let (tx, rx) = std::sync::mpsc::channel();
        self.say(format!("Loading environment {} …", path.display()));
        let waker = self.waker.clone();
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
        self.jobs.environment_load = Some(rx);
    }

    /// Takes in what the background threads finished: the analysis (fits,
    /// tables, a slow model's curves), an environment map, exports.
    /// Takes in an environment map that finished loading.
    pub(super) fn poll_environment(&mut self) {
        if let Some(rx) = &self.jobs.environment_load {
            match rx.try_recv() {
                Ok(Ok((path, sh, bg))) => {
                    self.view.background_map =
                        bg.map(|m| viewport::SharedMap(std::sync::Arc::new(m)));
                    let v = &mut self.ui_state.view;
                    v.environment_map_sh = Some(sh);
                    match self.view.keep_environment.take() {
                        // The remembered map read again at start-up: the
                        // artist's choice stays, and nothing is said.
                        Some(env) => v.environment = env,
                        None => {
                            v.environment = state::EnvironmentChoice::Map;
                            self.say(format!("Environment {}", path.display()));
                        }
                    }
                    self.ui_state.environment_file = Some(path);
                    self.environment_loaded();
                    self.jobs.environment_load = None;
                }
                Ok(Err(e)) => {
                    self.view.keep_environment = None;
                    self.say(format!("Error: {e}"));
                    self.jobs.environment_load = None;
                    // The HDR rig that asked for this map is off.
                    self.environment_not_loaded();
                }
                Err(std::sync::mpsc::TryRecvError::Empty) => {}
                Err(_) => self.jobs.environment_load = None,
            }
        }
    }
}
