//! Progress bars for long parallel runs ([`run_jobs`](crate::jobs::run_jobs)),
//! drawn by [`indicatif`].
//!
//! Off by default: a library must not write to the terminal unasked. A
//! program (the `areawarp report` command) turns them on with [`enable`]
//! and names the current step with [`set_label`]; every [`run_jobs`]
//! call of at least [`MIN_JOBS`] jobs then shows a bar on standard error
//! as jobs complete — only when standard error is a terminal, so logs and
//! CI output stay clean (indicatif's own terminal check, and ours). Drawing
//! never touches the jobs' results: studies stay deterministic.
//!
//! [`run_jobs`]: crate::jobs::run_jobs

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

static ENABLED: AtomicBool = AtomicBool::new(false);
static LABEL: Mutex<String> = Mutex::new(String::new());

/// Runs with fewer jobs than this draw no bar.
pub const MIN_JOBS: usize = 16;

/// The bar's template: label, bar, percentage, count, elapsed and ETA.
const TEMPLATE: &str = "{msg} [{bar:30}] {percent:>3}% ({pos}/{len}) {elapsed} eta {eta}";

/// Turns progress bars on or off for the whole process (they are drawn
/// only if standard error is a terminal).
pub fn enable(on: bool) {
    ENABLED.store(on && std::io::stderr().is_terminal(), Ordering::Relaxed);
}

/// Whether bars are drawn.
pub fn enabled() -> bool {
    ENABLED.load(Ordering::Relaxed)
}

/// The text shown before the bar (e.g. the report's current step).
pub fn set_label(label: &str) {
    if let Ok(mut l) = LABEL.lock() {
        l.clear();
        l.push_str(label);
    }
}

/// A bar for `total` jobs, drawn to `target`, labelled with the current
/// [`set_label`] text.
fn bar(total: usize, target: ProgressDrawTarget) -> ProgressBar {
    let label = LABEL.lock().map(|l| l.clone()).unwrap_or_default();
    let style = ProgressStyle::with_template(TEMPLATE)
        .expect("a valid template")
        .progress_chars("#>-");
    ProgressBar::with_draw_target(Some(total as u64), target)
        .with_style(style)
        .with_message(label)
}

/// Counts the completed jobs of one run on an indicatif bar.
pub(crate) struct Tracker {
    bar: ProgressBar,
}

impl Tracker {
    /// A tracker for `total` jobs, if bars are on and the run is long enough.
    pub(crate) fn new(total: usize) -> Option<Tracker> {
        if !enabled() || total < MIN_JOBS {
            return None;
        }
        Some(Tracker {
            bar: bar(total, ProgressDrawTarget::stderr()),
        })
    }

    /// One job completed (thread-safe: indicatif's bar is shared state).
    pub(crate) fn tick(&self) {
        self.bar.inc(1);
    }
}

impl Drop for Tracker {
    /// Clears the bar's line.
    fn drop(&mut self) {
        self.bar.finish_and_clear();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bar_counts_jobs() {
        set_label("x");
        let b = bar(10, ProgressDrawTarget::hidden());
        for _ in 0..5 {
            b.inc(1);
        }
        assert_eq!((b.position(), b.length()), (5, Some(10)));
        assert_eq!(b.message(), "x");
    }

    #[test]
    fn no_tracker_unless_enabled_on_a_terminal() {
        // Tests run with stderr captured or piped: enabling is refused.
        if !std::io::stderr().is_terminal() {
            enable(true);
            assert!(!enabled());
            assert!(Tracker::new(1000).is_none());
        }
        assert!(Tracker::new(MIN_JOBS - 1).is_none());
    }
}
