//! Table 1 from the shipped data: the improved clump is exact, the ORC clump is not.

use clumpgen::ClumpParams;
use std::path::Path;

#[test]
fn table1_improved_is_exact_and_orc_deviates() {
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data");
    let t = validation::table1::table1(
        &data.join("outlines/table1-grain.csv"),
        &data.join("reference/ye_xu_2010_table1.json"),
        &ClumpParams::default(),
    )
    .unwrap();
    let [real, orc, imp] = [&t.rows[0], &t.rows[1], &t.rows[2]];
    assert_eq!(
        (
            real.method.as_str(),
            orc.method.as_str(),
            imp.method.as_str()
        ),
        ("real", "orc", "improved")
    );
    // The stand-in grain has the paper's area, and ρ·t reproduces the paper's real inertia.
    assert!((real.area_mm2 - 2246.63).abs() < 1e-9);
    assert!((real.inertia_g_mm2 - 7.57e5).abs() < 1e-6);
    // Improved ORC: centroid deviation <= 1e-9 mm, inertia equal to 1e-9 relative, same area.
    assert!(imp.centroid_dx_mm.abs() <= 1e-9 && imp.centroid_dy_mm.abs() <= 1e-9);
    assert!((imp.inertia_g_mm2 / real.inertia_g_mm2 - 1.0).abs() <= 1e-9);
    assert!((imp.area_mm2 / real.area_mm2 - 1.0).abs() <= 1e-9);
    assert!(imp.cover >= 0.95);
    // ORC: overlaps counted twice; centroid and inertia off.
    assert!(orc.area_mm2 > real.area_mm2);
    assert!(orc.centroid_dx_mm.hypot(orc.centroid_dy_mm) > 1e-3);
    assert!((orc.inertia_g_mm2 / real.inertia_g_mm2 - 1.0).abs() > 1e-3);
    // The paper's figures are carried beside ours.
    assert_eq!(orc.paper_inertia_g_mm2, 5.62e4);
    assert!(t.markdown().contains("| mass moment of inertia (g·mm²) |"));
}
