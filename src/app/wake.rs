//! Waking the UI from another thread. egui draws a frame only on input or
//! when asked to, so a background job that finishes asks for one: its
//! result is on screen at once, not at the next mouse move (issue 36).
//! And the other way: a thread that works on the newest request only.

use std::sync::mpsc::{Receiver, TryRecvError};
use std::sync::{Arc, OnceLock};

/// Asks egui for a frame from any thread. Cloned into each job; the
/// context is attached by the first frame (`EditorApp::show`), so jobs
/// started before it (the analysis and the viewport start with the
/// editor) wake it too.
#[derive(Clone, Default)]
pub struct Waker(Arc<OnceLock<egui::Context>>);

impl Waker {
    /// A waker attached to `ctx` now, if there is one.
    pub fn new(ctx: Option<&egui::Context>) -> Self {
        let w = Self::default();
        if let Some(c) = ctx {
            w.attach(c);
        }
        w
    }

    /// From now on, wakes `ctx` (a second context is ignored: the editor
    /// has one).
    pub fn attach(&self, ctx: &egui::Context) {
        let _ = self.0.set(ctx.clone());
    }

    /// Asks for a frame now.
    pub fn wake(&self) {
        if let Some(c) = self.0.get() {
            c.request_repaint();
        }
    }

    /// A closure that wakes, for the threads that take one.
    pub fn as_fn(&self) -> impl Fn() + Send + Sync + 'static {
        let w = self.clone();
        move || w.wake()
    }
}

/// Blocks for a message, then drains the queue and returns the newest one
/// (older requests are superseded); `None` once the sender is gone.
pub fn recv_newest<T>(rx: &Receiver<T>) -> Option<T> {
    let mut newest = rx.recv().ok()?;
    loop {
        match rx.try_recv() {
            Ok(newer) => newest = newer,
            Err(TryRecvError::Empty) => return Some(newest),
            Err(TryRecvError::Disconnected) => return None,
        }
    }
}
