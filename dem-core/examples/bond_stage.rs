//! Bonded-lattice benchmark: `cargo run --release -p dem-core --example bond_stage --
//! [world|stage] [steps] [threads] [cells_x cells_y]`. `world` runs the whole step (the
//! `dem bench bonded` figure), `stage` the bond stage alone.
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let what = a.get(1).map(String::as_str).unwrap_or("world");
    let steps: usize = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(500);
    let threads = a.get(3).and_then(|s| s.parse().ok()).unwrap_or(1);
    let cx = a.get(4).and_then(|s| s.parse().ok()).unwrap_or(200);
    let cy = a.get(5).and_then(|s| s.parse().ok()).unwrap_or(115);
    use dem_core::bond::bench;
    if what == "stage" {
        let r = bench::bond_stage_rate([cx, cy], steps, threads);
        println!(
            "bond stage, {threads} thread(s): {:.2} M disc-steps/s",
            r / 1e6
        );
        return;
    }
    match bench::run_bonded_bench([cx, cy], steps as u64, threads) {
        Ok(r) => {
            print!("{}", r.counters.report());
            println!(
                "{} discs, {} bonds, {} steps, dt {:.3e} s, {:.2} s, {} thread(s)",
                r.discs, r.bonds, r.steps, r.dt, r.seconds, r.threads
            );
            println!("particle-steps/s: {:.0}", r.particle_steps_per_s);
        }
        Err(e) => {
            eprintln!("error: {e}");
            std::process::exit(1);
        }
    }
}
