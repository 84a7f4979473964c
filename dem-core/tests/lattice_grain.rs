//! Lattice grains (S3's crushable grains, issue 25 item 4) placed as bonded clumps: the nodes
//! become free discs with the template's masses, the bonds are exactly the template's links
//! (no pair search), and with contact-bond springs k_n, k_s from `link_stiffness(E, ν, t)` an
//! affine strain stores, link by link, the lattice energy of docs/lattice.md:
//! U = Σ_links ½S²[k_n (nᵀεn)² + k_s (tᵀεn)²] (θ = ω = 0 for a symmetric ε); summed over the
//! three link directions in equal numbers this is the plane-stress energy of the medium with
//! the E and ν asked for.

use clumpgen::clump::LatticeParams;
use clumpgen::lattice::LinkKind;
use clumpgen::lattice_elastic::{link_stiffness, LinkStiffness};
use clumpgen::outline::parse_outline;
use clumpgen::{make_template, ClumpParams, Length, Method, ReadOptions, Template};
use dem_core::bond::{BondGroup, BondModel, Bonds, ContactBondParams, Criterion};
use dem_core::bonded_clump::{place_bonded_clump_in, Placement};
use dem_core::State;

const E: f64 = 70e9;
const NU: f64 = 0.2;

fn lattice_template(spacing_m: f64) -> Template {
    let text = "x,y\n0,0\n4,0\n4,2\n0,2\n"; // a 4 × 2 mm rectangle
    let ol = parse_outline(text, "g", "g.csv", false, &ReadOptions::default()).unwrap();
    let p = ClumpParams {
        method: Method::Lattice,
        lattice: Some(LatticeParams {
            spacing: Length::Metres(spacing_m),
            node_radius: 1.0,
        }),
        ..ClumpParams::default()
    };
    make_template(&ol, &p).unwrap()
}

fn place(tpl: &Template, angle: f64) -> (State, Bonds) {
    let mut st = State {
        thickness: tpl.thickness,
        ..State::default()
    };
    let k = link_stiffness(E, NU, st.thickness).unwrap();
    let mut bonds = Bonds::new(vec![BondGroup {
        name: "lattice".into(),
        model: BondModel::Contact(ContactBondParams {
            kn: k.k_n,
            ks: k.k_s,
        }),
        criterion: Criterion::Force {
            tensile: 1e30,
            shear: 1e30,
            moment: f64::INFINITY,
        },
    }])
    .unwrap();
    let placed = place_bonded_clump_in(
        &mut st,
        &mut bonds,
        tpl,
        &Placement {
            x: 0.01,
            y: -0.02,
            angle,
            material: 0,
            grain: 7,
            intra_group: 0,
            touch_tol: 0.0,
        },
    )
    .unwrap();
    assert_eq!(placed.discs.len(), tpl.discs.len());
    (st, bonds)
}

/// The energy ½S²[k_n (nᵀεn)² + k_s (tᵀεn)²] of a link of direction φ under the strain ε.
fn link_energy(k: &LinkStiffness, s: f64, eps: [[f64; 2]; 2], phi: f64) -> f64 {
    let (n, t) = ([phi.cos(), phi.sin()], [-phi.sin(), phi.cos()]);
    let en = [
        eps[0][0] * n[0] + eps[0][1] * n[1],
        eps[1][0] * n[0] + eps[1][1] * n[1],
    ];
    let (nn, tn) = (n[0] * en[0] + n[1] * en[1], t[0] * en[0] + t[1] * en[1]);
    0.5 * s * s * (k.k_n * nn * nn + k.k_s * tn * tn)
}

#[test]
fn the_bonds_are_the_templates_links() {
    let tpl = lattice_template(0.2e-3);
    let lat = tpl.lattice.as_ref().expect("a lattice template");
    let s = lat.spacing;
    for angle in [0.0, 0.7] {
        let (st, bonds) = place(&tpl, angle);
        assert_eq!(bonds.len(), lat.links.len());
        assert!(lat.links.len() > 2 * tpl.discs.len(), "a 2D lattice");
        for (b, l) in bonds.iter().zip(&lat.links) {
            assert_eq!((b.i as usize, b.j as usize), (l.i, l.j));
            let d = &st.discs;
            let dist = (d.x[l.j] - d.x[l.i]).hypot(d.y[l.j] - d.y[l.i]);
            assert!((dist - s).abs() <= 1e-12 * s, "link {l:?}: {dist} vs {s}");
        }
        let m: f64 = st.discs.m.iter().sum();
        assert!((m - tpl.achieved.mass).abs() <= 1e-12 * m);
        assert!(st.discs.group.iter().all(|&g| g == 7));
    }
}

/// Kinematic steps as in bond_parallel.rs: bond stage at the current positions and
/// velocities, then x += v·dt.
fn strain_energy(tpl: &Template, eps: [[f64; 2]; 2]) -> (f64, f64) {
    let (mut st, mut bonds) = place(tpl, 0.3);
    let dt = 1e-9;
    let (cx, cy) = (0.01, -0.02);
    let d = &mut st.discs;
    for k in 0..d.len() {
        let (x, y) = (d.x[k] - cx, d.y[k] - cy);
        d.vx[k] = (eps[0][0] * x + eps[0][1] * y) / dt;
        d.vy[k] = (eps[1][0] * x + eps[1][1] * y) / dt;
    }
    for _ in 0..2 {
        st.discs.clear_forces();
        bonds.compute(&mut st, dt);
        let d = &mut st.discs;
        for k in 0..d.len() {
            d.x[k] += d.vx[k] * dt;
            d.y[k] += d.vy[k] * dt;
            d.vx[k] = 0.0;
            d.vy[k] = 0.0;
        }
    }
    // The lattice energy, link by link, from the template's link directions (rotated by the
    // placement's 0.3 rad).
    let k = link_stiffness(E, NU, st.thickness).unwrap();
    let s = tpl.lattice.as_ref().unwrap().spacing;
    let mut expected = 0.0;
    for l in &tpl.lattice.as_ref().unwrap().links {
        let phi = 0.3
            + match l.kind {
                LinkKind::D0 => 0.0,
                LinkKind::D60 => 60f64.to_radians(),
                LinkKind::D120 => 120f64.to_radians(),
            };
        expected += link_energy(&k, s, eps, phi);
    }
    (bonds.strain_energy(), expected)
}

#[test]
fn an_affine_strain_stores_the_lattice_energy() {
    let tpl = lattice_template(0.2e-3);
    for eps in [
        [[1e-6, 0.0], [0.0, 0.0]],
        [[0.0, 0.0], [0.0, -2e-6]],
        [[0.0, 1.5e-6], [1.5e-6, 0.0]],
        [[1e-6, -0.7e-6], [-0.7e-6, 0.4e-6]],
    ] {
        let (u, expected) = strain_energy(&tpl, eps);
        assert!(expected > 0.0);
        // Second-order terms (the link turning during the step, ~ε) bound the difference.
        assert!(
            (u - expected).abs() <= 1e-4 * expected,
            "ε = {eps:?}: {u} vs {expected}"
        );
    }
}

/// With the three link directions in equal numbers the per-link energies sum to the
/// plane-stress energy of the medium: U = N/3 · A_c · t · E/(2(1 − ν²)) · [(1 − ν) ε:ε + ν (tr ε)²]
/// per set of three links (A_c = (√3/2) S²): here checked with the link energies of the test
/// above, reweighted to equal direction counts.
#[test]
fn three_link_directions_give_the_continuum_energy() {
    let s: f64 = 1e-4;
    let t = 1.0;
    let k = link_stiffness(E, NU, t).unwrap();
    for eps in [
        [[1e-6, 0.0], [0.0, 0.0]],
        [[0.0, 1.5e-6], [1.5e-6, 0.0]],
        [[1e-6, -0.7e-6], [-0.7e-6, 0.4e-6]],
    ] {
        let mut u = 0.0;
        for phi in [0.0f64, 60.0, 120.0] {
            u += link_energy(&k, s, eps, phi.to_radians() + 0.3);
        }
        let tr = eps[0][0] + eps[1][1];
        let ee: f64 = eps.iter().flatten().map(|v| v * v).sum();
        let ac = 3f64.sqrt() / 2.0 * s * s;
        let continuum = ac * t * E / (2.0 * (1.0 - NU * NU)) * ((1.0 - NU) * ee + NU * tr * tr);
        assert!(
            (u - continuum).abs() <= 1e-12 * continuum,
            "{u} vs {continuum}"
        );
    }
}
