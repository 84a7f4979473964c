//! Dense-lattice benchmark (the LAMMPS peer scene): `cargo run --release -p dem-core
//! --example bench -- [steps] [threads]`. Prints the stage timing and, last,
//! `particle-steps/s: <number>`.

use dem_core::bench::{dense_lattice_scene, run_bench_on};

fn main() {
    let mut args = std::env::args().skip(1);
    let steps: u64 = args.next().and_then(|s| s.parse().ok()).unwrap_or(2000);
    let threads: usize = args.next().and_then(|s| s.parse().ok()).unwrap_or(1);
    let mut world = dense_lattice_scene();
    println!(
        "dense lattice: {} discs, {} pairs listed, {} steps, {} thread(s)",
        world.state.discs.len(),
        world.n_pairs(),
        steps,
        threads
    );
    let rate = run_bench_on(&mut world, steps, threads);
    print!("{}", world.counters.report());
    println!("particle-steps/s: {rate:.0}");
}
