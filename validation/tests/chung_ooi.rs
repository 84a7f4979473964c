//! The Chung & Ooi (2011) benchmark at reduced resolution (dt = t_c/500): tests 1–3 within
//! 1 % of their closed forms, and the gross-sliding figures of tests 4–8 (issue 50 item 4).

use validation::chung_ooi::{run_all, TOLERANCE_PCT};

#[test]
fn the_chung_ooi_benchmark_holds_its_closed_forms() {
    let r = run_all(500);
    let bad: Vec<String> = r
        .checks
        .iter()
        .filter(|c| c.asserted && (c.error_pct.is_nan() || c.error_pct.abs() >= TOLERANCE_PCT))
        .map(|c| {
            format!(
                "test {} {} {}: {:.4} %",
                c.test, c.case, c.figure, c.error_pct
            )
        })
        .collect();
    assert!(bad.is_empty(), "beyond {TOLERANCE_PCT} %: {bad:#?}");
    // Every test has asserted figures; the normal ones all are.
    for t in 1..=8u8 {
        assert!(
            r.checks.iter().any(|c| c.test == t && c.asserted),
            "test {t} asserts nothing"
        );
    }
    assert!(r.checks.iter().filter(|c| c.test <= 2).all(|c| c.asserted));
    if std::env::var_os("CHUNG_OOI_PRINT").is_some() {
        for c in &r.checks {
            println!(
                "{} | {} | {} | {:.6e} | {:.6e} | {:.4} | {} | {}",
                c.test, c.case, c.figure, c.ours, c.closed_form, c.error_pct, c.asserted, c.regime
            );
        }
    }
}
