//! Two-disc flat joint (Potyondy 2012) in the bond stage: an intact interface moves the discs
//! exactly as a parallel bond of the same k̄n, k̄s, R̄ does; its elements break one by one and
//! the bond leaves the stage (logged once) when the last one breaks; its state survives a
//! checkpoint; scene groups name their fields. The law's closed forms are tested in
//! `dem_core::bond::flat_joint`. Motions are imposed as in `bond_parallel.rs`.

use dem_core::bond::{
    BondGroup, BondModel, BondStatus, Bonds, BreakMode, Criterion, FlatJointParams,
    ParallelBondParams,
};
use dem_core::State;

const R: f64 = 1e-3;
const T: f64 = 2e-3;
const KN: f64 = 4e12; // Pa/m
const KS: f64 = 1.5e12;

fn stress(tensile: f64, cohesion: f64) -> Criterion {
    Criterion::Stress {
        tensile,
        cohesion,
        friction_angle: 0.5,
    }
}

fn flat_joint(elements: u8, crit: Criterion) -> BondGroup {
    BondGroup {
        name: "fj".into(),
        model: BondModel::FlatJoint(FlatJointParams {
            kn: KN,
            ks: KS,
            lambda: 0.8,
            elements,
            friction: 0.4,
            bonded_fraction: 1.0,
        }),
        criterion: crit,
    }
}

/// Discs of radius R at (0,0) and (2R, 0), bonded with `group`.
fn pair(group: BondGroup) -> (State, Bonds) {
    let mut st = State {
        thickness: T,
        ..State::default()
    };
    st.discs.push_uniform(0.0, 0.0, R, 3000.0, T, 0);
    st.discs.push_uniform(2.0 * R, 0.0, R, 3000.0, T, 0);
    let mut b = Bonds::new(vec![group]).unwrap();
    b.add(&st, 0, 1, 0).unwrap();
    (st, b)
}

/// One kinematic step: bond stage at the current positions/velocities, then x += v·dt.
fn step(st: &mut State, b: &mut Bonds, dt: f64) {
    st.discs.clear_forces();
    b.compute(st, dt);
    let d = &mut st.discs;
    for k in 0..d.len() {
        d.x[k] += d.vx[k] * dt;
        d.y[k] += d.vy[k] * dt;
        d.theta[k] += d.omega[k] * dt;
    }
    st.time += dt;
    st.step += 1;
}

/// A motion of disc 1 mixing approach, sliding and turning, changing over the steps.
fn drive(st: &mut State, k: usize) {
    let s = (k as f64 * 0.05).sin();
    st.discs.vx[1] = -0.2 * s;
    st.discs.vy[1] = 0.3 * (1.0 + s);
    st.discs.omega[1] = 400.0 * s - 100.0;
    st.discs.omega[0] = 50.0;
}

#[test]
fn an_intact_flat_joint_moves_the_discs_as_a_parallel_bond() {
    let strong = stress(1e30, 1e30);
    let pb = BondGroup {
        name: "pb".into(),
        model: BondModel::Parallel(ParallelBondParams {
            kn: KN,
            ks: KS,
            lambda: 0.8,
            beta: 1.0,
        }),
        criterion: strong,
    };
    for elements in [1, 2, 5] {
        let (mut s1, mut b1) = pair(flat_joint(elements, strong));
        let (mut s2, mut b2) = pair(pb.clone());
        let dt = 1e-8;
        let mut scale = 0.0f64;
        for k in 0..200 {
            drive(&mut s1, k);
            drive(&mut s2, k);
            step(&mut s1, &mut b1, dt);
            step(&mut s2, &mut b2, dt);
            let (d1, d2) = (&s1.discs, &s2.discs);
            scale = scale.max(d2.fx[1].abs()).max(d2.fy[1].abs());
            for (a, b) in [(d1.fx[1], d2.fx[1]), (d1.fy[1], d2.fy[1])] {
                assert!(
                    (a - b).abs() <= 1e-9 * scale,
                    "N {elements}, step {k}: {a} vs {b}"
                );
            }
            let tscale = d2.torque[1].abs().max(d2.torque[0].abs()).max(1e-30);
            for (a, b) in [(d1.torque[0], d2.torque[0]), (d1.torque[1], d2.torque[1])] {
                assert!(
                    (a - b).abs() <= 1e-9 * tscale,
                    "N {elements}, step {k}: {a} vs {b}"
                );
            }
        }
        assert!(scale > 1.0, "the motion loaded the bond: {scale} N");
        let (e1, e2) = (b1.strain_energy(), b2.strain_energy());
        assert!((e1 - e2).abs() <= 1e-9 * e2, "energy {e1} vs {e2}");
        assert_eq!(b1.get(0).status, BondStatus::Intact);
    }
}

#[test]
fn elements_break_one_by_one_and_the_bond_leaves_at_the_last() {
    // Bending disc 1 counter-clockwise opens the side s < 0: with 2 elements, element 0 holds
    // the tension. Edge stress k̄n θ R̄ reaches σc at θ = σc/(k̄n R̄).
    let rbar = 0.8 * R;
    let sigma_c = 2e6;
    let (mut st, mut b) = pair(flat_joint(2, stress(sigma_c, 1e30)));
    let dt = 1e-8;
    let th_break = sigma_c / (KN * rbar);
    st.discs.omega[1] = th_break / (50.5 * dt);
    let mut broke_at = None;
    for k in 0..60 {
        step(&mut st, &mut b, dt);
        let fj = b.flat_joint(0).expect("a flat joint");
        if fj.bonded_count() == 1 && broke_at.is_none() {
            broke_at = Some(k);
        }
    }
    // θ after step k (the bond stage sees k+1 increments): breaks at the 51st step.
    assert_eq!(broke_at, Some(50));
    assert_eq!(
        b.get(0).status,
        BondStatus::Intact,
        "one element still bonded"
    );
    assert_eq!(b.log().len(), 0, "a partial break is not a bond break");
    // The moment is now carried by element 1 alone (element 0 is open).
    let th = b.flat_joint(0).unwrap().theta;
    let m_expected = -KN * T * th * rbar.powi(3) / 3.0;
    assert!(
        (b.get(0).m - m_expected).abs() <= 1e-9 * m_expected.abs(),
        "{} vs {m_expected}",
        b.get(0).m
    );
    // Pulling the discs apart breaks the last element in tension: the bond leaves, logged once.
    st.discs.omega[1] = 0.0;
    // (Element 1's open edge s = 0 reaches σc at δ = σc/k̄n = 5e-7 m: the 5th step.)
    st.discs.vx[1] = 10.0;
    for _ in 0..20 {
        step(&mut st, &mut b, dt);
    }
    assert_eq!(b.get(0).status, BondStatus::Broken(BreakMode::Tension));
    assert_eq!(b.log().len(), 1);
    assert_eq!(b.broken_counts()[0], [1, 0]);
    let v = b.get(0);
    assert_eq!([v.fn_, v.fs, v.m], [0.0; 3]);
}

/// Potyondy (2012): an interface whose elements all broke while pressed together stays a
/// frictional flat contact: the break is logged once (and the bond no longer counts as
/// intact), yet the interface keeps carrying compression, friction and a moment against
/// rolling, until the discs separate; then it leaves without a second log entry.
#[test]
fn a_broken_interface_in_contact_stays_a_frictional_contact_until_it_opens() {
    let (mut st, mut b) = pair(flat_joint(2, stress(1e30, 1e5)));
    let dt = 1e-8;
    // Press (δ = −2e-8 m), then slide: every element breaks in shear (cohesion 0.1 MPa).
    st.discs.vx[1] = -1.0;
    for _ in 0..2 {
        step(&mut st, &mut b, dt);
    }
    st.discs.vx[1] = 0.0;
    st.discs.vy[1] = 5.0;
    for _ in 0..5 {
        step(&mut st, &mut b, dt);
    }
    let fj = *b.flat_joint(0).unwrap();
    assert_eq!(fj.bonded, 0, "every element broke");
    assert!(fj.logged);
    assert_eq!(b.log().len(), 1);
    assert_eq!(b.broken_counts()[0], [0, 1]);
    assert_eq!(b.n_intact(), 0);
    assert_eq!(b.get(0).status, BondStatus::Broken(BreakMode::Shear));
    let v = b.get(0);
    assert!(v.fn_ > 0.0, "still pressed: {}", v.fn_);
    assert!(
        (v.fs.abs() - 0.4 * v.fn_).abs() <= 1e-9 * v.fn_,
        "sliding at μ F_n: {} vs {}",
        v.fs,
        v.fn_
    );
    // Rolling disc 1 meets the moment of the compressed part (half the interface closes).
    st.discs.vy[1] = 0.0;
    st.discs.omega[1] = 2.0;
    step(&mut st, &mut b, dt);
    assert!(b.get(0).m < 0.0, "resists rolling: M = {}", b.get(0).m);
    // Separating: the interface leaves, no second entry.
    st.discs.omega[1] = 0.0;
    st.discs.vx[1] = 10.0;
    for _ in 0..5 {
        step(&mut st, &mut b, dt);
    }
    let v = b.get(0);
    assert_eq!([v.fn_, v.fs, v.m], [0.0; 3]);
    assert_eq!(b.log().len(), 1);
    assert_eq!(b.broken_counts()[0], [0, 1]);
    assert_eq!(v.status, BondStatus::Broken(BreakMode::Shear));
}

#[test]
fn the_interface_survives_a_checkpoint_and_bad_state_is_refused() {
    let (mut st, mut b) = pair(flat_joint(3, stress(1e30, 1e30)));
    for k in 0..30 {
        drive(&mut st, k);
        step(&mut st, &mut b, 1e-8);
    }
    let text = serde_json::to_string(&b).unwrap();
    assert!(text.contains("\"fj\""), "the interface state is written");
    let back: Bonds = serde_json::from_str(&text).unwrap();
    assert_eq!(back, b);
    back.check_restored(2).unwrap();
    // Continuing from the copy gives the same bits.
    let (mut st2, mut b2) = (st.clone(), back);
    for k in 30..40 {
        drive(&mut st, k);
        drive(&mut st2, k);
        step(&mut st, &mut b, 1e-8);
        step(&mut st2, &mut b2, 1e-8);
    }
    assert_eq!(st, st2);
    assert_eq!(b, b2);
    // Element bits beyond the group's 3 elements: refused with the bond named.
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["fj"][0]["bonded"] = 0b1111.into();
    let bad: Bonds = serde_json::from_value(v).unwrap();
    let e = bad.check_restored(2).unwrap_err().to_string();
    assert!(e.contains("bond 0") && e.contains("flat-joint"), "{e}");
    // A store without the states: refused.
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v.as_object_mut().unwrap().remove("fj");
    let bad: Bonds = serde_json::from_value(v).unwrap();
    let e = bad.check_restored(2).unwrap_err().to_string();
    assert!(e.contains("0 flat-joint states for 1 bonds"), "{e}");
}

#[test]
fn a_flat_joint_group_needs_the_stress_criterion() {
    let g = flat_joint(
        2,
        Criterion::Force {
            tensile: 1.0,
            shear: 1.0,
            moment: f64::INFINITY,
        },
    );
    let e = Bonds::new(vec![g]).unwrap_err().to_string();
    assert!(e.contains("`fj`") && e.contains("stress"), "{e}");
}

/// Determinism: a lattice of flat joints large enough for the bond stage's parallel path
/// (≥ 8,192 bonds) gives the same bits on one and two threads.
#[test]
fn a_flat_joint_lattice_is_bit_identical_on_one_and_two_threads() {
    use dem_core::bond::bench::{bonded_lattice_with, lattice_flat_joint_group};
    let run = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let mut w = bonded_lattice_with(Some([50, 30]), &|t| lattice_flat_joint_group(t, 3));
            for _ in 0..40 {
                w.step();
            }
            w
        })
    };
    let (a, b) = (run(1), run(2));
    let bonds = a.bonds.as_ref().unwrap();
    assert!(bonds.len() >= 8192, "{} bonds", bonds.len());
    assert!(bonds.flat_joint(0).is_some());
    assert!(a.state.discs.fx.iter().any(|&f| f != 0.0));
    assert_eq!(a.state, b.state);
    assert_eq!(a.bonds, b.bonds);
}
