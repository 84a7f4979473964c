//! The consistency solve of the improved ORC method (Ye & Xu 2010, eqs. (1)–(3)): per-disc
//! masses `m_i > 0` such that the clump has exactly the grain's mass, centroid and mass moment of
//! inertia about the centroid:
//!
//! * `Σ m_i = m_p`                                  (mass)
//! * `Σ m_i x_i = 0`, `Σ m_i y_i = 0`               (centroid; discs in the grain's centroid frame)
//! * `Σ m_i (r_i²/2 + x_i² + y_i²) = I_p`            (disc inertia `m r²/2` plus parallel axis)
//!
//! Among all solutions we take the one closest to a prior (the uniform-density masses), i.e. the
//! convex quadratic program
//!
//! `min Σ (m_i − m0_i)² / m0_i   s.t.   A m = b,  m_i ≥ ε·m0_i`.
//!
//! Phase 1 finds a feasible point with Lawson & Hanson's NNLS, which also proves infeasibility
//! (the best nonnegative fit keeps a residual). Phase 2 is the primal active-set method (Nocedal &
//! Wright, *Numerical Optimization*, 2nd ed., Algorithm 16.3): with the active bounds held, the
//! step solving the equality-constrained subproblem has the closed form
//! `p_i = −m0_i (g_i − a_iᵀλ)` with `(Σ_free m0_i a_i a_iᵀ) λ = Σ_free m0_i g_i a_i`, a 4×4 system
//! solved by SVD (so rank-deficient cases, such as one centred disc or discs on a line, work).
//! Everything is done in scaled units (masses over `m_p`, lengths over the equivalent radius) and
//! finished with iterative refinement, which brings the residuals to round-off (~1e-15).
//!
//! Conditioning: with `Σ m_i = m_p` the inertia equation is equivalent to
//! `Σ m_i (s_i − k²) = 0`, with `s_i = r_i²/2 + x_i² + y_i²` and `k² = I_p/m_p` the grain's squared
//! radius of gyration. When every disc that carries mass has `s_i` close to `k²` (a dense circle:
//! one disc nearly the grain, repair discs on the ring `s ≈ k²`), the rows `1` and `s_i` of the
//! plain system are nearly parallel and the 4×4 solves lose the inertia equation to round-off
//! (the smallest singular value falls below the SVD cut-off). So if the plain system fails, the
//! fit is repeated (`Mode::Careful`) with the inertia row replaced by `(s_i − k²)/σ`,
//! `σ = max |s_i − k²|` (a row operation and a row scaling: the same solutions, equilibrated
//! rows), with Lawson & Hanson's guard against a column that cannot enter the NNLS passive set
//! (it is set aside instead of entering and leaving again until the iteration limit), and with
//! a phase-1 residual up to 1e-8 handed on to phase 2 (whose refinement brings the equalities
//! to round-off; the residual check at the end decides). Fits that succeed on the plain system
//! are unchanged, bit for bit.

use nalgebra::{Matrix4, Vector4};

/// Targets of the consistency equations, in the grain's centroid frame.
#[derive(Debug, Clone, Copy)]
pub struct MassTargets {
    /// Grain mass `m_p = ρ·t·A` (kg).
    pub mass: f64,
    /// Grain mass moment of inertia about its centroid `I_p = ρ·t·J` (kg·m²).
    pub inertia: f64,
    /// Length scale for scaling and for the centroid residual (equivalent radius, m).
    pub length: f64,
}

/// Residuals of a set of disc masses against the targets.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
pub struct Residuals {
    /// `|Σm − m_p| / m_p`.
    pub mass_rel: f64,
    /// `|Σ m_i (x_i, y_i)| / m_p`, divided by the equivalent radius.
    pub centroid_rel: f64,
    /// `|I − I_p| / I_p`.
    pub inertia_rel: f64,
}

impl Residuals {
    /// The largest of the three.
    pub fn max(&self) -> f64 {
        self.mass_rel.max(self.centroid_rel).max(self.inertia_rel)
    }
}

/// Why no consistent set of positive masses was found.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MassFitError {
    #[error("no discs to fit")]
    NoDiscs,
    #[error(
        "no positive masses satisfy mass, centroid and inertia together (best residual {0:.2e}): \
         the discs cannot reach the grain's centroid or inertia"
    )]
    Infeasible(f64),
}

/// Mass moment of inertia of uniform discs about the origin: `Σ m (r²/2 + x² + y²)`.
pub fn inertia_about_origin(xyr: &[[f64; 3]], m: &[f64]) -> f64 {
    xyr.iter()
        .zip(m)
        .map(|(d, &mi)| mi * (0.5 * d[2] * d[2] + d[0] * d[0] + d[1] * d[1]))
        .sum()
}

/// Residuals of masses `m` for discs `xyr` (`[x, y, r]`, centroid frame) against `t`.
pub fn residuals(xyr: &[[f64; 3]], m: &[f64], t: &MassTargets) -> Residuals {
    let mass: f64 = m.iter().sum();
    let mx: f64 = xyr.iter().zip(m).map(|(d, mi)| mi * d[0]).sum();
    let my: f64 = xyr.iter().zip(m).map(|(d, mi)| mi * d[1]).sum();
    Residuals {
        mass_rel: (mass - t.mass).abs() / t.mass,
        centroid_rel: mx.hypot(my) / t.mass / t.length,
        inertia_rel: (inertia_about_origin(xyr, m) - t.inertia).abs() / t.inertia,
    }
}

/// `(Σ_{i∈F} w_i a_i a_iᵀ)⁺ rhs` by SVD (pseudo-inverse, so rank-deficient sets work).
fn solve4(a: &[Vector4<f64>], w: &[f64], free: &[bool], rhs: Vector4<f64>) -> Vector4<f64> {
    let mut k = Matrix4::zeros();
    for i in 0..a.len() {
        if free[i] {
            k += a[i] * a[i].transpose() * w[i];
        }
    }
    let svd = k.svd(true, true);
    let eps = 1e-13 * svd.singular_values.max().max(f64::MIN_POSITIVE);
    svd.solve(&rhs, eps).unwrap_or_else(|_| Vector4::zeros())
}

/// Phase 1: a point with `A z = r`, `z ≥ 0` by Lawson & Hanson's NNLS (*Solving Least Squares
/// Problems*, 1974, ch. 23), minimising `‖A z − r‖`. Returns `z` and the residual norm.
///
/// With `guard`, a column whose least-squares value is not positive right after it entered
/// (round-off: its dual value `a_jᵀ e` was barely positive) is set aside until the passive set
/// changes, instead of entering and leaving again until the iteration limit; Lawson & Hanson's
/// own NNLS code does the same ("reject j as a candidate to be moved from set Z to set P …
/// set w(j) = 0 and loop back to test dual coefficients again").
fn nnls(a: &[Vector4<f64>], r: Vector4<f64>, guard: bool) -> (Vec<f64>, f64) {
    let n = a.len();
    let mut z = vec![0.0; n];
    let mut passive = vec![false; n];
    let mut aside = vec![false; n];
    let ones = vec![1.0; n];
    let resid = |z: &[f64]| -> Vector4<f64> {
        let mut e = r;
        for i in 0..n {
            e -= a[i] * z[i];
        }
        e
    };
    for _ in 0..3 * n + 10 {
        let e = resid(&z);
        let j = (0..n)
            .filter(|&i| !passive[i] && !aside[i])
            .map(|i| (i, a[i].dot(&e)))
            .filter(|&(_, w)| w > 1e-14)
            .max_by(|p, q| p.1.total_cmp(&q.1));
        let Some((j, _)) = j else { break };
        passive[j] = true;
        for first in std::iter::once(true)
            .chain(std::iter::repeat(false))
            .take(3 * n + 10)
        {
            // Least squares on the passive columns: s = A_Pᵀ (A_P A_Pᵀ)⁺ r is the minimum-norm
            // solution; any least-squares solution serves NNLS.
            let y = solve4(a, &ones, &passive, r);
            let s: Vec<f64> = (0..n)
                .map(|i| if passive[i] { a[i].dot(&y) } else { 0.0 })
                .collect();
            if (0..n).all(|i| !passive[i] || s[i] > 0.0) {
                z = s;
                aside.iter_mut().for_each(|x| *x = false);
                break;
            }
            if guard && first && s[j] <= 0.0 {
                passive[j] = false;
                aside[j] = true;
                break;
            }
            let mut alpha = f64::INFINITY;
            for i in 0..n {
                if passive[i] && s[i] <= 0.0 {
                    alpha = alpha.min(z[i] / (z[i] - s[i]));
                }
            }
            for i in 0..n {
                z[i] += alpha * (s[i] - z[i]);
                if passive[i] && z[i] <= 1e-15 {
                    passive[i] = false;
                    z[i] = 0.0;
                }
            }
        }
    }
    let e = resid(&z).norm();
    (z, e)
}

/// Solves for per-disc masses. `prior` are the uniform-density masses `m0_i > 0`; `eps` is the
/// lower bound as a fraction of the prior (`m_i ≥ eps·m0_i`, eps in (0, 1)); `tol` is the largest
/// residual accepted (relative, as in [`Residuals`]).
///
/// Phase 1 finds a feasible point by NNLS (or proves there is none: the residual of the best
/// nonnegative fit stays positive); phase 2 is the primal active-set method, whose steps keep
/// the bounds and the equalities and end at the unique optimum.
///
/// ```
/// use clumpgen::massfit::{fit_masses, MassTargets};
/// // Three equal discs in a row: the middle one must take the mass that makes I = 0.3.
/// let discs = [[-1.0, 0.0, 0.5], [0.0, 0.0, 0.5], [1.0, 0.0, 0.5]];
/// let t = MassTargets { mass: 1.0, inertia: 0.3, length: 1.0 };
/// let (m, res) = fit_masses(&discs, &[1.0 / 3.0; 3], &t, 1e-3, 1e-12).unwrap();
/// assert!(res.max() < 1e-12 && m.iter().all(|&mi| mi > 0.0));
/// ```
pub fn fit_masses(
    xyr: &[[f64; 3]],
    prior: &[f64],
    t: &MassTargets,
    eps: f64,
    tol: f64,
) -> Result<(Vec<f64>, Residuals), MassFitError> {
    match fit_mode(xyr, prior, t, eps, tol, Mode::Plain) {
        Err(MassFitError::Infeasible(plain)) => {
            match fit_mode(xyr, prior, t, eps, tol, Mode::Careful) {
                Err(MassFitError::Infeasible(careful)) => {
                    Err(MassFitError::Infeasible(plain.min(careful)))
                }
                other => other,
            }
        }
        other => other,
    }
}

/// The same problem as [`fit_masses`] (`min Σ (m_i − m0_i)²/m0_i` subject to the four
/// consistency equations), solved as if no bound were active: by the Lagrange conditions the
/// solution is `m_i = m0_i·(1 + a_iᵀλ)`, `a_i = (1, x_i, y_i, r_i²/2 + x_i² + y_i²)`, with the
/// 4×4 system `(Σ m0_i a_i a_iᵀ) λ = b − Σ m0_i a_i` (scaled units as in [`fit_masses`], two
/// rounds of iterative refinement). When every mass is then at least `eps·m0_i` this is the
/// optimum of the bounded problem too (its bound multipliers are zero, so the KKT conditions
/// hold); otherwise `None` and [`fit_masses`] must solve it with the bounds. For many discs
/// that fill a grain evenly (a lattice, `crate::lattice`) the bounds are inactive and this is
/// `O(n)`.
pub fn fit_masses_interior(
    xyr: &[[f64; 3]],
    prior: &[f64],
    t: &MassTargets,
    eps: f64,
    tol: f64,
) -> Option<(Vec<f64>, Residuals)> {
    let n = xyr.len();
    if n == 0 || prior.len() != n {
        return None;
    }
    let l = t.length;
    let a: Vec<Vector4<f64>> = xyr
        .iter()
        .map(|d| {
            let (x, y, r) = (d[0] / l, d[1] / l, d[2] / l);
            Vector4::new(1.0, x, y, 0.5 * r * r + x * x + y * y)
        })
        .collect();
    let b = Vector4::new(1.0, 0.0, 0.0, t.inertia / (t.mass * l * l));
    let psum: f64 = prior.iter().sum();
    let m0: Vec<f64> = prior.iter().map(|p| p / psum).collect();
    let mut k = Matrix4::zeros();
    for i in 0..n {
        k += a[i] * a[i].transpose() * m0[i];
    }
    let lu = k.lu();
    let mut m = m0.clone();
    for _ in 0..3 {
        let mut r = b;
        for i in 0..n {
            r -= a[i] * m[i];
        }
        let y = lu.solve(&r)?;
        for i in 0..n {
            m[i] += m0[i] * a[i].dot(&y);
        }
    }
    // (NaN masses fail too.)
    if !(0..n).all(|i| m[i].is_finite() && m[i] >= eps * m0[i]) {
        return None;
    }
    let masses: Vec<f64> = m.iter().map(|mi| mi * t.mass).collect();
    let res = residuals(xyr, &masses, t);
    (res.max() <= tol).then_some((masses, res))
}

/// [`fit_masses`] without the careful refit: the fit of the versions before 2026-11-27, kept
/// for templates that must not change ([`crate::ClumpParams::rescue`]).
pub fn fit_masses_plain(
    xyr: &[[f64; 3]],
    prior: &[f64],
    t: &MassTargets,
    eps: f64,
    tol: f64,
) -> Result<(Vec<f64>, Residuals), MassFitError> {
    fit_mode(xyr, prior, t, eps, tol, Mode::Plain)
}

/// How the scaled system is set up and solved (see the module docs on conditioning).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Mode {
    /// Inertia row `s_i`, right-hand side `k²`; phase 1 must reach 1e-11.
    Plain,
    /// Inertia row `(s_i − k²)/σ`, right-hand side 0; NNLS with the entering-column guard;
    /// phase 1 hands on residuals up to 1e-8.
    Careful,
}

/// [`fit_masses`] in one [`Mode`].
fn fit_mode(
    xyr: &[[f64; 3]],
    prior: &[f64],
    t: &MassTargets,
    eps: f64,
    tol: f64,
    mode: Mode,
) -> Result<(Vec<f64>, Residuals), MassFitError> {
    let n = xyr.len();
    if n == 0 {
        return Err(MassFitError::NoDiscs);
    }
    let l = t.length;
    // Scaled columns a_i and right-hand side b (masses in units of m_p, lengths in units of l).
    let mut a: Vec<Vector4<f64>> = xyr
        .iter()
        .map(|d| {
            let (x, y, r) = (d[0] / l, d[1] / l, d[2] / l);
            Vector4::new(1.0, x, y, 0.5 * r * r + x * x + y * y)
        })
        .collect();
    let mut b = Vector4::new(1.0, 0.0, 0.0, t.inertia / (t.mass * l * l));
    if mode == Mode::Careful {
        let k2 = b[3];
        let sigma = a.iter().map(|ai| (ai[3] - k2).abs()).fold(0.0, f64::max);
        let sigma = if sigma > 0.0 { sigma } else { 1.0 };
        for ai in &mut a {
            ai[3] = (ai[3] - k2) / sigma;
        }
        b[3] = 0.0;
    }
    let psum: f64 = prior.iter().sum();
    let m0: Vec<f64> = prior.iter().map(|p| p / psum).collect();
    let lb: Vec<f64> = m0.iter().map(|p| eps * p).collect();

    // Phase 1: m = lb + z with A z = b − A lb, z ≥ 0.
    let mut r1 = b;
    for i in 0..n {
        r1 -= a[i] * lb[i];
    }
    let careful = mode == Mode::Careful;
    let (z, res1) = nnls(&a, r1, careful);
    if res1 > if careful { 1e-8 } else { 1e-11 } {
        return Err(MassFitError::Infeasible(res1));
    }
    let mut m: Vec<f64> = (0..n).map(|i| lb[i] + z[i]).collect();
    let mut free: Vec<bool> = z.iter().map(|&zi| zi > 0.0).collect();

    // Phase 2: primal active set (Nocedal & Wright, Algorithm 16.3), H = diag(1/m0).
    for _ in 0..10 * n + 20 {
        let g: Vec<f64> = (0..n).map(|i| (m[i] - m0[i]) / m0[i]).collect();
        let mut rhs = Vector4::zeros();
        for i in 0..n {
            if free[i] {
                rhs += a[i] * (m0[i] * g[i]);
            }
        }
        let lambda = solve4(&a, &m0, &free, rhs);
        let p: Vec<f64> = (0..n)
            .map(|i| {
                if free[i] {
                    -m0[i] * (g[i] - a[i].dot(&lambda))
                } else {
                    0.0
                }
            })
            .collect();
        let pnorm = p.iter().map(|v| v.abs()).fold(0.0, f64::max);
        if pnorm <= 1e-15 {
            // Multipliers of the active bounds: release the most negative one, or stop.
            let release = (0..n)
                .filter(|&i| !free[i])
                .map(|i| (i, g[i] - a[i].dot(&lambda)))
                .filter(|&(_, k)| k < -1e-12)
                .min_by(|p, q| p.1.total_cmp(&q.1));
            match release {
                Some((i, _)) => free[i] = true,
                None => break,
            }
            continue;
        }
        let mut alpha = 1.0;
        let mut block = None;
        for i in 0..n {
            if free[i] && p[i] < 0.0 {
                let ai = (lb[i] - m[i]) / p[i];
                if ai < alpha {
                    alpha = ai;
                    block = Some(i);
                }
            }
        }
        for i in 0..n {
            m[i] += alpha * p[i];
        }
        if let Some(i) = block {
            m[i] = lb[i];
            free[i] = false;
        }
    }
    // Iterative refinement of the equalities on the free set (round-off only).
    for _ in 0..2 {
        let mut r = b;
        for i in 0..n {
            r -= a[i] * m[i];
        }
        let y = solve4(&a, &m0, &free, r);
        for i in 0..n {
            if free[i] {
                m[i] = (m[i] + m0[i] * a[i].dot(&y)).max(lb[i]);
            }
        }
    }
    let masses: Vec<f64> = m.iter().map(|mi| mi * t.mass).collect();
    let res = residuals(xyr, &masses, t);
    let positive = masses.iter().all(|&mi| mi > 0.0 && mi.is_finite());
    if positive && res.max() <= tol {
        Ok((masses, res))
    } else {
        Err(MassFitError::Infeasible(if res.max().is_finite() {
            res.max()
        } else {
            f64::INFINITY
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn single_centred_disc_matches_its_own_inertia() {
        let d = [[0.0, 0.0, 2.0]];
        let t = MassTargets {
            mass: 3.0,
            inertia: 3.0 * 2.0,
            length: 2.0,
        };
        let (m, r) = fit_masses(&d, &[1.0], &t, 1e-3, 1e-12).unwrap();
        assert!((m[0] - 3.0).abs() < 1e-14 && r.max() < 1e-14);
    }

    #[test]
    fn single_disc_cannot_reach_a_larger_inertia() {
        let d = [[0.0, 0.0, 1.0]];
        let t = MassTargets {
            mass: 1.0,
            inertia: 0.6,
            length: 1.0,
        };
        assert!(matches!(
            fit_masses(&d, &[1.0], &t, 1e-3, 1e-9),
            Err(MassFitError::Infeasible(_))
        ));
    }

    #[test]
    fn centroid_outside_the_discs_hull_is_infeasible() {
        // All discs on the right of the origin: Σ m x = 0 needs a negative mass.
        let d = [[1.0, 0.0, 0.3], [2.0, 1.0, 0.3], [2.0, -1.0, 0.3]];
        let t = MassTargets {
            mass: 1.0,
            inertia: 2.0,
            length: 1.0,
        };
        assert!(fit_masses(&d, &[1.0; 3], &t, 1e-3, 1e-9).is_err());
    }

    #[test]
    fn interior_closed_form_is_the_bounded_optimum_when_no_bound_is_active() {
        // A hexagon of discs and one at the centre; the target inertia a little above the
        // uniform masses' inertia, so no mass comes near its floor.
        let mut d = vec![[0.0, 0.0, 0.5]];
        for k in 0..6 {
            let a = k as f64 * std::f64::consts::PI / 3.0 + 0.1;
            d.push([a.cos(), a.sin(), 0.5]);
        }
        let prior = [1.0; 7];
        let t = MassTargets {
            mass: 7.0,
            inertia: 7.0 * 0.85,
            length: 1.0,
        };
        let (mi, ri) = fit_masses_interior(&d, &prior, &t, 1e-3, 1e-12).unwrap();
        let (ma, _) = fit_masses(&d, &prior, &t, 1e-3, 1e-12).unwrap();
        assert!(ri.max() < 1e-14, "{ri:?}");
        for (a, b) in mi.iter().zip(&ma) {
            assert!((a - b).abs() < 1e-9, "{mi:?} vs {ma:?}");
        }
        // Discs on a line: the 4×4 system is singular, no closed form (the caller falls back).
        let line = [[-1.0, 0.0, 0.5], [0.0, 0.0, 0.5], [1.0, 0.0, 0.5]];
        let t = MassTargets {
            mass: 1.0,
            inertia: 0.3,
            length: 1.0,
        };
        assert!(fit_masses_interior(&line, &[1.0; 3], &t, 1e-3, 1e-12).is_none());
        // A target that needs a mass below its floor (the centre disc at 0.035 of its prior,
        // the floor at half of it): none either.
        let t = MassTargets {
            mass: 7.0,
            inertia: 7.0 * 1.12,
            length: 1.0,
        };
        assert!(fit_masses_interior(&d, &prior, &t, 1e-3, 1e-12).is_some());
        assert!(fit_masses_interior(&d, &prior, &t, 0.5, 1e-12).is_none());
    }

    #[test]
    fn bounds_become_active_and_solution_is_kkt() {
        // Many discs, target inertia near the top of the reachable range, so several masses
        // must sit at their lower bound.
        let mut d = vec![];
        for k in 0..16 {
            let th = k as f64 * 0.41;
            let rad = 0.2 + 0.8 * (k as f64 / 15.0);
            d.push([rad * th.cos(), rad * th.sin(), 0.1 + 0.02 * k as f64]);
        }
        let prior = vec![1.0; d.len()];
        let t = MassTargets {
            mass: 2.0,
            inertia: 2.0 * 0.62,
            length: 1.0,
        };
        let eps = 1e-2;
        let (m, r) = fit_masses(&d, &prior, &t, eps, 1e-12).unwrap();
        assert!(r.max() < 1e-12, "{r:?}");
        let lb = eps * 2.0 / d.len() as f64;
        let active = m.iter().filter(|&&mi| (mi - lb).abs() < 1e-12).count();
        assert!(active > 0, "expected active bounds: {m:?}");
        assert!(m.iter().all(|&mi| mi >= lb * (1.0 - 1e-12)));
        // Optimality check against random feasible perturbations: any direction in the null
        // space of A that keeps the bounds must not lower the objective.
        let obj = |mm: &[f64]| -> f64 {
            mm.iter()
                .map(|mi| (mi - 2.0 / 16.0).powi(2) / (2.0 / 16.0))
                .sum()
        };
        let base = obj(&m);
        let a: Vec<[f64; 4]> = d
            .iter()
            .map(|q| {
                [
                    1.0,
                    q[0],
                    q[1],
                    0.5 * q[2] * q[2] + q[0] * q[0] + q[1] * q[1],
                ]
            })
            .collect();
        let mut s = 7u64;
        for _ in 0..200 {
            // Random direction, projected on the null space of A by Gram–Schmidt.
            let mut v: Vec<f64> = (0..16)
                .map(|_| {
                    s = s.wrapping_mul(6364136223846793005).wrapping_add(1);
                    (s >> 11) as f64 / (1u64 << 53) as f64 - 0.5
                })
                .collect();
            let mut basis: Vec<Vec<f64>> = vec![];
            for row in 0..4 {
                let mut u: Vec<f64> = a.iter().map(|ai| ai[row]).collect();
                for bv in &basis {
                    let p: f64 = u.iter().zip(bv).map(|(x, y)| x * y).sum();
                    u.iter_mut().zip(bv).for_each(|(x, y)| *x -= p * y);
                }
                let nrm = u.iter().map(|x| x * x).sum::<f64>().sqrt();
                u.iter_mut().for_each(|x| *x /= nrm);
                basis.push(u);
            }
            for bv in &basis {
                let p: f64 = v.iter().zip(bv).map(|(x, y)| x * y).sum();
                v.iter_mut().zip(bv).for_each(|(x, y)| *x -= p * y);
            }
            let step = 1e-4;
            let trial: Vec<f64> = m.iter().zip(&v).map(|(mi, vi)| mi + step * vi).collect();
            if trial.iter().all(|&mi| mi >= lb) {
                assert!(obj(&trial) >= base - 1e-15, "not optimal");
            }
        }
    }
}
