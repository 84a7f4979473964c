//! The bonded-lattice benchmark: the dense hex lattice of `shared/bench/lammps-dense2d.in`
//! (46,000 discs, spacing 1 mm, diameter 1.002 mm, periodic in x and y, tiny random
//! displacement, density 2500 kg/m³) with a parallel bond at every contact.
//!
//! Disc thickness t = (4/3)·r makes each disc's mass ρ·t·π·r² equal LAMMPS's sphere mass
//! ρ·(4/3)π r³ (LAMMPS `set density` on `atom_style sphere` gives spheres even in 2D).
//! The bonds' k̄nĀ and k̄sĀ equal the contact stiffness kn = 1e5 N/m of the LAMMPS input; their
//! strengths (1e8 Pa) are far above the loads the 1 µm displacement creates, so none break.

use super::{world_with_bonds, BondGroup, BondModel, Bonds, Criterion, ParallelBondParams};
use crate::contact::{LinearSpringDashpot, NormalDamping};
use crate::counters::Counters;
use crate::pipeline::World;
use crate::state::{Periodic, State};
use crate::{ContactLaws, ContactModel, Params};

/// Lattice spacing (m), disc radius (m), density (kg/m³) of the LAMMPS input.
pub const SPACING: f64 = 1e-3;
pub const RADIUS: f64 = 0.5 * 1.002e-3;
pub const DENSITY: f64 = 2500.0;
/// Lattice cells in x and y (two discs per cell): 200 × 115 × 2 = 46,000 discs.
pub const CELLS: [usize; 2] = [200, 115];
/// Contact normal stiffness of the LAMMPS input (N/m), which the bonds' k̄nĀ match.
pub const KN: f64 = 1e5;

/// LAMMPS-style `lattice hex` of any size (the full benchmark world is built by
/// [`crate::bench::dense_lattice_scene`]; this one serves smaller test lattices):
/// a1 = (a, 0), a2 = (0, √3 a), basis (0,0) and (a/2, √3a/2); each disc displaced by a uniform
/// random amount in [−1, 1] µm per axis (deterministic LCG).
pub fn hex_lattice_state(cells: [usize; 2]) -> State {
    let a = SPACING;
    let h = 3f64.sqrt() * a;
    let mut st = State {
        thickness: 4.0 / 3.0 * RADIUS,
        periodic: Periodic {
            lo: [0.0, 0.0],
            length: [Some(cells[0] as f64 * a), Some(cells[1] as f64 * h)],
        },
        ..State::default()
    };
    let mut s: u64 = 123;
    let mut rnd = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        2.0 * ((s >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    };
    for cy in 0..cells[1] {
        for cx in 0..cells[0] {
            for (bx, by) in [(0.0, 0.0), (0.5, 0.5)] {
                let x = (cx as f64 + bx) * a + 1e-6 * rnd();
                let y = (cy as f64 + by) * h + 1e-6 * rnd();
                let (x, y) = (st.periodic.wrap(0, x), st.periodic.wrap(1, y));
                st.discs
                    .push_uniform(x, y, RADIUS, DENSITY, st.thickness, 0);
            }
        }
    }
    st
}

/// [`hex_lattice_state`] with random velocities (uniform in ±v/2 per axis) and spins (±w/2)
/// from a seeded LCG: the moving lattice the contact-pass bit-identity tests compare on.
#[cfg(test)]
pub(crate) fn shaken_hex_lattice(cells: [usize; 2], seed: u64, v: f64, w: f64) -> State {
    let mut st = hex_lattice_state(cells);
    let mut s = seed;
    let mut r = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    };
    for k in 0..st.discs.len() {
        st.discs.vx[k] = v * r();
        st.discs.vy[k] = v * r();
        st.discs.omega[k] = w * r();
    }
    st
}

/// The bond group of the benchmark lattice: k̄n = k̄s = KN/Ā with Ā = 2·r·t.
/// The benchmark group and a second parallel-bond group with the stress criterion, stiffer in
/// normal, softer in shear, with β̄ = 0.5 and the given strengths (improved ORC's two groups;
/// discs of thickness `t`).
#[cfg(test)]
pub(crate) fn two_groups(t: f64, tensile: f64, cohesion: f64) -> Vec<BondGroup> {
    let g0 = lattice_bond_group(t);
    let mut g1 = g0.clone();
    g1.name = "other".into();
    if let BondModel::Parallel(p) = &mut g1.model {
        p.kn *= 1.7;
        p.ks *= 0.6;
        p.beta = 0.5;
    }
    g1.criterion = Criterion::Stress {
        tensile,
        cohesion,
        friction_angle: 0.3,
    };
    vec![g0, g1]
}

pub fn lattice_bond_group(t: f64) -> BondGroup {
    let area = 2.0 * RADIUS * t;
    BondGroup {
        name: "lattice".into(),
        model: BondModel::Parallel(ParallelBondParams {
            kn: KN / area,
            ks: KN / area,
            lambda: 1.0,
            beta: 1.0,
        }),
        criterion: Criterion::Stress {
            tensile: 1e8,
            cohesion: 1e8,
            friction_angle: 0.5,
        },
    }
}

/// The lattice's bond group as a flat joint of `elements` elements (Potyondy 2012,
/// [`super::flat_joint`]): the same k̄n, k̄s, R̄ and strengths, so an intact lattice moves as
/// with the parallel bond; for the flat joint's cost against the parallel bond's.
pub fn lattice_flat_joint_group(t: f64, elements: u8) -> BondGroup {
    let mut g = lattice_bond_group(t);
    if let BondModel::Parallel(p) = g.model {
        g.model = BondModel::FlatJoint(super::FlatJointParams {
            kn: p.kn,
            ks: p.ks,
            lambda: p.lambda,
            elements,
            friction: 0.5,
            bonded_fraction: 1.0,
        });
    }
    g.name = "lattice_flat_joint".into();
    g
}

/// The benchmark lattice with a parallel bond at every contact (≈ 3 bonds per disc).
pub fn bonded_lattice_state(cells: [usize; 2]) -> (State, Bonds) {
    lattice_state_with(cells, &lattice_bond_group)
}

fn lattice_state_with(cells: [usize; 2], group: &dyn Fn(f64) -> BondGroup) -> (State, Bonds) {
    let st = hex_lattice_state(cells);
    let mut bonds =
        Bonds::new(vec![group(st.thickness)]).expect("the benchmark bond group is valid");
    bonds
        .install_at_contacts(&st, 0.1 * RADIUS, 0)
        .expect("lattice discs are valid");
    (st, bonds)
}

/// The bonded-lattice benchmark world: the dense-lattice scene of the peer benchmark
/// ([`crate::bench::dense_lattice_scene`], the same discs, contacts and skin) with a parallel
/// bond at every contact (≈138,000 bonds, [`lattice_bond_group`]) and the automatic time step
/// (the scene's fixed 1 µs is not stable once the bonds double the stiffness).
pub fn bonded_lattice_scene() -> World {
    bonded_lattice_with(None, &lattice_bond_group)
}

/// [`bonded_lattice_scene`] (`cells` None) or [`bonded_lattice_world`] with the bonds of
/// `group` (given the disc thickness): [`lattice_bond_group`] or
/// [`lattice_flat_joint_group`].
pub fn bonded_lattice_with(cells: Option<[usize; 2]>, group: &dyn Fn(f64) -> BondGroup) -> World {
    if let Some(c) = cells {
        return lattice_world_with(c, group);
    }
    let mut w = crate::bench::dense_lattice_scene();
    w.params.dt_fixed = None;
    let mut bonds =
        Bonds::new(vec![group(w.state.thickness)]).expect("the benchmark bond group is valid");
    bonds
        .install_at_contacts(&w.state, 0.1 * RADIUS, 0)
        .expect("lattice discs are valid");
    super::attach(&mut w, bonds);
    w
}

/// A smaller bonded lattice of `cells` cells (see [`bonded_lattice_state`]) in a world with
/// the benchmark's contact law and the automatic time step.
pub fn bonded_lattice_world(cells: [usize; 2]) -> World {
    lattice_world_with(cells, &lattice_bond_group)
}

fn lattice_world_with(cells: [usize; 2], group: &dyn Fn(f64) -> BondGroup) -> World {
    let (st, bonds) = lattice_state_with(cells, group);
    let law = LinearSpringDashpot {
        kn: KN,
        ks: 2.0 / 7.0 * KN,
        damping: NormalDamping::Gamma(100.0),
        shear_damping: 0.5,
        mu: 0.5,
    };
    let params = Params {
        track_energy: false,
        skin: Some(1e-4),
        ..Params::default()
    };
    world_with_bonds(
        st,
        params,
        ContactLaws::uniform(ContactModel::Linear(law)),
        bonds,
        &[],
    )
    .expect("the benchmark scene is valid")
}

/// Figures of one benchmark run.
#[derive(Clone, Debug)]
pub struct BenchRun {
    pub discs: usize,
    pub bonds: usize,
    pub steps: u64,
    pub threads: usize,
    pub dt: f64,
    /// Wall time of the stepping (s), scene building excluded.
    pub seconds: f64,
    /// discs × steps / seconds.
    pub particle_steps_per_s: f64,
    /// Per-stage times of the run.
    pub counters: Counters,
}

/// Why the bonded benchmark could not run or ended in an invalid state.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error("cannot build the thread pool: {0}")]
    ThreadPool(#[from] rayon::ThreadPoolBuildError),
    #[error(transparent)]
    Guard(#[from] crate::guard::GuardError),
}

/// Run the bonded lattice (`cells` = [`CELLS`]: the full [`bonded_lattice_scene`], else
/// [`bonded_lattice_world`]) for `steps` steps on `threads` threads (a rayon pool of that
/// size); the first step (neighbour build, reorder) is not timed.
pub fn run_bonded_bench(
    cells: [usize; 2],
    steps: u64,
    threads: usize,
) -> Result<BenchRun, BenchError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()?;
    pool.install(|| {
        let mut w = if cells == CELLS {
            bonded_lattice_scene()
        } else {
            bonded_lattice_world(cells)
        };
        w.step();
        w.counters.reset();
        let t0 = std::time::Instant::now();
        w.run(steps);
        let seconds = t0.elapsed().as_secs_f64();
        w.check()?;
        let n = w.state.discs.len();
        Ok(BenchRun {
            discs: n,
            bonds: w.bonds.as_ref().map_or(0, |b| b.n_intact()),
            steps,
            threads: threads.max(1),
            dt: w.dt(),
            seconds,
            particle_steps_per_s: n as f64 * steps as f64 / seconds,
            counters: w.counters.clone(),
        })
    })
}

/// Throughput of the bond stage alone on the benchmark lattice (`CELLS` for the full one): `steps` calls of
/// [`Bonds::compute`] (plus clearing forces) on `threads` threads, positions frozen and velocities
/// small and random (so every bond does its full work without breaking). Returns
/// disc-steps per second of wall time.
pub fn bond_stage_rate(cells: [usize; 2], steps: usize, threads: usize) -> f64 {
    let (mut st, mut bonds) = bonded_lattice_state(cells);
    let mut s: u64 = 7;
    for k in 0..st.discs.len() {
        let mut r = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            2.0 * ((s >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        };
        st.discs.vx[k] = 1e-4 * r();
        st.discs.vy[k] = 1e-4 * r();
        st.discs.omega[k] = 0.1 * r();
    }
    let pool = match rayon::ThreadPoolBuilder::new()
        .num_threads(threads.max(1))
        .build()
    {
        Ok(p) => p,
        Err(_) => return f64::NAN,
    };
    pool.install(|| {
        let t0 = std::time::Instant::now();
        for _ in 0..steps {
            st.discs.clear_forces();
            bonds.compute(&mut st, 1e-7);
        }
        (st.discs.len() * steps) as f64 / t0.elapsed().as_secs_f64()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_lattice_has_three_bonds_per_disc() {
        let (st, b) = bonded_lattice_state([10, 6]);
        assert_eq!(st.discs.len(), 120);
        assert_eq!(b.len(), 3 * 120);
        // Every disc has six bonded neighbours.
        let mut deg = vec![0; 120];
        for v in b.iter() {
            deg[v.i as usize] += 1;
            deg[v.j as usize] += 1;
        }
        assert!(deg.iter().all(|&d| d == 6));
    }
}
