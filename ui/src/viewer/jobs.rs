//! Work off the UI thread (loading and importing sets, long exports) with progress the UI can
//! show, and a Cancel the worker checks.
//!
//! - A job runs on its own thread; the worker writes its progress (counts and a message), and
//!   the UI reads it and polls for the result each frame.
//! - Cancel only sets a flag, which the worker checks.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Arc, Mutex};

/// Progress of a job: counts and a message, written by the worker, read by the UI.
#[derive(Default)]
pub struct Progress {
    done: AtomicUsize,
    total: AtomicUsize,
    message: Mutex<String>,
    cancelled: AtomicBool,
}

impl Progress {
    pub fn set(&self, done: usize, total: usize, message: &str) {
        self.done.store(done, Ordering::Relaxed);
        self.total.store(total, Ordering::Relaxed);
        if let Ok(mut m) = self.message.lock() {
            message.clone_into(&mut m);
        }
    }

    /// 0..=1, or `None` before the worker knows its total.
    pub fn fraction(&self) -> Option<f32> {
        let total = self.total.load(Ordering::Relaxed);
        (total > 0).then(|| self.done.load(Ordering::Relaxed) as f32 / total as f32)
    }

    /// Asks the worker to stop.
    pub fn cancel(&self) {
        self.cancelled.store(true, Ordering::Relaxed);
    }

    pub fn is_cancelled(&self) -> bool {
        self.cancelled.load(Ordering::Relaxed)
    }

    pub fn message(&self) -> String {
        self.message.lock().map(|m| m.clone()).unwrap_or_default()
    }
}

/// A job running on its own thread; the UI polls it each frame.
pub struct Job<T> {
    pub title: String,
    pub progress: Arc<Progress>,
    rx: mpsc::Receiver<T>,
}

impl<T: Send + 'static> Job<T> {
    /// Starts `work`; `ctx` is asked to repaint when it finishes.
    pub fn spawn(
        title: impl Into<String>,
        ctx: &eframe::egui::Context,
        work: impl FnOnce(&Progress) -> T + Send + 'static,
    ) -> Job<T> {
        let (tx, rx) = mpsc::channel();
        let progress = Arc::new(Progress::default());
        let (p, ctx) = (progress.clone(), ctx.clone());
        std::thread::spawn(move || {
            let result = work(&p);
            let _ = tx.send(result);
            ctx.request_repaint();
        });
        Job { title: title.into(), progress, rx }
    }

    /// The result once the job has finished (once).
    pub fn poll(&self) -> Option<T> {
        self.rx.try_recv().ok()
    }
}
