//! Per-stage wall-clock timing and event counts of the step.

use std::time::{Duration, Instant};

/// Time spent per stage and counts, since creation (or the last [`Counters::reset`]).
#[derive(Clone, Debug, Default)]
pub struct Counters {
    pub neighbours: Duration,
    pub contacts: Duration,
    pub walls: Duration,
    pub bonds: Duration,
    pub integrate: Duration,
    pub steps: u64,
    pub rebuilds: u64,
    pub reorders: u64,
    /// Disc–disc passes that read disc records packed by the previous step's integrator
    /// (steps inside `World::run_while` after the first, without rigid clumps or a rebuild).
    pub packed_by_integrator: u64,
    /// Steps whose parallel bonds were evaluated in the disc–disc pass (`bond::fused`; their
    /// time is then in `contacts`, the bond stage only logs breaks).
    pub bonds_fused: u64,
}

impl Counters {
    pub fn reset(&mut self) {
        *self = Counters::default();
    }

    /// Add the time since `t` to `slot` and return now.
    #[inline]
    pub fn lap(slot: &mut Duration, t: Instant) -> Instant {
        let now = Instant::now();
        *slot += now - t;
        now
    }

    /// Total timed duration.
    pub fn total(&self) -> Duration {
        self.neighbours + self.contacts + self.walls + self.bonds + self.integrate
    }

    /// One line per stage: name, seconds, share.
    pub fn report(&self) -> String {
        let tot = self.total().as_secs_f64().max(1e-300);
        let mut s = String::new();
        for (name, d) in [
            ("neighbours", self.neighbours),
            ("contacts", self.contacts),
            ("walls", self.walls),
            ("bonds", self.bonds),
            ("integrate", self.integrate),
        ] {
            let t = d.as_secs_f64();
            s += &format!("{name:>11}: {t:9.3} s {:5.1} %\n", 100.0 * t / tot);
        }
        s += &format!(
            "steps {} rebuilds {} reorders {} packed by the integrator {} bonds fused {}\n",
            self.steps, self.rebuilds, self.reorders, self.packed_by_integrator, self.bonds_fused
        );
        s
    }
}
