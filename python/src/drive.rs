//! Running long work off the calling thread: the work runs on a scoped thread inside a rayon
//! pool of the asked size; the calling thread waits with the GIL released, wakes every
//! [`POLL`](crate::POLL) to check for Ctrl-C (only the main thread sees signals), and runs the
//! user's callback when the work asks ([`Ctl::ask`]). A stop (Ctrl-C, a callback's
//! exception, a callback returning False where that ends the work) sets a flag the work
//! checks at its progress cadence ([`Ctl::check`]): it then unwinds out of the library call
//! (no panic message: `resume_unwind`), dropping the run as a killed `dem` would leave it
//! (the files written so far, its checkpoints to resume from).

use pyo3::prelude::*;
use std::panic::AssertUnwindSafe;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::{Arc, Mutex};

/// What the work tells the callback.
pub enum Msg {
    /// A specimen generation stage and its completion in [0, 1].
    Stage(String, f64),
    /// Steps done of the total.
    Progress(u64, u64),
    /// The state (a copy) at a callback step of a scene run.
    State(Box<dem_core::state::State>),
}

/// The callback's answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reply {
    Go,
    Stop,
}

/// The unwinding payload of a stopped work.
struct Cancelled;

/// The work's side of the link.
#[derive(Clone)]
pub struct Ctl {
    tx: mpsc::Sender<(Msg, mpsc::Sender<Reply>)>,
    cancel: Arc<AtomicBool>,
    user_stop: Arc<AtomicBool>,
}

impl Ctl {
    /// Unwinds out of the work when it was asked to stop.
    pub fn check(&self) {
        if self.cancel.load(Ordering::Relaxed) {
            std::panic::resume_unwind(Box::new(Cancelled));
        }
    }

    /// Asks the callback (on the calling thread) and waits for its answer.
    pub fn ask(&self, m: Msg) -> Reply {
        let (rtx, rrx) = mpsc::channel();
        if self.tx.send((m, rtx)).is_err() {
            return Reply::Go;
        }
        let r = rrx.recv().unwrap_or(Reply::Go);
        self.check();
        r
    }

    /// Stops the work as the user asked (the callback returned False): `DemStopped`.
    pub fn stop(&self) -> ! {
        self.user_stop.store(true, Ordering::Relaxed);
        self.cancel.store(true, Ordering::Relaxed);
        std::panic::resume_unwind(Box::new(Cancelled));
    }
}

/// Runs `work` on `threads` threads (None or 0: all cores) with the GIL released, `handle`
/// answering its messages on this thread.
pub fn drive<T: Send>(
    py: Python<'_>,
    threads: Option<usize>,
    work: impl FnOnce(&Ctl) -> T + Send,
    mut handle: impl FnMut(Python<'_>, Msg) -> PyResult<Reply>,
) -> PyResult<T> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.unwrap_or(0))
        .build()
        .map_err(|e| crate::msg_err(e.to_string()))?;
    let (tx, rx) = mpsc::channel();
    let ctl = Ctl {
        tx,
        cancel: Arc::new(AtomicBool::new(false)),
        user_stop: Arc::new(AtomicBool::new(false)),
    };
    let (cancel, user_stop) = (ctl.cancel.clone(), ctl.user_stop.clone());
    let rx = Mutex::new(rx);
    let mut pending: Option<PyErr> = None;
    let joined = std::thread::scope(|sc| {
        let h = sc.spawn(move || {
            let r = std::panic::catch_unwind(AssertUnwindSafe(|| pool.install(|| work(&ctl))));
            drop(ctl);
            r
        });
        loop {
            let got = py.allow_threads(|| rx.lock().expect("receiver").recv_timeout(crate::POLL));
            match got {
                Ok((m, reply)) => {
                    let r = match pending {
                        Some(_) => Reply::Go,
                        None => handle(py, m).unwrap_or_else(|e| {
                            pending = Some(e);
                            cancel.store(true, Ordering::Relaxed);
                            Reply::Go
                        }),
                    };
                    let _ = reply.send(r);
                    // (Messages may come faster than the poll: Ctrl-C is checked here too.)
                    if let Err(e) = py.check_signals() {
                        pending.get_or_insert(e);
                        cancel.store(true, Ordering::Relaxed);
                    }
                }
                Err(RecvTimeoutError::Timeout) => {
                    if let Err(e) = py.check_signals() {
                        pending.get_or_insert(e);
                        cancel.store(true, Ordering::Relaxed);
                    }
                }
                Err(RecvTimeoutError::Disconnected) => break,
            }
        }
        py.allow_threads(move || h.join())
    });
    let r = match joined {
        Ok(r) => r,
        Err(p) => std::panic::resume_unwind(p),
    };
    match r {
        Ok(v) => match pending {
            Some(e) => Err(e),
            None => Ok(v),
        },
        Err(p) if p.is::<Cancelled>() => Err(match pending {
            Some(e) => e,
            None if user_stop.load(Ordering::Relaxed) => crate::exc(
                py,
                "DemStopped",
                "stopped by the callback (run it again into the same folder to continue from \
                 its last checkpoint)"
                    .to_string(),
            ),
            None => pyo3::exceptions::PyKeyboardInterrupt::new_err("stopped"),
        }),
        Err(p) => std::panic::resume_unwind(p),
    }
}
