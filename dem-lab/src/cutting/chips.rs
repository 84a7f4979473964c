//! Fragments of a cut specimen: the connected components of the intact-bond graph, with the
//! members of a rigid clump (ORC grain) counted as one node; the component with the largest
//! mass is the workpiece, the others are detached fragments. A fragment whose mass centre lies
//! above the nominal machined surface is a chip; one below it is a loose fragment left in the
//! workpiece (a disc or grain cracked free but still in place). Broken bonds between two
//! workpiece discs below the nominal surface are residual (subsurface) cracks.
//!
//! Flat joints (Potyondy 2012, [`dem_core::bond::flat_joint`]) break element by element. The store
//! reports an interface as intact ([`BondStatus::Intact`] in its [`dem_core::bond::BondView`],
//! counted by `Bonds::n_intact`) while any of its bonded elements holds, and as broken once
//! the last one has broken (its cement is gone; it is then logged once, with that element's
//! mode, and counted in `Bonds::broken_counts`), even while the interface still touches as a
//! frictional contact. So here a flat joint joins its two discs into one fragment while it
//! has cement, and a residual crack is an interface whose cement is all gone. An interface
//! installed with every element slit (bonded fraction below 1) never had cement: the store
//! reports it broken from the start, but it is no crack ([`cemented_at_install`]).

use dem_core::bond::flat_joint::FlatJointState;
use dem_core::bond::{BondModel, BondStatus, Bonds};
use dem_core::state::{State, FREE};
use serde::{Deserialize, Serialize};

/// Union-find with path halving and union by size.
struct UnionFind {
    parent: Vec<u32>,
    size: Vec<u32>,
}

impl UnionFind {
    fn new(n: usize) -> UnionFind {
        UnionFind {
            parent: (0..n as u32).collect(),
            size: vec![1; n],
        }
    }

    fn find(&mut self, mut a: u32) -> u32 {
        while self.parent[a as usize] != a {
            let p = self.parent[a as usize];
            self.parent[a as usize] = self.parent[p as usize];
            a = self.parent[a as usize];
        }
        a
    }

    fn union(&mut self, a: u32, b: u32) {
        let (mut ra, mut rb) = (self.find(a), self.find(b));
        if ra == rb {
            return;
        }
        if self.size[ra as usize] < self.size[rb as usize] {
            std::mem::swap(&mut ra, &mut rb);
        }
        self.parent[rb as usize] = ra;
        self.size[ra as usize] += self.size[rb as usize];
    }
}

/// One connected component.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fragment {
    /// Disc indices (current positions in [`dem_core::Discs`]), ascending.
    pub discs: Vec<usize>,
    /// Σ m of the member discs (kg; for rigid-clump members their shares, which sum to the
    /// clump's ORC mass).
    pub mass: f64,
    /// Mass centre (m).
    pub centre: [f64; 2],
}

/// The components of the intact-bond graph (rigid clumps joined), ordered by decreasing mass
/// (ties: by smallest disc index), so `[0]` is the workpiece.
pub fn fragments(st: &State, bonds: Option<&Bonds>) -> Vec<Fragment> {
    let d = &st.discs;
    let n = d.len();
    let mut uf = UnionFind::new(n);
    // Rigid clumps: members are one node. `body` gives the clump of each disc.
    let mut first_of_clump: Vec<u32> = vec![u32::MAX; st.clumps.len()];
    for k in 0..n {
        let b = d.body[k];
        if b != FREE {
            let f = &mut first_of_clump[b as usize];
            if *f == u32::MAX {
                *f = k as u32;
            } else {
                uf.union(*f, k as u32);
            }
        }
    }
    if let Some(b) = bonds {
        for v in b.iter() {
            if v.status == BondStatus::Intact {
                uf.union(v.i, v.j);
            }
        }
    }
    let mut index_of_root: Vec<u32> = vec![u32::MAX; n];
    let mut out: Vec<Fragment> = Vec::new();
    let mut mx: Vec<[f64; 2]> = Vec::new();
    for k in 0..n {
        let r = uf.find(k as u32) as usize;
        if index_of_root[r] == u32::MAX {
            index_of_root[r] = out.len() as u32;
            out.push(Fragment {
                discs: Vec::new(),
                mass: 0.0,
                centre: [0.0; 2],
            });
            mx.push([0.0; 2]);
        }
        let c = index_of_root[r] as usize;
        out[c].discs.push(k);
        out[c].mass += d.m[k];
        mx[c][0] += d.m[k] * d.x[k];
        mx[c][1] += d.m[k] * d.y[k];
    }
    for (f, m) in out.iter_mut().zip(&mx) {
        if f.mass > 0.0 {
            f.centre = [m[0] / f.mass, m[1] / f.mass];
        }
    }
    out.sort_by(|a, b| b.mass.total_cmp(&a.mass).then(a.discs[0].cmp(&b.discs[0])));
    out
}

/// Count, discs and mass of a set of fragments.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct FragmentCount {
    pub count: usize,
    pub discs: usize,
    /// kg, for the scene thickness.
    pub mass: f64,
    /// Discs in the largest one.
    pub largest_discs: usize,
}

impl FragmentCount {
    fn add(&mut self, f: &Fragment) {
        self.count += 1;
        self.discs += f.discs.len();
        self.mass += f.mass;
        self.largest_discs = self.largest_discs.max(f.discs.len());
    }
}

/// Workpiece, chips and loose fragments.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ChipReport {
    pub workpiece_discs: usize,
    pub workpiece_mass: f64,
    /// Detached fragments whose mass centre lies above the nominal machined surface.
    pub chips: FragmentCount,
    /// Detached fragments whose mass centre lies at or below it (cracked free, left in place).
    pub loose_below_surface: FragmentCount,
}

/// Sort the fragments (from [`fragments`]) into workpiece (`[0]`), chips (mass centre above
/// `surface_y`) and loose fragments below it.
pub fn classify(frags: &[Fragment], surface_y: f64) -> ChipReport {
    let mut r = ChipReport::default();
    let Some(w) = frags.first() else {
        return r;
    };
    r.workpiece_discs = w.discs.len();
    r.workpiece_mass = w.mass;
    for f in &frags[1..] {
        if f.centre[1] > surface_y {
            r.chips.add(f);
        } else {
            r.loose_below_surface.add(f);
        }
    }
    r
}

/// Bonded elements of flat joint `k` (store position) at installation and now, `None` for
/// other bonds. The installed set is recomputed as the store drew it
/// ([`FlatJointState::installed`]: a hash of the bond id and the element index against the
/// bonded fraction φ_B), so it is known without a record kept from the start.
pub fn flat_joint_elements(b: &Bonds, k: usize) -> Option<(u32, u32)> {
    let v = b.get(k);
    let BondModel::FlatJoint(p) = b.groups()[v.group as usize].model else {
        return None;
    };
    let now = b.flat_joint(k)?.bonded_count();
    Some((FlatJointState::installed(&p, v.id).bonded_count(), now))
}

/// Whether bond `k` (store position) had cement when it was installed: every parallel and
/// contact bond; a flat joint unless all its elements were slit (Potyondy 2012's slit
/// elements, [`dem_core::bond::flat_joint::FlatJointParams::bonded_fraction`]).
pub fn cemented_at_install(b: &Bonds, k: usize) -> bool {
    flat_joint_elements(b, k).is_none_or(|(installed, _)| installed > 0)
}

/// Residual cracks: broken bonds whose two discs are both in the workpiece and whose contact
/// point (current positions) lies below the nominal machined surface. A flat joint counts when
/// its cement is all gone (the store's broken status), not when only some elements broke, and
/// never when it was installed without cement (see the module docs).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ResidualCracks {
    pub count: usize,
    /// Depth of the deepest one below the nominal surface (m; 0 when none).
    pub deepest: f64,
    /// Mean depth below the nominal surface (m; 0 when none).
    pub mean_depth: f64,
    /// Of them, those within the cut length (x between the entry edge and the end of the cut).
    pub within_cut: usize,
}

/// Residual cracks below `surface_y`, counting `within_cut` for contact points with x in
/// `[x_from, x_to]`. `workpiece` is the workpiece fragment.
pub fn residual_cracks(
    st: &State,
    bonds: Option<&Bonds>,
    workpiece: &Fragment,
    surface_y: f64,
    x_from: f64,
    x_to: f64,
) -> ResidualCracks {
    let mut r = ResidualCracks::default();
    let Some(b) = bonds else {
        return r;
    };
    let mut in_work = vec![false; st.discs.len()];
    for &k in &workpiece.discs {
        in_work[k] = true;
    }
    let mut depth_sum = 0.0;
    for k in 0..b.len() {
        let v = b.get(k);
        if v.status == BondStatus::Intact
            || !in_work[v.i as usize]
            || !in_work[v.j as usize]
            || !cemented_at_install(b, k)
        {
            continue;
        }
        let [x, y] = b.centre(st, k);
        if y < surface_y {
            let depth = surface_y - y;
            r.count += 1;
            r.deepest = r.deepest.max(depth);
            depth_sum += depth;
            if x >= x_from && x <= x_to {
                r.within_cut += 1;
            }
        }
    }
    if r.count > 0 {
        r.mean_depth = depth_sum / r.count as f64;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use dem_core::bond::{BondGroup, BondModel, Criterion, ParallelBondParams};
    use dem_core::clump::orc::make_rigid_clump;

    fn group() -> BondGroup {
        BondGroup {
            name: "gb".into(),
            model: BondModel::Parallel(ParallelBondParams {
                kn: 1e12,
                ks: 4e11,
                lambda: 1.0,
                beta: 1.0,
            }),
            criterion: Criterion::Stress {
                tensile: 1e8,
                cohesion: 1e8,
                friction_angle: 0.0,
            },
        }
    }

    /// A row of 6 touching discs on y = 0 (0-1-2 bonded: workpiece), two discs 3, 4 up at
    /// y = 5 made one rigid clump (a chip of one node, no bond), disc 5 alone at y = −5 (loose,
    /// below the surface y = 1).
    #[test]
    fn components_join_bonds_and_rigid_clumps() {
        let mut st = State::default();
        let r = 0.5;
        for (x, y) in [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (0.0, 5.0), (1.0, 5.0)] {
            st.discs.push_uniform(x, y, r, 1000.0, 1.0, 0);
        }
        st.discs.push_uniform(3.0, -5.0, r, 1000.0, 1.0, 0);
        assert!(make_rigid_clump(&mut st, &[3, 4], "grain").is_some());
        let mut b = Bonds::new(vec![group()]).unwrap();
        b.add(&st, 0, 1, 0).unwrap();
        b.add(&st, 1, 2, 0).unwrap();
        let f = fragments(&st, Some(&b));
        assert_eq!(f.len(), 3);
        assert_eq!(f[0].discs, vec![0, 1, 2]);
        assert_eq!(f[1].discs, vec![3, 4]);
        assert_eq!(f[2].discs, vec![5]);
        let m = st.discs.m[0];
        assert!((f[0].mass - 3.0 * m).abs() < 1e-12 * m);
        assert!((f[0].centre[0] - 1.0).abs() < 1e-12 && f[0].centre[1].abs() < 1e-12);
        assert!((f[1].centre[0] - 0.5).abs() < 1e-12 && (f[1].centre[1] - 5.0).abs() < 1e-12);
        let c = classify(&f, 1.0);
        assert_eq!(c.workpiece_discs, 3);
        assert_eq!(
            (c.chips.count, c.chips.discs, c.chips.largest_discs),
            (1, 2, 2)
        );
        assert_eq!(
            (c.loose_below_surface.count, c.loose_below_surface.discs),
            (1, 1)
        );
        // Without bonds every free disc is its own component; the clump stays one.
        let f0 = fragments(&st, None);
        assert_eq!(f0.len(), 5);
        assert_eq!(f0[0].discs, vec![3, 4]);
    }

    /// Two bonded discs below the surface: no crack while the bond holds; pulled apart so the
    /// bond breaks in tension, one crack at the contact point's depth.
    #[test]
    fn a_broken_bond_below_the_surface_is_a_residual_crack() {
        let mut st = State::default();
        for x in [0.0, 1.0] {
            st.discs.push_uniform(x, 0.0, 0.5, 1000.0, 1.0, 0);
        }
        // A third disc bonded to both keeps them one component after the break.
        st.discs.push_uniform(0.5, 0.866, 0.5, 1000.0, 1.0, 0);
        let mut b = Bonds::new(vec![group()]).unwrap();
        b.add(&st, 0, 1, 0).unwrap();
        b.add(&st, 0, 2, 0).unwrap();
        b.add(&st, 1, 2, 0).unwrap();
        let f = fragments(&st, Some(&b));
        assert_eq!(f.len(), 1);
        let c = residual_cracks(&st, Some(&b), &f[0], 2.0, -1.0, 2.0);
        assert_eq!(c, ResidualCracks::default());
        // Move disc 1 by Δ = 1.5e-4 m along x (the bond's normal force follows the gap;
        // Ā = 2R̄t = 1 m²): the 0-1 bond carries σ̄ = k̄n Δ = 1.5e8 Pa ≥ σ̄c = 1e8 and breaks
        // in tension; the 1-2 bond opens by about 0.5Δ (0.75e8 Pa) and holds.
        st.discs.x[1] += 1.5e-4;
        b.compute(&mut st, 1.0);
        let broken: Vec<_> = b
            .iter()
            .filter(|v| v.status != BondStatus::Intact)
            .collect();
        assert_eq!(broken.len(), 1);
        assert_eq!((broken[0].i, broken[0].j), (0, 1));
        let f = fragments(&st, Some(&b));
        let work = f.iter().find(|g| g.discs.contains(&0)).unwrap();
        let c = residual_cracks(&st, Some(&b), work, 2.0, -1.0, 2.0);
        let in_work = |v: &dem_core::bond::BondView| {
            work.discs.contains(&(v.i as usize)) && work.discs.contains(&(v.j as usize))
        };
        assert_eq!(c.count, broken.iter().filter(|v| in_work(v)).count());
        assert!(c.count >= 1);
        // The 0-1 contact point lies at y = 0: depth 2 below the surface y = 2.
        assert!(c.deepest >= 2.0 - 1e-9 && c.deepest < 2.0 + 1e-3);
        assert_eq!(c.within_cut, c.count);
        let c_out = residual_cracks(&st, Some(&b), work, 2.0, 5.0, 6.0);
        assert_eq!(c_out.within_cut, 0);
        // Above the surface nothing counts.
        assert_eq!(
            residual_cracks(&st, Some(&b), work, -1.0, -1.0, 2.0).count,
            0
        );
    }

    fn flat_joint_group(name: &str, bonded_fraction: f64) -> BondGroup {
        BondGroup {
            name: name.into(),
            model: BondModel::FlatJoint(dem_core::bond::flat_joint::FlatJointParams {
                kn: 1e12,
                ks: 4e11,
                lambda: 1.0,
                elements: 2,
                friction: 0.5,
                bonded_fraction,
            }),
            ..group()
        }
    }

    /// Flat joints (Potyondy 2012): a fully slit interface (bonded fraction 0) is reported
    /// broken by the store from the start but is no crack and no broken bond, and does not
    /// join its discs; a cemented interface pulled open breaks both its elements, is one
    /// broken bond and one residual crack. Discs 0, 1 on y = 0, 2 above and 3 below them.
    #[test]
    fn flat_joints_count_as_broken_when_their_cement_is_gone() {
        let mut st = State::default();
        for (x, y) in [(0.0, 0.0), (1.0, 0.0), (0.5, 0.866), (0.5, -0.866)] {
            st.discs.push_uniform(x, y, 0.5, 1000.0, 1.0, 0);
        }
        let mut b = Bonds::new(vec![
            flat_joint_group("fj", 1.0),
            flat_joint_group("slit", 0.0),
        ])
        .unwrap();
        b.add(&st, 1, 2, 1).unwrap();
        for (i, j) in [(0, 1), (0, 2), (0, 3), (1, 3)] {
            b.add(&st, i, j, 0).unwrap();
        }
        assert_eq!(flat_joint_elements(&b, 0), Some((0, 0)));
        assert!(!cemented_at_install(&b, 0));
        assert_ne!(b.get(0).status, BondStatus::Intact);
        for k in 1..5 {
            assert_eq!(flat_joint_elements(&b, k), Some((2, 2)));
            assert!(cemented_at_install(&b, k));
        }
        let f = fragments(&st, Some(&b));
        assert_eq!(f.len(), 1);
        assert_eq!(
            residual_cracks(&st, Some(&b), &f[0], 2.0, -1.0, 2.0).count,
            0
        );
        let bb = crate::cutting::broken_bonds(&b);
        assert_eq!(
            (
                bb[1].total,
                bb[1].slit,
                bb[1].elements_bonded,
                bb[1].tension
            ),
            (0, Some(1), Some(0), 0)
        );
        assert_eq!((bb[0].total, bb[0].elements_bonded), (4, Some(8)));
        // Disc 1 moved by Δ = 1.5e-4 m along x: the 0-1 interface opens evenly, k̄n Δ =
        // 1.5e8 Pa ≥ σc = 1e8 on both elements, which break in tension; 1-3 opens by about
        // 0.5 Δ (0.75e8 Pa) and holds, so all four discs stay one fragment through 3.
        st.discs.x[1] += 1.5e-4;
        b.compute(&mut st, 1.0);
        assert_eq!(flat_joint_elements(&b, 1), Some((2, 0)));
        assert_ne!(b.get(1).status, BondStatus::Intact);
        for k in 2..5 {
            assert_eq!(b.get(k).status, BondStatus::Intact, "bond {k}");
        }
        let f = fragments(&st, Some(&b));
        assert_eq!(f.len(), 1);
        // One crack, the 0-1 interface (contact point y = 0, depth 2), not the slit 1-2 one.
        let c = residual_cracks(&st, Some(&b), &f[0], 2.0, -1.0, 2.0);
        assert_eq!(c.count, 1);
        assert!((c.deepest - 2.0).abs() < 1e-3, "{c:?}");
        let bb = crate::cutting::broken_bonds(&b);
        assert_eq!((bb[0].tension, bb[0].shear, bb[0].total), (1, 0, 4));
        assert_eq!(
            (bb[0].elements_broken, bb[0].partly_broken, bb[0].slit),
            (Some(2), Some(0), Some(0))
        );
        assert_eq!(bb[1].tension + bb[1].shear, 0);
    }
}
