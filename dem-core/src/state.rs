//! Simulation state in structure-of-arrays form: discs, rigid clumps, walls, the periodic box.
//!
//! Discs are 2D cylinders of thickness `t` ([`State::thickness`], default 1 m as in PFC2D): a
//! uniform disc of radius r has mass ρ·t·π·r² and moment of inertia m·r²/2 about its centre.
//! Every hot loop indexes these vectors with plain `usize`/`u32` indices; [`Discs::id`] is the
//! stable identity that survives spatial reordering (outputs and checkpoints use it).
//!
//! Time integration is PFC's central-difference (leapfrog) scheme: positions `x, y, theta` are
//! at time t, velocities `vx, vy, omega` at t − dt/2 while forces are being computed (so the
//! displacement increment of the last step is v·dt), and at t + dt/2 after the kick.

use serde::{Deserialize, Serialize};

/// `Discs::body` value of a disc that is not a member of a rigid clump.
pub const FREE: u32 = u32::MAX;

/// All discs, one entry per vector per disc (SoA).
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Discs {
    /// Stable identity (index at creation); survives reordering.
    pub id: Vec<u32>,
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    /// Rotation angle (rad), counter-clockwise.
    pub theta: Vec<f64>,
    pub vx: Vec<f64>,
    pub vy: Vec<f64>,
    /// Angular velocity (rad/s), counter-clockwise.
    pub omega: Vec<f64>,
    pub r: Vec<f64>,
    /// Mass (kg). For a member of a rigid clump this is the member's share, used only for
    /// contact damping; the clump integrates with its own mass.
    pub m: Vec<f64>,
    /// Moment of inertia about the disc centre (kg·m²).
    pub inertia: Vec<f64>,
    /// Force and torque accumulated in the current step (N, N·m).
    pub fx: Vec<f64>,
    pub fy: Vec<f64>,
    pub torque: Vec<f64>,
    /// Owning rigid clump index into [`Clumps`], or [`FREE`].
    pub body: Vec<u32>,
    /// Material index (selects the contact law of a pair).
    pub material: Vec<u16>,
    /// User group (e.g. grain id of a bonded clump, or a tag); written to outputs.
    pub group: Vec<u32>,
    /// Fixed discs keep their velocity (zero or prescribed); they are not integrated.
    pub fixed: Vec<bool>,
}

impl Discs {
    pub fn len(&self) -> usize {
        self.x.len()
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Append a disc at rest with mass `m` and inertia `inertia`; returns its index.
    #[allow(clippy::too_many_arguments)]
    pub fn push(
        &mut self,
        x: f64,
        y: f64,
        r: f64,
        m: f64,
        inertia: f64,
        material: u16,
        group: u32,
    ) -> usize {
        let i = self.x.len();
        self.id.push(i as u32);
        self.x.push(x);
        self.y.push(y);
        self.theta.push(0.0);
        self.vx.push(0.0);
        self.vy.push(0.0);
        self.omega.push(0.0);
        self.r.push(r);
        self.m.push(m);
        self.inertia.push(inertia);
        self.fx.push(0.0);
        self.fy.push(0.0);
        self.torque.push(0.0);
        self.body.push(FREE);
        self.material.push(material);
        self.group.push(group);
        self.fixed.push(false);
        i
    }

    /// Append a uniform disc of density `rho` and thickness `t`: m = ρ t π r², I = m r²/2.
    pub fn push_uniform(
        &mut self,
        x: f64,
        y: f64,
        r: f64,
        rho: f64,
        t: f64,
        material: u16,
    ) -> usize {
        let m = rho * t * std::f64::consts::PI * r * r;
        self.push(x, y, r, m, 0.5 * m * r * r, material, 0)
    }

    /// Zero the force and torque accumulators.
    pub fn clear_forces(&mut self) {
        self.fx.fill(0.0);
        self.fy.fill(0.0);
        self.torque.fill(0.0);
    }

    /// Apply a permutation: new position `k` holds the disc that was at `order[k]`.
    pub fn permute(&mut self, order: &[u32]) {
        fn p<T: Copy>(v: &mut Vec<T>, order: &[u32]) {
            let old = std::mem::take(v);
            *v = order.iter().map(|&k| old[k as usize]).collect();
        }
        p(&mut self.id, order);
        p(&mut self.x, order);
        p(&mut self.y, order);
        p(&mut self.theta, order);
        p(&mut self.vx, order);
        p(&mut self.vy, order);
        p(&mut self.omega, order);
        p(&mut self.r, order);
        p(&mut self.m, order);
        p(&mut self.inertia, order);
        p(&mut self.fx, order);
        p(&mut self.fy, order);
        p(&mut self.torque, order);
        p(&mut self.body, order);
        p(&mut self.material, order);
        p(&mut self.group, order);
        p(&mut self.fixed, order);
    }
}

/// Rigid clumps (ORC): one rigid body each, members are discs at fixed body-frame offsets.
/// Mass, centroid and inertia are the template's (not the sum of the members').
#[derive(Clone, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Clumps {
    /// Centre of mass (m) and orientation (rad).
    pub x: Vec<f64>,
    pub y: Vec<f64>,
    pub theta: Vec<f64>,
    pub vx: Vec<f64>,
    pub vy: Vec<f64>,
    pub omega: Vec<f64>,
    pub m: Vec<f64>,
    /// Moment of inertia about the centre of mass (kg·m²).
    pub inertia: Vec<f64>,
    pub fx: Vec<f64>,
    pub fy: Vec<f64>,
    pub torque: Vec<f64>,
    /// Members of clump c are `members[member_start[c]..member_start[c+1]]` (disc ids, i.e.
    /// [`Discs::id`], so they survive reordering) with body-frame offsets `offset_x/offset_y`
    /// at the same positions (angle 0 = template frame).
    pub member_start: Vec<u32>,
    pub members: Vec<u32>,
    pub offset_x: Vec<f64>,
    pub offset_y: Vec<f64>,
    /// Template id of each clump (for outputs).
    pub template: Vec<String>,
}

impl Clumps {
    pub fn len(&self) -> usize {
        self.x.len()
    }

    pub fn is_empty(&self) -> bool {
        self.x.is_empty()
    }

    /// Range of clump `c` in `members`/`offset_x`/`offset_y`.
    pub fn member_range(&self, c: usize) -> std::ops::Range<usize> {
        self.member_start[c] as usize..self.member_start[c + 1] as usize
    }
}

/// A wall: a straight segment from `a` to `b`, or a polyline a → `via[0]` → … → b (a rigid
/// body of several faces, e.g. a cutting tool). Walls move rigidly with velocity `v` and
/// angular velocity `omega` about `center`; they are not integrated (prescribed motion) and
/// record the reaction (the sum of the forces discs exert on them) and its moment about
/// `center`. A disc has at most one contact with a wall, at the wall's point nearest to it
/// ([`crate::neighbors::closest_on_wall`]): at a convex corner of a polyline the contact
/// is with the vertex, not with both faces.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct Wall {
    pub name: String,
    pub a: [f64; 2],
    pub b: [f64; 2],
    /// Inner vertices of a polyline wall, in order from `a` to `b` (empty: a segment).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub via: Vec<[f64; 2]>,
    pub v: [f64; 2],
    pub omega: f64,
    pub center: [f64; 2],
    pub material: u16,
    /// Force exerted by the discs on the wall in the last step (N) and its moment about
    /// `center` (N·m).
    pub force: [f64; 2],
    pub moment: f64,
    /// Work done by the wall on the discs since the start (J).
    pub work: f64,
    /// Stress control (a servo sets `v` each step; [`crate::wall_servo`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub servo: Option<crate::wall_servo::WallServo>,
    /// Sum of the normal stiffnesses of the wall's touching contacts in the last step (N/m;
    /// summed only for a servo wall).
    #[serde(skip)]
    pub stiffness: f64,
}

impl Wall {
    pub fn new(name: &str, a: [f64; 2], b: [f64; 2], material: u16) -> Wall {
        Wall {
            name: name.to_string(),
            a,
            b,
            via: Vec::new(),
            v: [0.0; 2],
            omega: 0.0,
            center: [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])],
            material,
            force: [0.0; 2],
            moment: 0.0,
            work: 0.0,
            servo: None,
            stiffness: 0.0,
        }
    }

    /// The wall's vertices in order: a, the `via` points, b.
    /// Move the wall (its end points, inner vertices and centre) by `d` (m).
    pub fn translate(&mut self, d: [f64; 2]) {
        for p in [&mut self.a, &mut self.b, &mut self.center]
            .into_iter()
            .chain(self.via.iter_mut())
        {
            p[0] += d[0];
            p[1] += d[1];
        }
    }

    pub fn vertices(&self) -> impl Iterator<Item = [f64; 2]> + '_ {
        std::iter::once(self.a)
            .chain(self.via.iter().copied())
            .chain(std::iter::once(self.b))
    }
}

/// Periodic box: an axis is periodic when its length is `Some`; the box is
/// `[lo, lo + length)` on that axis.
#[derive(Clone, Copy, Debug, Default, Serialize, Deserialize, PartialEq)]
pub struct Periodic {
    pub lo: [f64; 2],
    pub length: [Option<f64>; 2],
}

impl Periodic {
    /// Wrap a coordinate into the box along `axis`.
    #[inline]
    pub fn wrap(&self, axis: usize, x: f64) -> f64 {
        match self.length[axis] {
            Some(l) => {
                let lo = self.lo[axis];
                lo + (x - lo).rem_euclid(l)
            }
            None => x,
        }
    }
}

/// The minimum-image convention of a [`Periodic`] box, for positions at most 1.5 box lengths
/// apart (positions are wrapped into the box, so any two are): the one implementation the
/// neighbour search, the contact and wall passes, the bond kernels and bond installation use.
#[derive(Clone, Copy, Debug)]
pub struct MinImage {
    lx: f64,
    hx: f64,
    ly: f64,
    hy: f64,
}

impl MinImage {
    pub fn new(p: &Periodic) -> MinImage {
        let (lx, ly) = (
            p.length[0].unwrap_or(f64::INFINITY),
            p.length[1].unwrap_or(f64::INFINITY),
        );
        MinImage {
            lx,
            hx: 0.5 * lx,
            ly,
            hy: 0.5 * ly,
        }
    }

    /// Whether either axis is periodic. When neither is, [`MinImage::delta`] is the identity
    /// for every input (the half lengths are +∞: no comparison holds, not even for NaN or ±∞),
    /// so hot loops may skip it.
    #[inline(always)]
    pub fn is_periodic(&self) -> bool {
        self.hx != f64::INFINITY || self.hy != f64::INFINITY
    }

    /// [L_x, L_x/2, L_y, L_y/2] (+∞ on an axis that is not periodic), for vectorised copies
    /// of [`MinImage::delta_select`].
    pub fn parts(&self) -> [f64; 4] {
        [self.lx, self.hx, self.ly, self.hy]
    }

    /// Minimum image of the difference (dx, dy) (valid for |d| < 1.5 L).
    #[inline(always)]
    pub fn delta(&self, mut dx: f64, mut dy: f64) -> (f64, f64) {
        if dx > self.hx {
            dx -= self.lx;
        } else if dx < -self.hx {
            dx += self.lx;
        }
        if dy > self.hy {
            dy -= self.ly;
        } else if dy < -self.hy {
            dy += self.ly;
        }
        (dx, dy)
    }

    /// [`MinImage::delta`] written with selects instead of branches (the same values, bit for
    /// bit: each axis picks d − L, d + L or d by the same comparisons), so that the blocked
    /// force pass can apply it to a whole block in vector registers.
    #[inline(always)]
    pub fn delta_select(&self, dx: f64, dy: f64) -> (f64, f64) {
        let (ax, bx) = (dx - self.lx, dx + self.lx);
        let (ay, by) = (dy - self.ly, dy + self.ly);
        let dx = if dx > self.hx {
            ax
        } else if dx < -self.hx {
            bx
        } else {
            dx
        };
        let dy = if dy > self.hy {
            ay
        } else if dy < -self.hy {
            by
        } else {
            dy
        };
        (dx, dy)
    }
}

/// Everything that changes during a run except the contact and bond stores.
#[derive(Clone, Debug, Serialize, Deserialize, PartialEq)]
pub struct State {
    pub discs: Discs,
    pub clumps: Clumps,
    pub walls: Vec<Wall>,
    pub periodic: Periodic,
    /// Disc thickness t (m); 2D discs are cylinders of this length.
    pub thickness: f64,
    pub time: f64,
    pub step: u64,
}

impl Default for State {
    fn default() -> State {
        State {
            discs: Discs::default(),
            clumps: Clumps::default(),
            walls: Vec::new(),
            periodic: Periodic::default(),
            thickness: 1.0,
            time: 0.0,
            step: 0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_disc_mass_and_inertia() {
        let mut d = Discs::default();
        let i = d.push_uniform(0.0, 0.0, 0.5, 2000.0, 0.1, 0);
        let m = 2000.0 * 0.1 * std::f64::consts::PI * 0.25;
        assert!((d.m[i] - m).abs() < 1e-12 * m);
        assert!((d.inertia[i] - 0.5 * m * 0.25).abs() < 1e-12 * m);
    }

    #[test]
    fn permute_keeps_ids_with_data() {
        let mut d = Discs::default();
        for k in 0..4 {
            d.push_uniform(k as f64, 0.0, 0.1, 1.0, 1.0, 0);
        }
        d.permute(&[3, 1, 0, 2]);
        assert_eq!(d.id, vec![3, 1, 0, 2]);
        assert_eq!(d.x, vec![3.0, 1.0, 0.0, 2.0]);
    }

    /// The one minimum image gives the bits of the rounding form d − L·round(d/L) the bond
    /// kernels used before (issue 23) on every difference away from the ties at ±L/2 and
    /// below 1.5 L, on a periodic axis and on one that is not (identity).
    #[test]
    fn min_image_equals_the_former_rounding_form() {
        const M: f64 = 6_755_399_441_055_744.0;
        let round_form = |d: f64, l: f64, inv: f64| d - l * ((d * inv + M) - M);
        let l = 3.7e-3;
        let img = MinImage::new(&Periodic {
            length: [Some(l), None],
            ..Periodic::default()
        });
        let mut checked = 0;
        for k in -1499..=1499 {
            let d = k as f64 * 1e-3 * l + 1e-9 * (k % 7) as f64;
            if ((d.abs() - 0.5 * l).abs()) < 1e-12 {
                continue;
            }
            let (x, y) = img.delta_select(d, d);
            assert_eq!(x.to_bits(), round_form(d, l, 1.0 / l).to_bits(), "d = {d}");
            assert_eq!(y.to_bits(), round_form(d, 0.0, 0.0).to_bits(), "d = {d}");
            assert_eq!((x, y), img.delta(d, d));
            checked += 1;
        }
        assert!(checked > 2900);
    }

    #[test]
    fn periodic_minimum_image_and_wrap() {
        let p = Periodic {
            lo: [0.0, 0.0],
            length: [Some(10.0), None],
        };
        let img = MinImage::new(&p);
        let (dx, dy) = img.delta(0.5 - 9.5, 0.5 - 9.5);
        assert!((dx - 1.0).abs() < 1e-12);
        assert!((dy + 9.0).abs() < 1e-12);
        assert!((p.wrap(0, -0.5) - 9.5).abs() < 1e-12);
        assert!((p.wrap(0, 10.5) - 0.5).abs() < 1e-12);
    }
}
