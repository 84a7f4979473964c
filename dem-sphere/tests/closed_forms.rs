//! The solver against closed forms: restitution on a plane, Hertz contact time, energy
//! balance, Galilean invariance, rigid rotation.

mod common;
use common::*;
use dem_sphere::{Config, Laws, Plane, World};
use nalgebra::{Rotation3, Vector3};

#[test]
fn a_sphere_dropped_on_a_plane_rebounds_with_e() {
    for &e in &[0.3, 0.5, 0.9] {
        let l = law(&format!(
            r#"{{"normal": {{"model": "hooke", "kn": 1e4}},
                "damping": {{"model": "coeff_restitution", "e": {e}}},
                "tangential": {{"model": "linear_history", "kt": 8e3, "mu": 0.5}}}}"#
        ));
        let mut w = World::new(Config::default(), Laws::single(l, l)).unwrap();
        w.add_wall(Plane::new(Vector3::zeros(), Vector3::z()).unwrap())
            .unwrap();
        let r = 1e-3;
        w.add_sphere(
            Vector3::new(0.0, 0.0, r + 1e-5),
            Vector3::new(0.0, 0.0, -1.0),
            r,
            2500.0,
            0,
        )
        .unwrap();
        w.config.dt = w.critical_dt(0.01, 0.0);
        let gap = |w: &World| w.spheres.x[0].z - r;
        let mut v_in = 0.0;
        while gap(&w) > 0.0 {
            v_in = w.spheres.v[0].z;
            w.step();
        }
        while gap(&w) <= 0.0 {
            w.step();
        }
        let v_out = w.spheres.v[0].z;
        let e_out = -v_out / v_in;
        println!(
            "e = {e}: rebound e = {e_out:.6} (rel. error {:.2e})",
            e_out / e - 1.0
        );
        assert!((e_out / e - 1.0).abs() < 0.01, "e {e} -> {e_out}");
    }
}

/// ∫₀¹ dx/√(1 − x^p) by x = 1 − u², Simpson.
fn impact_integral(p: f64) -> f64 {
    let n = 20_000;
    let f = |u: f64| {
        if u == 0.0 {
            2.0 / p.sqrt()
        } else {
            2.0 * u / (1.0 - (1.0 - u * u).powf(p)).sqrt()
        }
    };
    let h = 1.0 / n as f64;
    let mut s = f(0.0) + f(1.0);
    for k in 1..n {
        s += if k % 2 == 1 { 4.0 } else { 2.0 } * f(k as f64 * h);
    }
    s * h / 3.0
}

#[test]
fn hertz_contact_time_is_johnsons() {
    let l = law(
        r#"{"normal": {"model": "hertz/material", "E": 7e10, "nu": 0.3},
                    "tangential": {"model": "mindlin", "mu": 0.3}}"#,
    );
    let cfg = Config {
        gravity: Vector3::zeros(),
        ..Config::default()
    };
    let (r1, r2, rho, v) = (1e-3, 1.5e-3, 2500.0, 1.0);
    let mut w = World::new(cfg, Laws::single(l, l)).unwrap();
    w.add_sphere(
        Vector3::zeros(),
        Vector3::new(0.5 * v, 0.0, 0.0),
        r1,
        rho,
        0,
    )
    .unwrap();
    w.add_sphere(
        Vector3::new(r1 + r2 + 1e-7, 0.0, 0.0),
        Vector3::new(-0.5 * v, 0.0, 0.0),
        r2,
        rho,
        0,
    )
    .unwrap();
    let m = |r: f64| rho * 4.0 / 3.0 * std::f64::consts::PI * r.powi(3);
    let m_eff = m(r1) * m(r2) / (m(r1) + m(r2));
    let r_eff = r1 * r2 / (r1 + r2);
    let e_star = 7e10 / (2.0 * (1.0 - 0.09));
    // Johnson 1985, §11.4: ½m*v² = (8/15)E*√R* δ_max^{5/2}, t_c = 2 δ_max/v ∫₀¹ dx/√(1 − x^{5/2}).
    let d_max = (15.0 * m_eff * v * v / (16.0 * e_star * r_eff.sqrt())).powf(0.4);
    let i = impact_integral(2.5);
    let t_c = 2.0 * d_max / v * i;
    // A step not commensurate with t_c; the crossings of δ = 0 interpolated linearly.
    w.config.dt = t_c / 3777.7;
    let overlap = |w: &World| r1 + r2 - (w.spheres.x[1] - w.spheres.x[0]).norm();
    let mut d_prev = overlap(&w);
    while overlap(&w) <= 0.0 {
        d_prev = overlap(&w);
        w.step();
    }
    let cross = |w: &World, d0: f64, d1: f64| w.time - w.config.dt * d1 / (d1 - d0);
    let t0 = cross(&w, d_prev, overlap(&w));
    let v0 = w.spheres.v[1].x - w.spheres.v[0].x;
    while overlap(&w) > 0.0 {
        d_prev = overlap(&w);
        w.step();
    }
    let t = cross(&w, d_prev, overlap(&w)) - t0;
    let e = -(w.spheres.v[1].x - w.spheres.v[0].x) / v0;
    println!(
        "2·I(5/2) = {:.5}; t_c = {t_c:.6e} s, measured {t:.6e} s (rel. {:.2e}); e = {e:.6}",
        2.0 * i,
        t / t_c - 1.0
    );
    assert!((t / t_c - 1.0).abs() < 0.01);
    assert!((e - 1.0).abs() < 1e-3);
}

#[test]
fn a_frictional_pour_balances_its_energy() {
    let mut w = pour(200, 7, true);
    let mut worst = 0.0f64;
    let steps = (0.06 / w.config.dt) as u64;
    for _ in 0..steps / 100 {
        w.run(100);
        worst = worst.max(w.energy().balance_error.abs());
    }
    let e = w.energy();
    println!(
        "{} steps, dt {:.3e}: E0 {:.4e} J, kinetic {:.3e}, gravity {:.4e}, strain {:.3e}, damping {:.3e}, friction {:.3e}; balance error now {:.2e}, worst {:.2e}",
        w.counters.steps, w.config.dt, e.initial, e.kinetic(), e.gravity_potential, e.strain, e.damping, e.friction, e.balance_error, worst
    );
    assert!(e.damping > 0.01 * e.initial && e.friction > 0.0);
    assert!(worst < 2e-3, "worst balance error {worst}");
}

fn cluster(u: Vector3<f64>) -> World {
    let l = hooke_friction(1000.0, 0.1, 0.4);
    let mut w = World::new(Config::default(), Laws::single(l, l)).unwrap();
    // A box of six walls, all translating at u.
    for p in dem_sphere::box_walls(
        Vector3::new(-0.004, -0.004, 0.0),
        Vector3::new(0.004, 0.004, 0.02),
    )
    .unwrap()
    {
        w.add_wall(p.moving(u)).unwrap();
    }
    let mut rng = dem_sphere::rng::SplitMix64::new(3);
    let radii: Vec<f64> = (0..20).map(|_| rng.range(0.8e-3, 1.2e-3)).collect();
    let pl = dem_sphere::pack::insert_rsi(
        &radii,
        Vector3::new(-0.004, -0.004, 0.0),
        Vector3::new(0.004, 0.004, 0.008),
        3,
        10_000,
    )
    .unwrap();
    for (x, r) in pl {
        let v = Vector3::new(
            rng.range(-0.2, 0.2),
            rng.range(-0.2, 0.2),
            rng.range(-0.2, 0.2),
        );
        w.add_sphere(x, v + u, r, 2500.0, 0).unwrap();
    }
    w.config.dt = w.critical_dt(0.1, 0.05);
    w
}

#[test]
fn motion_relative_to_a_moving_wall_is_galilean_invariant() {
    let u = Vector3::new(0.7, -0.3, 0.2);
    let mut a = cluster(Vector3::zeros());
    let mut b = cluster(u);
    let n = (0.08 / a.config.dt) as u64;
    let mut most = 0;
    for _ in 0..n / 100 {
        a.run(100);
        b.run(100);
        most = most.max(a.contacts().filter(|c| c.2 > 0.0).count());
    }
    let t = b.time;
    let (mut dx, mut dv) = (0.0f64, 0.0f64);
    for i in 0..a.spheres.len() {
        dx = dx.max((b.spheres.x[i] - u * t - a.spheres.x[i]).norm());
        dv = dv.max((b.spheres.v[i] - u - a.spheres.v[i]).norm());
        dv = dv.max((b.spheres.w[i] - a.spheres.w[i]).norm() * 1e-3);
    }
    let contacts = most;
    let wc = a.wall_contacts().len();
    println!("after {n} steps ({t:.3} s, at most {contacts} sphere contacts, {wc} wall contacts at the end): max |Δx| = {dx:.2e} m, max |Δv| = {dv:.2e} m/s");
    assert!(contacts > 5 && wc > 5);
    assert!(dx < 1e-9 && dv < 1e-6, "dx {dx} dv {dv}");
}

#[test]
fn a_rigidly_rotating_pair_feels_no_spurious_force() {
    let l = law(
        r#"{"normal": {"model": "hertz/material", "E": 7e10, "nu": 0.3},
                    "damping": {"model": "tsuji", "e": 0.5},
                    "tangential": {"model": "mindlin", "mu": 0.5},
                    "rolling": {"model": "elastic_plastic", "mu_r": 0.1},
                    "twisting": {"model": "marshall"}}"#,
    );
    let cfg = Config {
        gravity: Vector3::zeros(),
        dt: 1e-7,
        ..Config::default()
    };
    let mut w = World::new(cfg, Laws::single(l, l)).unwrap();
    let (r1, r2, delta) = (1e-3, 0.6e-3, 1e-6);
    let d = r1 + r2 - delta;
    w.add_sphere(Vector3::zeros(), Vector3::zeros(), r1, 2500.0, 0)
        .unwrap();
    w.add_sphere(Vector3::zeros(), Vector3::zeros(), r2, 2500.0, 0)
        .unwrap();
    let omega = Vector3::new(0.3, -1.0, 2.0).normalize() * 300.0;
    let centre = Vector3::new(1e-3, 2e-3, -1e-3);
    let x0 = [
        Vector3::new(-0.4 * d, 0.0, 0.0),
        Vector3::new(0.6 * d, 0.0, 0.0),
    ];
    let (mut fn0, mut worst_t, mut worst_n, mut worst_m) = (0.0, 0.0f64, 0.0f64, 0.0f64);
    for k in 0..200 {
        let rot = Rotation3::new(omega * (k as f64 * 1e-4));
        for (i, x) in x0.iter().enumerate() {
            let p = rot * x;
            w.spheres.x[i] = centre + p;
            w.spheres.v[i] = omega.cross(&p);
            w.spheres.w[i] = omega;
        }
        w.touch();
        w.compute_forces();
        let (_, _, f_n, f_t) = w.pair_forces()[0];
        if k == 0 {
            fn0 = f_n;
        }
        worst_n = worst_n.max((f_n / fn0 - 1.0).abs());
        worst_t = worst_t.max(f_t / fn0);
        // Torques: only the arms of the normal force (zero) — no rolling or twisting moment.
        let (_, t) = w.forces();
        worst_m = worst_m.max(t[0].norm().max(t[1].norm()) / (fn0 * r1));
    }
    println!("200 rotated states over {:.1} rad: |F_n/F_n0 − 1| ≤ {worst_n:.2e}, |F_t|/F_n ≤ {worst_t:.2e}, |T|/(F_n r) ≤ {worst_m:.2e}", omega.norm() * 199e-4);
    assert!(worst_n < 1e-6 && worst_t < 1e-9 && worst_m < 1e-9);
}

#[test]
fn a_sliding_sphere_rolls_at_five_sevenths_of_its_speed() {
    // Coulomb sliding on a plane: the friction μmg slows the centre and spins the sphere up
    // until v = rω; for a solid sphere (I = 2/5 mr²) then v = (5/7) v₀, after t = 2v₀/(7μg).
    let l = hooke_friction(1e4, 0.5, 0.3);
    let mut w = World::new(Config::default(), Laws::single(l, l)).unwrap();
    w.add_wall(Plane::new(Vector3::zeros(), Vector3::z()).unwrap())
        .unwrap();
    let (r, v0, mu, g) = (1e-3, 0.5, 0.3, 9.81);
    let m = 2500.0 * 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    // Start at the static overlap mg/k_n.
    w.add_sphere(
        Vector3::new(0.0, 0.0, r - m * g / 1e4),
        Vector3::new(v0, 0.0, 0.0),
        r,
        2500.0,
        0,
    )
    .unwrap();
    w.config.dt = w.critical_dt(0.05, 0.0);
    let t_roll = 2.0 * v0 / (7.0 * mu * g);
    w.run((2.0 * t_roll / w.config.dt) as u64);
    let v = w.spheres.v[0].x;
    let slip = v - r * w.spheres.w[0].y;
    println!(
        "v/v0 = {:.5} (5/7 = {:.5}, rel. {:.2e}); slip velocity {slip:.2e} m/s",
        v / v0,
        5.0 / 7.0,
        v / v0 * 7.0 / 5.0 - 1.0
    );
    assert!((v / v0 * 7.0 / 5.0 - 1.0).abs() < 0.01);
    assert!(slip.abs() < 1e-3 * v0);
}

#[test]
fn hertz_on_a_plane_uses_r_and_m() {
    let l = law(
        r#"{"normal": {"model": "hertz/material", "E": 7e10, "nu": 0.3},
                    "tangential": {"model": "mindlin", "mu": 0.3}}"#,
    );
    let cfg = Config {
        gravity: Vector3::zeros(),
        ..Config::default()
    };
    let mut w = World::new(cfg, Laws::single(l, l)).unwrap();
    w.add_wall(Plane::new(Vector3::zeros(), Vector3::new(1.0, 1.0, 1.0)).unwrap())
        .unwrap();
    let (r, v) = (1e-3, 1.0);
    let n = Vector3::new(1.0, 1.0, 1.0).normalize();
    w.add_sphere(n * (r + 1e-7), -n * v, r, 2500.0, 0).unwrap();
    let m = w.spheres.m[0];
    let e_star = 7e10 / (2.0 * (1.0 - 0.09));
    let d_max = (15.0 * m * v * v / (16.0 * e_star * r.sqrt())).powf(0.4);
    let t_c = 2.0 * d_max / v * impact_integral(2.5);
    w.config.dt = t_c / 3777.7;
    let overlap = |w: &World| r - w.walls[0].gap(&w.spheres.x[0]);
    let mut d_prev = overlap(&w);
    while overlap(&w) <= 0.0 {
        d_prev = overlap(&w);
        w.step();
    }
    let cross = |w: &World, d0: f64, d1: f64| w.time - w.config.dt * d1 / (d1 - d0);
    let t0 = cross(&w, d_prev, overlap(&w));
    while overlap(&w) > 0.0 {
        d_prev = overlap(&w);
        w.step();
    }
    let t = cross(&w, d_prev, overlap(&w)) - t0;
    let e = w.spheres.v[0].dot(&n) / v;
    println!("sphere on an oblique plane: t_c = {t_c:.6e} s, measured {t:.6e} s (rel. {:.2e}); e = {e:.6}", t / t_c - 1.0);
    assert!((t / t_c - 1.0).abs() < 0.01 && (e - 1.0).abs() < 1e-3);
}

#[test]
fn an_adhesive_collision_balances_its_energy() {
    // JKR + van der Waals: the list must keep the pair while the neck stretches (reach).
    let l = law(
        r#"{"normal": {"model": "jkr", "E": 1e8, "nu": 0.3, "gamma": 0.05},
                    "damping": {"model": "viscoelastic", "eta": 20},
                    "tangential": {"model": "mindlin", "mu": 0.3},
                    "vdw": {"hamaker": 1e-19, "cutoff": 1e-7}}"#,
    );
    let cfg = Config {
        gravity: Vector3::zeros(),
        energy: true,
        ..Config::default()
    };
    let mut w = World::new(cfg, Laws::single(l, l)).unwrap();
    let r = 10e-6;
    w.add_sphere(Vector3::zeros(), Vector3::new(0.1, 0.02, 0.0), r, 2500.0, 0)
        .unwrap();
    w.add_sphere(
        Vector3::new(2.0 * r + 2e-7, 0.3 * r, 0.0),
        Vector3::new(-0.1, 0.0, 0.0),
        0.8 * r,
        2500.0,
        0,
    )
    .unwrap();
    w.config.dt = w.critical_dt(0.02, 0.05);
    let mut worst = 0.0f64;
    let mut touched = false;
    for _ in 0..200 {
        w.run(50);
        touched |= w.contacts().any(|c| c.2 > 0.0);
        worst = worst.max(w.energy().balance_error.abs());
    }
    let e = w.energy();
    let sep = (w.spheres.x[1] - w.spheres.x[0]).norm() - 1.8 * r;
    println!(
        "{} steps: gap now {sep:.2e} m; E0 {:.3e} J, kinetic {:.3e}, strain {:.3e}, damping {:.3e}, friction {:.3e}; worst balance error {worst:.2e}",
        w.counters.steps, e.initial, e.kinetic(), e.strain, e.damping, e.friction
    );
    assert!(touched && worst < 1e-3);
}
