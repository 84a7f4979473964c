//! Blow-up guard: checks at output intervals that the state is finite, no disc travels more
//! than [`MAX_TRAVEL_PER_STEP`] of its radius in one step, overlaps are moderate and the
//! kinetic energy has not grown beyond the energy supplied. [`World::guard`] keeps a
//! copy of the last state that passed ([`World::last_good`]) so a failed run can save it.

use crate::neighbors::{closest_on_wall, MinImage};
use crate::pipeline::World;

/// Largest travel of a disc in one time step, as a fraction of its radius. An explicit DEM
/// step resolves a contact over many steps (at the critical step a disc crosses a contact's
/// overlap range in ~π/(2·0.3) ≈ 5 steps); a disc that moves half its radius in one step
/// has left the regime where contacts are detected and integrated (a velocity of 1e200 given
/// in a scene, or a blow-up), long before any value overflows.
pub const MAX_TRAVEL_PER_STEP: f64 = 0.5;

/// Why the guard stopped a run. Each names the step, the disc (stable id) and a likely cause.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GuardError {
    #[error("step {step}: disc {disc}: {field} is not finite; likely cause: {cause}")]
    NonFinite {
        step: u64,
        disc: u32,
        field: &'static str,
        cause: String,
    },
    #[error(
        "step {step}: disc {disc}: speed {speed:.4e} m/s moves it {fraction:.3e} of its radius \
         per step (limit {limit}); likely cause: {cause}"
    )]
    Speed {
        step: u64,
        disc: u32,
        speed: f64,
        fraction: f64,
        limit: f64,
        cause: String,
    },
    #[error(
        "step {step}: {pair}: overlap is {fraction:.3} of {} (limit {limit}); likely cause: \
         {cause}",
        if *.other == u32::MAX { "the disc's radius" } else { "the smaller radius" }
    )]
    Overlap {
        step: u64,
        disc: u32,
        /// Partner disc id, or `u32::MAX` for a wall.
        other: u32,
        fraction: f64,
        limit: f64,
        cause: String,
        /// The pair as the message names it: "discs 3 and 4", or "disc 3 and wall 'tool'"
        /// (issue 48 D10: the wall was named by its sentinel id, 4294967295); the overlap is
        /// of the smaller radius, or of the disc's for a wall.
        pair: Box<str>,
    },
    #[error(
        "step {step}: kinetic energy {kinetic:.4e} J exceeds {limit}× the energy supplied \
         ({supplied:.4e} J); most energetic disc {disc}; likely cause: {cause}"
    )]
    EnergyGrowth {
        step: u64,
        disc: u32,
        kinetic: f64,
        supplied: f64,
        limit: f64,
        cause: String,
    },
}

/// The deepest contact of a state ([`World::deepest_overlap`]).
#[derive(Debug, Clone, PartialEq)]
pub struct DeepestOverlap {
    /// Overlap over the smaller radius (disc pair) or the disc radius (wall); negative when
    /// the closest neighbour is apart.
    pub fraction: f64,
    /// Stable disc id.
    pub disc: u32,
    /// Partner disc id, or `u32::MAX` for a wall.
    pub other: u32,
    /// The wall's index in `State::walls` for a disc-wall contact.
    pub wall: Option<usize>,
}

impl GuardError {
    /// The same stop with another "likely cause": a caller that knows more than the engine (the
    /// specimen generator, whose command has no time-step flag) says what to do in its terms.
    pub fn with_cause(mut self, new: String) -> Self {
        match &mut self {
            GuardError::NonFinite { cause, .. }
            | GuardError::Speed { cause, .. }
            | GuardError::Overlap { cause, .. }
            | GuardError::EnergyGrowth { cause, .. } => *cause = new,
        }
        self
    }
}

impl World {
    fn dt_cause(&self) -> String {
        let crit = self.critical_dt();
        format!(
            "time step too large for the stiffness (dt = {:.3e} s, critical dt = {:.3e} s, \
             ratio {:.2}); lower the time-step factor (scene run.dt_factor, --dt-factor) or set \
             a fixed step (scene run.dt)",
            self.dt(),
            crit,
            self.dt() / crit
        )
    }

    /// Check the state: finite values, overlaps below [`crate::Params::max_overlap_fraction`],
    /// kinetic energy below [`crate::Params::max_energy_growth`] × the energy supplied plus
    /// the rounding-level energy of the positions (needs [`crate::Params::track_energy`]).
    pub fn check(&self) -> Result<(), GuardError> {
        self.check_deepest().map(|_| ())
    }

    /// [`World::check`], returning on success the deepest overlap it measured (the fraction of
    /// [`World::deepest_overlap`], 0 when nothing touches).
    fn check_deepest(&self) -> Result<f64, GuardError> {
        let st = &self.state;
        let d = &st.discs;
        let step = st.step;
        for i in 0..d.len() {
            let fields: [(&'static str, f64); 9] = [
                ("x", d.x[i]),
                ("y", d.y[i]),
                ("theta", d.theta[i]),
                ("vx", d.vx[i]),
                ("vy", d.vy[i]),
                ("omega", d.omega[i]),
                ("fx", d.fx[i]),
                ("fy", d.fy[i]),
                ("torque", d.torque[i]),
            ];
            if let Some((field, _)) = fields.iter().find(|(_, v)| !v.is_finite()) {
                return Err(GuardError::NonFinite {
                    step,
                    disc: d.id[i],
                    field,
                    cause: self.dt_cause(),
                });
            }
            let speed = d.vx[i].hypot(d.vy[i]);
            let fraction = speed * self.dt() / d.r[i];
            if fraction > MAX_TRAVEL_PER_STEP {
                let cause = if step == 0 {
                    match self.params.dt_fixed {
                        // Speed × step: with a fixed step the step is as likely the mistake as
                        // the speed (issue 48 D14: `dt: 1` was blamed on the velocity alone).
                        Some(dt) => format!(
                            "the fixed time step (scene run.dt = {dt:.4e} s) is too long for \
                             the speed the input gives it (no step has run yet): at most \
                             {:.3e} s keeps it within {MAX_TRAVEL_PER_STEP} of its radius per \
                             step, and the critical step √(m/K) of this scene is {:.3e} s (the \
                             automatic step, without run.dt, would be {:.3e} s); or check the \
                             velocity in the scene's discs or clumps",
                            MAX_TRAVEL_PER_STEP * d.r[i] / speed,
                            self.critical_dt(),
                            self.params.dt_factor * self.critical_dt()
                        ),
                        None => "the input gives it this speed (no step has run yet): check \
                                 the velocity in the scene's discs or clumps"
                            .to_string(),
                    }
                } else {
                    format!(
                        "accelerated beyond control: a load too large for the disc (gravity, \
                         wall speed, applied force) or {}",
                        self.dt_cause()
                    )
                };
                return Err(GuardError::Speed {
                    step,
                    disc: d.id[i],
                    speed,
                    fraction,
                    limit: MAX_TRAVEL_PER_STEP,
                    cause,
                });
            }
        }
        let limit = self.params.max_overlap_fraction;
        let deepest = self.deepest_overlap();
        if let Some(o) = &deepest {
            if o.fraction > limit {
                let cause = match o.wall {
                    _ if step == 0 => format!(
                        "the input already places {} (no step has run yet): fix the positions \
                         or radii in the scene, or raise run.max_overlap_fraction",
                        if o.wall.is_some() {
                            "the disc this deep in the wall".to_string()
                        } else if o.fraction >= 1.999 {
                            "the two discs at (nearly) the same point, or one inside the other"
                                .to_string()
                        } else {
                            "the two discs this deep in each other".to_string()
                        }
                    ),
                    Some(w) => format!(
                        "wall '{}' pushed too far or too fast, or {}",
                        st.walls[w].name,
                        self.dt_cause()
                    ),
                    None => format!(
                        "{}, or contact stiffness too low for the load",
                        self.dt_cause()
                    ),
                };
                let pair = match o.wall {
                    Some(w) => format!("disc {} and wall '{}'", o.disc, st.walls[w].name),
                    None => format!("discs {} and {}", o.disc, o.other),
                };
                return Err(GuardError::Overlap {
                    step,
                    disc: o.disc,
                    other: o.other,
                    fraction: o.fraction,
                    limit,
                    cause,
                    pair: pair.into(),
                });
            }
        }
        if self.params.track_energy && self.energy.initial.is_some() {
            let e = self.energy();
            let supplied = e.initial - self.energy.initial_grav
                + (self.energy.initial_grav - e.gravity_potential)
                + e.boundary_work;
            let limit = self.params.max_energy_growth;
            let ke = e.kinetic();
            if ke > 0.0 && ke > limit * supplied.max(0.0) + self.rounding_energy() {
                let mut best = (0usize, -1.0f64);
                for i in 0..d.len() {
                    let k = d.m[i] * (d.vx[i] * d.vx[i] + d.vy[i] * d.vy[i])
                        + d.inertia[i] * d.omega[i] * d.omega[i];
                    if k > best.1 {
                        best = (i, k);
                    }
                }
                return Err(GuardError::EnergyGrowth {
                    step,
                    disc: d.id.get(best.0).copied().unwrap_or(0),
                    kinetic: ke,
                    supplied,
                    limit,
                    cause: format!("energy created by the integration: {}", self.dt_cause()),
                });
            }
        }
        Ok(deepest.map_or(0.0, |o| o.fraction.max(0.0)))
    }

    /// The deepest overlap of the current neighbour lists: disc pairs (beyond their reference
    /// gap, over the smaller radius) and disc-wall contacts (over the disc radius), as the
    /// guard measures it. `None` before the first neighbour build or with no pair at all.
    pub fn deepest_overlap(&self) -> Option<DeepestOverlap> {
        let st = &self.state;
        let d = &st.discs;
        let img = MinImage::new(&st.periodic);
        let nb = &self.nb;
        if nb.start.len() != d.len() + 1 {
            return None;
        }
        let mut best: Option<DeepestOverlap> = None;
        let mut keep = |fraction: f64, disc: u32, other: u32, wall: Option<usize>| {
            if best.as_ref().is_none_or(|b| fraction > b.fraction) {
                best = Some(DeepestOverlap {
                    fraction,
                    disc,
                    other,
                    wall,
                });
            }
        };
        for i in 0..d.len() {
            for p in nb.start[i] as usize..nb.start[i + 1] as usize {
                let j = nb.nbr[p] as usize;
                let (dx, dy) = img.delta(d.x[j] - d.x[i], d.y[j] - d.y[i]);
                let g0 = nb.g0.get(p).copied().unwrap_or(0.0);
                let ov = d.r[i] + d.r[j] + g0 - (dx * dx + dy * dy).sqrt();
                keep(ov / d.r[i].min(d.r[j]), d.id[i], d.id[j], None);
            }
        }
        for q in 0..nb.walls.wall.len() {
            let (w, i) = (nb.walls.wall[q] as usize, nb.walls.disc[q] as usize);
            if i >= d.len() {
                continue;
            }
            let (_, _, dist) = closest_on_wall(&st.walls[w], d.x[i], d.y[i], &img);
            keep((d.r[i] - dist) / d.r[i], d.id[i], u32::MAX, Some(w));
        }
        best
    }

    /// Energy at the rounding level of the positions, Σᵢ ½ Kᵢ (16 ε Lᵢ)² with Kᵢ the disc's
    /// stiffness sum of the time-step estimate, ε the machine epsilon and Lᵢ = |xᵢ| + |yᵢ| + rᵢ.
    /// A state at rest (e.g. a bonded lattice) has only forces from the rounding of its
    /// positions, so kinetic energy and energy supplied are both of this order (~1e-31 J for a
    /// 200-disc SiC block of 2.5 µm discs, where the floor is ~1e-26 J): below it, kinetic
    /// energy is rounding noise, not growth. Exponential growth (a step above the critical
    /// one) passes it within a few steps.
    fn rounding_energy(&self) -> f64 {
        let d = &self.state.discs;
        let k = &self.cache.k_trans;
        (0..d.len().min(k.len()))
            .map(|i| {
                let l = 16.0 * f64::EPSILON * (d.x[i].abs() + d.y[i].abs() + d.r[i]);
                0.5 * k[i] * l * l
            })
            .sum()
    }

    /// [`World::check`], keeping a copy of the state when it passes; returns the deepest
    /// overlap it measured (fraction of the radius, see [`World::deepest_overlap`]; 0 when
    /// nothing touches), so callers that report it need not scan the contacts again.
    pub fn guard(&mut self) -> Result<f64, GuardError> {
        let deepest = self.check_deepest()?;
        self.last_good = Some(Box::new(self.state.clone()));
        Ok(deepest)
    }

    /// The last state that passed [`World::guard`] (to save when a run is stopped).
    pub fn last_good(&self) -> Option<&crate::state::State> {
        self.last_good.as_deref()
    }
}
