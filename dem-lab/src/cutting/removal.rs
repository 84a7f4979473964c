//! How material leaves a cut, in the terms S0 (Ye & Xu 2010) uses to tell the specimen types
//! apart: traditional chips "leave gently as single discs", ORC chips like the traditional
//! ones, improved-ORC chips "spray out fast when intra-grain bonds snap". From the final state
//! and its fragments ([`super::chips::fragments`]): of the discs in chips (fragments whose mass
//! centre is above the nominal surface), the share in chips of a single grain (one disc of a
//! traditional specimen, one rigid ORC clump, the discs of one improved-ORC grain: discs of one
//! [`dem_core::Discs::group`]) and in small chips (at most [`SMALL_CHIP_GRAINS`] grains), and the
//! chips' speeds (mass-centre speed, mass-weighted mean and largest) against the tool's.
//!
//! ```
//! use dem_lab::cutting::chips::fragments;
//! use dem_lab::cutting::removal::removal_mode;
//! use dem_core::State;
//! let mut st = State::default();
//! st.discs.push_uniform(0.0, 0.0, 1.0, 1.0, 1.0, 0); // the workpiece (the heaviest)
//! st.discs.push_uniform(5.0, 3.0, 0.5, 1.0, 1.0, 0); // a one-disc chip, above y = 1
//! for k in 0..2 {
//!     st.discs.group[k] = k as u32;
//! }
//! st.discs.vx[1] = 3.0;
//! let frags = fragments(&st, None);
//! let r = removal_mode(&st, &frags, 1.0, 1.0);
//! assert_eq!((r.chip_discs, r.single_grain_share), (1, 1.0));
//! assert_eq!(r.chip_speed_max, 3.0);
//! ```

use super::chips::Fragment;
use dem_core::State;
use serde::{Deserialize, Serialize};

/// Largest chip (in grains) counted as a small chip.
pub const SMALL_CHIP_GRAINS: usize = 3;

/// The removal mode of a cut (see the module docs).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct RemovalMode {
    /// Discs and chips above the nominal surface (not the workpiece).
    pub chip_discs: usize,
    pub chips: usize,
    /// Share of the chip discs that are in chips of one grain, and in chips of at most
    /// [`SMALL_CHIP_GRAINS`] grains (0 when there are no chips).
    pub single_grain_share: f64,
    pub small_chip_share: f64,
    /// Grains in the largest chip.
    pub largest_chip_grains: usize,
    /// Chips' mass-centre speed (m/s): mass-weighted mean and largest; 0 without chips.
    pub chip_speed_mean: f64,
    pub chip_speed_max: f64,
    /// The tool's speed (m/s), the scale of the chip speeds.
    pub tool_speed: f64,
}

/// The removal mode of the fragments `frags` (`[0]` the workpiece) of the state `st`, with
/// the nominal surface at `surface_y` and the tool moving at `tool_speed`.
pub fn removal_mode(
    st: &State,
    frags: &[Fragment],
    surface_y: f64,
    tool_speed: f64,
) -> RemovalMode {
    let d = &st.discs;
    let mut r = RemovalMode {
        tool_speed,
        ..Default::default()
    };
    let (mut single, mut small, mut mass, mut mv) = (0usize, 0usize, 0.0, 0.0);
    for f in frags.iter().skip(1).filter(|f| f.centre[1] > surface_y) {
        let mut grains: Vec<u32> = f.discs.iter().map(|&k| d.group[k]).collect();
        grains.sort_unstable();
        grains.dedup();
        let n = f.discs.len();
        r.chips += 1;
        r.chip_discs += n;
        r.largest_chip_grains = r.largest_chip_grains.max(grains.len());
        if grains.len() == 1 {
            single += n;
        }
        if grains.len() <= SMALL_CHIP_GRAINS {
            small += n;
        }
        let (mut m, mut px, mut py) = (0.0, 0.0, 0.0);
        for &k in &f.discs {
            m += d.m[k];
            px += d.m[k] * d.vx[k];
            py += d.m[k] * d.vy[k];
        }
        if m > 0.0 {
            let v = px.hypot(py) / m;
            r.chip_speed_max = r.chip_speed_max.max(v);
            mass += m;
            mv += m * v;
        }
    }
    if r.chip_discs > 0 {
        r.single_grain_share = single as f64 / r.chip_discs as f64;
        r.small_chip_share = small as f64 / r.chip_discs as f64;
    }
    if mass > 0.0 {
        r.chip_speed_mean = mv / mass;
    }
    r
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cutting::chips::fragments;
    use dem_core::bond::{BondGroup, BondModel, Bonds, Criterion, ParallelBondParams};

    /// A workpiece of 6 bonded discs, a one-disc chip, a chip of two discs of one grain, a
    /// chip of four grains (bonded in a row) and a one-disc fragment below the surface.
    #[test]
    fn shares_and_speeds_of_constructed_chips() {
        let mut st = State::default();
        let add = |st: &mut State, x: f64, y: f64, g: u32, vx: f64| {
            st.discs.push_uniform(x, y, 0.5, 1.0, 1.0, 0);
            let k = st.discs.len() - 1;
            st.discs.group[k] = g;
            st.discs.vx[k] = vx;
        };
        for k in 0..6 {
            add(&mut st, k as f64, 0.0, k, 0.0);
        }
        add(&mut st, 0.0, 5.0, 100, 2.0); // 6: single-disc chip
        add(&mut st, 3.0, 5.0, 101, 1.0); // 7, 8: one grain, two discs
        add(&mut st, 4.0, 5.0, 101, 1.0);
        for k in 0..4 {
            add(&mut st, 10.0 + k as f64, 5.0, 200 + k, 0.5); // 9..12: four grains
        }
        add(&mut st, 20.0, -3.0, 300, 9.0); // 13: below the surface
        let params = ParallelBondParams {
            kn: 1.0,
            ks: 1.0,
            lambda: 1.0,
            beta: 1.0,
        };
        let mut b = Bonds::new(vec![BondGroup {
            name: "g".into(),
            model: BondModel::Parallel(params),
            criterion: Criterion::Stress {
                tensile: 1.0,
                cohesion: 1.0,
                friction_angle: 0.0,
            },
        }])
        .unwrap();
        for (i, j) in [
            (0, 1),
            (1, 2),
            (2, 3),
            (3, 4),
            (4, 5),
            (7, 8),
            (9, 10),
            (10, 11),
            (11, 12),
        ] {
            b.add(&st, i, j, 0).unwrap();
        }
        let frags = fragments(&st, Some(&b));
        let r = removal_mode(&st, &frags, 1.0, 1.0);
        assert_eq!(r.chips, 3);
        assert_eq!(r.chip_discs, 7);
        assert_eq!(r.largest_chip_grains, 4);
        // Single grain: the lone disc and the two-disc grain (3 of 7 discs); small: those 3.
        assert!((r.single_grain_share - 3.0 / 7.0).abs() < 1e-15);
        assert!((r.small_chip_share - 3.0 / 7.0).abs() < 1e-15);
        // Speeds: 2, 1 and 0.5 m/s with masses 1, 2, 4 (the fragment below is left out).
        assert_eq!(r.chip_speed_max, 2.0);
        assert!((r.chip_speed_mean - (2.0 + 2.0 + 2.0) / 7.0).abs() < 1e-15);
    }
}
