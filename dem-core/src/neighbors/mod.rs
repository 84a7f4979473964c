//! Neighbour list: a Verlet list built from a multi-level cell grid (`grid.rs`), rebuilt only
//! when some disc or wall moved more than half the skin since the last build (then no pair
//! outside the list can have come into contact: each side moved < skin/2).
//!
//! The list is a half list in CSR form sorted by (i, j) with i < j: the partners of disc i are
//! `nbr[start[i]..start[i+1]]`. Per-pair contact history (`us`, `mr`) and reference gaps
//! (`g0`) sit in slots parallel to `nbr`; a rebuild carries the history of touching pairs over
//! by merging the old and new sorted lists. `reorder` renumbers discs in cell order for
//! cache locality. `rstart/rpair` list, for each disc k, the pairs where k is the partner j in
//! increasing pair order: the parallel force pass gathers per disc in exactly the order the
//! serial pass scatters, so results are bit-identical for any thread count.

pub(crate) mod grid;
pub(crate) mod reorder;

pub use crate::state::MinImage;
use crate::state::{State, Wall};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Key of an unordered pair of disc ids (or indices), smaller first.
#[inline]
pub fn pair_key(a: u32, b: u32) -> u64 {
    let (p, q) = if a < b { (a, b) } else { (b, a) };
    ((p as u64) << 32) | q as u64
}

/// Disc–wall candidate pairs with their history.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct WallPairs {
    pub wall: Vec<u32>,
    pub disc: Vec<u32>,
    pub us: Vec<f64>,
    pub mr: Vec<f64>,
}

/// The Verlet neighbour list with contact history.
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Neighbors {
    pub skin: f64,
    pub start: Vec<u32>,
    pub nbr: Vec<u32>,
    /// Tangential spring displacement per pair (m), along t = (−n_y, n_x).
    pub us: Vec<f64>,
    /// Rolling moment on disc i per pair (N·m).
    pub mr: Vec<f64>,
    /// Reference gap g₀ per pair (m); empty when no offsets are registered.
    pub g0: Vec<f64>,
    pub rstart: Vec<u32>,
    pub rpair: Vec<u32>,
    /// Positions at the last build (discs) and wall end points at the last build.
    pub x0: Vec<f64>,
    pub y0: Vec<f64>,
    pub wall0: Vec<[f64; 4]>,
    /// The `via` vertices of polyline walls at the last build, all walls in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub wall0_via: Vec<[f64; 2]>,
    pub walls: WallPairs,
    /// Number of builds so far.
    pub builds: u64,
    /// Whether every index in the lists is known to be in range (set by `rebuild`, which
    /// builds them so; cleared by deserialisation and `remap`). The force pass checks the
    /// indices once when this is false.
    #[serde(skip)]
    pub verified: bool,
    /// The disc i of each pair (parallel to `nbr`: `owner[p] = i` for p in
    /// `start[i]..start[i+1]`), read by the AVX2 gather instead of walking `start`. Made by
    /// [`Neighbors::set_owner`] with every build and whenever the force pass verifies the list.
    #[serde(skip)]
    pub owner: Vec<u32>,
}

impl Neighbors {
    pub fn n_pairs(&self) -> usize {
        self.nbr.len()
    }

    /// Fill [`Neighbors::owner`] from `start` (a consistent `start` gives owners < n).
    pub fn set_owner(&mut self) {
        self.owner.clear();
        self.owner.reserve(self.nbr.len());
        for (i, w) in self.start.windows(2).enumerate() {
            let k = (w[1] as usize).saturating_sub(w[0] as usize);
            self.owner.extend(std::iter::repeat_n(i as u32, k));
        }
    }

    /// Largest squared displacement of a disc since the last build (serial max: exact).
    pub fn max_disp2(&self, st: &State) -> f64 {
        let d = &st.discs;
        if self.x0.len() != d.len() {
            return f64::INFINITY;
        }
        let mut m = 0.0f64;
        for k in 0..d.len() {
            let dx = d.x[k] - self.x0[k];
            let dy = d.y[k] - self.y0[k];
            m = m.max(dx * dx + dy * dy);
        }
        m
    }

    /// Largest displacement of a wall vertex since the last build (walls move rigidly, so no
    /// point of a wall moved further than its farthest-moved vertex: the displacement of a
    /// rigid motion is affine in the point, its length convex).
    pub fn max_wall_disp(&self, walls: &[Wall]) -> f64 {
        let n_via: usize = walls.iter().map(|w| w.via.len()).sum();
        if self.wall0.len() != walls.len() || self.wall0_via.len() != n_via {
            return f64::INFINITY;
        }
        let mut m = 0.0f64;
        for (w, r) in walls.iter().zip(&self.wall0) {
            let da = (w.a[0] - r[0]).hypot(w.a[1] - r[1]);
            let db = (w.b[0] - r[2]).hypot(w.b[1] - r[3]);
            m = m.max(da).max(db);
        }
        let via = walls.iter().flat_map(|w| w.via.iter());
        for (p, r) in via.zip(&self.wall0_via) {
            m = m.max((p[0] - r[0]).hypot(p[1] - r[1]));
        }
        m
    }

    /// Rebuild the list for the current (wrapped) positions, keeping the history of pairs
    /// present before. `offsets` are the reference gaps keyed by [`pair_key`] of disc ids.
    pub fn rebuild(&mut self, st: &State, skin: f64, offsets: &BTreeMap<u64, f64>) {
        let n = st.discs.len();
        let img = MinImage::new(&st.periodic);
        let keys = grid::find_pairs(st, skin, &img);
        // Old history, sorted by key (only nonzero entries matter).
        let mut old: Vec<(u64, f64, f64)> = Vec::new();
        if self.start.len() == n + 1 {
            for i in 0..n {
                for p in self.start[i] as usize..self.start[i + 1] as usize {
                    if self.us[p] != 0.0 || self.mr[p] != 0.0 {
                        let j = self.nbr[p];
                        old.push((((i as u64) << 32) | j as u64, self.us[p], self.mr[p]));
                    }
                }
            }
        }
        old.sort_unstable_by_key(|e| e.0);
        self.start.clear();
        self.start.resize(n + 1, 0);
        self.nbr.clear();
        self.us.clear();
        self.mr.clear();
        self.g0.clear();
        let mut o = 0;
        for &k in &keys {
            let i = (k >> 32) as usize;
            self.start[i + 1] += 1;
            self.nbr.push(k as u32);
            while o < old.len() && old[o].0 < k {
                o += 1;
            }
            if o < old.len() && old[o].0 == k {
                self.us.push(old[o].1);
                self.mr.push(old[o].2);
            } else {
                self.us.push(0.0);
                self.mr.push(0.0);
            }
        }
        for i in 0..n {
            self.start[i + 1] += self.start[i];
        }
        if !offsets.is_empty() {
            let id = &st.discs.id;
            for &k in &keys {
                let (i, j) = ((k >> 32) as usize, (k as u32) as usize);
                let g = offsets.get(&pair_key(id[i], id[j])).copied().unwrap_or(0.0);
                self.g0.push(g);
            }
        }
        // Reverse (partner-side) lists, in increasing pair order.
        self.rstart.clear();
        self.rstart.resize(n + 1, 0);
        for &j in &self.nbr {
            self.rstart[j as usize + 1] += 1;
        }
        for k in 0..n {
            self.rstart[k + 1] += self.rstart[k];
        }
        self.rpair.clear();
        self.rpair.resize(self.nbr.len(), 0);
        let mut fill: Vec<u32> = self.rstart[..n].to_vec();
        for (p, &j) in self.nbr.iter().enumerate() {
            self.rpair[fill[j as usize] as usize] = p as u32;
            fill[j as usize] += 1;
        }
        self.rebuild_walls(st, skin, &img);
        self.x0.clone_from(&st.discs.x);
        self.y0.clone_from(&st.discs.y);
        self.wall0 = st
            .walls
            .iter()
            .map(|w| [w.a[0], w.a[1], w.b[0], w.b[1]])
            .collect();
        self.wall0_via = st
            .walls
            .iter()
            .flat_map(|w| w.via.iter().copied())
            .collect();
        self.skin = skin;
        self.builds += 1;
        self.set_owner();
        self.verified = true;
    }

    fn rebuild_walls(&mut self, st: &State, skin: f64, img: &MinImage) {
        let mut old: Vec<(u64, f64, f64)> = (0..self.walls.wall.len())
            .filter(|&p| self.walls.us[p] != 0.0 || self.walls.mr[p] != 0.0)
            .map(|p| {
                let k = ((self.walls.wall[p] as u64) << 32) | self.walls.disc[p] as u64;
                (k, self.walls.us[p], self.walls.mr[p])
            })
            .collect();
        old.sort_unstable_by_key(|e| e.0);
        let w = &mut self.walls;
        w.wall.clear();
        w.disc.clear();
        w.us.clear();
        w.mr.clear();
        let d = &st.discs;
        let mut o = 0;
        for (wi, wall) in st.walls.iter().enumerate() {
            for k in 0..d.len() {
                let (_, _, dist) = closest_on_wall(wall, d.x[k], d.y[k], img);
                if dist < d.r[k] + skin {
                    let key = ((wi as u64) << 32) | k as u64;
                    w.wall.push(wi as u32);
                    w.disc.push(k as u32);
                    while o < old.len() && old[o].0 < key {
                        o += 1;
                    }
                    if o < old.len() && old[o].0 == key {
                        w.us.push(old[o].1);
                        w.mr.push(old[o].2);
                    } else {
                        w.us.push(0.0);
                        w.mr.push(0.0);
                    }
                }
            }
        }
    }

    /// Renumber discs: `new_of_old[old] = new`. Keeps the history with its pairs (a swapped
    /// pair keeps u_s, whose sign is invariant under i↔j, and flips the rolling moment).
    pub fn remap(&mut self, new_of_old: &[u32]) {
        let n = new_of_old.len();
        if self.start.len() != n + 1 {
            return;
        }
        let mut entries: Vec<(u64, f64, f64, f64)> = Vec::with_capacity(self.nbr.len());
        for i in 0..n {
            for p in self.start[i] as usize..self.start[i + 1] as usize {
                let (a, b) = (new_of_old[i], new_of_old[self.nbr[p] as usize]);
                let g = self.g0.get(p).copied().unwrap_or(0.0);
                if a < b {
                    entries.push((((a as u64) << 32) | b as u64, self.us[p], self.mr[p], g));
                } else {
                    entries.push((((b as u64) << 32) | a as u64, self.us[p], -self.mr[p], g));
                }
            }
        }
        entries.sort_unstable_by_key(|e| e.0);
        let has_g0 = !self.g0.is_empty();
        self.start.iter_mut().for_each(|s| *s = 0);
        self.nbr.clear();
        self.us.clear();
        self.mr.clear();
        self.g0.clear();
        for e in &entries {
            self.start[(e.0 >> 32) as usize + 1] += 1;
            self.nbr.push(e.0 as u32);
            self.us.push(e.1);
            self.mr.push(e.2);
            if has_g0 {
                self.g0.push(e.3);
            }
        }
        for i in 0..n {
            self.start[i + 1] += self.start[i];
        }
        for dsc in &mut self.walls.disc {
            *dsc = new_of_old[*dsc as usize];
        }
        // Positions at build and reverse lists are refreshed by the rebuild that follows.
        self.verified = false;
        self.x0.clear();
        self.y0.clear();
    }
}

/// Closest point of wall `w` (a segment or a polyline) to (x, y) (minimum image) and the
/// distance: returns (px, py, dist) with (px, py) on the wall, in the image nearest the point.
/// On a polyline the nearest of its segments wins (the first of equals: at a vertex shared by
/// two faces, the face that comes first from `a`; both give the vertex itself), so a disc gets
/// one contact per wall, with its nearest feature (face or vertex). A plain segment takes
/// exactly the arithmetic of [`closest_on_segment`].
#[inline]
pub fn closest_on_wall(w: &Wall, x: f64, y: f64, img: &MinImage) -> (f64, f64, f64) {
    if w.via.is_empty() {
        return closest_on_segment(w.a, w.b, x, y, img);
    }
    let mut best = (0.0, 0.0, f64::INFINITY);
    let mut a = w.a;
    for b in w.via.iter().copied().chain(std::iter::once(w.b)) {
        let c = closest_on_segment(a, b, x, y, img);
        if c.2 < best.2 {
            best = c;
        }
        a = b;
    }
    best
}

/// Closest point of the segment from `a` to `b` to (x, y) (minimum image) and the distance:
/// returns (px, py, dist) with (px, py) on the segment, in the image nearest the point.
#[inline]
pub fn closest_on_segment(
    a: [f64; 2],
    b: [f64; 2],
    x: f64,
    y: f64,
    img: &MinImage,
) -> (f64, f64, f64) {
    let (rx, ry) = img.delta(x - a[0], y - a[1]);
    let (ex, ey) = (b[0] - a[0], b[1] - a[1]);
    let l2 = ex * ex + ey * ey;
    let s = if l2 > 0.0 {
        ((rx * ex + ry * ey) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let (px, py) = (s * ex, s * ey);
    let (dx, dy) = (rx - px, ry - py);
    // Return the point in the frame of (x, y): x − (r − p).
    (x - dx, y - dy, (dx * dx + dy * dy).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn history_follows_pairs_through_remap_and_rebuild() {
        let mut st = State::default();
        for k in 0..6 {
            st.discs
                .push_uniform(k as f64 * 0.019, 0.0, 0.01, 1.0, 1.0, 0);
        }
        let mut nb = Neighbors::default();
        let none = BTreeMap::new();
        nb.rebuild(&st, 0.001, &none);
        assert_eq!(nb.n_pairs(), 5);
        // History value = 10·i + j (ids), rolling = i − j.
        for i in 0..6 {
            for p in nb.start[i] as usize..nb.start[i + 1] as usize {
                let j = nb.nbr[p] as usize;
                nb.us[p] = 10.0 * i as f64 + j as f64;
                nb.mr[p] = i as f64 - j as f64;
            }
        }
        // Reverse the order of the discs.
        let order: Vec<u32> = (0..6).rev().collect();
        let new_of_old: Vec<u32> = (0..6u32).map(|o| 5 - o).collect();
        st.discs.permute(&order);
        nb.remap(&new_of_old);
        nb.rebuild(&st, 0.001, &none);
        assert_eq!(nb.n_pairs(), 5);
        for i in 0..6 {
            for p in nb.start[i] as usize..nb.start[i + 1] as usize {
                let j = nb.nbr[p] as usize;
                let (a, b) = (st.discs.id[i] as f64, st.discs.id[j] as f64);
                // Pair keyed by ids: (lo, hi) = (min, max); u_s is invariant under i ↔ j, the
                // rolling moment on the new first disc flips sign.
                let (lo, hi) = (a.min(b), a.max(b));
                assert_eq!(nb.us[p], 10.0 * lo + hi);
                assert_eq!(nb.mr[p], a - b, "rolling moment sign");
            }
        }
        // A pair that separates beyond the skin loses its history; a new pair starts at 0.
        st.discs.x[0] += 1.0;
        nb.rebuild(&st, 0.001, &none);
        assert_eq!(nb.n_pairs(), 4);
    }
}
