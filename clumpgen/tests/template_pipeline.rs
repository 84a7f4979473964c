//! End-to-end: outline text → template, on closed-form shapes and on the shipped data set.

use clumpgen::geom::distance_to_boundary;
use clumpgen::outline::parse_outline;
use clumpgen::template::TemplateError;
use clumpgen::{make_template, ClumpParams, Method, ReadOptions, Template};
use std::f64::consts::PI;
use std::path::Path;

fn ngon_csv(n: usize, r_mm: f64, cx: f64, cy: f64) -> String {
    let mut s = String::from("x,y\n");
    for k in 0..n {
        let t = k as f64 / n as f64 * 2.0 * PI;
        s.push_str(&format!(
            "{},{}\n",
            cx + r_mm * t.cos(),
            cy + r_mm * t.sin()
        ));
    }
    s
}

fn template_of(text: &str, p: &ClumpParams) -> Template {
    let ol = parse_outline(text, "g", "mem.csv", false, &ReadOptions::default()).unwrap();
    make_template(&ol, p).unwrap()
}

#[test]
fn disc_outline_recovers_its_own_properties() {
    // 720-gon of radius 10 mm, far from the origin (local-origin precision).
    let n = 720;
    let r = 10e-3;
    let text = ngon_csv(n, 10.0, 3.0e5, -2.0e5);
    let p = ClumpParams::default();
    let t = template_of(&text, &p);
    // Exact regular-polygon area and polar moment: A = n R² sin(2π/n)/2, J = A R² (2 + cos(2π/n))/6.
    let a = n as f64 * r * r * (2.0 * PI / n as f64).sin() / 2.0;
    let j = a * r * r * (2.0 + (2.0 * PI / n as f64).cos()) / 6.0;
    let rho_t = p.density * p.thickness;
    assert!((t.target.mass - rho_t * a).abs() < 1e-12 * rho_t * a);
    assert!((t.target.inertia - rho_t * j).abs() < 1e-10 * rho_t * j);
    // The first disc is the inscribed circle (radius R cos(π/n)) at the centre.
    let d0 = t.discs[0];
    assert!(d0.x.hypot(d0.y) < 1e-6 * r, "{d0:?}");
    assert!((d0.r - r * (PI / n as f64).cos()).abs() < 1e-6 * r);
    assert!(t.cover.value >= 0.95);
    assert!(t.residuals.mass_rel <= 1e-9);
    assert!(t.residuals.inertia_rel <= 1e-9);
    assert!(t.residuals.centroid_rel <= 1e-9);
    assert!(t.discs.iter().all(|d| d.m > 0.0));
    // Grain centroid goes back to where it was (in metres, mm input).
    assert!((t.source.centroid_m[0] - 300.0).abs() < 1e-9);
    assert!((t.source.centroid_m[1] + 200.0).abs() < 1e-9);
}

#[test]
fn orc_sums_uniform_discs_and_reports_its_deviation() {
    let text = "x y\n0 0\n30 0\n30 10\n10 10\n10 30\n0 30\n"; // an L, mm
    let p = ClumpParams {
        method: Method::Orc,
        ..ClumpParams::default()
    };
    let t = template_of(text, &p);
    let rho_t = p.density * p.thickness;
    for d in &t.discs {
        assert!((d.m - rho_t * PI * d.r * d.r).abs() <= 1e-12 * d.m);
    }
    // Overlaps are counted twice, so the ORC clump is heavier than its cover alone would be.
    assert!(t.achieved.mass > rho_t * t.cover.union_area);
    assert!(
        t.residuals.max() > 1e-6,
        "ORC should not match the grain exactly"
    );
    // The improved clump of the same L is exact.
    let ti = template_of(text, &ClumpParams::default());
    assert!(ti.residuals.max() <= 1e-9);
    assert_eq!(
        ti.discs.iter().map(|d| (d.x, d.y, d.r)).collect::<Vec<_>>()[..t.discs.len()],
        t.discs.iter().map(|d| (d.x, d.y, d.r)).collect::<Vec<_>>()[..]
    );
}

#[test]
fn template_round_trips_and_is_deterministic() {
    let text = ngon_csv(7, 5.0, 0.0, 0.0);
    let p = ClumpParams::default();
    let dir = std::env::temp_dir().join(format!("clumpgen-rt-{}", std::process::id()));
    let (a, b) = (dir.join("a.json"), dir.join("b.json"));
    template_of(&text, &p).save(&a).unwrap();
    template_of(&text, &p).save(&b).unwrap();
    let (ba, bb) = (std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    assert_eq!(ba, bb, "two runs must give identical bytes");
    let back = Template::load(&a).unwrap();
    assert_eq!(back, template_of(&text, &p));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn loader_names_the_bad_field() {
    let t = template_of(&ngon_csv(9, 5.0, 0.0, 0.0), &ClumpParams::default());
    let good = serde_json::to_value(&t).unwrap();
    let mut v = good.clone();
    v["discs"][2]["m"] = serde_json::json!(-1.0);
    match Template::from_json(&v.to_string(), "x.json") {
        Err(TemplateError::Field { field, .. }) => assert_eq!(field, "discs[2].m"),
        other => panic!("{other:?}"),
    }
    let mut v = good.clone();
    v["schema"] = serde_json::json!("clumpgen.template/0");
    assert!(matches!(
        Template::from_json(&v.to_string(), "x.json"),
        Err(TemplateError::Schema { .. })
    ));
    let mut v = good;
    v["discs"][0]["r"] = serde_json::Value::Null;
    let e = Template::from_json(&v.to_string(), "x.json").unwrap_err();
    assert!(e.to_string().starts_with("x.json"), "{e}");
}

/// Issue 48 D16: discs edited after generation (one mass × 10, one disc moved, one radius
/// grown) disagree with the stated clump properties, which a rigid clump moves with: the
/// loader refuses them naming `achieved.mass`, `achieved.centroid` or `achieved.inertia` and
/// both values; the template as written loads.
#[test]
fn discs_that_disagree_with_the_clump_properties_are_refused() {
    let t = template_of(&ngon_csv(9, 5.0, 0.0, 0.0), &ClumpParams::default());
    let good = serde_json::to_value(&t).unwrap();
    assert!(Template::from_json(&good.to_string(), "x.json").is_ok());
    let last = t.discs.len() - 1;
    let edits: [(&str, f64, &str); 3] = [
        ("m", 10.0, "mass"),
        ("x", 1.5, "centroid"),
        ("r", 1.2, "inertia"),
    ];
    for (key, factor, field) in edits {
        let mut v = good.clone();
        let d = &mut v["discs"][last][key];
        *d = serde_json::json!(d.as_f64().unwrap() * factor + if key == "x" { 1e-4 } else { 0.0 });
        match Template::from_json(&v.to_string(), "x.json") {
            Err(TemplateError::Field {
                field: f, reason, ..
            }) => {
                assert_eq!(f, format!("achieved.{field}"), "{key}: {reason}");
                assert!(
                    reason.contains("the discs give") && reason.contains("states"),
                    "{reason}"
                );
            }
            other => panic!("{key}: {other:?}"),
        }
    }
}

/// Every shipped outline: cover ≥ 0.95, positive masses, residuals ≤ 1e-9, discs inside.
#[test]
fn shipped_outlines_meet_the_targets() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../data/outlines");
    let inputs = clumpgen::batch::collect_inputs(&[dir]).unwrap();
    assert!(inputs.len() >= 20, "expected the shipped outlines");
    for inp in inputs {
        let ol = clumpgen::read_outline(&inp.path, &ReadOptions::default()).unwrap();
        let t = make_template(&ol, &ClumpParams::default())
            .unwrap_or_else(|e| panic!("{}: {e}", inp.path.display()));
        let name = inp.path.display();
        assert!(t.cover.value >= 0.95, "{name}: cover {}", t.cover.value);
        assert!(t.discs.iter().all(|d| d.m > 0.0), "{name}");
        assert!(t.residuals.mass_rel <= 1e-9, "{name}: {:?}", t.residuals);
        assert!(t.residuals.inertia_rel <= 1e-9, "{name}: {:?}", t.residuals);
        assert!(
            t.residuals.centroid_rel <= 1e-9,
            "{name}: {:?}",
            t.residuals
        );
        // Discs inside the outline (in the centroid frame) within the stated tolerance.
        let c = clumpgen::props::polygon_props(&ol.points).centroid;
        let poly: Vec<[f64; 2]> = ol
            .points
            .iter()
            .map(|q| [q[0] - c[0], q[1] - c[1]])
            .collect();
        for d in &t.discs {
            assert!(
                clumpgen::geom::point_in_polygon([d.x, d.y], &poly),
                "{name}"
            );
            let room = distance_to_boundary([d.x, d.y], &poly);
            assert!(
                d.r <= room + t.fill.inside_tolerance,
                "{name}: {d:?} room {room}"
            );
        }
    }
}
