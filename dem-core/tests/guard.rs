//! Stability: a run at twice the critical time step is stopped by the guard with its message
//! (no NaN in the last good state); the same scene is stable at the automatic step; a SiC
//! scene (E = 430 GPa, contact stiffness k_n = E t) runs 1e5 steps at the automatic step.

use clumpgen::synth::SplitMix64;
use dem_core::contact::{LinearSpringDashpot, NormalDamping};
use dem_core::{ContactLaws, ContactModel, GuardError, Params, State, Wall, World};

/// A compressed chain of 10 discs (overlap 1e-4 m each), undamped.
fn chain(params: Params) -> World {
    let mut st = State {
        thickness: 0.01,
        ..State::default()
    };
    for k in 0..10 {
        st.discs
            .push_uniform(k as f64 * 0.0199, 0.0, 0.01, 2500.0, 0.01, 0);
    }
    let law = LinearSpringDashpot::elastic(1e6, 5e5, 0.5);
    World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)))
}

fn finite(st: &State) -> bool {
    let d = &st.discs;
    [&d.x, &d.y, &d.vx, &d.vy, &d.omega, &d.theta]
        .iter()
        .all(|v| v.iter().all(|x| x.is_finite()))
}

#[test]
fn twice_the_critical_step_is_stopped_by_the_guard() {
    let mut w = chain(Params::default());
    let crit = w.critical_dt();
    w.params.dt_fixed = Some(2.0 * crit);
    w.refresh();
    w.guard().expect("the initial state is good");
    let mut err = None;
    for _ in 0..1000 {
        w.run(10);
        if let Err(e) = w.guard() {
            err = Some(e);
            break;
        }
    }
    let e = err.expect("the guard must stop a run at 2x the critical step");
    let msg = e.to_string();
    eprintln!("{msg}");
    assert!(msg.contains("step ") && msg.contains("disc"), "{msg}");
    assert!(msg.contains("time step too large"), "{msg}");
    assert!(matches!(
        e,
        GuardError::Overlap { .. }
            | GuardError::EnergyGrowth { .. }
            | GuardError::NonFinite { .. }
            | GuardError::Speed { .. }
    ));
    let good = w.last_good().expect("a good state was kept");
    assert!(finite(good), "last good state has non-finite values");
    assert!(good.step < w.state.step);
}

#[test]
fn same_scene_is_stable_at_the_automatic_step() {
    let mut w = chain(Params::default());
    let e0 = {
        w.step();
        w.energy().total
    };
    for _ in 0..100 {
        w.run(100);
        w.guard().expect("stable");
    }
    let e = w.energy();
    assert!(
        (e.total / e0 - 1.0).abs() < 1e-3,
        "energy {} vs {e0}",
        e.total
    );
}

#[test]
fn sic_stiffness_scene_runs_stably() {
    // SiC: E = 430 GPa, ρ = 3210 kg/m³ (S4 Table 1). Discs 0.1–0.2 mm in a 4 mm walled box.
    let (young, t) = (430e9, 1e-3);
    let mut rng = SplitMix64::new(5);
    let mut st = State {
        thickness: t,
        ..State::default()
    };
    let (w_box, h_box) = (4e-3, 4e-3);
    for iy in 0..12 {
        for ix in 0..12 {
            let r = rng.range(1e-4, 1.6e-4);
            let k = st.discs.push_uniform(
                (ix as f64 + 0.5) * w_box / 12.0,
                (iy as f64 + 0.5) * h_box / 12.0 * 0.9,
                r,
                3210.0,
                t,
                0,
            );
            st.discs.vx[k] = rng.range(-0.5, 0.5);
            st.discs.vy[k] = rng.range(-0.5, 0.5);
        }
    }
    for (name, a, b) in [
        ("bottom", [0.0, 0.0], [w_box, 0.0]),
        ("top", [w_box, h_box], [0.0, h_box]),
        ("left", [0.0, h_box], [0.0, 0.0]),
        ("right", [w_box, 0.0], [w_box, h_box]),
    ] {
        st.walls.push(Wall::new(name, a, b, 0));
    }
    let kn = young * t;
    let law = LinearSpringDashpot {
        kn,
        ks: 0.4 * kn,
        damping: NormalDamping::from_restitution(0.5),
        shear_damping: 0.0,
        mu: 0.5,
    };
    let params = Params {
        gravity: Some([0.0, -9.81]),
        ..Params::default()
    };
    let mut w = World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)));
    for _ in 0..100 {
        w.run(1000);
        w.guard().expect("SiC scene must stay stable");
    }
    let e = w.energy();
    eprintln!("{e:?}");
    eprintln!(
        "SiC: dt {:.3e} s, {} contacts, balance error {:.2e}, kinetic {:.3e} J of initial {:.3e} J",
        w.dt(),
        w.contacts().count(),
        e.balance_error,
        e.kinetic(),
        e.initial
    );
    assert!(finite(&w.state));
    assert!(
        e.damping + e.friction > 0.1 * e.initial,
        "collisions must have dissipated energy"
    );
    assert!(
        e.balance_error.abs() < 1e-3,
        "energy balance {}",
        e.balance_error
    );
}

/// Issue 48 D10: a disc placed deep in a wall is named with the wall's name, not the
/// sentinel partner id 4294967295, and the overlap is of the disc's radius.
#[test]
fn a_disc_in_a_wall_names_the_wall() {
    let mut w = chain(Params::default());
    w.state
        .walls
        .push(Wall::new("floor", [-1.0, 0.005], [1.0, 0.005], 0));
    w.refresh();
    let e = w.guard().expect_err("disc 0 half inside the floor");
    let msg = e.to_string();
    assert!(matches!(e, GuardError::Overlap { step: 0, .. }), "{msg}");
    assert!(msg.contains("and wall 'floor'"), "{msg}");
    assert!(msg.contains("of the disc's radius"), "{msg}");
    assert!(!msg.contains("4294967295"), "{msg}");
}

#[test]
fn input_errors_are_named_as_input_not_as_the_time_step() {
    // Two discs at the same point: the state before any step is refused as an input overlap.
    let mut w = chain(Params::default());
    w.state.discs.x[3] = w.state.discs.x[2];
    w.refresh();
    let e = w.guard().expect_err("coincident discs");
    let msg = e.to_string();
    assert!(matches!(e, GuardError::Overlap { step: 0, .. }), "{msg}");
    assert!(
        msg.contains("same point") && msg.contains("no step has run yet"),
        "{msg}"
    );
    assert!(!msg.contains("time step too large"), "{msg}");

    // A velocity of 1e200 m/s in the input: refused before it reaches any output.
    let mut w = chain(Params::default());
    w.state.discs.vx[5] = 1e200;
    let e = w.guard().expect_err("absurd speed");
    let msg = e.to_string();
    assert!(matches!(e, GuardError::Speed { step: 0, .. }), "{msg}");
    assert!(msg.contains("input gives it this speed"), "{msg}");

    // Gravity 1e300 m/s²: the first checked step stops it (finite values, runaway speed), and
    // the last good state is the finite initial one.
    let mut w = chain(Params::default());
    w.params.gravity = Some([0.0, -1e300]);
    w.refresh();
    w.guard().expect("the initial state is good");
    w.run(1);
    let e = w.guard().expect_err("runaway");
    assert!(
        matches!(
            e,
            GuardError::Speed { step: 1, .. } | GuardError::NonFinite { step: 1, .. }
        ),
        "{e}"
    );
    assert!(finite(w.last_good().unwrap()));
    assert_eq!(w.last_good().unwrap().step, 0);
}

/// Issue 48 D14: with a fixed step of 1 s a disc moving 1 m/s crosses 100 radii per step; the
/// message puts the fixed step first, with the step that would do and the automatic one
/// (before: "the input gives it this speed ... check the velocity", the step not named).
#[test]
fn a_fixed_step_too_long_for_the_speed_is_named_as_the_step() {
    let mut w = chain(Params {
        dt_fixed: Some(1.0),
        ..Params::default()
    });
    w.state.discs.vx[5] = 1.0;
    w.refresh();
    let e = w.guard().expect_err("100 radii per step");
    let msg = e.to_string();
    assert!(matches!(e, GuardError::Speed { step: 0, .. }), "{msg}");
    assert!(
        msg.contains("fixed time step (scene run.dt = 1.0000e0 s) is too long"),
        "{msg}"
    );
    // 0.5 of r = 0.01 m at 1 m/s: 5e-3 s.
    assert!(msg.contains("at most 5.000e-3 s"), "{msg}");
    let crit = w.critical_dt();
    assert!(msg.contains(&format!("{crit:.3e} s")), "{msg}");
}

#[test]
fn fast_but_resolved_motion_passes() {
    // A disc crossing a tenth of its radius per step is fast but integrated: no stop.
    let mut w = chain(Params::default());
    let v = 0.1 * 0.01 / w.dt();
    w.state.discs.vy[9] = v;
    w.guard().expect("a tenth of the radius per step passes");
}
