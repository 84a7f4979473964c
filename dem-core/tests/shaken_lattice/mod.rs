//! Shared by the tests that need a moving bonded lattice: a deterministic random sequence and
//! the bonded hex lattice with weak parallel bonds (they break under shaking), shaken.

#![allow(dead_code)]

use dem_core::bond::bench::bonded_lattice_state;
use dem_core::bond::{world_with_bonds, Bonds, Criterion};
use dem_core::contact::LinearSpringDashpot;
use dem_core::{ContactLaws, ContactModel, Params, World};

/// Deterministic numbers in [−1, 1) (a 64-bit LCG, Knuth's MMIX constants).
pub fn rng(seed: u64) -> impl FnMut() -> f64 {
    let mut s = seed;
    move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        2.0 * ((s >> 11) as f64 / (1u64 << 53) as f64) - 1.0
    }
}

/// The 60 × 30-cell bonded lattice (3,600 discs, 10,800 bonds, above the bond stage's
/// parallel threshold) with weak bonds (σ̄c = 200 kPa, c̄ = 240 kPa, φ̄ = 0.3) at every contact,
/// velocities `v`·[−1, 1) m/s and spins 40·[−1, 1) rad/s from `rng(seed)`, elastic linear
/// contacts (k_n = 1e5, k_s = 2e4 N/m, μ = 0.5) and `params`.
pub fn weak_shaken_lattice(seed: u64, v: f64, params: Params) -> World {
    let (mut st, b) = bonded_lattice_state([60, 30]);
    let mut g = b.groups()[0].clone();
    g.criterion = Criterion::Stress {
        tensile: 2e5,
        cohesion: 2.4e5,
        friction_angle: 0.3,
    };
    let mut bonds = Bonds::new(vec![g]).unwrap();
    bonds.install_at_contacts(&st, 1e-5, 0).unwrap();
    let mut rnd = rng(seed);
    for k in 0..st.discs.len() {
        st.discs.vx[k] = v * rnd();
        st.discs.vy[k] = v * rnd();
        st.discs.omega[k] = 40.0 * rnd();
    }
    let laws = ContactLaws::uniform(ContactModel::Linear(LinearSpringDashpot::elastic(
        1e5, 2e4, 0.5,
    )));
    world_with_bonds(st, params, laws, bonds, &[]).unwrap()
}
