//! Bonded scenes at the automatic time step: a radius ratio of 1:20 and SiC stiffness
//! (E = 430 GPa, S4 Table 1) run 1e5 undamped steps stably (finite, within the guard, energy
//! conserved, no bond broken); a bonded lattice with breaking bonds gives identical bytes on 1
//! and 2 threads.

use dem_core::bond::{
    world_with_bonds, BondGroup, BondModel, Bonds, Criterion, ParallelBondParams,
};
use dem_core::contact::LinearSpringDashpot;
use dem_core::{ContactLaws, ContactModel, Params, State, World};

mod shaken_lattice;

use shaken_lattice::rng;

/// Parallel bonds with the PFC deformability relation k̄n = E/(R1 + R2) (taken at the mean
/// radius sum `rsum`), k̄s = k̄n/2.5, and strengths far above the loads of the test.
fn strong_group(e: f64, rsum: f64) -> BondGroup {
    let kn = e / rsum;
    BondGroup {
        name: "bonds".into(),
        model: BondModel::Parallel(ParallelBondParams {
            kn,
            ks: kn / 2.5,
            lambda: 1.0,
            beta: 1.0,
        }),
        criterion: Criterion::Stress {
            tensile: 1e15,
            cohesion: 1e15,
            friction_angle: 0.5,
        },
    }
}

/// Run `steps` steps checking the guard every 1000; return the largest |balance error| and
/// the largest relative growth of the total energy over the initial one.
fn run_checked(w: &mut World, steps: usize) -> (f64, f64) {
    let mut worst: f64 = 0.0;
    let mut growth = f64::NEG_INFINITY;
    for _ in 0..steps / 1000 {
        w.run(1000);
        if let Err(e) = w.check() {
            panic!("guard: {e}");
        }
        let e = w.energy();
        worst = worst.max(e.balance_error.abs());
        growth = growth.max(e.total / e.initial - 1.0);
    }
    (worst, growth)
}

/// The 1:20 scene; returns the world after 1e5 steps, the worst balance error and the largest
/// total energy seen relative to the initial one.
fn ratio_scene(friction: bool) -> (World, f64, f64) {
    // A disc of radius 20r with 24 discs of radius r bonded around it, and a second large disc
    // bonded to the first through one small disc; random velocities and spins.
    let (r, big) = (1e-4, 2e-3);
    let t = 1e-3;
    let mut st = State {
        thickness: t,
        ..State::default()
    };
    let c0 = st.discs.push_uniform(0.0, 0.0, big, 2500.0, t, 0);
    let mut small = Vec::new();
    for k in 0..24 {
        let a = k as f64 / 24.0 * std::f64::consts::TAU;
        let d = big + r;
        small.push(
            st.discs
                .push_uniform(d * a.cos(), d * a.sin(), r, 2500.0, t, 0),
        );
    }
    // Small disc 0 sits at (big + r, 0); the second large disc touches it on the right.
    let c1 = st
        .discs
        .push_uniform(2.0 * big + 2.0 * r, 0.0, big, 2500.0, t, 0);
    let mut rnd = rng(3);
    for k in 0..st.discs.len() {
        st.discs.vx[k] = 0.01 * rnd();
        st.discs.vy[k] = 0.01 * rnd();
        st.discs.omega[k] = 10.0 * rnd();
    }
    let e = 50e9;
    let mut bonds = Bonds::new(vec![strong_group(e, big + r)]).unwrap();
    for &s in &small {
        bonds.add(&st, c0, s, 0).unwrap();
    }
    bonds.add(&st, small[0], c1, 0).unwrap();
    let (ks, mu) = if friction {
        (e * t / 2.5, 0.5)
    } else {
        (0.0, 0.0)
    };
    let laws = ContactLaws::uniform(ContactModel::Linear(LinearSpringDashpot::elastic(
        e * t,
        ks,
        mu,
    )));
    let mut w = world_with_bonds(st, Params::default(), laws, bonds, &[]).unwrap();
    let (worst, growth) = run_checked(&mut w, 100_000);
    (w, worst, growth)
}

#[test]
fn radius_ratio_1_to_20_bonded_scene_is_stable_at_the_automatic_dt() {
    // Frictionless contacts: the bonds and contacts are elastic, energy is conserved.
    let (w, worst, _) = ratio_scene(false);
    eprintln!(
        "ratio 1:20: dt {:.3e} (critical {:.3e}), worst balance error {worst:.2e}",
        w.dt(),
        w.critical_dt()
    );
    assert_eq!(w.bonds.as_ref().unwrap().n_intact(), 25);
    assert!(worst < 1e-4, "energy balance error {worst}");
    // Frictional contacts between the bonded discs: still stable, energy never grows.
    let (w, worst, growth) = ratio_scene(true);
    eprintln!("ratio 1:20 with friction: balance error {worst:.2e}, max E/E0 − 1 = {growth:.2e}");
    assert_eq!(w.bonds.as_ref().unwrap().n_intact(), 25);
    assert!(growth < 1e-4, "energy grew by {growth}");
}

#[test]
fn sic_stiffness_bonded_block_is_stable_at_the_automatic_dt() {
    // 12 × 8 hexagonal block of 5 µm discs (SiC grain size, S4), E = 430 GPa, ρ = 3210 kg/m³,
    // bonded at every contact, random velocities; frictionless contacts (elastic: energy is
    // conserved).
    let r = 5e-6;
    let t = 1e-3;
    let e = 430e9;
    let mut st = State {
        thickness: t,
        ..State::default()
    };
    let h = 3f64.sqrt() * r;
    for row in 0..8 {
        for col in 0..12 {
            let x = (2 * col + row % 2) as f64 * r;
            st.discs.push_uniform(x, row as f64 * h, r, 3210.0, t, 0);
        }
    }
    let mut rnd = rng(11);
    for k in 0..st.discs.len() {
        st.discs.vx[k] = 0.05 * rnd();
        st.discs.vy[k] = 0.05 * rnd();
        st.discs.omega[k] = 1e3 * rnd();
    }
    let mut bonds = Bonds::new(vec![strong_group(e, 2.0 * r)]).unwrap();
    let n = bonds.install_at_contacts(&st, 1e-3 * r, 0).unwrap();
    assert!(n > 200, "{n} bonds");
    let laws = ContactLaws::uniform(ContactModel::Linear(LinearSpringDashpot::elastic(
        e * t,
        0.0,
        0.0,
    )));
    let mut w = world_with_bonds(st, Params::default(), laws, bonds, &[]).unwrap();
    let (worst, _) = run_checked(&mut w, 100_000);
    eprintln!(
        "SiC: dt {:.3e} (critical {:.3e}), worst balance error {worst:.2e}",
        w.dt(),
        w.critical_dt()
    );
    assert_eq!(w.bonds.as_ref().unwrap().n_intact(), n);
    assert!(worst < 1e-3, "energy balance error {worst}");
}

#[test]
fn bonded_world_is_bit_identical_on_one_and_two_threads() {
    let go = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            // 3600 discs, 10,800 weak bonds (above the parallel threshold), shaken.
            let mut w = shaken_lattice::weak_shaken_lattice(5, 0.02, Params::default());
            w.run(1000);
            let b = w.bonds.as_ref().unwrap();
            (
                serde_json::to_string(&w.state).unwrap(),
                serde_json::to_string(b).unwrap(),
                b.log().len(),
            )
        })
    };
    let (s1, b1, n1) = go(1);
    let (s2, b2, n2) = go(2);
    eprintln!("{n1} bonds broke");
    assert!(n1 > 10, "breaks {n1}");
    assert_eq!(n1, n2);
    assert!(s1 == s2, "state differs");
    assert!(b1 == b2, "bonds differ");
}
