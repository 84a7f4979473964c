//! Patch test of the lattice's equivalent elastic constants (docs/lattice.md, S3): a periodic
//! patch of the triangular lattice with link springs from `link_stiffness(E, ν, t)`, solved
//! statically (nalgebra, dense LU) under a uniaxial stress and a simple shear, gives back E and
//! ν; and E, ν → k_n, k_s → E, ν round-trips.
//!
//! Kinematics (the choice of docs/lattice.md): three degrees of freedom per node (u_x, u_y, θ);
//! per link from node a to node b (unit n, t = ẑ × n, spacing S) the normal spring acts on
//! δ_n = n·(u_b − u_a), the shear spring on the relative displacement at the link's midpoint,
//! δ_s = t·(u_b − u_a) − (S/2)(θ_a + θ_b), as a DEM bond. Periodicity: u = H·x + ũ with ũ and θ
//! periodic; H is the imposed displacement gradient. Stress (per thickness, N/m) by the virial
//! σ·t = (1/A) Σ_links f ⊗ (S n), f = k_n δ_n n + k_s δ_s t.

use clumpgen::{lattice_elastic, link_stiffness, LinkStiffness};
use nalgebra::{DMatrix, DVector, Matrix2};

struct Patch {
    /// Node positions.
    x: Vec<[f64; 2]>,
    /// Links (a, b, unit direction n).
    links: Vec<(usize, usize, [f64; 2])>,
    s: f64,
    area: f64,
}

/// `nx` nodes per row, `2·ny` rows: periodic in a rectangle `nx·S × 2ny·(√3/2)S`.
fn patch(nx: usize, ny: usize, s: f64) -> Patch {
    let h = s * 3f64.sqrt() / 2.0;
    let rows = 2 * ny;
    let id = |i: i64, j: i64| -> usize {
        let i = i.rem_euclid(nx as i64) as usize;
        let j = j.rem_euclid(rows as i64) as usize;
        j * nx + i
    };
    let mut x = Vec::new();
    let mut links = Vec::new();
    let half = 0.5;
    let up = [0.5, 3f64.sqrt() / 2.0];
    let up_left = [-0.5, 3f64.sqrt() / 2.0];
    for j in 0..rows as i64 {
        for i in 0..nx as i64 {
            let odd = j % 2 == 1;
            x.push([
                i as f64 * s + if odd { half * s } else { 0.0 },
                j as f64 * h,
            ]);
            let a = id(i, j);
            links.push((a, id(i + 1, j), [1.0, 0.0]));
            // Up-right and up-left neighbours, in the row above.
            let (ur, ul) = if odd { (i + 1, i) } else { (i, i - 1) };
            links.push((a, id(ur, j + 1), up));
            links.push((a, id(ul, j + 1), up_left));
        }
    }
    Patch {
        x,
        links,
        s,
        area: nx as f64 * s * rows as f64 * h,
    }
}

/// Solves the patch under the displacement gradient `h`; returns σ·t (N/m) and the node
/// rotations.
fn solve(p: &Patch, k: LinkStiffness, h: Matrix2<f64>) -> (Matrix2<f64>, Vec<f64>) {
    let n = p.x.len();
    let dof = 3 * n;
    let mut kk = DMatrix::<f64>::zeros(dof, dof);
    let mut f = DVector::<f64>::zeros(dof);
    let s = p.s;
    // (row over dofs as (index, coefficient) pairs, constant) for δ_n and δ_s of a link.
    let rows = |a: usize, b: usize, nv: [f64; 2]| {
        let t = [-nv[1], nv[0]];
        let hn = [
            h[(0, 0)] * nv[0] + h[(0, 1)] * nv[1],
            h[(1, 0)] * nv[0] + h[(1, 1)] * nv[1],
        ];
        let dn = vec![
            (3 * a, -nv[0]),
            (3 * a + 1, -nv[1]),
            (3 * b, nv[0]),
            (3 * b + 1, nv[1]),
        ];
        let ds = vec![
            (3 * a, -t[0]),
            (3 * a + 1, -t[1]),
            (3 * b, t[0]),
            (3 * b + 1, t[1]),
            (3 * a + 2, -s / 2.0),
            (3 * b + 2, -s / 2.0),
        ];
        let cn = s * (nv[0] * hn[0] + nv[1] * hn[1]);
        let cs = s * (t[0] * hn[0] + t[1] * hn[1]);
        (dn, cn, ds, cs)
    };
    for &(a, b, nv) in &p.links {
        let (dn, cn, ds, cs) = rows(a, b, nv);
        for (row, c, kv) in [(&dn, cn, k.k_n), (&ds, cs, k.k_s)] {
            for &(i, bi) in row {
                f[i] -= kv * c * bi;
                for &(j, bj) in row {
                    kk[(i, j)] += kv * bi * bj;
                }
            }
        }
    }
    // Node 0's periodic displacement is fixed (the two translations).
    let free: Vec<usize> = (2..dof).collect();
    let kr = kk.select_rows(&free).select_columns(&free);
    let fr = f.select_rows(&free);
    let qr = kr
        .clone()
        .lu()
        .solve(&fr)
        .expect("patch stiffness is regular");
    let resid = (&kr * &qr - &fr).norm() / fr.norm().max(f64::MIN_POSITIVE);
    assert!(resid < 1e-10, "linear solve residual {resid:e}");
    let mut q = DVector::<f64>::zeros(dof);
    for (k2, &i) in free.iter().enumerate() {
        q[i] = qr[k2];
    }
    let mut sigma = Matrix2::zeros();
    for &(a, b, nv) in &p.links {
        let (dn, cn, ds, cs) = rows(a, b, nv);
        let dot = |row: &Vec<(usize, f64)>| row.iter().map(|&(i, c)| c * q[i]).sum::<f64>();
        let d_n = dot(&dn) + cn;
        let d_s = dot(&ds) + cs;
        let t = [-nv[1], nv[0]];
        let fv = [
            k.k_n * d_n * nv[0] + k.k_s * d_s * t[0],
            k.k_n * d_n * nv[1] + k.k_s * d_s * t[1],
        ];
        for i in 0..2 {
            for j in 0..2 {
                sigma[(i, j)] += fv[i] * s * nv[j] / p.area;
            }
        }
    }
    let theta = (0..n).map(|i| q[3 * i + 2]).collect();
    (sigma, theta)
}

/// E·t and ν of the patch: uniaxial stress along x (ε_xx = e, ε_yy chosen so σ_yy = 0, by
/// two solves: σ is linear in ε_yy), and E·t again from simple shear, E = 2(1+ν)G.
fn measure(p: &Patch, k: LinkStiffness) -> (f64, f64, f64) {
    let e = 1e-4;
    let (s0, _) = solve(p, k, Matrix2::new(e, 0.0, 0.0, 0.0));
    let (s1, _) = solve(p, k, Matrix2::new(e, 0.0, 0.0, e));
    // σ_yy(ε_yy) = s0 + (s1 − s0)·ε_yy/e = 0.
    let eyy = -s0[(1, 1)] / (s1[(1, 1)] - s0[(1, 1)]) * e;
    let sxx = s0[(0, 0)] + (s1[(0, 0)] - s0[(0, 0)]) * eyy / e;
    let (et, nu) = (sxx / e, -eyy / e);
    // Simple shear u_x = γ·y (γ = 2ε_xy, with a rigid rotation −γ/2): σ_xy = G·γ; the nodes
    // must turn with the material, θ = −γ/2.
    let g = 1e-4;
    let (ss, theta) = solve(p, k, Matrix2::new(0.0, g, 0.0, 0.0));
    for th in theta {
        assert!(
            (th + g / 2.0).abs() < 1e-9 * g,
            "node rotation {th:e}, not {:e}",
            -g / 2.0
        );
    }
    assert!(
        (ss[(0, 1)] - ss[(1, 0)]).abs() < 1e-9 * ss[(0, 1)].abs(),
        "stress not symmetric: {ss}"
    );
    let et_shear = 2.0 * (1.0 + nu) * ss[(0, 1)] / g;
    (et, nu, et_shear)
}

#[test]
fn periodic_patch_recovers_e_and_nu() {
    let t = 1e-3;
    let s = 2e-5;
    let p = patch(4, 3, s);
    for &(e, nu) in &[(430e9, 0.14), (310e9, 0.27), (70e9, 0.0), (1e9, 0.33)] {
        let k = link_stiffness(e, nu, t).unwrap();
        let (et, nu_p, et_shear) = measure(&p, k);
        let (e_p, e_shear) = (et / t, et_shear / t);
        println!(
            "E {e:.3e} nu {nu}: k_n {:.4e} N/m, k_s {:.4e} N/m; patch E {e_p:.6e} \
             (rel {:.1e}), nu {nu_p:.6} (abs {:.1e}), E from shear {e_shear:.6e} (rel {:.1e})",
            k.k_n,
            k.k_s,
            (e_p - e).abs() / e,
            (nu_p - nu).abs(),
            (e_shear - e).abs() / e
        );
        assert!((e_p - e).abs() < 0.01 * e, "E {e_p:e} vs {e:e}");
        assert!((nu_p - nu).abs() < 0.01 * nu.max(0.01), "nu {nu_p} vs {nu}");
        assert!(
            (e_shear - e).abs() < 0.01 * e,
            "E from shear {e_shear:e} vs {e:e}"
        );
        // The forward formula agrees with the patch too.
        let fwd = lattice_elastic(k, t).unwrap();
        assert!((fwd.e - e_p).abs() < 0.01 * e && (fwd.nu - nu_p).abs() < 0.01 * nu.max(0.01));
    }
}

#[test]
fn patch_size_does_not_matter() {
    // The periodic solution is affine: one cell or many give the same constants.
    let k = link_stiffness(200e9, 0.2, 1.0).unwrap();
    let a = measure(&patch(2, 1, 1.0), k);
    let b = measure(&patch(5, 4, 1.0), k);
    assert!((a.0 - b.0).abs() < 1e-9 * a.0 && (a.1 - b.1).abs() < 1e-9);
}

#[test]
fn round_trip_through_the_springs() {
    for &(e, nu, t) in &[(430e9, 0.14, 1e-3), (50e9, 0.3, 0.02), (2e11, 0.0, 1.0)] {
        let k = link_stiffness(e, nu, t).unwrap();
        let back = lattice_elastic(k, t).unwrap();
        assert!((back.e - e).abs() < 1e-12 * e && (back.nu - nu).abs() < 1e-12);
    }
}
