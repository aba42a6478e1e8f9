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
//!
//! When stderr is not a terminal (a batch job, a pipe), an enabled, non-quiet progress
//! writes instead one plain line every 10 s (`NMM_PROGRESS_SECONDS` sets another interval):
//! `progress: step 1200/8020 (15.0%), t = 1.2 s, 10 s elapsed, about 57 s left; solves …,
//! cuts …, active-set changes …; factorisations … (… symbolic), GMRES iterations …` (the
//! bar shows the same counters).

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;

const TEMPLATE: &str =
    "[{elapsed_precise}] {bar:30.cyan/blue} step {pos}/{len}  t = {prefix}  {msg}  ETA {eta}";

/// Progress of a run of `total_steps` steps.
pub struct Progress {
    bar: ProgressBar,
    drawn: bool,
    quiet: bool,
    /// Plain lines when the bar is not drawn: (interval, start, last line, counters).
    plain: Option<Plain>,
    /// The counters as shown in plain lines and on the bar: solves, cuts, active-set
    /// changes; then the linear solver's.
    counts_text: (String, String),
    linear_text: (String, String),
}

/// The state of the plain progress lines.
struct Plain {
    every: std::time::Duration,
    start: std::time::Instant,
    last: std::time::Instant,
    counts: String,
    first_step: usize,
}

/// The interval of the plain progress lines: `NMM_PROGRESS_SECONDS`, else 10 s.
fn plain_interval() -> std::time::Duration {
    let s = std::env::var("NMM_PROGRESS_SECONDS")
        .ok()
        .and_then(|v| v.parse::<f64>().ok())
        .filter(|v| v.is_finite() && *v >= 0.0)
        .unwrap_or(10.0);
    std::time::Duration::from_secs_f64(s)
}

impl Progress {
    /// A bar over `total_steps` steps, drawn only if `enabled` and stderr is a terminal.
    pub fn new(total_steps: usize, enabled: bool) -> Self {
        let terminal = std::io::stderr().is_terminal();
        let mut p = Self::with_terminal(total_steps, enabled && terminal);
        if enabled && !terminal {
            p.plain = Some(Plain::new(plain_interval()));
        }
        p
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
            plain: None,
            counts_text: Default::default(),
            linear_text: Default::default(),
        }
    }

    /// Hide the model's warnings and the plain progress lines (`--quiet`).
    pub fn quiet(mut self, quiet: bool) -> Self {
        self.quiet = quiet;
        if quiet {
            self.plain = None;
        }
        self
    }

    /// The plain progress line, if one is due (see the module doc).
    fn plain_line(&mut self, step: usize, time: f64) -> Option<String> {
        let total = self.bar.length().unwrap_or(0) as usize;
        let p = self.plain.as_mut()?;
        let now = std::time::Instant::now();
        if now.duration_since(p.last) < p.every || step >= total {
            return None;
        }
        p.last = now;
        let elapsed = now.duration_since(p.start).as_secs_f64();
        let done = step.saturating_sub(p.first_step);
        let left = if done > 0 {
            let left = elapsed / done as f64 * total.saturating_sub(step) as f64;
            if left < 10.0 {
                format!(", about {left:.1} s left")
            } else {
                format!(", about {left:.0} s left")
            }
        } else {
            String::new()
        };
        Some(format!(
            "progress: step {step}/{total} ({:.1}%), t = {}, {elapsed:.0} s elapsed{left}{}",
            100.0 * step as f64 / total.max(1) as f64,
            format_time(time),
            p.counts
        ))
    }

    /// Whether the bar is drawn.
    #[cfg(test)]
    pub fn is_drawn(&self) -> bool {
        self.drawn
    }

    /// Reports that `step` steps are done and the simulated time is `time` (s).
    pub fn set(&mut self, step: usize, time: f64) {
        self.bar.set_position(step as u64);
        if self.drawn {
            self.bar.set_prefix(format_time(time));
        }
        if let Some(line) = self.plain_line(step, time) {
            eprintln!("{line}");
        }
    }

    /// Shows the run's counters: linear solves, Δt cuts, active-set changes.
    pub fn set_counts(&mut self, solves: usize, cuts: usize, changes: usize) {
        self.counts_text = (
            format!("; solves {solves}, cuts {cuts}, active-set changes {changes}"),
            format!("solves {solves}  cuts {cuts}  active-set changes {changes}"),
        );
        self.show_counts();
    }

    /// Adds the linear solver's counters: factorisations (symbolic analyses), GMRES
    /// iterations.
    pub fn set_linear(&mut self, s: &nmm::solver::LinearStats) {
        self.linear_text = (
            format!(
                "; factorisations {} ({} symbolic), GMRES iterations {}",
                s.factorisations + s.lu_factorisations,
                s.symbolic_analyses,
                s.gmres_iterations
            ),
            format!(
                "  factorisations {}  GMRES {}",
                s.factorisations + s.lu_factorisations,
                s.gmres_iterations
            ),
        );
        self.show_counts();
    }

    fn show_counts(&mut self) {
        if let Some(p) = self.plain.as_mut() {
            p.counts = format!("{}{}", self.counts_text.0, self.linear_text.0);
        }
        if self.drawn {
            self.bar
                .set_message(format!("{}{}", self.counts_text.1, self.linear_text.1));
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

impl Plain {
    fn new(every: std::time::Duration) -> Self {
        let now = std::time::Instant::now();
        Plain {
            every,
            start: now,
            last: now,
            counts: String::new(),
            first_step: 0,
        }
    }
}

impl nmm::simulation::RunObserver for Progress {
    fn start(&mut self, step: usize, total_steps: usize) {
        self.bar.set_length(total_steps as u64);
        if let Some(p) = self.plain.as_mut() {
            p.first_step = step;
        }
        self.set(step, 0.0);
    }
    fn step_done(&mut self, step: usize, time: f64) {
        self.set(step, time);
    }
    fn counts(&mut self, solves: usize, cuts: usize, changes: usize) {
        self.set_counts(solves, cuts, changes);
    }
    fn linear(&mut self, stats: &nmm::solver::LinearStats) {
        self.set_linear(stats);
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
        let mut p = Progress::with_terminal(10, false);
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
    fn plain_lines_when_not_a_terminal() {
        let mut p = Progress::with_terminal(10, false);
        p.plain = Some(super::Plain::new(std::time::Duration::ZERO));
        p.start(0, 10);
        p.counts(7, 1, 3);
        let line = p.plain_line(4, 0.004).unwrap();
        assert!(
            line.starts_with("progress: step 4/10 (40.0%), t = 0.004 s, "),
            "{line}"
        );
        assert!(
            line.ends_with("; solves 7, cuts 1, active-set changes 3"),
            "{line}"
        );
        let stats = nmm::solver::LinearStats {
            factorisations: 5,
            symbolic_analyses: 2,
            gmres_iterations: 40,
            lu_factorisations: 1,
            ..Default::default()
        };
        p.linear(&stats);
        let line = p.plain_line(5, 0.005).unwrap();
        assert!(
            line.ends_with("; solves 7, cuts 1, active-set changes 3; factorisations 6 (2 symbolic), GMRES iterations 40"),
            "{line}"
        );
        // none at the end, and none before the interval
        assert!(p.plain_line(10, 0.01).is_none());
        p.plain = Some(super::Plain::new(std::time::Duration::from_secs(3600)));
        assert!(p.plain_line(5, 0.005).is_none());
        // --quiet: none at all
        let q = Progress::with_terminal(10, false).quiet(true);
        assert!(q.plain.is_none());
    }

    #[test]
    fn disabled_is_never_drawn() {
        // Whatever stderr is, a disabled bar is not drawn.
        assert!(!Progress::new(5, false).is_drawn());
    }
}
