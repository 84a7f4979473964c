//! Bad input is refused with an error naming the field, never a panic.

mod common;
use common::*;
use dem_sphere::{Config, GridKind, Laws, Plane, World};
use nalgebra::Vector3;

#[test]
fn bad_spheres_walls_and_config_name_the_field() {
    let l = hooke_friction(1000.0, 0.5, 0.5);
    let laws = || Laws::single(l, l);
    let mut w = World::new(Config::default(), laws()).unwrap();
    let z = Vector3::zeros();
    let msg = |e: dem_sphere::SphereError| e.to_string();
    assert!(msg(w.add_sphere(z, z, 0.0, 2500.0, 0).unwrap_err())
        .starts_with("sphere.radius: must be a finite number > 0, got 0"));
    assert!(msg(w.add_sphere(z, z, -1.0, 2500.0, 0).unwrap_err()).starts_with("sphere.radius: "));
    assert!(
        msg(w.add_sphere(z, z, f64::NAN, 2500.0, 0).unwrap_err()).starts_with("sphere.radius: ")
    );
    assert!(msg(w.add_sphere(z, z, 1e-3, 0.0, 0).unwrap_err()).starts_with("sphere.density: "));
    assert!(msg(w.add_sphere(z, z, 1e-3, 1.0, 1).unwrap_err())
        .starts_with("sphere.species: must be < 1"));
    assert!(msg(w
        .add_sphere(Vector3::new(f64::INFINITY, 0.0, 0.0), z, 1e-3, 1.0, 0)
        .unwrap_err())
    .starts_with("sphere.x: "));
    assert!(msg(w
        .add_wall(Plane {
            point: z,
            normal: z,
            velocity: z
        })
        .unwrap_err())
    .starts_with("plane.normal: "));
    for p in dem_sphere::box_walls(z, Vector3::repeat(0.002)).unwrap() {
        w.add_wall(p).unwrap();
    }
    let e = msg(w
        .add_sphere(Vector3::repeat(0.001), z, 1.5e-3, 2500.0, 0)
        .unwrap_err());
    assert!(
        e.starts_with("sphere.radius: the diameter 0.003 exceeds the gap 0.002"),
        "{e}"
    );
    assert!(msg(dem_sphere::box_walls(z, z).unwrap_err()).starts_with("box.hi: "));
    let bad = |c: Config| msg(World::new(c, laws()).unwrap_err());
    assert!(bad(Config {
        dt: 0.0,
        ..Config::default()
    })
    .starts_with("config.dt: "));
    assert!(bad(Config {
        skin: -1.0,
        ..Config::default()
    })
    .starts_with("config.skin: "));
    assert!(bad(Config {
        grid: GridKind::MultiLevel { ratio: 1.0 },
        ..Config::default()
    })
    .starts_with("config.grid.ratio: "));
    assert!(msg(Laws::table(vec![l; 3], vec![l; 2]).unwrap_err()).starts_with("laws.pair: "));
}

#[test]
fn an_empty_world_and_a_lone_sphere_step() {
    let l = hooke_friction(1000.0, 0.5, 0.5);
    let mut w = World::new(Config::default(), Laws::single(l, l)).unwrap();
    w.run(3);
    w.add_sphere(Vector3::zeros(), Vector3::zeros(), 1e-3, 2500.0, 0)
        .unwrap();
    w.run(10);
    let t = 10.0 * w.config.dt;
    assert!((w.spheres.v[0].z + 9.81 * t).abs() < 1e-12);
}

#[test]
fn a_blown_up_state_does_not_hang_or_panic_the_grids() {
    use dem_sphere::{find_pairs, Periodic};
    let x = vec![
        Vector3::new(f64::NAN, 0.0, 0.0),
        Vector3::zeros(),
        Vector3::new(1e300, -1e300, 0.0),
    ];
    let r = vec![1.0, 1.0, 1.0];
    for kind in [GridKind::Single, GridKind::MultiLevel { ratio: 2.0 }] {
        let (p, _) = find_pairs(kind, &Periodic::none(), &x, &r, 0.1);
        assert!(p.is_empty());
    }
}

#[test]
fn each_species_pair_takes_its_own_law() {
    let k = |kn: f64| hooke_friction(kn, 0.5, 0.5);
    // Species 0 and 1: k_00 = 100, k_01 = k_10 = 200, k_11 = 300; walls 400 and 500.
    let laws = Laws::table(
        vec![k(100.0), k(200.0), k(200.0), k(300.0)],
        vec![k(400.0), k(500.0)],
    )
    .unwrap();
    let cfg = Config {
        gravity: Vector3::zeros(),
        ..Config::default()
    };
    let mut w = World::new(cfg, laws).unwrap();
    w.add_wall(Plane::new(Vector3::zeros(), Vector3::z()).unwrap())
        .unwrap();
    let (r, d) = (1e-3, 1e-5);
    let z = Vector3::zeros();
    w.add_sphere(Vector3::new(0.0, 0.0, r - d), z, r, 2500.0, 0)
        .unwrap();
    w.add_sphere(Vector3::new(2.0 * r - d, 0.0, r - 2.0 * d), z, r, 2500.0, 1)
        .unwrap();
    w.add_sphere(Vector3::new(-2.0 * r + d, 0.0, 0.5), z, r, 2500.0, 0)
        .unwrap();
    w.add_sphere(Vector3::new(-4.0 * r + 2.0 * d, 0.0, 0.5), z, r, 2500.0, 0)
        .unwrap();
    w.compute_forces();
    let f = w.forces().0;
    // Sphere 0: wall 400·d up, species 0–1 pair ≈ 200·d along −x (the pair is tilted by
    // d/2r: within 1 %); sphere 1: wall 500·2d; spheres 2–3: 100·d.
    let near = |a: f64, b: f64| (a / b - 1.0).abs() < 0.01;
    assert!(
        near(f[0].z, 400.0 * d) && near(-f[0].x, 200.0 * d),
        "{:?}",
        f[0]
    );
    assert!(
        near(f[1].z, 1000.0 * d) && near(f[1].x, 200.0 * d),
        "{:?}",
        f[1]
    );
    assert!(near(f[2].x.abs(), 100.0 * d), "{:?}", f[2]);
    let e = Laws::table(
        vec![k(100.0), k(200.0), k(250.0), k(300.0)],
        vec![k(1.0); 2],
    )
    .unwrap_err();
    assert!(e.to_string().starts_with("laws.pair[1][0]: "));
}
