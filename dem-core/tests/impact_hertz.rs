//! Two-disc normal impact with Hertz–Mindlin: undamped contact time within 2 % of Hertz
//! theory t_c = 2.9432 δ_max/v (Johnson 1985 §11.4, δ_max = (15 m* v²/(16 E* √R*))^{2/5},
//! v the approach speed), and the calibrated damping gives the set restitution within 1 %.

use dem_core::contact::HertzMindlin;
use dem_core::{ContactLaws, ContactModel, Params, State, World};

/// Returns (contact time, theory, restitution).
fn impact(e_target: f64, v: f64) -> (f64, f64, f64) {
    let (r, rho, young, nu) = (0.01, 2500.0, 70e9, 0.3);
    let mut st = State::default();
    st.discs.push_uniform(0.0, 0.0, r, rho, 0.01, 0);
    st.discs.push_uniform(2.0 * r + 1e-6, 0.0, r, rho, 0.01, 0);
    st.discs.vx[0] = 0.5 * v;
    st.discs.vx[1] = -0.5 * v;
    let law = HertzMindlin::from_materials(young, nu, young, nu, e_target, 0.0);
    let params = Params {
        dt_factor: 0.05,
        reorder_every: 0,
        ..Params::default()
    };
    let mut w = World::new(
        st,
        params,
        ContactLaws::uniform(ContactModel::HertzMindlin(law)),
    );
    let m_eff = 0.5 * w.state.discs.m[0];
    let e_star = young / (2.0 * (1.0 - nu * nu));
    let r_eff = 0.5 * r;
    let d_max = (15.0 * m_eff * v * v / (16.0 * e_star * r_eff.sqrt())).powf(0.4);
    let t_theory = 2.9432 * d_max / v;
    let gap = |w: &World| {
        let d = &w.state.discs;
        d.x[1] - d.x[0] - d.r[0] - d.r[1]
    };
    let (mut t_in, mut t_out) = (None, None);
    let (mut g_prev, mut t_prev) = (gap(&w), w.state.time);
    for _ in 0..10_000_000 {
        w.step();
        let (g, t) = (gap(&w), w.state.time);
        if t_in.is_none() && g < 0.0 {
            t_in = Some(t_prev + (t - t_prev) * g_prev / (g_prev - g));
        } else if t_in.is_some() && g >= 0.0 {
            t_out = Some(t_prev + (t - t_prev) * (-g_prev) / (g - g_prev));
            break;
        }
        (g_prev, t_prev) = (g, t);
    }
    let tc = t_out.expect("separated") - t_in.expect("touched");
    w.run(5);
    let d = &w.state.discs;
    (tc, t_theory, (d.vx[1] - d.vx[0]) / v)
}

#[test]
fn hertz_contact_time_matches_theory() {
    for v in [0.2, 1.0, 5.0] {
        let (tc, tt, e) = impact(1.0, v);
        eprintln!("v {v}: t_c {tc:.6e} theory {tt:.6e} e {e:.6}");
        assert!((tc / tt - 1.0).abs() < 0.02, "v {v}: {tc} vs {tt}");
        assert!((e - 1.0).abs() < 1e-3, "undamped restitution {e}");
    }
}

#[test]
fn hertz_damping_gives_the_set_restitution() {
    for (e_t, v) in [(0.8, 1.0), (0.5, 3.0), (0.95, 0.3)] {
        let (_, _, e) = impact(e_t, v);
        eprintln!("target {e_t} v {v}: e {e:.5}");
        assert!((e / e_t - 1.0).abs() < 0.01, "target {e_t}: got {e}");
    }
}
