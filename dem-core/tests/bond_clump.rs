//! Bonded (improved-ORC) clumps: placed members carry the grain's exact mass, centroid and
//! inertia; the intra-clump bond graph is connected; overlapping pairs are reported with their
//! reference gap.

use clumpgen::outline::parse_outline;
use clumpgen::{make_template, ClumpParams, ReadOptions, Template};
use dem_core::bond::{BondGroup, BondModel, Bonds, Criterion, ParallelBondParams};
use dem_core::bonded_clump::{place_bonded_clump_in, Placement};
use dem_core::State;

/// An L-shaped grain (mm) with at most 9 discs, as in S0's cutting runs.
fn template() -> Template {
    let text = "x y\n0 0\n3 0\n3 1\n1 1\n1 3\n0 3\n";
    let ol = parse_outline(text, "L", "mem.csv", false, &ReadOptions::default()).unwrap();
    let p = ClumpParams {
        thickness: 1e-3,
        max_discs: 9,
        ..ClumpParams::default()
    };
    make_template(&ol, &p).unwrap()
}

fn bonds() -> Bonds {
    Bonds::new(vec![BondGroup {
        name: "intra".into(),
        model: BondModel::Parallel(ParallelBondParams {
            kn: 1e14,
            ks: 4e13,
            lambda: 1.0,
            beta: 1.0,
        }),
        criterion: Criterion::Stress {
            tensile: 1e8,
            cohesion: 1e8,
            friction_angle: 0.5,
        },
    }])
    .unwrap()
}

#[test]
fn placed_members_have_the_grain_mass_centroid_and_inertia() {
    let tpl = template();
    assert!(tpl.discs.len() >= 3 && tpl.discs.len() <= 9);
    let mut st = State {
        thickness: 2e-3, // twice the template's: masses double
        ..State::default()
    };
    st.discs.push_uniform(-1.0, -1.0, 1e-3, 1.0, 2e-3, 0); // an unrelated disc first
    let mut b = bonds();
    let p = Placement {
        x: 0.25,
        y: -0.1,
        angle: 0.7,
        material: 2,
        grain: 5,
        intra_group: 0,
        touch_tol: 0.0,
    };
    let placed = place_bonded_clump_in(&mut st, &mut b, &tpl, &p).unwrap();
    let d = &st.discs;
    let m: f64 = placed.discs.iter().map(|&k| d.m[k]).sum();
    let mp = 2.0 * tpl.target.mass;
    assert!((m - mp).abs() < 1e-9 * mp);
    let cx = placed.discs.iter().map(|&k| d.m[k] * d.x[k]).sum::<f64>() / m;
    let cy = placed.discs.iter().map(|&k| d.m[k] * d.y[k]).sum::<f64>() / m;
    let size = tpl.shape.r_eq;
    assert!((cx - 0.25).abs() < 1e-9 * size && (cy + 0.1).abs() < 1e-9 * size);
    let inertia: f64 = placed
        .discs
        .iter()
        .map(|&k| d.inertia[k] + d.m[k] * ((d.x[k] - cx).powi(2) + (d.y[k] - cy).powi(2)))
        .sum();
    let ip = 2.0 * tpl.target.inertia;
    assert!((inertia - ip).abs() < 1e-8 * ip, "{inertia} vs {ip}");
    assert!(placed
        .discs
        .iter()
        .all(|&k| d.group[k] == 5 && d.material[k] == 2));
    // Connected bond graph: n − 1 bonds at least, every member reached from the first.
    let n = placed.discs.len();
    assert!(placed.bonds.len() >= n - 1);
    let mut reach = vec![false; st.discs.len()];
    reach[placed.discs[0]] = true;
    for _ in 0..n {
        for v in b.iter() {
            if reach[v.i as usize] || reach[v.j as usize] {
                reach[v.i as usize] = true;
                reach[v.j as usize] = true;
            }
        }
    }
    assert!(placed.discs.iter().all(|&k| reach[k]));
    // Every overlapping member pair is bonded and reported with g0 = its (negative) gap.
    for v in b.iter() {
        let g = dem_core::bond::install::gap(&st, v.i as usize, v.j as usize);
        assert!((v.g0 - g).abs() < 1e-15);
        if g < 0.0 {
            let ids = (st.discs.id[v.i as usize], st.discs.id[v.j as usize]);
            assert!(placed
                .offsets
                .iter()
                .any(|&(a, c, g0)| (a, c) == ids && g0 == v.g0));
        }
    }
    assert!(!placed.offsets.is_empty());
}

#[test]
fn disconnected_members_are_joined_along_a_minimum_spanning_tree() {
    // Three discs far apart on a line: no touching pairs; the MST bonds 0-1 and 1-2, not 0-2.
    let mut tpl = template();
    tpl.discs.truncate(3);
    for (k, d) in tpl.discs.iter_mut().enumerate() {
        d.x = [0.0, 1.0, 2.5][k];
        d.y = 0.0;
        d.r = 0.1;
    }
    let mut st = State::default();
    let mut b = bonds();
    let p = Placement {
        x: 0.0,
        y: 0.0,
        angle: 0.0,
        material: 0,
        grain: 0,
        intra_group: 0,
        touch_tol: 0.0,
    };
    let placed = place_bonded_clump_in(&mut st, &mut b, &tpl, &p).unwrap();
    let mut pairs: Vec<(u32, u32)> = b.iter().map(|v| (v.i, v.j)).collect();
    pairs.sort();
    assert_eq!(pairs, vec![(0, 1), (1, 2)]);
    assert!(placed.offsets.is_empty());
    // Bad input is an error, not a panic.
    let mut bad = tpl.clone();
    bad.discs[1].m = -1.0;
    assert!(place_bonded_clump_in(&mut st, &mut b, &bad, &p).is_err());
    let mut p2 = p;
    p2.intra_group = 3;
    assert!(place_bonded_clump_in(&mut st, &mut b, &tpl, &p2).is_err());
    assert_eq!(st.discs.len(), 3);
}
