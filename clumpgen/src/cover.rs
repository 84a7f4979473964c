//! Exact area of a union of discs, and the arcs that bound it.
//!
//! The union's boundary is made of circular arcs: the parts of each circle not inside any other
//! disc. By Green's theorem the enclosed area is `½∮(x dy − y dx)`; over an arc of circle
//! (centre `(cx, cy)`, radius `r`) from angle θ₁ to θ₂ (counter-clockwise) this integrates to
//!
//! `½ [ r²(θ₂ − θ₁) + r·cx·(sin θ₂ − sin θ₁) − r·cy·(cos θ₂ − cos θ₁) ]`
//!
//! (see e.g. the "area of union of circles" method in de Berg et al., *Computational Geometry*, or
//! any text on Green's theorem). Summing over all uncovered arcs gives the union area exactly, up to
//! floating-point rounding. Since the filler keeps every disc inside the outline, this union area is
//! also the covered part of the grain, so the cover `A_r = 1 − A_unfilled/A_p` of Ye & Xu (2010)
//! is `union / A_p` with no raster error.

use std::f64::consts::TAU;

/// A disc: centre and radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Circle {
    pub x: f64,
    pub y: f64,
    pub r: f64,
}

/// One uncovered arc of circle `disc`, from angle `a0` to `a1` (counter-clockwise, `a1 > a0`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Arc {
    pub disc: usize,
    pub a0: f64,
    pub a1: f64,
}

/// Union area and its boundary arcs.
#[derive(Debug, Clone)]
pub struct Union {
    pub area: f64,
    pub arcs: Vec<Arc>,
}

/// True when disc `i` lies inside disc `j` (ties between identical discs go to the lower index,
/// so exactly one of two identical discs survives).
fn contained(i: usize, j: usize, c: &[Circle]) -> bool {
    let (a, b) = (c[i], c[j]);
    let d = (a.x - b.x).hypot(a.y - b.y);
    if a == b {
        return j < i;
    }
    d + a.r <= b.r
}

/// Exact area of the union of `discs` and the arcs of its boundary.
///
/// ```
/// use clumpgen::cover::{union_area, Circle};
/// // Two unit discs whose centres are one radius apart: area 2π − (2π/3 − √3/2).
/// let u = union_area(&[Circle { x: 0.0, y: 0.0, r: 1.0 }, Circle { x: 1.0, y: 0.0, r: 1.0 }]);
/// let lens = 2.0 * std::f64::consts::PI / 3.0 - 3f64.sqrt() / 2.0;
/// assert!((u.area - (2.0 * std::f64::consts::PI - lens)).abs() < 1e-14);
/// ```
pub fn union_area(discs: &[Circle]) -> Union {
    let n = discs.len();
    let mut area = 0.0;
    let mut arcs = Vec::new();
    let mut cover: Vec<(f64, f64)> = Vec::new();
    'disc: for i in 0..n {
        let a = discs[i];
        if a.r <= 0.0 {
            continue;
        }
        cover.clear();
        for j in 0..n {
            if i == j || discs[j].r <= 0.0 {
                continue;
            }
            if contained(i, j, discs) {
                continue 'disc;
            }
            let b = discs[j];
            let (dx, dy) = (b.x - a.x, b.y - a.y);
            let d = dx.hypot(dy);
            if d >= a.r + b.r || d + b.r <= a.r {
                continue; // apart, or j inside i: no part of circle i is covered by j
            }
            let cos_half = ((a.r * a.r + d * d - b.r * b.r) / (2.0 * a.r * d)).clamp(-1.0, 1.0);
            let half = cos_half.acos();
            let mid = dy.atan2(dx);
            let s = (mid - half).rem_euclid(TAU);
            let e = s + 2.0 * half;
            if e > TAU {
                cover.push((s, TAU));
                cover.push((0.0, e - TAU));
            } else {
                cover.push((s, e));
            }
        }
        cover.sort_by(|p, q| p.0.total_cmp(&q.0));
        // Walk the merged covered intervals; the gaps are the uncovered arcs.
        let mut at = 0.0;
        let mut emit = |a0: f64, a1: f64, area: &mut f64| {
            if a1 > a0 {
                *area += 0.5
                    * (a.r * a.r * (a1 - a0) + a.r * a.x * (a1.sin() - a0.sin())
                        - a.r * a.y * (a1.cos() - a0.cos()));
                arcs.push(Arc { disc: i, a0, a1 });
            }
        };
        for &(s, e) in &cover {
            if s > at {
                emit(at, s, &mut area);
            }
            at = at.max(e);
        }
        emit(at, TAU, &mut area);
    }
    Union { area, arcs }
}

/// A conservative bound on the floating-point error of [`union_area`] for `n` discs whose
/// extent (centre distance from the origin plus radius) is at most `extent`: each arc term is
/// a handful of operations on numbers of size `extent²`, with at most `2n²` arcs.
pub fn union_area_error_bound(n: usize, extent: f64) -> f64 {
    let arcs = (2 * n * n).max(1) as f64;
    64.0 * f64::EPSILON * arcs * extent * extent * TAU
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    fn c(x: f64, y: f64, r: f64) -> Circle {
        Circle { x, y, r }
    }

    #[test]
    fn single_disc_is_pi_r2() {
        let u = union_area(&[c(3.0, -2.0, 1.5)]);
        assert!((u.area - PI * 2.25).abs() < 1e-13);
        assert_eq!(u.arcs.len(), 1);
    }

    #[test]
    fn contained_and_duplicate_discs_count_once() {
        let u = union_area(&[c(0.0, 0.0, 2.0), c(0.5, 0.0, 1.0), c(0.0, 0.0, 2.0)]);
        assert!((u.area - 4.0 * PI).abs() < 1e-13);
    }

    #[test]
    fn disjoint_and_tangent_discs_add() {
        let u = union_area(&[c(0.0, 0.0, 1.0), c(2.0, 0.0, 1.0), c(10.0, 0.0, 0.5)]);
        assert!((u.area - (2.0 * PI + 0.25 * PI)).abs() < 1e-13);
    }

    #[test]
    fn lens_of_two_unequal_discs() {
        // Lens area of circles r1, r2 at distance d (closed form, e.g. Weisstein, MathWorld
        // "Circle-Circle Intersection").
        let (r1, r2, d): (f64, f64, f64) = (1.0, 0.7, 1.2);
        let lens = r1 * r1 * ((d * d + r1 * r1 - r2 * r2) / (2.0 * d * r1)).acos()
            + r2 * r2 * ((d * d + r2 * r2 - r1 * r1) / (2.0 * d * r2)).acos()
            - 0.5 * ((-d + r1 + r2) * (d + r1 - r2) * (d - r1 + r2) * (d + r1 + r2)).sqrt();
        let u = union_area(&[c(0.0, 0.0, r1), c(d, 0.0, r2)]);
        assert!((u.area - (PI * (r1 * r1 + r2 * r2) - lens)).abs() < 1e-13);
    }

    #[test]
    fn many_discs_match_a_fine_raster() {
        let discs: Vec<Circle> = (0..12)
            .map(|k| {
                let t = k as f64 * 0.7;
                c(
                    t.cos() * (1.0 + 0.1 * k as f64),
                    t.sin(),
                    0.4 + 0.05 * k as f64,
                )
            })
            .collect();
        let exact = union_area(&discs).area;
        // Midpoint raster on a 2000² grid: error ~ perimeter·h, far below the tolerance.
        let (lo, hi, m) = (-3.0, 3.0, 2000);
        let h = (hi - lo) / m as f64;
        let mut count = 0usize;
        for iy in 0..m {
            let y = lo + (iy as f64 + 0.5) * h;
            for ix in 0..m {
                let x = lo + (ix as f64 + 0.5) * h;
                if discs
                    .iter()
                    .any(|d| (x - d.x).powi(2) + (y - d.y).powi(2) < d.r * d.r)
                {
                    count += 1;
                }
            }
        }
        let raster = count as f64 * h * h;
        assert!((exact - raster).abs() < 2e-4 * exact, "{exact} vs {raster}");
    }
}
