//! SVG plots of the report (plotters, SVG backend, no fonts needed: text is SVG `<text>`).
//! Each function returns the SVG text; the report writes it to a file and inlines it in
//! `index.html`.

use crate::error::{Error, Result};
use plotters::prelude::*;

/// One line of a line chart.
#[derive(Debug, Clone)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// Matplotlib's "tab10": ten colours before a series repeats one (the speed-damping study
/// draws seven lines; with six colours its first and seventh were both blue).
const COLORS: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

fn range(v: impl Iterator<Item = f64>, log: bool) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for x in v.filter(|x| x.is_finite() && (!log || *x > 0.0)) {
        lo = lo.min(x);
        hi = hi.max(x);
    }
    if !lo.is_finite() {
        return if log { (0.1, 1.0) } else { (0.0, 1.0) };
    }
    if log {
        (lo / 1.2, hi * 1.2)
    } else {
        let pad = 0.05 * (hi - lo).max(hi.abs() * 1e-3).max(1e-300);
        (lo - pad, hi + pad)
    }
}

/// A tick label with at most three significant digits (log axes' ticks otherwise print as
/// `0.6000000000000001`); scientific notation outside [1e-3, 1e5).
/// A tick value at rounding distance from zero on the axis `[lo, hi]` is zero: a tick at
/// −2.2e-16 on the Weibull plot's axis (issue 48) is the 0 that accumulated steps missed.
fn snap(v: f64, lo: f64, hi: f64) -> f64 {
    if v.abs() <= 1e-9 * (hi - lo).abs() {
        0.0
    } else {
        v
    }
}

fn tick(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if !(1e-3..1e5).contains(&a) {
        return format!("{v:.1e}");
    }
    let decimals = (2 - a.log10().floor() as i32).max(0) as usize;
    let t = format!("{v:.decimals$}");
    if t.contains('.') {
        t.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        t
    }
}

/// Upper left or upper right, whichever holds fewer of the points (the top 35 % of the height,
/// the outer 40 % of the width, on the axes' own scales); upper left on a tie.
fn legend_corner(
    series: &[Series],
    (x0, x1, log_x): (f64, f64, bool),
    (y0, y1, log_y): (f64, f64, bool),
) -> SeriesLabelPosition {
    let frac = |v: f64, a: f64, b: f64, log: bool| {
        if log {
            (v.ln() - a.ln()) / (b.ln() - a.ln())
        } else {
            (v - a) / (b - a)
        }
    };
    let (mut left, mut right) = (0, 0);
    for p in series.iter().flat_map(|s| &s.points) {
        let (fx, fy) = (frac(p.0, x0, x1, log_x), frac(p.1, y0, y1, log_y));
        if fy > 0.65 {
            left += usize::from(fx < 0.4);
            right += usize::from(fx > 0.6);
        }
    }
    if right < left {
        SeriesLabelPosition::UpperRight
    } else {
        SeriesLabelPosition::UpperLeft
    }
}

fn err<E: std::fmt::Display>(e: E) -> Error {
    Error::Plot(e.to_string())
}

/// Line chart with markers; `log_x`, `log_y` for logarithmic axes.
pub fn lines(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    log_x: bool,
    log_y: bool,
) -> Result<String> {
    chart(title, x_label, y_label, series, &[], (log_x, log_y))
}

/// Line chart whose series `k` with `markers_only[k]` true are drawn as markers alone (a
/// scatter of measured points beside fitted lines).
pub fn scatter_and_lines(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    markers_only: &[bool],
    log_x: bool,
    log_y: bool,
) -> Result<String> {
    chart(
        title,
        x_label,
        y_label,
        series,
        markers_only,
        (log_x, log_y),
    )
}

fn chart(
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
    markers_only: &[bool],
    (log_x, log_y): (bool, bool),
) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (720, 440)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let (x0, x1) = range(
            series.iter().flat_map(|s| s.points.iter().map(|p| p.0)),
            log_x,
        );
        let (y0, y1) = range(
            series.iter().flat_map(|s| s.points.iter().map(|p| p.1)),
            log_y,
        );
        let mut b = ChartBuilder::on(&root);
        b.caption(title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(70);
        macro_rules! draw {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(x_label)
                    .y_desc(y_label)
                    .x_label_formatter(&|v| tick(snap(*v, x0, x1)))
                    .y_label_formatter(&|v| tick(snap(*v, y0, y1)))
                    .draw()
                    .map_err(err)?;
                for (k, s) in series.iter().enumerate() {
                    let c = COLORS[k % COLORS.len()];
                    let pts: Vec<(f64, f64)> = s
                        .points
                        .iter()
                        .copied()
                        .filter(|p| p.0.is_finite() && p.1.is_finite())
                        .collect();
                    let only = markers_only.get(k).copied().unwrap_or(false);
                    if only {
                        chart
                            .draw_series(pts.iter().map(|p| Circle::new(*p, 3, c.filled())))
                            .map_err(err)?
                            .label(s.name.clone())
                            .legend(move |(x, y)| Circle::new((x + 9, y), 3, c.filled()));
                        continue;
                    }
                    chart
                        .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                        .map_err(err)?
                        .label(s.name.clone())
                        .legend(move |(x, y)| {
                            PathElement::new(vec![(x, y), (x + 18, y)], c.stroke_width(2))
                        });
                    if pts.len() <= 40 {
                        chart
                            .draw_series(pts.iter().map(|p| Circle::new(*p, 3, c.filled())))
                            .map_err(err)?;
                    }
                }
                chart
                    .configure_series_labels()
                    .position(legend_corner(series, (x0, x1, log_x), (y0, y1, log_y)))
                    .background_style(WHITE.mix(0.8))
                    .border_style(BLACK)
                    .draw()
                    .map_err(err)?;
            }};
        }
        // A log axis spanning less than 64× gets its ticks at powers of 2 (0.25, 0.5, 1, 2, 4
        // for a speed study), wider ones at powers of 10.
        let log_base = |a: f64, b: f64| if b / a < 64.0 { 2.0 } else { 10.0 };
        let (bx, by) = (log_base(x0, x1), log_base(y0, y1));
        match (log_x, log_y) {
            (false, false) => draw!(b.build_cartesian_2d(x0..x1, y0..y1).map_err(err)?),
            (true, false) => draw!(b
                .build_cartesian_2d((x0..x1).log_scale().base(bx), y0..y1)
                .map_err(err)?),
            (false, true) => draw!(b
                .build_cartesian_2d(x0..x1, (y0..y1).log_scale().base(by))
                .map_err(err)?),
            (true, true) => draw!(b
                .build_cartesian_2d((x0..x1).log_scale().base(bx), (y0..y1).log_scale().base(by))
                .map_err(err)?),
        }
        root.present().map_err(err)?;
    }
    Ok(svg)
}

/// Grouped bar chart: one group per category, one bar per series (values ≥ 0).
pub fn bars(
    title: &str,
    y_label: &str,
    categories: &[String],
    series: &[(String, Vec<f64>)],
) -> Result<String> {
    let styled: Vec<_> = series
        .iter()
        .enumerate()
        .map(|(s, (name, vals))| {
            (
                name.clone(),
                vals.clone(),
                COLORS[s % COLORS.len()].filled(),
            )
        })
        .collect();
    bar_chart(title, y_label, categories, &styled)
}

/// Grouped bar chart of ours against a reference: one group per category; per series a solid
/// bar (ours) beside a pale bar of the same colour (the reference), so that 3 methods × 2
/// values stay readable with 4 categories. Values ≥ 0; non-finite values are left out.
pub fn bars_against(
    title: &str,
    y_label: &str,
    categories: &[String],
    series: &[(String, Vec<f64>, Vec<f64>)],
    reference: &str,
) -> Result<String> {
    let mut styled = vec![];
    for (s, (name, ours, theirs)) in series.iter().enumerate() {
        let c = COLORS[s % COLORS.len()];
        styled.push((name.clone(), ours.clone(), c.filled()));
        styled.push((
            format!("{name}, {reference}"),
            theirs.clone(),
            c.mix(0.35).filled(),
        ));
    }
    bar_chart(title, y_label, categories, &styled)
}

/// The grouped bars of [`bars`] and [`bars_against`]: series in order within each category,
/// the legend top left above the bars (head room grows with the number of series).
fn bar_chart(
    title: &str,
    y_label: &str,
    categories: &[String],
    series: &[(String, Vec<f64>, ShapeStyle)],
) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, (860, 440)).into_drawing_area();
        root.fill(&WHITE).map_err(err)?;
        let ymax = series
            .iter()
            .flat_map(|s| s.1.iter().copied())
            .filter(|v| v.is_finite())
            .fold(0.0f64, f64::max)
            * (1.2 + 0.1 * series.len() as f64);
        let n = categories.len().max(1) as f64;
        let mut chart = ChartBuilder::on(&root)
            .caption(title, ("sans-serif", 18))
            .margin(12)
            .x_label_area_size(40)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..n, 0.0..ymax.max(1e-300))
            .map_err(err)?;
        let cats = categories.to_vec();
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(categories.len() * 2 + 1)
            .x_label_formatter(&move |x| {
                let i = x.floor() as usize;
                if (x - x.floor() - 0.5).abs() < 0.26 && i < cats.len() {
                    cats[i].clone()
                } else {
                    String::new()
                }
            })
            .y_desc(y_label)
            .draw()
            .map_err(err)?;
        let w = 0.8 / series.len().max(1) as f64;
        for (s, (name, vals, style)) in series.iter().enumerate() {
            let style = *style;
            chart
                .draw_series(vals.iter().enumerate().filter(|(_, v)| v.is_finite()).map(
                    |(i, v)| {
                        let x0 = i as f64 + 0.1 + s as f64 * w;
                        Rectangle::new([(x0, 0.0), (x0 + w * 0.9, *v)], style)
                    },
                ))
                .map_err(err)?
                .label(name.clone())
                .legend(move |(x, y)| Rectangle::new([(x, y - 5), (x + 12, y + 5)], style));
        }
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperLeft)
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(err)?;
        root.present().map_err(err)?;
    }
    Ok(svg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_labels_are_short() {
        assert_eq!(tick(0.6000000000000001), "0.6");
        assert_eq!(tick(100.0), "100");
        assert_eq!(tick(90.0), "90");
        assert_eq!(tick(0.25), "0.25");
        assert_eq!(tick(12.345), "12.3");
        assert_eq!(tick(2.5e-9), "2.5e-9");
        assert_eq!(tick(0.0), "0");
        // Issue 48: the Weibull plot's "-2.2e-16".
        assert_eq!(tick(snap(-2.220446049250313e-16, -4.0, 2.0)), "0");
        assert_eq!(tick(snap(1e-6, 0.0, 1e-5)), "1.0e-6");
    }

    #[test]
    fn line_and_bar_charts_are_svg() {
        let s = vec![Series {
            name: "a".into(),
            points: vec![(1.0, 2.0), (10.0, 3.0), (100.0, f64::NAN)],
        }];
        let svg = lines("t", "x", "y", &s, true, false).unwrap();
        assert!(svg.starts_with("<svg") && (svg.contains("<polyline") || svg.contains("<path")));
        let p = bars_against(
            "t",
            "kN",
            &["c1".into(), "c2".into()],
            &[("orc".into(), vec![1.0, f64::NAN], vec![2.0, 3.0])],
            "paper",
        )
        .unwrap();
        assert!(p.starts_with("<svg") && p.contains("orc, paper"));
        let b = bars(
            "t",
            "kN",
            &["c1".into(), "c2".into()],
            &[("ours".into(), vec![1.0, 2.0])],
        )
        .unwrap();
        assert!(b.contains("<rect"));
        assert!(b.contains("c1"));
    }

    #[test]
    fn the_legend_goes_to_the_emptier_upper_corner() {
        let falling = [Series {
            name: "a".into(),
            points: vec![(1.0, 10.0), (2.0, 5.0), (3.0, 1.0)],
        }];
        let rising = [Series {
            name: "a".into(),
            points: vec![(1.0, 1.0), (2.0, 5.0), (3.0, 10.0)],
        }];
        let ax = (1.0, 3.0, false);
        let ay = (1.0, 10.0, false);
        assert!(matches!(
            legend_corner(&falling, ax, ay),
            SeriesLabelPosition::UpperRight
        ));
        assert!(matches!(
            legend_corner(&rising, ax, ay),
            SeriesLabelPosition::UpperLeft
        ));
    }
}
