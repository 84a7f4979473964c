//! Force statistics of cutting histories, fixed before comparing with a paper's numbers.
//!
//! S0 (Ye & Xu 2010, Table 2) reports a "peak" and a "mean" main cutting force, each the mean of
//! 5 runs, and never says how its peak was read. A DEM force history is a train of contact
//! events: its largest sample is one event, 14–26× the mean in our Table 2 runs, while the
//! paper's peak is 1.5–1.9× its mean. This module gives one documented statistic for "the peak
//! as the paper most likely read it" beside the raw one:
//!
//! 1. **Resampling.** Each run's history (travel s_i, force F_i; s non-decreasing, any spacing)
//!    is read as the piecewise-linear function F(s) through its samples. It is resampled onto a
//!    grid of cells of width h starting at the window's start: the value of cell
//!    [s₀ + jh, s₀ + (j+1)h] is the mean of F over the cell, ∫F ds / h, computed exactly from
//!    the cumulative trapezoid integral. This is area-preserving: the work ∫F ds of every cell
//!    is kept, so a one-sample spike is neither lost between grid points nor counted twice,
//!    whatever h and the run's sampling are.
//! 2. **Seed average.** The runs of one cell (seeds) are averaged cell by cell on the common
//!    grid, which covers the part of the window [from, to] that every run's history covers.
//! 3. **Moving mean.** The averaged history is smoothed by a moving mean over n = round(w/h)
//!    cells (width w of travel, at least one cell); the **peak** is the largest of these means
//!    over the stretches that lie wholly inside the grid. With one run it is that run's own
//!    moving-mean peak.
//!
//! Properties (tests below): a constant force gives peak = mean; a square pulse of height H and
//! length ℓ on a baseline B gives H for w ≤ ℓ and B + (H − B) ℓ/w for w > ℓ (edges on the
//! grid); two runs with the same pulse at different travel give half the pulse above the
//! baseline. The seed-averaged mean equals the mean of the runs' travel-weighted means.
//!
//! Inputs with a non-finite value, mismatched lengths or decreasing travel are errors; an empty
//! window or a width no stretch fits gives `None`. Nothing returns NaN.

/// Why a force history cannot be analysed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ForceStatsError {
    #[error("run {run}: {travel} travel values but {force} force values")]
    Lengths {
        run: usize,
        travel: usize,
        force: usize,
    },
    #[error("run {run}: sample {index} is not finite")]
    NonFinite { run: usize, index: usize },
    #[error("run {run}: travel decreases at sample {index}")]
    Decreasing { run: usize, index: usize },
    #[error("{what} must be finite and positive, got {value}")]
    Param { what: &'static str, value: f64 },
}

/// One force history: travel (m or any length unit) and force, one value per sample.
pub type History<'a> = (&'a [f64], &'a [f64]);

/// The seed-averaged moving-mean peak of one cell ([`seed_averaged_peak`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct PeakStat {
    /// Largest moving mean of the seed-averaged history (force unit of the input).
    pub peak: f64,
    /// Travel where that stretch starts.
    pub at: f64,
    /// Travel-weighted mean of the seed-averaged history over the grid (= the mean of the runs'
    /// travel-weighted means over the same range).
    pub mean: f64,
    /// Runs averaged.
    pub runs: usize,
    /// The grid: first cell's start, cell width h and number of cells.
    pub from: f64,
    pub step: f64,
    pub cells: usize,
    /// Moving-mean width actually used: a whole number of cells (n·h).
    pub width: f64,
}

/// Statistics of one run over the window, all travel-weighted on the resampled grid except the
/// raw peak ([`run_stats`]).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RunStats {
    /// ∫F ds / (range length) over the grid.
    pub mean: f64,
    /// Median of the grid cells' means (a travel-weighted median at resolution h).
    pub median: f64,
    /// Largest *sample* in the window (not resampled): the statistic used before.
    pub raw_peak: f64,
    /// Largest moving mean over width w of this run alone; `None` when no stretch fits.
    pub moving_peak: Option<f64>,
    /// Share of the work ∫F ds done over the 5 % of travel with the largest force (the top
    /// ⌈0.05 m⌉ of the m grid cells); `None` when the total work is not positive.
    pub top5_work_share: Option<f64>,
    /// Samples of the run inside the window.
    pub samples: usize,
}

fn check(run: usize, (s, f): History) -> Result<(), ForceStatsError> {
    if s.len() != f.len() {
        return Err(ForceStatsError::Lengths {
            run,
            travel: s.len(),
            force: f.len(),
        });
    }
    for i in 0..s.len() {
        if !(s[i].is_finite() && f[i].is_finite()) {
            return Err(ForceStatsError::NonFinite { run, index: i });
        }
        if i > 0 && s[i] < s[i - 1] {
            return Err(ForceStatsError::Decreasing { run, index: i });
        }
    }
    Ok(())
}

fn positive(what: &'static str, value: f64) -> Result<f64, ForceStatsError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ForceStatsError::Param { what, value })
    }
}

/// The grid every run covers: (first cell start, cells) for cells of width `step` over
/// [max(from, first samples), min(to, last samples)]; `None` when not one whole cell fits.
fn common_grid(runs: &[History], from: f64, to: f64, step: f64) -> Option<(f64, usize)> {
    let mut lo = from;
    let mut hi = to;
    for (s, _) in runs {
        lo = lo.max(*s.first()?);
        hi = hi.min(*s.last()?);
    }
    // A relative tolerance so that a range of exactly k cells is not cut to k − 1 by rounding.
    let cells = ((hi - lo) / step * (1.0 + 1e-12)).floor();
    (cells >= 1.0).then_some((lo, cells as usize))
}

/// Cell means of the linear interpolant of (s, f) on the grid `lo + j·step`, j < `cells`; the
/// grid must lie inside [s₀, s_last].
fn resample((s, f): History, lo: f64, step: f64, cells: usize) -> Vec<f64> {
    // Integral of the interpolant from s[0] to x, with a segment pointer that only moves on
    // (the grid edges increase).
    let mut k = 0usize; // segment [s[k], s[k+1]]
    let mut cum = 0.0; // ∫ from s[0] to s[k]
    let mut integral_to = |x: f64| -> f64 {
        while k + 1 < s.len() && s[k + 1] <= x {
            cum += 0.5 * (s[k + 1] - s[k]) * (f[k] + f[k + 1]);
            k += 1;
        }
        if k + 1 >= s.len() || x <= s[k] {
            return cum;
        }
        let t = (x - s[k]) / (s[k + 1] - s[k]);
        let fx = f[k] + t * (f[k + 1] - f[k]);
        cum + 0.5 * (x - s[k]) * (f[k] + fx)
    };
    let mut prev = integral_to(lo);
    (1..=cells)
        .map(|j| {
            let next = integral_to(lo + j as f64 * step);
            let v = (next - prev) / step;
            prev = next;
            v
        })
        .collect()
}

/// Largest mean of `n` consecutive values and the index where that run starts (first on ties);
/// `None` when n is 0 or larger than the list.
fn max_moving_mean(v: &[f64], n: usize) -> Option<(usize, f64)> {
    if n == 0 || n > v.len() {
        return None;
    }
    let mut prefix = Vec::with_capacity(v.len() + 1);
    prefix.push(0.0);
    for x in v {
        prefix.push(prefix.last().unwrap() + x);
    }
    (0..=v.len() - n)
        .map(|j| (j, (prefix[j + n] - prefix[j]) / n as f64))
        .fold(None, |best: Option<(usize, f64)>, (j, m)| match best {
            Some((_, b)) if b >= m => best,
            _ => Some((j, m)),
        })
}

/// Cells of a moving mean of `width` on a grid of `step`: round(width/step), at least 1.
fn width_cells(width: f64, step: f64) -> usize {
    ((width / step).round() as usize).max(1)
}

/// The seed-averaged moving-mean peak of one cell: `runs` (travel, force) resampled onto a
/// common grid of cell width `step` within `window` = [from, to], averaged cell by cell over
/// the runs, smoothed by a moving mean of `width` of travel, its maximum (module docs).
///
/// `Ok(None)` when there is no run, the runs share no whole grid cell inside the window, or
/// the width is longer than the grid. Errors: a non-finite sample, mismatched lengths,
/// decreasing travel, a step or width that is not finite and positive.
///
/// ```
/// use dem_lab::analysis::force_stats::seed_averaged_peak;
/// let s = [0.0, 1.0, 2.0, 3.0, 4.0];
/// let (a, b) = ([1.0, 1.0, 5.0, 1.0, 1.0], [1.0, 1.0, 1.0, 1.0, 1.0]);
/// let p = seed_averaged_peak(&[(&s[..], &a[..]), (&s[..], &b[..])], [0.0, 4.0], 0.5, 0.5)
///     .unwrap()
///     .unwrap();
/// // The spike's linear interpolant peaks at 5 at s = 2; its half-cells next to it mean 4,
/// // averaged with the other run's 1: 2.5.
/// assert_eq!((p.peak, p.runs, p.cells), (2.5, 2, 8));
/// ```
pub fn seed_averaged_peak(
    runs: &[History],
    window: [f64; 2],
    step: f64,
    width: f64,
) -> Result<Option<PeakStat>, ForceStatsError> {
    let step = positive("grid step", step)?;
    let width = positive("moving-mean width", width)?;
    for (i, r) in runs.iter().enumerate() {
        check(i, *r)?;
    }
    if runs.is_empty() || runs.iter().any(|(s, _)| s.is_empty()) {
        return Ok(None);
    }
    let Some((lo, cells)) = common_grid(runs, window[0], window[1], step) else {
        return Ok(None);
    };
    let mut avg = vec![0.0; cells];
    for r in runs {
        for (a, v) in avg.iter_mut().zip(resample(*r, lo, step, cells)) {
            *a += v;
        }
    }
    let n = runs.len() as f64;
    avg.iter_mut().for_each(|a| *a /= n);
    let w = width_cells(width, step);
    let Some((j, peak)) = max_moving_mean(&avg, w) else {
        return Ok(None);
    };
    Ok(Some(PeakStat {
        peak,
        at: lo + j as f64 * step,
        mean: avg.iter().sum::<f64>() / cells as f64,
        runs: runs.len(),
        from: lo,
        step,
        cells,
        width: w as f64 * step,
    }))
}

/// Statistics of one run over `window` on a grid of `step` ([`RunStats`]); the moving-mean
/// peak over `width`. `Ok(None)` when the window holds no whole grid cell of the history.
/// Errors as [`seed_averaged_peak`].
pub fn run_stats(
    run: History,
    window: [f64; 2],
    step: f64,
    width: f64,
) -> Result<Option<RunStats>, ForceStatsError> {
    let step = positive("grid step", step)?;
    let width = positive("moving-mean width", width)?;
    check(0, run)?;
    if run.0.is_empty() {
        return Ok(None);
    }
    let Some((lo, cells)) = common_grid(&[run], window[0], window[1], step) else {
        return Ok(None);
    };
    let v = resample(run, lo, step, cells);
    let total: f64 = v.iter().sum();
    let mut sorted = v.clone();
    sorted.sort_by(|a, b| b.total_cmp(a));
    let median = if cells % 2 == 1 {
        sorted[cells / 2]
    } else {
        0.5 * (sorted[cells / 2 - 1] + sorted[cells / 2])
    };
    let top = (0.05 * cells as f64).ceil() as usize;
    let top5 = (total > 0.0).then(|| sorted[..top].iter().sum::<f64>() / total);
    let in_window = |x: &f64| *x >= window[0] && *x <= window[1];
    let raw: Vec<f64> = run
        .0
        .iter()
        .zip(run.1)
        .filter(|(x, _)| in_window(x))
        .map(|(_, f)| *f)
        .collect();
    let raw_peak = raw.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    Ok(Some(RunStats {
        mean: total / cells as f64,
        median,
        // A window narrower than the sampling holds no sample: the resampled maximum stands in.
        raw_peak: if raw.is_empty() { sorted[0] } else { raw_peak },
        moving_peak: max_moving_mean(&v, width_cells(width, step)).map(|(_, m)| m),
        top5_work_share: top5,
        samples: raw.len(),
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Travel 0..=len in steps of `ds` (exact binary fractions in the tests).
    fn travel(len: f64, ds: f64) -> Vec<f64> {
        let n = (len / ds).round() as usize;
        (0..=n).map(|i| i as f64 * ds).collect()
    }

    /// A square pulse of `h` on [a, a + l) over baseline `b`, sampled at `s`: the interpolant
    /// ramps over one sample spacing at each edge (`step_pulse` makes the edges exact).
    fn pulse(s: &[f64], b: f64, h: f64, a: f64, l: f64) -> Vec<f64> {
        s.iter()
            .map(|&x| if x >= a && x < a + l { h } else { b })
            .collect()
    }

    /// Samples of an exact step pulse: travel with the edges repeated (a vertical jump of the
    /// interpolant), force B / H.
    fn step_pulse(len: f64, ds: f64, b: f64, h: f64, a: f64, l: f64) -> (Vec<f64>, Vec<f64>) {
        let (mut s, mut f) = (vec![], vec![]);
        for x in travel(len, ds) {
            if x == a {
                s.push(x);
                f.push(b);
            }
            if x == a + l {
                s.push(x);
                f.push(h);
            }
            s.push(x);
            f.push(if x >= a && x < a + l { h } else { b });
        }
        (s, f)
    }

    fn one(s: &[f64], f: &[f64], w: [f64; 2], h: f64, width: f64) -> PeakStat {
        seed_averaged_peak(&[(s, f)], w, h, width).unwrap().unwrap()
    }

    #[test]
    fn a_constant_force_has_peak_equal_to_mean() {
        let s = travel(10.0, 0.25);
        let f = vec![7.0; s.len()];
        for width in [0.125, 1.0, 3.0, 8.0] {
            let p = one(&s, &f, [2.0, 10.0], 0.125, width);
            assert!((p.peak - 7.0).abs() < 1e-12 && (p.mean - 7.0).abs() < 1e-12);
            assert_eq!((p.from, p.cells), (2.0, 64));
        }
        let r = run_stats((&s, &f), [2.0, 10.0], 0.125, 1.0)
            .unwrap()
            .unwrap();
        assert_eq!((r.mean, r.median, r.raw_peak), (7.0, 7.0, 7.0));
        assert_eq!(r.moving_peak, Some(7.0));
        assert_eq!(r.samples, 33);
        // 5 % of 64 cells: ⌈3.2⌉ = 4 cells, 4/64 of the work.
        assert!((r.top5_work_share.unwrap() - 4.0 / 64.0).abs() < 1e-12);
    }

    #[test]
    fn a_square_pulse_narrower_and_wider_than_the_width() {
        // B = 2, H = 12 over [4, 5.5): ℓ = 1.5.
        let (b, h, a, l) = (2.0, 12.0, 4.0, 1.5);
        let (s, f) = step_pulse(10.0, 1.0 / 64.0, b, h, a, l);
        for width in [0.25, 1.0, 1.5] {
            let p = one(&s, &f, [0.0, 10.0], 1.0 / 64.0, width);
            assert!((p.peak - h).abs() < 1e-12, "w {width}: {}", p.peak);
            assert!(p.at >= a && p.at + width <= a + l + 1e-12);
        }
        for width in [2.0, 3.0, 6.0] {
            let p = one(&s, &f, [0.0, 10.0], 1.0 / 64.0, width);
            let expect = b + (h - b) * l / width;
            assert!((p.peak - expect).abs() < 1e-12, "w {width}: {}", p.peak);
        }
        // The mean is the work over the range: B + (H − B) ℓ/L.
        let p = one(&s, &f, [0.0, 10.0], 1.0 / 64.0, 1.0);
        assert!((p.mean - (b + (h - b) * l / 10.0)).abs() < 1e-12);
        // Sampled without the repeated edges, the interpolant ramps over one spacing at each
        // edge (the pulse keeps its area): the peak is still H for w ≤ ℓ − spacing.
        let s2 = travel(10.0, 1.0 / 64.0);
        let f2 = pulse(&s2, b, h, a, l);
        let p = one(&s2, &f2, [0.0, 10.0], 1.0 / 64.0, 1.0);
        assert!((p.peak - h).abs() < 1e-12);
        let p = one(&s2, &f2, [0.0, 10.0], 1.0 / 64.0, 3.0);
        assert!((p.peak - (b + (h - b) * l / 3.0)).abs() < 1e-12);
    }

    #[test]
    fn pulses_at_different_travel_halve_the_averaged_peak() {
        let (b, h, l) = (1.0, 21.0, 0.5);
        let (s1, f1) = step_pulse(10.0, 1.0 / 32.0, b, h, 3.0, l);
        let (s2, f2) = step_pulse(10.0, 1.0 / 32.0, b, h, 7.0, l);
        let both = [(&s1[..], &f1[..]), (&s2[..], &f2[..])];
        let p = seed_averaged_peak(&both, [2.0, 10.0], 1.0 / 32.0, 0.25)
            .unwrap()
            .unwrap();
        // Each run alone peaks at H; averaged, one pulse over the other's baseline.
        assert!((p.peak - (b + (h - b) / 2.0)).abs() < 1e-12, "{}", p.peak);
        assert_eq!(p.runs, 2);
        let alone = one(&s1, &f1, [2.0, 10.0], 1.0 / 32.0, 0.25);
        assert!((alone.peak - h).abs() < 1e-12);
        // Pulses at the same travel average to H.
        let same = [(&s1[..], &f1[..]), (&s1[..], &f1[..])];
        let p = seed_averaged_peak(&same, [2.0, 10.0], 1.0 / 32.0, 0.25)
            .unwrap()
            .unwrap();
        assert!((p.peak - h).abs() < 1e-12);
        // The averaged mean is the mean of the runs' means.
        let m1 = run_stats((&s1, &f1), [2.0, 10.0], 1.0 / 32.0, 0.25)
            .unwrap()
            .unwrap()
            .mean;
        let p = seed_averaged_peak(&both, [2.0, 10.0], 1.0 / 32.0, 0.25)
            .unwrap()
            .unwrap();
        assert!((p.mean - m1).abs() < 1e-12);
        assert!((m1 - (b + (h - b) * l / 8.0)).abs() < 1e-12);
    }

    #[test]
    fn non_uniform_sampling_keeps_the_work() {
        // F(s) = s on [0, 10], sampled at irregular points: the interpolant is exact, so the
        // cell means are the cell midpoints and the moving mean of width w ends at 10.
        let mut s = vec![0.0];
        let mut x: f64 = 0.0;
        let mut k = 0;
        while x < 10.0 {
            x = (x + [0.013, 0.31, 0.0007, 0.127][k % 4]).min(10.0);
            s.push(x);
            k += 1;
        }
        let f = s.clone();
        let p = one(&s, &f, [1.0, 10.0], 0.01, 2.0);
        // Grid [1, 10]: the last 2-wide stretch is [8, 10], mean 9.
        assert!((p.peak - 9.0).abs() < 1e-9, "{}", p.peak);
        assert!((p.mean - 5.5).abs() < 1e-9);
        // A coarse second run sampled at the ends only gives the same line.
        let (sc, fc) = (vec![0.0, 10.0], vec![0.0, 10.0]);
        let p2 = seed_averaged_peak(&[(&s, &f), (&sc, &fc)], [1.0, 10.0], 0.01, 2.0)
            .unwrap()
            .unwrap();
        assert!((p2.peak - 9.0).abs() < 1e-9);
        // A single-sample spike keeps its area (½·base·height) at any grid step.
        let s3 = [0.0, 1.0, 1.1, 1.2, 3.0];
        let f3 = [0.0, 0.0, 50.0, 0.0, 0.0];
        for h in [0.01, 0.05, 0.3] {
            let r = run_stats((&s3, &f3), [0.0, 3.0], h, 0.5).unwrap().unwrap();
            let range = (3.0 / h * (1.0 + 1e-12)).floor() * h;
            assert!((r.mean * range - 5.0).abs() < 1e-9, "h {h}: {}", r.mean);
            assert_eq!(r.raw_peak, 50.0);
        }
    }

    #[test]
    fn runs_cover_different_ranges() {
        // The grid is the part of the window every run covers.
        let a = travel(10.0, 0.5);
        let b: Vec<f64> = travel(7.0, 0.5).iter().map(|x| x + 1.0).collect(); // [1, 8]
        let fa = vec![2.0; a.len()];
        let fb = vec![4.0; b.len()];
        let p = seed_averaged_peak(&[(&a, &fa), (&b, &fb)], [0.5, 9.0], 0.25, 1.0)
            .unwrap()
            .unwrap();
        assert_eq!((p.from, p.cells), (1.0, 28));
        assert!((p.peak - 3.0).abs() < 1e-12 && (p.mean - 3.0).abs() < 1e-12);
    }

    #[test]
    fn empty_windows_and_bad_input() {
        let s = travel(10.0, 0.5);
        let f = vec![1.0; s.len()];
        let r = [(&s[..], &f[..])];
        // Window outside the history, narrower than a cell, no runs, empty run, width too long.
        assert_eq!(seed_averaged_peak(&r, [20.0, 30.0], 0.5, 1.0), Ok(None));
        assert_eq!(seed_averaged_peak(&r, [2.0, 2.1], 0.5, 0.5), Ok(None));
        assert_eq!(seed_averaged_peak(&[], [0.0, 10.0], 0.5, 1.0), Ok(None));
        assert_eq!(
            seed_averaged_peak(&[(&[], &[])], [0.0, 1.0], 0.5, 1.0),
            Ok(None)
        );
        assert_eq!(seed_averaged_peak(&r, [0.0, 10.0], 0.5, 10.5), Ok(None));
        assert_eq!(run_stats(r[0], [20.0, 30.0], 0.5, 1.0), Ok(None));
        let one_wide = run_stats(r[0], [0.0, 10.0], 0.5, 20.0).unwrap().unwrap();
        assert_eq!(one_wide.moving_peak, None);
        // NaN anywhere, mismatched lengths, decreasing travel, bad parameters: errors.
        let mut g = f.clone();
        g[3] = f64::NAN;
        assert_eq!(
            seed_averaged_peak(&[r[0], (&s, &g)], [0.0, 10.0], 0.5, 1.0),
            Err(ForceStatsError::NonFinite { run: 1, index: 3 })
        );
        assert!(run_stats((&s, &g), [0.0, 10.0], 0.5, 1.0).is_err());
        assert!(matches!(
            seed_averaged_peak(&[(&s, &f[1..])], [0.0, 10.0], 0.5, 1.0),
            Err(ForceStatsError::Lengths { .. })
        ));
        let mut back = s.clone();
        back.swap(4, 5);
        assert_eq!(
            seed_averaged_peak(&[(&back, &f)], [0.0, 10.0], 0.5, 1.0),
            Err(ForceStatsError::Decreasing { run: 0, index: 5 })
        );
        for (h, w) in [
            (0.0, 1.0),
            (f64::NAN, 1.0),
            (0.5, -1.0),
            (0.5, f64::INFINITY),
        ] {
            assert!(matches!(
                seed_averaged_peak(&r, [0.0, 10.0], h, w),
                Err(ForceStatsError::Param { .. })
            ));
        }
        // Huge but finite values give a finite answer, never NaN.
        let big = vec![1e300; s.len()];
        let p = seed_averaged_peak(&[(&s, &big)], [0.0, 10.0], 0.5, 1.0)
            .unwrap()
            .unwrap();
        assert!(p.peak.is_finite());
    }

    #[test]
    fn top_five_percent_of_travel_and_median() {
        // Force 100 over the first 0.5 of a 10-long range (5 % of travel), 0 elsewhere: all
        // the work in the top 5 %; the median is 0.
        let (s, f) = step_pulse(10.0, 0.125, 0.0, 100.0, 0.0, 0.5);
        let r = run_stats((&s, &f), [0.0, 10.0], 0.125, 0.25)
            .unwrap()
            .unwrap();
        assert!((r.top5_work_share.unwrap() - 1.0).abs() < 1e-12);
        assert_eq!(r.median, 0.0);
        assert!((r.mean - 5.0).abs() < 1e-12);
        // No positive work: no share.
        let z = vec![0.0; s.len()];
        let r = run_stats((&s, &z), [0.0, 10.0], 0.125, 0.25)
            .unwrap()
            .unwrap();
        assert_eq!(r.top5_work_share, None);
    }
}
