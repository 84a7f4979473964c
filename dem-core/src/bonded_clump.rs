//! Bonded clumps: the "improved ORC" grains of Ye & Xu (2010) (S0 in `shared/SOURCES.md`).
//!
//! A grain is a clumpgen [`Template`]: discs whose masses were solved so that the grain's mass,
//! centroid and moment of inertia are exact (consistency equations (1)-(3) of S0:
//! Σm_i = m_p, Σm_i·x_i = 0, Σm_i(r_i²/2 + |x_i|²) = I_p). Placed in a scene, each template
//! disc becomes a *free* disc carrying the template's mass m_i and the inertia m_i·r_i²/2 of a
//! uniform disc about its own centre, so the members together have the grain's mass, centroid
//! and inertia. The members are joined by bonds of the clump's own group ("the discs inside one
//! cluster are joined by bonds of their own strength", S0), so a grain can crush when they
//! break:
//!
//! - every member pair that overlaps or touches within `touch_tol` is bonded;
//! - if that bond graph is not connected, it is completed along a minimum spanning tree of the
//!   member centre distances (Kruskal), so no member is left loose;
//! - each bond's reference gap is the gap at placement (members overlap by design), so the
//!   clump starts force-free.
//!
//! The contact law must not push overlapping members apart either: each overlapping pair's
//! reference gap g0 = min(0, gap) is returned in [`PlacedClump::offsets`], to be registered with
//! the world's contact-offset table (see `docs/dem-core-design.md`), so contact acts only on the
//! overlap beyond the initial one, before and after the intra bond breaks.
//!
//! **Lattice grains** (S3's crushable grains: a `clumpgen.template/2` whose `lattice` record
//! lists the links of a triangular node lattice, docs/lattice.md): the members are the nodes and
//! the bonds are exactly the template's links, the lattice springs (a contact bond group gives
//! the normal and shear springs k_n, k_s of lattice.md; any of the four criteria makes the grain
//! crushable, and its fragments keep their links and break again). No pair search and no
//! spanning tree: a grain of 10,000 nodes is placed in O(links).
//!
//! Masses scale with the scene thickness: a template made for thickness t_tpl placed in a scene
//! of thickness t gets masses m_i·t/t_tpl (same density).

use crate::bond::{BondError, Bonds};
use crate::pipeline::World;
use crate::state::State;
use clumpgen::Template;

/// Result of placing one bonded clump.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacedClump {
    /// Indices of the member discs (in template order).
    pub discs: Vec<usize>,
    /// Bond store positions of the intra-clump bonds.
    pub bonds: Vec<usize>,
    /// Overlapping member pairs: (disc id a, disc id b, reference gap g0 < 0).
    pub offsets: Vec<(u32, u32, f64)>,
}

/// Where and how to place a bonded clump.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Position of the grain's centroid (m) and rotation of the template (rad, CCW).
    pub x: f64,
    pub y: f64,
    pub angle: f64,
    /// Material of the member discs.
    pub material: u16,
    /// Grain id written to [`crate::Discs::group`] of every member.
    pub grain: u32,
    /// Bond group of the intra-clump bonds.
    pub intra_group: u16,
    /// Members closer than this gap (m) are bonded (0: only touching/overlapping pairs).
    pub touch_tol: f64,
}

fn template_error(t: &Template, what: impl Into<String>) -> BondError {
    BondError::Template {
        id: t.id.clone(),
        what: what.into(),
    }
}

/// Add the members of `tpl` to `st` as free discs and bond them with group
/// `p.intra_group` (see the module docs).
pub fn place_bonded_clump_in(
    st: &mut State,
    bonds: &mut Bonds,
    tpl: &Template,
    p: &Placement,
) -> Result<PlacedClump, BondError> {
    if tpl.discs.is_empty() {
        return Err(template_error(tpl, "has no discs"));
    }
    if !(tpl.thickness > 0.0 && tpl.thickness.is_finite()) {
        return Err(template_error(tpl, "thickness must be positive"));
    }
    if let Some(d) = tpl
        .discs
        .iter()
        .find(|d| !(d.r > 0.0 && d.m > 0.0 && d.r.is_finite() && d.m.is_finite()))
    {
        return Err(template_error(
            tpl,
            format!("disc with radius {} and mass {} is not positive", d.r, d.m),
        ));
    }
    if ![p.x, p.y, p.angle, p.touch_tol]
        .iter()
        .all(|v| v.is_finite())
    {
        return Err(template_error(tpl, "placement is not finite"));
    }
    if p.intra_group as usize >= bonds.groups().len() {
        return Err(BondError::UnknownGroup(p.intra_group as usize));
    }
    for (a, da) in tpl.discs.iter().enumerate() {
        if tpl.discs[a + 1..]
            .iter()
            .any(|db| db.x == da.x && db.y == da.y)
        {
            return Err(template_error(
                tpl,
                format!("disc {a} shares its centre with another"),
            ));
        }
    }
    if !(st.thickness > 0.0 && st.thickness.is_finite()) {
        return Err(template_error(tpl, "scene thickness must be positive"));
    }
    let scale = st.thickness / tpl.thickness;
    let (s, c) = p.angle.sin_cos();
    // Fresh ids above every existing one (ids stay unique after reorders and removals).
    let first_id = st.discs.id.iter().map(|&i| i + 1).max().unwrap_or(0);
    let mut discs = Vec::with_capacity(tpl.discs.len());
    for (id, d) in (first_id..).zip(&tpl.discs) {
        let x = st.periodic.wrap(0, p.x + c * d.x - s * d.y);
        let y = st.periodic.wrap(1, p.y + s * d.x + c * d.y);
        let m = d.m * scale;
        let k = st
            .discs
            .push(x, y, d.r, m, 0.5 * m * d.r * d.r, p.material, p.grain);
        st.discs.theta[k] = p.angle;
        st.discs.id[k] = id;
        discs.push(k);
    }
    let n = discs.len();
    let edges = match &tpl.lattice {
        Some(lat) => lattice_edges(st, tpl, &lat.links, &discs)?,
        None => touching_edges(st, &discs, p.touch_tol),
    };
    let mut placed = PlacedClump {
        discs: discs.clone(),
        bonds: Vec::with_capacity(edges.len()),
        offsets: Vec::new(),
    };
    for (a, b, gap) in edges {
        // Cannot fail: indices, radii, group and distinct centres were checked above.
        placed
            .bonds
            .push(bonds.add(st, discs[a], discs[b], p.intra_group)?);
        if gap < 0.0 {
            placed
                .offsets
                .push((st.discs.id[discs[a]], st.discs.id[discs[b]], gap));
        }
    }
    debug_assert_eq!(placed.discs.len(), n);
    Ok(placed)
}

/// A lattice grain (S3's crushable grain, a `clumpgen.template/2` with a `lattice` record):
/// exactly the template's links, each a bond (the lattice springs), with its gap.
fn lattice_edges(
    st: &State,
    tpl: &Template,
    links: &[clumpgen::lattice::Link],
    discs: &[usize],
) -> Result<Vec<(usize, usize, f64)>, BondError> {
    let n = discs.len();
    links
        .iter()
        .enumerate()
        .map(|(k, l)| {
            if l.i >= n || l.j >= n || l.i == l.j {
                return Err(template_error(
                    tpl,
                    format!("lattice.links[{k}] joins nodes {} and {} of {n}", l.i, l.j),
                ));
            }
            let gap = crate::bond::install::gap(st, discs[l.i], discs[l.j]);
            Ok((l.i, l.j, gap))
        })
        .collect()
}

/// An improved-ORC grain: every member pair within `touch_tol`, completed along a minimum
/// spanning tree of the centre distances (see the module docs).
fn touching_edges(st: &State, discs: &[usize], touch_tol: f64) -> Vec<(usize, usize, f64)> {
    let n = discs.len();
    // Candidate pairs with their gaps, sorted by centre distance (ties by index).
    let mut pairs = Vec::with_capacity(n * (n - 1) / 2);
    for a in 0..n {
        for b in a + 1..n {
            let gap = crate::bond::install::gap(st, discs[a], discs[b]);
            let dist = gap + st.discs.r[discs[a]] + st.discs.r[discs[b]];
            pairs.push((dist, a, b, gap));
        }
    }
    pairs.sort_by(|x, y| x.0.total_cmp(&y.0).then((x.1, x.2).cmp(&(y.1, y.2))));
    let mut uf = crate::fragments::UnionFind::new(n);
    let mut edges = Vec::new();
    for &(_, a, b, gap) in &pairs {
        if gap <= touch_tol.max(0.0) {
            uf.union(a, b);
            edges.push((a, b, gap));
        }
    }
    // Minimum spanning tree completion over centre distances.
    for &(_, a, b, gap) in &pairs {
        if uf.union(a, b) {
            edges.push((a, b, gap));
        }
    }
    edges
}

/// Add a bonded clump to a running world: members go into `world.state`, intra bonds into
/// `world.bonds` (which must exist), the overlapping pairs' reference gaps into the world's
/// contact-offset table; the world is refreshed (neighbours, time step). Returns the member
/// disc indices, valid until the next step (which may reorder discs; ids are stable).
pub fn place_bonded_clump(
    world: &mut World,
    tpl: &Template,
    p: &Placement,
) -> Result<Vec<usize>, BondError> {
    let bonds = world.bonds.as_mut().ok_or(BondError::NoBondStage)?;
    let placed = place_bonded_clump_in(&mut world.state, bonds, tpl, p)?;
    for &(a, b, g0) in &placed.offsets {
        world.set_contact_offset(a, b, g0);
    }
    world.refresh();
    Ok(placed.discs)
}
