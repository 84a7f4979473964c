//! A bonded-disc cantilever (a straight chain of discs joined by parallel bonds, the first disc
//! clamped) under a tip load: the static tip deflection equals Euler–Bernoulli's
//! δ = P L³/(3 E I) with the bond's bending stiffness per unit length, E I = k̄n Ī · L_b
//! (a bond is a rotational spring k̄n Ī over one disc spacing L_b; L = n L_b for n bonds).
//!
//! The tip load is applied by a frictionless wall pressed against the tip disc; the load P is
//! the wall's recorded reaction, the deflection the tip disc's displacement. Local damping
//! (α = 0.7) brings the chain to rest. The discrete chain differs from the continuum beam by
//! −1/(4n²) (rotational springs at the bond midpoints) plus the bonds' shear compliance
//! n P/(k̄s Ā), both well under 1 % here.

use dem_core::bond::{
    world_with_bonds, BondGroup, BondModel, Bonds, Criterion, ParallelBondParams,
};
use dem_core::contact::LinearSpringDashpot;
use dem_core::{ContactLaws, ContactModel, Params, State, Wall};

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
    // Wall under the tip, pressed 2 µm into it (material 1: frictionless, stiff).
    let x_tip = l;
    let y_wall = -R + 2e-6;
    st.walls.push(Wall::new(
        "load",
        [x_tip - 0.5 * R, y_wall],
        [x_tip + 0.5 * R, y_wall],
        1,
    ));
    let mut laws = ContactLaws::new(
        2,
        ContactModel::Linear(LinearSpringDashpot::elastic(1e6, 1e6, 0.0)),
    );
    laws.set(
        0,
        1,
        ContactModel::Linear(LinearSpringDashpot::elastic(2e5, 0.0, 0.0)),
    );
    let params = Params {
        local_damping: 0.7,
        dt_factor: 0.3,
        ..Params::default()
    };
    let mut w = world_with_bonds(st, params, laws, bonds, &[]).unwrap();
    let tip = w.index_of_id(n as u32).unwrap();
    let y0 = w.state.discs.y[tip];
    let steps = 200_000;
    w.run(steps);
    let tip = w.index_of_id(n as u32).unwrap();
    let delta = w.state.discs.y[tip] - y0;
    let p = -w.state.walls[0].force[1]; // the tip pushes the wall down
    assert!(w.check().is_ok());
    assert!(p > 0.0 && delta > 0.0, "P {p} δ {delta}");
    // At rest: the tip velocity and the wall force no longer change.
    assert!(w.state.discs.vy[tip].abs() * w.dt() < 1e-6 * delta);
    let eb = p * l.powi(3) / (3.0 * ei);
    let err = delta / eb - 1.0;
    eprintln!("cantilever: P = {p:.4e} N, δ = {delta:.5e} m, PL³/(3EI) = {eb:.5e} m, error {:.3} %, dt {:.3e}", 100.0 * err, w.dt());
    assert!(err.abs() < 0.02, "error {err}");
}
