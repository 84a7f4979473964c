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
