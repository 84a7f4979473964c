//! Bond-stage throughput on the 46,000-disc bonded lattice: `cargo run --release -p dem-core
//! --example bond_stage -- [steps] [threads]`.
fn main() {
    let a: Vec<String> = std::env::args().collect();
    let steps = a.get(1).and_then(|s| s.parse().ok()).unwrap_or(500);
    let threads = a.get(2).and_then(|s| s.parse().ok()).unwrap_or(1);
    let cx = a.get(3).and_then(|s| s.parse().ok()).unwrap_or(200);
    let cy = a.get(4).and_then(|s| s.parse().ok()).unwrap_or(115);
    let r = dem_core::bond::bench::bond_stage_rate([cx, cy], steps, threads);
    println!(
        "bond stage, {threads} thread(s): {:.1} M disc-steps/s",
        r / 1e6
    );
}
