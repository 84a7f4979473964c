//! Packing scene: RSI, frictionless pour, settle, packing fraction and coordination.

mod common;
use common::*;
use dem_sphere::pack::{pack, PackSpec, SizeDist};
use dem_sphere::GridKind;
use nalgebra::Vector3;

fn spec(n: usize, sizes: SizeDist) -> PackSpec {
    let l = law(r#"{"normal": {"model": "hooke", "kn": 2000},
                    "damping": {"model": "coeff_restitution", "e": 0.3},
                    "tangential": {"model": "linear_nohistory", "gamma_t": 0, "mu": 0}}"#);
    PackSpec {
        n,
        sizes,
        density: 2500.0,
        box_lo: Vector3::zeros(),
        box_hi: Vector3::new(0.012, 0.012, 0.05),
        fill_top: 0.045,
        law: l,
        wall_law: l,
        gravity: Vector3::new(0.0, 0.0, -9.81),
        ke_per_sphere: 1e-10,
        max_time: 0.5,
        dt_fraction: 0.15,
        delta_rel: 0.05,
        seed: 1,
        attempts: 10_000,
        grid: GridKind::default(),
    }
}

#[test]
fn a_frictionless_pour_packs_densely() {
    let s = spec(
        400,
        SizeDist::Uniform {
            min: 0.9e-3,
            max: 1.1e-3,
        },
    );
    let p = pack(&s).unwrap();
    let (lo, hi) = p.window;
    println!(
        "400 spheres r ∈ [0.9, 1.1] mm, frictionless, e = 0.3: settled {} at t = {:.3} s ({} steps, KE/sphere {:.2e} J); \
         window ({:.2}, {:.2}, {:.2})–({:.2}, {:.2}, {:.2}) mm, {} spheres: φ = {:.4}, Z = {:.3}",
        p.settled, p.time, p.steps, p.ke_per_sphere,
        lo.x * 1e3, lo.y * 1e3, lo.z * 1e3, hi.x * 1e3, hi.y * 1e3, hi.z * 1e3,
        p.in_window, p.fraction, p.coordination
    );
    assert!(p.settled);
    // A tiny bed (6 diameters wide): a sane range, not 0.64.
    assert!(p.fraction > 0.55 && p.fraction < 0.66, "φ = {}", p.fraction);
    // Frictionless, near isostatic (Z → 6) for the non-rattlers.
    assert!(
        p.coordination > 4.5 && p.coordination < 7.0,
        "Z = {}",
        p.coordination
    );
}

#[test]
fn bad_input_is_refused_naming_the_field() {
    let mut s = spec(10, SizeDist::Mono(-1e-3));
    assert!(pack(&s)
        .unwrap_err()
        .to_string()
        .starts_with("sizes.radius: "));
    s.sizes = SizeDist::Mono(0.007);
    let e = pack(&s).unwrap_err().to_string();
    assert!(
        e.starts_with("box: extent 0.012 on axis 0 is smaller"),
        "{e}"
    );
    s.sizes = SizeDist::Mono(2e-3);
    s.n = 2000;
    let e = pack(&s).unwrap_err().to_string();
    assert!(e.starts_with("pack.n: could not insert sphere"), "{e}");
    println!("{e}");
    s.n = 10;
    s.fill_top = 0.06;
    assert!(pack(&s)
        .unwrap_err()
        .to_string()
        .starts_with("pack.fill_top: "));
    s.fill_top = 0.03;
    s.box_hi = Vector3::new(0.012, -1.0, 0.05);
    assert!(pack(&s).unwrap_err().to_string().starts_with("box"));
}
