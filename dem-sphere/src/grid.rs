//! Broad phase: candidate pairs (a Verlet list) from a single uniform cell grid or from the
//! multi-level grid of Ogarko & Luding (2012).
//!
//! **Verlet list with skin** (Verlet 1967; Allen & Tildesley 1987, *Computer Simulation of
//! Liquids*, §5.3). The list holds every pair with |x_j − x_i| < r_i + r_j + m, the margin
//! m = skin + reach (reach: the largest separation at which a law still acts, JKR neck or van
//! der Waals cut-off). It stays valid while no sphere has moved more than skin/2 since the
//! build (two spheres then close by at most `skin`), which the step checks.
//!
//! **Single grid.** Cubic cells of side c ≥ 2 r_max + m; a pair can only be in the same or
//! adjacent cells (27-cell stencil). With size ratio R/r = 10 the cells are sized by the
//! large spheres and each small sphere visits ~(c/2r)³ ≈ 10³ small neighbours for a few
//! contacts: the cost grows with the size ratio cubed.
//!
//! **Multi-level grid** (Ogarko & Luding 2012, Comput. Phys. Commun. 183:931–936). Levels
//! k = 0…L−1 of cell side c_k = 2 r_min ρ^k + m (ρ = the level ratio, default 2), the last one
//! covering 2 r_max + m; each sphere is stored only in the grid of the lowest level whose
//! cells hold it (2r + m ≤ c_k). A sphere i of level l searches
//!
//! * its own level with the 27-cell stencil (pairs j > i), and
//! * every coarser level k > l in the cells overlapping the box x_i ± (r_i + r_max,k + m),
//!   r_max,k the largest radius stored at level k: at most a 2–3 cell stencil per axis, since
//!   c_k ≥ 2 r_max,k;
//!
//! so cross-level pairs are found once, from the smaller sphere, and each sphere only visits
//! cells of a size matched to the partner's. The cost per sphere is then nearly independent
//! of the size ratio (the paper's result, checked by the benchmark test `bench_grids`).
//!
//! Both grids give the same sorted list of pairs (i < j), built in parallel over fixed index
//! ranges and concatenated in order, so it does not depend on the thread count. Grids are
//! dense arrays over the particles' bounding box; a level whose array would exceed
//! 64 N + 4096 cells gets larger cells (still correct, only slower).

use nalgebra::Vector3;
use rayon::prelude::*;

/// Which grid the broad phase uses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GridKind {
    /// One uniform grid of cells sized by the largest sphere.
    Single,
    /// Ogarko & Luding's hierarchy, cell sides growing by `ratio` (> 1) from level to level.
    MultiLevel { ratio: f64 },
}

impl Default for GridKind {
    fn default() -> GridKind {
        GridKind::MultiLevel { ratio: 2.0 }
    }
}

/// One dense cell grid (counting-sorted particle indices).
#[derive(Clone, Debug)]
struct Level {
    cell: f64,
    dims: [i64; 3],
    /// start[c]..start[c+1] in `items` for cell c.
    start: Vec<u32>,
    items: Vec<u32>,
    r_max: f64,
}

impl Level {
    fn build(
        cell: f64,
        origin: &Vector3<f64>,
        ext: &Vector3<f64>,
        x: &[Vector3<f64>],
        members: &[u32],
        cap: usize,
    ) -> Level {
        let mut cell = cell;
        let dims = loop {
            let d = [0, 1, 2].map(|k| ((ext[k] / cell).floor() as i64 + 1).max(1));
            if (d[0] * d[1] * d[2]) as usize <= cap {
                break d;
            }
            cell *= 1.25;
        };
        let ncell = (dims[0] * dims[1] * dims[2]) as usize;
        let mut count = vec![0u32; ncell + 1];
        let key = |i: u32| -> usize {
            let p = x[i as usize] - origin;
            let c = [0, 1, 2].map(|k| ((p[k] / cell).floor() as i64).clamp(0, dims[k] - 1));
            ((c[2] * dims[1] + c[1]) * dims[0] + c[0]) as usize
        };
        let keys: Vec<usize> = members.iter().map(|&i| key(i)).collect();
        for &k in &keys {
            count[k + 1] += 1;
        }
        for c in 0..ncell {
            count[c + 1] += count[c];
        }
        let mut fill = count.clone();
        let mut items = vec![0u32; members.len()];
        for (&i, &k) in members.iter().zip(&keys) {
            items[fill[k] as usize] = i;
            fill[k] += 1;
        }
        Level {
            cell,
            dims,
            start: count,
            items,
            r_max: 0.0,
        }
    }

    fn coord(&self, p: f64, k: usize) -> i64 {
        ((p / self.cell).floor() as i64).clamp(0, self.dims[k] - 1)
    }

    /// Visit every particle in the cells overlapping [lo, hi] (relative to the origin).
    #[inline]
    fn visit(&self, lo: &Vector3<f64>, hi: &Vector3<f64>, mut f: impl FnMut(u32)) {
        let a = [0, 1, 2].map(|k| self.coord(lo[k], k));
        let b = [0, 1, 2].map(|k| self.coord(hi[k], k));
        for cz in a[2]..=b[2] {
            for cy in a[1]..=b[1] {
                let row = (cz * self.dims[1] + cy) * self.dims[0];
                let s = self.start[(row + a[0]) as usize] as usize;
                let e = self.start[(row + b[0]) as usize + 1] as usize;
                for &j in &self.items[s..e] {
                    f(j);
                }
            }
        }
    }
}

/// Statistics of the last build.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct GridStats {
    /// Number of levels (1 for the single grid).
    pub levels: usize,
    /// Candidate pairs tested (distance computed).
    pub tests: u64,
    /// Pairs in the list.
    pub pairs: usize,
}

/// All pairs i < j with |x_j − x_i| < r_i + r_j + margin, sorted, and the build statistics.
pub fn find_pairs(
    kind: GridKind,
    x: &[Vector3<f64>],
    r: &[f64],
    margin: f64,
) -> (Vec<(u32, u32)>, GridStats) {
    let n = x.len();
    if n < 2 {
        return (Vec::new(), GridStats::default());
    }
    let mut lo = x[0];
    let mut hi = x[0];
    let (mut r_min, mut r_max) = (f64::INFINITY, 0.0f64);
    for (p, &ri) in x.iter().zip(r) {
        lo = lo.inf(p);
        hi = hi.sup(p);
        r_min = r_min.min(ri);
        r_max = r_max.max(ri);
    }
    let ext = hi - lo;
    let cap = 64 * n + 4096;
    // Level cell sides and each particle's level.
    let sides: Vec<f64> = match kind {
        GridKind::Single => vec![2.0 * r_max + margin],
        GridKind::MultiLevel { ratio } => {
            let ratio = if ratio > 1.0 { ratio } else { 2.0 };
            let mut s = vec![2.0 * r_min + margin];
            while *s.last().unwrap() < 2.0 * r_max + margin {
                let k = s.len() as i32;
                s.push(
                    (2.0 * r_min * ratio.powi(k) + margin)
                        .min(2.0 * r_max + margin)
                        .max(*s.last().unwrap()),
                );
                if s[s.len() - 1] >= 2.0 * r_max + margin {
                    break;
                }
            }
            s
        }
    };
    let nl = sides.len();
    let level_of = |ri: f64| {
        sides
            .iter()
            .position(|&c| 2.0 * ri + margin <= c)
            .unwrap_or(nl - 1)
    };
    let lev: Vec<u8> = r.iter().map(|&ri| level_of(ri) as u8).collect();
    let mut members = vec![Vec::new(); nl];
    for (i, &l) in lev.iter().enumerate() {
        members[l as usize].push(i as u32);
    }
    let mut levels: Vec<Level> = (0..nl)
        .map(|l| Level::build(sides[l], &lo, &ext, x, &members[l], cap))
        .collect();
    for (l, m) in members.iter().enumerate() {
        levels[l].r_max = m.iter().map(|&i| r[i as usize]).fold(0.0, f64::max);
    }
    let chunk = 256usize;
    let parts: Vec<(Vec<(u32, u32)>, u64)> = (0..n.div_ceil(chunk))
        .into_par_iter()
        .map(|c| {
            let mut out = Vec::new();
            let mut tests = 0u64;
            for i in c * chunk..((c + 1) * chunk).min(n) {
                let l = lev[i] as usize;
                let p = x[i] - lo;
                let ri = r[i];
                for (k, level) in levels.iter().enumerate().skip(l) {
                    if level.items.is_empty() {
                        continue;
                    }
                    let reach = if k == l {
                        level.cell
                    } else {
                        ri + level.r_max + margin
                    };
                    let e = Vector3::repeat(reach);
                    level.visit(&(p - e), &(p + e), |j| {
                        if k == l && j as usize <= i {
                            return;
                        }
                        tests += 1;
                        let s = ri + r[j as usize] + margin;
                        if (x[j as usize] - x[i]).norm_squared() < s * s {
                            let i = i as u32;
                            out.push((i.min(j), i.max(j)));
                        }
                    });
                }
            }
            (out, tests)
        })
        .collect();
    let tests = parts.iter().map(|p| p.1).sum();
    let mut pairs: Vec<(u32, u32)> = parts.into_iter().flat_map(|p| p.0).collect();
    pairs.par_sort_unstable();
    let stats = GridStats {
        levels: nl,
        tests,
        pairs: pairs.len(),
    };
    (pairs, stats)
}

/// Brute-force reference: all pairs by O(N²) search (tests).
pub fn find_pairs_brute(x: &[Vector3<f64>], r: &[f64], margin: f64) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for i in 0..x.len() {
        for j in i + 1..x.len() {
            let s = r[i] + r[j] + margin;
            if (x[j] - x[i]).norm_squared() < s * s {
                out.push((i as u32, j as u32));
            }
        }
    }
    out
}
