//! The documented peak width is what the stated rule gives on the committed Table 2 runs
//! (docs/report/table2-runs-2026-11-25, a_p = 1 mm cells only), and the statistic reads all 60 runs.

use std::path::Path;
use validation::force_statistics as fs;

#[test]
fn the_committed_runs_give_the_documented_width() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../docs/report/table2-runs-2026-11-25");
    let runs = fs::load_runs(&dir).unwrap();
    assert_eq!(runs.len(), 60);
    let cells = fs::cells(&runs);
    assert_eq!(cells.len(), 12);
    let rows: Vec<fs::WidthRow> = cells
        .iter()
        .filter(|c| c[0].depth_mm == 1.0)
        .map(|c| fs::width_row(c).unwrap())
        .collect();
    assert_eq!(rows.len(), 6);
    let (chosen, _) = fs::choose_width(&rows);
    assert_eq!(
        chosen.unwrap_or(fs::FALLBACK_WIDTH_AP),
        fs::PEAK_WIDTH_AP,
        "the rule and PEAK_WIDTH_AP disagree: update the constant and docs/cutting.md"
    );
    let mut worst: f64 = 0.0;
    for c in &cells {
        let s = fs::cell_stats(c, fs::PEAK_WIDTH_AP).unwrap();
        worst = worst.max((s.averaged_mean_n / s.mean_n - 1.0).abs());
        eprintln!(
            "{} {} {}: travel-weighted / sample mean {:.4}",
            s.method,
            s.depth_mm,
            s.speed_m_s,
            s.averaged_mean_n / s.mean_n
        );
        assert_eq!(s.seeds, 5);
        // The moving mean lies between the mean and the raw peak.
        assert!(
            s.peak_n > s.averaged_mean_n && s.peak_n < s.raw_peak_n,
            "{s:?}"
        );
    }
    // The travel-weighted mean of the averaged history and the results' sample mean agree
    // within a few per cent (they differ where the time step, hence the sampling in travel,
    // changed during a run).
    assert!(worst < 0.05, "{worst}");
}
