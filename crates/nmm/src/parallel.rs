//! The run's threads: local work (element integrals, contact laws, matrix rows) spread
//! over a rayon pool of a chosen size, its results gathered **in index order**, so that
//! every sum the global scatter then makes is the same whatever the thread count: a run
//! gives the same numbers on 1 thread as on 8, bit for bit. Work split in two fixed parts
//! (the factor's two subtrees, the contact product's two halves) runs on two threads when
//! the pool has them, and in the same order on one.
//!
//! The count is `--threads N` (`threads=` in Python), else the environment's
//! `NMM_THREADS`, else the cores the process may use (`available_parallelism`, which
//! honours CPU affinity and cgroup quotas). With one thread no pool is made and every loop
//! runs inline.

use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The environment variable that sets the default thread count.
pub const THREADS_VAR: &str = "NMM_THREADS";

/// Loops below this many items run inline (a pool's dispatch costs more than they do).
///
/// Measured on the 2-core machine (whole runs, alternated, before the keepers): with 256
/// the arch example (1,000 unknowns, 1,293 elements, up to 319 contacts) took 22.4–22.9 s
/// on two threads against 19.7–21.4 s on one (3 s of system time waking the pool's other
/// thread at every assembly and contact loop); with 2048, 19.3–19.4 s on two and 19.3 s on
/// one. The brick
/// walls are unchanged within noise (20×20: 1.20–1.27 s, 40×40: 6.4–7.1 s, 12 steps):
/// their time is in the factorisation and the triangular solves, which two threads share
/// only for large factors (solver/cholesky.rs: the two parts of a split elimination tree;
/// faer's own parallel supernodal factorisation was slower on two threads than on one on
/// the 40×40 wall's tangent: 34 against 26 ms).
///
/// Lowered to 256 on 2026-12-05, with the keepers ([`KEEP_WARM`], which came later and
/// take the wake-up out of every loop), together with the contacts' split
/// (contact/set.rs `SPLIT_PRODUCT`, 2048 → 256) and the factor's (solver/cholesky.rs
/// `MIN_SPLIT_VALUES`, 131,072 → 8,192 values), each loop in pieces of at least
/// `MIN_PARALLEL / 4` items (`map` too, whose finer splitting by rayon cost more than it
/// shared). Measured on two threads, alternated, against the build before: the 10×10
/// wall 2.32–2.58 → 1.98–2.05 ms a step (medians of 7; one thread 2.36–2.39, as before),
/// the arch example 9.46–9.50 → 8.96–9.02 s, the tunnel 10.75–11.41 → 9.93–10.12 s; the
/// 20×20 and larger walls as before (their loops and factors were split already). The
/// assembly's element loop is split only when 256 elements have unknowns
/// (simulation/mod.rs): the shaking-table slope's 1,153 elements, all but a few in its
/// fixed table, took 1.07 → 1.25 s split (10,000 steps; 1.11 s with that rule).
pub const MIN_PARALLEL: usize = 256;

/// How long a keeper of [`Threads::keep_warm`] waits for a job before it lets its thread
/// sleep. A pool thread that sleeps takes 50–100 µs on this 2-core machine to wake when a
/// job is pushed (measured: `rayon::join` of two 20 µs tasks 25 µs back to back, 56–86 µs
/// after an idle gap of 50 µs to 1 ms; 21 µs at any gap with a keeper), and a Newton
/// iteration of a 20×20 wall has about ten parallel loops of 20–400 µs with serial work
/// between them. Every step asks for keepers (simulation: `Simulation::advance`): the
/// other threads wait actively while a run goes on, as OpenMP's active wait policy does,
/// and sleep again 10 ms after it (or during a longer pause, such as writing outputs). A
/// keeper yields its core between looks (`std::thread::yield_now`): spinning instead made
/// two arch examples run at once on the 2-core machine take 18.3 s against 9.4 s without
/// keepers; yielding, 9.6 against 9.7 s (20×20 wall alone: 11.5 ms a step either way).
/// It is waiting, not work: the user time of a run on two threads is about twice its
/// wall time.
pub const KEEP_WARM: Duration = Duration::from_millis(10);

/// The default thread count: `NMM_THREADS` if set, else the cores the process may use.
/// A malformed `NMM_THREADS` is an error naming it.
pub fn default_threads() -> Result<usize, String> {
    match std::env::var(THREADS_VAR) {
        Ok(v) => parse_threads(&v).map_err(|e| format!("{THREADS_VAR}: {e}")),
        Err(_) => Ok(std::thread::available_parallelism().map_or(1, |n| n.get())),
    }
}

/// A thread count as written by a user: an integer ≥ 1.
pub fn parse_threads(v: &str) -> Result<usize, String> {
    match v.trim().parse::<usize>() {
        Ok(n) if n >= 1 => Ok(n),
        _ => Err(format!("expected an integer ≥ 1, got {v:?}")),
    }
}

/// A handle on the run's threads (cheap to clone).
#[derive(Clone, Default)]
pub struct Threads {
    pool: Option<Arc<rayon::ThreadPool>>,
    /// Keepers of [`Threads::keep_warm`] running.
    keepers: Arc<AtomicUsize>,
}

impl std::fmt::Debug for Threads {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Threads({})", self.count())
    }
}

impl Threads {
    /// `n` threads (1: none besides the caller's).
    pub fn new(n: usize) -> Result<Threads, String> {
        if n <= 1 {
            return Ok(Threads::default());
        }
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .thread_name(|i| format!("nmm-{i}"))
            .build()
            .map_err(|e| format!("cannot start {n} threads: {e}"))?;
        Ok(Threads {
            pool: Some(Arc::new(pool)),
            keepers: Default::default(),
        })
    }

    pub fn count(&self) -> usize {
        self.pool.as_ref().map_or(1, |p| p.current_num_threads())
    }

    /// These threads for a loop of `items` items of work when there are at least `min`,
    /// else the calling thread alone (for a loop whose length overstates its work, or that
    /// is split by hand: below `min` the dispatch costs more than it shares).
    pub fn for_items(&self, items: usize, min: usize) -> Threads {
        match items >= min {
            true => self.clone(),
            false => Threads::default(),
        }
    }

    /// Run `f` on the pool (inline with one thread), so that the parallel loops it makes
    /// are joined by the pool's other threads while its own thread takes part.
    pub fn install<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        match &self.pool {
            Some(p) => p.install(f),
            None => f(),
        }
    }

    /// Keep the pool's other threads looking for work: each runs a keeper that takes the
    /// pool's pending jobs ([`rayon::yield_now`]) and spins between them, until it has
    /// found none for [`KEEP_WARM`] (see there for why). Keepers still running are not
    /// started again: a run that asks at every step starts them once. Nothing with one
    /// thread.
    pub fn keep_warm(&self) {
        let Some(p) = &self.pool else {
            return;
        };
        let creator = rayon::current_thread_index();
        while self.keepers.load(Ordering::Acquire) + 1 < p.current_num_threads() {
            self.keepers.fetch_add(1, Ordering::AcqRel);
            let live = self.keepers.clone();
            p.spawn(move || {
                // a keeper taken up by the thread that asked for it (while it waits in a
                // join) would hold that thread: it ends at once there
                if creator.is_none() || rayon::current_thread_index() != creator {
                    let mut last = Instant::now();
                    loop {
                        match rayon::yield_now() {
                            Some(rayon::Yield::Executed) => last = Instant::now(),
                            _ if last.elapsed() > KEEP_WARM => break,
                            // the core to any other thread that wants it (another run's,
                            // another process's): a keeper must not slow down what shares
                            // the machine with it
                            _ => std::thread::yield_now(),
                        }
                    }
                }
                live.fetch_sub(1, Ordering::AcqRel);
            });
        }
    }

    /// `(a(), b())`: at once on two threads when the run has them, else one after the
    /// other (the work split in two fixed parts: the result does not depend on the thread
    /// count).
    pub fn join<A: Send, B: Send>(
        &self,
        a: impl FnOnce() -> A + Send,
        b: impl FnOnce() -> B + Send,
    ) -> (A, B) {
        match &self.pool {
            Some(p) => p.install(|| active_join(a, b)),
            None => (a(), b()),
        }
    }

    /// `(0..n).map(f)` collected in order, computed on the run's threads.
    pub fn map<T: Send>(&self, n: usize, f: impl Fn(usize) -> T + Sync + Send) -> Vec<T> {
        match &self.pool {
            Some(p) if n >= MIN_PARALLEL => p.install(|| {
                (0..n)
                    .into_par_iter()
                    .with_min_len(MIN_PARALLEL / 4)
                    .map(f)
                    .collect()
            }),
            _ => (0..n).map(f).collect(),
        }
    }

    /// `f(i, &mut out[i])` for every i, on the run's threads (each item written by one
    /// call: the result does not depend on the thread count).
    pub fn for_each_mut<T: Send>(&self, out: &mut [T], f: impl Fn(usize, &mut T) + Sync + Send) {
        match &self.pool {
            Some(p) if out.len() >= MIN_PARALLEL => p.install(|| {
                out.par_iter_mut()
                    .enumerate()
                    .with_min_len(MIN_PARALLEL / 4)
                    .for_each(|(i, x)| f(i, x))
            }),
            _ => out.iter_mut().enumerate().for_each(|(i, x)| f(i, x)),
        }
    }

    /// `f(i, chunk_i)` for every chunk of `stride` items of `out` (the last may be shorter),
    /// on the run's threads (each chunk written by one call: the result does not depend on
    /// the thread count).
    pub fn for_each_chunk_mut<T: Send>(
        &self,
        out: &mut [T],
        stride: usize,
        f: impl Fn(usize, &mut [T]) + Sync + Send,
    ) {
        let n = out.len().div_ceil(stride.max(1));
        match &self.pool {
            Some(p) if n >= MIN_PARALLEL => p.install(|| {
                out.par_chunks_mut(stride)
                    .enumerate()
                    .with_min_len(MIN_PARALLEL / 4)
                    .for_each(|(i, x)| f(i, x))
            }),
            _ => out
                .chunks_mut(stride)
                .enumerate()
                .for_each(|(i, x)| f(i, x)),
        }
    }
}

/// `(a(), b())` on the current pool's threads ([`Threads::join`]): b offered to the other
/// threads (a job of the calling thread's queue, which a keeper takes), a run at once, then
/// the calling thread waits for b **actively**: it runs its own queued jobs (b itself if no
/// other thread took it) and yields its core between looks, as the keepers do. rayon's
/// own `join` lets the waiting thread fall asleep after some 32 looks, and waking it took
/// 50–100 µs on the 2-core machine. Measured (2026-12-05; scratch timers, 12 steps): the
/// joins of a 20×20 wall waited 4.9 ms beyond their longer halves with rayon's `join` (79 of
/// 726 by more than 20 µs; the factor's two parts 37 µs on average), 3.5 ms with this one;
/// per step (alternated, medians of 51 / 101 / 9 pairs of runs) 20×20 9.10 → 8.77 ms, 10×10
/// 1.76 → 1.72, 40×40 48.7 → 49.1 (within noise); the arch example 8.39–8.59 → 8.21–8.36
/// s; two arch examples at once on the 2 cores 11.1–12.3 → 9.9–10.1 s; every output the
/// same bytes. Measured and rejected with it: the parallel loops ([`Threads::map`] and the
/// others) split by hand into halves joined this way instead of rayon's iterators: the
/// 10×10 wall 1.76 → 1.82 ms/step. Only jobs of its own queue: a keeper taken from another
/// queue (one asked for outside the pool) would hold the thread for 10 ms.
fn active_join<A: Send, B: Send>(
    a: impl FnOnce() -> A + Send,
    b: impl FnOnce() -> B + Send,
) -> (A, B) {
    /// Sets its flag when dropped: also when b panics (the scope then passes the panic on).
    struct Done<'a>(&'a AtomicBool);
    impl Drop for Done<'_> {
        fn drop(&mut self) {
            self.0.store(true, Ordering::Release);
        }
    }
    let done = AtomicBool::new(false);
    let mut rb = None;
    let ra = rayon::in_place_scope(|s| {
        let (flag, slot) = (&done, &mut rb);
        s.spawn(move |_| {
            let _done = Done(flag);
            *slot = Some(b());
        });
        let ra = a();
        while !done.load(Ordering::Acquire) {
            match rayon::yield_local() {
                Some(rayon::Yield::Executed) => {}
                _ => std::thread::yield_now(),
            }
        }
        ra
    });
    (ra, rb.expect("the other half ran"))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Joins within joins give the sums a single thread gives, on 2 and on 4 threads, and
    /// a panic in either half reaches the caller (the active wait does not hang on it).
    #[test]
    fn nested_joins_agree_and_a_panic_is_passed_on() {
        fn sum(t: &Threads, v: &[f64]) -> f64 {
            if v.len() <= 8 {
                return v.iter().sum();
            }
            let (a, b) = v.split_at(v.len() / 2);
            let (x, y) = t.join(|| sum(t, a), || sum(t, b));
            x + y
        }
        let v: Vec<f64> = (0..1000).map(|i| (i as f64).sin()).collect();
        let one = sum(&Threads::new(1).unwrap(), &v);
        for n in [2, 4] {
            let t = Threads::new(n).unwrap();
            t.keep_warm();
            let s = t.install(|| sum(&t, &v));
            assert_eq!(s.to_bits(), one.to_bits(), "{n} threads");
            for first in [true, false] {
                let r = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
                    t.install(|| t.join(|| assert!(!first, "half a"), || assert!(first, "half b")))
                }));
                assert!(r.is_err(), "{n} threads, first {first}");
            }
        }
    }

    #[test]
    fn results_are_in_order_whatever_the_thread_count() {
        let f = |i: usize| (i as f64).sqrt().sin();
        let one = Threads::new(1).unwrap().map(5000, f);
        let four = Threads::new(4).unwrap();
        assert_eq!(four.count(), 4);
        assert_eq!(one, four.map(5000, f));
        let mut a = vec![0.0; 3000];
        let mut b = vec![0.0; 3000];
        Threads::new(1)
            .unwrap()
            .for_each_mut(&mut a, |i, x| *x = f(i));
        four.for_each_mut(&mut b, |i, x| *x = f(i));
        assert_eq!(a, b);
        let (mut c, mut d) = (vec![0.0; 3000], vec![0.0; 3000]);
        let g = |i: usize, x: &mut [f64]| {
            x.iter_mut()
                .enumerate()
                .for_each(|(j, y)| *y = f(3 * i + j))
        };
        Threads::new(1).unwrap().for_each_chunk_mut(&mut c, 3, g);
        four.for_each_chunk_mut(&mut d, 3, g);
        assert_eq!(c, a);
        assert_eq!(d, a);
        // a loop with too little work runs on the calling thread alone
        assert_eq!(four.for_items(255, 256).count(), 1);
        assert_eq!(four.for_items(256, 256).count(), 4);
    }

    #[test]
    fn thread_counts_are_checked() {
        assert_eq!(parse_threads(" 3 "), Ok(3));
        assert!(parse_threads("0").is_err());
        assert!(parse_threads("two").is_err());
    }
}
