#![allow(dead_code)]
use dem_laws::GranularLaw;
use dem_sphere::{box_walls, Config, Laws, World};
use nalgebra::Vector3;

pub fn law(json: &str) -> GranularLaw {
    GranularLaw::from_json(json, None).unwrap()
}

/// Hooke + coeff_restitution + linear_history (frictional).
pub fn hooke_friction(kn: f64, e: f64, mu: f64) -> GranularLaw {
    law(&format!(
        r#"{{"normal": {{"model": "hooke", "kn": {kn}}},
            "damping": {{"model": "coeff_restitution", "e": {e}}},
            "tangential": {{"model": "linear_history", "kt": {}, "mu": {mu}}}}}"#,
        0.8 * kn
    ))
}

/// A small frictional pour: `n` spheres of radius ~1 mm inserted in a box, walls, gravity.
pub fn pour(n: usize, seed: u64, energy: bool) -> World {
    let l = hooke_friction(1000.0, 0.5, 0.5);
    let cfg = Config {
        energy,
        ..Config::default()
    };
    let mut w = World::new(cfg, Laws::single(l, l)).unwrap();
    let lo = Vector3::zeros();
    let hi = Vector3::new(0.012, 0.012, 0.04);
    for p in box_walls(lo, hi).unwrap() {
        w.add_wall(p).unwrap();
    }
    let mut rng = dem_sphere::rng::SplitMix64::new(seed);
    let radii: Vec<f64> = (0..n).map(|_| rng.range(0.8e-3, 1.2e-3)).collect();
    let placed =
        dem_sphere::pack::insert_rsi(&radii, lo, Vector3::new(hi.x, hi.y, 0.03), seed, 10_000)
            .unwrap();
    for (x, r) in placed {
        let v = Vector3::new(
            rng.range(-0.1, 0.1),
            rng.range(-0.1, 0.1),
            rng.range(-0.1, 0.1),
        );
        w.add_sphere(x, v, r, 2500.0, 0).unwrap();
    }
    w.config.dt = w.critical_dt(0.1, 0.05);
    w
}
