//! Grain recognition for the ORC and improved-ORC specimens: grain seeds with a target mean
//! grain size, their Voronoi tessellation of the specimen box, and the assignment of discs to
//! grains.
//!
//! The papers (S0, Ye & Xu 2010) recognise grains automatically from micrographs; no micrograph
//! exists for the 20 × 10 mm Si3N4 specimen, so grains are synthetic: `n = round(A / (π d²/4))`
//! seeds (d the target mean equivalent grain diameter, A the box area) drawn uniformly in the box
//! with a hard-core distance d/2 between seeds (random sequential addition, so no grain is a
//! sliver), and each grain is the seed's Voronoi cell clipped to the box. A disc belongs to the
//! grain whose seed is nearest its centre, i.e. whose cell contains its centre. The cells tile the
//! box exactly, so the ORC grains (discs grouped by cell) and the improved-ORC grains (cells
//! filled with clumpgen templates) are the same grains.

use super::rng::Rng;
use super::SpecimenError;

/// Seeds and cells of a grain tessellation of the box `[0, w] × [0, h]`.
#[derive(Clone, Debug, PartialEq)]
pub struct Grains {
    pub seeds: Vec<[f64; 2]>,
    /// Voronoi cell of each seed clipped to the box: convex, counter-clockwise.
    pub cells: Vec<Vec<[f64; 2]>>,
    pub width: f64,
    pub height: f64,
}

/// Draw seeds for mean equivalent grain diameter `d` (m) in a `w × h` box.
pub fn draw_seeds(rng: &mut Rng, w: f64, h: f64, d: f64) -> Result<Vec<[f64; 2]>, SpecimenError> {
    if !(d > 0.0 && d.is_finite() && w > 0.0 && h > 0.0) {
        return Err(SpecimenError::Param(format!(
            "grain size {d} m must be positive"
        )));
    }
    let n = ((w * h) / (std::f64::consts::PI * 0.25 * d * d))
        .round()
        .max(1.0) as usize;
    if n > 10_000_000 {
        return Err(SpecimenError::Param(format!(
            "grain size {d} m gives {n} grains; too many"
        )));
    }
    let mut hard = 0.5 * d;
    let mut seeds: Vec<[f64; 2]> = Vec::with_capacity(n);
    let mut grid = PointGrid::new(w, h, hard.max(1e-300));
    let mut fails = 0usize;
    while seeds.len() < n {
        let p = [rng.range(0.0, w), rng.range(0.0, h)];
        if grid.nearest_within(&seeds, p, hard).is_none() {
            grid.insert(seeds.len(), p);
            seeds.push(p);
            fails = 0;
        } else {
            fails += 1;
            if fails > 10_000 {
                // Saturated (cannot happen for hard = d/2, which covers a quarter of the box,
                // below the RSA limit 0.547); relax the hard core and go on.
                hard *= 0.8;
                fails = 0;
            }
        }
    }
    Ok(seeds)
}

/// Voronoi cells of `seeds` clipped to `[0, w] × [0, h]`.
pub fn tessellate(seeds: &[[f64; 2]], w: f64, h: f64) -> Grains {
    let n = seeds.len();
    let mut by_dist: Vec<usize> = (0..n).collect();
    let cells = (0..n)
        .map(|i| {
            let s = seeds[i];
            let mut cell = vec![[0.0, 0.0], [w, 0.0], [w, h], [0.0, h]];
            let d2 = |j: usize| {
                let (dx, dy) = (seeds[j][0] - s[0], seeds[j][1] - s[1]);
                dx * dx + dy * dy
            };
            by_dist.sort_by(|&a, &b| d2(a).total_cmp(&d2(b)).then(a.cmp(&b)));
            for &j in &by_dist {
                if j == i {
                    continue;
                }
                // A seed farther than twice the cell's farthest vertex cannot cut the cell.
                let reach = cell
                    .iter()
                    .map(|p| (p[0] - s[0]).powi(2) + (p[1] - s[1]).powi(2))
                    .fold(0.0, f64::max);
                if d2(j) > 4.0 * reach {
                    break;
                }
                let t = seeds[j];
                // Half-plane of points nearer s than t: (t − s)·p ≤ (|t|² − |s|²)/2.
                let a = [t[0] - s[0], t[1] - s[1]];
                let c = 0.5 * ((t[0] * t[0] + t[1] * t[1]) - (s[0] * s[0] + s[1] * s[1]));
                cell = clip(&cell, a, c);
                if cell.len() < 3 {
                    break;
                }
            }
            cell
        })
        .collect();
    Grains {
        seeds: seeds.to_vec(),
        cells,
        width: w,
        height: h,
    }
}

/// Sutherland–Hodgman clip of a convex polygon by the half-plane a·p ≤ c.
fn clip(poly: &[[f64; 2]], a: [f64; 2], c: f64) -> Vec<[f64; 2]> {
    let f = |p: &[f64; 2]| a[0] * p[0] + a[1] * p[1] - c;
    let mut out = Vec::with_capacity(poly.len() + 1);
    for k in 0..poly.len() {
        let (p, q) = (poly[k], poly[(k + 1) % poly.len()]);
        let (fp, fq) = (f(&p), f(&q));
        if fp <= 0.0 {
            out.push(p);
        }
        if (fp < 0.0 && fq > 0.0) || (fp > 0.0 && fq < 0.0) {
            let t = fp / (fp - fq);
            out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
        }
    }
    out
}

/// Index of the nearest seed to each point (ties: lowest index).
pub fn assign(seeds: &[[f64; 2]], w: f64, h: f64, points: &[[f64; 2]]) -> Vec<usize> {
    if seeds.is_empty() {
        return vec![0; points.len()];
    }
    let cell = (w * h / seeds.len() as f64).sqrt().max(1e-300);
    let mut grid = PointGrid::new(w, h, cell);
    for (k, &s) in seeds.iter().enumerate() {
        grid.insert(k, s);
    }
    points.iter().map(|&p| grid.nearest(seeds, p)).collect()
}

/// Signed area (positive for counter-clockwise).
pub fn polygon_area(poly: &[[f64; 2]]) -> f64 {
    let n = poly.len();
    0.5 * (0..n)
        .map(|k| {
            let (p, q) = (poly[k], poly[(k + 1) % n]);
            p[0] * q[1] - q[0] * p[1]
        })
        .sum::<f64>()
}

/// Uniform bucket grid of points over a box (points may lie slightly outside; they are
/// clamped into the edge cells).
struct PointGrid {
    cell: f64,
    nx: usize,
    ny: usize,
    buckets: Vec<Vec<usize>>,
}

impl PointGrid {
    fn new(w: f64, h: f64, cell: f64) -> PointGrid {
        let nx = ((w / cell).ceil() as usize).clamp(1, 4096);
        let ny = ((h / cell).ceil() as usize).clamp(1, 4096);
        let cell = (w / nx as f64).max(h / ny as f64);
        PointGrid {
            cell,
            nx,
            ny,
            buckets: vec![Vec::new(); nx * ny],
        }
    }

    fn index(&self, p: [f64; 2]) -> (i64, i64) {
        let ix = ((p[0] / self.cell).floor() as i64).clamp(0, self.nx as i64 - 1);
        let iy = ((p[1] / self.cell).floor() as i64).clamp(0, self.ny as i64 - 1);
        (ix, iy)
    }

    fn insert(&mut self, k: usize, p: [f64; 2]) {
        let (ix, iy) = self.index(p);
        self.buckets[iy as usize * self.nx + ix as usize].push(k);
    }

    /// Any point within `r` of `p`.
    fn nearest_within(&self, pts: &[[f64; 2]], p: [f64; 2], r: f64) -> Option<usize> {
        let (ix, iy) = self.index(p);
        let reach = (r / self.cell).ceil() as i64;
        for y in (iy - reach).max(0)..=(iy + reach).min(self.ny as i64 - 1) {
            for x in (ix - reach).max(0)..=(ix + reach).min(self.nx as i64 - 1) {
                for &k in &self.buckets[y as usize * self.nx + x as usize] {
                    let (dx, dy) = (pts[k][0] - p[0], pts[k][1] - p[1]);
                    if dx * dx + dy * dy < r * r {
                        return Some(k);
                    }
                }
            }
        }
        None
    }

    /// Nearest point to `p` (rings of cells until no closer point can exist).
    fn nearest(&self, pts: &[[f64; 2]], p: [f64; 2]) -> usize {
        let (ix, iy) = self.index(p);
        let mut best = (f64::INFINITY, usize::MAX);
        let max_ring = self.nx.max(self.ny) as i64;
        for ring in 0..=max_ring {
            for y in iy - ring..=iy + ring {
                for x in ix - ring..=ix + ring {
                    let on_ring = (y - iy).abs() == ring || (x - ix).abs() == ring;
                    if !on_ring || x < 0 || y < 0 || x >= self.nx as i64 || y >= self.ny as i64 {
                        continue;
                    }
                    for &k in &self.buckets[y as usize * self.nx + x as usize] {
                        let (dx, dy) = (pts[k][0] - p[0], pts[k][1] - p[1]);
                        let d2 = dx * dx + dy * dy;
                        if d2 < best.0 || (d2 == best.0 && k < best.1) {
                            best = (d2, k);
                        }
                    }
                }
            }
            // Points outside the searched square are at least `ring * cell` away (p lies in
            // the centre cell, possibly clamped: then only farther).
            let safe = ring as f64 * self.cell;
            if best.1 != usize::MAX && best.0 <= safe * safe {
                break;
            }
        }
        best.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_tile_the_box_and_contain_their_seed() {
        let mut rng = Rng::new(3);
        let (w, h, d) = (4e-3, 2e-3, 0.5e-3);
        let seeds = draw_seeds(&mut rng, w, h, d).unwrap();
        let n_expect = (w * h / (std::f64::consts::PI * 0.25 * d * d)).round() as usize;
        assert_eq!(seeds.len(), n_expect);
        let g = tessellate(&seeds, w, h);
        let total: f64 = g.cells.iter().map(|c| polygon_area(c)).sum();
        assert!((total - w * h).abs() < 1e-9 * w * h, "{total}");
        for (c, s) in g.cells.iter().zip(&seeds) {
            assert!(polygon_area(c) > 0.0);
            // The seed is inside its (convex, CCW) cell.
            for k in 0..c.len() {
                let (p, q) = (c[k], c[(k + 1) % c.len()]);
                let cross = (q[0] - p[0]) * (s[1] - p[1]) - (q[1] - p[1]) * (s[0] - p[0]);
                assert!(cross >= -1e-18);
            }
        }
        // Nearest-seed assignment agrees with brute force.
        let pts: Vec<[f64; 2]> = (0..500)
            .map(|_| [rng.range(0.0, w), rng.range(0.0, h)])
            .collect();
        let a = assign(&seeds, w, h, &pts);
        for (p, &k) in pts.iter().zip(&a) {
            let d2 = |s: &[f64; 2]| (s[0] - p[0]).powi(2) + (s[1] - p[1]).powi(2);
            let best = seeds.iter().map(d2).fold(f64::INFINITY, f64::min);
            assert_eq!(d2(&seeds[k]), best);
        }
    }
}
