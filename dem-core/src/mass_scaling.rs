//! Selective mass scaling: make the lightest discs heavier so that they stop setting the time
//! step, within a stated budget of added mass and added spin inertia.
//!
//! The automatic step ([`crate::timestep`]) is f · min over bodies of √(m/K) and √(I/K_rot).
//! In an improved-ORC specimen the template discs of a grain share its mass (the mass fit of
//! clumpgen gives overlapping discs a fraction of their uniform-density mass, ~0.13 for the
//! largest template discs of the Table 2 specimen), so a few hundred of them set a step 3.5×
//! smaller than the plain discs' (issue 21: 27 M steps for one 10 mm cut).
//!
//! The remedy is the one explicit codes use: PFC's density scaling sets each body's inertial
//! mass and moment of inertia apart from its gravitational mass so that the body's critical
//! step meets a target (Itasca PFC manual, "Timestep determination", density scaling, which
//! scales the translational and rotational inertias separately); Abaqus/Explicit's fixed mass
//! scaling "to a target time increment" scales only the elements whose stable increment is
//! below the target and reports the added mass (Abaqus Analysis User's Guide §11.7.1, "Mass
//! scaling"). Here, once, before the run (fixed, not variable, scaling: momentum and energy
//! stay those of one set of masses), for the free discs only (rigid clumps and walls are
//! left as they are):
//!
//! ```text
//! m_i ← max(m_i, K_i T²),   I_i ← max(I_i, K_rot,i T²)
//! ```
//!
//! with K_i, K_rot,i the stiffness sums of the time-step estimate. The target critical step T is
//! the largest for which the added mass Σ max(0, K_i T² − m_i) is at most `budget` · Σ m_i *and*
//! the added spin inertia Σ max(0, K_rot,i T² − I_i) at most `budget` · Σ I_i ([`target_step`]
//! solves each exactly: the added amount is piecewise linear in T²). The report
//! ([`MassScaling`]) states what was added; the forces' sensitivity to it is measured on the
//! Table 2 specimens in docs/cutting.md ("Mass scaling").
//!
//! What it changes: the scaled discs respond more slowly (inertial mass) and a grain holding
//! them is heavier by its share of the added mass (improved ORC's "exact mass" holds for the
//! unscaled grain); quasi-static results do not depend on inertia, dynamic ones do, by an
//! amount the budget bounds. There is no gravity in the scenes that use it (the gravitational
//! mass would otherwise have to stay apart).

use serde::{Deserialize, Serialize};

/// What [`crate::World::scale_inertia`] did.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MassScaling {
    /// The budget: largest added mass and added spin inertia, as fractions of the free discs'
    /// totals.
    pub budget: f64,
    /// Target critical step T (s; without the safety factor).
    pub target_dt: f64,
    /// Critical step before and after (s; after may stay below T where a rigid clump or a
    /// fixed-stiffness bound sets it).
    pub critical_dt_before: f64,
    pub critical_dt_after: f64,
    /// Discs whose mass, and whose moment of inertia, were raised.
    pub discs_mass: usize,
    pub discs_inertia: usize,
    /// Mass added (kg) and as a fraction of the free discs' mass.
    pub added_mass: f64,
    pub added_mass_fraction: f64,
    /// Spin inertia added as a fraction of the free discs' Σ I.
    pub added_inertia_fraction: f64,
}

/// The largest step T with Σ max(0, k_i T² − m_i) ≤ `budget` · Σ m_i (`m`: masses or moments
/// of inertia; `k`: their stiffness sums; entries with k ≤ 0 are ignored). `None` when no entry
/// has a stiffness. With `budget` = 0 it is the current critical step min √(m_i/k_i).
///
/// ```
/// use dem_core::mass_scaling::target_step;
/// // Two unit springs with masses 1 and 4: steps 1 and 2. A budget of 3/5 of the total
/// // mass (3 kg) raises the light one to 4 kg, i.e. T = 2.
/// let t = target_step(&[1.0, 4.0], &[1.0, 1.0], 0.6).unwrap();
/// assert!((t - 2.0).abs() < 1e-12);
/// ```
pub fn target_step(m: &[f64], k: &[f64], budget: f64) -> Option<f64> {
    // Thresholds s_i = m_i/k_i of T²: the added amount is Σ_{s_i < s} (k_i s − m_i), linear in s
    // between consecutive thresholds.
    let mut t: Vec<(f64, f64, f64)> = m
        .iter()
        .zip(k)
        .filter(|(_, &k)| k > 0.0)
        .map(|(&m, &k)| (m / k, m, k))
        .collect();
    if t.is_empty() {
        return None;
    }
    t.sort_by(|a, b| a.0.total_cmp(&b.0));
    let allowed = budget.max(0.0) * m.iter().sum::<f64>();
    let (mut ks, mut ms) = (0.0, 0.0);
    for j in 0..t.len() {
        ks += t[j].2;
        ms += t[j].1;
        // Within [s_j, s_{j+1}] the added amount is ks·s − ms.
        let s = (allowed + ms) / ks;
        let next = t.get(j + 1).map_or(f64::INFINITY, |n| n.0);
        if s <= next {
            return Some(s.max(t[0].0).sqrt());
        }
    }
    unreachable!("the last interval is unbounded")
}

/// Raises the masses `m` and moments of inertia `inertia` of the discs `free` (indices into
/// all four slices) to `k_trans` T² and `k_rot` T², T the largest step within `budget`
/// ([`target_step`] of each, the smaller); `budget` ≤ 0 changes nothing. The report's critical
/// steps are left 0 for the caller ([`crate::World::scale_inertia`]) to fill.
pub fn scale_discs(
    m: &mut [f64],
    inertia: &mut [f64],
    k_trans: &[f64],
    k_rot: &[f64],
    free: &[usize],
    budget: f64,
) -> MassScaling {
    let pick = |v: &[f64]| free.iter().map(|&i| v[i]).collect::<Vec<f64>>();
    let (m0, i0) = (pick(m), pick(inertia));
    let b = budget.max(0.0);
    let t = match (
        target_step(&m0, &pick(k_trans), b),
        target_step(&i0, &pick(k_rot), b),
    ) {
        (Some(a), Some(c)) => a.min(c),
        (a, c) => a.or(c).unwrap_or(0.0),
    };
    let (mut nm, mut ni, mut dm, mut di) = (0, 0, 0.0, 0.0);
    if b > 0.0 {
        for &i in free {
            let (m_new, i_new) = (k_trans[i] * t * t, k_rot[i] * t * t);
            if m_new > m[i] {
                dm += m_new - m[i];
                m[i] = m_new;
                nm += 1;
            }
            if i_new > inertia[i] {
                di += i_new - inertia[i];
                inertia[i] = i_new;
                ni += 1;
            }
        }
    }
    let frac = |added: f64, v: &[f64]| {
        let total: f64 = v.iter().sum();
        if total > 0.0 {
            added / total
        } else {
            0.0
        }
    };
    MassScaling {
        budget: b,
        target_dt: t,
        critical_dt_before: 0.0,
        critical_dt_after: 0.0,
        discs_mass: nm,
        discs_inertia: ni,
        added_mass: dm,
        added_mass_fraction: frac(dm, &m0),
        added_inertia_fraction: frac(di, &i0),
    }
}

#[cfg(test)]
mod tests {
    use super::target_step;
    use crate::contact::{LinearSpringDashpot, NormalDamping};
    use crate::{ContactLaws, ContactModel, Params, State, World};

    /// Two touching discs (radii 10 and 5 mm, ρ = 2500, t = 1 m) on a frictionless linear law
    /// without shear stiffness: only the translational bounds √(m/k_n) count.
    fn pair() -> World {
        let mut st = State::default();
        st.discs.push_uniform(0.0, 0.0, 0.01, 2500.0, 1.0, 0);
        st.discs.push_uniform(0.0149, 0.0, 0.005, 2500.0, 1.0, 0);
        let law = LinearSpringDashpot {
            kn: 1e6,
            ks: 0.0,
            damping: NormalDamping::from_restitution(1.0),
            shear_damping: 0.0,
            mu: 0.0,
        };
        World::new(
            st,
            Params::default(),
            ContactLaws::uniform(ContactModel::Linear(law)),
        )
    }

    /// The light disc (m/4) is raised to k T² with T² = (m/4 + b · 5m/4)/k, the closed form of
    /// the budget while only it is below T; the world's critical step becomes T.
    #[test]
    fn the_light_disc_takes_the_budget_and_the_step_rises_to_the_target() {
        let mut w = pair();
        let (m_big, m_small) = (w.state.discs.m[0], w.state.discs.m[1]);
        assert!((m_small / m_big - 0.25).abs() < 1e-12);
        let kn = 1e6;
        let before = w.critical_dt();
        assert!((before - (m_small / kn).sqrt()).abs() < 1e-12 * before);
        let b = 0.2;
        let r = w.scale_inertia(b);
        let t2 = (m_small + b * (m_big + m_small)) / kn;
        assert!(
            (r.target_dt - t2.sqrt()).abs() < 1e-12 * r.target_dt,
            "{r:?}"
        );
        assert!((w.critical_dt() - t2.sqrt()).abs() < 1e-12 * r.target_dt);
        assert_eq!(r.critical_dt_after, w.critical_dt());
        assert_eq!(r.critical_dt_before, before);
        assert_eq!((r.discs_mass, r.discs_inertia), (1, 0));
        assert!((r.added_mass_fraction - b).abs() < 1e-12);
        assert!((w.state.discs.m[1] - kn * t2).abs() < 1e-12 * m_small);
        assert_eq!(w.state.discs.m[0], m_big, "the heavy disc is left alone");
        // The step follows: f · T.
        assert!((w.dt() - w.params.dt_factor * t2.sqrt()).abs() < 1e-12 * w.dt());
        assert_eq!(w.mass_scaling(), Some(&r));
    }

    /// Budget 0 changes no mass, inertia or step.
    #[test]
    fn budget_zero_changes_nothing() {
        let mut w = pair();
        let (m, i, dt) = (
            w.state.discs.m.clone(),
            w.state.discs.inertia.clone(),
            w.dt(),
        );
        let r = w.scale_inertia(0.0);
        assert_eq!((r.discs_mass, r.discs_inertia, r.added_mass), (0, 0, 0.0));
        assert_eq!(w.state.discs.m, m);
        assert_eq!(w.state.discs.inertia, i);
        assert_eq!(w.dt(), dt);
    }

    #[test]
    fn target_step_solves_the_budget_exactly() {
        // Steps √(m/k): 1, 2, 3. Budget 0: the smallest step.
        let (m, k) = ([1.0, 8.0, 9.0], [1.0, 2.0, 1.0]);
        assert_eq!(target_step(&m, &k, 0.0), Some(1.0));
        // Σm = 18; raising the first to T = 2 adds 3 (= 1/6 of 18); T = 2.5 adds (6.25 − 1) +
        // (12.5 − 8) = 9.75: a budget of 9.75/18 gives 2.5 exactly.
        let t = target_step(&m, &k, 9.75 / 18.0).unwrap();
        assert!((t - 2.5).abs() < 1e-12, "{t}");
        let t = target_step(&m, &k, 3.0 / 18.0).unwrap();
        assert!((t - 2.0).abs() < 1e-12, "{t}");
        // The added amount at the answer equals the budget (a random case).
        let m: Vec<f64> = (1..40)
            .map(|i| (i as f64 * 0.37).sin().abs() + 0.1)
            .collect();
        let k: Vec<f64> = (1..40)
            .map(|i| (i as f64 * 0.11).cos().abs() + 0.5)
            .collect();
        let b = 0.07;
        let t = target_step(&m, &k, b).unwrap();
        let added: f64 = m
            .iter()
            .zip(&k)
            .map(|(m, k)| (k * t * t - m).max(0.0))
            .sum();
        let total: f64 = m.iter().sum();
        assert!(
            (added - b * total).abs() < 1e-12 * total,
            "{added} {}",
            b * total
        );
    }

    #[test]
    fn entries_without_stiffness_are_ignored() {
        assert_eq!(target_step(&[1.0], &[0.0], 0.5), None);
        assert_eq!(target_step(&[1.0, 4.0], &[0.0, 1.0], 0.0), Some(2.0));
    }
}
