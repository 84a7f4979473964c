//! Closed-form checks of the damping terms and the reference-gap offset:
//! * PFC local damping: a free disc pushed by a constant force F accelerates at (1 − α)F/m
//!   (F_d = −α|F| sign v, Cundall 1987);
//! * global viscous damping: a disc under constant F approaches v_t = F/c with
//!   v(t) = v_t (1 − e^{−ct/m}), c = 2ζ√(mK);
//! * reference gap: two discs overlapping by design with g₀ = gap carry no force, and react
//!   with k_n (δ − 0) only to overlap beyond g₀.

use dem_core::contact::LinearSpringDashpot;
use dem_core::{ContactLaws, ContactModel, ExternalLoad, Params, State, World};

fn one_disc(params: Params) -> World {
    let mut st = State::default();
    st.discs.push_uniform(0.0, 0.0, 0.01, 2500.0, 0.01, 0);
    let law = LinearSpringDashpot::elastic(1e5, 5e4, 0.5);
    let mut w = World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)));
    w.loads.push(ExternalLoad {
        id: 0,
        force: [0.3, -0.1],
        torque: 1e-4,
    });
    w
}

#[test]
fn local_damping_scales_acceleration_by_one_minus_alpha() {
    let alpha = 0.7;
    let mut w = one_disc(Params {
        local_damping: alpha,
        ..Params::default()
    });
    w.step(); // from rest sign(v) = 0: the first kick is undamped
    let d = &w.state.discs;
    let (vx1, vy1, w1) = (d.vx[0], d.vy[0], d.omega[0]);
    w.run(100);
    let d = &w.state.discs;
    let t = 100.0 * w.dt();
    let (m, i) = (d.m[0], d.inertia[0]);
    let ax = (d.vx[0] - vx1) / t;
    let ay = (d.vy[0] - vy1) / t;
    let aw = (d.omega[0] - w1) / t;
    assert!((ax / ((1.0 - alpha) * 0.3 / m) - 1.0).abs() < 1e-9, "{ax}");
    assert!((ay / ((1.0 - alpha) * -0.1 / m) - 1.0).abs() < 1e-9, "{ay}");
    assert!((aw / ((1.0 - alpha) * 1e-4 / i) - 1.0).abs() < 1e-9, "{aw}");
    let e = w.energy();
    eprintln!("balance error {:.3e}", e.balance_error);
    assert!(e.damping > 0.0 && e.balance_error.abs() < 1e-2, "{e:?}");
}

#[test]
fn viscous_damping_gives_exponential_approach_to_terminal_velocity() {
    let zeta = 0.2;
    let mut w = one_disc(Params {
        viscous_damping: zeta,
        ..Params::default()
    });
    // Isolated disc: K is the stiffest contact it could make, k_n = 1e5 N/m.
    let m = w.state.discs.m[0];
    let c = 2.0 * zeta * (m * 1e5).sqrt();
    let v_t = 0.3 / c;
    let steps = 60;
    w.run(steps);
    let t = steps as f64 * w.dt();
    // Central differences with a half-step velocity: v_{n+1/2} = v_{n-1/2}(1 − c dt/m) + F dt/m.
    let q = 1.0 - c * w.dt() / m;
    let v_discrete = v_t * (1.0 - q.powi(steps as i32));
    let v_exact = v_t * (1.0 - (-c * t / m).exp());
    let v = w.state.discs.vx[0];
    eprintln!("v {v}, discrete {v_discrete}, continuous {v_exact}, terminal {v_t}");
    assert!((v / v_discrete - 1.0).abs() < 1e-12);
    // The damping force uses v(t − dt/2) (explicit, as in PFC): first order in c·dt/m = 0.016
    // here, so the continuous solution is matched to about that over c·t/m ≈ 1.
    assert!((v / v_exact - 1.0).abs() < 0.01);
    assert!(
        v < 0.7 * v_t,
        "still accelerating: the test samples the transient"
    );
}

#[test]
fn reference_gap_offsets_the_overlap() {
    let (r, kn) = (0.01, 1e5);
    let mut st = State::default();
    let gap0 = -0.002; // overlapping by 2 mm by design
    st.discs.push_uniform(0.0, 0.0, r, 2500.0, 0.01, 0);
    st.discs
        .push_uniform(2.0 * r + gap0, 0.0, r, 2500.0, 0.01, 0);
    let law = LinearSpringDashpot::elastic(kn, 0.0, 0.0);
    let params = Params {
        reorder_every: 0,
        ..Params::default()
    };
    let mut w = World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)));
    w.set_contact_offset(0, 1, gap0);
    w.step();
    assert_eq!(w.state.discs.fx[0], 0.0, "no force at the reference gap");
    assert_eq!(w.state.discs.vx[1], 0.0);
    // Push 0.1 mm further: force k_n · 1e-4 N.
    w.state.discs.x[1] -= 1e-4;
    w.refresh();
    w.step();
    let f = w.state.discs.fx[1];
    assert!((f / (kn * 1e-4) - 1.0).abs() < 1e-9, "{f}");
    let c: Vec<_> = w.contacts().collect();
    assert_eq!(c.len(), 1);
    // One step has moved the discs apart by ~F dt²/m ≈ 2e-7 m since the force was computed.
    assert!((c[0].overlap / 1e-4 - 1.0).abs() < 0.01, "{:?}", c[0]);
    assert!((c[0].overlap - (gap0 - c[0].gap)).abs() < 1e-15);
    assert!((c[0].f_n / (kn * c[0].overlap) - 1.0).abs() < 1e-12);
}
