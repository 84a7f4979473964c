//! The tangential history of a contact, a scalar in 2D and a vector in 3D.
//!
//! A law is written once over [`Tangent`]: in 2D the tangent plane of a disc–disc contact is
//! a line, so the shear displacement u_s and the tangential velocity v_t are scalars along
//! t = (−n_y, n_x) and carrying the scalar from step to step is the exact rotation of the
//! shear vector with the contact normal (Cundall & Strack 1979, Géotechnique 29:47). In 3D
//! they are vectors in the plane normal to n; the history must be brought into the new
//! tangent plane each step before the law updates it ([`rotate_history`], the rule of
//! LAMMPS `pair_style granular` and LIGGGHTS: project out the normal part and restore the
//! length).
//!
//! Every operation a law needs is here, with the 2D forms written so that the 2D solver's
//! arithmetic is exactly what it was before the laws moved here (`copysign` for the Coulomb
//! limit, not `x · (max/|x|)`): the benchmark digests of `dem bench` pin that.

use nalgebra::Vector3;

/// Shear displacement / tangential velocity / tangential force of one contact.
pub trait Tangent: Copy + Default + core::fmt::Debug + PartialEq {
    /// The zero vector.
    fn zero() -> Self {
        Self::default()
    }
    /// `self + s · v`.
    fn add_scaled(self, v: Self, s: f64) -> Self;
    /// `s · self`.
    fn scale(self, s: f64) -> Self;
    /// `self / d`.
    fn div(self, d: f64) -> Self;
    /// Euclidean length |self|.
    fn norm(self) -> f64;
    /// Dot product.
    fn dot(self, o: Self) -> f64;
    /// The vector of length `max ≥ 0` along `self` (the Coulomb-limited force); the zero
    /// vector if `self` is zero. In 2D `max.copysign(self)`.
    fn with_length(self, max: f64) -> Self;
}

impl Tangent for f64 {
    #[inline(always)]
    fn add_scaled(self, v: f64, s: f64) -> f64 {
        self + v * s
    }
    #[inline(always)]
    fn scale(self, s: f64) -> f64 {
        s * self
    }
    #[inline(always)]
    fn div(self, d: f64) -> f64 {
        self / d
    }
    #[inline(always)]
    fn norm(self) -> f64 {
        self.abs()
    }
    #[inline(always)]
    fn dot(self, o: f64) -> f64 {
        self * o
    }
    #[inline(always)]
    fn with_length(self, max: f64) -> f64 {
        max.copysign(self)
    }
}

impl Tangent for Vector3<f64> {
    #[inline(always)]
    fn add_scaled(self, v: Self, s: f64) -> Self {
        self + v * s
    }
    #[inline(always)]
    fn scale(self, s: f64) -> Self {
        self * s
    }
    #[inline(always)]
    fn div(self, d: f64) -> Self {
        self / d
    }
    #[inline(always)]
    fn norm(self) -> f64 {
        Vector3::norm(&self)
    }
    #[inline(always)]
    fn dot(self, o: Self) -> f64 {
        Vector3::dot(&self, &o)
    }
    #[inline(always)]
    fn with_length(self, max: f64) -> Self {
        let l = Vector3::norm(&self);
        if l > 0.0 {
            self * (max / l)
        } else {
            Vector3::zeros()
        }
    }
}

/// Bring a 3D shear history into the tangent plane of the current unit normal `n`: remove
/// its normal component and rescale it to its former length (LAMMPS `pair_style granular`,
/// `fix wall/gran`; Luding 2008, Granular Matter 10:235, §2.3 uses the same rotation).
#[inline]
pub fn rotate_history(us: Vector3<f64>, n: Vector3<f64>) -> Vector3<f64> {
    let l0 = Vector3::norm(&us);
    let p = us - n * Vector3::dot(&n, &us);
    let l1 = Vector3::norm(&p);
    if l1 > 0.0 {
        p * (l0 / l1)
    } else {
        Vector3::zeros()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn the_2d_coulomb_limit_is_copysign() {
        assert_eq!((-3.0f64).with_length(2.0), -2.0);
        assert_eq!(3.0f64.with_length(2.0), 2.0);
        assert_eq!(Tangent::norm(-4.0f64), 4.0);
    }

    #[test]
    fn the_3d_limit_keeps_the_direction() {
        let v = Vector3::new(3.0, 4.0, 0.0).with_length(10.0);
        assert_relative_eq!(v, Vector3::new(6.0, 8.0, 0.0), epsilon = 1e-12);
        assert_eq!(Vector3::zeros().with_length(1.0), Vector3::<f64>::zeros());
    }

    #[test]
    fn a_rotated_history_is_tangent_and_keeps_its_length() {
        let n = Vector3::new(1.0, 1.0, 0.0).normalize();
        let us = Vector3::new(0.0, 2.0, 1.0);
        let r = rotate_history(us, n);
        assert_relative_eq!(Vector3::dot(&r, &n), 0.0, epsilon = 1e-15);
        assert_relative_eq!(Vector3::norm(&r), Vector3::norm(&us), epsilon = 1e-14);
    }
}
