//! Single-grain crushing (`dem_lab::crushing::grain`, docs/lattice.md §4) and its parts:
//!
//! - one lattice link pulled apart breaks at the force its criterion gives in closed form
//!   (force: F_t; strain: k_n ε_t S; energy: √(2 k_n G_c (S/√3) t), the energy criterion's
//!   G_c(S/√3)t converted to the bond's G_c/(f√3) per area f S t);
//! - a crushed disc-shaped grain: strength positive, both stages' fragments, the break log
//!   consistent with the fragments (the components of the links not broken by stage 1's time
//!   are stage 1's fragments), every logged break at or above the energy threshold, and the
//!   energy balance through breakage (work = strain + kinetic + damping + friction + released)
//!   within 1 % of the work.

use clumpgen::clump::LatticeParams;
use clumpgen::outline::parse_outline;
use clumpgen::{make_template, ClumpParams, Length, Method, ReadOptions};
use dem_core::bond::{BondGroup, BondModel, BondStatus, Bonds, ContactBondParams};
use dem_core::fragments::lattice_components;
use dem_core::State;
use dem_lab::crushing::grain::{self, CrushTest, LinkCriterion};

/// Two nodes of radius f·S/2, S apart, one link; the right node pulled along +x at a small
/// constant speed; the link's normal force in the step before it breaks (N, tension > 0).
fn pull_to_failure(c: LinkCriterion, f: f64) -> (f64, f64) {
    let (e, nu, t, s) = (70e9, 0.2, 1.0, 1e-4);
    let k = clumpgen::link_stiffness(e, nu, t).unwrap();
    let mut st = State {
        thickness: t,
        ..State::default()
    };
    let r = 0.5 * f * s;
    st.discs.push(0.0, 0.0, r, 1.0, 1.0, 0, 0);
    st.discs.push(s, 0.0, r, 1.0, 1.0, 0, 0);
    let mut bonds = Bonds::new(vec![BondGroup {
        name: "lattice".into(),
        model: BondModel::Contact(ContactBondParams {
            kn: k.k_n,
            ks: k.k_s,
        }),
        criterion: c.bond_criterion(f, s, t),
    }])
    .unwrap();
    bonds.add(&st, 0, 1, 0).unwrap();
    let expected = k.k_n * c.failure_strain(k.k_n, s, t) * s;
    // Steps of 1e-4 of the failure opening.
    let (dt, v) = (1e-9, expected / k.k_n * 1e-4 / 1e-9);
    st.discs.vx[1] = v;
    let mut last = 0.0;
    for _ in 0..20_000 {
        st.discs.clear_forces();
        bonds.compute(&mut st, dt);
        let b = bonds.get(0);
        if b.status != BondStatus::Intact {
            return (last, expected);
        }
        last = -b.fn_;
        st.discs.x[1] += v * dt;
    }
    panic!("the link did not break (force {last}, expected {expected})");
}

#[test]
fn a_link_breaks_at_its_criterions_closed_form_force() {
    for (c, f) in [
        (
            LinkCriterion::Force {
                tensile: 2.0e3,
                shear: 2.0e3,
            },
            0.9,
        ),
        (
            // 50 MPa on A = (S/√3)·t = 5.77e-5 m²: 2.89 kN.
            LinkCriterion::Stress {
                tensile: 50e6,
                shear: 50e6,
            },
            0.9,
        ),
        (
            LinkCriterion::Strain {
                tensile: 1.5e-3,
                shear: 1.5e-3,
            },
            1.0,
        ),
        (
            LinkCriterion::Energy {
                fracture_energy: 30.0,
            },
            0.9,
        ),
        (
            LinkCriterion::Energy {
                fracture_energy: 30.0,
            },
            1.0,
        ),
    ] {
        let (got, expected) = pull_to_failure(c, f);
        // The last intact step is within one step's increment (1e-4) below the failure load.
        assert!(
            got <= expected && got >= expected * (1.0 - 2e-4),
            "{c:?}, f {f}: {got} N vs {expected} N"
        );
    }
    // The stress criterion's force, by hand: σ_t times the cell edge S/√3 times t (S = 0.1 mm,
    // t = 1 m): 2886.75 N.
    let c = LinkCriterion::Stress {
        tensile: 50e6,
        shear: 50e6,
    };
    let (got, _) = pull_to_failure(c, 0.9);
    let by_hand = 50e6 * 1e-4 / 3f64.sqrt();
    assert!(
        got <= by_hand && got >= by_hand * (1.0 - 2e-4),
        "{got} N vs {by_hand} N"
    );
}

fn disc_template(dir: &std::path::Path) -> (std::path::PathBuf, clumpgen::Template) {
    // A 64-gon of radius 1 mm.
    let mut text = String::from("# units: mm\nx,y\n");
    for k in 0..64 {
        let a = k as f64 * std::f64::consts::TAU / 64.0;
        text += &format!("{},{}\n", a.cos(), a.sin());
    }
    let ol = parse_outline(&text, "disc", "disc.csv", false, &ReadOptions::default()).unwrap();
    let p = ClumpParams {
        method: Method::Lattice,
        density: 2650.0,
        lattice: Some(LatticeParams {
            spacing: Length::OfReq(0.2),
            node_radius: 0.9,
        }),
        ..ClumpParams::default()
    };
    let tpl = make_template(&ol, &p).unwrap();
    std::fs::create_dir_all(dir).unwrap();
    let file = dir.join("disc.json");
    tpl.save(&file).unwrap();
    (file, tpl)
}

#[test]
fn a_crushed_disc_breaks_in_two_stages_with_its_energy_balanced() {
    let dir = std::env::temp_dir().join(format!("dem-crush-test-{}", std::process::id()));
    let (file, tpl) = disc_template(&dir);
    let g_c = 30.0;
    let test = CrushTest {
        criterion: LinkCriterion::Energy {
            fracture_energy: g_c,
        },
        ..CrushTest::default()
    };
    let o = grain::run(&test, &file, &dir, &mut |_, _| {}).unwrap();
    let r = &o.result;
    assert!(r.strength > 0.0 && r.strength.is_finite());
    assert_eq!(r.grain.nodes, tpl.discs.len());
    // d: the platen gap at first contact, at most the disc's diameter.
    assert!(
        r.grain.d > 1.5e-3 && r.grain.d <= 2e-3 + 1e-12,
        "{}",
        r.grain.d
    );
    // Stage 1 ended at the first major breakage: the largest fragment below 90 %.
    assert!(
        r.stage1.fragments.largest_mass_fraction < 0.9,
        "{:?}",
        r.stage1
    );
    assert!(r.stage2.broken_links >= r.stage1.broken_links);
    assert!(r.stage2.closure > 1.9 * r.stage1.closure);
    // The break log and the fragments agree.
    let csv = std::fs::read_to_string(dir.join("crush.breaks.csv")).unwrap();
    let lat = tpl.lattice.as_ref().unwrap();
    let mut broken1 = vec![];
    let mut n = 0;
    for line in csv.lines().skip(1) {
        let f: Vec<&str> = line.split(',').collect();
        let time: f64 = f[0].parse().unwrap();
        let link: usize = f[3].parse().unwrap();
        let (i, j): (usize, usize) = (f[4].parse().unwrap(), f[5].parse().unwrap());
        assert_eq!((lat.links[link].i, lat.links[link].j), (i, j));
        assert_eq!(f[6], "energy");
        // Every break at or above the threshold G_c (S/√3) t.
        let energy: f64 = f[10].parse().unwrap();
        let threshold = g_c * lat.spacing / 3f64.sqrt() * tpl.thickness;
        assert!(energy >= threshold * (1.0 - 1e-9), "{energy} < {threshold}");
        if time <= r.stage1.time {
            broken1.push(link);
        }
        n += 1;
    }
    assert_eq!(n, r.stage2.broken_links);
    assert_eq!(broken1.len(), r.stage1.broken_links);
    let comps = lattice_components(tpl.discs.len(), &lat.links, &broken1);
    let big = comps.iter().filter(|c| c.len() > 1).count();
    assert_eq!(
        (big, comps.len() - big),
        (r.stage1.fragments.fragments, r.stage1.fragments.fines)
    );
    // Energy balance through breakage.
    let sum = r.strain_energy + r.kinetic_energy + r.damping + r.friction + r.released;
    assert!(r.work > 0.0 && r.released > 0.0);
    assert!(
        (sum - r.work).abs() <= 0.01 * r.work,
        "work {} vs {sum}",
        r.work
    );
    // The force-displacement file has both stages' rows.
    let f = std::fs::read_to_string(dir.join("crush.force.csv")).unwrap();
    let last: Vec<f64> = f
        .lines()
        .last()
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    // The last row is at the last multiple of the history cadence before the end.
    assert!(
        last[1] <= r.stage2.closure * (1.0 + 1e-12) && last[1] >= 0.99 * r.stage2.closure,
        "{} vs {}",
        last[1],
        r.stage2.closure
    );
    let _ = std::fs::remove_dir_all(&dir);
}
