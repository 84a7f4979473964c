//! The 2D parallel bond of Potyondy & Cundall (2004), "A bonded-particle model for rock",
//! Int. J. Rock Mech. Min. Sci. 41:1329-1364, (= PFC's linear parallel bond with zero
//! reference gap; S4, Tan et al., uses it for SiC).
//!
//! A parallel bond is a rectangular patch of cement of half-width R̄ = λ̄·min(R1, R2) and
//! thickness t (the disc thickness) between two discs, acting in parallel with their contact.
//! Its cross-section has area Ā = 2R̄t and second moment Ī = (2/3)R̄³t (its 2D form). With
//! normal and shear stiffness per unit area k̄n, k̄s (Pa/m) it carries a normal force F̄n
//! (positive in compression), a shear force F̄s and a moment M̄, updated each step from the
//! relative motion of the discs:
//!
//! ```text
//! F̄n -= k̄n Ā Δδn      Δδn: change of the gap (opening positive)
//! F̄s -= k̄s Ā Δδs      Δδs: relative shear displacement at the contact point
//! M̄  -= k̄n Ī Δθ       Δθ = (ω2 − ω1) Δt
//! ```
//!
//! **Normal part in total form.** Since k̄nĀ is constant, summing the normal increments gives
//! F̄n = −k̄n Ā (g − g0) exactly, g the current gap and g0 the gap at installation (the reference
//! gap: a bond installed across a gap or an overlap starts force-free). The total form is used:
//! it equals the incremental law without its drift (the incremental gap change v·Δt differs from
//! the true change by O(Δt²) when the pair rotates).
//!
//! **Shear part.** Δδs = (v_c2 − v_c1)·t̂ Δt, the tangential relative velocity of the two discs'
//! material points at the contact point x_c = x1 + (R1 + g/2) n̂, including the rotation terms
//! ω × (x_c − x_k). In 2D the shear force is stored as its component along the current tangent
//! t̂ = (−n_y, n_x); keeping the scalar while t̂ turns with the pair *is* the rotation of the
//! shear force with the contact plane. A rigid rotation of the pair leaves F̄s and M̄ unchanged.
//!
//! **Time integration** (see `docs/dem-core-design.md`): positions are at t, velocities at
//! t − Δt/2, so v·Δt is the displacement increment of the last step.
//!
//! **Forces on the discs.** On disc 2 (j): F = F̄n n̂ + F̄s t̂ at x_c, plus the moment M̄; on
//! disc 1 (i) the opposite force at x_c and −M̄. The torque of the shear force about disc k's
//! centre is −a_k F̄s with a_k = R_k + g/2 the distance from its centre to x_c.
//!
//! **Strength**: σ̄ = −F̄n/Ā + β̄|M̄|R̄/Ī, τ̄ = |F̄s|/Ā, see [`super::criteria`].

use super::criteria::Loads;
use super::BondError;
use serde::{Deserialize, Serialize};

/// Parallel-bond parameters of a bond group.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParallelBondParams {
    /// Normal stiffness per unit area k̄n (Pa/m).
    pub kn: f64,
    /// Shear stiffness per unit area k̄s (Pa/m).
    pub ks: f64,
    /// Radius multiplier λ̄: R̄ = λ̄·min(R1, R2) (default 1).
    #[serde(default = "one")]
    pub lambda: f64,
    /// Moment-contribution factor β̄ ∈ [0, 1] in σ̄ (PFC 5; default 1 = Potyondy & Cundall 2004).
    #[serde(default = "one")]
    pub beta: f64,
}

fn one() -> f64 {
    1.0
}

impl ParallelBondParams {
    pub fn validate(&self, group: &str) -> Result<(), BondError> {
        let bad = |field: &str, value: f64| BondError::Parameter {
            group: group.to_string(),
            field: field.to_string(),
            value,
        };
        for (f, v) in [("kn", self.kn), ("ks", self.ks), ("lambda", self.lambda)] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(bad(f, v));
            }
        }
        if !(0.0..=1.0).contains(&self.beta) {
            return Err(bad("beta", self.beta));
        }
        Ok(())
    }
}

/// Bond cross-section area Ā = 2R̄t (m²).
#[inline]
pub fn area(rbar: f64, t: f64) -> f64 {
    2.0 * rbar * t
}

/// Bond second moment of area Ī = (2/3)R̄³t (m⁴): a 2R̄ × t rectangle bent about the axis
/// normal to the plane, (2R̄)³t/12.
#[inline]
pub fn inertia(rbar: f64, t: f64) -> f64 {
    2.0 / 3.0 * rbar * rbar * rbar * t
}

/// Relative motion of the two discs of a bond over the last step (built by the bond stage).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Kinematics {
    /// Gap g = |x2 − x1| − R1 − R2 (opening positive).
    pub gap: f64,
    /// Shear displacement increment Δδs along t̂ at the contact point.
    pub dus: f64,
    /// Relative rotation increment Δθ = (ω2 − ω1)Δt.
    pub dtheta: f64,
}

/// The bond forces `f = [F̄n, F̄s, M̄]` after one step, and the loads they put on the bond.
#[inline(always)]
pub(crate) fn update(
    p: &ParallelBondParams,
    rbar: f64,
    t: f64,
    g0: f64,
    length: f64,
    k: &Kinematics,
    f: [f64; 3],
) -> ([f64; 3], Loads) {
    let a = area(rbar, t);
    let i = inertia(rbar, t);
    let kn_a = p.kn * a;
    let ks_a = p.ks * a;
    let kn_i = p.kn * i;
    let f = [
        -kn_a * (k.gap - g0),
        f[1] - ks_a * k.dus,
        f[2] - kn_i * k.dtheta,
    ];
    let l = Loads {
        fn_: f[0],
        fs_abs: f[1].abs(),
        m_abs: f[2].abs(),
        area: a,
        lever: rbar * (1.0 / 3.0), // Ī/(R̄Ā) = (2/3)R̄³t / (R̄·2R̄t)
        beta: p.beta,
        kn_a,
        ks_a,
        kn_i,
        length,
    };
    (f, l)
}

/// Strain energy F̄n²/(2k̄nĀ) + F̄s²/(2k̄sĀ) + M̄²/(2k̄nĪ) (J).
#[inline]
pub fn energy(p: &ParallelBondParams, rbar: f64, t: f64, f: &[f64; 3]) -> f64 {
    let a = area(rbar, t);
    f[0] * f[0] / (2.0 * p.kn * a)
        + f[1] * f[1] / (2.0 * p.ks * a)
        + f[2] * f[2] / (2.0 * p.kn * inertia(rbar, t))
}

/// Stiffness of the bond seen by one of its discs, for the time-step estimate: translational
/// max(k̄n, k̄s)Ā and rotational k̄nĪ + k̄sĀ·arm² (arm = distance from the disc centre to the
/// contact point: a shear spring at the rim resists rotation too).
#[inline]
pub fn stiffness(p: &ParallelBondParams, rbar: f64, t: f64, arm: f64) -> (f64, f64) {
    let a = area(rbar, t);
    (
        p.kn.max(p.ks) * a,
        p.kn * inertia(rbar, t) + p.ks * a * arm * arm,
    )
}
