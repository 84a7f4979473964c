//! Finding the disc pairs to bond: all pairs whose gap is at most a tolerance (touching or
//! overlapping discs, or discs closer than `tol`). One-off, used when a specimen is bonded.
//!
//! Method: a uniform grid whose cell size is twice the median radius plus the tolerance; every
//! disc is entered in each cell its bounding box (grown by tol/2) touches, so large discs do not
//! force large cells and the cost stays linear in N for wide size ratios. Two discs within the
//! tolerance have intersecting grown boxes, hence share a cell. Pairs found in several cells are
//! deduplicated. Periodic axes wrap (minimum image).

use crate::state::State;

/// All pairs (i < j) with gap |x_j − x_i| − r_i − r_j ≤ `tol`, sorted.
pub fn pairs_within_gap(st: &State, tol: f64) -> Vec<(u32, u32)> {
    let d = &st.discs;
    let n = d.len();
    if n < 2 || tol.is_nan() {
        return Vec::new();
    }
    let tol = tol.max(0.0);
    let mut radii: Vec<f64> = d.r.clone();
    radii.sort_by(f64::total_cmp);
    let h = 2.0 * radii[n / 2] + tol;
    if !(h > 0.0 && h.is_finite()) {
        return Vec::new();
    }
    let per = &st.periodic;
    // Grid along each axis: origin, cell width, count, periodic.
    let mut ax = [(0.0, h, 1usize, false); 2];
    for (a, c) in [&d.x, &d.y].into_iter().enumerate() {
        match per.length[a] {
            Some(l) => {
                let cells = ((l / h).floor() as usize).clamp(1, 1 << 20);
                ax[a] = (per.lo[a], l / cells as f64, cells, true);
            }
            None => {
                let lo = (0..n).map(|k| c[k] - d.r[k]).fold(f64::INFINITY, f64::min) - tol;
                let hi = (0..n)
                    .map(|k| c[k] + d.r[k])
                    .fold(f64::NEG_INFINITY, f64::max)
                    + tol;
                let cells = (((hi - lo) / h).ceil() as usize).clamp(1, 1 << 20);
                ax[a] = (lo, h, cells, false);
            }
        }
    }
    if ax[0].2.saturating_mul(ax[1].2) > 1 << 26 {
        return brute_force(st, tol);
    }
    // Cell range of a disc on one axis, as (first, count) before wrapping.
    let range = |a: usize, c: f64, r: f64| -> (i64, i64) {
        let (lo, w, cells, periodic) = ax[a];
        let g = r + 0.5 * tol;
        let first = ((c - g - lo) / w).floor() as i64;
        let last = ((c + g - lo) / w).floor() as i64;
        if periodic {
            (first, (last - first + 1).min(cells as i64))
        } else {
            let first = first.clamp(0, cells as i64 - 1);
            let last = last.clamp(0, cells as i64 - 1);
            (first, last - first + 1)
        }
    };
    let cell_of = |a: usize, k: i64| -> usize { k.rem_euclid(ax[a].2 as i64) as usize };
    // Counting sort into cells (CSR).
    let ncell = ax[0].2 * ax[1].2;
    let mut start = vec![0u32; ncell + 1];
    let visit = |f: &mut dyn FnMut(usize, u32)| {
        for k in 0..n {
            let (fx, cx) = range(0, d.x[k], d.r[k]);
            let (fy, cy) = range(1, d.y[k], d.r[k]);
            for iy in fy..fy + cy {
                for ix in fx..fx + cx {
                    f(cell_of(1, iy) * ax[0].2 + cell_of(0, ix), k as u32);
                }
            }
        }
    };
    visit(&mut |c, _| start[c + 1] += 1);
    for c in 0..ncell {
        start[c + 1] += start[c];
    }
    let mut fill = start.clone();
    let mut members = vec![0u32; start[ncell] as usize];
    visit(&mut |c, k| {
        members[fill[c] as usize] = k;
        fill[c] += 1;
    });
    let mut pairs = Vec::new();
    for c in 0..ncell {
        let m = &members[start[c] as usize..start[c + 1] as usize];
        for (a, &p) in m.iter().enumerate() {
            for &q in &m[a + 1..] {
                if p != q && gap(st, p as usize, q as usize) <= tol {
                    pairs.push((p.min(q), p.max(q)));
                }
            }
        }
    }
    pairs.sort_unstable();
    pairs.dedup();
    pairs
}

/// Gap between discs `i` and `j` (minimum image on periodic axes).
pub fn gap(st: &State, i: usize, j: usize) -> f64 {
    let d = &st.discs;
    let (dx, dy) =
        crate::state::MinImage::new(&st.periodic).delta(d.x[j] - d.x[i], d.y[j] - d.y[i]);
    (dx * dx + dy * dy).sqrt() - d.r[i] - d.r[j]
}

fn brute_force(st: &State, tol: f64) -> Vec<(u32, u32)> {
    let n = st.discs.len();
    let mut v = Vec::new();
    for i in 0..n {
        for j in i + 1..n {
            if gap(st, i, j) <= tol {
                v.push((i as u32, j as u32));
            }
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::Periodic;

    /// Deterministic pseudo-random numbers in [0, 1).
    fn lcg(s: &mut u64) -> f64 {
        *s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*s >> 11) as f64 / (1u64 << 53) as f64
    }

    #[test]
    fn grid_matches_brute_force_with_size_ratio_and_periodic_axes() {
        for periodic in [false, true] {
            let mut st = State::default();
            if periodic {
                st.periodic = Periodic {
                    lo: [0.0, -1.0],
                    length: [Some(4.0), Some(3.0)],
                };
            }
            let mut s = 7u64;
            for k in 0..400 {
                let r = if k % 50 == 0 {
                    0.5
                } else {
                    0.025 + 0.03 * lcg(&mut s)
                };
                let x = 4.0 * lcg(&mut s);
                let y = -1.0 + 3.0 * lcg(&mut s);
                st.discs.push_uniform(x, y, r, 1.0, 1.0, 0);
            }
            let tol = 0.01;
            let a = pairs_within_gap(&st, tol);
            let b = brute_force(&st, tol);
            assert!(b.len() > 100, "{}", b.len());
            assert_eq!(a, b, "periodic = {periodic}");
        }
    }
}
