//! A disc launched along a wall under gravity: while it slides it decelerates at μg and spins
//! up at ω̇ = 2μg/R (friction μmg, I = mR²/2); after t = v₀/(3μg) it rolls with v = ωR = 2v₀/3
//! and keeps that speed (no rolling resistance). The wall reports the disc's weight and the
//! friction force as its reaction.

use dem_core::contact::{LinearSpringDashpot, NormalDamping};
use dem_core::{ContactLaws, ContactModel, Params, State, Wall, World};

#[test]
fn sliding_then_rolling_disc_on_a_wall() {
    let (r, rho, t, kn, mu, g, v0) = (0.01, 2500.0, 0.01, 1e6, 0.3, 9.81, 1.0);
    let mut st = State {
        thickness: t,
        ..State::default()
    };
    let m = rho * t * std::f64::consts::PI * r * r;
    let delta = m * g / kn;
    st.discs.push_uniform(0.0, r - delta, r, rho, t, 0);
    st.discs.vx[0] = v0;
    st.walls
        .push(Wall::new("floor", [-1.0, 0.0], [10.0, 0.0], 0));
    let law = LinearSpringDashpot {
        kn,
        ks: 0.5 * kn,
        damping: NormalDamping::Ratio(0.3),
        shear_damping: 0.0,
        mu,
    };
    let params = Params {
        gravity: Some([0.0, -g]),
        ..Params::default()
    };
    let mut w = World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)));
    let run_to = |w: &mut World, time: f64| {
        while w.state.time < time {
            w.step();
        }
        let d = &w.state.discs;
        (w.state.time, d.vx[0], d.omega[0])
    };
    // Sliding phase: 0 < t < v0/(3μg) = 0.113 s.
    let (t1, v1, w1) = run_to(&mut w, 0.02);
    let wall = &w.state.walls[0];
    assert!(
        (wall.force[1] / (-m * g) - 1.0).abs() < 1e-3,
        "wall normal {:?}",
        wall.force
    );
    assert!(
        (wall.force[0] / (mu * m * g) - 1.0).abs() < 1e-3,
        "wall friction {:?}",
        wall.force
    );
    let (t2, v2, w2) = run_to(&mut w, 0.08);
    let a = (v2 - v1) / (t2 - t1);
    let alpha = (w2 - w1) / (t2 - t1);
    eprintln!(
        "deceleration {a} (theory {}), spin-up {alpha} (theory {})",
        -mu * g,
        -2.0 * mu * g / r
    );
    assert!((a / (-mu * g) - 1.0).abs() < 0.01, "deceleration {a}");
    // Counter-clockwise positive: moving +x on a floor, friction spins the disc clockwise.
    assert!(
        (alpha / (-2.0 * mu * g / r) - 1.0).abs() < 0.01,
        "spin-up {alpha}"
    );
    // Rolling phase. The undamped tangential spring keeps a small stick oscillation between
    // translation and rotation (period 2π/√(3k_s/m) ≈ 0.5 ms), so compare means over 20 ms.
    let mean = |w: &mut World, from: f64| {
        run_to(w, from);
        let (mut sv, mut swr, mut k) = (0.0, 0.0, 0.0);
        while w.state.time < from + 0.02 {
            w.step();
            sv += w.state.discs.vx[0];
            swr += -w.state.discs.omega[0] * r;
            k += 1.0;
        }
        (sv / k, swr / k)
    };
    let (v3, wr3) = mean(&mut w, 0.2);
    let (v4, wr4) = mean(&mut w, 0.4);
    eprintln!("rolling: v {v3} {v4}, omega R {wr3} {wr4}");
    assert!(
        (v3 / (2.0 / 3.0 * v0) - 1.0).abs() < 0.002,
        "rolling speed {v3}"
    );
    assert!(
        (v3 - wr3).abs() < 1e-4 * v3,
        "v = ωR violated: {v3} vs {wr3}"
    );
    assert!(
        (v4 - wr4).abs() < 1e-4 * v4,
        "v = ωR violated: {v4} vs {wr4}"
    );
    assert!(
        (v4 / v3 - 1.0).abs() < 1e-4,
        "rolling disc changed speed: {v3} -> {v4}"
    );
}
