//! A progress bar for the run: step, simulated time and estimated time left, on stderr.
//!
//! Owns only the terminal display (through `indicatif`). The bar is drawn only when it is
//! enabled *and* stderr is a terminal (`std::io::IsTerminal`); otherwise (a pipe, a file, CI)
//! nothing is drawn, so logs stay clean. Messages given to [`Progress::println`] are always
//! written to stderr, one per line: above the bar when it is drawn, plainly otherwise; the
//! model's warnings (`warning: …`) likewise, unless the bar is quiet ([`Progress::quiet`]).
//!
//! A run that finishes leaves the bar full; an interrupted or failed one leaves it where the
//! run stopped (never a false 100% before "interrupted").

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

const TEMPLATE: &str =
    "[{elapsed_precise}] {bar:30.cyan/blue} step {pos}/{len}  t = {prefix}  {msg}  ETA {eta}";

/// Progress of a run of `total_steps` steps.
pub struct Progress {
    bar: ProgressBar,
    drawn: bool,
    quiet: bool,
}

impl Progress {
    /// A bar over `total_steps` steps, drawn only if `enabled` and stderr is a terminal.
    pub fn new(total_steps: usize, enabled: bool) -> Self {
        Self::with_terminal(total_steps, enabled && std::io::stderr().is_terminal())
    }

    fn with_terminal(total_steps: usize, drawn: bool) -> Self {
        let target = if drawn {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        let bar = ProgressBar::with_draw_target(Some(total_steps as u64), target);
        if let Ok(style) = ProgressStyle::with_template(TEMPLATE) {
            bar.set_style(style.progress_chars("=> "));
        }
        Self {
            bar,
            drawn,
            quiet: false,
        }
    }

    /// Hide the model's warnings (`--quiet`).
    pub fn quiet(mut self, quiet: bool) -> Self {
        self.quiet = quiet;
        self
    }

    /// Whether the bar is drawn.
    #[cfg(test)]
    pub fn is_drawn(&self) -> bool {
        self.drawn
    }

    /// Reports that `step` steps are done and the simulated time is `time` (s).
    pub fn set(&self, step: usize, time: f64) {
        self.bar.set_position(step as u64);
        if self.drawn {
            self.bar.set_prefix(format_time(time));
        }
    }

    /// Shows the run's counters: linear solves, Δt cuts, active-set changes.
    pub fn set_counts(&self, solves: usize, cuts: usize, changes: usize) {
        if self.drawn {
            self.bar.set_message(format!(
                "solves {solves}  cuts {cuts}  active-set changes {changes}"
            ));
        }
    }

    /// Current step as last set.
    #[cfg(test)]
    pub fn position(&self) -> usize {
        self.bar.position() as usize
    }

    /// Prints one line of text on stderr without breaking the bar.
    pub fn println(&self, msg: impl AsRef<str>) {
        if self.drawn {
            self.bar.println(msg);
        } else {
            eprintln!("{}", msg.as_ref());
        }
    }

    /// Leaves the bar in its final state (drawn bars stay on screen): full if the run
    /// finished, at the last completed step if it was interrupted or failed.
    pub fn finish(&self, status: nmm::simulation::RunStatus) {
        match status {
            nmm::simulation::RunStatus::Finished => self.bar.finish(),
            _ => self.bar.abandon(),
        }
        if self.drawn {
            // indicatif leaves the cursor at the end of the bar's line
            eprintln!();
        }
    }
}

/// Simulated time for display: six decimals, trailing zeros trimmed (`0.28 s`), or three
/// significant digits in exponent form outside `[1e-3, 1e6)` (`2.500e-5 s`).
fn format_time(t: f64) -> String {
    if t == 0.0 {
        return "0 s".to_string();
    }
    if !(1e-3..1e6).contains(&t.abs()) {
        return format!("{t:.3e} s");
    }
    let s = format!("{t:.6}");
    format!("{} s", s.trim_end_matches('0').trim_end_matches('.'))
}

impl nmm::simulation::RunObserver for Progress {
    fn start(&mut self, step: usize, total_steps: usize) {
        self.bar.set_length(total_steps as u64);
        self.set(step, 0.0);
    }
    fn step_done(&mut self, step: usize, time: f64) {
        self.set(step, time);
    }
    fn counts(&mut self, solves: usize, cuts: usize, changes: usize) {
        self.set_counts(solves, cuts, changes);
    }
    fn message(&mut self, line: &str) {
        self.println(line);
    }
    fn warning(&mut self, line: &str) {
        if !self.quiet {
            self.println(format!("warning: {line}"));
        }
    }
    fn finish(&mut self, status: nmm::simulation::RunStatus) {
        Progress::finish(self, status);
    }
}

impl Drop for Progress {
    fn drop(&mut self) {
        if !self.bar.is_finished() {
            self.bar.abandon();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{format_time, Progress};
    use nmm::simulation::{RunObserver, RunStatus};

    #[test]
    fn times_are_short() {
        assert_eq!(format_time(0.0), "0 s");
        assert_eq!(format_time(0.1 + 0.18), "0.28 s");
        assert_eq!(format_time(12.0), "12 s");
        assert_eq!(format_time(2.5e-5), "2.500e-5 s");
        assert_eq!(format_time(f64::NAN), "NaN s");
    }

    #[test]
    fn hidden_bar_tracks_position_without_drawing() {
        let p = Progress::with_terminal(10, false);
        assert!(!p.is_drawn());
        p.set(3, 0.25);
        assert_eq!(p.position(), 3);
        p.finish(RunStatus::Finished);
        assert_eq!(p.position(), 10);
    }

    #[test]
    fn an_interrupted_run_does_not_fill_the_bar() {
        for status in [RunStatus::Interrupted, RunStatus::Failed] {
            let mut p = Progress::with_terminal(10, false);
            p.start(0, 10);
            p.step_done(4, 0.004);
            RunObserver::finish(&mut p, status);
            assert_eq!(p.position(), 4, "{status:?}");
        }
    }

    #[test]
    fn disabled_is_never_drawn() {
        // Whatever stderr is, a disabled bar is not drawn.
        assert!(!Progress::new(5, false).is_drawn());
    }
}
