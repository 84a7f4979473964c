//! In-memory benchmark scenes.
//!
//! [`dense_lattice_scene`] is the peer benchmark `shared/bench/lammps-dense2d.in` rebuilt
//! exactly: LAMMPS `lattice hex 0.001` in 2D (unit cell a × √3a with atoms at (0, 0) and
//! (a/2, √3a/2)), `region block 0 200 0 115` → 200 × 115 cells, 46,000 discs; diameter
//! 1.002 mm; periodic in x and y; `displace_atoms random 1e-6 1e-6` (uniform in ±1 µm; our own
//! deterministic generator, LAMMPS's random stream is not reproduced); `gran/hooke/history
//! 1e5 NULL 100 NULL 0.5 1`: k_n = 1e5 N/m, k_t = 2/7 k_n (LAMMPS default for NULL),
//! F_n damping m*·γ_n·v_n with γ_n = 100 1/s, γ_t = γ_n/2 (NULL), μ = 0.5; dt = 1 µs; skin
//! 0.1 mm. Masses: LAMMPS (29 Sep 2021) `set density` gives a finite-size particle the mass of
//! a sphere, ρ·(4/3)πr³, even in 2D (checked with the installed `lmp`: 1.3168666e-6 kg for
//! r = 0.501 mm, ρ = 2500), while `fix nve/sphere disc` uses I = m r²/2. A disc of thickness
//! t = (4/3) r has the same mass and inertia, so the scene uses that thickness.

use crate::contact::{LinearSpringDashpot, NormalDamping};
use crate::{ContactLaws, ContactModel, Params, State, World};
use clumpgen::synth::SplitMix64;
use std::time::Instant;

/// Lattice constant (m), cells in x and y, disc diameter (m) of the LAMMPS benchmark.
pub const LATTICE: f64 = 1e-3;
pub const CELLS: (usize, usize) = (200, 115);
pub const DIAMETER: f64 = 1.002e-3;

/// The dense periodic hex-lattice scene of `lammps-dense2d.in` (46,000 discs).
pub fn dense_lattice_scene() -> World {
    let a = LATTICE;
    let h = 3f64.sqrt() * a;
    let (nx, ny) = CELLS;
    let r = 0.5 * DIAMETER;
    let rho = 2500.0;
    let mut st = State {
        thickness: 4.0 / 3.0 * r,
        ..State::default()
    };
    st.periodic.lo = [0.0, 0.0];
    st.periodic.length = [Some(nx as f64 * a), Some(ny as f64 * h)];
    let mut rng = SplitMix64::new(123);
    for j in 0..ny {
        for i in 0..nx {
            for (bx, by) in [(0.0, 0.0), (0.5, 0.5)] {
                let x = (i as f64 + bx) * a + rng.range(-1e-6, 1e-6);
                let y = (j as f64 + by) * h + rng.range(-1e-6, 1e-6);
                let t = st.thickness;
                st.discs.push_uniform(x, y, r, rho, t, 0);
            }
        }
    }
    let law = LinearSpringDashpot {
        kn: 1e5,
        ks: 2.0 / 7.0 * 1e5,
        damping: NormalDamping::Gamma(100.0),
        shear_damping: 0.5,
        mu: 0.5,
    };
    let params = Params {
        dt_fixed: Some(1e-6),
        skin: Some(1e-4),
        track_energy: false,
        ..Params::default()
    };
    World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)))
}

/// Run `steps` steps of `world` on `threads` threads (after one warm-up step) and return
/// particle-steps per second (discs × steps / wall time).
pub fn run_bench(mut world: World, steps: u64, threads: usize) -> f64 {
    run_bench_on(&mut world, steps, threads)
}

/// As [`run_bench`], leaving the world (and its stage counters) to the caller.
pub fn run_bench_on(world: &mut World, steps: u64, threads: usize) -> f64 {
    run_bench_timed(world, steps, threads).wall
}

/// Particle-steps per second of a benchmark run, by wall time and by CPU time.
#[derive(Clone, Copy, Debug)]
pub struct BenchRate {
    /// discs × steps / wall time.
    pub wall: f64,
    /// discs × steps / CPU time of all threads of the process (Linux only; `None` elsewhere).
    /// On a machine shared with other jobs this varies less than the wall figure.
    pub cpu: Option<f64>,
}

/// CPU time (s) used so far by all threads of this process, from
/// `/proc/self/task/*/schedstat` (nanoseconds on CPU); `None` when unavailable.
pub fn process_cpu_seconds() -> Option<f64> {
    let mut ns: u64 = 0;
    for e in std::fs::read_dir("/proc/self/task").ok()? {
        let p = e.ok()?.path().join("schedstat");
        let s = std::fs::read_to_string(p).ok()?;
        ns += s.split_whitespace().next()?.parse::<u64>().ok()?;
    }
    Some(ns as f64 * 1e-9)
}

/// As [`run_bench_on`], reporting the CPU-time rate as well.
pub fn run_bench_timed(world: &mut World, steps: u64, threads: usize) -> BenchRate {
    let mut go = || {
        world.step();
        world.counters.reset();
        let c0 = process_cpu_seconds();
        let t = Instant::now();
        world.run(steps);
        let s = t.elapsed().as_secs_f64();
        let c1 = process_cpu_seconds();
        let work = world.state.discs.len() as f64 * steps as f64;
        BenchRate {
            wall: work / s,
            cpu: c0.zip(c1).map(|(a, b)| work / (b - a).max(1e-9)),
        }
    };
    match rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
    {
        Ok(pool) => pool.install(go),
        Err(_) => go(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dense_lattice_matches_the_lammps_input() {
        let w = dense_lattice_scene();
        let d = &w.state.discs;
        assert_eq!(d.len(), 46_000);
        // LAMMPS 29 Sep 2021: `set density 2500` on diameter 1.002 mm gives 1.31686663906497e-6 kg.
        assert!(
            (d.m[0] / 1.31686663906497e-6 - 1.0).abs() < 1e-12,
            "mass {}",
            d.m[0]
        );
        assert!((d.inertia[0] / (0.5 * d.m[0] * 0.501e-3 * 0.501e-3) - 1.0).abs() < 1e-12);
        // Six touching neighbours per disc on the hex lattice, listed once: 3 per disc.
        assert_eq!(w.n_pairs(), 138_000);
        assert_eq!(w.dt(), 1e-6);
        let l = w.state.periodic.length;
        assert_eq!(l[0], Some(0.2));
        assert!((l[1].unwrap() - 115.0 * 3f64.sqrt() * 1e-3).abs() < 1e-15);
    }
}
