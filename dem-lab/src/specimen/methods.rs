//! The three methods of S0 (Ye & Xu 2010), each ending as a relaxed bonded specimen: see the
//! module docs of [`super`]. Disc groups ([`dem_core::Discs::group`]) are grain ids: a disc's own
//! index for the traditional method, the grain index otherwise.

use super::few::{self, Irregular};
use super::generator;
use super::grains::{self, Grains};
use super::improved;
use super::relax::{self, DISC};
use super::rng::Rng;
use super::summary::{self, Stats, Summary};
use super::{GrainMode, Method, Progress, SpecimenError, SpecimenParams};
use dem_core::bond::Bonds;
use dem_core::clump::orc::make_rigid_clump;
use dem_core::state::{State, FREE};
use dem_core::World;
use std::time::Instant;

// (The bond groups live in `groups`, which `few` and `improved` use too; re-exported here
// where they were first defined.)
pub use super::groups::{bond_groups, bond_groups_with, GB, INTRA};

/// A relaxed bonded specimen.
#[derive(Clone, Debug)]
pub struct Specimen {
    pub params: SpecimenParams,
    /// The relaxed world: no walls; bond groups [`super::GRAIN_BOUNDARY`], [`super::INTRA_GRAIN`].
    pub world: World,
    /// Contact reference gaps registered with the world (disc ids a, b, g0 < 0): overlapping
    /// members of improved-ORC grains.
    pub offsets: Vec<(u32, u32, f64)>,
    /// Grain tessellation (ORC and improved, [`GrainMode::All`]).
    pub grains: Option<Grains>,
    /// Irregular grains (ORC and improved, [`GrainMode::Few`]).
    pub irregular: Option<Irregular>,
    pub summary: Summary,
}

/// Build a specimen by `p.method`; `progress` is called during every long stage.
pub fn generate(
    p: &SpecimenParams,
    progress: &mut dyn FnMut(Progress),
) -> Result<Specimen, SpecimenError> {
    p.validate()?;
    let t0 = Instant::now();
    let mut rng = Rng::new(p.seed);
    // Grains come from their own stream, so ORC and improved specimens of one seed share them.
    let mut grain_rng = Rng::new(p.seed ^ 0x5bd1_e995_7f4a_7c15);
    let mut stats = Stats::default();
    let mut irregular = None;
    let (mut world, grains, offsets) = match (p.method, &p.grains) {
        (Method::Traditional, _) => {
            let (mut w, pack) = generator::pack(p, &mut rng, progress)?;
            for k in 0..w.state.discs.len() {
                w.state.discs.group[k] = w.state.discs.id[k];
            }
            stats.pack = pack;
            bond_and_release(&mut w, p, &mut stats, |_, _| Some(GB))?;
            (w, None, Vec::new())
        }
        (Method::Orc, GrainMode::All) => {
            let (w, pack) = generator::pack(p, &mut rng, progress)?;
            stats.pack = pack;
            let g = tessellation(p, &mut grain_rng)?;
            let mut w = clump_grains(w, &g, p)?;
            orc_bond(&mut w, p, &mut stats, progress)?;
            (w, Some(g), Vec::new())
        }
        (Method::Orc, GrainMode::Few(f)) => {
            // The traditional packing of this seed, a few of its disc groups merged.
            let (w, pack) = generator::pack(p, &mut rng, progress)?;
            stats.pack = pack;
            let irr = few::choose(p, f, &w.state, &mut grain_rng, progress)?;
            let mut w = clump_irregular(w, &irr, p)?;
            stats.irregular = Some(irr.stats());
            irregular = Some(irr);
            orc_bond(&mut w, p, &mut stats, progress)?;
            (w, None, Vec::new())
        }
        (Method::Improved, GrainMode::All) => {
            let g = tessellation(p, &mut grain_rng)?;
            let (mut w, offsets, tstats) = improved::build(p, &g, progress)?;
            stats.templates = Some(tstats);
            stats.pack.steps += improved::compact(&mut w, p, progress)?;
            stats.pack.wall_stress = relax::wall_stress(&w.state);
            let group = w.state.discs.group.clone();
            bond_and_release(&mut w, p, &mut stats, move |i, j| {
                (group[i] != group[j]).then_some(GB)
            })?;
            (w, Some(g), offsets)
        }
        (Method::Improved, GrainMode::Few(f)) => {
            let (w, pack) = generator::pack(p, &mut rng, progress)?;
            stats.pack = pack;
            let irr = few::choose(p, f, &w.state, &mut grain_rng, progress)?;
            let (mut w, offsets, tstats, free_area, steps) =
                few::build_improved(p, &w, &irr, progress)?;
            stats.templates = Some(tstats);
            stats.free_area = free_area;
            stats.pack.steps += steps;
            stats.pack.wall_stress = relax::wall_stress(&w.state);
            stats.irregular = Some(irr.stats());
            irregular = Some(irr);
            let group = w.state.discs.group.clone();
            bond_and_release(&mut w, p, &mut stats, move |i, j| {
                (group[i] != group[j]).then_some(GB)
            })?;
            (w, None, offsets)
        }
    };
    let (steps, ke, u) = relax::relax(&mut world, p.ke_ratio, p.max_stage_steps, progress)?;
    stats.relax_steps = steps;
    progress(Progress {
        stage: "summary",
        fraction: 1.0,
        message: format!("relaxed: KE {ke:.3e} J, strain energy {u:.3e} J"),
    });
    let summary = summary::summarize(
        p,
        &world,
        grains.as_ref(),
        &stats,
        t0.elapsed().as_secs_f64(),
    );
    Ok(Specimen {
        params: p.clone(),
        world,
        offsets,
        grains,
        irregular,
        summary,
    })
}

/// ORC: settle the clumps (contacts inside a clump vanish), then bond pairs of different
/// bodies.
fn orc_bond(
    w: &mut World,
    p: &SpecimenParams,
    stats: &mut Stats,
    progress: &mut dyn FnMut(Progress),
) -> Result<(), SpecimenError> {
    stats.pack.steps += generator::settle(w, "clumps", p, progress)?;
    stats.pack.wall_stress = relax::wall_stress(&w.state);
    let body = w.state.discs.body.clone();
    bond_and_release(w, p, stats, move |i, j| {
        (body[i] != body[j] || body[i] == FREE).then_some(GB)
    })
}

fn tessellation(p: &SpecimenParams, rng: &mut Rng) -> Result<Grains, SpecimenError> {
    let seeds = grains::draw_seeds(rng, p.width, p.height, p.grain_size)?;
    Ok(grains::tessellate(&seeds, p.width, p.height))
}

/// The packing's discs in id order (index = position in id order), walls kept.
fn in_id_order(w: &World) -> State {
    let d = &w.state.discs;
    let mut order: Vec<usize> = (0..d.len()).collect();
    order.sort_by_key(|&k| d.id[k]);
    let mut st = State {
        thickness: w.state.thickness,
        walls: w.state.walls.clone(),
        ..State::default()
    };
    for &k in &order {
        st.discs.push(
            d.x[k],
            d.y[k],
            d.r[k],
            d.m[k],
            d.inertia[k],
            d.material[k],
            0,
        );
    }
    st
}

/// Make each non-empty member list (indices into `st`) one rigid ORC clump whose discs get
/// the group `groups[g]`.
fn clump_lists(st: &mut State, members: &[Vec<usize>], groups: &[u32]) {
    for (gi, m) in members.iter().enumerate() {
        if m.is_empty() {
            continue;
        }
        for &k in m {
            st.discs.group[k] = groups[gi];
        }
        // Cannot fail: the members are distinct free discs.
        make_rigid_clump(st, m, &format!("grain-{gi}"));
    }
}

/// A new world whose discs (in id order) are grouped into one rigid ORC clump per grain.
fn clump_grains(w: World, g: &Grains, p: &SpecimenParams) -> Result<World, SpecimenError> {
    let mut st = in_id_order(&w);
    let pts: Vec<[f64; 2]> = (0..st.discs.len())
        .map(|k| [st.discs.x[k], st.discs.y[k]])
        .collect();
    let owner = grains::assign(&g.seeds, g.width, g.height, &pts);
    let mut members: Vec<Vec<usize>> = vec![Vec::new(); g.seeds.len()];
    for (k, &o) in owner.iter().enumerate() {
        members[o].push(k);
    }
    let groups: Vec<u32> = (0..members.len() as u32).collect();
    clump_lists(&mut st, &members, &groups);
    Ok(World::try_new(st, w.params.clone(), relax::laws(p, 0.0))?)
}

/// A new world (discs in id order) in which the packing discs of every irregular grain are one
/// rigid ORC clump. Groups: disc k alone the group k, grain g the group N + g (N discs).
fn clump_irregular(w: World, irr: &Irregular, p: &SpecimenParams) -> Result<World, SpecimenError> {
    let mut st = in_id_order(&w);
    let n = st.discs.len();
    let index: std::collections::HashMap<u32, usize> = {
        let d = &w.state.discs;
        let mut ids: Vec<u32> = d.id.clone();
        ids.sort_unstable();
        ids.into_iter().enumerate().map(|(k, id)| (id, k)).collect()
    };
    for k in 0..n {
        st.discs.group[k] = k as u32;
    }
    let members: Vec<Vec<usize>> = irr
        .grains
        .iter()
        .map(|g| g.packing_discs.iter().map(|id| index[id]).collect())
        .collect();
    let groups: Vec<u32> = (0..members.len()).map(|g| (n + g) as u32).collect();
    clump_lists(&mut st, &members, &groups);
    Ok(World::try_new(st, w.params.clone(), relax::laws(p, 0.0))?)
}

/// Install grain-boundary bonds (pairs within `p.bond_gap` that `choose` accepts), switch
/// friction on, remove the walls.
fn bond_and_release(
    w: &mut World,
    p: &SpecimenParams,
    stats: &mut Stats,
    choose: impl FnMut(usize, usize) -> Option<u16>,
) -> Result<(), SpecimenError> {
    // Intact bonds of the packing stage (unbreakable intra-grain bonds) are re-installed
    // force-free with the real groups, like every new bond.
    let mut bonds = Bonds::new(bond_groups(p))?;
    if let Some(old) = w.bonds.take() {
        for v in old.iter() {
            if v.status == dem_core::bond::BondStatus::Intact {
                bonds.add(&w.state, v.i as usize, v.j as usize, v.group)?;
            }
        }
    }
    bonds.install_within_gap(&w.state, p.bond_gap, choose)?;
    dem_core::bond::attach::attach(w, bonds);
    stats.bonded_box = relax::box_of_walls(&w.state).unwrap_or([0.0, p.width, 0.0, p.height]);
    // Without walls the wall law would only hold the time step down (its stiffness is part of
    // every disc's stiffness floor).
    w.laws = dem_core::contact::ContactLaws::uniform(
        *relax::laws(p, p.micro.friction).model(DISC, DISC),
    );
    w.state.walls.clear();
    w.refresh();
    Ok(())
}
