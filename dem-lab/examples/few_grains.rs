//! Disc counts and generation times of the 20 × 10 mm Si3N4 specimens with a few irregular
//! grains (`docs/specimen.md`, "Few irregular grains (S0)"):
//! `cargo run --release -p dem-lab --example few_grains -- SEED [METHOD...]`.

use dem_lab::specimen::{generate, FewGrains, GrainMode, Method, SpecimenParams};
use std::time::Instant;

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let seed: u64 = args.get(1).and_then(|s| s.parse().ok()).unwrap_or(1);
    let methods: Vec<Method> = if args.len() > 2 {
        args[2..].iter().filter_map(|m| Method::parse(m)).collect()
    } else {
        vec![Method::Traditional, Method::Orc, Method::Improved]
    };
    for m in methods {
        // data/materials/si3n4.json: ρ 3200 kg/m³, E 310 GPa, flexural 800 MPa; Table 2's
        // grain size and template r_min (validation/src/table2_section.rs).
        let mut p = SpecimenParams::new(
            m, 20e-3, 10e-3, 0.175e-3, 0.285e-3, 3200.0, 310e9, 800e6, seed,
        );
        p.grain_size = 0.86e-3;
        p.template_r_min = 0.08e-3;
        p.grains = GrainMode::Few(FewGrains::s0(&p));
        let t0 = Instant::now();
        let mut last = String::new();
        let verbose = std::env::var("FEW_VERBOSE").is_ok();
        let mut report = |pr: dem_lab::specimen::Progress| {
            if verbose && pr.stage != last {
                println!(
                    "  {:>7.1} s  {} {}",
                    t0.elapsed().as_secs_f64(),
                    pr.stage,
                    pr.message
                );
                last = pr.stage.to_string();
            }
        };
        match generate(&p, &mut report) {
            Ok(s) => {
                println!(
                    "seed {seed} {}: {} discs, {:.1} s",
                    m.name(),
                    s.summary.discs,
                    t0.elapsed().as_secs_f64()
                );
                print!("{}", s.summary.text());
            }
            Err(e) => println!("seed {seed} {}: error {e}", m.name()),
        }
    }
}
