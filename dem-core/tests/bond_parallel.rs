//! Two-disc parallel bond (Potyondy & Cundall 2004) against its closed forms: axial, shear and
//! bending stiffness; rigid rotation leaves it unloaded; work equals strain energy; it breaks at
//! the analytic load in pure tension, pure shear (with and without compression) and pure bending.
//! Motions are imposed (kinematic): positions at t, velocities v with x += v·dt after the bond
//! stage, as in the solver's central-difference scheme.

use dem_core::bond::{
    BondGroup, BondModel, BondStatus, Bonds, BreakMode, Criterion, ParallelBondParams,
};
use dem_core::State;

const R: f64 = 1e-3;
const T: f64 = 2e-3;
const KN: f64 = 4e12; // Pa/m
const KS: f64 = 1.5e12;

fn group(crit: Criterion, lambda: f64, beta: f64) -> BondGroup {
    BondGroup {
        name: "pb".into(),
        model: BondModel::Parallel(ParallelBondParams {
            kn: KN,
            ks: KS,
            lambda,
            beta,
        }),
        criterion: crit,
    }
}

fn strong() -> Criterion {
    Criterion::Stress {
        tensile: 1e30,
        cohesion: 1e30,
        friction_angle: 0.0,
    }
}

/// Discs of radius R at (0,0) and (2R + gap, 0), bonded.
fn pair(crit: Criterion, lambda: f64, beta: f64, gap: f64) -> (State, Bonds) {
    let mut st = State {
        thickness: T,
        ..State::default()
    };
    st.discs.push_uniform(0.0, 0.0, R, 3000.0, T, 0);
    st.discs.push_uniform(2.0 * R + gap, 0.0, R, 3000.0, T, 0);
    let mut b = Bonds::new(vec![group(crit, lambda, beta)]).unwrap();
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

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * b.abs().max(1e-300)
}

#[test]
fn axial_stiffness_is_kn_area() {
    let lambda = 0.8;
    let (mut st, mut b) = pair(strong(), lambda, 1.0, 0.0);
    let rbar = lambda * R;
    let area = 2.0 * rbar * T;
    for delta in [1e-7, -3e-8] {
        st.discs.x[1] = 2.0 * R + delta;
        st.discs.clear_forces();
        b.compute(&mut st, 1e-6);
        // Opening δ pulls disc 1 back (−x) with k̄nĀδ, disc 0 forward; no torque.
        let f = KN * area * delta;
        assert!(
            close(st.discs.fx[1], -f, 1e-9),
            "{} vs {}",
            st.discs.fx[1],
            -f
        );
        assert!(close(st.discs.fx[0], f, 1e-9));
        assert_eq!(st.discs.fy[1], 0.0);
        assert_eq!(st.discs.torque[0], 0.0);
        assert_eq!(st.discs.torque[1], 0.0);
        assert!(close(b.get(0).fn_, -f, 1e-9));
        // Strain energy F²/(2k̄nĀ) = k̄nĀδ²/2.
        assert!(close(
            b.strain_energy(),
            0.5 * KN * area * delta * delta,
            1e-9
        ));
    }
}

#[test]
fn bending_stiffness_is_kn_inertia() {
    let (mut st, mut b) = pair(strong(), 1.0, 1.0, 0.0);
    let inertia = 2.0 / 3.0 * R * R * R * T;
    let (w, dt) = (0.3, 1e-6);
    st.discs.omega[0] = -w;
    st.discs.omega[1] = w;
    let n = 50;
    for _ in 0..n {
        step(&mut st, &mut b, dt);
    }
    // Relative rotation θ = 2wΔt·n; M̄ = −k̄nĪθ on disc 1, +k̄nĪθ on disc 0; antisymmetric
    // rotation of equal discs moves the contact point of neither: no shear force.
    let theta = st.discs.theta[1] - st.discs.theta[0];
    let m = KN * inertia * theta;
    assert!(
        close(st.discs.torque[1], -m, 1e-9),
        "{} {}",
        st.discs.torque[1],
        -m
    );
    assert!(close(st.discs.torque[0], m, 1e-9));
    assert!(b.get(0).fs.abs() < 1e-12 * m / R);
    assert!(st.discs.fx[1].abs() < 1e-9 * m / R && st.discs.fy[1].abs() < 1e-9 * m / R);
}

#[test]
fn shear_stiffness_and_contact_point_torques() {
    let (mut st, mut b) = pair(strong(), 1.0, 1.0, 0.0);
    let area = 2.0 * R * T;
    let (v, dt) = (1e-3, 1e-7);
    st.discs.vy[1] = v;
    step(&mut st, &mut b, dt);
    // Disc 1 moved up by v·dt (the increment of the step): F̄s = −k̄sĀ v dt on disc 1 along
    // t̂ = +y; torque −a F̄s on both discs (a = R: the contact point is at the rim).
    let fs = -KS * area * v * dt;
    assert!(close(st.discs.fy[1], fs, 1e-12));
    assert!(close(st.discs.fy[0], -fs, 1e-12));
    assert!(close(st.discs.torque[1], -R * fs, 1e-12));
    assert!(close(st.discs.torque[0], -R * fs, 1e-12));
    // Spinning disc 0 alone moves its contact point by ω_0·R·dt along +y: same shear as
    // moving disc 1 down by that much, plus a bending moment.
    let (mut st, mut b) = pair(strong(), 1.0, 1.0, 0.0);
    let w = 2.0;
    st.discs.omega[0] = w;
    step(&mut st, &mut b, dt);
    assert!(close(b.get(0).fs, KS * area * w * R * dt, 1e-12));
    let inertia = 2.0 / 3.0 * R * R * R * T;
    assert!(close(b.get(0).m, KN * inertia * w * dt, 1e-12));
}

#[test]
fn rigid_rotation_of_the_pair_loads_nothing() {
    // Pair spinning about its midpoint at w for a quarter turn: the bond turns with it.
    let (mut st, mut b) = pair(strong(), 1.0, 1.0, 0.0);
    let (w, n) = (100.0, 20000);
    let dt = std::f64::consts::FRAC_PI_2 / w / n as f64;
    for _ in 0..n {
        // Velocities of a rigid rotation about the midpoint (for the step about to happen:
        // leapfrog mid-step velocities, so positions stay on the circle to O(dt²)).
        let (cx, cy) = (
            0.5 * (st.discs.x[0] + st.discs.x[1]),
            0.5 * (st.discs.y[0] + st.discs.y[1]),
        );
        for k in 0..2 {
            st.discs.vx[k] = -w * (st.discs.y[k] - cy);
            st.discs.vy[k] = w * (st.discs.x[k] - cx);
            st.discs.omega[k] = w;
        }
        step(&mut st, &mut b, dt);
    }
    let f = b.get(0);
    let scale = KN * 2.0 * R * T * 1e-9; // force of a 1 nm stretch
    assert!(f.fs.abs() < 1e-3 * scale, "shear {}", f.fs);
    assert_eq!(f.m, 0.0);
    assert!(
        st.discs.y[1] > 0.99 * R,
        "turned a quarter: {}",
        st.discs.y[1]
    );
}

#[test]
fn work_of_the_bond_forces_equals_its_strain_energy() {
    // Mixed motion: stretch, shear, spin; the work the discs do against the bond forces
    // (force × displacement, torque × rotation) equals the stored energy up to O(dt).
    let (mut st, mut b) = pair(strong(), 0.7, 1.0, 1e-5);
    st.discs.vx[1] = 2e-3;
    st.discs.vy[1] = -1e-3;
    st.discs.omega[0] = 0.5;
    st.discs.omega[1] = -1.2;
    let dt = 1e-8;
    let mut work = 0.0;
    for _ in 0..2000 {
        step(&mut st, &mut b, dt);
        let d = &st.discs;
        for k in 0..2 {
            work -= (d.fx[k] * d.vx[k] + d.fy[k] * d.vy[k] + d.torque[k] * d.omega[k]) * dt;
        }
    }
    let u = b.strain_energy();
    assert!(u > 0.0);
    assert!(close(work, u, 2e-3), "work {work} energy {u}");
}

/// Ramp an imposed motion until the bond breaks; return (load at the last intact step, load
/// in the step that broke it, mode).
fn ramp(
    st: &mut State,
    b: &mut Bonds,
    dt: f64,
    load: impl Fn(&Bonds) -> f64,
) -> (f64, f64, BreakMode) {
    let mut last = 0.0;
    for _ in 0..1_000_000 {
        step(st, b, dt);
        match b.get(0).status {
            BondStatus::Intact => last = load(b),
            BondStatus::Broken(mode) => {
                let e = &b.log().events[0];
                return (last, e.energy, mode);
            }
        }
    }
    panic!("bond never broke");
}

#[test]
fn breaks_at_the_analytic_tensile_load() {
    let sc = 5e6;
    let crit = Criterion::Stress {
        tensile: sc,
        cohesion: 1e30,
        friction_angle: 0.0,
    };
    let (mut st, mut b) = pair(crit, 1.0, 1.0, 0.0);
    let area = 2.0 * R * T;
    let fc = sc * area;
    // Opening speed: the critical stretch σ̄c/k̄n in ~2000 steps.
    let dt = 1e-6;
    st.discs.vx[1] = sc / KN / 2000.0 / dt;
    let (f_last, energy, mode) = ramp(&mut st, &mut b, dt, |b| -b.get(0).fn_);
    assert_eq!(mode, BreakMode::Tension);
    assert!(f_last < fc && f_last > 0.99 * fc, "{f_last} vs {fc}");
    // Energy released ≈ F²/(2k̄nĀ) at the break load; forces gone afterwards.
    assert!(close(energy, fc * fc / (2.0 * KN * area), 0.01));
    assert_eq!(b.get(0).fn_, 0.0);
    assert!(close(b.released_energy(), energy, 1e-12));
    assert_eq!(b.strain_energy(), 0.0);
    st.discs.clear_forces();
    b.compute(&mut st, dt);
    assert_eq!(st.discs.fx[1], 0.0);
    assert_eq!(b.broken_counts(), &[[1, 0]]);
}

#[test]
fn breaks_at_the_analytic_shear_load_with_mohr_coulomb_compression() {
    let c = 8e6;
    let phi: f64 = 0.6;
    let area = 2.0 * R * T;
    for sigma_n in [0.0, 4e6] {
        let crit = Criterion::Stress {
            tensile: 1e30,
            cohesion: c,
            friction_angle: phi,
        };
        // Precompress by σn (overlap σn/k̄n), then shear: τ̄c = c̄ + σn tan φ̄.
        let (mut st, mut b) = pair(crit, 1.0, 1.0, 0.0);
        st.discs.x[1] -= sigma_n / KN;
        let tau_c = c + sigma_n * phi.tan();
        let dt = 1e-6;
        st.discs.vy[1] = tau_c / KS / 3000.0 / dt;
        let (f_last, _, mode) = ramp(&mut st, &mut b, dt, |b| b.get(0).fs.abs());
        assert_eq!(mode, BreakMode::Shear);
        let fc = tau_c * area;
        assert!(
            f_last < fc && f_last > 0.99 * fc,
            "σn {sigma_n}: {f_last} vs {fc}"
        );
    }
}

#[test]
fn breaks_at_the_analytic_bending_moment() {
    let sc = 3e6;
    let crit = Criterion::Stress {
        tensile: sc,
        cohesion: 1e30,
        friction_angle: 0.0,
    };
    for (lambda, beta) in [(1.0, 1.0), (0.5, 0.6)] {
        let (mut st, mut b) = pair(crit, lambda, beta, 0.0);
        let rbar = lambda * R;
        let inertia = 2.0 / 3.0 * rbar.powi(3) * T;
        // σ̄ = β̄|M̄|R̄/Ī = σ̄c.
        let mc = sc * inertia / (beta * rbar);
        let dt = 1e-6;
        let w = mc / (KN * inertia) / 2.0 / 2000.0 / dt;
        st.discs.omega[0] = -w;
        st.discs.omega[1] = w;
        let (m_last, _, mode) = ramp(&mut st, &mut b, dt, |b| b.get(0).m.abs());
        assert_eq!(mode, BreakMode::Tension);
        assert!(m_last < mc && m_last > 0.99 * mc, "{m_last} vs {mc}");
    }
}

#[test]
fn bond_installed_across_a_gap_or_overlap_starts_force_free() {
    for gap in [2e-5, -3e-5] {
        let (mut st, mut b) = pair(strong(), 1.0, 1.0, gap);
        assert!(close(b.get(0).g0, gap, 1e-9));
        st.discs.clear_forces();
        b.compute(&mut st, 1e-6);
        assert!(st.discs.fx[1].abs() < 1e-3 * KN * 2.0 * R * T * 1e-15);
    }
}

#[test]
fn rejects_bad_input() {
    let (st, mut b) = pair(strong(), 1.0, 1.0, 0.0);
    assert!(b.add(&st, 0, 0, 0).is_err());
    assert!(b.add(&st, 0, 5, 0).is_err());
    assert!(b.add(&st, 0, 1, 3).is_err());
    let mut bad = group(strong(), 1.0, 1.0);
    bad.model = BondModel::Parallel(ParallelBondParams {
        kn: -1.0,
        ks: 1.0,
        lambda: 1.0,
        beta: 1.0,
    });
    assert!(Bonds::new(vec![bad]).is_err());
    assert!(Bonds::new(vec![group(strong(), 1.0, 1.0), group(strong(), 1.0, 1.0)]).is_err());
}
