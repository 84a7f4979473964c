//! Local damping in the frame of each bonded fragment: PFC's local damping of the motion
//! *relative to* the rigid motion of the fragment a body belongs to, with the net force and
//! moment of the damping removed per fragment, so that it leaves every rigid motion alone.
//!
//! **Why.** PFC local damping (Cundall 1987; Potyondy & Cundall 2004 eq. 4),
//! F_d = −α |F| sgn(v) per degree of freedom, opposes the velocity in the frame the scene is
//! written in. A body that translates faster than it vibrates never sees sgn(v) change, so
//! α|F| acts on it as a one-signed drag: the scene and its copy with every body given +U give
//! different forces (not Galilean-invariant), and a fragment flying off a cut is braked by a
//! force that has no physical origin. Itasca offers "combined damping" for rigid blocks in
//! steady motion for this reason (PFC 7 `rblock damping combined`; Cundall 1987).
//! [`DampingFrame::Fragment`] takes the other way, the one of structural codes that damp
//! "relative to the motion of a rigid body" (LS-DYNA `*DAMPING_RELATIVE`): damp only the
//! deformation.
//!
//! **Formula.** Nodes are the free discs and the rigid clumps (fixed discs are prescribed and
//! take no part). A fragment f is a connected set of nodes joined by intact bonds (a clump is
//! one node; a node without intact bonds is a fragment of its own). With the fragment's mass
//! M = Σ m_i, centroid X, velocity V = Σ m_i v_i / M, polar inertia J = Σ (I_i + m_i |r_i|²)
//! (r_i = x_i − X) and angular velocity Ω = Σ (I_i ω_i + m_i r_i × (v_i − V)) / J:
//!
//! ```text
//! u_i = v_i − V − Ω × r_i,   q_i = ω_i − Ω                     motion relative to the fragment
//! F*_i = −α |F_i| sgn(u_i)  (per component),  T*_i = −α |T_i| sgn(q_i)      PFC local damping
//! a = Σ F*_i / M,   β = Σ (T*_i + r_i × F*_i) / J       rigid acceleration the F* would give
//! F_d,i = F*_i − m_i (a + β × r_i),   T_d,i = T*_i − I_i β                   the damping applied
//! ```
//!
//! with F_i, T_i the body's total force (gravity included) and torque, as in local damping.
//! Properties (tested in `tests/invariance.rs`):
//! * Galilean invariance: u, q and F do not change when every body and wall is given +U;
//! * Σ F_d = 0 and Σ (T_d + r × F_d) = 0 over each fragment: its momentum and angular
//!   momentum are those of the undamped motion, and a rigidly moving fragment is not braked;
//! * it dissipates: the power Σ F_d·v + T_d ω = Σ F*·u + T* q = −α Σ |F||u| − α Σ |T||q| ≤ 0
//!   (the subtracted part is a rigid field, whose power on the motion is a·P + β·L, which
//!   cancels the rigid part of Σ F*·v exactly);
//! * a free disc or clump alone is not damped at all (it has no deformation);
//! * a bonded pair vibrating along its axis (equal masses) is damped exactly as one disc on a
//!   spring under local damping: the amplitude falls by √((1 − α)/(1 + α)) every half period.
//!
//! Fragments are found again (union–find over the intact bonds) when the bond count, the
//! break count, the disc or clump count or the neighbour list (which reorders discs)
//! changes. The damping itself is three serial passes (moments, damping, rigid correction):
//! over the discs of the largest fragment branch-free and on four lanes (AVX2 where the CPU
//! has it, the same bits either way), over the other nodes one by one; the same arithmetic
//! for any thread count.

use crate::bond::Bonds;
use crate::fragments::UnionFind;
use crate::state::{MinImage, State, FREE};
use serde::{Deserialize, Serialize};

/// The frame of reference of local damping (scene `damping.frame`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[cfg_attr(feature = "schema", derive(schemars::JsonSchema))]
#[serde(rename_all = "snake_case")]
pub enum DampingFrame {
    /// PFC local damping of each body's own velocity, F_d = −α|F| sgn(v) (Cundall 1987): the
    /// damping of Itasca's PFC. Not Galilean-invariant: a body in steady motion is dragged.
    #[default]
    Lab,
    /// Local damping of the motion relative to the body's bonded fragment, with the net force
    /// and moment removed per fragment (module docs): leaves rigid motion alone.
    Fragment,
}

impl DampingFrame {
    pub fn is_lab(&self) -> bool {
        *self == DampingFrame::Lab
    }

    /// The name used in scene files and on the command line (`lab`, `fragment`).
    pub fn name(&self) -> &'static str {
        match self {
            DampingFrame::Lab => "lab",
            DampingFrame::Fragment => "fragment",
        }
    }
}

/// A damping frame's name that is neither `lab` nor `fragment` (the name it was given).
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("{0:?} is not lab or fragment")]
pub struct UnknownDampingFrame(pub String);

impl std::str::FromStr for DampingFrame {
    type Err = UnknownDampingFrame;

    /// Parses a scene's or a flag's name; the error says what is accepted.
    fn from_str(s: &str) -> Result<Self, UnknownDampingFrame> {
        match s {
            "lab" => Ok(DampingFrame::Lab),
            "fragment" => Ok(DampingFrame::Fragment),
            _ => Err(UnknownDampingFrame(s.to_string())),
        }
    }
}

/// The damping forces of one step in the fragment frame, and the fragments they were
/// computed on (the step's scratch: rebuilt when stale, never saved).
///
/// Speed: the largest fragment (in a cut, the workpiece: most discs) is summed and damped in
/// branch-free passes over the disc arrays, masked by [`FragmentDamping::mask`], with four
/// partial sums per quantity (added in a fixed order: the same bits for any thread count);
/// the other nodes (small fragments, clumps) one by one.
#[derive(Clone, Debug, Default)]
pub(crate) struct FragmentDamping {
    /// What the fragments were found for: discs, clumps, bonds, breaks, neighbour builds.
    key: Option<[usize; 5]>,
    /// Fragment of each node (discs 0..n, then clumps n..n+n_c); `NONE` for fixed discs and
    /// clump members (their clump is the node).
    label: Vec<u32>,
    /// First node of each fragment (positions are taken relative to it: minimum image).
    first: Vec<u32>,
    /// Nodes in each fragment.
    count: Vec<u32>,
    /// The largest fragment (of two nodes or more), or `NONE`.
    big: u32,
    /// 1 for the discs of the largest fragment, else 0.
    mask: Vec<f64>,
    /// The nodes outside the masked passes: discs of other fragments, and every clump.
    others: Vec<u32>,
    /// Per fragment: the sums M, Σ m d (d = minimum image of x − origin; 2), Σ m v (2),
    /// Σ (I + m|d|²), Σ (I ω + m d × v).
    sums: Vec<[f64; 7]>,
    /// Per fragment: the position of its first node now (scratch, kept to avoid allocating).
    origin: Vec<[f64; 2]>,
    /// Per fragment: its origin, rigid motion and the resultant of the local damping.
    rigid: Vec<Rigid>,
    /// Gathered clump forces and torques (members' sums, gravity included).
    cf: Vec<[f64; 3]>,
    /// The damping force and torque of each disc (0 for discs that are not free nodes).
    pub disc: [Vec<f64>; 3],
    /// The damping force and torque of each clump.
    pub clump: Vec<[f64; 3]>,
}

const NONE: u32 = u32::MAX;

/// A node's mass, inertia, position, velocity, spin, force and torque.
#[derive(Clone, Copy)]
struct Node {
    m: f64,
    i: f64,
    x: [f64; 2],
    v: [f64; 2],
    w: f64,
    f: [f64; 2],
    t: f64,
}

/// A fragment's rigid motion, about its origin o (its first node's position now): centroid
/// offset c = Σ m d / M, V, Ω, M, J about the centroid; and the resultant force and moment
/// (about the centroid) of the local damping F*, T* on it.
#[derive(Clone, Copy, Debug, Default)]
struct Rigid {
    o: [f64; 2],
    c: [f64; 2],
    v: [f64; 2],
    om: f64,
    m: f64,
    j: f64,
    force: [f64; 2],
    moment: f64,
}

impl Rigid {
    /// From the sums of pass 1 (parallel axes for J and L).
    fn of(o: [f64; 2], s: &[f64; 7]) -> Rigid {
        let m = s[0];
        let (cx, cy, vx, vy) = (s[1] / m, s[2] / m, s[3] / m, s[4] / m);
        let j = s[5] - m * (cx * cx + cy * cy);
        let l = s[6] - m * (cx * vy - cy * vx);
        let om = if j > 0.0 { l / j } else { 0.0 };
        Rigid {
            o,
            c: [cx, cy],
            v: [vx, vy],
            om,
            m,
            j,
            ..Rigid::default()
        }
    }

    /// The rigid acceleration a and angular acceleration β the resultant would give.
    fn acc(&self) -> ([f64; 2], f64) {
        let beta = if self.j > 0.0 {
            self.moment / self.j
        } else {
            0.0
        };
        ([self.force[0] / self.m, self.force[1] / self.m], beta)
    }
}

/// Lanes of the masked passes' partial sums.
const L: usize = 4;

impl FragmentDamping {
    /// Fill [`FragmentDamping::disc`] and [`FragmentDamping::clump`] with the damping of
    /// coefficient `alpha` for the forces now on the discs (contacts, walls, bonds, loads) and
    /// `gravity`. `index_of_id` maps disc ids to indices (clump members); `builds` is the
    /// neighbour list's build count (a rebuild may reorder the discs).
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    pub fn compute(
        &mut self,
        st: &State,
        inv_m: &[f64],
        bonds: Option<&Bonds>,
        index_of_id: &[u32],
        builds: u64,
        alpha: f64,
        gravity: [f64; 2],
    ) {
        let (n, nc) = (st.discs.len(), st.clumps.len());
        let key = [
            n,
            nc,
            bonds.map_or(0, |b| b.len()),
            // (Every break, of a bond or of a flat joint's last element, is counted here.)
            bonds.map_or(0, |b| {
                b.broken_counts().iter().map(|c| c[0] + c[1]).sum::<u64>() as usize
            }),
            builds as usize,
        ];
        if self.key != Some(key) {
            self.find_fragments(st, inv_m, bonds);
            self.key = Some(key);
        }
        if nc > 0 {
            self.gather_clumps(st, index_of_id, gravity);
        }
        let img = MinImage::new(&st.periodic);
        let nf = self.first.len();
        for v in self.disc.iter_mut() {
            v.resize(n, 0.0);
        }
        self.clump.clear();
        self.clump.resize(nc, [0.0; 3]);
        // Pass 1: mass, first and second moments and momenta about each fragment's origin.
        self.origin.clear();
        (self.origin)
            .extend((self.first.iter()).map(|&k| node(st, &self.cf, k as usize, gravity).x));
        let origin = &self.origin;
        self.sums.clear();
        self.sums.resize(nf, [0.0; 7]);
        if self.big != NONE {
            let b = self.big as usize;
            self.sums[b] = moments_masked(&Arrays::of(st, &self.mask), origin[b], &img);
        }
        for &k in &self.others {
            let k = k as usize;
            let f = self.label[k] as usize;
            let p = node(st, &self.cf, k, gravity);
            let (o, s) = (origin[f], &mut self.sums[f]);
            let (dx, dy) = img.delta(p.x[0] - o[0], p.x[1] - o[1]);
            s[0] += p.m;
            s[1] += p.m * dx;
            s[2] += p.m * dy;
            s[3] += p.m * p.v[0];
            s[4] += p.m * p.v[1];
            s[5] += p.i + p.m * (dx * dx + dy * dy);
            s[6] += p.i * p.w + p.m * (dx * p.v[1] - dy * p.v[0]);
        }
        // The rigid motion: centroid, V, J and L about the centroid (parallel axes), Ω.
        self.rigid.clear();
        (self.rigid).extend(origin.iter().zip(&self.sums).map(|(&o, s)| Rigid::of(o, s)));
        // Pass 2: local damping of the relative motion, and its resultant per fragment.
        if self.big != NONE {
            let b = self.big as usize;
            let a = Arrays::of(st, &self.mask);
            let p = DampIn {
                rg: &self.rigid[b],
                alpha,
                g: gravity,
            };
            let res = damp_masked(&a, &p, &img, &mut self.disc);
            self.rigid[b].force = [res[0], res[1]];
            self.rigid[b].moment = res[2];
        } else {
            for v in self.disc.iter_mut() {
                v.fill(0.0);
            }
        }
        for q in 0..self.others.len() {
            let k = self.others[q] as usize;
            let f = self.label[k] as usize;
            let p = node(st, &self.cf, k, gravity);
            let rg = &mut self.rigid[f];
            let (dx, dy) = img.delta(p.x[0] - rg.o[0], p.x[1] - rg.o[1]);
            let (rx, ry) = (dx - rg.c[0], dy - rg.c[1]);
            let ux = p.v[0] - rg.v[0] + rg.om * ry;
            let uy = p.v[1] - rg.v[1] - rg.om * rx;
            let d = [
                -alpha * p.f[0].abs() * sgn(ux),
                -alpha * p.f[1].abs() * sgn(uy),
                -alpha * p.t.abs() * sgn(p.w - rg.om),
            ];
            rg.force[0] += d[0];
            rg.force[1] += d[1];
            rg.moment += d[2] + rx * d[1] - ry * d[0];
            self.put(k, n, d);
        }
        // Pass 3: remove the rigid part; a fragment of one node is not damped at all.
        if self.big != NONE {
            let rg = &self.rigid[self.big as usize];
            correct_masked(&Arrays::of(st, &self.mask), rg, &img, &mut self.disc);
        }
        for q in 0..self.others.len() {
            let k = self.others[q] as usize;
            let f = self.label[k] as usize;
            if self.count[f] < 2 {
                self.put(k, n, [0.0; 3]);
                continue;
            }
            let p = node(st, &self.cf, k, gravity);
            let rg = &self.rigid[f];
            let (dx, dy) = img.delta(p.x[0] - rg.o[0], p.x[1] - rg.o[1]);
            let (rx, ry) = (dx - rg.c[0], dy - rg.c[1]);
            let ([ax, ay], beta) = rg.acc();
            let d = self.get(k, n);
            self.put(
                k,
                n,
                [
                    d[0] - p.m * (ax - beta * ry),
                    d[1] - p.m * (ay + beta * rx),
                    d[2] - p.i * beta,
                ],
            );
        }
    }

    fn put(&mut self, k: usize, n: usize, d: [f64; 3]) {
        if k < n {
            self.disc[0][k] = d[0];
            self.disc[1][k] = d[1];
            self.disc[2][k] = d[2];
        } else {
            self.clump[k - n] = d;
        }
    }

    fn get(&self, k: usize, n: usize) -> [f64; 3] {
        if k < n {
            [self.disc[0][k], self.disc[1][k], self.disc[2][k]]
        } else {
            self.clump[k - n]
        }
    }

    /// Union–find of the nodes over the intact bonds; labels in order of each fragment's
    /// first node (deterministic); the largest fragment's mask and the other nodes' list.
    #[inline(never)]
    fn find_fragments(&mut self, st: &State, inv_m: &[f64], bonds: Option<&Bonds>) {
        let (n, nc) = (st.discs.len(), st.clumps.len());
        let node_of = |i: usize| -> Option<usize> {
            let b = st.discs.body[i];
            if b != FREE {
                Some(n + b as usize)
            } else if inv_m.get(i).is_some_and(|&v| v > 0.0) {
                Some(i)
            } else {
                None
            }
        };
        let mut uf = UnionFind::new(n + nc);
        if let Some(b) = bonds {
            for (i, j) in b.intact_pairs() {
                if let (Some(a), Some(c)) = (node_of(i), node_of(j)) {
                    uf.union(a, c);
                }
            }
        }
        let mut is_node = vec![false; n + nc];
        for i in 0..n {
            if let Some(k) = node_of(i) {
                is_node[k] = true;
            }
        }
        self.label.clear();
        self.label.resize(n + nc, NONE);
        self.first.clear();
        self.count.clear();
        let mut of_root = vec![NONE; n + nc];
        for (k, _) in is_node.iter().enumerate().filter(|(_, &is)| is) {
            let r = uf.find(k);
            if of_root[r] == NONE {
                of_root[r] = self.first.len() as u32;
                self.first.push(k as u32);
                self.count.push(0);
            }
            self.label[k] = of_root[r];
            self.count[of_root[r] as usize] += 1;
        }
        // The largest fragment (the first of the largest, for determinism), if of 2+ nodes.
        self.big = NONE;
        let mut most = 1;
        for (f, &c) in self.count.iter().enumerate() {
            if c > most {
                most = c;
                self.big = f as u32;
            }
        }
        self.mask.clear();
        self.mask.resize(n, 0.0);
        self.others.clear();
        for k in 0..n + nc {
            let f = self.label[k];
            if f == NONE {
                continue;
            }
            if k < n && f == self.big {
                self.mask[k] = 1.0;
            } else {
                self.others.push(k as u32);
            }
        }
    }

    /// Each clump's force and torque from its members' (about the clump's centre), gravity
    /// included, as the clump pass will sum them.
    #[inline(never)]
    fn gather_clumps(&mut self, st: &State, index_of_id: &[u32], gravity: [f64; 2]) {
        let (cl, d) = (&st.clumps, &st.discs);
        let img = MinImage::new(&st.periodic);
        self.cf.clear();
        for c in 0..cl.len() {
            let (mut fx, mut fy, mut t) = (0.0, 0.0, 0.0);
            for q in cl.member_range(c) {
                let i = index_of_id[cl.members[q] as usize] as usize;
                let (rx, ry) = img.delta(d.x[i] - cl.x[c], d.y[i] - cl.y[c]);
                fx += d.fx[i];
                fy += d.fy[i];
                t += d.torque[i] + rx * d.fy[i] - ry * d.fx[i];
            }
            self.cf
                .push([fx + cl.m[c] * gravity[0], fy + cl.m[c] * gravity[1], t]);
        }
    }
}

/// Node `k` (a disc below `st.discs.len()`, else a clump) with its force and torque, gravity
/// included (`cf`: the clumps' gathered forces).
#[inline]
fn node(st: &State, cf: &[[f64; 3]], k: usize, gravity: [f64; 2]) -> Node {
    let n = st.discs.len();
    if k < n {
        let d = &st.discs;
        Node {
            m: d.m[k],
            i: d.inertia[k],
            x: [d.x[k], d.y[k]],
            v: [d.vx[k], d.vy[k]],
            w: d.omega[k],
            f: [d.fx[k] + d.m[k] * gravity[0], d.fy[k] + d.m[k] * gravity[1]],
            t: d.torque[k],
        }
    } else {
        let (c, cl) = (k - n, &st.clumps);
        Node {
            m: cl.m[c],
            i: cl.inertia[c],
            x: [cl.x[c], cl.y[c]],
            v: [cl.vx[c], cl.vy[c]],
            w: cl.omega[c],
            f: [cf[c][0], cf[c][1]],
            t: cf[c][2],
        }
    }
}

/// Partial sums in `L` lanes, added in lane order.
#[inline(always)]
fn total(a: [f64; L]) -> f64 {
    (a[0] + a[1]) + (a[2] + a[3])
}

/// The disc arrays the masked passes read, cut to one length.
struct Arrays<'a> {
    mask: &'a [f64],
    m: &'a [f64],
    ii: &'a [f64],
    x: &'a [f64],
    y: &'a [f64],
    vx: &'a [f64],
    vy: &'a [f64],
    w: &'a [f64],
    fx: &'a [f64],
    fy: &'a [f64],
    tq: &'a [f64],
}

impl<'a> Arrays<'a> {
    fn of(st: &'a State, mask: &'a [f64]) -> Arrays<'a> {
        let d = &st.discs;
        let n = d.len();
        Arrays {
            mask: &mask[..n],
            m: &d.m[..n],
            ii: &d.inertia[..n],
            x: &d.x[..n],
            y: &d.y[..n],
            vx: &d.vx[..n],
            vy: &d.vy[..n],
            w: &d.omega[..n],
            fx: &d.fx[..n],
            fy: &d.fy[..n],
            tq: &d.torque[..n],
        }
    }
}

/// The sums of pass 1 over the masked discs: M, Σ m d (2), Σ m v (2), Σ (I + m|d|²),
/// Σ (I ω + m d × v), d the minimum image of x − `o`.
fn moments_masked(a: &Arrays, o: [f64; 2], img: &MinImage) -> [f64; 7] {
    #[cfg(target_arch = "x86_64")]
    if crate::lanes::has_avx2() {
        // SAFETY: the CPU has AVX2.
        return unsafe { simd::moments(a, o, img) };
    }
    moments_lanes(a, o, img, [[0.0; L]; 7], 0).map(total)
}

/// Pass 1 in lanes: lane l takes the discs L b + l of the whole blocks from `from` on, lane 0
/// the rest (the order the four-lane copy in [`simd`] keeps: the same bits).
fn moments_lanes(
    a: &Arrays,
    o: [f64; 2],
    img: &MinImage,
    mut s: [[f64; L]; 7],
    from: usize,
) -> [[f64; L]; 7] {
    let n = a.m.len();
    let blocks = (n - from) / L;
    for k in from..n {
        let l = if k < from + blocks * L {
            (k - from) % L
        } else {
            0
        };
        let (mk, mm) = (a.mask[k], a.mask[k] * a.m[k]);
        let (dx, dy) = img.delta_select(a.x[k] - o[0], a.y[k] - o[1]);
        s[0][l] += mm;
        s[1][l] += mm * dx;
        s[2][l] += mm * dy;
        s[3][l] += mm * a.vx[k];
        s[4][l] += mm * a.vy[k];
        s[5][l] += mk * a.ii[k] + mm * (dx * dx + dy * dy);
        s[6][l] += mk * a.ii[k] * a.w[k] + mm * (dx * a.vy[k] - dy * a.vx[k]);
    }
    s
}

/// Pass 2 over the masked discs: F* = −α|F| sgn(u), T* = −α|T| sgn(ω − Ω) into `out` (0 for
/// the discs outside the mask); returns the resultant force and its moment about the
/// centroid. `rg`: the fragment's [c (2), V (2), Ω, …].
fn damp_masked(a: &Arrays, p: &DampIn, img: &MinImage, out: &mut [Vec<f64>; 3]) -> [f64; 3] {
    #[cfg(target_arch = "x86_64")]
    if crate::lanes::has_avx2() {
        // SAFETY: the CPU has AVX2.
        return unsafe { simd::damp(a, p, img, out) };
    }
    damp_lanes(a, p, img, out, [[0.0; L]; 3], 0).map(total)
}

/// What pass 2 needs besides the discs: the fragment's rigid motion, α and g.
struct DampIn<'a> {
    rg: &'a Rigid,
    alpha: f64,
    g: [f64; 2],
}

/// Pass 2 from disc `from` on, lanes as in [`moments_lanes`].
fn damp_lanes(
    a: &Arrays,
    p: &DampIn,
    img: &MinImage,
    out: &mut [Vec<f64>; 3],
    mut s: [[f64; L]; 3],
    from: usize,
) -> [[f64; L]; 3] {
    let n = a.m.len();
    let blocks = (n - from) / L;
    #[allow(clippy::needless_range_loop)] // (k indexes eleven arrays)
    for k in from..n {
        let l = if k < from + blocks * L {
            (k - from) % L
        } else {
            0
        };
        let (dx, dy) = img.delta_select(a.x[k] - p.rg.o[0], a.y[k] - p.rg.o[1]);
        let (rx, ry) = (dx - p.rg.c[0], dy - p.rg.c[1]);
        let ux = a.vx[k] - p.rg.v[0] + p.rg.om * ry;
        let uy = a.vy[k] - p.rg.v[1] - p.rg.om * rx;
        let ka = a.mask[k] * p.alpha;
        let dfx = -ka * (a.fx[k] + a.m[k] * p.g[0]).abs() * sgn(ux);
        let dfy = -ka * (a.fy[k] + a.m[k] * p.g[1]).abs() * sgn(uy);
        let dt = -ka * a.tq[k].abs() * sgn(a.w[k] - p.rg.om);
        s[0][l] += dfx;
        s[1][l] += dfy;
        s[2][l] += dt + rx * dfy - ry * dfx;
        out[0][k] = dfx;
        out[1][k] = dfy;
        out[2][k] = dt;
    }
    s
}

/// The masked passes 1 and 2 on four lanes (AVX2): every lane performs the scalar code's
/// operations in the scalar code's order, so the results are the same bits.
#[cfg(target_arch = "x86_64")]
mod simd {
    use super::{correct_from, damp_lanes, moments_lanes, total, Arrays, DampIn, Rigid, L};
    use crate::lanes::F64x4;
    use crate::state::MinImage;

    /// Four lanes `[x, ...]` of `v` from index `i` (`i + 4 <= v.len()`).
    macro_rules! ld {
        ($v:expr, $i:expr) => {{
            let (v, i): (&[f64], usize) = ($v, $i);
            assert!(i + 4 <= v.len());
            // SAFETY: i..i + 4 lies in v (asserted); AVX2 is the caller's promise.
            unsafe { F64x4::load(v.as_ptr().add(i)) }
        }};
    }

    /// `MinImage::delta_select` on four lanes (an exact copy: the same comparisons and
    /// selects).
    macro_rules! delta {
        ($img:expr, $dx:expr, $dy:expr) => {{
            let (dx, dy): (F64x4, F64x4) = ($dx, $dy);
            let [lx, hx, ly, hy] = $img.parts();
            let set = |v| unsafe { F64x4::splat(v) };
            let (ax, bx) = (dx - set(lx), dx + set(lx));
            let (ay, by) = (dy - set(ly), dy + set(ly));
            (
                dx.gt(set(hx)).select(ax, dx.lt(set(-hx)).select(bx, dx)),
                dy.gt(set(hy)).select(ay, dy.lt(set(-hy)).select(by, dy)),
            )
        }};
    }

    fn lanes(v: F64x4) -> [f64; 4] {
        let mut o = [0.0; 4];
        // SAFETY: o holds four f64; a value of F64x4 exists only where AVX2 does.
        unsafe { v.store(o.as_mut_ptr()) };
        o
    }

    /// # Safety
    /// The CPU must support AVX2.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn moments(a: &Arrays, o: [f64; 2], img: &MinImage) -> [f64; 7] {
        let n = a.m.len();
        let blocks = n / L;
        let z = F64x4::zero();
        let mut s = [z; 7];
        let (o0, o1) = (F64x4::splat(o[0]), F64x4::splat(o[1]));
        for b in 0..blocks {
            let i = b * L;
            let mk = ld!(a.mask, i);
            let mm = mk * ld!(a.m, i);
            let (dx, dy) = delta!(img, ld!(a.x, i) - o0, ld!(a.y, i) - o1);
            let (vx, vy, ii) = (ld!(a.vx, i), ld!(a.vy, i), ld!(a.ii, i));
            s[0] = s[0] + mm;
            s[1] = s[1] + mm * dx;
            s[2] = s[2] + mm * dy;
            s[3] = s[3] + mm * vx;
            s[4] = s[4] + mm * vy;
            s[5] = s[5] + (mk * ii + mm * (dx * dx + dy * dy));
            s[6] = s[6] + (mk * ii * ld!(a.w, i) + mm * (dx * vy - dy * vx));
        }
        // The rest, in lane 0, by the scalar code.
        let rest = moments_lanes(a, o, img, s.map(lanes), blocks * L);
        rest.map(total)
    }

    /// # Safety
    /// The CPU must support AVX2.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn damp(
        a: &Arrays,
        p: &DampIn,
        img: &MinImage,
        out: &mut [Vec<f64>; 3],
    ) -> [f64; 3] {
        let n = a.m.len();
        let blocks = n / L;
        let set = |v| F64x4::splat(v);
        let (zero, one, sign) = (F64x4::zero(), set(1.0), set(-0.0));
        let mut s = [zero; 3];
        let (o0, o1, c0, c1) = (
            set(p.rg.o[0]),
            set(p.rg.o[1]),
            set(p.rg.c[0]),
            set(p.rg.c[1]),
        );
        let (v0, v1, om, al) = (set(p.rg.v[0]), set(p.rg.v[1]), set(p.rg.om), set(p.alpha));
        let (g0, g1) = (set(p.g[0]), set(p.g[1]));
        let sg = |u: F64x4| u.gt(zero).select(one, zero) - u.lt(zero).select(one, zero);
        let [ox, oy, ot] = out;
        assert!(ox.len() >= n && oy.len() >= n && ot.len() >= n);
        for b in 0..blocks {
            let i = b * L;
            let (dx, dy) = delta!(img, ld!(a.x, i) - o0, ld!(a.y, i) - o1);
            let (rx, ry) = (dx - c0, dy - c1);
            let ux = ld!(a.vx, i) - v0 + om * ry;
            let uy = ld!(a.vy, i) - v1 - om * rx;
            let m = ld!(a.m, i);
            let nka = sign ^ (ld!(a.mask, i) * al);
            let dfx = nka * sign.andnot(ld!(a.fx, i) + m * g0) * sg(ux);
            let dfy = nka * sign.andnot(ld!(a.fy, i) + m * g1) * sg(uy);
            let dt = nka * sign.andnot(ld!(a.tq, i)) * sg(ld!(a.w, i) - om);
            s[0] = s[0] + dfx;
            s[1] = s[1] + dfy;
            s[2] = s[2] + (dt + rx * dfy - ry * dfx);
            // SAFETY: i + 4 <= n <= the outputs' lengths (asserted above).
            dfx.store(ox.as_mut_ptr().add(i));
            dfy.store(oy.as_mut_ptr().add(i));
            dt.store(ot.as_mut_ptr().add(i));
        }
        let rest = damp_lanes(a, p, img, out, s.map(lanes), blocks * L);
        rest.map(total)
    }

    /// # Safety
    /// The CPU must support AVX2.
    #[target_feature(enable = "avx2")]
    pub(super) unsafe fn correct(a: &Arrays, rg: &Rigid, img: &MinImage, out: &mut [Vec<f64>; 3]) {
        let n = a.m.len();
        let blocks = n / L;
        let set = |v| F64x4::splat(v);
        let (o0, o1, c0, c1) = (set(rg.o[0]), set(rg.o[1]), set(rg.c[0]), set(rg.c[1]));
        let ([a0, a1], beta) = rg.acc();
        let (a0, a1, beta) = (set(a0), set(a1), set(beta));
        let [ox, oy, ot] = out;
        assert!(ox.len() >= n && oy.len() >= n && ot.len() >= n);
        for b in 0..blocks {
            let i = b * L;
            let (dx, dy) = delta!(img, ld!(a.x, i) - o0, ld!(a.y, i) - o1);
            let (rx, ry) = (dx - c0, dy - c1);
            let mk = ld!(a.mask, i);
            let mm = mk * ld!(a.m, i);
            let fx = ld!(ox, i) - mm * (a0 - beta * ry);
            let fy = ld!(oy, i) - mm * (a1 + beta * rx);
            let t = ld!(ot, i) - mk * ld!(a.ii, i) * beta;
            // SAFETY: i + 4 <= n <= the outputs' lengths (asserted above).
            fx.store(ox.as_mut_ptr().add(i));
            fy.store(oy.as_mut_ptr().add(i));
            t.store(ot.as_mut_ptr().add(i));
        }
        correct_from(a, rg, img, out, blocks * L);
    }
}

/// Pass 3 over the masked discs: subtract the rigid acceleration field of the resultant,
/// m (a + β × r) and I β, from `out`.
fn correct_masked(a: &Arrays, rg: &Rigid, img: &MinImage, out: &mut [Vec<f64>; 3]) {
    #[cfg(target_arch = "x86_64")]
    if crate::lanes::has_avx2() {
        // SAFETY: the CPU has AVX2.
        return unsafe { simd::correct(a, rg, img, out) };
    }
    correct_from(a, rg, img, out, 0)
}

fn correct_from(a: &Arrays, rg: &Rigid, img: &MinImage, out: &mut [Vec<f64>; 3], from: usize) {
    let n = a.m.len();
    let [ox, oy, ot] = out;
    let (ox, oy, ot) = (&mut ox[..n], &mut oy[..n], &mut ot[..n]);
    let (acc, beta) = rg.acc();
    for i in from..n {
        let (dx, dy) = img.delta_select(a.x[i] - rg.o[0], a.y[i] - rg.o[1]);
        let (rx, ry) = (dx - rg.c[0], dy - rg.c[1]);
        let mm = a.mask[i] * a.m[i];
        ox[i] -= mm * (acc[0] - beta * ry);
        oy[i] -= mm * (acc[1] + beta * rx);
        ot[i] -= a.mask[i] * a.ii[i] * beta;
    }
}

/// sign(v) with sign(0) = sign(NaN) = 0, as [`crate::integrate::sgn`], written as two
/// selects: the signs of relative velocities are unpredictable, and a branch per sign costs
/// more than the rest of the pass.
#[inline(always)]
fn sgn(v: f64) -> f64 {
    let p = if v > 0.0 { 1.0 } else { 0.0 };
    let q = if v < 0.0 { 1.0 } else { 0.0 };
    p - q
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Discs with varied values, a mask over some of them, and a periodic x axis.
    fn state(n: usize) -> (State, Vec<f64>) {
        let mut st = State::default();
        let mut r = 0x2545_f491_4f6c_dd1d_u64;
        let mut u = || {
            r ^= r << 13;
            r ^= r >> 7;
            r ^= r << 17;
            (r >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        for _ in 0..n {
            let k =
                st.discs
                    .push_uniform(u() * 0.02, u() * 0.01, 1e-4 * (1.5 + u()), 3000.0, 1.0, 0);
            st.discs.vx[k] = u();
            st.discs.vy[k] = u();
            st.discs.omega[k] = 100.0 * u();
            st.discs.fx[k] = 10.0 * u();
            st.discs.fy[k] = 10.0 * u();
            st.discs.torque[k] = 1e-3 * u();
        }
        st.discs.vx[3] = 0.0;
        st.periodic.length = [Some(0.015), None];
        let mask = (0..n).map(|k| if k % 7 == 3 { 0.0 } else { 1.0 }).collect();
        (st, mask)
    }

    /// The four-lane passes give the scalar passes' bits (n = 4k + 3: both loops run).
    #[test]
    fn simd_passes_equal_the_scalar_ones_bit_for_bit() {
        if !crate::lanes::has_avx2() {
            return;
        }
        let (st, mask) = state(103);
        let img = MinImage::new(&st.periodic);
        let a = Arrays::of(&st, &mask);
        let o = [0.001, -0.002];
        // SAFETY: AVX2 checked above.
        let vm = unsafe { simd::moments(&a, o, &img) };
        let sm = moments_lanes(&a, o, &img, [[0.0; L]; 7], 0).map(total);
        assert_eq!(vm.map(f64::to_bits), sm.map(f64::to_bits));
        let rg = Rigid {
            o,
            c: [0.003, 0.001],
            v: [0.1, -0.2],
            om: 3.0,
            m: 2.0,
            j: 0.5,
            force: [1.0, -0.5],
            moment: 3.5,
        };
        let p = DampIn {
            rg: &rg,
            alpha: 0.7,
            g: [0.0, -9.81],
        };
        let mut out_v: [Vec<f64>; 3] = Default::default();
        let mut out_s: [Vec<f64>; 3] = Default::default();
        for o in out_v.iter_mut().chain(out_s.iter_mut()) {
            o.resize(103, 0.0);
        }
        // SAFETY: AVX2 checked above.
        let rv = unsafe { simd::damp(&a, &p, &img, &mut out_v) };
        let rs = damp_lanes(&a, &p, &img, &mut out_s, [[0.0; L]; 3], 0).map(total);
        assert_eq!(rv.map(f64::to_bits), rs.map(f64::to_bits));
        assert_eq!(out_v, out_s);
        // (a = force/m = [0.5, −0.25], β = moment/J = 7.)
        // SAFETY: AVX2 checked above.
        unsafe { simd::correct(&a, &rg, &img, &mut out_v) };
        correct_from(&a, &rg, &img, &mut out_s, 0);
        assert_eq!(out_v, out_s);
        assert!(out_s[0].iter().any(|&v| v != 0.0));
    }
}
