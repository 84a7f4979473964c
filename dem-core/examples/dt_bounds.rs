//! Which discs set the automatic time step of a scene: the smallest √(m/K) and √(I/K_rot)
//! bounds with each disc's radius, mass and stiffness sum.
//!
//! ```text
//! cargo run --release -p dem-core --example dt_bounds -- scene.json [count]
//! ```

use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = PathBuf::from(args.next().ok_or("usage: dt_bounds scene.json [count]")?);
    let count: usize = args.next().map_or(Ok(12), |s| s.parse())?;
    let scene = dem_core::scene::load(&path)?;
    let mut world = dem_core::scene::build(&scene)?;
    world.refresh();
    println!(
        "{}: {} discs, critical dt {:.4e} s, dt {:.4e} s",
        path.display(),
        world.state.discs.len(),
        world.critical_dt(),
        world.dt()
    );
    let d = &world.state.discs;
    let r_mean = d.r.iter().sum::<f64>() / d.len().max(1) as f64;
    println!("mean radius {:.4e} m", r_mean);
    println!("      dt (s)     kind    disc  clump    r (m)      m (kg)     m/(ρ-free prior)  K");
    for b in world.dt_bounds().iter().take(count) {
        let i = b.disc;
        let prior = d.m[i] / (d.r[i] * d.r[i]);
        println!(
            "{:12.4e}  {:8}  {:5}  {:5}  {:10.4e} {:10.4e} {:10.4e}  {:10.4e}",
            b.dt,
            if b.rotational { "rotation" } else { "trans" },
            i,
            b.clump.map_or("-".to_string(), |c| c.to_string()),
            d.r[i],
            d.m[i],
            prior,
            b.stiffness
        );
    }
    Ok(())
}
