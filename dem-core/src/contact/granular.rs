//! The catalogue law ([`dem_laws::GranularLaw`], LAMMPS `pair_style granular`-like: normal +
//! damping + tangential sub-models named in the scene, `docs/laws.md`) on 2D discs.
//!
//! The 2D solver keeps one scalar of history per listed pair (the shear displacement u_s) and
//! evaluates only touching pairs (δ > 0), so it runs the sub-models whose state is u_s alone
//! and that act only in contact: normal hooke, hertz, hertz/material, dmt; any damping;
//! tangential linear_nohistory, linear_history. JKR (a neck beyond contact), Walton–Braun
//! (δ_max), the mindlin family (its slip work is booked against the previous step's k_t and
//! energy; no-slip Mindlin on discs is the solver's own `hertz_mindlin` law),
//! Mindlin–Deresiewicz (turning points), van der Waals (a force across a gap) and twisting
//! (3D) need more history or pairs out of contact: [`check_2d`] refuses them with the reason.
//! Rolling resistance on discs stays the scene's `"rolling"` switch
//! ([`super::RollingResistance`]).
//!
//! Like LAMMPS and YADE applying their sphere laws to discs, the law acts per contact (not per
//! unit thickness), with R* the discs' effective radius; the exact same function serves the
//! 3D solver with a vector history.

use super::{PairKin, PairOut};
use dem_laws::{ContactLaw, GranularHistory, GranularLaw, Normal, NormalHistory, Tangential};

/// Why `law` cannot run on 2D discs, or `Ok`.
pub fn check_2d(law: &GranularLaw) -> Result<(), String> {
    let why = match (&law.normal, &law.tangential) {
        (Normal::Jkr { .. }, _) => {
            "normal model jkr holds a neck beyond contact, which the 2D solver does not evaluate"
        }
        (Normal::WaltonBraun { .. }, _) => {
            "normal model walton_braun needs the largest overlap as history, which the 2D solver does not keep"
        }
        (_, Tangential::MindlinDeresiewicz { .. }) => {
            "tangential model mindlin/deresiewicz needs its turning points as history, which the 2D solver does not keep"
        }
        (_, Tangential::Mindlin { .. }) => {
            "the mindlin tangential models need the previous stiffness as history, which the 2D solver does not keep (no-slip Mindlin on discs: \"law\": \"hertz_mindlin\")"
        }
        _ if law.twisting.is_some() => "twisting has no meaning for discs",
        _ if law.vdw.is_some() => {
            "van der Waals acts across a gap; the 2D solver evaluates touching pairs only"
        }
        _ if law.rolling.is_some() => {
            "rolling inside the law is for 3D; on discs use the pair's \"rolling\": true with rolling_friction"
        }
        _ => return Ok(()),
    };
    Err(format!("{why} (3D only for now; docs/laws.md)"))
}

/// The force of a pair under a 2D-checked `law` ([`check_2d`]), its shear history in `us`.
#[inline(always)]
pub fn force<const E: bool>(law: &GranularLaw, k: &PairKin, us: &mut f64) -> PairOut {
    let mut h = GranularHistory::<f64>::default();
    h.tangential.us = *us;
    // R₁, R₂ only enter the van der Waals term, which check_2d refuses.
    let r = 2.0 * k.r_eff;
    let o = law.force_pair::<E, f64>(k, r, r, &mut h);
    *us = h.tangential.us;
    o
}

/// Normal stiffness S_n at overlap δ (time step, rolling).
#[inline(always)]
pub fn kn(law: &GranularLaw, r_eff: f64, delta: f64) -> f64 {
    ContactLaw::<f64>::kn(law, r_eff, delta)
}

/// Tangential stiffness at overlap δ.
#[inline(always)]
pub fn ks(law: &GranularLaw, r_eff: f64, delta: f64) -> f64 {
    ContactLaw::<f64>::ks(law, r_eff, delta)
}

/// Elastic normal force and its strain energy at overlap δ (contact views, removal energy).
pub fn spring_normal(law: &GranularLaw, r_eff: f64, delta: f64) -> (f64, f64) {
    let nf = law
        .normal
        .eval(r_eff, delta.max(0.0), &mut NormalHistory::default());
    (nf.f, nf.energy)
}

/// Whether every parameter of the (2D-checked) law is finite (a restored checkpoint is checked
/// with it).
pub fn is_finite(law: &GranularLaw) -> bool {
    use dem_laws::Damping as D;
    let n = match law.normal {
        Normal::Hooke { kn } | Normal::Hertz { kn } => vec![kn],
        Normal::HertzMaterial(m) => vec![m.e_star, m.g_star],
        Normal::Dmt { material: m, gamma } | Normal::Jkr { material: m, gamma } => {
            vec![m.e_star, m.g_star, gamma]
        }
        Normal::WaltonBraun { k1, k2 } => vec![k1, k2],
    };
    let d = match law.damping {
        D::None => vec![],
        D::Velocity { gamma } | D::MassVelocity { gamma } => vec![gamma],
        D::Viscoelastic { eta } => vec![eta],
        D::Tsuji { e, eta } | D::CoeffRestitution { e, eta, .. } => vec![e, eta],
    };
    let t = match law.tangential {
        Tangential::LinearNoHistory { gamma_t, mu } => vec![gamma_t, mu],
        Tangential::LinearHistory { kt, xgammat, mu } => vec![kt, xgammat, mu],
        Tangential::Mindlin {
            g_star,
            xgammat,
            mu,
            ..
        } => vec![g_star, xgammat, mu],
        Tangential::MindlinDeresiewicz { g_star, mu } => vec![g_star, mu],
    };
    n.iter().chain(&d).chain(&t).all(|v| v.is_finite())
}

/// Whether the law has a dashpot (any damping sub-model but `none`).
pub fn has_dashpot(law: &GranularLaw) -> bool {
    !matches!(law.damping, dem_laws::Damping::None)
}

#[cfg(test)]
mod tests {
    use super::*;
    use dem_laws::GranularSpec;

    fn law(json: &str) -> GranularLaw {
        GranularSpec::from_json(json, None)
            .unwrap()
            .build()
            .unwrap()
    }

    #[test]
    fn hooke_with_linear_history_is_the_linear_law() {
        // Same k_n, k_t, μ and no damping: the catalogue's composition and the 2D solver's
        // fused linear law give the same force and history.
        let g = law(r#"{"normal": {"model": "hooke", "kn": 1e6},
                        "tangential": {"model": "linear_history", "kt": 4e5, "mu": 0.5}}"#);
        check_2d(&g).unwrap();
        let l = dem_laws::LinearSpringDashpot::elastic(1e6, 4e5, 0.5);
        let k = PairKin {
            delta: 1e-5,
            vn: -0.1,
            vt: 0.3,
            m_eff: 1e-3,
            r_eff: 1e-3,
            dt: 1e-6,
        };
        let (mut u1, mut u2) = (2e-6, 2e-6);
        for _ in 0..50 {
            let a = force::<false>(&g, &k, &mut u1);
            let b = l.force::<false, f64>(&k, &mut u2);
            approx::assert_relative_eq!(a.f_n, b.f_n, max_relative = 1e-14);
            approx::assert_relative_eq!(a.f_t, b.f_t, max_relative = 1e-12);
            approx::assert_relative_eq!(u1, u2, max_relative = 1e-12);
        }
    }

    #[test]
    fn laws_needing_more_history_are_refused_with_the_reason() {
        let jkr = law(
            r#"{"normal": {"model": "jkr", "E": 1e9, "nu": 0.3, "gamma": 0.1},
                          "tangential": {"model": "mindlin", "mu": 0.3}}"#,
        );
        assert!(check_2d(&jkr).unwrap_err().contains("jkr"));
        let md = law(
            r#"{"normal": {"model": "hertz/material", "E": 1e9, "nu": 0.3},
                         "tangential": {"model": "mindlin/deresiewicz", "mu": 0.3}}"#,
        );
        assert!(check_2d(&md).unwrap_err().contains("deresiewicz"));
    }
}
