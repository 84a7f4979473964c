//! The template stage of improved-ORC specimens on a coarse tessellation (20 × 10 mm, grains
//! 1.4 mm, template discs from 0.25 mm) that once failed: a mass-fit repair disc was placed on
//! a fill disc's raster centre, and the bonded clump rejected the two concentric members
//! ("disc 3 shares its centre with another", grain 69 of seed 1). Every cell must now give a
//! template whose members are pairwise apart by at least half the smaller radius.

use dem_lab::specimen::grains::{draw_seeds, tessellate};
use dem_lab::specimen::improved::build;
use dem_lab::specimen::rng::Rng;
use dem_lab::specimen::{Method, SpecimenParams};

#[test]
fn coarse_templates_build_without_concentric_members() {
    let mut p = SpecimenParams::new(
        Method::Improved,
        20e-3,
        10e-3,
        0.3e-3,
        0.5e-3,
        3200.0,
        310e9,
        800e6,
        1,
    );
    p.grain_size = 1.4e-3;
    p.template_r_min = 0.25e-3;
    // The stream `generate` uses for the tessellation (methods.rs).
    let mut rng = Rng::new(p.seed ^ 0x5bd1_e995_7f4a_7c15);
    let seeds = draw_seeds(&mut rng, p.width, p.height, p.grain_size).unwrap();
    let g = tessellate(&seeds, p.width, p.height);
    let (world, _, stats) = build(&p, &g, &mut |_| {}).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(stats.grains, g.cells.len());
    let d = &world.state.discs;
    // Members of one grain (bonded clumps keep the grain id in `group`/`grain`): check all
    // pairs of discs closer than half the smaller radius.
    for i in 0..d.len() {
        for j in i + 1..d.len() {
            let dist = (d.x[i] - d.x[j]).hypot(d.y[i] - d.y[j]);
            assert!(
                dist >= 0.5 * d.r[i].min(d.r[j]) * 0.999,
                "discs {i} and {j} are {dist} m apart (radii {}, {})",
                d.r[i],
                d.r[j]
            );
        }
    }
}
