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
