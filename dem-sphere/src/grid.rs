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
//! **Periodic axes** ([`Periodic`]): positions stay unwrapped; the grids place each sphere by
//! its wrapped position, the cells of a periodic axis divide the period exactly and wrap,
//! and every distance is the minimum image.
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

/// Periodic boundaries: axis k is periodic with period `len[k]` over [lo_k, lo_k + len_k).
/// Positions are kept unwrapped; pair vectors take the minimum image (Allen & Tildesley
/// 1987, §1.5.2), and the grids wrap their cells on those axes.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Periodic {
    /// Origin of the periodic cell (m).
    pub lo: Vector3<f64>,
    /// Period along each axis (m), None: not periodic.
    pub len: [Option<f64>; 3],
}

impl Periodic {
    /// No periodic axis.
    pub fn none() -> Periodic {
        Periodic::default()
    }

    /// Minimum image of the pair vector `d`.
    #[inline]
    pub fn delta(&self, mut d: Vector3<f64>) -> Vector3<f64> {
        for k in 0..3 {
            if let Some(l) = self.len[k] {
                d[k] -= l * (d[k] / l).round();
            }
        }
        d
    }

    /// `p` brought into the periodic cell.
    #[inline]
    pub fn wrap(&self, mut p: Vector3<f64>) -> Vector3<f64> {
        for k in 0..3 {
            if let Some(l) = self.len[k] {
                p[k] = self.lo[k] + (p[k] - self.lo[k]).rem_euclid(l);
            }
        }
        p
    }
}

/// One dense cell grid (counting-sorted particle indices).
#[derive(Clone, Debug)]
struct Level {
    /// Cell side per axis (a periodic axis divides its period exactly).
    cell: [f64; 3],
    dims: [i64; 3],
    periodic: [bool; 3],
    /// start[c]..start[c+1] in `items` for cell c.
    start: Vec<u32>,
    items: Vec<u32>,
    r_max: f64,
}

impl Level {
    fn build(
        side: f64,
        ext: &Vector3<f64>,
        periodic: [bool; 3],
        x: &[Vector3<f64>],
        members: &[u32],
        cap: usize,
    ) -> Level {
        let mut side = side;
        let (dims, cell) = loop {
            let d = [0, 1, 2].map(|k| {
                if periodic[k] {
                    ((ext[k] / side).floor() as i64).max(1)
                } else {
                    ((ext[k] / side).floor() as i64 + 1).max(1)
                }
            });
            // In f64: a huge extent must not overflow the product.
            if (d[0] as f64) * (d[1] as f64) * (d[2] as f64) <= cap as f64 {
                let c = [0, 1, 2].map(|k| {
                    if periodic[k] {
                        ext[k] / d[k] as f64
                    } else {
                        side
                    }
                });
                break (d, c);
            }
            side *= 1.25;
        };
        let ncell = (dims[0] * dims[1] * dims[2]) as usize;
        let mut count = vec![0u32; ncell + 1];
        // `x` is relative to the origin and wrapped.
        let key = |i: u32| -> usize {
            let p = x[i as usize];
            let c = [0, 1, 2].map(|k| ((p[k] / cell[k]).floor() as i64).clamp(0, dims[k] - 1));
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
            periodic,
            start: count,
            items,
            r_max: 0.0,
        }
    }

    /// The cell range of [lo, hi] along axis k: (first, last, wraps). A periodic range
    /// covering the whole axis is the axis once.
    #[inline]
    fn range(&self, lo: f64, hi: f64, k: usize) -> (i64, i64, bool) {
        let a = (lo / self.cell[k]).floor() as i64;
        let b = (hi / self.cell[k]).floor() as i64;
        let n = self.dims[k];
        if !self.periodic[k] {
            (a.clamp(0, n - 1), b.clamp(0, n - 1), false)
        } else if b - a + 1 >= n {
            (0, n - 1, false)
        } else {
            (a, b, a < 0 || b >= n)
        }
    }

    /// Visit every particle in the cells overlapping [lo, hi] (relative to the origin,
    /// wrapped on the periodic axes), each cell once.
    #[inline]
    fn visit(&self, lo: &Vector3<f64>, hi: &Vector3<f64>, mut f: impl FnMut(u32)) {
        let r = [0, 1, 2].map(|k| self.range(lo[k], hi[k], k));
        let m = |c: i64, k: usize| c.rem_euclid(self.dims[k]);
        for cz in r[2].0..=r[2].1 {
            let cz = m(cz, 2);
            for cy in r[1].0..=r[1].1 {
                let cy = m(cy, 1);
                let row = (cz * self.dims[1] + cy) * self.dims[0];
                if !r[0].2 {
                    let s = self.start[(row + r[0].0) as usize] as usize;
                    let e = self.start[(row + r[0].1) as usize + 1] as usize;
                    for &j in &self.items[s..e] {
                        f(j);
                    }
                } else {
                    for cx in r[0].0..=r[0].1 {
                        let c = (row + m(cx, 0)) as usize;
                        for &j in &self.items[self.start[c] as usize..self.start[c + 1] as usize] {
                            f(j);
                        }
                    }
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
/// On the periodic axes of `per` the pair vector is the minimum image.
pub fn find_pairs(
    kind: GridKind,
    per: &Periodic,
    x: &[Vector3<f64>],
    r: &[f64],
    margin: f64,
) -> (Vec<(u32, u32)>, GridStats) {
    let n = x.len();
    if n < 2 {
        return (Vec::new(), GridStats::default());
    }
    let xw: Vec<Vector3<f64>> = x.iter().map(|p| per.wrap(*p)).collect();
    let mut lo = xw[0];
    let mut hi = xw[0];
    let (mut r_min, mut r_max) = (f64::INFINITY, 0.0f64);
    for (p, &ri) in xw.iter().zip(r) {
        lo = lo.inf(p);
        hi = hi.sup(p);
        r_min = r_min.min(ri);
        r_max = r_max.max(ri);
    }
    let periodic = [0, 1, 2].map(|k| per.len[k].is_some());
    for k in 0..3 {
        if let Some(l) = per.len[k] {
            lo[k] = per.lo[k];
            hi[k] = per.lo[k] + l;
        }
    }
    // Non-finite positions (a blown-up run) must not hang the grid: they find no pairs.
    let ext = (hi - lo).map(|e| if e.is_finite() { e } else { 0.0 });
    // Positions relative to the grid origin, in the periodic cell.
    let xr: Vec<Vector3<f64>> = xw.iter().map(|p| p - lo).collect();
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
        .map(|l| Level::build(sides[l], &ext, periodic, &xr, &members[l], cap))
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
                let p = xr[i];
                let ri = r[i];
                for (k, level) in levels.iter().enumerate().skip(l) {
                    if level.items.is_empty() {
                        continue;
                    }
                    let e = if k == l {
                        Vector3::from(level.cell)
                    } else {
                        Vector3::repeat(ri + level.r_max + margin)
                    };
                    level.visit(&(p - e), &(p + e), |j| {
                        if k == l && j as usize <= i {
                            return;
                        }
                        tests += 1;
                        let s = ri + r[j as usize] + margin;
                        if per.delta(x[j as usize] - x[i]).norm_squared() < s * s {
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

/// Brute-force reference: all pairs by O(N²) search, minimum image on the periodic axes
/// (tests).
pub fn find_pairs_brute(
    per: &Periodic,
    x: &[Vector3<f64>],
    r: &[f64],
    margin: f64,
) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for i in 0..x.len() {
        for j in i + 1..x.len() {
            let s = r[i] + r[j] + margin;
            if per.delta(x[j] - x[i]).norm_squared() < s * s {
                out.push((i as u32, j as u32));
            }
        }
    }
    out
}
