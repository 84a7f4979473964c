//! Disc filling by the "minimum residual area" rule of Ye & Xu (2010): discs are added one at a
//! time, each chosen to remove as much still-uncovered grain area as it can, until the area cover
//! `A_r = 1 − A_unfilled/A_p` reaches the target or the disc budget is spent.
//!
//! How a disc is chosen:
//! 1. The grain is rasterised once (`raster` cells along its longer side) and the uncovered cells
//!    are tracked. The exact Euclidean distance transform of the uncovered region (Felzenszwalb &
//!    Huttenlocher, "Distance transforms of sampled functions", Theory of Computing 8, 2012) gives,
//!    at every cell, the radius of the largest disc of uncovered area centred there; its local
//!    maxima are the candidate centres (the medial axis of what is left).
//! 2. Each candidate gets the largest radius that keeps the disc inside the outline, from the
//!    *exact* distance to the polygon's boundary (so discs may overlap earlier discs, as in ORC,
//!    but never leave the grain), clamped to `[r_min, r_max]`; candidates that cannot hold
//!    `r_min` are dropped.
//! 3. The candidate covering the most uncovered cells wins.
//!
//! The raster only steers the choice; the cover that is reported and that stops the loop is
//! computed exactly from the discs ([`crate::cover::union_area`]). Because every disc lies inside
//! the outline, the union of the discs *is* the covered part of the grain.

use crate::cover::{union_area, union_area_error_bound, Circle};
use crate::geom::{point_in_polygon, EdgeGrid};

/// Parameters of the filler (lengths in metres, in the grain's centroid frame).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct FillParams {
    /// Target area cover `A_r` (Ye & Xu 2010 use 0.95).
    pub cover: f64,
    /// Smallest disc radius allowed (m).
    pub r_min: f64,
    /// Largest disc radius allowed (m).
    pub r_max: f64,
    /// Largest number of discs (the paper caps cutting clumps at 9).
    pub max_discs: usize,
}

/// Why the filler stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum StopReason {
    /// The cover target was reached.
    CoverReached,
    /// `max_discs` discs were placed first.
    MaxDiscs,
    /// No place is left that can hold a disc of radius `r_min`.
    NoRoom,
    /// A lattice template: the nodes are every lattice point whose disc fits; there is no cover
    /// target (`crate::lattice`).
    Lattice,
}

/// The discs and the cover they reach.
#[derive(Debug, Clone)]
pub struct Fill {
    pub discs: Vec<Circle>,
    /// Exact area cover `A_r` (union of discs over grain area).
    pub cover: f64,
    /// Bound on the floating-point error of `cover`.
    pub cover_bound: f64,
    pub stop: StopReason,
}

/// Raster state of one grain: which cells are inside and which are still uncovered.
pub struct Filler<'a> {
    poly: &'a [[f64; 2]],
    grid: EdgeGrid<'a>,
    area: f64,
    x0: f64,
    y0: f64,
    h: f64,
    nx: usize,
    ny: usize,
    inside: Vec<bool>,
    uncovered: Vec<bool>,
    /// Scratch buffers for the distance transform.
    dist2: Vec<f64>,
    col: Vec<f64>,
    col2: Vec<f64>,
    v: Vec<usize>,
    z: Vec<f64>,
    pub discs: Vec<Circle>,
}

impl<'a> Filler<'a> {
    /// Rasterises `poly` (centroid frame, counter-clockwise) of area `area`.
    pub fn new(poly: &'a [[f64; 2]], area: f64, raster: usize) -> Self {
        let ([x0, y0], [x1, y1]) = crate::geom::bbox(poly);
        let h = (x1 - x0).max(y1 - y0) / raster.max(4) as f64;
        let nx = ((x1 - x0) / h).ceil() as usize + 1;
        let ny = ((y1 - y0) / h).ceil() as usize + 1;
        let mut inside = vec![false; nx * ny];
        // Scanline fill: crossings of each row's centre line with the edges.
        let mut xs = Vec::new();
        for iy in 0..ny {
            let yc = y0 + (iy as f64 + 0.5) * h;
            xs.clear();
            let n = poly.len();
            for i in 0..n {
                let (a, b) = (poly[i], poly[(i + 1) % n]);
                if (a[1] > yc) != (b[1] > yc) {
                    xs.push(a[0] + (yc - a[1]) * (b[0] - a[0]) / (b[1] - a[1]));
                }
            }
            xs.sort_by(f64::total_cmp);
            for pair in xs.chunks_exact(2) {
                let i0 = ((pair[0] - x0) / h - 0.5).ceil().max(0.0) as usize;
                let i1 = ((pair[1] - x0) / h - 0.5).floor();
                if i1 < 0.0 {
                    continue;
                }
                for ix in i0..=(i1 as usize).min(nx - 1) {
                    inside[iy * nx + ix] = true;
                }
            }
        }
        let m = nx.max(ny);
        Filler {
            poly,
            grid: EdgeGrid::new(poly),
            area,
            x0,
            y0,
            h,
            nx,
            ny,
            uncovered: inside.clone(),
            inside,
            dist2: vec![0.0; nx * ny],
            col: vec![0.0; m],
            col2: vec![0.0; m],
            v: vec![0; m],
            z: vec![0.0; m + 1],
            discs: Vec::new(),
        }
    }

    fn centre(&self, ix: usize, iy: usize) -> [f64; 2] {
        [
            self.x0 + (ix as f64 + 0.5) * self.h,
            self.y0 + (iy as f64 + 0.5) * self.h,
        ]
    }

    /// Exact distance from `p` to the outline (the largest disc centred at `p` that stays inside).
    pub fn room(&self, p: [f64; 2]) -> f64 {
        self.grid.distance(p)
    }

    /// Squared distance transform (in cells²) of the uncovered cells to the nearest other cell.
    fn distance_transform(&mut self) {
        let (nx, ny) = (self.nx, self.ny);
        const INF: f64 = 1e20;
        for i in 0..nx * ny {
            self.dist2[i] = if self.uncovered[i] { INF } else { 0.0 };
        }
        // Rows, then columns; the grid border counts as an obstacle (cells outside are outside).
        for iy in 0..ny {
            let row = &self.dist2[iy * nx..(iy + 1) * nx];
            edt_1d(row, &mut self.col[..nx], &mut self.v, &mut self.z);
            for ix in 0..nx {
                let b = (ix + 1).min(nx - ix) as f64;
                self.dist2[iy * nx + ix] = self.col[ix].min(b * b);
            }
        }
        for ix in 0..nx {
            for iy in 0..ny {
                self.col2[iy] = self.dist2[iy * nx + ix];
            }
            edt_1d(
                &self.col2[..ny],
                &mut self.col[..ny],
                &mut self.v,
                &mut self.z,
            );
            for iy in 0..ny {
                let b = (iy + 1).min(ny - iy) as f64;
                self.dist2[iy * nx + ix] = self.col[iy].min(b * b);
            }
        }
    }

    /// Uncovered cells whose centres lie inside the disc `(c, r)`.
    fn gain(&self, c: [f64; 2], r: f64) -> usize {
        let (fx, fy) = (
            (c[0] - self.x0) / self.h - 0.5,
            (c[1] - self.y0) / self.h - 0.5,
        );
        let rc = r / self.h;
        let iy0 = (fy - rc).ceil().max(0.0) as usize;
        let iy1 = ((fy + rc).floor().max(-1.0) as isize).min(self.ny as isize - 1);
        let mut count = 0;
        for iy in iy0..=iy1.max(0) as usize {
            if iy as isize > iy1 {
                break;
            }
            let dy = iy as f64 - fy;
            let half = (rc * rc - dy * dy).max(0.0).sqrt();
            let ix0 = (fx - half).ceil().max(0.0) as usize;
            let ix1 = (fx + half).floor();
            if ix1 < 0.0 {
                continue;
            }
            let row = &self.uncovered[iy * self.nx..(iy + 1) * self.nx];
            for &u in &row[ix0.min(self.nx)..=(ix1 as usize).min(self.nx - 1)] {
                count += u as usize;
            }
        }
        count
    }

    /// Adds a disc and marks the cells it covers.
    pub fn place(&mut self, d: Circle) {
        let (fx, fy) = (
            (d.x - self.x0) / self.h - 0.5,
            (d.y - self.y0) / self.h - 0.5,
        );
        let rc = d.r / self.h;
        for iy in 0..self.ny {
            let dy = iy as f64 - fy;
            if dy.abs() > rc {
                continue;
            }
            let half = (rc * rc - dy * dy).sqrt();
            let ix0 = (fx - half).ceil().max(0.0) as usize;
            let ix1 = (fx + half).floor();
            if ix1 < 0.0 {
                continue;
            }
            for ix in ix0..=(ix1 as usize).min(self.nx - 1) {
                self.uncovered[iy * self.nx + ix] = false;
            }
        }
        self.discs.push(d);
    }

    /// The next disc by the minimum-residual-area rule, or `None` if no uncovered place can hold
    /// a disc of radius `r_min`.
    pub fn next_disc(&mut self, r_min: f64, r_max: f64) -> Option<Circle> {
        self.distance_transform();
        let (nx, ny) = (self.nx, self.ny);
        // Local maxima of the distance transform over the uncovered cells (8-neighbourhood;
        // ties go to the lower index so a plateau keeps exactly one representative). Cells off
        // the grid count as 0, which the distance transform never exceeds on an uncovered cell.
        let mut cand: Vec<(f64, usize)> = Vec::new();
        let d2 = &self.dist2;
        let at = |x: isize, y: isize| -> f64 {
            if x < 0 || y < 0 || x >= nx as isize || y >= ny as isize {
                0.0
            } else {
                d2[y as usize * nx + x as usize]
            }
        };
        for iy in 0..ny {
            for ix in 0..nx {
                let i = iy * nx + ix;
                let d = d2[i];
                if d <= 0.0 {
                    continue;
                }
                let (x, y) = (ix as isize, iy as isize);
                // Neighbours after i in index order must be strictly lower, before i not higher.
                let later = [
                    at(x + 1, y),
                    at(x - 1, y + 1),
                    at(x, y + 1),
                    at(x + 1, y + 1),
                ];
                if later.iter().any(|&v| v >= d) {
                    continue;
                }
                let earlier = [
                    at(x - 1, y),
                    at(x - 1, y - 1),
                    at(x, y - 1),
                    at(x + 1, y - 1),
                ];
                if earlier.iter().any(|&v| v > d) {
                    continue;
                }
                cand.push((d, i));
            }
        }
        cand.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
        let mut best: Option<(usize, Circle)> = None;
        let mut tried = 0;
        for &(_, i) in &cand {
            if tried >= 8 {
                break;
            }
            let c = self.centre(i % nx, i / nx);
            let room = self.room(c);
            if room < r_min || !point_in_polygon(c, self.poly) {
                continue;
            }
            tried += 1;
            let r = room.min(r_max);
            let g = self.gain(c, r);
            if g > 0 && best.is_none_or(|(bg, _)| g > bg) {
                best = Some((
                    g,
                    Circle {
                        x: c[0],
                        y: c[1],
                        r,
                    },
                ));
            }
        }
        best.map(|(_, c)| self.refine(c, r_min, r_max))
    }

    /// Local pattern search around a chosen centre (steps of h/2 down to h/64). The first disc
    /// maximises its radius (the whole grain is uncovered, so the largest disc removes the most
    /// area: this converges to the largest inscribed circle); later discs maximise the uncovered
    /// cells they cover, with the radius as tie-breaker.
    fn refine(&self, c: Circle, r_min: f64, r_max: f64) -> Circle {
        let first = self.discs.is_empty();
        let score = |p: [f64; 2]| -> Option<(f64, f64)> {
            let room = self.room(p);
            if room < r_min || !point_in_polygon(p, self.poly) {
                return None;
            }
            let r = room.min(r_max);
            let s = if first {
                r
            } else {
                self.gain(p, r) as f64 + 1e-6 * r / self.h
            };
            Some((s, r))
        };
        let (mut best, mut r) = match score([c.x, c.y]) {
            Some(v) => v,
            None => return c,
        };
        let mut at = [c.x, c.y];
        let levels = if first { 12 } else { 2 };
        let mut step = 0.5 * self.h;
        for _ in 0..levels {
            loop {
                let mut moved = false;
                for (dx, dy) in [
                    (1.0, 0.0),
                    (-1.0, 0.0),
                    (0.0, 1.0),
                    (0.0, -1.0),
                    (1.0, 1.0),
                    (1.0, -1.0),
                    (-1.0, 1.0),
                    (-1.0, -1.0),
                ] {
                    let p = [at[0] + dx * step, at[1] + dy * step];
                    if let Some((s, rr)) = score(p) {
                        if s > best {
                            (best, r, at, moved) = (s, rr, p, true);
                        }
                    }
                }
                if !moved {
                    break;
                }
            }
            step *= 0.5;
        }
        Circle {
            x: at[0],
            y: at[1],
            r,
        }
    }

    /// A disc that helps the mass fit when the discs cannot reach the grain's inertia or
    /// centroid. With `k2` the grain's squared radius of gyration (J/A), a disc at distance d
    /// with radius r can raise the clump's inertia only if `s = r²/2 + d² > k2`; positive
    /// masses need such discs on all sides of the centroid. So the repair disc goes near the
    /// boundary, as far from the centroid as it can (radius `r_min`, or a little more where there
    /// is room), on the side opposite the discs that already have `s > k2` (opposite the
    /// discs' uniform-density centroid when none has).
    pub fn repair_disc(&self, r_min: f64, r_max: f64, k2: f64) -> Option<Circle> {
        let (u, high) = self.repair_side(k2);
        // Where the outline is at least 1.5 r_min away (a bound from the edge grid, no edge
        // visited) the radius does not depend on the exact room: r = max(r_min, min(r_max,
        // 1.5 r_min)). Only cells near the boundary need the exact distance.
        let r_deep = r_min.max(r_max.min(r_min * 1.5));
        let mut best: Option<(f64, Circle)> = None;
        for iy in 0..self.ny {
            for ix in 0..self.nx {
                if !self.inside[iy * self.nx + ix] {
                    continue;
                }
                let c = self.centre(ix, iy);
                let r = if self.grid.lower_bound(c) >= r_min * 1.5 {
                    r_deep
                } else {
                    let room = self.room(c);
                    if room < r_min {
                        continue;
                    }
                    r_min.max(room.min(r_max).min(r_min * 1.5))
                };
                let d2 = c[0] * c[0] + c[1] * c[1];
                let cosang = if d2 > 0.0 {
                    (u[0] * c[0] + u[1] * c[1]) / d2.sqrt()
                } else {
                    0.0
                };
                let score = (0.5 * r * r + d2) * (1.0 + cosang);
                if !self.repair_clashes(&high, c, r) && best.is_none_or(|(s, _)| score > s) {
                    best = Some((
                        score,
                        Circle {
                            x: c[0],
                            y: c[1],
                            r,
                        },
                    ));
                }
            }
        }
        best.map(|(_, c)| c)
    }

    /// A repair disc of radius `r_min` on the ring `s = r_min²/2 + d² = s_ring` around the
    /// centroid, on the side [`Filler::repair_disc`] would choose (a point of the ring in the
    /// direction of an inside raster cell beyond it; the direction most opposite the pull wins).
    ///
    /// [`Filler::repair_disc`] puts repair discs as far out as it can, where a small mass
    /// moves the inertia most. When the fill discs nearly have the grain's moments already (a
    /// dense circle: the inscribed disc of a regular n-gon lacks only
    /// `ΔJ/J = (1 − cos(2π/n))/6 ≈ π²/(3n²)` of its inertia), those far discs would need masses
    /// below their floor `mass_floor·m0`. On the ring `s_ring = k2 + Δ` a repair disc that
    /// carries a deficit `D` of `s` needs the mass `D/Δ`, so a `Δ` chosen from the deficit
    /// gives it a mass near its prior.
    pub fn ring_repair_disc(&self, r_min: f64, k2: f64, s_ring: f64) -> Option<Circle> {
        let (u, high) = self.repair_side(k2);
        let d_ring2 = s_ring - 0.5 * r_min * r_min;
        if d_ring2.is_nan() || d_ring2 <= 0.0 {
            return None;
        }
        let d_ring = d_ring2.sqrt();
        // Candidates: inside cells beyond the ring, moved onto it along their direction from
        // the centroid; best first (stable, so ties keep the scan order).
        let mut cand: Vec<(f64, [f64; 2])> = Vec::new();
        for iy in 0..self.ny {
            for ix in 0..self.nx {
                if !self.inside[iy * self.nx + ix] {
                    continue;
                }
                let c = self.centre(ix, iy);
                let d = c[0].hypot(c[1]);
                if d <= d_ring {
                    continue;
                }
                let p = [c[0] * (d_ring / d), c[1] * (d_ring / d)];
                let cosang = (u[0] * c[0] + u[1] * c[1]) / d;
                cand.push((1.0 + cosang, p));
            }
        }
        cand.sort_by(|a, b| b.0.total_cmp(&a.0));
        cand.into_iter()
            .map(|(_, p)| p)
            .find(|&p| {
                (self.grid.lower_bound(p) >= r_min || self.room(p) >= r_min)
                    && point_in_polygon(p, self.poly)
                    && !self.repair_clashes(&high, p, r_min)
            })
            .map(|p| Circle {
                x: p[0],
                y: p[1],
                r: r_min,
            })
    }

    /// The side a repair disc goes to (a unit vector from the centroid; zero if the discs give
    /// no side) and the discs that already have `s > k2`.
    fn repair_side(&self, k2: f64) -> ([f64; 2], Vec<&Circle>) {
        let s_of = |d: &Circle| 0.5 * d.r * d.r + d.x * d.x + d.y * d.y;
        let high: Vec<&Circle> = self.discs.iter().filter(|d| s_of(d) > k2).collect();
        let pull = if high.is_empty() {
            let w: f64 = self.discs.iter().map(|d| d.r * d.r).sum();
            [
                self.discs.iter().map(|d| d.r * d.r * d.x).sum::<f64>() / w,
                self.discs.iter().map(|d| d.r * d.r * d.y).sum::<f64>() / w,
            ]
        } else {
            let k = high.len() as f64;
            [
                high.iter().map(|d| d.x).sum::<f64>() / k,
                high.iter().map(|d| d.y).sum::<f64>() / k,
            ]
        };
        let pn = pull[0].hypot(pull[1]);
        let u = if pn > 0.0 {
            [-pull[0] / pn, -pull[1] / pn]
        } else {
            [0.0, 0.0]
        };
        (u, high)
    }

    /// Whether a repair disc `(c, r)` would sit on top of a disc with `s > k2` (`high`), or
    /// (nearly) concentric with any disc: fill discs sit on the same raster centres, and two
    /// members with one centre have no bond direction (a bonded clump rejects them).
    fn repair_clashes(&self, high: &[&Circle], c: [f64; 2], r: f64) -> bool {
        high.iter()
            .any(|o| (o.x - c[0]).hypot(o.y - c[1]) < o.r + r)
            || self
                .discs
                .iter()
                .any(|o| (o.x - c[0]).hypot(o.y - c[1]) < 0.5 * o.r.min(r))
    }

    /// Exact cover of the current discs and its rounding bound.
    pub fn cover(&self) -> (f64, f64) {
        let u = union_area(&self.discs);
        let ext = self
            .discs
            .iter()
            .map(|d| d.x.hypot(d.y) + d.r)
            .fold(0.0, f64::max);
        (
            u.area / self.area,
            union_area_error_bound(self.discs.len(), ext) / self.area,
        )
    }

    /// Runs the minimum-residual-area fill to the target.
    pub fn run(&mut self, p: &FillParams) -> Fill {
        let mut stop = StopReason::NoRoom;
        let mut cover = self.cover().0;
        if cover >= p.cover {
            stop = StopReason::CoverReached;
        }
        while cover < p.cover {
            if self.discs.len() >= p.max_discs {
                stop = StopReason::MaxDiscs;
                break;
            }
            match self.next_disc(p.r_min, p.r_max) {
                Some(d) => self.place(d),
                None => {
                    stop = StopReason::NoRoom;
                    break;
                }
            }
            cover = self.cover().0;
            if cover >= p.cover {
                stop = StopReason::CoverReached;
            }
        }
        let (cover, cover_bound) = self.cover();
        Fill {
            discs: self.discs.clone(),
            cover,
            cover_bound,
            stop,
        }
    }
}

/// One-dimensional squared Euclidean distance transform (Felzenszwalb & Huttenlocher 2012,
/// algorithm DT(f)): `d(q) = min_p ((q − p)² + f(p))`, written to `d`. `v` and `z` are scratch
/// of length `n` and `n + 1`.
fn edt_1d(f: &[f64], d: &mut [f64], v: &mut [usize], z: &mut [f64]) {
    let n = f.len();
    if n == 0 {
        return;
    }
    let mut k = 0usize;
    v[0] = 0;
    z[0] = f64::NEG_INFINITY;
    z[1] = f64::INFINITY;
    for q in 1..n {
        let mut s;
        loop {
            let p = v[k];
            s = ((f[q] + (q * q) as f64) - (f[p] + (p * p) as f64)) / (2.0 * (q - p) as f64);
            if s <= z[k] && k > 0 {
                k -= 1;
            } else {
                break;
            }
        }
        if s <= z[k] {
            // k == 0: the new parabola is lower everywhere the old one was the envelope.
            v[0] = q;
            z[0] = f64::NEG_INFINITY;
            z[1] = f64::INFINITY;
        } else {
            k += 1;
            v[k] = q;
            z[k] = s;
            z[k + 1] = f64::INFINITY;
        }
    }
    let mut k = 0;
    for (q, dq) in d.iter_mut().enumerate().take(n) {
        while z[k + 1] < q as f64 {
            k += 1;
        }
        let p = v[k];
        *dq = (q as f64 - p as f64).powi(2) + f[p];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edt_1d_matches_brute_force() {
        let f = [1e20, 0.0, 1e20, 1e20, 4.0, 1e20, 1e20, 1e20, 0.0, 1e20, 2.0];
        let mut d = [0.0; 11];
        let (mut v, mut z) = ([0usize; 11], [0.0; 12]);
        edt_1d(&f, &mut d, &mut v, &mut z);
        for (q, &dq) in d.iter().enumerate() {
            let brute = (0..11)
                .map(|p| (q as f64 - p as f64).powi(2) + f[p])
                .fold(f64::INFINITY, f64::min);
            assert_eq!(dq, brute, "q = {q}");
        }
    }

    fn square(s: f64) -> Vec<[f64; 2]> {
        vec![[-s, -s], [s, -s], [s, s], [-s, s]]
    }

    #[test]
    fn square_first_disc_is_the_inscribed_circle() {
        let sq = square(1.0);
        let mut f = Filler::new(&sq, 4.0, 64);
        let d = f.next_disc(0.01, 10.0).unwrap();
        assert!(d.x.abs() < 0.02 && d.y.abs() < 0.02, "{d:?}");
        assert!((d.r - 1.0).abs() < 0.02);
    }

    #[test]
    fn square_reaches_the_cover_with_discs_inside() {
        let sq = square(1.0);
        let mut f = Filler::new(&sq, 4.0, 64);
        let p = FillParams {
            cover: 0.95,
            r_min: 0.02,
            r_max: 10.0,
            max_discs: 100,
        };
        let fill = f.run(&p);
        assert_eq!(fill.stop, StopReason::CoverReached);
        assert!(fill.cover >= 0.95);
        for d in &fill.discs {
            assert!(d.x.abs() + d.r <= 1.0 + 1e-12 && d.y.abs() + d.r <= 1.0 + 1e-12);
        }
    }

    #[test]
    fn max_discs_stops_early_and_reports_cover() {
        let sq = square(1.0);
        let mut f = Filler::new(&sq, 4.0, 64);
        let p = FillParams {
            cover: 0.95,
            r_min: 0.02,
            r_max: 10.0,
            max_discs: 1,
        };
        let fill = f.run(&p);
        assert_eq!(fill.stop, StopReason::MaxDiscs);
        assert!(
            (fill.cover - std::f64::consts::PI / 4.0).abs() < 1e-6,
            "{fill:?}"
        );
    }
}
