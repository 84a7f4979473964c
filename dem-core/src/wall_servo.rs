//! Stress-controlled walls: the numerical servo of PFC's biaxial test (Itasca, PFC2D manual,
//! "biaxial test" example; Potyondy & Cundall 2004, "A bonded-particle model for rock",
//! Int. J. Rock Mech. Min. Sci. 41:1329-1364, §3, confined tests), which holds a wall's normal
//! stress at a target σ_req while the specimen deforms.
//!
//! Each step, from the force F the discs exerted on the wall in that step and the sum K of the
//! normal stiffnesses of its touching contacts, the wall's speed toward the specimen (along the
//! unit `direction`) for the next step is
//!
//! ```text
//! σ = −F·d / (L t)                     measured normal stress (compression positive)
//! u̇ = G (σ_req − σ),  G = α L t / (K Δt)   (PFC: G = α A / (k_n N_c Δt))
//! ```
//!
//! clamped to ±`max_speed`. With α < 1 the stress error of one step shrinks by the factor
//! 1 − α if the specimen were rigid behind the wall (the wall's displacement u̇Δt changes the
//! contact forces by K u̇ Δt = α L t (σ_req − σ)); PFC uses α = 0.5. A wall without contacts
//! (K = 0) approaches at `max_speed` when σ_req > 0 and stays when σ_req = 0.
//!
//! K counts springs only: with a contact dashpot c the wall's own speed changes its force by
//! c Δu̇, which the gain ignores, and a stiff dashpot makes the servo chatter between ±the speed
//! limit (seen in `tests/wall_servo.rs` with a damping ratio 0.7). Servo scenes damp locally,
//! as PFC's biaxial test and the lab's scenes do.

use serde::{Deserialize, Serialize};

/// A servo on a wall (SI): target normal stress, the loaded length the stress is measured
/// over, the unit direction of approach, relaxation factor α and speed limit.
#[derive(Clone, Copy, Debug, Serialize, Deserialize, PartialEq)]
pub struct WallServo {
    /// Target normal stress σ_req (Pa, compression positive).
    pub stress: f64,
    /// Loaded length L (m): the stress is F/(L t).
    pub length: f64,
    /// Unit vector of the wall's motion toward the specimen.
    pub direction: [f64; 2],
    /// Relaxation factor α in (0, 1].
    pub alpha: f64,
    /// Largest speed (m/s).
    pub max_speed: f64,
}

impl WallServo {
    /// The measured normal stress (Pa, compression positive) of a wall on which the discs
    /// exert `force` (N), for disc thickness `thickness` (m).
    pub fn stress_of(&self, force: [f64; 2], thickness: f64) -> f64 {
        -(force[0] * self.direction[0] + force[1] * self.direction[1]) / (self.length * thickness)
    }

    /// The wall's velocity for the next step (m/s) from this step's `force` (N) and contact
    /// stiffness sum `stiffness` (N/m); `dt` the step (s), `thickness` t (m).
    pub fn velocity(&self, force: [f64; 2], stiffness: f64, dt: f64, thickness: f64) -> [f64; 2] {
        let err = self.stress - self.stress_of(force, thickness);
        let speed = if stiffness > 0.0 {
            let gain = self.alpha * self.length * thickness / (stiffness * dt);
            (gain * err).clamp(-self.max_speed, self.max_speed)
        } else if self.stress > 0.0 {
            self.max_speed
        } else {
            0.0
        };
        [speed * self.direction[0], speed * self.direction[1]]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn servo(alpha: f64) -> WallServo {
        WallServo {
            stress: 2e6,
            length: 0.01,
            direction: [1.0, 0.0],
            alpha,
            max_speed: 1e3,
        }
    }

    /// Against a rigid spring bed of stiffness K behind the wall, each step shrinks the stress
    /// error by 1 − α exactly (the closed form of the update).
    #[test]
    fn the_error_shrinks_by_one_minus_alpha_each_step() {
        let (k, dt, t) = (5e8, 1e-7, 0.002);
        for alpha in [0.25, 0.5, 1.0] {
            let s = servo(alpha);
            let mut x = 0.0; // wall penetration into the bed (m)
            let mut err0 = s.stress;
            for _ in 0..20 {
                // The bed pushes the wall back: force on the wall along −direction.
                let force = [-k * x, 0.0];
                let err = s.stress - s.stress_of(force, t);
                assert!(
                    (err - err0).abs() <= 1e-9 * s.stress,
                    "α {alpha}: error {err}, expected {err0}"
                );
                let v = s.velocity(force, k, dt, t);
                x += v[0] * dt;
                err0 = err * (1.0 - alpha);
            }
        }
    }

    #[test]
    fn clamped_and_idle_without_contacts() {
        let mut s = servo(0.5);
        s.max_speed = 0.1;
        assert_eq!(s.velocity([0.0; 2], 0.0, 1e-7, 1.0), [0.1, 0.0]);
        // Far above the target: backs off at the limit.
        assert_eq!(s.velocity([-1e9, 0.0], 1e3, 1e-7, 1.0), [-0.1, 0.0]);
        s.stress = 0.0;
        assert_eq!(s.velocity([0.0; 2], 0.0, 1e-7, 1.0), [0.0, 0.0]);
    }
}
