//! Spatial reordering of discs for cache locality: discs are sorted by the cell they fall in
//! on a grid of cell side ≈ the median diameter, cells taken in square tiles of [`STRIP`] ×
//! [`STRIP`] cells (tiles row of tiles by row of tiles, left to right; within a tile row by
//! row), ties kept in the current order. A disc's partners then sit within about two tile rows
//! of it in memory (a few kB per array), which measured faster on the dense benchmark than
//! Morton (Z) order, whose block boundaries put some partners far away: the force pass reads
//! partner data from cache. The caller applies the permutation to the state and remaps every
//! per-disc and per-pair array (neighbour history, bonds, clump member lookup).
//!
//! **Why tiles, not full-height strips.** The split force pass (`contact::owned`) cuts the
//! order into contiguous ranges; the discs of a later range that an earlier range's pairs
//! reach ("shared" discs) take a slower path. With full-height strips a range boundary runs
//! down a strip, so one or two shared discs sat in every strip row and a third of the blocks
//! of pairs met one; with tiles the shared discs are whole tile rows, contiguous, and 94 % of
//! the blocks take the plain path (dense benchmark lattice on two threads: 2,033 of 2,157
//! blocks, against 1,452 with strips). Measured: +14 % on two threads (8 alternating rounds,
//! higher in 6), one thread unchanged (1.007, 8 rounds).

use crate::state::State;

/// Tile side in cells.
pub const STRIP: u32 = 32;
const _: () = assert!(
    STRIP <= 32,
    "the sort key packs in-tile rows and columns in 5 bits"
);
const MAXC: i64 = (1 << 21) - 1;

/// Order of discs (new position k holds old index `order[k]`) and its inverse
/// (`new_of_old[old] = new`). Returns `None` when the current order is already that order.
pub fn spatial_order(st: &State) -> Option<(Vec<u32>, Vec<u32>)> {
    let d = &st.discs;
    let n = d.len();
    if n < 2 {
        return None;
    }
    let mut rs = d.r.clone();
    rs.sort_unstable_by(|a, b| a.total_cmp(b));
    let cell = (2.0 * rs[n / 2]).max(1e-300);
    let (mut xmin, mut ymin) = (f64::INFINITY, f64::INFINITY);
    for k in 0..n {
        xmin = xmin.min(d.x[k]);
        ymin = ymin.min(d.y[k]);
    }
    let mut keyed: Vec<(u64, u32)> = (0..n)
        .map(|k| {
            let cx = (((d.x[k] - xmin) / cell).floor() as i64).clamp(0, MAXC) as u32;
            let cy = (((d.y[k] - ymin) / cell).floor() as i64).clamp(0, MAXC) as u32;
            // Tile row, tile column, row and column in the tile (STRIP ≤ 32: 5 bits each).
            let (ty, tx) = ((cy / STRIP) as u64, (cx / STRIP) as u64);
            let key = ty << 42 | tx << 21 | ((cy % STRIP) as u64) << 5 | (cx % STRIP) as u64;
            (key, k as u32)
        })
        .collect();
    keyed.sort_unstable();
    let order: Vec<u32> = keyed.iter().map(|e| e.1).collect();
    if order.iter().enumerate().all(|(k, &o)| k as u32 == o) {
        return None;
    }
    let mut new_of_old = vec![0u32; n];
    for (k, &o) in order.iter().enumerate() {
        new_of_old[o as usize] = k as u32;
    }
    Some((order, new_of_old))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn order_is_a_permutation_grouping_space() {
        let mut st = State::default();
        for k in 0..100 {
            // Interleave far-apart halves so the order must change.
            let x = if k % 2 == 0 {
                k as f64
            } else {
                1000.0 + k as f64
            };
            st.discs.push_uniform(x, 0.0, 0.4, 1.0, 1.0, 0);
        }
        let (order, inv) = spatial_order(&st).expect("reordered");
        let mut seen = [false; 100];
        for &o in &order {
            seen[o as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
        for (k, &o) in order.iter().enumerate() {
            assert_eq!(inv[o as usize] as usize, k);
        }
        // The first half of the new order holds the even (left) discs.
        assert!(order[..50].iter().all(|&o| o % 2 == 0));
    }

    /// A square grid of 2·STRIP × 2·STRIP discs, one per cell, is taken tile by tile (lower
    /// left, lower right, upper left, upper right) and row by row within a tile.
    #[test]
    fn cells_are_taken_in_tiles() {
        let n = 2 * STRIP as usize;
        let mut st = State::default();
        // Added column-major, so that the order must change.
        for cx in 0..n {
            for cy in 0..n {
                st.discs
                    .push_uniform(cx as f64 + 0.5, cy as f64 + 0.5, 0.5, 1.0, 1.0, 0);
            }
        }
        let (order, _) = spatial_order(&st).expect("reordered");
        let cell = |o: u32| (o as usize / n, o as usize % n); // (cx, cy) of disc o
        let s = STRIP as usize;
        for (k, &o) in order.iter().enumerate() {
            let (tile, within) = (k / (s * s), k % (s * s));
            let want = ((tile % 2) * s + within % s, (tile / 2) * s + within / s);
            assert_eq!(cell(o), want, "position {k}");
        }
    }
}
