//! Walls: infinite planes (a point and a unit normal pointing into the domain, optionally
//! translating at a constant velocity) and the box of six planes.
//!
//! Sphere–plane contact (as LAMMPS `fix wall/gran`): the wall is body i, the sphere body j,
//! n the plane's normal, the gap s = (x − p)·n, the overlap δ = r − s, and the same law as a
//! sphere pair with R* = r, m* = m (the wall is infinitely large and heavy). The sphere's
//! arm to the contact point is r − δ/2 (LAMMPS `dist_to_contact`), the relative velocity
//! v_rel = v − u − (r − δ/2) ω × n with u the wall's velocity. Van der Waals takes the
//! sphere–sphere Hamaker form at R₂ = 10⁹ r, the sphere–wall limit within 10⁻⁹.

use crate::error::{finite3, SphereError};
use nalgebra::Vector3;

/// An infinite plane wall.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plane {
    /// A point of the plane (m), at the time of the last step.
    pub point: Vector3<f64>,
    /// Unit normal pointing into the domain (towards the spheres it holds).
    pub normal: Vector3<f64>,
    /// Translation velocity (m/s), constant.
    pub velocity: Vector3<f64>,
}

impl Plane {
    /// A fixed plane through `point` with normal `normal` (normalised here).
    pub fn new(point: Vector3<f64>, normal: Vector3<f64>) -> Result<Plane, SphereError> {
        finite3("plane.point", &point)?;
        finite3("plane.normal", &normal)?;
        let l = normal.norm();
        if l.is_nan() || l <= 0.0 {
            return Err(SphereError::invalid(
                "plane.normal",
                "must be a non-zero vector, got (0, 0, 0)",
            ));
        }
        Ok(Plane {
            point,
            normal: normal / l,
            velocity: Vector3::zeros(),
        })
    }

    /// The same plane translating at `u`.
    pub fn moving(mut self, u: Vector3<f64>) -> Plane {
        self.velocity = u;
        self
    }

    /// Signed distance of `x` from the plane along the normal.
    pub fn gap(&self, x: &Vector3<f64>) -> f64 {
        (x - self.point).dot(&self.normal)
    }
}

/// The six planes of the box [lo, hi] with normals pointing inwards, in the order
/// −x, +x, −y, +y, −z (floor), +z (lid).
pub fn box_walls(lo: Vector3<f64>, hi: Vector3<f64>) -> Result<Vec<Plane>, SphereError> {
    finite3("box.lo", &lo)?;
    finite3("box.hi", &hi)?;
    for k in 0..3 {
        if hi[k] <= lo[k] {
            return Err(SphereError::invalid(
                "box.hi",
                format!(
                    "must exceed box.lo on every axis, axis {k}: {} ≤ {}",
                    hi[k], lo[k]
                ),
            ));
        }
    }
    let mut w = Vec::with_capacity(6);
    for k in 0..3 {
        let e = Vector3::ith(k, 1.0);
        w.push(Plane::new(lo, e)?);
        w.push(Plane::new(hi, -e)?);
    }
    Ok(w)
}
