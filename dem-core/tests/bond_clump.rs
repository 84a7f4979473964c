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
        // No nearly massless members (they would set a tiny time step).
        mass_floor: 0.05,
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

/// Least-squares slope of `y` against `x`.
fn slope(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    sxy / sxx
}

#[test]
fn a_kicked_bonded_clump_moves_with_the_grain_mass_and_inertia() {
    const STEPS: usize = 100_000;
    use dem_core::bond::world_with_bonds;
    use dem_core::contact::LinearSpringDashpot;
    use dem_core::{ContactLaws, ContactModel, Params};
    // A member disc is given an impulse J = m_k v0 (a short force). The clump must then move
    // as the grain would: centroid velocity J/M and angular velocity (r_k × J)/I with the
    // template's mass M and inertia I about its centroid (S0, consistency equations 1-3).
    let tpl = template();
    let mut st = State {
        thickness: 1e-3,
        ..State::default()
    };
    let mut b = bonds();
    let p = Placement {
        x: 0.0,
        y: 0.0,
        angle: 0.3,
        material: 0,
        grain: 1,
        intra_group: 0,
        touch_tol: 0.0,
    };
    let placed = place_bonded_clump_in(&mut st, &mut b, &tpl, &p).unwrap();
    let ids: Vec<u32> = placed.discs.iter().map(|&k| st.discs.id[k]).collect();
    // Normal-only contact between members: with overlapping members a tangential contact
    // force would be applied with the torque arms R_i, R_j of the contact law rather than the
    // distances to the contact point, which does not conserve angular momentum at deep
    // overlaps; this test is about the clump's mass and inertia.
    let laws = ContactLaws::uniform(ContactModel::Linear(LinearSpringDashpot::elastic(
        1e7, 0.0, 0.0,
    )));
    let mut w = world_with_bonds(st, Params::default(), laws, b, &placed.offsets).unwrap();
    // Force-free at rest, although members overlap (bond and contact reference gaps).
    w.step();
    let fmax = (0..w.state.discs.len())
        .map(|k| w.state.discs.fx[k].abs().max(w.state.discs.fy[k].abs()))
        .fold(0.0, f64::max);
    assert!(fmax < 1e-9, "force at rest {fmax}");
    // Kick the member farthest from the centroid.
    let idx = |w: &dem_core::World, id: u32| w.index_of_id(id).unwrap();
    let far = *ids
        .iter()
        .max_by(|&&a, &&c| {
            let d = &w.state.discs;
            let (ka, kc) = (idx(&w, a), idx(&w, c));
            d.x[ka].hypot(d.y[ka]).total_cmp(&d.x[kc].hypot(d.y[kc]))
        })
        .unwrap();
    let k = idx(&w, far);
    let v0 = [0.02, -0.05];
    let (mk, rx, ry) = (w.state.discs.m[k], w.state.discs.x[k], w.state.discs.y[k]);
    w.state.discs.vx[k] = v0[0];
    w.state.discs.vy[k] = v0[1];
    let mass = tpl.target.mass;
    let inertia = tpl.target.inertia;
    let (j0, j1) = (mk * v0[0], mk * v0[1]);
    let v_expect = [j0 / mass, j1 / mass];
    let w_expect = (rx * j1 - ry * j0) / inertia;
    // Track the centroid and the mass-weighted best-fit rotation of the members about it
    // (θ = atan2 Σ m (r₀ × r), Σ m (r₀ · r), r₀ the initial offsets): the rigid-body part of
    // the motion, insensitive to the vibration of light members.
    let r0: Vec<(f64, f64, f64)> = ids
        .iter()
        .map(|&id| {
            let q = idx(&w, id);
            let d = &w.state.discs;
            (d.m[q], d.x[q], d.y[q])
        })
        .collect();
    let (mut ts, mut cx, mut cy, mut ang) = (vec![], vec![], vec![], vec![]);
    for _ in 0..STEPS {
        w.step();
        let d = &w.state.discs;
        let (mut sm, mut sx, mut sy) = (0.0, 0.0, 0.0);
        for &id in &ids {
            let q = idx(&w, id);
            sm += d.m[q];
            sx += d.m[q] * d.x[q];
            sy += d.m[q] * d.y[q];
        }
        let (xc, yc) = (sx / sm, sy / sm);
        let (mut cross, mut dot) = (0.0, 0.0);
        for (&id, &(m, x0, y0)) in ids.iter().zip(&r0) {
            let q = idx(&w, id);
            let (x, y) = (d.x[q] - xc, d.y[q] - yc);
            cross += m * (x0 * y - y0 * x);
            dot += m * (x0 * x + y0 * y);
        }
        ts.push(w.state.time);
        cx.push(xc);
        cy.push(yc);
        ang.push(cross.atan2(dot));
    }
    let (vx, vy, om) = (slope(&ts, &cx), slope(&ts, &cy), slope(&ts, &ang));
    let vmag = v_expect[0].hypot(v_expect[1]);
    eprintln!(
        "clump: V = ({vx:.5e}, {vy:.5e}) expected ({:.5e}, {:.5e}); ω = {om:.5e} expected {w_expect:.5e}; rotated {:.3} rad",
        v_expect[0],
        v_expect[1],
        ang.last().unwrap() - ang[0]
    );
    assert!((vx - v_expect[0]).abs() < 1e-3 * vmag && (vy - v_expect[1]).abs() < 1e-3 * vmag);
    assert!((om / w_expect - 1.0).abs() < 2e-3, "ω {om} vs {w_expect}");
    assert_eq!(w.bonds.as_ref().unwrap().n_intact(), placed.bonds.len());
}

/// Least-squares fit y ≈ a + b x + c x²; returns c.
fn quad_coeff(x: &[f64], y: &[f64]) -> f64 {
    // Normal equations of the 3-parameter fit, on centred x for conditioning.
    let n = x.len() as f64;
    let mx = x.iter().sum::<f64>() / n;
    let mut s = [0.0f64; 5];
    let mut t = [0.0f64; 3];
    for (&xi, &yi) in x.iter().zip(y) {
        let u = xi - mx;
        let mut p = 1.0;
        for (k, sk) in s.iter_mut().enumerate() {
            *sk += p;
            if k < 3 {
                t[k] += p * yi;
            }
            p *= u;
        }
    }
    let a = [[s[0], s[1], s[2]], [s[1], s[2], s[3]], [s[2], s[3], s[4]]];
    let det = |m: [[f64; 3]; 3]| {
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    };
    let mut a2 = a;
    for r in 0..3 {
        a2[r][2] = t[r];
    }
    det(a2) / det(a)
}

#[test]
fn a_bonded_clump_under_force_and_torque_accelerates_with_the_grain_mass_and_inertia() {
    use dem_core::bond::world_with_bonds;
    use dem_core::contact::LinearSpringDashpot;
    use dem_core::{ContactLaws, ContactModel, ExternalLoad, Params};
    // A constant force F on one member and a torque T on another: the centroid accelerates at
    // F/M and the clump turns with α = (T + r × F)/I, M and I the template's (S0).
    let tpl = template();
    let mut st = State {
        thickness: 1e-3,
        ..State::default()
    };
    let mut b = bonds();
    let p = Placement {
        x: 0.0,
        y: 0.0,
        angle: -0.4,
        material: 0,
        grain: 1,
        intra_group: 0,
        touch_tol: 0.0,
    };
    let placed = place_bonded_clump_in(&mut st, &mut b, &tpl, &p).unwrap();
    let ids: Vec<u32> = placed.discs.iter().map(|&k| st.discs.id[k]).collect();
    let (fk, tk) = (placed.discs[1], placed.discs[0]);
    let (rx, ry) = (st.discs.x[fk], st.discs.y[fk]);
    let laws = ContactLaws::uniform(ContactModel::Linear(LinearSpringDashpot::elastic(
        1e7, 0.0, 0.0,
    )));
    let (f, torque) = ([2e-3, -1e-3], 3e-6);
    let mut w = world_with_bonds(st.clone(), Params::default(), laws, b, &placed.offsets).unwrap();
    w.loads.push(ExternalLoad {
        id: st.discs.id[fk],
        force: f,
        torque: 0.0,
    });
    w.loads.push(ExternalLoad {
        id: st.discs.id[tk],
        force: [0.0, 0.0],
        torque,
    });
    let (mass, inertia) = (tpl.target.mass, tpl.target.inertia);
    let a_expect = [f[0] / mass, f[1] / mass];
    let alpha_expect = (torque + rx * f[1] - ry * f[0]) / inertia;
    let idx = |w: &dem_core::World, id: u32| w.index_of_id(id).unwrap();
    let r0: Vec<(f64, f64, f64)> = ids
        .iter()
        .map(|&id| {
            let d = &w.state.discs;
            let q = idx(&w, id);
            (d.m[q], d.x[q], d.y[q])
        })
        .collect();
    let (mut ts, mut cx, mut cy, mut ang) = (vec![], vec![], vec![], vec![]);
    for _ in 0..100_000 {
        w.step();
        let d = &w.state.discs;
        let (mut sm, mut sx, mut sy) = (0.0, 0.0, 0.0);
        for &id in &ids {
            let q = idx(&w, id);
            sm += d.m[q];
            sx += d.m[q] * d.x[q];
            sy += d.m[q] * d.y[q];
        }
        let (xc, yc) = (sx / sm, sy / sm);
        let (mut cross, mut dot) = (0.0, 0.0);
        for (&id, &(m, x0, y0)) in ids.iter().zip(&r0) {
            let q = idx(&w, id);
            let (x, y) = (d.x[q] - xc, d.y[q] - yc);
            cross += m * (x0 * y - y0 * x);
            dot += m * (x0 * x + y0 * y);
        }
        ts.push(w.state.time);
        cx.push(xc);
        cy.push(yc);
        ang.push(cross.atan2(dot));
    }
    let (ax, ay, alpha) = (
        2.0 * quad_coeff(&ts, &cx),
        2.0 * quad_coeff(&ts, &cy),
        2.0 * quad_coeff(&ts, &ang),
    );
    eprintln!(
        "clump under load: a = ({ax:.5e}, {ay:.5e}) expected ({:.5e}, {:.5e}); α = {alpha:.5e} expected {alpha_expect:.5e}; turned {:.2e} rad",
        a_expect[0],
        a_expect[1],
        ang.last().unwrap()
    );
    let amag = a_expect[0].hypot(a_expect[1]);
    assert!((ax - a_expect[0]).abs() < 1e-3 * amag && (ay - a_expect[1]).abs() < 1e-3 * amag);
    assert!(
        (alpha / alpha_expect - 1.0).abs() < 1e-3,
        "α {alpha} vs {alpha_expect}"
    );
}
