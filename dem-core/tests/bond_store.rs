//! The bond store: contact bonds, the strain/force/energy criteria in a running pair, the break
//! log, per-disc stiffness for the time step, remapping after a disc reorder, serialization, and
//! bit-identical results for 1 and 2 threads (with bonds breaking).

use dem_core::bond::bench::bonded_lattice_state;
use dem_core::bond::{
    BondGroup, BondModel, BondStatus, Bonds, BreakMode, ContactBondParams, Criterion,
    ParallelBondParams,
};
use dem_core::State;

const R: f64 = 1e-3;
const T: f64 = 1e-3;

fn pair(model: BondModel, crit: Criterion) -> (State, Bonds) {
    let mut st = State {
        thickness: T,
        ..State::default()
    };
    st.discs.push_uniform(0.0, 0.0, R, 3000.0, T, 0);
    st.discs.push_uniform(2.0 * R, 0.0, R, 3000.0, T, 0);
    let mut b = Bonds::new(vec![BondGroup {
        name: "g".into(),
        model,
        criterion: crit,
    }])
    .unwrap();
    b.add(&st, 0, 1, 0).unwrap();
    (st, b)
}

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

/// Step until the bond breaks; the last intact value of `load`.
fn ramp(st: &mut State, b: &mut Bonds, dt: f64, load: impl Fn(&Bonds) -> f64) -> (f64, BreakMode) {
    let mut last = 0.0;
    for _ in 0..100_000 {
        step(st, b, dt);
        match b.get(0).status {
            BondStatus::Intact => last = load(b),
            BondStatus::Broken(m) => return (last, m),
        }
    }
    panic!("never broke");
}

const CB: BondModel = BondModel::Contact(ContactBondParams { kn: 2e6, ks: 1e6 });

#[test]
fn contact_bond_springs_carry_force_but_no_moment() {
    let force = Criterion::Force {
        tensile: 1e30,
        shear: 1e30,
        moment: f64::INFINITY,
    };
    let (mut st, mut b) = pair(CB, force);
    let dt = 1e-6;
    st.discs.x[1] += 1e-7;
    st.discs.vy[1] = 0.1;
    st.discs.omega[0] = -3.0;
    st.discs.omega[1] = 3.0;
    step(&mut st, &mut b, dt);
    // Fn = −kn δ, Fs = −ks·(v·dt) (the antisymmetric spin moves no contact point), M = 0.
    assert!((st.discs.fx[1] + 2e6 * 1e-7).abs() < 1e-9 * 0.2);
    assert!((st.discs.fy[1] + 1e6 * 0.1 * dt).abs() < 1e-12);
    let arm = R + 0.5e-7; // contact point mid-gap
    assert!((st.discs.torque[1] - arm * 1e6 * 0.1 * dt).abs() < 1e-15);
    assert_eq!(b.get(0).m, 0.0);
    // Energy Fn²/(2kn) + Fs²/(2ks).
    let e = (0.2f64).powi(2) / 4e6 + (0.1f64 * dt * 1e6).powi(2) / 2e6;
    assert!((b.strain_energy() - e).abs() < 1e-9 * e);
}

#[test]
fn contact_bond_breaks_at_its_force_strengths() {
    let crit = Criterion::Force {
        tensile: 3.0,
        shear: 2.0,
        moment: f64::INFINITY,
    };
    let dt = 1e-6;
    let (mut st, mut b) = pair(CB, crit);
    st.discs.vx[1] = 3.0 / 2e6 / 1000.0 / dt;
    let (f, mode) = ramp(&mut st, &mut b, dt, |b| -b.get(0).fn_);
    assert_eq!(mode, BreakMode::Tension);
    assert!(f < 3.0 && f > 0.99 * 3.0, "{f}");
    let (mut st, mut b) = pair(CB, crit);
    st.discs.vy[1] = -2.0 / 1e6 / 1000.0 / dt;
    let (f, mode) = ramp(&mut st, &mut b, dt, |b| b.get(0).fs.abs());
    assert_eq!(mode, BreakMode::Shear);
    assert!(f < 2.0 && f > 0.99 * 2.0, "{f}");
    // A stress criterion makes no sense without a cross-section.
    let stress = Criterion::Stress {
        tensile: 1.0,
        cohesion: 1.0,
        friction_angle: 0.0,
    };
    assert!(Bonds::new(vec![BondGroup {
        name: "c".into(),
        model: CB,
        criterion: stress,
    }])
    .is_err());
}

const PB: BondModel = BondModel::Parallel(ParallelBondParams {
    kn: 1e13,
    ks: 5e12,
    lambda: 1.0,
    beta: 1.0,
});

#[test]
fn strain_criterion_breaks_at_the_critical_stretch() {
    // L = 2R; ε̄c = 1e-4 → opening 2e-7 m, force k̄nĀ·2e-7.
    let crit = Criterion::Strain {
        tensile: 1e-4,
        shear: 1.0,
    };
    let (mut st, mut b) = pair(PB, crit);
    let dt = 1e-6;
    st.discs.vx[1] = 2e-7 / 2000.0 / dt;
    let (f, mode) = ramp(&mut st, &mut b, dt, |b| -b.get(0).fn_);
    let fc = 1e13 * 2.0 * R * T * 2e-7;
    assert_eq!(mode, BreakMode::Tension);
    assert!(f < fc && f > 0.99 * fc, "{f} {fc}");
}

#[test]
fn energy_criterion_breaks_when_strain_energy_reaches_gc_area() {
    // G_c·Ā = F²/(2k̄nĀ) → F = Ā·sqrt(2 k̄n G_c).
    let gc = 0.5;
    let crit = Criterion::Energy {
        fracture_energy: gc,
    };
    let area = 2.0 * R * T;
    let fc = area * (2.0 * 1e13 * gc).sqrt();
    let (mut st, mut b) = pair(PB, crit);
    let dt = 1e-6;
    st.discs.vx[1] = fc / (1e13 * area) / 2000.0 / dt;
    let (f, mode) = ramp(&mut st, &mut b, dt, |b| -b.get(0).fn_);
    assert_eq!(mode, BreakMode::Tension);
    assert!(f < fc && f > 0.99 * fc, "{f} {fc}");
    assert!((b.released_energy() - gc * area).abs() < 0.02 * gc * area);
    // Squeezing does not break it.
    let (mut st, mut b) = pair(PB, crit);
    st.discs.vx[1] = -fc / (1e13 * area) / 200.0 / dt;
    for _ in 0..1000 {
        step(&mut st, &mut b, dt);
    }
    assert_eq!(b.get(0).status, BondStatus::Intact);
    assert!(b.strain_energy() > 10.0 * gc * area);
}

#[test]
fn break_log_records_time_place_group_mode_and_disc_ids() {
    let crit = Criterion::Force {
        tensile: 1.0,
        shear: 1.0,
        moment: f64::INFINITY,
    };
    let (mut st, mut b) = pair(CB, crit);
    // Shift everything by (5, 7): the logged position is the bond centre (contact point).
    for k in 0..2 {
        st.discs.x[k] += 5.0;
        st.discs.y[k] += 7.0;
    }
    st.discs.id = vec![40, 41];
    st.discs.vx[1] = 1e-3;
    let dt = 1e-6;
    ramp(&mut st, &mut b, dt, |_| 0.0);
    let e = &b.log().events[0];
    assert_eq!(
        (e.id_i, e.id_j, e.group, e.mode),
        (40, 41, 0, BreakMode::Tension)
    );
    // Tensile force 1 N at kn = 2e6 → opening 5e-7 m, reached in the step at t = 500 dt.
    assert!((e.time - 500.0 * dt).abs() < 1.5 * dt, "{}", e.time);
    assert!((e.x - (5.0 + R + 0.25e-6)).abs() < 1e-8 && (e.y - 7.0).abs() < 1e-12);
    let csv = b.log().to_csv(&b.group_names());
    assert!(csv.lines().nth(1).unwrap().contains(",g,tension,40,41,"));
}

#[test]
fn stiffness_for_the_time_step() {
    let (st, b) = pair(
        PB,
        Criterion::Strain {
            tensile: 1.0,
            shear: 1.0,
        },
    );
    let mut kt = vec![0.0; 2];
    let mut kr = vec![0.0; 2];
    b.add_stiffness(&st, &mut kt, &mut kr);
    let area = 2.0 * R * T;
    let inertia = 2.0 / 3.0 * R.powi(3) * T;
    assert!((kt[0] - 1e13 * area).abs() < 1e-9 * kt[0]);
    let krot = 1e13 * inertia + 5e12 * area * R * R;
    assert!((kr[1] - krot).abs() < 1e-9 * krot);
}

#[test]
fn install_skips_existing_pairs_and_rigid_clump_members() {
    let mut st = State::default();
    for k in 0..4 {
        st.discs.push_uniform(2.0 * k as f64, 0.0, 1.0, 1.0, 1.0, 0);
    }
    st.discs.body[2] = 0;
    st.discs.body[3] = 0;
    let mut b = Bonds::new(vec![BondGroup {
        name: "g".into(),
        model: CB,
        criterion: Criterion::Force {
            tensile: 1.0,
            shear: 1.0,
            moment: f64::INFINITY,
        },
    }])
    .unwrap();
    b.add(&st, 1, 0, 0).unwrap();
    let added = b.install_at_contacts(&st, 1e-9, 0).unwrap();
    // Pairs (0,1) exists, (1,2) is new, (2,3) is inside one rigid clump.
    assert_eq!(added, 1);
    assert_eq!(b.len(), 2);
    assert!(b.install_at_contacts(&st, 1e-9, 7).is_ok()); // nothing left to add
}

fn shake(st: &mut State) {
    let mut s = 99u64;
    let d = &mut st.discs;
    for k in 0..d.len() {
        let mut r = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            2.0 * ((s >> 11) as f64 / (1u64 << 53) as f64) - 1.0
        };
        d.vx[k] = 0.02 * r();
        d.vy[k] = 0.02 * r();
        d.omega[k] = 40.0 * r();
    }
}

/// Leapfrog with the bond stage only.
fn run(st: &mut State, b: &mut Bonds, steps: usize, dt: f64) {
    for _ in 0..steps {
        st.discs.clear_forces();
        b.compute(st, dt);
        let d = &mut st.discs;
        for k in 0..d.len() {
            d.vx[k] += d.fx[k] / d.m[k] * dt;
            d.vy[k] += d.fy[k] / d.m[k] * dt;
            d.omega[k] += d.torque[k] / d.inertia[k] * dt;
            d.x[k] = st.periodic.wrap(0, d.x[k] + d.vx[k] * dt);
            d.y[k] = st.periodic.wrap(1, d.y[k] + d.vy[k] * dt);
            d.theta[k] += d.omega[k] * dt;
        }
        st.time += dt;
        st.step += 1;
    }
}

fn weak_lattice() -> (State, Bonds) {
    // 60 × 30 cells = 3600 discs, 10,800 bonds: above the parallel threshold.
    let (mut st, b) = bonded_lattice_state([60, 30]);
    let mut g = b.groups()[0].clone();
    g.criterion = Criterion::Stress {
        tensile: 1e4,
        cohesion: 1.2e4,
        friction_angle: 0.3,
    };
    let mut weak = Bonds::new(vec![g]).unwrap();
    weak.install_at_contacts(&st, 1e-5, 0).unwrap();
    shake(&mut st);
    (st, weak)
}

#[test]
fn one_and_two_threads_give_identical_bytes_with_breaks() {
    let go = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| {
            let (mut st, mut b) = weak_lattice();
            run(&mut st, &mut b, 300, 2e-7);
            (
                serde_json::to_string(&st).unwrap(),
                serde_json::to_string(&b).unwrap(),
                b.log().len(),
            )
        })
    };
    let (s1, b1, n1) = go(1);
    let (s2, b2, n2) = go(2);
    assert!(n1 > 10 && n1 < 5_000, "breaks {n1}");
    eprintln!("{n1} of 10800 bonds broke");
    assert_eq!(n1, n2);
    assert!(s1 == s2, "state differs");
    assert!(b1 == b2, "bonds differ");
}

#[test]
fn remap_follows_a_disc_reorder() {
    let (mut st, mut b) = weak_lattice();
    run(&mut st, &mut b, 50, 2e-7);
    let mut st2 = st.clone();
    let mut b2 = b.clone();
    // Reverse the discs.
    let n = st.discs.len();
    let order: Vec<u32> = (0..n as u32).rev().collect();
    st2.discs.permute(&order);
    let mut new_of_old = vec![0u32; n];
    for (new, &old) in order.iter().enumerate() {
        new_of_old[old as usize] = new as u32;
    }
    b2.remap(&new_of_old);
    run(&mut st, &mut b, 1, 2e-7);
    run(&mut st2, &mut b2, 1, 2e-7);
    // Same bonds (by id) with the same forces, same disc forces (to rounding: sums reorder).
    let by_id = |b: &Bonds| {
        let mut v: Vec<_> = b.iter().map(|v| (v.id, v.fn_, v.fs, v.m)).collect();
        v.sort_by_key(|t| t.0);
        v
    };
    assert_eq!(by_id(&b), by_id(&b2));
    for (old, &new) in new_of_old.iter().enumerate() {
        let new = new as usize;
        let (a, c) = (st.discs.fx[old], st2.discs.fx[new]);
        assert!((a - c).abs() <= 1e-9 * a.abs().max(1e-6), "{a} {c}");
    }
    // The store is sorted by smaller disc index after the remap.
    let keys: Vec<u32> = b2.iter().map(|v| v.i.min(v.j)).collect();
    assert!(keys.windows(2).all(|w| w[0] <= w[1]));
}

#[test]
fn serde_round_trip_continues_identically() {
    let (mut st, mut b) = weak_lattice();
    run(&mut st, &mut b, 100, 2e-7);
    let text = serde_json::to_string(&b).unwrap();
    let mut b2: Bonds = serde_json::from_str(&text).unwrap();
    assert_eq!(b, b2);
    let mut st2 = st.clone();
    run(&mut st, &mut b, 100, 2e-7);
    run(&mut st2, &mut b2, 100, 2e-7);
    assert_eq!(st, st2);
    assert_eq!(b, b2);
}

#[test]
fn fast_and_general_kernel_paths_agree_bitwise() {
    // Same lattice and parameters; in the second run every other bond belongs to an identical
    // second group, so no block qualifies for the one-group fast path.
    let run_with = |split: bool| {
        let (mut st, b) = bonded_lattice_state([20, 12]);
        let g = b.groups()[0].clone();
        let mut g2 = g.clone();
        g2.name = "copy".into();
        let mut weak = Bonds::new(vec![g, g2]).unwrap();
        let mut k = 0u16;
        weak.install_within_gap(&st, 1e-5, |_, _| {
            k += 1;
            Some(if split { k % 2 } else { 0 })
        })
        .unwrap();
        shake(&mut st);
        run(&mut st, &mut weak, 200, 2e-7);
        let forces: Vec<(f64, f64, f64)> = weak.iter().map(|v| (v.fn_, v.fs, v.m)).collect();
        (st, forces)
    };
    let (s1, f1) = run_with(false);
    let (s2, f2) = run_with(true);
    assert!(f1.iter().any(|f| f.0 != 0.0));
    assert_eq!(f1, f2);
    assert_eq!(s1, s2);
}
