//! A step against one numeric factorisation of its own tangent, on the scaling study's walls.
//!
//! ```sh
//! cargo run --release --example factor_ratio -- --walls 10,20,30,40
//! cargo run --release --example factor_ratio -- --walls 20 --threads 1 --reps 5
//! ```
//!
//! For each wall (the scaling study's: `nmm::generate::brick_wall_model` with the peer's
//! settings, dynamic, Δt 1 ms, cover 0.2 m) it runs steps 1 … `--steps` twice in one
//! process, on the same threads:
//! 1. timed: the wall-clock time of each `Simulation::advance` from step `--from` on (the
//!    whole step: detection, assembly, every Newton iteration's contact passes,
//!    factorisations and solves, the commit), with the solver's counts;
//! 2. recorded: the same run (bit for bit: recording changes nothing) with a linear
//!    solver that keeps the tangent of each step's first Newton iterate — the matrix
//!    whose factorisation starts the step — as it is about to be factorised.
//!
//! Then each recorded tangent is factorised alone on its own symbolic analysis, `--reps`
//! times from scratch (no factor held: every supernode computed), as the solver factorises
//! it (the LU without pivoting of the whole tangent when 8 or more contacts slide, else the
//! Cholesky factor of its symmetric part), and the step is compared with the median.
//! Prints one line per wall: ms per step, ms per factorisation alone, their ratio (the
//! acceptance asks ≤ 2), and the solver's factorisations and linear solves per step.

use clap::Parser;
use nmm::generate::{brick_wall_model, WallOptions};
use nmm::model::parse_model;
use nmm::parallel::{default_threads, Threads};
use nmm::simulation::Simulation;
use nmm::solver::{
    Cholesky, LinearSolver, LinearStats, SolveError, SparseMatrix, TangentOperator, TangentSolver,
    MIN_LU_PIECES,
};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

#[derive(Parser)]
#[command(about = "A step's cost against one numeric factorisation of its tangent")]
struct Args {
    /// Walls: N (N×N bricks), comma-separated.
    #[arg(long, default_value = "10,20,30,40")]
    walls: String,
    /// Threads (default: the cores the process may use, or NMM_THREADS).
    #[arg(long)]
    threads: Option<usize>,
    /// Steps run.
    #[arg(long, default_value_t = 12)]
    steps: usize,
    /// First step timed and recorded (the steps before it settle the first contacts, as
    /// the scaling study's difference T(12) − T(2) leaves them out).
    #[arg(long, default_value_t = 3)]
    from: usize,
    /// Factorisations of each recorded tangent (median taken).
    #[arg(long, default_value_t = 5)]
    reps: usize,
}

/// A recorded tangent and how the solver factorises it.
struct Recorded {
    matrix: SparseMatrix,
    lu: bool,
}

/// The [`TangentSolver`], keeping the tangent of the first solve after each invalidation
/// (the first Newton iterate of a step) while `armed`.
struct Recorder {
    inner: TangentSolver,
    fresh: bool,
    armed: Arc<Mutex<bool>>,
    kept: Arc<Mutex<Vec<Recorded>>>,
}

impl LinearSolver for Recorder {
    fn solve(
        &mut self,
        op: &mut dyn TangentOperator,
        rhs: &[f64],
        x: &mut [f64],
        rtol: f64,
    ) -> Result<(), SolveError> {
        if self.fresh && *self.armed.lock().expect("flag") {
            let pattern = op.pattern();
            let mut values = vec![0.0; pattern.nnz()];
            op.assemble(&mut values, false);
            let lu = op.unsymmetric_pieces() >= MIN_LU_PIECES;
            let matrix = SparseMatrix { pattern, values };
            self.kept
                .lock()
                .expect("list")
                .push(Recorded { matrix, lu });
        }
        self.fresh = false;
        self.inner.solve(op, rhs, x, rtol)
    }

    fn invalidate(&mut self) {
        self.fresh = true;
        self.inner.invalidate();
    }

    fn loose_solves_pay(&self, op: &dyn TangentOperator) -> bool {
        self.inner.loose_solves_pay(op)
    }

    fn stats(&self) -> LinearStats {
        self.inner.stats()
    }

    fn factor_len(&self) -> usize {
        self.inner.factor_len()
    }
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    match v.len() {
        0 => f64::NAN,
        n if n % 2 == 1 => v[n / 2],
        n => 0.5 * (v[n / 2 - 1] + v[n / 2]),
    }
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

fn simulation(n: usize, steps: usize, threads: &Threads) -> Result<Simulation, String> {
    let text = brick_wall_model(&WallOptions {
        steps,
        ..WallOptions::new(n, n)
    });
    let model = parse_model(&text, std::path::Path::new(".")).map_err(|e| e.to_string())?;
    let mut sim = Simulation::new(model)?;
    sim.set_threads(threads.clone());
    Ok(sim)
}

/// One numeric factorisation of `r` from scratch, `reps` times (the symbolic analysis
/// made once before): the median time.
fn factorise_alone(r: &Recorded, reps: usize, threads: &Threads) -> Result<f64, String> {
    let mut chol = Cholesky::default();
    let once = |chol: &mut Cholesky| match r.lu {
        true => chol.factorize_lu_on(&r.matrix, threads),
        false => chol.factorize_on(&r.matrix, threads),
    };
    once(&mut chol).map_err(|e| e.to_string())?;
    let mut times = Vec::with_capacity(reps);
    for _ in 0..reps {
        chol.invalidate();
        let t = Instant::now();
        once(&mut chol).map_err(|e| e.to_string())?;
        times.push(ms(t.elapsed()));
    }
    Ok(median(times))
}

fn wall(n: usize, a: &Args, threads: &Threads) -> Result<(), String> {
    let timed_steps = a.steps + 1 - a.from;
    // 1. timed
    let mut sim = simulation(n, a.steps, threads)?;
    let mut step_ms = Vec::new();
    let mut counts = LinearStats::default();
    for k in 1..=a.steps {
        let t = Instant::now();
        let rep = sim
            .advance()
            .map_err(|e| format!("{n}×{n} wall, step {k}: {e}"))?;
        if k >= a.from {
            step_ms.push(ms(t.elapsed()));
            counts += rep.linear;
        }
    }
    // 2. recorded
    let armed = Arc::new(Mutex::new(false));
    let kept = Arc::new(Mutex::new(Vec::new()));
    let mut sim = simulation(n, a.steps, threads)?;
    sim.set_linear_solver(Box::new(Recorder {
        inner: TangentSolver::default(),
        fresh: false,
        armed: armed.clone(),
        kept: kept.clone(),
    }));
    for k in 1..=a.steps {
        *armed.lock().expect("flag") = k >= a.from;
        sim.advance()
            .map_err(|e| format!("{n}×{n} wall, step {k}: {e}"))?;
    }
    let recorded = std::mem::take(&mut *kept.lock().expect("list"));
    let mut factor_ms = Vec::with_capacity(recorded.len());
    for r in &recorded {
        factor_ms.push(factorise_alone(r, a.reps, threads)?);
    }
    let lu = recorded.iter().filter(|r| r.lu).count();
    let (step, factor) = (median(step_ms.clone()), median(factor_ms));
    let per = |c: usize| c as f64 / timed_steps as f64;
    println!(
        "{:>7} {:>9} {:>10.3} {:>10.3} {:>9.3} {:>7.2} {:>11.2} {:>12.2} {:>10.3} {:>5}/{}",
        format!("{n}×{n}"),
        sim.n_dofs(),
        step,
        step_ms.iter().sum::<f64>() / step_ms.len() as f64,
        factor,
        step / factor,
        per(counts.factorisations),
        per(counts.solves),
        ms(counts.factorisation_time) / timed_steps as f64,
        lu,
        recorded.len(),
    );
    Ok(())
}

fn main() -> std::process::ExitCode {
    let a = Args::parse();
    let n_threads = match a.threads.map_or_else(default_threads, Ok) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {e}");
            return std::process::ExitCode::from(2);
        }
    };
    let threads = match Threads::new(n_threads) {
        Ok(t) => t,
        Err(e) => {
            eprintln!("error: {e}");
            return std::process::ExitCode::from(2);
        }
    };
    if a.from < 1 || a.from > a.steps || a.reps == 0 {
        eprintln!("error: need 1 ≤ --from ≤ --steps and --reps ≥ 1");
        return std::process::ExitCode::from(2);
    }
    println!(
        "# {} thread(s); steps {}…{}; ms per step (median, mean), one numeric factorisation of \
         the step's first tangent alone (median), step / factorisation, and per step the \
         solver's factorisations, linear solves and factorisation ms; LU tangents / recorded",
        threads.count(),
        a.from,
        a.steps
    );
    println!(
        "{:>7} {:>9} {:>10} {:>10} {:>9} {:>7} {:>11} {:>12} {:>10} {:>7}",
        "wall",
        "unknowns",
        "step_ms",
        "step_mean",
        "factor_ms",
        "ratio",
        "factor/step",
        "solves/step",
        "fact_ms/st",
        "LU"
    );
    let mut status = std::process::ExitCode::SUCCESS;
    for w in a.walls.split(',').filter(|s| !s.trim().is_empty()) {
        let r = match w.trim().parse::<usize>() {
            // on the run's threads, as `nmm run` computes (its thread takes part in the
            // parallel loops instead of waiting for the pool's)
            Ok(n) if n >= 1 => threads.install(|| wall(n, &a, &threads)),
            _ => Err(format!("--walls: `{w}` is not a number of bricks ≥ 1")),
        };
        if let Err(e) = r {
            eprintln!("error: {e}");
            status = std::process::ExitCode::FAILURE;
        }
    }
    status
}
