//! Undamped elastic granular gas in a periodic box (196 discs, radii ±20 %, area fraction
//! 0.26, random unit speeds): with the automatic time step and the default safety factor the
//! total energy (kinetic + contact strain) drifts by less than 1e-4 over 1e5 steps.

use clumpgen::synth::SplitMix64;
use dem_core::contact::LinearSpringDashpot;
use dem_core::{ContactLaws, ContactModel, Params, State, World};

pub fn gas(n_side: usize, seed: u64, params: Params) -> World {
    let mut rng = SplitMix64::new(seed);
    let (r0, spacing) = (0.01, 0.035);
    let l = n_side as f64 * spacing;
    let mut st = State {
        thickness: 0.01,
        ..State::default()
    };
    st.periodic.length = [Some(l), Some(l)];
    for iy in 0..n_side {
        for ix in 0..n_side {
            let r = r0 * rng.range(0.8, 1.2);
            let k = st.discs.push_uniform(
                (ix as f64 + 0.5) * spacing,
                (iy as f64 + 0.5) * spacing,
                r,
                2500.0,
                0.01,
                0,
            );
            let a = rng.range(0.0, std::f64::consts::TAU);
            st.discs.vx[k] = a.cos();
            st.discs.vy[k] = a.sin();
        }
    }
    let law = LinearSpringDashpot::elastic(1e5, 0.0, 0.0);
    World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)))
}

#[test]
fn elastic_gas_conserves_energy_at_the_automatic_step() {
    let mut w = gas(14, 11, Params::default());
    w.step();
    let e0 = w.energy().total;
    let mut worst = 0.0f64;
    let mut contacts_seen = 0usize;
    for _ in 0..100 {
        w.run(1000);
        worst = worst.max((w.energy().total / e0 - 1.0).abs());
        contacts_seen += w.contacts().count();
    }
    let rel = w.energy().total / e0 - 1.0;
    eprintln!("dt {:.3e} (critical {:.3e}); drift at end {rel:.3e}, worst {worst:.3e}, contacts sampled {contacts_seen}", w.dt(), w.critical_dt());
    assert!(contacts_seen > 20, "too few collisions to test anything");
    assert!(rel.abs() < 1e-4, "relative energy drift {rel}");
}

/// Issue 20: before the first step the energies are the state's own (a summary of a
/// `"steps": 0` run reported 0 J), and they equal the first step's without forces.
#[test]
fn energies_before_the_first_step_are_the_states() {
    let mut w = gas(4, 3, Params::default());
    let d = &w.state.discs;
    let hand: f64 = (0..d.len())
        .map(|i| 0.5 * d.m[i] * (d.vx[i] * d.vx[i] + d.vy[i] * d.vy[i]))
        .sum();
    let e = w.energy();
    assert!(hand > 0.0);
    assert_eq!(e.kinetic_translation, hand);
    assert_eq!(e.kinetic_rotation, 0.0);
    assert_eq!(e.total, hand);
    assert_eq!(e.initial, hand);
    assert_eq!(e.balance_error, 0.0);
    // The discs of this gas do not touch at first: one step keeps the kinetic energy.
    w.step();
    let after = w.energy().kinetic_translation;
    assert!((after / hand - 1.0).abs() < 1e-12, "{after} vs {hand}");
}

/// The gravity potential before the first step is −Σ m g·x of the state, the value the first
/// step books (it takes the positions before its drift).
#[test]
fn gravity_potential_before_the_first_step_is_the_states() {
    let p = Params {
        gravity: Some([0.0, -9.81]),
        ..Params::default()
    };
    let mut w = gas(4, 5, p);
    let d = &w.state.discs;
    let hand: f64 = (0..d.len()).map(|i| d.m[i] * 9.81 * d.y[i]).sum();
    let before = w.energy().gravity_potential;
    assert!((before / hand - 1.0).abs() < 1e-12, "{before} vs {hand}");
    w.step();
    let first = w.energy().gravity_potential;
    assert!((first / before - 1.0).abs() < 1e-12, "{first} vs {before}");
}
