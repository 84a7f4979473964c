//! A team of spinning workers for the step's parallel stages ([`run`]).
//!
//! Each parallel stage of a step (the disc–disc pass, the bond stage, the integrator) is one
//! fork-join region of a few hundred microseconds or less. With rayon, the other workers go
//! to sleep between regions and are woken through the kernel; on the 2-vCPU development VM
//! that cost 10–45 µs more per region than spinning workers (measured: two threads sweeping
//! their own halves of an array, regions of 110–150 µs, 0.93–1.79x over one thread with a
//! rayon `broadcast` per region against 1.15–1.95x with a spinning helper, 4 runs;
//! docs/performance.md, ninth round). Here
//! the calling thread runs part 0 itself and `T − 1` helper threads, kept per calling thread,
//! run the others; between regions the helpers spin on a generation counter for up to
//! `SPIN` before parking (so an idle world costs no CPU), and the caller spins until they
//! are done.
//!
//! `T` is `rayon::current_num_threads()` at the call (at most the cores there are, see
//! [`workers`]), so a world stepped inside a rayon pool of T threads uses T threads, as
//! before; with one thread there are no helpers and `run` calls the parts in turn. Which
//! worker runs which part does not change any result: the stages give each part fixed data
//! (ranges of discs or bonds) and combine the parts in a fixed order, so results are
//! bit-identical for any thread count.

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering::*};
use std::sync::{Arc, Condvar, Mutex};
use std::time::{Duration, Instant};

/// How long an idle helper spins before parking.
const SPIN: Duration = Duration::from_micros(200);

/// Run `f(p)` for every part `p` in `0..parts` on the calling thread's team and return when
/// all are done: part 0 on the caller itself, part `w` below the team size always on helper
/// `w`, any further parts on whichever worker is free. A panic in any part is raised again
/// here, after every part has finished.
pub fn run(parts: usize, f: &(dyn Fn(usize) + Sync)) {
    let threads = workers();
    // (On a helper: a call from inside a part runs its parts here, in turn.)
    if parts <= 1 || threads == 1 || HELPER.with(|h| h.get()) {
        (0..parts).for_each(f);
        return;
    }
    TEAM.with(|t| {
        // A call from inside a part on this thread finds its team busy: the same.
        let Ok(mut t) = t.try_borrow_mut() else {
            (0..parts).for_each(f);
            return;
        };
        if t.as_ref().is_none_or(|t| t.size() != threads) {
            // (Dropping the old team stops its helpers.)
            *t = Some(Team::new(threads));
        }
        t.as_ref().expect("made above").run(parts, f)
    })
}

/// The thread counts a step works with, read once at its start (the world's step workspace
/// holds them): `ranges`, the rayon pool's size, into which the parallel passes cut their
/// work; `workers`, the team's size ([`workers`]). Results do not depend on either.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Threads {
    pub ranges: usize,
    pub workers: usize,
}

impl Threads {
    /// The counts of the calling thread's rayon pool.
    pub fn current() -> Threads {
        Threads {
            ranges: rayon::current_num_threads(),
            workers: workers(),
        }
    }
}

impl Default for Threads {
    fn default() -> Threads {
        Threads {
            ranges: 1,
            workers: 1,
        }
    }
}

/// The team size for the current rayon thread count: that count, but at most the cores
/// the process may use (more spinning threads than cores would take the cores from the
/// workers that have work; the parts are then shared among fewer workers, which changes
/// no result).
pub fn workers() -> usize {
    static CORES: std::sync::OnceLock<usize> = std::sync::OnceLock::new();
    let cores = *CORES.get_or_init(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    rayon::current_num_threads().clamp(1, cores.max(1))
}

thread_local! {
    /// Whether this thread is a team helper.
    static HELPER: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
    /// The team of the threads that step worlds (made on first use, resized with the rayon
    /// thread count).
    static TEAM: std::cell::RefCell<Option<Team>> = const { std::cell::RefCell::new(None) };
}

/// The job the helpers run: a type-erased `&dyn Fn(usize) + Sync` valid while
/// [`Team::run`] waits.
#[derive(Clone, Copy)]
struct Job {
    f: *const (dyn Fn(usize) + Sync + 'static),
    parts: usize,
}
// SAFETY: the closure is `Sync` and outlives every use (see `Team::run`).
unsafe impl Send for Job {}

struct Shared {
    /// The number of the latest job (bumped once more at shutdown), polled by idle helpers.
    generation: AtomicUsize,
    /// The latest job and its number (read together: a helper that had no part in a job and
    /// looks only after the next one is published must see the next one's number).
    job: Mutex<(usize, Option<Job>)>,
    /// Next part to take (parts beyond the team size) and parts finished.
    next: AtomicUsize,
    done: AtomicUsize,
    panicked: AtomicBool,
    shutdown: AtomicBool,
    /// Helpers parked (or about to) on `wake`.
    sleeping: AtomicUsize,
    park: Mutex<()>,
    wake: Condvar,
    /// Tests: helpers pause between seeing a job and reading it.
    #[cfg(test)]
    slow: AtomicBool,
}

struct Team {
    shared: Arc<Shared>,
    helpers: Vec<std::thread::JoinHandle<()>>,
}

impl Team {
    fn new(size: usize) -> Team {
        let shared = Arc::new(Shared {
            generation: AtomicUsize::new(0),
            job: Mutex::new((0, None)),
            next: AtomicUsize::new(0),
            done: AtomicUsize::new(0),
            panicked: AtomicBool::new(false),
            shutdown: AtomicBool::new(false),
            sleeping: AtomicUsize::new(0),
            park: Mutex::new(()),
            wake: Condvar::new(),
            #[cfg(test)]
            slow: AtomicBool::new(false),
        });
        let mut helpers = Vec::new();
        for w in 1..size {
            let s = Arc::clone(&shared);
            let h = std::thread::Builder::new()
                .name(format!("dem-team-{w}"))
                .spawn(move || helper(&s, w));
            match h {
                Ok(h) => helpers.push(h),
                // No more threads: the parts are taken by the workers there are.
                Err(_) => break,
            }
        }
        Team { shared, helpers }
    }

    /// Workers: the caller and its helpers.
    fn size(&self) -> usize {
        1 + self.helpers.len()
    }

    fn run(&self, parts: usize, f: &(dyn Fn(usize) + Sync)) {
        let s = &*self.shared;
        // SAFETY: the `'static` lifetime is a lie the helpers never act on: this function
        // returns (or panics) only after every part is counted done, and no helper touches
        // the job after counting its last part.
        let f_static: &'static (dyn Fn(usize) + Sync) = unsafe { std::mem::transmute(f) };
        let number = {
            let mut j = s.job.lock().unwrap_or_else(|e| e.into_inner());
            j.0 += 1;
            j.1 = Some(Job { f: f_static, parts });
            j.0
        };
        s.next.store(self.size(), Relaxed);
        s.done.store(0, Relaxed);
        s.panicked.store(false, Relaxed);
        s.generation.store(number, SeqCst);
        if s.sleeping.load(SeqCst) > 0 {
            let _g = s.park.lock().unwrap_or_else(|e| e.into_inner());
            s.wake.notify_all();
        }
        // Part 0 here, then any parts beyond the team size. A panic is caught (and raised
        // again below) so that this thread still waits for the helpers' parts.
        run_parts(s, f, 0, parts);
        let mut k = 0u32;
        while s.done.load(Acquire) < parts {
            k = k.wrapping_add(1);
            if k.is_multiple_of(1024) {
                std::thread::yield_now();
            } else {
                std::hint::spin_loop();
            }
        }
        if s.panicked.load(Acquire) {
            panic!("a part of a parallel stage panicked");
        }
    }
}

/// Run part `first` and then the parts taken from `next` until none is left, each counted
/// done after the next one is claimed (so that a finished worker never touches `next` once
/// the caller may have moved on to another job).
fn run_parts(s: &Shared, f: &(dyn Fn(usize) + Sync), first: usize, parts: usize) {
    let mut p = first;
    while p < parts {
        if catch_unwind(AssertUnwindSafe(|| f(p))).is_err() {
            s.panicked.store(true, Release);
        }
        let q = s.next.fetch_add(1, Relaxed);
        s.done.fetch_add(1, Release);
        p = q;
    }
}

impl Drop for Team {
    fn drop(&mut self) {
        let s = &*self.shared;
        s.shutdown.store(true, SeqCst);
        s.generation.fetch_add(1, SeqCst);
        {
            let _g = s.park.lock().unwrap_or_else(|e| e.into_inner());
            s.wake.notify_all();
        }
        for h in self.helpers.drain(..) {
            let _ = h.join();
        }
    }
}

/// Helper `w`: wait for a job (spin, then park), run part `w` and any parts left beyond the
/// team size, count them done.
fn helper(s: &Shared, w: usize) {
    HELPER.with(|h| h.set(true));
    let mut seen = 0;
    loop {
        let t0 = Instant::now();
        let mut k = 0u32;
        loop {
            if s.generation.load(Acquire) != seen {
                break;
            }
            k = k.wrapping_add(1);
            if !k.is_multiple_of(64) || t0.elapsed() < SPIN {
                std::hint::spin_loop();
                continue;
            }
            // Park: announce it, then re-check under the lock (the caller bumps the
            // generation before reading `sleeping`, so one of the two sees the other).
            let mut g = s.park.lock().unwrap_or_else(|e| e.into_inner());
            s.sleeping.fetch_add(1, SeqCst);
            while s.generation.load(SeqCst) == seen {
                g = s.wake.wait(g).unwrap_or_else(|e| e.into_inner());
            }
            s.sleeping.fetch_sub(1, SeqCst);
        }
        if s.shutdown.load(Acquire) {
            return;
        }
        #[cfg(test)]
        if s.slow.load(Relaxed) {
            // Widen the window between seeing a new job and reading it (test of the race).
            std::thread::sleep(Duration::from_micros(300));
        }
        let (number, job) = *s.job.lock().unwrap_or_else(|e| e.into_inner());
        seen = number;
        if let Some(job) = job {
            // SAFETY: the caller waits in `Team::run` until every part below `job.parts` is
            // counted done; with no part here (w >= parts) `f` is not called.
            let f = unsafe { &*job.f };
            run_parts(s, f, w, job.parts);
        }
    }
}

/// A raw pointer to an array that the parts of a team job share, each touching its own
/// disjoint indices (the disc–disc pass's and the bond stage's ranges, the integrator's
/// chunks).
pub(crate) struct SyncPtr<T>(*mut T);
impl<T> Clone for SyncPtr<T> {
    fn clone(&self) -> Self {
        *self
    }
}
impl<T> Copy for SyncPtr<T> {}
unsafe impl<T> Send for SyncPtr<T> {}
unsafe impl<T> Sync for SyncPtr<T> {}

impl<T> SyncPtr<T> {
    pub(crate) fn of(v: &mut [T]) -> SyncPtr<T> {
        SyncPtr(v.as_mut_ptr())
    }

    /// The pointer (a method, so that closures capture the whole `SyncPtr`).
    pub(crate) fn ptr(self) -> *mut T {
        self.0
    }

    /// # Safety
    /// `[a, a + len)` must be in bounds of the array and not aliased by any live reference.
    pub(crate) unsafe fn slice<'a>(self, a: usize, len: usize) -> &'a mut [T] {
        if len == 0 {
            return &mut [];
        }
        std::slice::from_raw_parts_mut(self.0.add(a), len)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Whether `go`, given a part function, ran every part of `0..parts` exactly once.
    fn each_part_once(parts: usize, go: impl FnOnce(&(dyn Fn(usize) + Sync))) -> bool {
        let hits: Vec<AtomicUsize> = (0..parts).map(|_| AtomicUsize::new(0)).collect();
        go(&|p| {
            hits[p].fetch_add(1, Relaxed);
        });
        hits.iter().all(|h| h.load(Relaxed) == 1)
    }

    fn pool(t: usize) -> rayon::ThreadPool {
        rayon::ThreadPoolBuilder::new()
            .num_threads(t)
            .build()
            .unwrap()
    }

    #[test]
    fn every_part_runs_once_for_any_part_and_thread_count() {
        for t in 1..=4 {
            pool(t).install(|| {
                for parts in [0, 1, 2, 3, 4, 7, 64] {
                    for _ in 0..50 {
                        let once = each_part_once(parts, |f| run(parts, f));
                        assert!(once, "{t} threads, {parts} parts");
                    }
                }
            });
        }
    }

    #[test]
    fn with_one_part_per_worker_part_w_runs_on_one_thread_at_every_call() {
        pool(3).install(|| {
            let n = workers();
            let first: Vec<Mutex<Option<std::thread::ThreadId>>> =
                (0..n).map(|_| Mutex::new(None)).collect();
            for _ in 0..100 {
                run(n, &|p| {
                    let me = std::thread::current().id();
                    let mut f = first[p].lock().unwrap();
                    assert_eq!(*f.get_or_insert(me), me, "part {p} moved");
                });
            }
        });
    }

    #[test]
    fn helpers_without_a_part_never_run_one_later() {
        // A team of 4 (more than this machine may have cores) with jobs of 2-5 parts in turn,
        // helpers slowed between seeing a job and reading it: a helper with no part in one
        // job that reads only after the next is published must run its part of the next one
        // exactly once.
        let team = Team::new(4);
        team.shared.slow.store(true, Relaxed);
        for round in 0..400 {
            let parts = 2 + round % 4;
            let once = each_part_once(parts, |f| team.run(parts, f));
            assert!(once, "round {round}, {parts} parts");
        }
    }

    #[test]
    fn a_nested_call_runs_its_parts_in_turn() {
        pool(2).install(|| {
            let n = AtomicUsize::new(0);
            run(2, &|_| {
                run(3, &|_| {
                    n.fetch_add(1, Relaxed);
                });
            });
            assert_eq!(n.load(Relaxed), 6);
        });
    }

    #[test]
    fn helpers_park_when_idle_and_wake_for_the_next_job() {
        pool(2).install(|| {
            let n = AtomicUsize::new(0);
            run(2, &|_| {
                n.fetch_add(1, Relaxed);
            });
            std::thread::sleep(SPIN * 5);
            run(2, &|_| {
                n.fetch_add(1, Relaxed);
            });
            assert_eq!(n.load(Relaxed), 4);
        });
    }

    #[test]
    fn a_panic_on_a_helper_reaches_the_caller_after_all_parts() {
        pool(2).install(|| {
            let done = AtomicUsize::new(0);
            let r = catch_unwind(AssertUnwindSafe(|| {
                run(4, &|p| {
                    done.fetch_add(1, Relaxed);
                    if p == 1 {
                        panic!("part 1");
                    }
                })
            }));
            assert!(r.is_err());
            assert_eq!(done.load(Relaxed), 4);
            // The team still works afterwards.
            let n = AtomicUsize::new(0);
            run(2, &|_| {
                n.fetch_add(1, Relaxed);
            });
            assert_eq!(n.load(Relaxed), 2);
        });
    }
}
