//! Van der Waals attraction of [`crate::GranularLaw`] (the `vdw` block), from the Hamaker
//! constant A (J) and the surface separation h = −δ (m).
//!
//! Sphere–sphere, exact (Hamaker 1937, Physica 4:1058–1072), with s = h² + 2R₁h + 2R₂h
//! (= d² − (R₁+R₂)², d the centre distance) and s' = s + 4R₁R₂ (= d² − (R₁−R₂)²):
//!
//! * U(h) = −(A/6) [2R₁R₂/s + 2R₁R₂/s' + ln(s/s')];
//! * F(h) = −dU/dh = (A/6) · 64R₁³R₂³(h + R₁ + R₂) / (s² s'²) (attractive, returned ≥ 0).
//!
//! Limits: h ≪ R: U → −AR*/(6h), F → AR*/(6h²) (Derjaguin; Israelachvili 2011,
//! *Intermolecular and Surface Forces*, 3rd ed., table 13.1). d ≫ R: U → −(16/9)AR₁³R₂³/d⁶,
//! F → (32/3)AR₁³R₂³/d⁷ (the London pair sum).
//! Sphere–wall (R₂ → ∞): U = −(A/6)[R/h + R/(h + 2R) + ln(h/(h + 2R))],
//! F = (2/3) A R³ / (h² (h + 2R)²).
//! Two parallel cylinders, per unit length, h ≪ R (Israelachvili 2011, table 13.1):
//! U/L = −A √R* / (12√2 h^{3/2}), F/L = A √R* / (8√2 h^{5/2}).
//!
//! In the law: h_eff = max(h, h_min), so inside contact the attraction is the constant
//! F(h_min). h_min defaults to 0.4 nm ([`H_MIN_DEFAULT`]), a value commonly taken in DEM of
//! fine powders for the separation of touching surfaces (Israelachvili 2011, ch. 13, uses
//! 0.165 nm to match surface energies; set `h_min` to choose). The two-cylinder form is
//! checked here by the Derjaguin integral ∫ −A/(12π(h + y²/2R*)²) dy = −A√(2R*)/(24 h^{3/2}).
//! No force beyond the cut-off h > h_cut (unshifted: F jumps by F(h_cut), which the cut-off
//! should make negligible). Potential tracked with the E flag: V(h) = U(h_eff) − U(h_cut),
//! continued linearly below h_min (V = V(h_min) − F(h_min)(h_min − h)),
//! so −dV/dh is the applied force throughout.
//!
//! A 2D disc takes the sphere–sphere form per contact, as the sphere laws are applied to
//! discs (see `docs/laws.md`); with `length` L given, it takes the parallel-cylinder form
//! × L instead (a disc as a cylinder of thickness L).
//! The exact sphere form needs R₁, R₂: [`crate::GranularLaw::force_pair`] takes them;
//! [`crate::ContactLaw::force`] has only R* and uses R₁ = R₂ = 2R* (exact for equal spheres).

use serde::{Deserialize, Serialize};

/// Default minimum separation h_min (m): 0.4 nm.
pub const H_MIN_DEFAULT: f64 = 4e-10;

/// Exact Hamaker sphere–sphere attraction F(h) ≥ 0 (N).
pub fn sphere_sphere_force(a: f64, r1: f64, r2: f64, h: f64) -> f64 {
    let s = h * h + 2.0 * r1 * h + 2.0 * r2 * h;
    let s2 = s + 4.0 * r1 * r2;
    let r13 = r1 * r1 * r1;
    let r23 = r2 * r2 * r2;
    (a / 6.0) * 64.0 * r13 * r23 * (h + r1 + r2) / (s * s * s2 * s2)
}

/// Exact Hamaker sphere–sphere potential U(h) ≤ 0 (J).
pub fn sphere_sphere_potential(a: f64, r1: f64, r2: f64, h: f64) -> f64 {
    let s = h * h + 2.0 * r1 * h + 2.0 * r2 * h;
    let s2 = s + 4.0 * r1 * r2;
    let rr = 2.0 * r1 * r2;
    // ln(s/s') = −ln(1 + 4R₁R₂/s), with ln_1p for accuracy when s ≫ R₁R₂.
    -(a / 6.0) * (rr / s + rr / s2 - (4.0 * r1 * r2 / s).ln_1p())
}

/// Near-field sphere–sphere attraction A R*/(6h²) (N).
pub fn sphere_sphere_force_near(a: f64, r_eff: f64, h: f64) -> f64 {
    a * r_eff / (6.0 * h * h)
}

/// Sphere–wall attraction (2/3) A R³ / (h²(h + 2R)²) (N).
pub fn sphere_wall_force(a: f64, r: f64, h: f64) -> f64 {
    (2.0 / 3.0) * a * r * r * r / (h * h * (h + 2.0 * r) * (h + 2.0 * r))
}

/// Sphere–wall potential −(A/6)[R/h + R/(h+2R) + ln(h/(h+2R))] (J).
pub fn sphere_wall_potential(a: f64, r: f64, h: f64) -> f64 {
    -(a / 6.0) * (r / h + r / (h + 2.0 * r) - (2.0 * r / h).ln_1p())
}

/// Parallel cylinders, attraction per unit length A√R*/(8√2 h^{5/2}) (N/m).
pub fn cylinders_force_per_length(a: f64, r_eff: f64, h: f64) -> f64 {
    a * r_eff.sqrt() / (8.0 * std::f64::consts::SQRT_2 * h * h * h.sqrt())
}

/// Parallel cylinders, potential per unit length −A√R*/(12√2 h^{3/2}) (J/m).
pub fn cylinders_potential_per_length(a: f64, r_eff: f64, h: f64) -> f64 {
    -a * r_eff.sqrt() / (12.0 * std::f64::consts::SQRT_2 * h * h.sqrt())
}

/// The van der Waals sub-model.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct VanDerWaals {
    /// Hamaker constant A (J).
    pub hamaker: f64,
    /// Minimum separation h_min (m).
    pub h_min: f64,
    /// Cut-off separation h_cut (m), > h_min.
    pub cutoff: f64,
    /// Cylinder length L (m) for the 2D parallel-cylinder form; None: spheres.
    pub length: Option<f64>,
}

impl VanDerWaals {
    fn f_u(&self, r1: f64, r2: f64, h: f64) -> (f64, f64) {
        let a = self.hamaker;
        match self.length {
            None => (
                sphere_sphere_force(a, r1, r2, h),
                sphere_sphere_potential(a, r1, r2, h),
            ),
            Some(l) => {
                let r = r1 * r2 / (r1 + r2);
                (
                    l * cylinders_force_per_length(a, r, h),
                    l * cylinders_potential_per_length(a, r, h),
                )
            }
        }
    }

    /// Attraction (≥ 0, N) and potential V (≤ 0, J; module docs) at overlap `delta` for
    /// radii R₁, R₂.
    pub fn eval(&self, r1: f64, r2: f64, delta: f64) -> (f64, f64) {
        let h = -delta;
        if h > self.cutoff || self.hamaker == 0.0 {
            return (0.0, 0.0);
        }
        let he = h.max(self.h_min);
        let (f, u) = self.f_u(r1, r2, he);
        let (_, u_cut) = self.f_u(r1, r2, self.cutoff);
        let v = u - u_cut - f * (he - h);
        (f, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: f64 = 6.5e-20;

    #[test]
    fn exact_tends_to_derjaguin_near_contact() {
        let (r1, r2) = (1e-6, 3e-6);
        let re = r1 * r2 / (r1 + r2);
        let mut last = f64::INFINITY;
        for &h in &[1e-8, 1e-9, 1e-10, 1e-12] {
            let err = sphere_sphere_force(A, r1, r2, h) / sphere_sphere_force_near(A, re, h) - 1.0;
            println!("h/R* = {:.1e}: exact/near − 1 = {err:.3e}", h / re);
            assert!(err.abs() < 3.0 * h / re && err.abs() < last);
            last = err.abs();
        }
        let h = 1e-12;
        let u = sphere_sphere_potential(A, r1, r2, h);
        // Relative correction O((h/R*) ln(R*/h)) from the logarithm.
        assert!((u / (-A * re / (6.0 * h)) - 1.0).abs() < 2.0 * h / re * (re / h).ln());
    }

    #[test]
    fn exact_tends_to_london_far_away() {
        let (r1, r2) = (1e-6f64, 2e-6f64);
        for &k in &[10.0f64, 100.0, 1000.0] {
            let h = k * (r1 + r2);
            let d = h + r1 + r2;
            let far = 32.0 / 3.0 * A * (r1 * r2).powi(3) / d.powi(7);
            let err = sphere_sphere_force(A, r1, r2, h) / far - 1.0;
            println!(
                "d/(R1+R2) = {:.0}: exact/far − 1 = {err:.3e}",
                d / (r1 + r2)
            );
            // Leading correction O(((R1+R2)/d)²).
            assert!(err.abs() < 5.0 * ((r1 + r2) / d).powi(2));
        }
        let h = 20.0 * (r1 + r2);
        let d = h + r1 + r2;
        let u_far = -16.0 / 9.0 * A * (r1 * r2).powi(3) / d.powi(6);
        assert!((sphere_sphere_potential(A, r1, r2, h) / u_far - 1.0).abs() < 0.02);
    }

    #[test]
    fn forces_are_minus_the_potential_gradients() {
        let (r1, r2) = (1e-6, 2.5e-6);
        for &h in &[1e-9, 1e-8, 1e-7, 1e-6] {
            let dh = h * 1e-5;
            let num = |u: &dyn Fn(f64) -> f64| -(u(h + dh) - u(h - dh)) / (2.0 * dh);
            let fs = num(&|x| sphere_sphere_potential(A, r1, r2, x));
            assert!(
                (fs / -sphere_sphere_force(A, r1, r2, h) - 1.0).abs() < 1e-6,
                "h {h}"
            );
            let fw = num(&|x| sphere_wall_potential(A, r1, x));
            assert!((fw / -sphere_wall_force(A, r1, h) - 1.0).abs() < 1e-6);
            let fc = num(&|x| cylinders_potential_per_length(A, r1, x));
            assert!((fc / -cylinders_force_per_length(A, r1, h) - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn the_wall_is_the_large_sphere_limit() {
        let r = 1e-6;
        for &h in &[1e-9, 1e-7, 1e-5] {
            let big = sphere_sphere_force(A, r, 1e6, h);
            assert!((big / sphere_wall_force(A, r, h) - 1.0).abs() < 1e-5);
        }
        // Near contact the wall is Derjaguin with R* = R.
        let h = 1e-12;
        assert!(
            (sphere_wall_force(A, r, h) / sphere_sphere_force_near(A, r, h) - 1.0).abs() < 1e-5
        );
    }

    #[test]
    fn law_saturates_below_h_min_and_cuts_off() {
        let v = VanDerWaals {
            hamaker: A,
            h_min: H_MIN_DEFAULT,
            cutoff: 1e-7,
            length: None,
        };
        let (r1, r2) = (1e-6, 1e-6);
        let (f0, _) = v.eval(r1, r2, -H_MIN_DEFAULT);
        assert_eq!(v.eval(r1, r2, 1e-8).0, f0);
        assert_eq!(v.eval(r1, r2, -1.01e-7), (0.0, 0.0));
        // V is continuous at h_min and 0 at the cut-off.
        let (_, va) = v.eval(r1, r2, -H_MIN_DEFAULT * (1.0 + 1e-9));
        let (_, vb) = v.eval(r1, r2, -H_MIN_DEFAULT * (1.0 - 1e-9));
        assert!((va - vb).abs() < 1e-8 * va.abs());
        assert!(v.eval(r1, r2, -1e-7).1.abs() < 1e-30);
    }
}
