//! Deleting detached fragments during a cut (`CuttingTest::delete_fragments`; issue 19, item 4):
//! debris that has left the cutting zone is taken out of the world, so it cannot pile up ahead
//! of the rake face and be pushed along by the tool. Deleting particles that leave the region
//! of interest is common DEM practice (Itasca PFC `ball delete` of particles leaving the
//! model); the rules here decide what "left the cutting zone" means. `docs/cutting.md`,
//! "Deleting fragments", gives the reasons.
//!
//! A fragment is a connected component of the intact-bond graph with rigid clumps as one node
//! ([`chips::fragments`]); the heaviest is the workpiece. A fragment is deleted when all of:
//!
//! 1. it is not the workpiece (so it has no intact bond to it);
//! 2. every disc centre lies above y_n + m, y_n the nominal machined surface and the margin m
//!    one mean disc radius of the current assembly;
//! 3. every disc is clear of the tool: its centre is farther than r + m from the tool (the
//!    polyline wall `tool`, or the faces `rake` and `clearance` of the two-segment model), so
//!    it does not touch it, nor will it within the next checks at cutting speed;
//! 4. it is clear of the workpiece (every gap to a workpiece disc > m), or every disc centre
//!    lies above the specimen's initial top y_top: a fragment lying on the uncut surface is
//!    debris, but one touching the workpiece lower down, or lifted off it by less than m, may
//!    be uncut material cracked free in place (or about to settle back), which the tool still
//!    has to cut (deleting it would remove resistance the papers' runs have);
//! 5. it has no fixed disc.
//!
//! The check runs on every history row (`history_every` steps) through the run driver's
//! [`StepHook`]: it is a function of the world alone, so a run resumed from a checkpoint
//! deletes the same fragments at the same steps.

use super::chips::{self, Fragment};
use super::tool::{CLEARANCE, RAKE, TOOL};
use dem_core::bond::Bonds;
use dem_core::neighbors::{closest_on_wall, MinImage};
use dem_core::output::driver::StepHook;
use dem_core::pipeline::RemovalTotals;
use dem_core::state::{State, Wall};
use dem_core::{World, WorldError};
use serde::{Deserialize, Serialize};

/// The levels of the rules (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DebrisRule {
    /// Nominal machined surface y_n.
    pub nominal_y: f64,
    /// The specimen's top before the cut (rule 4).
    pub top_y: f64,
}

/// The fragments to delete from `st` (with `bonds`), by the module's rules, with the tool
/// walls `tool` (segments or polylines); in [`chips::fragments`] order. A pure function of its
/// arguments.
pub fn deletable(
    st: &State,
    bonds: Option<&Bonds>,
    tool: &[&Wall],
    rule: &DebrisRule,
) -> Vec<Fragment> {
    let d = &st.discs;
    if d.is_empty() {
        return Vec::new();
    }
    let margin = d.r.iter().sum::<f64>() / d.len() as f64;
    let img = MinImage::new(&st.periodic);
    // (The contact pass's distance: a disc touches a wall when this is below its radius.)
    let distance = |w: &Wall, k: usize| closest_on_wall(w, d.x[k], d.y[k], &img).2;
    let mut frags = chips::fragments(st, bonds);
    if frags.len() < 2 {
        return Vec::new();
    }
    let work = frags.remove(0);
    let above = |k: usize| d.y[k] > rule.nominal_y + margin;
    let clear = |k: usize| tool.iter().all(|w| distance(w, k) > d.r[k] + margin);
    // Workpiece discs by x, for the clearance test (built when first needed).
    let mut by_x: Option<(Vec<(f64, usize)>, f64)> = None;
    let mut near_work = |f: &Fragment| {
        let (list, rmax) = by_x.get_or_insert_with(|| {
            let mut v: Vec<(f64, usize)> = work.discs.iter().map(|&k| (d.x[k], k)).collect();
            v.sort_by(|a, b| a.0.total_cmp(&b.0));
            let rmax = work.discs.iter().map(|&k| d.r[k]).fold(0.0, f64::max);
            (v, rmax)
        });
        f.discs.iter().any(|&k| {
            let reach = d.r[k] + *rmax + margin;
            let lo = list.partition_point(|e| e.0 < d.x[k] - reach);
            list[lo..]
                .iter()
                .take_while(|e| e.0 <= d.x[k] + reach)
                .any(|&(_, j)| {
                    let gap = (d.x[j] - d.x[k]).hypot(d.y[j] - d.y[k]) - d.r[j] - d.r[k];
                    gap <= margin
                })
        })
    };
    frags
        .into_iter()
        .filter(|f| {
            f.discs.iter().all(|&k| above(k) && clear(k) && !d.fixed[k])
                && (f.discs.iter().all(|&k| d.y[k] > rule.top_y) || !near_work(f))
        })
        .collect()
}

/// Delete the [`deletable`] fragments of `world` (the tool: the walls named `tool`, `rake` and
/// `clearance`), one [`World::remove_discs`] call per fragment, so the world's count of
/// removals is the count of fragments deleted. Returns the number deleted.
pub fn delete_fragments(world: &mut World, rule: &DebrisRule) -> Result<usize, WorldError> {
    let st = &world.state;
    let tool: Vec<&Wall> = st
        .walls
        .iter()
        .filter(|w| [TOOL, RAKE, CLEARANCE].contains(&w.name.as_str()))
        .collect();
    let ids: Vec<Vec<u32>> = deletable(st, world.bonds.as_ref(), &tool, rule)
        .iter()
        .map(|f| f.discs.iter().map(|&k| st.discs.id[k]).collect())
        .collect();
    for f in &ids {
        world.remove_discs(f)?;
    }
    Ok(ids.len())
}

/// The run driver's hook deleting fragments every `every` steps.
pub fn hook(every: u64, rule: DebrisRule) -> StepHook {
    StepHook {
        every: every.max(1),
        run: Box::new(move |w: &mut World| {
            delete_fragments(w, &rule).map(|_| ()).map_err(Into::into)
        }),
        stop: None,
    }
}

/// What the cut deleted ([`crate::cutting::CuttingResult::deleted`]; SI units).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct DeletedFragments {
    /// Steps between checks (the history cadence).
    pub check_every: u64,
    pub fragments: u64,
    pub discs: u64,
    /// Bonds (intact and broken) that went with them.
    pub bonds: u64,
    /// kg, for the scene thickness.
    pub mass: f64,
    /// Kinetic energy at deletion (J).
    pub kinetic_energy: f64,
    /// All the energy they took out (kinetic + contact and bond strain + gravity potential,
    /// the energy balance's `removed` term, J).
    pub energy: f64,
}

impl DeletedFragments {
    /// From a world's totals (every removal there is one fragment, see [`delete_fragments`]).
    pub fn from_totals(t: &RemovalTotals, check_every: u64) -> DeletedFragments {
        DeletedFragments {
            check_every,
            fragments: t.removals,
            discs: t.discs,
            bonds: t.bonds,
            mass: t.mass,
            kinetic_energy: t.kinetic,
            energy: t.energy,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dem_core::bond::bench::lattice_bond_group;

    const R: f64 = 0.5e-3;

    /// The constructed scene of the Done-when: a bonded 10 × 4 block (the workpiece,
    /// top row centres at 3√3/2 mm, top y_top = that + R, nominal surface y_top − 1 mm), a
    /// rake face at x = −2 mm and a clearance face, and around them (ids):
    /// - 40, 41: a bonded pair high above, far from the tool: deleted;
    /// - 42, 43: a bonded pair touching the rake face: kept;
    /// - 44: a loose disc below y_n: kept;
    /// - 45: a disc bonded to the workpiece on its top (above y_n): kept (part of it);
    /// - 46: a loose disc touching the block's top row from the side, centre above y_n + R but
    ///   below y_top (maybe uncut material cracked free): kept;
    /// - 47: a loose disc resting on the top row (centre above y_top): deleted;
    /// - 48: a loose disc 0.3 R from the rake face (not touching, inside the clearance): kept;
    /// - 49: a loose disc about 0.5 R off the block's left end (not touching, inside the
    ///   clearance), centre below y_top: kept.
    fn scene() -> (State, Bonds, DebrisRule) {
        let mut st = State {
            thickness: 1e-3,
            ..State::default()
        };
        let h = 3f64.sqrt() * R;
        for row in 0..4 {
            for c in 0..10 {
                let x = (2 * c + row % 2) as f64 * R;
                st.discs.push_uniform(x, row as f64 * h, R, 2500.0, 1e-3, 0);
            }
        }
        let top_row = 3.0 * h;
        let top_y = top_row + R;
        let rule = DebrisRule {
            nominal_y: top_y - 1e-3,
            top_y,
        };
        let mut push = |x: f64, y: f64| st.discs.push_uniform(x, y, R, 2500.0, 1e-3, 0);
        push(5e-3, 8e-3); // 40
        push(5e-3 + 2.0 * R, 8e-3); // 41
        push(-2e-3 + 0.95 * R, 4e-3); // 42
        push(-2e-3 + 0.95 * R, 4e-3 + 2.0 * R); // 43
        push(25e-3, 0.5e-3); // 44
        push(4.0 * R, top_row + 0.99 * h); // 45: on discs 31 and 32 (x = 3R, 5R)
        push(19.0 * R + 1.98 * R, top_row + 0.2 * R); // 46: beside disc 39 (x = 19R)
        push(10.0 * R, top_row + 0.995 * h); // 47: on 34 and 35 (x = 9R, 11R)
        push(-2e-3 + 1.3 * R, 6e-3); // 48
        push(-1.5 * R, top_row + 0.3 * R); // 49: left of disc 30 (x = R, y = 3h)
        st.walls = vec![
            Wall::new(RAKE, [-2e-3, 1.5e-3], [-2e-3, 9e-3], 1),
            Wall::new(CLEARANCE, [-2e-3, 1.5e-3], [-6e-3, 2e-3], 1),
        ];
        let mut b = Bonds::new(vec![lattice_bond_group(1e-3)]).unwrap();
        b.install_pairs(
            &st,
            (0..40)
                .flat_map(|i| (i + 1..40).map(move |j| (i, j, 0)))
                .filter(|&(i, j, _)| {
                    let d = &st.discs;
                    (d.x[i] - d.x[j]).hypot(d.y[i] - d.y[j]) < 2.0 * R + 1e-9
                }),
        )
        .unwrap();
        b.install_pairs(&st, [(40, 41, 0), (42, 43, 0), (45, 32, 0)])
            .unwrap();
        (st, b, rule)
    }

    fn ids(st: &State, f: &[Fragment]) -> Vec<Vec<u32>> {
        f.iter()
            .map(|f| f.discs.iter().map(|&k| st.discs.id[k]).collect())
            .collect()
    }

    #[test]
    fn only_fragments_clear_of_tool_and_workpiece_go() {
        let (st, b, rule) = scene();
        let d = &st.discs;
        // The set-up is what the doc says.
        let gap = |i: usize, j: usize| (d.x[i] - d.x[j]).hypot(d.y[i] - d.y[j]) - 2.0 * R;
        assert!(gap(46, 39) < 0.0 && d.y[46] > rule.nominal_y + R && d.y[46] < rule.top_y);
        assert!(gap(47, 34) < 0.0 && gap(47, 35) < 0.0 && d.y[47] > rule.top_y);
        assert!(gap(45, 31) < 0.0 && d.y[45] > rule.nominal_y + R);
        assert!(d.y[44] < rule.nominal_y);
        let g49 = gap(49, 30);
        assert!(g49 > 0.0 && g49 < R && d.y[49] > rule.nominal_y + R && d.y[49] < rule.top_y);
        assert!((0..40).all(|k| gap(49, k) > 0.0));
        let tool: Vec<&Wall> = st.walls.iter().collect();
        let img = MinImage::new(&st.periodic);
        let dist = |w: &Wall, k: usize| closest_on_wall(w, d.x[k], d.y[k], &img).2;
        assert!(dist(tool[0], 42) < R, "42 touches the rake");
        let d48 = dist(tool[0], 48);
        assert!(d48 > R && d48 < 2.0 * R, "48 is near the rake, not on it");
        let frags = chips::fragments(&st, Some(&b));
        assert_eq!(frags[0].discs.len(), 41, "the block and disc 45");
        let gone = deletable(&st, Some(&b), &tool, &rule);
        assert_eq!(ids(&st, &gone), vec![vec![40, 41], vec![47]]);
        // The same tool as one rigid polyline wall (clearance end, edge, rake end).
        let mut one = Wall::new(TOOL, st.walls[1].b, st.walls[0].b, 1);
        one.via = vec![st.walls[0].a];
        let gone = deletable(&st, Some(&b), &[&one], &rule);
        assert_eq!(ids(&st, &gone), vec![vec![40, 41], vec![47]]);
        // Without the tool nearby the pair 42-43 and disc 48 would go too.
        let far = [Wall::new(RAKE, [-50e-3, 0.0], [-50e-3, 1e-3], 1)];
        let gone = deletable(&st, Some(&b), &[&far[0]], &rule);
        assert_eq!(
            ids(&st, &gone),
            vec![vec![40, 41], vec![42, 43], vec![47], vec![48]],
            "49 stays: it is within one radius of the workpiece"
        );
    }

    #[test]
    fn the_world_deletes_one_fragment_per_removal() {
        let (mut st, b, rule) = scene();
        // The rigid tool of the cutting test: one polyline wall named `tool`.
        let mut one = Wall::new(TOOL, st.walls[1].b, st.walls[0].b, 1);
        one.via = vec![st.walls[0].a];
        st.walls = vec![one];
        let laws = dem_core::ContactLaws::new(
            2,
            dem_core::ContactModel::Linear(dem_core::LinearSpringDashpot::elastic(1e5, 4e4, 0.5)),
        );
        let mut w = dem_core::bond::world_with_bonds(st, dem_core::Params::default(), laws, b, &[])
            .unwrap();
        let n_bonds = w.bonds.as_ref().unwrap().len();
        w.step();
        assert_eq!(delete_fragments(&mut w, &rule), Ok(2));
        let t = w.removal_totals();
        assert_eq!((t.removals, t.discs, t.bonds), (2, 3, 1));
        for id in [40, 41, 47] {
            assert_eq!(w.index_of_id(id), None);
        }
        assert_eq!(w.state.discs.len(), 47);
        assert_eq!(w.bonds.as_ref().unwrap().len(), n_bonds - 1);
        let m = 2500.0 * 1e-3 * std::f64::consts::PI * R * R;
        let r = DeletedFragments::from_totals(t, 7);
        assert!((r.mass - 3.0 * m).abs() < 1e-12 * m, "{r:?}");
        assert_eq!((r.fragments, r.check_every), (2, 7));
        // A second check finds nothing more.
        assert_eq!(delete_fragments(&mut w, &rule), Ok(0));
    }
}
