//! Fragments of crushable (lattice) grains and their broken-link log (issue 25 item 3; S3 in
//! `shared/SOURCES.md`: broken grains keep their lattice and break again).
//!
//! A fragment is a connected component of a grain's nodes joined by its *intact* bonds
//! (union-find over the grain's nodes, only its remaining bonds): a grain with no broken link
//! is one fragment; a node whose links have all broken is a fragment of one node, reported as
//! *fines* (the lattice cannot resolve anything smaller). Grains are told apart by
//! [`crate::Discs::group`] (the grain id a clump placement writes); a bond joining discs of
//! two groups (an inter-grain bond) does not join fragments.
//!
//! Size: a fragment's area is its nodes' mass over ρ·t (`A = Σm_i/(ρt)`; the lattice template's
//! node masses are solved so that they sum to the grain's mass ρ·t·A_grain, docs/lattice.md,
//! so the fragments' areas sum to the grain's area exactly), and its equivalent diameter
//! `d_eq = 2√(A/π)`. On a regular lattice this is about the node count × the cell area
//! `A_c = (√3/2)S²`.
//!
//! The log: every break of a lattice grain's bond, from the bond store's crack record
//! ([`crate::bond::BreakLog`]: time, position, mode, the two discs' stable ids), with the grain
//! and the template link it was ([`lattice_breaks`]).

use crate::bond::{BondStatus, Bonds, BreakMode};
use crate::state::State;
use serde::{Deserialize, Serialize};
use std::collections::{BTreeMap, HashMap};

/// Disjoint sets (path halving, union by size).
#[derive(Clone, Debug)]
pub struct UnionFind {
    parent: Vec<usize>,
    size: Vec<usize>,
}

impl UnionFind {
    pub fn new(n: usize) -> Self {
        UnionFind {
            parent: (0..n).collect(),
            size: vec![1; n],
        }
    }

    pub fn find(&mut self, mut a: usize) -> usize {
        while self.parent[a] != a {
            self.parent[a] = self.parent[self.parent[a]];
            a = self.parent[a];
        }
        a
    }

    /// Joins the sets of `a` and `b`; false when they were one already.
    pub fn union(&mut self, a: usize, b: usize) -> bool {
        let (mut a, mut b) = (self.find(a), self.find(b));
        if a == b {
            return false;
        }
        if self.size[a] < self.size[b] {
            std::mem::swap(&mut a, &mut b);
        }
        self.parent[b] = a;
        self.size[a] += self.size[b];
        true
    }
}

/// The connected components of nodes `0..n` joined by `edges`, each sorted, ordered by their
/// smallest node (deterministic). Edges with an end outside `0..n` are ignored.
pub fn components(n: usize, edges: impl IntoIterator<Item = (usize, usize)>) -> Vec<Vec<usize>> {
    let mut uf = UnionFind::new(n);
    for (a, b) in edges {
        if a < n && b < n {
            uf.union(a, b);
        }
    }
    let mut by_root: BTreeMap<usize, Vec<usize>> = BTreeMap::new();
    let mut first: HashMap<usize, usize> = HashMap::new();
    for k in 0..n {
        let r = uf.find(k);
        let key = *first.entry(r).or_insert(k);
        by_root.entry(key).or_default().push(k);
    }
    by_root.into_values().collect()
}

/// One fragment of a grain.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Fragment {
    /// Grain id ([`crate::Discs::group`]).
    pub grain: u32,
    /// Its nodes (discs).
    pub nodes: usize,
    /// Σ m_i (kg).
    pub mass: f64,
    /// A = Σm_i/(ρt) (m²).
    pub area: f64,
    /// d_eq = 2√(A/π) (m).
    pub d_eq: f64,
    /// Stable ids of its discs, ascending.
    pub ids: Vec<u32>,
}

impl Fragment {
    /// A single node: fines.
    pub fn is_fines(&self) -> bool {
        self.nodes == 1
    }
}

/// The fragments of every grain (discs grouped by [`crate::Discs::group`], joined by the intact
/// bonds of `bonds` between discs of one group), ordered by grain, then by decreasing mass
/// (ties by smallest id). `density` (kg/m³) gives the areas. `grains`: only these groups
/// (`None`: every group that has a disc).
pub fn fragments(
    st: &State,
    bonds: Option<&Bonds>,
    density: f64,
    grains: Option<&[u32]>,
) -> Vec<Fragment> {
    let d = &st.discs;
    let n = d.len();
    let keep = |g: u32| grains.is_none_or(|gs| gs.contains(&g));
    let edges = bonds.into_iter().flat_map(|b| {
        b.iter().filter_map(|v| {
            let (i, j) = (v.i as usize, v.j as usize);
            (v.status == BondStatus::Intact && d.group[i] == d.group[j]).then_some((i, j))
        })
    });
    let mut out: Vec<Fragment> = components(n, edges)
        .into_iter()
        .filter(|c| keep(d.group[c[0]]))
        .map(|c| {
            let mass: f64 = c.iter().map(|&k| d.m[k]).sum();
            let area = mass / (density * st.thickness);
            let mut ids: Vec<u32> = c.iter().map(|&k| d.id[k]).collect();
            ids.sort_unstable();
            Fragment {
                grain: d.group[c[0]],
                nodes: c.len(),
                mass,
                area,
                d_eq: 2.0 * (area / std::f64::consts::PI).sqrt(),
                ids,
            }
        })
        .collect();
    out.sort_by(|a, b| {
        (a.grain.cmp(&b.grain))
            .then(b.mass.total_cmp(&a.mass))
            .then(a.ids[0].cmp(&b.ids[0]))
    });
    out
}

/// Summary of one grain's fragments.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct FragmentSummary {
    /// Fragments of two nodes or more, and single nodes (fines).
    pub fragments: usize,
    pub fines: usize,
    /// Mass of the largest fragment over the grain's (1: intact).
    pub largest_mass_fraction: f64,
    /// Mass of the fines over the grain's.
    pub fines_mass_fraction: f64,
    /// Equivalent diameters d_eq (m) of the fragments of two nodes or more, decreasing.
    pub d_eq: Vec<f64>,
    /// Their node counts, in the same order.
    pub nodes: Vec<usize>,
}

impl FragmentSummary {
    /// The summary of `frags` (one grain's, as [`fragments`] orders them).
    pub fn of(frags: &[Fragment]) -> FragmentSummary {
        let total: f64 = frags.iter().map(|f| f.mass).sum();
        let big: Vec<&Fragment> = frags.iter().filter(|f| !f.is_fines()).collect();
        let fines_mass: f64 = frags.iter().filter(|f| f.is_fines()).map(|f| f.mass).sum();
        let largest = frags.iter().map(|f| f.mass).fold(0.0, f64::max);
        let frac = |m: f64| if total > 0.0 { m / total } else { 0.0 };
        FragmentSummary {
            fragments: big.len(),
            fines: frags.len() - big.len(),
            largest_mass_fraction: frac(largest),
            fines_mass_fraction: frac(fines_mass),
            d_eq: big.iter().map(|f| f.d_eq).collect(),
            nodes: big.iter().map(|f| f.nodes).collect(),
        }
    }
}

/// One broken link of a lattice grain.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct LinkBreak {
    /// Simulation time (s) and step of the break.
    pub time: f64,
    pub step: u64,
    /// Grain id ([`crate::Discs::group`]).
    pub grain: u32,
    /// Index of the link in the template's `lattice.links`, and its two nodes (template
    /// indices).
    pub link: usize,
    pub node_i: usize,
    pub node_j: usize,
    /// The bond group's criterion (`force`, `strain`, `energy`, `stress`) and the mode.
    pub criterion: String,
    pub mode: BreakMode,
    /// Bond centre at the break (m).
    pub x: f64,
    pub y: f64,
    /// Strain energy the link held when it broke (J).
    pub energy: f64,
}

/// A placed lattice grain: its grain id, the stable id of its node 0 (a placement gives its
/// nodes consecutive ids in template order) and the template's links.
pub struct LatticeGrain<'a> {
    pub grain: u32,
    pub first_id: u32,
    pub links: &'a [clumpgen::lattice::Link],
}

/// The breaks of `bonds`' log that are links of `grains`, in log order (breaks of other bonds
/// are left out).
pub fn lattice_breaks(bonds: &Bonds, grains: &[LatticeGrain]) -> Vec<LinkBreak> {
    let mut index: HashMap<(u32, u32), (u32, usize, usize, usize)> = HashMap::new();
    for g in grains {
        for (k, l) in g.links.iter().enumerate() {
            let (a, b) = (g.first_id + l.i as u32, g.first_id + l.j as u32);
            index.insert((a.min(b), a.max(b)), (g.grain, k, l.i, l.j));
        }
    }
    let crit = |group: u16| {
        bonds
            .groups()
            .get(group as usize)
            .map(|g| criterion_name(&g.criterion).to_string())
            .unwrap_or_default()
    };
    bonds
        .log()
        .events
        .iter()
        .filter_map(|e| {
            let key = (e.id_i.min(e.id_j), e.id_i.max(e.id_j));
            index
                .get(&key)
                .map(|&(grain, link, node_i, node_j)| LinkBreak {
                    time: e.time,
                    step: e.step,
                    grain,
                    link,
                    node_i,
                    node_j,
                    criterion: crit(e.group),
                    mode: e.mode,
                    x: e.x,
                    y: e.y,
                    energy: e.energy,
                })
        })
        .collect()
}

/// The criterion's name as in the scene schema.
pub fn criterion_name(c: &crate::bond::Criterion) -> &'static str {
    use crate::bond::Criterion::*;
    match c {
        Stress { .. } => "stress",
        Force { .. } => "force",
        Strain { .. } => "strain",
        Energy { .. } => "energy",
    }
}

/// The log as CSV: `time,step,grain,link,node_i,node_j,criterion,mode,x,y,energy`.
pub fn breaks_csv(breaks: &[LinkBreak]) -> String {
    use std::fmt::Write as _;
    let mut s = String::from("time,step,grain,link,node_i,node_j,criterion,mode,x,y,energy\n");
    for b in breaks {
        let _ = writeln!(
            s,
            "{:e},{},{},{},{},{},{},{},{:e},{:e},{:e}",
            b.time,
            b.step,
            b.grain,
            b.link,
            b.node_i,
            b.node_j,
            b.criterion,
            b.mode.name(),
            b.x,
            b.y,
            b.energy
        );
    }
    s
}

/// The fragments of one lattice grain of `n` nodes after the links in `broken` (template link
/// indices) broke: components of the intact links. For a break log read back, e.g. the
/// fragments at any time of a run from its [`LinkBreak`]s up to that time.
pub fn lattice_components(
    n: usize,
    links: &[clumpgen::lattice::Link],
    broken: &[usize],
) -> Vec<Vec<usize>> {
    let mut cut = vec![false; links.len()];
    for &k in broken {
        if let Some(c) = cut.get_mut(k) {
            *c = true;
        }
    }
    components(
        n,
        links
            .iter()
            .zip(&cut)
            .filter(|(_, &c)| !c)
            .map(|(l, _)| (l.i, l.j)),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use clumpgen::lattice::{Link, LinkKind};

    fn link(i: usize, j: usize) -> Link {
        Link {
            i,
            j,
            kind: LinkKind::D0,
        }
    }

    /// A hand-made lattice: two triangles (0-1-2 and 3-4-5) joined by the links 2-3 and 1-4;
    /// node 6 hangs on node 5 by one link.
    #[test]
    fn cut_links_give_the_known_components() {
        let links = vec![
            link(0, 1),
            link(1, 2),
            link(0, 2),
            link(3, 4),
            link(4, 5),
            link(3, 5),
            link(2, 3),
            link(1, 4),
            link(5, 6),
        ];
        assert_eq!(
            lattice_components(7, &links, &[]),
            vec![vec![0, 1, 2, 3, 4, 5, 6]]
        );
        // Cutting one of the two joining links leaves one piece.
        assert_eq!(lattice_components(7, &links, &[6]).len(), 1);
        // Cutting both splits the two triangles; cutting 5-6 frees node 6 as fines.
        assert_eq!(
            lattice_components(7, &links, &[6, 7, 8]),
            vec![vec![0, 1, 2], vec![3, 4, 5], vec![6]]
        );
        // Every link of node 0 cut: it alone, the rest one piece.
        assert_eq!(
            lattice_components(7, &links, &[0, 2]),
            vec![vec![0], vec![1, 2, 3, 4, 5, 6]]
        );
        // Out-of-range indices are ignored, not a panic.
        assert_eq!(lattice_components(7, &links, &[99]).len(), 1);
        assert_eq!(components(3, [(0, 7)]).len(), 3);
    }

    #[test]
    fn summary_counts_fines_and_fractions() {
        let f = |nodes: usize, mass: f64| Fragment {
            grain: 0,
            nodes,
            mass,
            area: mass,
            d_eq: 2.0 * (mass / std::f64::consts::PI).sqrt(),
            ids: vec![0],
        };
        let s = FragmentSummary::of(&[f(5, 5.0), f(3, 3.0), f(1, 1.0), f(1, 1.0)]);
        assert_eq!((s.fragments, s.fines), (2, 2));
        assert_eq!(s.largest_mass_fraction, 0.5);
        assert_eq!(s.fines_mass_fraction, 0.2);
        assert_eq!(s.nodes, vec![5, 3]);
    }
}
