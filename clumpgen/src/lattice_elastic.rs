//! Equivalent elastic constants of the triangular node lattice of [`crate::lattice`], by
//! strain-energy equivalence between one lattice cell and the continuum (S3, the patent "DEM
//! for crushing particles of arbitrary shape": `U_continuum = U_cell`). Derivation:
//! docs/lattice.md.
//!
//! Every link (spacing `S`, unit direction `n`, normal `t = ẑ × n`) carries a normal spring
//! `k_n` on the normal relative displacement `δ_n = n·(u_j − u_i)` and a shear spring `k_s` on
//! the shear relative displacement at the contact point (the link's midpoint), with node
//! rotations: `δ_s = t·(u_j − u_i) − (S/2)(θ_i + θ_j)` (as a DEM bond; a rigid rotation stores
//! no energy). Under a uniform strain `ε` the nodes rotate with the material
//! (`θ = ω`, because the three directions give `Σ_k t_kᵀ ε n_k = 0`), so each link stores
//! `½S²[k_n (nᵀεn)² + k_s (tᵀεn)²]`. One node per cell of area `A_c = (√3/2)S²` and three links
//! per cell (directions 0°, 60°, 120°) give, with `Σ_k n⊗n⊗n⊗n = (3/8)(δδ + δδ + δδ)`,
//!
//! `U/A = (1/A_c) Σ_{k=1..3} ½S²[…] = ½λ't (tr ε)² + μ't ε:ε`,
//! `λ't = (√3/4)(k_n − k_s)`, `μ't = (√3/4)(k_n + k_s)`,
//!
//! and in plane stress
//!
//! `E·t = 2√3·k_n(k_n + k_s)/(3k_n + k_s)`,  `ν = (k_n − k_s)/(3k_n + k_s)`,
//!
//! independent of `S` (a 2D lattice's stiffness per thickness has the units of a spring, N/m).
//! The inverse: `k_n = E·t/(√3(1 − ν))`, `k_s = E·t(1 − 3ν)/(√3(1 − ν²))`, for
//! `0 ≤ ν < 1/3` (`ν = 1/3` is `k_s = 0`, `ν < 0` would need `k_s > k_n`).

/// Stiffnesses of one lattice link (N/m): normal `k_n`, shear `k_s`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinkStiffness {
    pub k_n: f64,
    pub k_s: f64,
}

/// Plane-stress elastic constants of the lattice: Young's modulus `e` (Pa), Poisson's ratio
/// `nu`, for a thickness `t` (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Elastic {
    pub e: f64,
    pub nu: f64,
}

/// A value out of range; `field` names it (`E`, `nu`, `thickness`, `k_n`, `k_s`).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{field} {value}: {reason}")]
pub struct ElasticError {
    pub field: &'static str,
    pub value: f64,
    pub reason: &'static str,
}

fn positive(field: &'static str, value: f64) -> Result<(), ElasticError> {
    if value.is_finite() && value > 0.0 {
        Ok(())
    } else {
        Err(ElasticError {
            field,
            value,
            reason: "must be positive and finite",
        })
    }
}

/// `E` and `ν` of the lattice with link stiffnesses `k` and thickness `t` (module docs,
/// docs/lattice.md; S3): `E·t = 2√3·k_n(k_n + k_s)/(3k_n + k_s)`,
/// `ν = (k_n − k_s)/(3k_n + k_s)`. Needs `k_n > 0`, `k_s ≥ 0`, `t > 0`.
pub fn lattice_elastic(k: LinkStiffness, t: f64) -> Result<Elastic, ElasticError> {
    positive("k_n", k.k_n)?;
    positive("thickness", t)?;
    if !(k.k_s.is_finite() && k.k_s >= 0.0) {
        return Err(ElasticError {
            field: "k_s",
            value: k.k_s,
            reason: "must be finite and >= 0",
        });
    }
    let (kn, ks) = (k.k_n, k.k_s);
    Ok(Elastic {
        e: 2.0 * 3f64.sqrt() * kn * (kn + ks) / (3.0 * kn + ks) / t,
        nu: (kn - ks) / (3.0 * kn + ks),
    })
}

/// Link stiffnesses that give the lattice Young's modulus `e` (Pa) and Poisson's ratio `nu` at
/// thickness `t` (m): the inverse of [`lattice_elastic`] (derivation in docs/lattice.md, from
/// S3's strain-energy equivalence):
///
/// `k_n = E·t / (√3·(1 − ν))`,  `k_s = E·t·(1 − 3ν) / (√3·(1 − ν²))`.
///
/// A triangular lattice with these springs reaches only `0 ≤ ν < 1/3`; outside, the error
/// names `nu` (and `E`, `thickness` when not positive and finite).
pub fn link_stiffness(e: f64, nu: f64, t: f64) -> Result<LinkStiffness, ElasticError> {
    positive("E", e)?;
    positive("thickness", t)?;
    if !(nu.is_finite() && (0.0..1.0 / 3.0).contains(&nu)) {
        return Err(ElasticError {
            field: "nu",
            value: nu,
            reason: "a triangular lattice of normal and shear springs reaches only 0 <= nu < 1/3 \
                     (nu = 1/3 needs k_s = 0, nu < 0 needs k_s > k_n)",
        });
    }
    let et = e * t;
    let sqrt3 = 3f64.sqrt();
    Ok(LinkStiffness {
        k_n: et / (sqrt3 * (1.0 - nu)),
        k_s: et * (1.0 - 3.0 * nu) / (sqrt3 * (1.0 - nu * nu)),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_e_nu_to_springs_and_back() {
        for &(e, nu, t) in &[
            (430e9, 0.14, 1e-3),
            (310e9, 0.27, 0.05),
            (50e9, 0.0, 1.0),
            (1e6, 0.333, 2.0),
        ] {
            let k = link_stiffness(e, nu, t).unwrap();
            let back = lattice_elastic(k, t).unwrap();
            assert!(((back.e - e) / e).abs() < 1e-12, "{e} {nu}: {back:?}");
            assert!((back.nu - nu).abs() < 1e-12, "{e} {nu}: {back:?}");
        }
        // ν = 0 is k_s = k_n = E t/√3.
        let k = link_stiffness(1.0, 0.0, 1.0).unwrap();
        assert!((k.k_n - 1.0 / 3f64.sqrt()).abs() < 1e-15 && (k.k_s - k.k_n).abs() < 1e-15);
    }

    #[test]
    fn out_of_range_inputs_name_the_field() {
        for nu in [-0.1, 1.0 / 3.0, 0.4, f64::NAN] {
            assert_eq!(link_stiffness(1e9, nu, 1.0).unwrap_err().field, "nu");
        }
        assert_eq!(link_stiffness(0.0, 0.2, 1.0).unwrap_err().field, "E");
        assert_eq!(
            link_stiffness(1e9, 0.2, -1.0).unwrap_err().field,
            "thickness"
        );
        let e = link_stiffness(1e9, 0.4, 1.0).unwrap_err().to_string();
        assert!(
            e.starts_with("nu 0.4: ") && e.contains("0 <= nu < 1/3"),
            "{e}"
        );
        let k = LinkStiffness {
            k_n: 1.0,
            k_s: -1.0,
        };
        assert_eq!(lattice_elastic(k, 1.0).unwrap_err().field, "k_s");
    }
}
