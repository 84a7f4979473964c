//! Contact history survives neighbour rebuilds: a disc sheared against a fixed one follows the
//! same trajectory, to the last bit, whether the list is built once or rebuilt at every step
//! (the discs are also renumbered by the first build). The remapping of history under
//! reordering is unit-tested in `neighbors::tests`.

use dem_core::contact::{LinearSpringDashpot, NormalDamping};
use dem_core::{ContactLaws, ContactModel, Params, State, World};

fn run(skin: f64, reorder_every: u32) -> (f64, f64, f64, u64, u64) {
    let r = 0.01;
    let mut st = State::default();
    // Created first, but above the mover: the spatial order puts it second.
    let f = st
        .discs
        .push_uniform(0.0, 2.0 * r - 1e-5, r, 2500.0, 0.01, 0);
    st.discs.fixed[f] = true;
    let m = st.discs.push_uniform(0.0, 0.0, r, 2500.0, 0.01, 0);
    st.discs.vx[m] = 0.02;
    let law = LinearSpringDashpot {
        kn: 1e5,
        ks: 5e4,
        damping: NormalDamping::Ratio(0.0),
        shear_damping: 0.0,
        mu: 10.0,
    };
    let params = Params {
        skin: Some(skin),
        reorder_every,
        ..Params::default()
    };
    let mut w = World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)));
    w.run(3000);
    let i = w.index_of_id(1).expect("mover");
    let d = &w.state.discs;
    (
        d.vx[i],
        d.vy[i],
        d.omega[i],
        w.counters.rebuilds,
        w.counters.reorders,
    )
}

#[test]
fn history_survives_rebuilds_and_reordering() {
    let (vx0, vy0, w0, rb0, _) = run(0.5, 0);
    let (vx1, vy1, w1, rb1, ro1) = run(1e-9, 1);
    eprintln!("no rebuild: {vx0} {vy0} {w0} ({rb0} rebuilds); rebuilt: {vx1} {vy1} {w1} ({rb1} rebuilds, {ro1} reorders)");
    assert!(rb1 > 1000 && ro1 >= 1 && rb0 <= 1);
    // The tangential spring must have acted (the mover was slowed and spun).
    assert!(vx0 < 0.019 && w0.abs() > 0.1);
    for (a, b) in [(vx0, vx1), (vy0, vy1), (w0, w1)] {
        assert!((a - b).abs() <= 1e-9 * a.abs().max(1e-3), "{a} vs {b}");
    }
}
