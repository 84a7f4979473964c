//! Multi-level cell grid for the pair search (Ogarko & Luding 2012, Comput. Phys. Commun.
//! 183:931, "A fast multilevel algorithm for contact detection of arbitrarily polydisperse
//! objects"), reduced to what 2D discs need.
//!
//! Discs are sorted into levels by radius (level ℓ holds r ∈ [r_min 2^ℓ, r_min 2^{ℓ+1})); level
//! ℓ has its own grid of cell size s_ℓ = 2 r_max,ℓ + skin. A disc of level a looks for
//! partners of its own and larger levels b ≥ a in the 3×3 cells of grid b around it: any
//! partner within reach (r_i + r_j + skin ≤ s_b) lies there. Small discs therefore never scan
//! cells crowded by the size of the largest disc, and large discs find small partners through
//! the small discs' own search: the cost stays linear in N for any radius ratio, with at most
//! ⌈log₂(r_max/r_min)⌉ + 1 levels. Cells are a counting sort (cell start + sorted indices).
//!
//! **Sparse scenes.** When the discs of a level span far more cells than they fill (debris
//! flown clear of a cut: chips leave at ~20 m/s under damping that does not drag them, and
//! the bounding box grows to many times the specimen), a level keeps its cell size and lists
//! only its occupied cells (sorted cell indices, found by binary search) instead of
//! coarsening the grid: coarse cells put tens of discs in each cell of the specimen and made
//! the pair search half of a cut's time. The pairs found do not depend on the cells (every
//! candidate is tested against its reach, and the keys are sorted), so both layouts give the
//! same list, bit for bit.

#![allow(clippy::needless_range_loop)] // SoA: one index into several arrays

use super::MinImage;
use crate::state::{State, FREE};
use rayon::prelude::*;

const MAX_LEVELS: usize = 12;

/// One level's grid.
struct Level {
    /// Cell sides (each ≥ the level's reach s).
    cx: f64,
    cy: f64,
    nx: usize,
    ny: usize,
    ox: f64,
    oy: f64,
    /// Periodic axes wrap cell coordinates.
    px: bool,
    py: bool,
    /// Dense: the items of cell c are `items[start[c]..start[c + 1]]`. Sparse: those of the
    /// k-th occupied cell, `cells[k]`.
    start: Vec<u32>,
    items: Vec<u32>,
    /// Sparse levels: the occupied cells' indices, ascending; empty for a dense level.
    cells: Vec<u64>,
    sparse: bool,
}

impl Level {
    #[inline]
    fn coord(&self, x: f64, y: f64) -> (i64, i64) {
        let cx = ((x - self.ox) / self.cx).floor() as i64;
        let cy = ((y - self.oy) / self.cy).floor() as i64;
        (
            wrap_or_clamp(cx, self.nx, self.px),
            wrap_or_clamp(cy, self.ny, self.py),
        )
    }

    #[inline]
    fn cell_index(&self, x: f64, y: f64) -> usize {
        let (cx, cy) = self.coord(x, y);
        cy as usize * self.nx + cx as usize
    }

    /// The discs (indices) in cell `c`.
    #[inline]
    fn items_of(&self, c: usize) -> &[u32] {
        let k = if self.sparse {
            match self.cells.binary_search(&(c as u64)) {
                Ok(k) => k,
                Err(_) => return &[],
            }
        } else {
            c
        };
        &self.items[self.start[k] as usize..self.start[k + 1] as usize]
    }
}

/// Most cells per axis of a sparse level (its cell indices y·nx + x stay below 2⁶²).
const MAX_AXIS_CELLS: usize = 1 << 31;

#[inline]
fn wrap_or_clamp(c: i64, n: usize, periodic: bool) -> i64 {
    if periodic {
        c.rem_euclid(n as i64)
    } else {
        c.clamp(0, n as i64 - 1)
    }
}

/// Level of every disc and the number of levels.
fn levels_of(r: &[f64]) -> (Vec<u8>, usize) {
    let r_min = r.iter().cloned().fold(f64::INFINITY, f64::min).max(1e-300);
    let lv: Vec<u8> = r
        .iter()
        .map(|&ri| ((ri / r_min).log2().floor().max(0.0) as usize).min(MAX_LEVELS - 1) as u8)
        .collect();
    let n = lv.iter().map(|&l| l as usize + 1).max().unwrap_or(1);
    (lv, n)
}

/// Sorted, unique pair keys `(i << 32) | j` with i < j of all disc pairs with gap < skin,
/// excluding members of the same rigid clump. Positions must be wrapped into periodic axes.
pub fn find_pairs(st: &State, skin: f64, img: &MinImage) -> Vec<u64> {
    let d = &st.discs;
    let n = d.len();
    if n < 2 {
        return Vec::new();
    }
    let (lv, nlev) = levels_of(&d.r);
    // Bounding box (non-periodic axes) over all discs.
    let (mut xmin, mut xmax, mut ymin, mut ymax) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for k in 0..n {
        xmin = xmin.min(d.x[k]);
        xmax = xmax.max(d.x[k]);
        ymin = ymin.min(d.y[k]);
        ymax = ymax.max(d.y[k]);
    }
    let mut rmax = vec![0.0f64; nlev];
    let mut count = vec![0usize; nlev];
    for k in 0..n {
        let l = lv[k] as usize;
        rmax[l] = rmax[l].max(d.r[k]);
        count[l] += 1;
    }
    let grids: Vec<Option<Level>> = (0..nlev)
        .map(|l| {
            if count[l] == 0 {
                return None;
            }
            let s = 2.0 * rmax[l] + skin;
            Some(make_level(
                st,
                &lv,
                l as u8,
                count[l],
                s,
                [xmin, xmax, ymin, ymax],
            ))
        })
        .collect();
    let mut keys: Vec<u64> = (0..n)
        .into_par_iter()
        .with_min_len(1024)
        .fold(Vec::new, |mut out, i| {
            partners(st, &lv, &grids, i, skin, img, &mut out);
            out
        })
        .reduce(Vec::new, |mut a, mut b| {
            a.append(&mut b);
            a
        });
    keys.par_sort_unstable();
    keys.dedup();
    keys
}

fn make_level(st: &State, lv: &[u8], l: u8, count: usize, s: f64, bb: [f64; 4]) -> Level {
    let per = st.periodic;
    let axis = |a: usize, lo: f64, hi: f64| -> (usize, f64, f64, bool) {
        match per.length[a] {
            Some(len) => {
                let nc = ((len / s).floor() as usize).max(1);
                (nc, len / nc as f64, per.lo[a], true)
            }
            None => {
                // (Saturating: a disc flown to 1e300 m gives the most cells, then coarsening.)
                let nc = (((hi - lo) / s).floor().min(1e18) as usize).saturating_add(1);
                (nc.max(1), s, lo, false)
            }
        }
    };
    let (mut nx, mut cx, ox, px) = axis(0, bb[0], bb[1]);
    let (mut ny, mut cy, oy, py) = axis(1, bb[2], bb[3]);
    // Sparse scenes (discs flown far apart): list the occupied cells only (module docs), with
    // the axes coarsened only as far as the cell indices need.
    let cap = 4 * count + 64;
    let sparse = nx.checked_mul(ny).is_none_or(|c| c > cap);
    while sparse && (nx > MAX_AXIS_CELLS || ny > MAX_AXIS_CELLS) {
        let mut changed = false;
        if !px && nx > 1 {
            nx = nx.div_ceil(2);
            cx *= 2.0;
            changed = true;
        }
        if !py && ny > 1 {
            ny = ny.div_ceil(2);
            cy *= 2.0;
            changed = true;
        }
        if !changed {
            break;
        }
    }
    let mut g = Level {
        cx,
        cy,
        nx,
        ny,
        ox,
        oy,
        px,
        py,
        start: Vec::new(),
        items: vec![0; count],
        cells: Vec::new(),
        sparse,
    };
    let d = &st.discs;
    if sparse {
        // (cell, disc) sorted: the discs of a cell in ascending order, as the counting sort.
        let mut at: Vec<(u64, u32)> = (0..d.len())
            .filter(|&k| lv[k] == l)
            .map(|k| (g.cell_index(d.x[k], d.y[k]) as u64, k as u32))
            .collect();
        at.sort_unstable();
        g.start.push(0);
        for (n, &(c, k)) in at.iter().enumerate() {
            if g.cells.last() != Some(&c) {
                if !g.cells.is_empty() {
                    g.start.push(n as u32);
                }
                g.cells.push(c);
            }
            g.items[n] = k;
        }
        g.start.push(at.len() as u32);
        return g;
    }
    g.start = vec![0; nx * ny + 1];
    for k in 0..d.len() {
        if lv[k] == l {
            let c = g.cell_index(d.x[k], d.y[k]);
            g.start[c + 1] += 1;
        }
    }
    for c in 0..nx * ny {
        g.start[c + 1] += g.start[c];
    }
    let mut fill = g.start.clone();
    for k in 0..d.len() {
        if lv[k] == l {
            let c = g.cell_index(d.x[k], d.y[k]);
            g.items[fill[c] as usize] = k as u32;
            fill[c] += 1;
        }
    }
    g
}

#[allow(clippy::too_many_arguments)]
fn partners(
    st: &State,
    lv: &[u8],
    grids: &[Option<Level>],
    i: usize,
    skin: f64,
    img: &MinImage,
    out: &mut Vec<u64>,
) {
    let d = &st.discs;
    let (xi, yi, ri, bi) = (d.x[i], d.y[i], d.r[i], d.body[i]);
    let a = lv[i] as usize;
    let mut cells = [0usize; 9];
    for (b, g) in grids.iter().enumerate().skip(a) {
        let Some(g) = g else { continue };
        let (cx, cy) = g.coord(xi, yi);
        let mut nc = 0;
        for dy in -1i64..=1 {
            let y = cy + dy;
            if !g.py && (y < 0 || y >= g.ny as i64) {
                continue;
            }
            let y = y.rem_euclid(g.ny as i64) as usize;
            for dx in -1i64..=1 {
                let x = cx + dx;
                if !g.px && (x < 0 || x >= g.nx as i64) {
                    continue;
                }
                let c = y * g.nx + x.rem_euclid(g.nx as i64) as usize;
                if !cells[..nc].contains(&c) {
                    cells[nc] = c;
                    nc += 1;
                }
            }
        }
        for &c in &cells[..nc] {
            for &j in g.items_of(c) {
                let j = j as usize;
                if j == i || (b == a && j < i) {
                    continue;
                }
                if bi != FREE && d.body[j] == bi {
                    continue;
                }
                let (ddx, ddy) = img.delta(d.x[j] - xi, d.y[j] - yi);
                let reach = ri + d.r[j] + skin;
                if ddx * ddx + ddy * ddy < reach * reach {
                    let (p, q) = if i < j { (i, j) } else { (j, i) };
                    out.push(((p as u64) << 32) | q as u64);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::Periodic;
    use clumpgen::synth::SplitMix64;

    /// All pairs with gap < skin by brute force (minimum image).
    fn brute(st: &State, skin: f64, img: &MinImage) -> Vec<u64> {
        let d = &st.discs;
        let mut out = Vec::new();
        for i in 0..d.len() {
            for j in i + 1..d.len() {
                let (dx, dy) = img.delta(d.x[j] - d.x[i], d.y[j] - d.y[i]);
                let reach = d.r[i] + d.r[j] + skin;
                if dx * dx + dy * dy < reach * reach {
                    out.push(((i as u64) << 32) | j as u64);
                }
            }
        }
        out
    }

    fn scene(periodic: [bool; 2], ratio: f64, seed: u64) -> State {
        let mut rng = SplitMix64::new(seed);
        let (lx, ly) = (1.0, 0.7);
        let mut st = State {
            periodic: Periodic {
                lo: [-0.2, 0.1],
                length: [periodic[0].then_some(lx), periodic[1].then_some(ly)],
            },
            ..State::default()
        };
        let r0 = 0.004;
        for _ in 0..1500 {
            // Log-uniform radii over the ratio, so every level is populated.
            let r = r0 * ratio.powf(rng.uniform());
            let x = -0.2 + lx * rng.uniform();
            let y = 0.1 + ly * rng.uniform();
            st.discs.push_uniform(x, y, r, 1000.0, 1.0, 0);
        }
        st
    }

    #[test]
    fn grid_pairs_equal_brute_force_for_radius_ratio_10() {
        for (k, per) in [[false, false], [true, false], [true, true]]
            .iter()
            .enumerate()
        {
            let st = scene(*per, 10.0, 7 + k as u64);
            let img = MinImage::new(&st.periodic);
            let skin = 0.001;
            let fast = find_pairs(&st, skin, &img);
            let slow = brute(&st, skin, &img);
            assert!(slow.len() > 1000, "scene too sparse: {}", slow.len());
            assert_eq!(fast, slow, "periodic {per:?}");
        }
    }

    /// Debris flown far (a few discs 10–10⁴ box sizes away, one at 1e200 m): the levels go
    /// sparse, and the pairs are still exactly the brute force's, near and far.
    #[test]
    fn sparse_levels_find_the_same_pairs() {
        let mut st = scene([false, false], 10.0, 11);
        let mut rng = SplitMix64::new(5);
        for k in 0..40 {
            let far = 10f64.powi(1 + k % 4);
            let (x, y) = (far * rng.uniform(), far * (rng.uniform() - 0.5));
            // Pairs of touching discs out there, so far pairs exist to be found.
            st.discs.push_uniform(x, y, 0.004, 1000.0, 1.0, 0);
            st.discs.push_uniform(x + 0.0075, y, 0.004, 1000.0, 1.0, 0);
        }
        st.discs.push_uniform(1e200, -1e200, 0.004, 1000.0, 1.0, 0);
        let img = MinImage::new(&st.periodic);
        let (lv, _) = levels_of(&st.discs.r);
        let g = make_level(&st, &lv, 0, lv.iter().filter(|&&l| l == 0).count(), 0.01, {
            let d = &st.discs;
            let f = |v: &[f64], m: fn(f64, f64) -> f64, z: f64| v.iter().fold(z, |a, &b| m(a, b));
            [
                f(&d.x, f64::min, f64::INFINITY),
                f(&d.x, f64::max, f64::NEG_INFINITY),
                f(&d.y, f64::min, f64::INFINITY),
                f(&d.y, f64::max, f64::NEG_INFINITY),
            ]
        });
        assert!(g.sparse && !g.cells.is_empty());
        let skin = 0.001;
        let fast = find_pairs(&st, skin, &img);
        let slow = brute(&st, skin, &img);
        let n0 = 1500u64;
        assert!(fast.iter().filter(|&&k| (k >> 32) >= n0).count() >= 40);
        assert_eq!(fast, slow);
    }

    #[test]
    fn clump_members_are_not_paired() {
        let mut st = scene([false, false], 1.0, 3);
        st.clumps.x.push(0.0);
        for b in st.discs.body.iter_mut().take(10) {
            *b = 0;
        }
        let img = MinImage::new(&st.periodic);
        let pairs = find_pairs(&st, 0.5, &img);
        for k in pairs {
            let (i, j) = ((k >> 32) as usize, (k as u32) as usize);
            assert!(!(i < 10 && j < 10), "members {i} and {j} paired");
        }
    }
}
