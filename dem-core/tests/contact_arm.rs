//! The tangential contact force acts at the contact point (midway in the geometric overlap,
//! Potyondy & Cundall 2004 §2.1), so the pair's forces and torques have zero net moment about
//! any point: total angular momentum L = Σ m (x v_y − y v_x) + I ω is conserved. For central
//! differences the exact discrete invariant is L with x(t + Δt) and v(t + Δt/2), the state
//! after each step (x(t+Δt) × v(t+Δt/2) = x(t) × v(t+Δt/2)), so it must hold to round-off.
//! With the arms r_i, r_j instead, a deep overlap h (bonded clump members, reference gap g₀)
//! changes L by h F_t Δt every step.

use dem_core::contact::{LinearSpringDashpot, NormalDamping};
use dem_core::{ContactLaws, ContactModel, Params, State, World};

fn angular_momentum(w: &World) -> (f64, f64) {
    let d = &w.state.discs;
    let (mut l, mut scale) = (0.0, 0.0);
    for i in 0..d.len() {
        let orb = d.m[i] * (d.x[i] * d.vy[i] - d.y[i] * d.vx[i]);
        let spin = d.inertia[i] * d.omega[i];
        l += orb + spin;
        scale += orb.abs() + spin.abs();
    }
    (l, scale)
}

#[test]
fn deep_overlap_with_tangential_force_conserves_angular_momentum() {
    let (ra, rb) = (0.01, 0.006);
    let (cx, cy) = (0.3, -0.2); // away from the origin: the orbital terms matter
    let dist = 0.012; // geometric overlap 4 mm (members of a bonded clump overlap by design)
    let mut st = State::default();
    st.discs.push_uniform(cx, cy, ra, 2500.0, 0.01, 0);
    st.discs.push_uniform(cx + dist, cy, rb, 2500.0, 0.01, 0);
    // Approach along the line of centres, slide across it and spin: sticking and slipping
    // tangential forces with both the spring and the tangential dashpot.
    st.discs.vx[1] = -0.05;
    st.discs.vy[1] = 0.4;
    st.discs.omega[0] = 30.0;
    let law = LinearSpringDashpot {
        kn: 1e4,
        ks: 5e3,
        damping: NormalDamping::Ratio(0.3),
        shear_damping: 0.5,
        mu: 0.5,
    };
    let params = Params {
        reorder_every: 0,
        dt_fixed: Some(1e-6),
        ..Params::default()
    };
    let mut w = World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)));
    // Reference gap at the initial geometry: the contact acts only on the extra overlap.
    w.set_contact_offset(0, 1, dist - ra - rb);
    w.step();
    let (l0, scale) = angular_momentum(&w);
    let (mut touching, mut max_ft) = (0, 0.0f64);
    let mut max_dev = 0.0f64;
    for _ in 0..20_000 {
        w.step();
        if let Some(c) = w.contacts().next() {
            touching += 1;
            max_ft = max_ft.max(c.f_t.abs());
        }
        let (l, _) = angular_momentum(&w);
        max_dev = max_dev.max((l - l0).abs());
    }
    eprintln!(
        "L0 {l0:.6e}, scale {scale:.3e}, max |L − L0| {max_dev:.3e}, touching {touching} steps, \
         max |F_t| {max_ft:.3e} N"
    );
    assert!(touching > 1000, "the test must sample a long contact");
    assert!(max_ft > 0.01, "the tangential force must act");
    assert!(
        max_dev <= 1e-11 * scale,
        "angular momentum drifts: {max_dev:e} (scale {scale:e})"
    );
}
