//! An exact two-body impact: one sphere (or disc) against a second one or a rigid wall,
//! integrated with small steps through a law of this crate, for benchmarks against closed
//! forms (Chung & Ooi 2011, Granular Matter 13:643, tests 1–8).
//!
//! The integrator is velocity Verlet with rotation, the form of LAMMPS `fix nve/sphere`: half
//! kick of velocity and spin with the last force and torque, drift, force of the new
//! configuration (the law sees the half-step velocities, so its tangential spring integrates
//! v_t at mid-step), second half kick. The step should be t_c/2000 or finer: with Hertz, the
//! rebound velocity is then exact to about 1e-6 and the contact time to dt/t_c (the end of the
//! contact is interpolated within its last step).
//!
//! Geometry of the contact: the unit normal n points from body 1's centre towards the partner
//! (the second sphere's centre, or the foot of the perpendicular on the wall); overlap
//! δ = r₁ + r₂ − |x₂ − x₁| (sphere) or r₁ − (x_w − x₁)·n (wall); contact arms a₁ = r₁ n and
//! a₂ = −r₂ n, the undeformed radii (rigid-body impact theory uses them too). The relative
//! velocity of the partner's contact point with respect to body 1's is
//! v = v₂ + ω₂ × a₂ − v₁ − ω₁ × a₁: v_n = v·n, v_t = v − v_n n. The law returns the force F on
//! the partner (F_n along n, F_t in the tangent plane); body 1 receives −F, and the torques are
//! a₁ × (−F) and a₂ × F. A rigid wall is the limit E_wall → ∞ (build the law with the wall
//! term of E*, G* dropped) of infinite mass: m* = m₁, R* = r₁.
//!
//! 3D ([`Vector3`] tangent): the tangential history is brought into the tangent plane of the
//! new normal with [`rotate_history`] every step. 2D (`f64` tangent, discs in the x–y plane,
//! spin about z): the tangent is t = (−n_y, n_x) and the scalar history is carried unchanged
//! (the exact rotation of the shear vector with the normal, see [`crate::Tangent`]). A disc's
//! inertia is ½ m r² (K = 1 + m r²/I = 3), a solid sphere's ⅖ m r² (K = 7/2); the body carries
//! its own inertia, so either can be run with either tangent.

use crate::{rotate_history, HertzMindlin, Kin, LinearSpringDashpot, Out, Tangent};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// A rigid sphere or disc: size, mass, inertia and state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Body {
    /// Radius r (m).
    pub radius: f64,
    /// Mass m (kg).
    pub mass: f64,
    /// Moment of inertia about a diameter (sphere) or the axis (disc), kg m².
    pub inertia: f64,
    /// Centre (m).
    pub position: Vector3<f64>,
    /// Velocity of the centre (m/s).
    pub velocity: Vector3<f64>,
    /// Angular velocity (rad/s).
    pub spin: Vector3<f64>,
}

impl Body {
    /// A solid sphere of density ρ at rest at the origin: m = (4/3)πr³ρ, I = (2/5) m r².
    pub fn sphere(radius: f64, density: f64) -> Body {
        let mass = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3) * density;
        Body {
            radius,
            mass,
            inertia: 0.4 * mass * radius * radius,
            position: Vector3::zeros(),
            velocity: Vector3::zeros(),
            spin: Vector3::zeros(),
        }
    }

    /// A disc of the given mass at rest at the origin: I = ½ m r².
    pub fn disc(radius: f64, mass: f64) -> Body {
        Body {
            radius,
            mass,
            inertia: 0.5 * mass * radius * radius,
            position: Vector3::zeros(),
            velocity: Vector3::zeros(),
            spin: Vector3::zeros(),
        }
    }

    /// K = 1 + m r²/I of rigid-body impact theory (7/2 for a solid sphere, 3 for a disc).
    pub fn k_factor(&self) -> f64 {
        1.0 + self.mass * self.radius * self.radius / self.inertia
    }

    /// The same body at `position` moving with `velocity` and spinning with `spin`.
    pub fn at(self, position: Vector3<f64>, velocity: Vector3<f64>, spin: Vector3<f64>) -> Body {
        Body {
            position,
            velocity,
            spin,
            ..self
        }
    }
}

/// What body 1 hits.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Partner {
    /// A second free body.
    Body(Body),
    /// A fixed rigid plane through `point` with unit `normal` pointing to body 1's side.
    Wall {
        point: Vector3<f64>,
        normal: Vector3<f64>,
    },
}

/// The contact law of the impact, driven through its inherent `force` method.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub enum Law {
    HertzMindlin(HertzMindlin),
    Linear(LinearSpringDashpot),
}

impl Law {
    fn force<T: Tangent>(&self, k: &Kin<T>, us: &mut T) -> Out<T> {
        match self {
            Law::HertzMindlin(l) => l.force::<false, T>(k, us),
            Law::Linear(l) => l.force::<false, T>(k, us),
        }
    }
}

/// The tangent types the impact runs with: how a tangent value maps to a 3D vector and how the
/// history follows the normal.
pub trait ImpactTangent: Tangent {
    /// The tangent component(s) of the 3D vector `v` for the unit normal `n`.
    fn from_vector(v: Vector3<f64>, n: Vector3<f64>) -> Self;
    /// The 3D vector of the tangent value for the unit normal `n`.
    fn to_vector(self, n: Vector3<f64>) -> Vector3<f64>;
    /// The history carried into the tangent plane of the new normal `n`.
    fn carry(self, n: Vector3<f64>) -> Self;
}

/// 2D: t = (−n_y, n_x, 0).
fn t2(n: Vector3<f64>) -> Vector3<f64> {
    Vector3::new(-n.y, n.x, 0.0)
}

impl ImpactTangent for f64 {
    fn from_vector(v: Vector3<f64>, n: Vector3<f64>) -> f64 {
        Vector3::dot(&v, &t2(n))
    }
    fn to_vector(self, n: Vector3<f64>) -> Vector3<f64> {
        t2(n) * self
    }
    fn carry(self, _n: Vector3<f64>) -> f64 {
        self
    }
}

impl ImpactTangent for Vector3<f64> {
    fn from_vector(v: Vector3<f64>, n: Vector3<f64>) -> Vector3<f64> {
        v - n * Vector3::dot(&n, &v)
    }
    fn to_vector(self, _n: Vector3<f64>) -> Vector3<f64> {
        self
    }
    fn carry(self, n: Vector3<f64>) -> Vector3<f64> {
        rotate_history(self, n)
    }
}

/// One impact to integrate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    pub body: Body,
    pub partner: Partner,
    pub law: Law,
    /// Time step (s).
    pub dt: f64,
    /// Record every n-th step in the trace (0: no trace).
    pub trace_every: usize,
    /// Stop after this many steps even if the bodies still touch.
    pub max_steps: u64,
}

/// One recorded step of the contact.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct TracePoint {
    /// Time since first touch (s).
    pub t: f64,
    /// Overlap δ (m).
    pub overlap: f64,
    /// Normal force F_n (N, positive repulsive).
    pub force: f64,
    /// Magnitude of the tangential force (N).
    pub tangential: f64,
}

/// What an impact gives.
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// The bodies separated (δ ≤ 0 after contact) within `max_steps`.
    pub separated: bool,
    /// Contact duration (s): from the first step with δ > 0 back to δ = 0, the end
    /// interpolated linearly within its last step.
    pub contact_time: f64,
    /// Largest normal force (N) and overlap (m) during the contact.
    pub max_force: f64,
    pub max_overlap: f64,
    /// Body 1 and the partner after the impact (the partner unchanged for a wall).
    pub body: Body,
    pub partner: Partner,
    /// The normal at the end of the contact (from body 1 to the partner).
    pub normal: Vector3<f64>,
    /// Steps integrated.
    pub steps: u64,
    pub trace: Vec<TracePoint>,
}

impl Outcome {
    /// Relative velocity of the partner's contact point with respect to body 1's, at the end.
    pub fn relative_contact_velocity(&self) -> Vector3<f64> {
        contact_velocity(&self.body, &self.partner, self.normal)
    }
}

fn contact_velocity(b: &Body, p: &Partner, n: Vector3<f64>) -> Vector3<f64> {
    let v1 = b.velocity + b.spin.cross(&(n * b.radius));
    let v2 = match p {
        Partner::Body(q) => q.velocity + q.spin.cross(&(-n * q.radius)),
        Partner::Wall { .. } => Vector3::zeros(),
    };
    v2 - v1
}

/// Normal (from body 1 to the partner), overlap, effective mass and radius.
fn geometry(b: &Body, p: &Partner) -> (Vector3<f64>, f64, f64, f64) {
    match p {
        Partner::Body(q) => {
            let d = q.position - b.position;
            let dist = Vector3::norm(&d);
            (
                d / dist,
                b.radius + q.radius - dist,
                b.mass * q.mass / (b.mass + q.mass),
                b.radius * q.radius / (b.radius + q.radius),
            )
        }
        Partner::Wall { point, normal } => {
            let h = Vector3::dot(&(b.position - point), normal);
            (-*normal, b.radius - h, b.mass, b.radius)
        }
    }
}

/// Integrates the impact until the bodies separate (or `max_steps`), with tangent type `T`.
pub fn run<T: ImpactTangent>(imp: &Impact) -> Outcome {
    let dt = imp.dt;
    let mut b = imp.body;
    let mut p = imp.partner;
    let mut us = T::zero();
    let mut trace = vec![];
    let (mut f1, mut t1) = (Vector3::zeros(), Vector3::zeros());
    let (mut f2, mut t2v) = (Vector3::zeros(), Vector3::zeros());
    let (mut max_force, mut max_overlap) = (0.0f64, 0.0f64);
    let mut touched = false;
    let (mut t_start, mut t_end) = (f64::NAN, f64::NAN);
    let mut prev_delta = geometry(&b, &p).1;
    let mut normal = geometry(&b, &p).0;
    let mut steps = 0u64;
    let mut separated = false;
    while steps < imp.max_steps {
        // First half kick and drift.
        b.velocity += f1 * (0.5 * dt / b.mass);
        b.spin += t1 * (0.5 * dt / b.inertia);
        b.position += b.velocity * dt;
        if let Partner::Body(q) = &mut p {
            q.velocity += f2 * (0.5 * dt / q.mass);
            q.spin += t2v * (0.5 * dt / q.inertia);
            q.position += q.velocity * dt;
        }
        steps += 1;
        let t = steps as f64 * dt;
        let (n, delta, m_eff, r_eff) = geometry(&b, &p);
        normal = n;
        f1 = Vector3::zeros();
        t1 = Vector3::zeros();
        f2 = Vector3::zeros();
        t2v = Vector3::zeros();
        if delta > 0.0 {
            if !touched {
                touched = true;
                // Interpolated first touch.
                t_start = t - dt * delta / (delta - prev_delta).max(f64::MIN_POSITIVE);
                t_start = t_start.max(t - dt);
            }
            us = us.carry(n);
            let v = contact_velocity(&b, &p, n);
            let vn = Vector3::dot(&v, &n);
            let k = Kin {
                delta,
                vn,
                vt: T::from_vector(v - n * vn, n),
                m_eff,
                r_eff,
                dt,
            };
            let out = imp.law.force::<T>(&k, &mut us);
            let f = n * out.f_n + out.f_t.to_vector(n);
            f1 = -f;
            t1 = (n * b.radius).cross(&(-f));
            if let Partner::Body(q) = &p {
                f2 = f;
                t2v = (-n * q.radius).cross(&f);
            }
            max_force = max_force.max(out.f_n);
            max_overlap = max_overlap.max(delta);
            if imp.trace_every > 0 && steps.is_multiple_of(imp.trace_every as u64) {
                trace.push(TracePoint {
                    t: t - t_start,
                    overlap: delta,
                    force: out.f_n,
                    tangential: out.f_t.norm(),
                });
            }
        } else if touched {
            t_end = t - dt * (-delta) / (prev_delta - delta).max(f64::MIN_POSITIVE);
            separated = true;
        }
        // Second half kick.
        b.velocity += f1 * (0.5 * dt / b.mass);
        b.spin += t1 * (0.5 * dt / b.inertia);
        if let Partner::Body(q) = &mut p {
            q.velocity += f2 * (0.5 * dt / q.mass);
            q.spin += t2v * (0.5 * dt / q.inertia);
        }
        prev_delta = delta;
        if separated {
            break;
        }
    }
    if imp.trace_every > 0 && separated {
        trace.push(TracePoint {
            t: t_end - t_start,
            overlap: 0.0,
            force: 0.0,
            tangential: 0.0,
        });
    }
    Outcome {
        separated,
        contact_time: t_end - t_start,
        max_force,
        max_overlap,
        body: b,
        partner: p,
        normal,
        steps,
        trace,
    }
}

/// Hertz's closed forms for a normal impact at approach speed v (Johnson, *Contact Mechanics*
/// 1985, §11.4; Chung & Ooi 2011 eqs. for tests 1–2): δ_max = (15 m* v²/(16 E* √R*))^{2/5},
/// F_max = (4/3) E* √R* δ_max^{3/2} and t_c = 2 (δ_max/v) ∫₀¹ dx/√(1 − x^{5/2})
/// = 2.943275 δ_max/v = 2.868266 (m*²/(R* E*² v))^{1/5}, the integral being
/// (2/5) B(2/5, 1/2) = 1.4716376.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct HertzImpact {
    pub max_overlap: f64,
    pub max_force: f64,
    pub contact_time: f64,
}

/// 2 ∫₀¹ dx/√(1 − x^{5/2}) = (4/5) Γ(2/5) Γ(1/2)/Γ(9/10).
pub const HERTZ_TIME_FACTOR: f64 = 2.943_275_184_324_705;

impl HertzImpact {
    pub fn new(m_eff: f64, r_eff: f64, e_star: f64, v: f64) -> HertzImpact {
        let d = (15.0 * m_eff * v * v / (16.0 * e_star * r_eff.sqrt())).powf(0.4);
        HertzImpact {
            max_overlap: d,
            max_force: 4.0 / 3.0 * e_star * r_eff.sqrt() * d.powf(1.5),
            contact_time: HERTZ_TIME_FACTOR * d / v,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn glass_pair(v: f64) -> (Impact, HertzImpact) {
        let law = HertzMindlin::from_materials(4.8e10, 0.2, 4.8e10, 0.2, 1.0, 0.35);
        let s = Body::sphere(0.01, 2800.0);
        let b1 = s.at(
            Vector3::new(-0.01, 0.0, 0.0),
            Vector3::new(v, 0.0, 0.0),
            Vector3::zeros(),
        );
        let b2 = s.at(
            Vector3::new(0.01, 0.0, 0.0),
            Vector3::new(-v, 0.0, 0.0),
            Vector3::zeros(),
        );
        let h = HertzImpact::new(0.5 * s.mass, 0.005, law.e_star, 2.0 * v);
        (
            Impact {
                body: b1,
                partner: Partner::Body(b2),
                law: Law::HertzMindlin(law),
                dt: h.contact_time / 2000.0,
                trace_every: 0,
                max_steps: 100_000,
            },
            h,
        )
    }

    #[test]
    fn an_elastic_hertz_impact_matches_the_closed_form() {
        let (imp, h) = glass_pair(10.0);
        let o = run::<Vector3<f64>>(&imp);
        assert!(o.separated);
        assert!((o.max_force / h.max_force - 1.0).abs() < 1e-4);
        assert!((o.max_overlap / h.max_overlap - 1.0).abs() < 1e-4);
        assert!((o.contact_time / h.contact_time - 1.0).abs() < 2e-3);
        assert!((o.body.velocity.x + 10.0).abs() < 1e-4);
    }

    #[test]
    fn the_2d_and_3d_runs_agree_on_a_normal_impact() {
        let (imp, _) = glass_pair(10.0);
        let a = run::<Vector3<f64>>(&imp);
        let b = run::<f64>(&imp);
        assert!((a.max_force - b.max_force).abs() <= 1e-9 * a.max_force);
    }
}
