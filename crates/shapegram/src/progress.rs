//! Progress bars for long runs.

use std::sync::OnceLock;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// How long work runs before its bar appears: quick runs print nothing.
const DELAY: Duration = Duration::from_millis(500);

/// A progress bar on stderr that appears only once the work has taken half a second. Safe to
/// update from parallel work.
pub struct LateBar {
    enabled: bool,
    started: Instant,
    template: &'static str,
    bar: OnceLock<ProgressBar>,
}

impl LateBar {
    /// A bar drawn with an indicatif `template`, or none at all when not `enabled` (stderr is not
    /// a terminal, or `-q`).
    pub fn new(enabled: bool, template: &'static str) -> Self {
        Self {
            enabled,
            started: Instant::now(),
            template,
            bar: OnceLock::new(),
        }
    }

    /// Reports `position` of `length`, with the message `message` makes (only asked for when
    /// the bar is shown).
    pub fn update(&self, position: u64, length: u64, message: impl FnOnce() -> String) {
        if !self.enabled || self.started.elapsed() < DELAY {
            return;
        }
        let bar = self.bar.get_or_init(|| {
            let bar = ProgressBar::with_draw_target(Some(length), ProgressDrawTarget::stderr());
            if let Ok(style) = ProgressStyle::with_template(self.template) {
                bar.set_style(style);
            }
            bar
        });
        bar.set_length(length);
        bar.set_position(position);
        bar.set_message(message());
    }

    /// Erases the bar, if it was shown.
    pub fn finish(self) {
        if let Some(bar) = self.bar.get() {
            bar.finish_and_clear();
        }
    }
}

/// Runs `work`, showing a spinner with `label` and the time so far on stderr (when `enabled`)
/// once it has taken half a second: for work that cannot say how far along it is.
pub fn with_spinner<T>(enabled: bool, label: &str, work: impl FnOnce() -> T) -> T {
    if !enabled {
        return work();
    }
    let (done, finished) = mpsc::channel::<()>();
    std::thread::scope(|scope| {
        scope.spawn(move || {
            if finished.recv_timeout(DELAY) != Err(RecvTimeoutError::Timeout) {
                return;
            }
            let spinner = ProgressBar::with_draw_target(None, ProgressDrawTarget::stderr());
            if let Ok(style) = ProgressStyle::with_template("{spinner} {msg}: {elapsed}") {
                spinner.set_style(style);
            }
            spinner.set_message(label.to_owned());
            spinner.enable_steady_tick(Duration::from_millis(100));
            // Returns when `done` is dropped.
            let _ = finished.recv();
            spinner.finish_and_clear();
        });
        let result = work();
        drop(done);
        result
    })
}
