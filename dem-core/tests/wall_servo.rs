//! A servo wall (`dem_core::wall_servo`, PFC's biaxial-test servo) pressing a row of discs
//! against a fixed wall, no gravity, local damping and no contact dashpot (as the lab's scenes): at equilibrium the wall's normal stress F/(L t) is the
//! target σ_req and the overlaps are the closed form of springs in series, δ = F/k_n per
//! contact; the servo keeps the speed limit while it approaches.

use dem_core::contact::{LinearSpringDashpot, NormalDamping};
use dem_core::wall_servo::WallServo;
use dem_core::{ContactLaws, ContactModel, Params, State, Wall, World};

#[test]
fn a_servo_wall_holds_its_stress_on_a_row_of_discs() {
    let (r, rho, t, kn) = (1e-3, 2500.0, 0.01, 1e7);
    let n = 5;
    let mut st = State {
        thickness: t,
        ..State::default()
    };
    for i in 0..n {
        st.discs
            .push_uniform((2 * i + 1) as f64 * r, 0.0, r, rho, t, 0);
    }
    st.walls
        .push(Wall::new("fixed", [0.0, -2.0 * r], [0.0, 2.0 * r], 0));
    // The servo wall starts 0.1 r clear of the last disc.
    let x1 = 2.0 * n as f64 * r + 0.1 * r;
    let mut w = Wall::new("servo", [x1, -2.0 * r], [x1, 2.0 * r], 0);
    let (sigma, length, vmax) = (2e5, 2.0 * r, 0.05);
    w.servo = Some(WallServo {
        stress: sigma,
        length,
        direction: [-1.0, 0.0],
        alpha: 0.5,
        max_speed: vmax,
    });
    st.walls.push(w);
    let law = LinearSpringDashpot {
        kn,
        ks: 0.5 * kn,
        damping: NormalDamping::Ratio(0.0),
        shear_damping: 0.0,
        mu: 0.0,
    };
    let params = Params {
        local_damping: 0.7,
        ..Params::default()
    };
    let mut world = World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)));
    // Approach: no contact yet, the wall closes at the speed limit.
    world.step();
    world.step();
    assert_eq!(world.state.walls[1].v, [-vmax, 0.0]);
    world.run(200_000);
    let target = sigma * length * t;
    let wall = &world.state.walls[1];
    // The discs push the servo wall along +x.
    let f = wall.force[0];
    assert!(
        (f / target - 1.0).abs() < 1e-6,
        "servo wall force {f} N, target {target} N"
    );
    assert!(wall.v[0].abs() < 1e-9, "still moving at {:?}", wall.v);
    // Springs in series: every one of the n + 1 contacts carries F, overlap F/k_n; the fixed
    // wall carries the same force.
    let fixed = world.state.walls[0].force[0];
    assert!((fixed / -target - 1.0).abs() < 1e-6, "fixed wall {fixed}");
    let gap_closed = 2.0 * n as f64 * r - (world.state.walls[1].a[0] - 0.0);
    let expect = (n + 1) as f64 * target / kn;
    assert!(
        (gap_closed / expect - 1.0).abs() < 1e-6,
        "overlap sum {gap_closed}, springs in series {expect}"
    );
}
