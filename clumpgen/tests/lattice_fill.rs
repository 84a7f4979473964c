//! The lattice fill (`method: lattice`, S3): node count against the grain area, nodes inside,
//! links only between lattice neighbours at the spacing, exact mass/centroid/inertia,
//! determinism, the template's version-2 record, and the errors that name the field.
//!
//! Node count, the tolerances stated: a node's disc (radius r = S/2) must lie inside the
//! outline, so the nodes fill the outline eroded by r. For a convex polygon that has area
//! A_r = A − P·r + r²·Σ cot(α_i/2) and perimeter P_r = P − 2r·Σ cot(α_i/2) (α_i the interior
//! angles; Σ = π for a disc, 4 for a square). With A_c = (√3/2)·S² the cell area:
//! * against the plain area (A/A_c), the count falls short by at most the boundary strip the
//!   nodes keep clear of plus 2 %: 1 − P·r/A − 0.02 ≤ N·A_c/A ≤ 1.01;
//! * against the eroded area, the lattice points of a closed convex region differ from
//!   A_r/A_c by at most about one row and one column of nodes: |N − A_r/A_c| ≤ 0.6·P_r/S + 1,
//!   and at R_eq/S = 20 by at most 1 %.

use clumpgen::clump::LatticeParams;
use clumpgen::geom::{distance_to_boundary, point_in_polygon};
use clumpgen::lattice::LinkKind;
use clumpgen::outline::parse_outline;
use clumpgen::template::{Template, TemplateError, SCHEMA_LATTICE};
use clumpgen::{
    make_template, polygon_props, read_outline, ClumpParams, Length, Method, ReadOptions,
};
use std::f64::consts::PI;
use std::path::Path;

fn ngon_csv(n: usize, r_mm: f64) -> String {
    let mut s = String::from("x,y\n");
    for k in 0..n {
        let t = k as f64 / n as f64 * 2.0 * PI;
        s.push_str(&format!(
            "{},{}\n",
            1.0 + r_mm * t.cos(),
            2.0 + r_mm * t.sin()
        ));
    }
    s
}

fn rect_csv(w_mm: f64, h_mm: f64) -> String {
    format!("x,y\n0,0\n{w_mm},0\n{w_mm},{h_mm}\n0,{h_mm}\n")
}

fn lattice(spacing: Length, node_radius: f64) -> ClumpParams {
    ClumpParams {
        method: Method::Lattice,
        lattice: Some(LatticeParams {
            spacing,
            node_radius,
        }),
        ..ClumpParams::default()
    }
}

fn make(text: &str, p: &ClumpParams) -> Result<Template, String> {
    let ol = parse_outline(text, "g", "g.csv", false, &ReadOptions::default()).unwrap();
    make_template(&ol, p).map_err(|e| e.to_string())
}

/// The outline in the template's frame (centroid at the origin), m.
fn outline_m(text: &str) -> Vec<[f64; 2]> {
    let ol = parse_outline(text, "g", "g.csv", false, &ReadOptions::default()).unwrap();
    let c = polygon_props(&ol.points).centroid;
    ol.points
        .iter()
        .map(|q| [q[0] - c[0], q[1] - c[1]])
        .collect()
}

/// Every property the brief asks for, on one template; returns N·A_c/A and N/(A_r/A_c).
fn check(t: &Template, poly: &[[f64; 2]], s: f64, name: &str) -> (f64, f64) {
    assert_eq!(t.schema, SCHEMA_LATTICE);
    assert_eq!(t.method, Method::Lattice);
    let l = t.lattice.as_ref().unwrap();
    assert!((l.spacing - s).abs() < 1e-15 * s);
    let r = l.node_radius_fraction * s / 2.0;
    let n = t.discs.len();
    // Inside: centre inside, disc inside (exact distance).
    for (k, d) in t.discs.iter().enumerate() {
        assert!(
            point_in_polygon([d.x, d.y], poly),
            "{name}: node {k} outside"
        );
        assert!(
            distance_to_boundary([d.x, d.y], poly) >= d.r,
            "{name}: node {k}'s disc crosses the outline"
        );
        assert_eq!(d.r, r);
        assert!(d.m > 0.0);
    }
    // Links: only lattice neighbours at S, in their direction; every pair at S is linked
    // (the grains here are convex and the nodes touch, so no segment leaves the outline).
    let mut linked = std::collections::HashSet::new();
    for k in &l.links {
        let (a, b) = (t.discs[k.i], t.discs[k.j]);
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        assert!(((dx.hypot(dy)) - s).abs() < 1e-12 * s, "{name}: link {k:?}");
        let want = match k.kind {
            LinkKind::D0 => 0.0f64,
            LinkKind::D60 => 60.0,
            LinkKind::D120 => 120.0,
        }
        .to_radians();
        // The direction from i to j is the kind's, or its opposite.
        let cross = dx * want.sin() - dy * want.cos();
        assert!(
            cross.abs() < 1e-9 * s,
            "{name}: link {k:?} not along its kind"
        );
        assert!(k.i < k.j && linked.insert((k.i, k.j)));
    }
    for i in 0..n {
        for j in i + 1..n {
            let (a, b) = (t.discs[i], t.discs[j]);
            let d = (b.x - a.x).hypot(b.y - a.y);
            assert!(d > s * (1.0 - 1e-9), "{name}: nodes {i}, {j} closer than S");
            if d < s * (1.0 + 1e-9) {
                assert!(
                    linked.contains(&(i, j)),
                    "{name}: neighbours {i}, {j} not linked"
                );
            }
        }
    }
    // Mass, centroid, inertia exact (1e-9 relative), recomputed from the discs.
    let m: f64 = t.discs.iter().map(|d| d.m).sum();
    let mx: f64 = t.discs.iter().map(|d| d.m * d.x).sum();
    let my: f64 = t.discs.iter().map(|d| d.m * d.y).sum();
    let i: f64 = t
        .discs
        .iter()
        .map(|d| d.m * (0.5 * d.r * d.r + d.x * d.x + d.y * d.y))
        .sum();
    let props = polygon_props(poly);
    let rho_t = t.density * t.thickness;
    let (mp, ip) = (rho_t * props.area, rho_t * props.j);
    assert!((m - mp).abs() <= 1e-9 * mp, "{name}: mass {m:e} vs {mp:e}");
    assert!(mx.hypot(my) / mp <= 1e-9 * t.shape.r_eq, "{name}: centroid");
    assert!(
        (i - ip).abs() <= 1e-9 * ip,
        "{name}: inertia {i:e} vs {ip:e}"
    );
    assert!(t.residuals.max() <= 1e-10, "{name}: {:?}", t.residuals);
    // The masses stay near the prior of one cell each: within 0.25 to 4 times the mean (the
    // closest-to-prior solution; not a few nodes carrying the grain).
    let mean = m / n as f64;
    let (lo, hi) = t.discs.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), d| {
        (lo.min(d.m / mean), hi.max(d.m / mean))
    });
    println!("{name}: node masses {lo:.3} to {hi:.3} times the mean");
    assert!(
        lo >= 0.25 && hi <= 4.0,
        "{name}: masses {lo} to {hi} times the mean"
    );
    // Node count against the area (module docs).
    let ac = 3f64.sqrt() / 2.0 * s * s;
    let cot_sum: f64 = (0..poly.len())
        .map(|k| {
            let (a, b, c) = (
                poly[(k + poly.len() - 1) % poly.len()],
                poly[k],
                poly[(k + 1) % poly.len()],
            );
            let (u, v) = ([a[0] - b[0], a[1] - b[1]], [c[0] - b[0], c[1] - b[1]]);
            let alpha = (u[0] * v[1] - u[1] * v[0])
                .abs()
                .atan2(u[0] * v[0] + u[1] * v[1]);
            1.0 / (alpha / 2.0).tan()
        })
        .sum();
    let a_r = props.area - props.perimeter * r + r * r * cot_sum;
    let p_r = props.perimeter - 2.0 * r * cot_sum;
    let plain = n as f64 * ac / props.area;
    let strip = props.perimeter * r / props.area;
    let excess = n as f64 - a_r / ac;
    println!(
        "{name}: {n} nodes, {} links; N·A_c/A = {plain:.4} (1 − P·r/A = {:.4}); \
         A_r/A_c = {:.1}, N − A_r/A_c = {excess:.1} ({:+.2} %, bound 0.6·P_r/S + 1 = {:.1})",
        l.links.len(),
        1.0 - strip,
        a_r / ac,
        100.0 * excess / (a_r / ac),
        0.6 * p_r / s + 1.0
    );
    assert!(
        plain <= 1.01 && plain >= 1.0 - strip - 0.02,
        "{name}: N·A_c/A = {plain}"
    );
    assert!(
        excess.abs() <= 0.6 * p_r / s + 1.0,
        "{name}: N − A_r/A_c = {excess}"
    );
    let eroded = n as f64 / (a_r / ac);
    (plain, eroded)
}

#[test]
fn disc_and_square_fill_as_the_area_says() {
    // A 720-gon of radius 10 mm and a 20 mm square, at R_eq/S from 5 to 20.
    let disc = ngon_csv(720, 10.0);
    let square = rect_csv(20.0, 20.0);
    for (name, text) in [("disc", &disc), ("square", &square)] {
        let poly = outline_m(text);
        let r_eq = (polygon_props(&poly).area / PI).sqrt();
        for ratio in [5.0, 10.3, 20.0] {
            let s = r_eq / ratio;
            let t = make(text, &lattice(Length::Metres(s), 1.0)).unwrap();
            let (_, eroded) = check(&t, &poly, s, &format!("{name}, R_eq/S = {ratio}"));
            if ratio == 20.0 {
                assert!(
                    (eroded - 1.0).abs() <= 0.01,
                    "{name}: N/(A_r/A_c) = {eroded}"
                );
            }
        }
    }
}

#[test]
fn smaller_nodes_and_shipped_grains_keep_the_invariants() {
    // Node radius 0.6·S/2: nodes nearer the outline, links still only at S.
    let square = rect_csv(20.0, 20.0);
    let poly = outline_m(&square);
    let t = make(&square, &lattice(Length::Metres(1e-3), 0.6)).unwrap();
    assert!(t.discs.iter().all(|d| d.r == 0.3e-3));
    let l = t.lattice.as_ref().unwrap();
    for k in &l.links {
        let (a, b) = (t.discs[k.i], t.discs[k.j]);
        assert!(((b.x - a.x).hypot(b.y - a.y) - 1e-3).abs() < 1e-15);
    }
    assert!(t
        .discs
        .iter()
        .all(|d| distance_to_boundary([d.x, d.y], &poly) >= d.r));
    // Every shipped outline (concave, elongated, ...) at S = R_eq/8: exact mass properties.
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/outlines");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .collect();
    files.sort();
    assert!(!files.is_empty());
    for f in files {
        let ol = read_outline(&f, &ReadOptions::default()).unwrap();
        let t = make_template(&ol, &lattice(Length::OfReq(0.125), 1.0))
            .unwrap_or_else(|e| panic!("{e}"));
        assert!(
            t.residuals.max() <= 1e-10,
            "{}: {:?}",
            f.display(),
            t.residuals
        );
        let mean = t.target.mass / t.discs.len() as f64;
        let spread = t
            .discs
            .iter()
            .map(|d| (d.m / mean).max(mean / d.m))
            .fold(0.0, f64::max);
        assert!(
            spread <= 4.0,
            "{}: node masses up to {spread} x the mean",
            f.display()
        );
        Template::from_json(&t.to_json("x").unwrap(), "x").unwrap();
        println!(
            "{}: {} nodes, {} links, residual {:.1e}, masses within {spread:.2}x the mean",
            f.display(),
            t.discs.len(),
            t.lattice.as_ref().unwrap().links.len(),
            t.residuals.max()
        );
    }
}

#[test]
fn lattice_templates_are_deterministic_and_round_trip() {
    let text = "x y\n0 0\n30 0\n30 10\n10 10\n10 30\n0 30\n"; // an L, mm
    let p = lattice(Length::Metres(2e-3), 1.0);
    let a = make(text, &p).unwrap().to_json("a").unwrap();
    let b = make(text, &p).unwrap().to_json("b").unwrap();
    assert_eq!(a, b);
    assert!(a.contains("\"schema\": \"clumpgen.template/2\""));
    assert!(a.contains("\"method\": \"lattice\"") && a.contains("\"kind\": \"d60\""));
    let back = Template::from_json(&a, "a").unwrap();
    assert_eq!(back.to_json("a").unwrap(), a);
    // The other methods still write version 1, without a lattice record.
    let imp = make(text, &ClumpParams::default())
        .unwrap()
        .to_json("i")
        .unwrap();
    assert!(imp.contains("\"schema\": \"clumpgen.template/1\"") && !imp.contains("\"lattice\""));
    Template::from_json(&imp, "i").unwrap();
}

#[test]
fn inconsistent_lattice_templates_are_refused_naming_the_field() {
    let text = rect_csv(10.0, 10.0);
    let good = make(&text, &lattice(Length::Metres(1e-3), 1.0)).unwrap();
    let v: serde_json::Value = serde_json::from_str(&good.to_json("t").unwrap()).unwrap();
    let field = |mut v: serde_json::Value, f: &dyn Fn(&mut serde_json::Value)| {
        f(&mut v);
        match Template::from_json(&v.to_string(), "t.json") {
            Err(TemplateError::Field { field, .. }) => field,
            Err(TemplateError::Schema { found, .. }) => format!("schema {found}"),
            other => panic!("{other:?}"),
        }
    };
    assert_eq!(
        field(v.clone(), &|v| v["schema"] = "clumpgen.template/1".into()),
        "method"
    );
    assert_eq!(
        field(v.clone(), &|v| {
            v.as_object_mut().unwrap().remove("lattice");
        }),
        "lattice"
    );
    assert_eq!(
        field(v.clone(), &|v| v["lattice"]["links"][3]["j"] = 0.into()),
        "lattice.links[3]"
    );
    assert_eq!(
        field(v.clone(), &|v| v["discs"][0]["x"] = 1.0.into()),
        "lattice.links[0]"
    );
    assert_eq!(
        field(v.clone(), &|v| v["lattice"]["spacing"] = (-1.0).into()),
        "lattice.spacing"
    );
    assert_eq!(
        field(v.clone(), &|v| v["schema"] = "clumpgen.template/3".into()),
        "schema clumpgen.template/3"
    );
}

#[test]
fn bad_spacings_and_thin_grains_give_errors_naming_grain_and_field() {
    let square = rect_csv(10.0, 10.0);
    // Out-of-range values are refused before any grain (the `dem clump` flags).
    for s in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        let e = lattice(Length::Metres(s), 1.0).check().unwrap_err();
        assert_eq!(e.name, "spacing", "{s}: {e}");
    }
    let e = lattice(Length::Metres(1e-3), 1.5).check().unwrap_err();
    assert_eq!(e.name, "node-radius");
    let no_spacing = ClumpParams {
        method: Method::Lattice,
        ..ClumpParams::default()
    };
    assert_eq!(no_spacing.check().unwrap_err().name, "spacing");
    let stray = ClumpParams {
        lattice: Some(LatticeParams {
            spacing: Length::Metres(1e-3),
            node_radius: 1.0,
        }),
        ..ClumpParams::default()
    };
    assert_eq!(stray.check().unwrap_err().name, "spacing");
    // Per grain: larger than the grain, thinner than a cell, too many nodes.
    let e = make(&square, &lattice(Length::Metres(0.02), 1.0)).unwrap_err();
    assert!(
        e.starts_with("g.csv: spacing: 2e-2 m is larger than the grain"),
        "{e}"
    );
    let e = make(&rect_csv(40.0, 1.5), &lattice(Length::Metres(1e-3), 1.0)).unwrap_err();
    assert!(
        e.starts_with("g.csv: spacing: the grain is thinner than one lattice cell"),
        "{e}"
    );
    let e = make(&square, &lattice(Length::Metres(1e-5), 1.0)).unwrap_err();
    assert!(e.starts_with("g.csv: spacing: 1e-5 m gives about"), "{e}");
    // The library refuses bad values too (no panic), naming the field.
    let e = make(&square, &lattice(Length::Metres(f64::NAN), 1.0)).unwrap_err();
    assert!(
        e.starts_with("g.csv: invalid parameter: spacing NaN"),
        "{e}"
    );
}
