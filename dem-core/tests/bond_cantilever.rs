//! A bonded-disc cantilever (a straight chain of discs joined by parallel bonds, the first disc
//! clamped) under a tip load: the static tip deflection equals Euler–Bernoulli's
//! δ = P L³/(3 E I) with the bond's bending stiffness per unit length, E I = k̄n Ī · L_b
//! (a bond is a rotational spring k̄n Ī over one disc spacing L_b; L = n L_b for n bonds).
//!
//! The tip load P is a constant external force on the tip disc; the deflection is the tip
//! disc's displacement. Local damping (α = 0.7) brings the chain to rest. The discrete chain differs from the continuum beam by
//! −1/(4n²) (rotational springs at the bond midpoints) plus the bonds' shear compliance
//! n P/(k̄s Ā), both under 1 % here; the deflection is also checked against that discrete
//! closed form (0.01 %).

use dem_core::bond::{
    world_with_bonds, BondGroup, BondModel, Bonds, Criterion, ParallelBondParams,
};
use dem_core::contact::LinearSpringDashpot;
use dem_core::pipeline::ExternalLoad;
use dem_core::{ContactLaws, ContactModel, Params, State};

const R: f64 = 1e-3;
const T: f64 = 1e-3;
const KN: f64 = 1e13;
const KS: f64 = 4e12;

#[test]
fn tip_deflection_matches_euler_bernoulli() {
    let n = 10; // bonds
    let gap = 1e-3 * R; // chain discs do not touch: only the bonds act between them
    let lb = 2.0 * R + gap;
    let mut st = State {
        thickness: T,
        ..State::default()
    };
    for k in 0..=n {
        st.discs.push_uniform(k as f64 * lb, 0.0, R, 3000.0, T, 0);
    }
    st.discs.fixed[0] = true;
    let mut bonds = Bonds::new(vec![BondGroup {
        name: "beam".into(),
        model: BondModel::Parallel(ParallelBondParams {
            kn: KN,
            ks: KS,
            lambda: 1.0,
            beta: 1.0,
        }),
        criterion: Criterion::Stress {
            tensile: 1e12,
            cohesion: 1e12,
            friction_angle: 0.0,
        },
    }])
    .unwrap();
    for k in 0..n {
        bonds.add(&st, k, k + 1, 0).unwrap();
    }
    let inertia = 2.0 / 3.0 * R.powi(3) * T;
    let ei = KN * inertia * lb;
    let l = n as f64 * lb;
    let laws = ContactLaws::uniform(ContactModel::Linear(LinearSpringDashpot::elastic(
        1e6, 1e6, 0.0,
    )));
    let params = Params {
        local_damping: 0.7,
        dt_factor: 0.3,
        ..Params::default()
    };
    let mut w = world_with_bonds(st, params, laws, bonds, &[]).unwrap();
    let tip = w.index_of_id(n as u32).unwrap();
    let y0 = w.state.discs.y[tip];
    let p = 1e-2; // N, upwards
    w.loads.push(ExternalLoad {
        id: n as u32,
        force: [0.0, p],
        torque: 0.0,
    });
    let steps = 200_000;
    w.run(steps);
    let tip = w.index_of_id(n as u32).unwrap();
    let delta = w.state.discs.y[tip] - y0;
    assert!(w.check().is_ok());
    assert!(delta > 0.0, "δ {delta}");
    // At rest: the tip velocity and the wall force no longer change.
    assert!(w.state.discs.vy[tip].abs() * w.dt() < 1e-6 * delta);
    let eb = p * l.powi(3) / (3.0 * ei);
    let err = delta / eb - 1.0;
    eprintln!("cantilever: P = {p:.4e} N, δ = {delta:.5e} m, PL³/(3EI) = {eb:.5e} m, error {:.3} %, dt {:.3e}", 100.0 * err, w.dt());
    assert!(err.abs() < 0.02, "error {err}");
    // The discrete chain exactly: rotational springs k̄nĪ at the bond midpoints
    // x_k = (k + ½)L_b give P L_b² Σ(n − k − ½)²/(k̄nĪ) = P L_b² (n³/3 − n/12)/(k̄nĪ); each bond's
    // shear spring adds P/(k̄sĀ).
    let nf = n as f64;
    let area = 2.0 * R * T;
    let discrete =
        p * (lb * lb * (nf.powi(3) / 3.0 - nf / 12.0) / (KN * inertia) + nf / (KS * area));
    eprintln!(
        "discrete chain: {discrete:.5e} m, error {:.4} %",
        100.0 * (delta / discrete - 1.0)
    );
    assert!((delta / discrete - 1.0).abs() < 1e-4);
}
