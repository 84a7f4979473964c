//! The state of the spheres, structure of arrays, apart from the step's scratch.

use nalgebra::Vector3;

/// Sphere state as structure of arrays: index `i` is sphere `i` in every column (the id the
/// contact histories are keyed by).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Spheres {
    /// Centre positions x (m).
    pub x: Vec<Vector3<f64>>,
    /// Velocities v (m/s).
    pub v: Vec<Vector3<f64>>,
    /// Angular velocities ω (rad/s).
    pub w: Vec<Vector3<f64>>,
    /// Radii r (m).
    pub r: Vec<f64>,
    /// Masses m (kg).
    pub m: Vec<f64>,
    /// Moments of inertia I = (2/5) m r² (kg·m², solid spheres).
    pub inertia: Vec<f64>,
    /// Species (index into the law table, [`crate::Laws`]).
    pub species: Vec<u16>,
}

impl Spheres {
    /// Number of spheres.
    pub fn len(&self) -> usize {
        self.r.len()
    }

    /// No spheres.
    pub fn is_empty(&self) -> bool {
        self.r.is_empty()
    }

    /// Append a sphere (unchecked: [`crate::World::add_sphere`] checks).
    pub(crate) fn push(&mut self, x: Vector3<f64>, v: Vector3<f64>, r: f64, m: f64, s: u16) {
        self.x.push(x);
        self.v.push(v);
        self.w.push(Vector3::zeros());
        self.r.push(r);
        self.m.push(m);
        self.inertia.push(0.4 * m * r * r);
        self.species.push(s);
    }

    /// Largest and smallest radius ((0, 0) when empty).
    pub fn radius_range(&self) -> (f64, f64) {
        let mut lo = f64::INFINITY;
        let mut hi = 0.0f64;
        for &r in &self.r {
            lo = lo.min(r);
            hi = hi.max(r);
        }
        if self.r.is_empty() {
            (0.0, 0.0)
        } else {
            (lo, hi)
        }
    }
}

/// What one force pass leaves per sphere (the step's scratch, rebuilt every step).
#[derive(Clone, Debug, Default)]
pub(crate) struct Scratch {
    /// Contact force on each sphere (N), gravity not included.
    pub f: Vec<Vector3<f64>>,
    /// Contact torque (N·m).
    pub t: Vec<Vector3<f64>>,
    /// Dashpot part of `f` and `t` (energy tracking only).
    pub df: Vec<Vector3<f64>>,
    pub dt: Vec<Vector3<f64>>,
    /// Power of the wall forces on the sphere at the walls' velocities, Σ F·u (W).
    pub wall_power: Vec<f64>,
    /// Strain energy and slip work of the sphere's wall contacts (J).
    pub wall_strain: Vec<f64>,
    pub wall_fric: Vec<f64>,
    /// Positions at the last neighbour-list build.
    pub x_build: Vec<Vector3<f64>>,
}

impl Scratch {
    pub fn resize(&mut self, n: usize) {
        let z = Vector3::zeros();
        for c in [&mut self.f, &mut self.t, &mut self.df, &mut self.dt] {
            c.resize(n, z);
        }
        for c in [
            &mut self.wall_power,
            &mut self.wall_strain,
            &mut self.wall_fric,
        ] {
            c.resize(n, 0.0);
        }
    }
}
