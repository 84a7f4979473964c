//! Determinism and restart: 1 thread and 2 threads give identical bytes of state after 1e4
//! steps (a scene exercising the parallel paths: > 2 chunks of discs, two materials with a
//! linear and a Hertz law and rolling resistance, walls, gravity, damping, reordering); a
//! World serialised to JSON and read back continues bit-identically.

use clumpgen::synth::SplitMix64;
use dem_core::contact::{HertzMindlin, LinearSpringDashpot, NormalDamping, RollingResistance};
use dem_core::{ContactLaws, ContactModel, Params, State, Wall, World};

fn scene(nx: usize, ny: usize) -> World {
    let mut rng = SplitMix64::new(42);
    let s = 0.0025;
    let mut st = State {
        thickness: 0.001,
        ..State::default()
    };
    let l = nx as f64 * s;
    st.periodic.length = [Some(l), None];
    for iy in 0..ny {
        for ix in 0..nx {
            let r = s * 0.5 * rng.range(0.97, 1.06);
            let k = st.discs.push_uniform(
                (ix as f64 + 0.5) * s,
                (iy as f64 + 0.5) * s,
                r,
                2600.0,
                0.001,
                (ix + iy) as u16 % 2,
            );
            st.discs.vx[k] = rng.range(-0.3, 0.3);
            st.discs.vy[k] = rng.range(-0.3, 0.3);
            st.discs.omega[k] = rng.range(-50.0, 50.0);
        }
    }
    st.walls.push(Wall::new("bottom", [0.0, 0.0], [l, 0.0], 0));
    let mut top = Wall::new(
        "top",
        [l, ny as f64 * s + 0.001],
        [0.0, ny as f64 * s + 0.001],
        1,
    );
    top.v = [0.0, -0.05];
    st.walls.push(top);
    let lin = LinearSpringDashpot {
        kn: 2e5,
        ks: 1e5,
        damping: NormalDamping::from_restitution(0.7),
        shear_damping: 0.1,
        mu: 0.4,
    };
    let mut laws = ContactLaws::new(2, ContactModel::Linear(lin));
    let hm = HertzMindlin::from_materials(5e8, 0.25, 5e8, 0.25, 0.8, 0.3);
    laws.set(1, 1, ContactModel::HertzMindlin(hm));
    laws.set_rolling(0, 1, Some(RollingResistance::new(0.1)));
    let params = Params {
        gravity: Some([0.0, -9.81]),
        local_damping: 0.05,
        reorder_every: 3,
        ..Params::default()
    };
    World::new(st, params, laws)
}

fn bytes(w: &World) -> String {
    serde_json::to_string(&w.state).expect("serialise")
}

fn run_on(threads: usize, steps: u64) -> (String, String) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("pool");
    pool.install(|| {
        let mut w = scene(40, 40);
        w.run(steps);
        eprintln!(
            "threads {threads}: t = {:.3e} s, dt {:.2e}, {} contacts, {} rebuilds",
            w.state.time,
            w.dt(),
            w.contacts().count(),
            w.counters.rebuilds
        );
        (bytes(&w), format!("{:?}", w.energy()))
    })
}

#[test]
fn one_and_two_threads_give_identical_bytes() {
    let (s1, e1) = run_on(1, 10_000);
    let (s2, e2) = run_on(2, 10_000);
    assert!(s1 == s2, "state differs between 1 and 2 threads");
    assert_eq!(e1, e2, "energies differ");
}

#[test]
fn checkpoint_round_trip_continues_bit_identically() {
    let mut a = scene(20, 15);
    a.run(1000);
    let json = serde_json::to_string(&a).expect("serialise world");
    let mut b: World = serde_json::from_str(&json).expect("deserialise world");
    assert_eq!(bytes(&a), bytes(&b));
    a.run(1000);
    b.run(1000);
    assert!(
        a.counters.rebuilds > 0,
        "the continuation must cross neighbour rebuilds"
    );
    assert!(bytes(&a) == bytes(&b), "restarted run diverged");
    assert_eq!(format!("{:?}", a.energy()), format!("{:?}", b.energy()));
}
