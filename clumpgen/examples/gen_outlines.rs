//! Generate the project's synthetic grain outlines (`data/outlines/`).
//!
//! ```text
//! cargo run -p clumpgen --release --example gen_outlines -- data/outlines [--preview out.svg]
//! ```
//!
//! Writes one CSV per grain of [`CATALOGUE`] (`# units: mm` comment, `x,y` header, vertices
//! counter-clockwise in millimetres, centroid at the origin, no repeated closing point), plus
//! `table1-grain.csv`, a stand-in for the grain of Ye & Xu (2010) Table 1 scaled to exactly
//! its published area of 2246.63 mm², and `README.md` with the table of files. Every file is
//! read back with `clumpgen::read_outline` (which validates it) to fill the table. Output is
//! identical on every run and platform (SplitMix64 generator, shortest round-trip decimals).
//! `--preview` also writes an SVG contact sheet of all grains.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use clumpgen::{
    polygon_props, read_outline, scale_to_area, shape_descriptors, synth_grain, ReadOptions,
    SynthParams,
};

/// One grain: file stem, seed, equivalent radius (mm), inertia aspect ratio, roughness,
/// concavity, vertex count. See `clumpgen::synth` for what the parameters mean.
struct Spec(&'static str, u64, f64, f64, f64, f64, usize);

/// Granite / ceramic-like grains, equivalent radius 0.5–2 mm, in five families.
const CATALOGUE: &[Spec] = &[
    // Equant, worn: low roughness, shallow dents.
    Spec("equant-01", 101, 1.00, 1.10, 0.04, 0.10, 120),
    Spec("equant-02", 102, 0.60, 1.20, 0.05, 0.15, 80),
    Spec("equant-03", 103, 1.50, 1.05, 0.06, 0.20, 160),
    Spec("equant-04", 104, 0.80, 1.30, 0.05, 0.10, 100),
    Spec("equant-05", 105, 1.80, 1.15, 0.07, 0.25, 200),
    Spec("equant-06", 106, 0.50, 1.25, 0.04, 0.15, 60),
    // Rough, irregular outlines.
    Spec("rough-01", 201, 1.20, 1.40, 0.10, 0.20, 150),
    Spec("rough-02", 202, 0.70, 1.60, 0.11, 0.25, 90),
    Spec("rough-03", 203, 1.60, 1.30, 0.12, 0.15, 180),
    Spec("rough-04", 204, 0.90, 1.80, 0.10, 0.30, 110),
    Spec("rough-05", 205, 2.00, 1.50, 0.09, 0.20, 200),
    Spec("rough-06", 206, 0.55, 1.20, 0.12, 0.25, 70),
    // Concave: deep dents (solidity well below 1).
    Spec("concave-01", 301, 1.10, 1.30, 0.06, 0.50, 140),
    Spec("concave-02", 302, 1.40, 1.60, 0.08, 0.55, 170),
    Spec("concave-03", 303, 0.75, 1.20, 0.07, 0.60, 100),
    Spec("concave-04", 304, 1.90, 2.00, 0.09, 0.50, 200),
    Spec("concave-05", 305, 0.95, 1.50, 0.10, 0.60, 120),
    Spec("concave-06", 306, 0.65, 1.40, 0.05, 0.45, 80),
    // Elongated: aspect ratio 2.5–3, some also concave.
    Spec("elongated-01", 401, 1.00, 3.00, 0.06, 0.15, 150),
    Spec("elongated-02", 402, 1.50, 2.80, 0.08, 0.30, 180),
    Spec("elongated-03", 403, 0.70, 3.00, 0.10, 0.45, 110),
    Spec("elongated-04", 404, 1.20, 2.50, 0.12, 0.20, 160),
    Spec("elongated-05", 405, 1.80, 3.00, 0.07, 0.50, 200),
    Spec("elongated-06", 406, 0.60, 2.70, 0.05, 0.10, 90),
    // Mixed.
    Spec("mixed-01", 501, 1.30, 1.90, 0.11, 0.35, 130),
    Spec("mixed-02", 502, 0.85, 2.20, 0.09, 0.25, 100),
    Spec("mixed-03", 503, 1.70, 1.70, 0.13, 0.40, 190),
    Spec("mixed-04", 504, 0.50, 1.50, 0.08, 0.30, 60),
];

/// Ye & Xu (2010) Table 1 grain area, mm² (its outline is not published).
const TABLE1_AREA_MM2: f64 = 2246.63;
const TABLE1: Spec = Spec("table1-grain", 601, 26.74, 1.60, 0.08, 0.35, 200);

fn write_csv(path: &Path, comment: &str, pts: &[[f64; 2]]) -> std::io::Result<()> {
    let mut s = String::new();
    writeln!(s, "# {comment}").unwrap();
    writeln!(s, "# units: mm").unwrap();
    writeln!(s, "x,y").unwrap();
    for p in pts {
        // `{}` prints the shortest decimal that reads back to the same f64.
        writeln!(s, "{},{}", p[0], p[1]).unwrap();
    }
    std::fs::write(path, s)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let out = PathBuf::from(
        args.first()
            .ok_or("usage: gen_outlines <dir> [--preview f.svg]")?,
    );
    let preview = args
        .iter()
        .position(|a| a == "--preview")
        .and_then(|i| args.get(i + 1))
        .map(PathBuf::from);
    std::fs::create_dir_all(&out)?;

    let mut rows = String::new();
    let mut shapes: Vec<(String, Vec<[f64; 2]>)> = Vec::new();
    for (spec, is_table1) in CATALOGUE
        .iter()
        .map(|s| (s, false))
        .chain(std::iter::once((&TABLE1, true)))
    {
        let Spec(name, seed, r_eq, ar, rough, conc, n) = *spec;
        let params = SynthParams {
            mean_radius: r_eq,
            aspect_ratio: ar,
            roughness: rough,
            concavity: conc,
            n_points: n,
        };
        let mut pts = synth_grain(seed, &params);
        let comment = if is_table1 {
            pts = scale_to_area(&pts, TABLE1_AREA_MM2);
            format!(
                "synthetic stand-in for the Ye & Xu (2010) Table 1 grain (outline not published), \
                 area {TABLE1_AREA_MM2} mm^2; clumpgen synth_grain seed {seed}, aspect {ar}, \
                 roughness {rough}, concavity {conc}, {n} points"
            )
        } else {
            format!(
                "synthetic grain {name}: clumpgen synth_grain seed {seed}, r_eq {r_eq} mm, \
                 aspect {ar}, roughness {rough}, concavity {conc}, {n} points"
            )
        };
        let path = out.join(format!("{name}.csv"));
        write_csv(&path, &comment, &pts)?;

        // Read back through the validating reader; describe what was read.
        let o = read_outline(&path, &ReadOptions::default())?;
        if !o.warnings.is_empty() {
            return Err(format!("{}: {:?}", path.display(), o.warnings).into());
        }
        let pr = polygon_props(&o.points);
        let d = shape_descriptors(&o.points, &pr);
        writeln!(
            rows,
            "| `{name}.csv` | {seed} | {n} | {rough} | {conc} | {:.3} | {:.3} | {:.2} | {:.3} | {:.3} |",
            pr.area * 1e6,
            d.r_eq * 1e3,
            d.aspect_ratio,
            d.solidity,
            d.circularity
        )?;
        println!(
            "{name}: area {:.6} mm^2, aspect {:.3}, solidity {:.3}",
            pr.area * 1e6,
            d.aspect_ratio,
            d.solidity
        );
        shapes.push((name.to_string(), o.points));
    }
    std::fs::write(out.join("README.md"), readme(&rows))?;
    if let Some(p) = preview {
        std::fs::write(p, svg(&shapes))?;
    }
    Ok(())
}

fn readme(rows: &str) -> String {
    format!(
        r#"# Synthetic grain outlines

Outlines the project made itself, for tests and examples of `clumpgen`. They are **synthetic**:
no granite or ceramic grain outlines are publicly available. (Real gravel outlines were used
only to test the reader, and are not part of the project.)

Generated by `clumpgen/examples/gen_outlines.rs`:

```text
cargo run -p clumpgen --release --example gen_outlines -- data/outlines
```

which rewrites every file here, this README included, identically on every run.

## Format

CSV: two `#` comment lines (what the grain is; `units: mm`), an `x,y` header, then one vertex per
line in millimetres, counter-clockwise, area centroid at the origin, no repeated closing point.
Read them with `clumpgen::read_outline`.

## How the grains are made

`clumpgen::synth::synth_grain(seed, params)`, documented in `clumpgen/src/synth.rs`:
a star-shaped polygon whose radius is a random Fourier series (harmonics 3 to min(n/4, 32),
amplitudes ∝ k^-1.5 scaled to the RMS `roughness`, random phases) times 1–3 Gaussian dents of
relative depth `concavity`·U(0.5, 1); then an affine map that makes the inertia aspect ratio
√(I_max/I_min) exactly the requested one, a random rotation, and scaling to area π r_eq². The
random numbers come from SplitMix64 seeded with the seed in the table. Families: `equant` (worn,
aspect 1–1.3), `rough` (irregular outlines), `concave` (deep dents), `elongated` (aspect 2.5–3),
`mixed`; equivalent radii 0.5–2 mm, the size of granite grains or of coarse ceramic grains.

`table1-grain.csv` is a **synthetic stand-in** for the grain of Ye & Xu (2010), Table 1, whose
outline is not published: only its area, 2246.63 mm², is taken from the paper, and the outline
is scaled so its area is exactly that. Its centroid and inertia are those of this synthetic
shape, not of the paper's grain (the paper's mass moment of inertia, 7.57×10⁵ g·mm², cannot be
compared without a density and thickness, which the paper does not give).

## Files

Measured from the files as read back by `clumpgen::read_outline`. Aspect ratio: inertia-based,
√(I_max/I_min). Solidity: area / convex-hull area. Circularity: 4πA/P².

| file | seed | vertices | roughness | concavity | area (mm²) | r_eq (mm) | aspect ratio | solidity | circularity |
|---|---|---|---|---|---|---|---|---|---|
{rows}"#
    )
}

/// Contact sheet: each grain scaled to its own cell.
fn svg(shapes: &[(String, Vec<[f64; 2]>)]) -> String {
    let cols = 6;
    let cell = 160.0;
    let rows = shapes.len().div_ceil(cols);
    let mut s = format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
        cols as f64 * cell,
        rows as f64 * cell
    );
    for (k, (name, pts)) in shapes.iter().enumerate() {
        let (cx, cy) = (
            (k % cols) as f64 * cell + cell / 2.0,
            (k / cols) as f64 * cell + cell / 2.0 - 8.0,
        );
        let ext = pts
            .iter()
            .fold(0.0f64, |m, p| m.max(p[0].abs()).max(p[1].abs()));
        let f = 0.4 * cell / ext;
        let d: Vec<String> = pts
            .iter()
            .map(|p| format!("{:.2},{:.2}", cx + f * p[0], cy - f * p[1]))
            .collect();
        let _ = writeln!(
            s,
            "<polygon points=\"{}\" fill=\"#d9c9a8\" stroke=\"black\" stroke-width=\"1\"/>\n<text x=\"{cx}\" y=\"{}\" font-size=\"12\" text-anchor=\"middle\">{name}</text>",
            d.join(" "),
            cy + cell / 2.0
        );
    }
    s.push_str("</svg>\n");
    s
}
