//! `World::run` runs its steps as one batch, in which each step's integrator packs the moved
//! discs for the next disc–disc pass (`Slots::packed_fresh`) instead of the pass packing them:
//! it must give the bits of the same number of single `World::step` calls — state, bonds,
//! break log and energies — on 1 and 2 threads, through neighbour rebuilds with reordering and
//! bond breaks, and `run_while` must stop where its condition says.

mod shaken_lattice;

use dem_core::bond::bench::RADIUS;
use dem_core::{Params, World};

/// The shaken weak-bond lattice ([`shaken_lattice::weak_shaken_lattice`]) with a small Verlet
/// skin, so that the list is rebuilt (and the discs reordered) during the run, and energies
/// tracked.
fn world() -> World {
    let params = Params {
        skin: Some(0.002 * RADIUS),
        reorder_every: 1,
        track_energy: true,
        ..Params::default()
    };
    shaken_lattice::weak_shaken_lattice(11, 0.05, params)
}

/// (state, bonds with their break log, energies) as text, and (passes with integrator-packed
/// records, rebuilds, breaks).
fn outcome(w: &World) -> ([String; 3], (u64, u64, usize)) {
    let b = w.bonds.as_ref().unwrap();
    (
        [
            serde_json::to_string(&w.state).unwrap(),
            serde_json::to_string(b).unwrap(),
            format!("{:?}", w.energy()),
        ],
        (
            w.counters.packed_by_integrator,
            w.counters.rebuilds,
            b.log().len(),
        ),
    )
}

#[test]
fn a_batch_gives_the_bits_of_single_steps() {
    const STEPS: u64 = 400;
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let (batch, single) = pool.install(|| {
            let mut a = world();
            a.counters.reset();
            a.run(STEPS);
            let mut b = world();
            b.counters.reset();
            for _ in 0..STEPS {
                b.step();
            }
            (outcome(&a), outcome(&b))
        });
        let (packed, rebuilds, breaks) = batch.1;
        assert!(rebuilds >= 2, "{threads} threads: only {rebuilds} rebuilds");
        assert!(breaks > 0, "{threads} threads: no bond broke");
        // With AVX2 the batch's passes (all but the first and those after a rebuild) read
        // the integrator's records; single steps never do.
        #[cfg(target_arch = "x86_64")]
        if std::is_x86_feature_detected!("avx2") {
            assert!(
                packed >= STEPS - 1 - rebuilds,
                "{threads} threads: {packed} passes"
            );
        }
        let _ = packed;
        assert_eq!(single.1 .0, 0);
        assert!(
            batch.0 == single.0,
            "{threads} threads: batch and single steps differ"
        );
    }
}

#[test]
fn run_while_stops_when_told() {
    let mut w = world();
    let s0 = w.state.step;
    let mut seen = Vec::new();
    let done = w.run_while(100, |w| {
        seen.push(w.state.step);
        w.state.step < s0 + 7
    });
    assert_eq!(done, 7);
    assert_eq!(w.state.step, s0 + 7);
    assert_eq!(seen, (s0 + 1..=s0 + 7).collect::<Vec<_>>());
    assert_eq!(w.run_while(5, |_| true), 5);
    assert_eq!(w.state.step, s0 + 12);
}
