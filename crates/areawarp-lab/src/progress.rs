//! Progress bars for long parallel runs ([`run_jobs`](crate::jobs::run_jobs)).
//!
//! Off by default: a library must not write to the terminal unasked. A
//! program (the `areawarp report` command) turns them on with [`enable`]
//! and names the current step with [`set_label`]; every [`run_jobs`]
//! call of at least [`MIN_JOBS`] jobs then redraws one line on standard
//! error as jobs complete — only when standard error is a terminal, so
//! logs and CI output stay clean. Drawing never touches the jobs' results:
//! studies stay deterministic.
//!
//! [`run_jobs`]: crate::jobs::run_jobs

use std::io::{IsTerminal, Write};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

static ENABLED: AtomicBool = AtomicBool::new(false);
static LABEL: Mutex<String> = Mutex::new(String::new());

/// Runs with fewer jobs than this draw no bar.
pub const MIN_JOBS: usize = 16;

/// Width of the bar in characters.
const WIDTH: usize = 30;

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

/// The bar's text for `done` of `total` jobs: `label [#####-----] 50% (5/10)`.
pub fn render(label: &str, done: usize, total: usize) -> String {
    let total = total.max(1);
    let done = done.min(total);
    let filled = done * WIDTH / total;
    format!(
        "{label} [{}{}] {:3}% ({done}/{total})",
        "#".repeat(filled),
        "-".repeat(WIDTH - filled),
        done * 100 / total
    )
}

/// Counts the completed jobs of one run and redraws the bar whenever the
/// filled width changes (at most [`WIDTH`] redraws per run).
pub(crate) struct Tracker {
    total: usize,
    done: AtomicUsize,
    label: String,
}

impl Tracker {
    /// A tracker for `total` jobs, if bars are on and the run is long enough.
    pub(crate) fn new(total: usize) -> Option<Tracker> {
        if !enabled() || total < MIN_JOBS {
            return None;
        }
        let label = LABEL.lock().map(|l| l.clone()).unwrap_or_default();
        Some(Tracker {
            total,
            done: AtomicUsize::new(0),
            label,
        })
    }

    /// One job completed.
    pub(crate) fn tick(&self) {
        let done = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        let before = (done - 1) * WIDTH / self.total;
        let now = done * WIDTH / self.total;
        if now != before || done == 1 {
            let mut err = std::io::stderr().lock();
            let _ = write!(err, "\r{}", render(&self.label, done, self.total));
            let _ = err.flush();
        }
    }
}

impl Drop for Tracker {
    /// Clears the bar's line.
    fn drop(&mut self) {
        let mut err = std::io::stderr().lock();
        let _ = write!(err, "\r{}\r", " ".repeat(self.label.len() + WIDTH + 24));
        let _ = err.flush();
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bar_text() {
        assert_eq!(
            render("x", 0, 10),
            format!("x [{}]   0% (0/10)", "-".repeat(WIDTH))
        );
        assert_eq!(
            render("x", 5, 10),
            format!("x [{}{}]  50% (5/10)", "#".repeat(15), "-".repeat(15))
        );
        assert_eq!(
            render("x", 12, 10),
            format!("x [{}] 100% (10/10)", "#".repeat(WIDTH))
        );
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
