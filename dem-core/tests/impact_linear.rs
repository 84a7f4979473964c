//! Two-disc normal impact with the linear spring–dashpot law: contact time
//! π/√(k/m* − c²/(4m*²)) and restitution e = exp(−π ζ/√(1−ζ²)) (damped harmonic oscillator;
//! e.g. Schwager & Pöschel 2007, Phys. Rev. E 75:051304), both within 1 %.

use dem_core::contact::{LinearSpringDashpot, NormalDamping};
use dem_core::{ContactLaws, ContactModel, Params, State, World};

fn impact(kn: f64, e_target: f64) -> (f64, f64, f64, f64) {
    let (r, rho) = (0.01, 2500.0);
    let mut st = State::default();
    let v0 = 0.5;
    let a = st.discs.push_uniform(0.0, 0.0, r, rho, 0.01, 0);
    let b = st.discs.push_uniform(2.0 * r + 1e-4, 0.0, r, rho, 0.01, 0);
    st.discs.vx[a] = v0;
    st.discs.vx[b] = -v0;
    let law = LinearSpringDashpot {
        kn,
        ks: 0.0,
        damping: NormalDamping::from_restitution(e_target),
        shear_damping: 0.0,
        mu: 0.0,
    };
    let params = Params {
        dt_factor: 0.02,
        ..Params::default()
    };
    let mut w = World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)));
    let m_eff = 0.5 * w.state.discs.m[0];
    let cn = law.cn(m_eff);
    let t_theory = std::f64::consts::PI / (kn / m_eff - cn * cn / (4.0 * m_eff * m_eff)).sqrt();
    // Contact from the first step with overlap to the first without, interpolated linearly
    // in the gap at both ends.
    let gap = |w: &World| {
        let d = &w.state.discs;
        (d.x[1] - d.x[0]).abs() - d.r[0] - d.r[1]
    };
    let (mut t_in, mut t_out) = (None, None);
    let mut g_prev = gap(&w);
    let mut t_prev = w.state.time;
    for _ in 0..2_000_000 {
        w.step();
        let g = gap(&w);
        let t = w.state.time;
        if t_in.is_none() && g < 0.0 {
            t_in = Some(t_prev + (t - t_prev) * g_prev / (g_prev - g));
        } else if t_in.is_some() && g >= 0.0 {
            t_out = Some(t_prev + (t - t_prev) * (-g_prev) / (g - g_prev));
            break;
        }
        g_prev = g;
        t_prev = t;
    }
    let tc = t_out.expect("separated") - t_in.expect("touched");
    w.run(10);
    let d = &w.state.discs;
    let e = (d.vx[1] - d.vx[0]).abs() / (2.0 * v0);
    (tc, t_theory, e, e_target)
}

#[test]
fn linear_impact_contact_time_and_restitution() {
    for &(kn, e_t) in &[(1e5, 0.9), (1e6, 0.5), (1e7, 1.0)] {
        let (tc, tt, e, et) = impact(kn, e_t);
        eprintln!("kn {kn}: tc {tc:.6e} theory {tt:.6e}, e {e:.5} target {et}");
        assert!(
            (tc / tt - 1.0).abs() < 0.01,
            "kn {kn}: contact time {tc} vs {tt}"
        );
        assert!(
            (e / et - 1.0).abs() < 0.01,
            "kn {kn}: restitution {e} vs {et}"
        );
    }
}
