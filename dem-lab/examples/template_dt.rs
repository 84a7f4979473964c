//! How the improved-ORC template parameters set the time step: for one grain tessellation of
//! the Table 2 specimen (20 × 10 mm, grains 0.86 mm), fill every cell with a clumpgen template
//! at several smallest template radii and mass floors, and print the disc count, the grains
//! that needed r_min reduced or failed, and the lightest disc.
//!
//! The automatic step is set by the lightest discs: both bounds √(m/K) and √(I/K_rot) with
//! I = m r²/2 and K_rot ≈ Σ k_s r² reduce to √(m / (n k)) for a disc with n partners of
//! stiffness k (in 2D the contact k_n = E_c t does not depend on the radius), so the step
//! scales as √(m_min). The last column is that ratio against the first configuration.
//!
//! ```text
//! cargo run --release -p dem-lab --example template_dt -- [seed] [r_min_mm:floor ...]
//! cargo run --release -p dem-lab --example template_dt -- 1 0.08:0.2 0.10:0.2 0.10:0.5 0.12:0.5
//! ```

use dem_lab::specimen::grains::{draw_seeds, tessellate};
use dem_lab::specimen::improved::cell_template_with;
use dem_lab::specimen::rng::Rng;
use dem_lab::specimen::{Method, SpecimenParams};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let seed: u64 = args.next().map_or(Ok(1), |s| s.parse())?;
    let mut configs: Vec<(f64, f64)> = vec![];
    for a in args {
        let (r, f) = a.split_once(':').ok_or("configs are r_min_mm:floor")?;
        configs.push((r.parse::<f64>()? * 1e-3, f.parse()?));
    }
    if configs.is_empty() {
        configs = vec![
            (0.08e-3, 0.2),
            (0.10e-3, 0.2),
            (0.10e-3, 0.5),
            (0.12e-3, 0.5),
        ];
    }
    // The Table 2 specimen (validation/src/table2_section.rs, full plan).
    let (w, h, r0, r1, grain, rho) = (20e-3, 10e-3, 0.175e-3, 0.285e-3, 0.86e-3, 3200.0);
    let mut p = SpecimenParams::new(Method::Improved, w, h, r0, r1, rho, 310e9, 800e6, seed);
    p.grain_size = grain;
    let g = tessellate(&draw_seeds(&mut Rng::new(seed), w, h, grain)?, w, h);
    let m_trad = rho * std::f64::consts::PI * r0 * r0 * p.thickness;
    println!(
        "{} grains; lightest traditional disc (r = {:.3} mm): {:.3e} kg",
        g.cells.len(),
        r0 * 1e3,
        m_trad
    );
    println!("r_min(mm) floor  discs  mean/grain  reduced  failed  lightest(kg)  r of it(mm)  dt/dt(first)  dt/dt(trad)");
    let mut first = None;
    for (r_min, floor) in configs {
        p.template_r_min = r_min;
        let (mut discs, mut reduced, mut failed) = (0usize, 0usize, 0usize);
        let mut lightest = (f64::INFINITY, 0.0);
        for (gi, cell) in g.cells.iter().enumerate() {
            match cell_template_with(gi, cell, &p, floor) {
                Ok((t, red)) => {
                    discs += t.discs.len();
                    reduced += red as usize;
                    for d in &t.discs {
                        if d.m < lightest.0 {
                            lightest = (d.m, d.r);
                        }
                    }
                }
                Err(_) => failed += 1,
            }
        }
        let m0 = *first.get_or_insert(lightest.0);
        println!(
            "{:9.3} {:5.2} {:6} {:11.2} {:8} {:7} {:13.3e} {:12.4} {:13.2} {:12.2}",
            r_min * 1e3,
            floor,
            discs,
            discs as f64 / g.cells.len() as f64,
            reduced,
            failed,
            lightest.0,
            lightest.1 * 1e3,
            (lightest.0 / m0).sqrt(),
            (lightest.0 / m_trad).sqrt()
        );
    }
    Ok(())
}
