//! Cases with clumps and extreme bonds: the 1:20 bonded clump (case 2), nearly coincident
//! members (case 3), the radius-ratio-10 bond (case 6) and the sliver grain (case 7).

use super::cases::{bond_group, material, scene, wall, CaseSpec, BALANCE_BOUND, SI3N4, T};
use super::{Expect, StabilityError};
use clumpgen::template::{CoverRecord, Disc, FillRecord, MassProps, Shape, Source, SCHEMA};
use clumpgen::{make_template, read_outline, ClumpParams, Method, ReadOptions, Template};
use serde_json::{json, Value};
use std::f64::consts::PI;
use std::path::Path;

fn n(quick: bool, q: u64, f: u64) -> u64 {
    if quick {
        q
    } else {
        f
    }
}

fn spec(
    name: &str,
    stresses: &str,
    scene: Value,
    steps: u64,
    files: Vec<(String, String)>,
) -> CaseSpec {
    CaseSpec {
        name: name.into(),
        stresses: stresses.into(),
        scene,
        files,
        steps,
        // Small scenes: sample often enough to see inside a collision (~50–100 steps).
        sample_every: 10,
        bound: BALANCE_BOUND,
        expect: Expect::Stable,
    }
}

/// A clump template made by hand from member discs `[x, y, r]` (ORC masses ρ·t·π·r², shifted
/// to the mass centre): target = achieved (there is no outline), cover 1 of the union, shape
/// of the equivalent circle. Used where the case needs a member layout no outline gives.
pub fn hand_template(id: &str, members: &[[f64; 3]], density: f64) -> Template {
    let m: Vec<f64> = members
        .iter()
        .map(|d| density * T * PI * d[2] * d[2])
        .collect();
    let mass: f64 = m.iter().sum();
    let cx = members.iter().zip(&m).map(|(d, m)| m * d[0]).sum::<f64>() / mass;
    let cy = members.iter().zip(&m).map(|(d, m)| m * d[1]).sum::<f64>() / mass;
    let discs: Vec<Disc> = members
        .iter()
        .zip(&m)
        .map(|(d, &m)| Disc {
            x: d[0] - cx,
            y: d[1] - cy,
            r: d[2],
            m,
        })
        .collect();
    // About the mass centre (the frame's origin): Σ m (r²/2 + d²) (uniform discs).
    let inertia: f64 = discs
        .iter()
        .map(|d| d.m * (0.5 * d.r * d.r + d.x * d.x + d.y * d.y))
        .sum();
    let circles: Vec<clumpgen::cover::Circle> = discs
        .iter()
        .map(|d| clumpgen::cover::Circle {
            x: d.x,
            y: d.y,
            r: d.r,
        })
        .collect();
    let union = clumpgen::cover::union_area(&circles).area;
    let props = MassProps {
        mass,
        centroid: [0.0, 0.0],
        inertia,
        inertia_own: inertia,
        area: discs.iter().map(|d| PI * d.r * d.r).sum(),
    };
    let r_eq = (union / PI).sqrt();
    Template {
        schema: SCHEMA.into(),
        id: id.into(),
        generator: "validation::stability (hand-made member layout)".into(),
        source: Source {
            file: String::new(),
            sha256: String::new(),
            units: "m".into(),
            vertices: 0,
            centroid_m: [0.0, 0.0],
            grain: None,
            warnings: vec![
                "hand-made: no outline; target = achieved (ORC masses); shape = equivalent \
                 circle of the union of the discs"
                    .into(),
            ],
        },
        units: [("length", "m"), ("mass", "kg"), ("inertia", "kg m^2")]
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect(),
        density,
        thickness: T,
        method: Method::Orc,
        fill: FillRecord {
            cover_target: 1.0,
            r_min: members.iter().map(|d| d[2]).fold(f64::INFINITY, f64::min),
            r_max: members.iter().map(|d| d[2]).fold(0.0, f64::max),
            max_discs: members.len(),
            raster: 0,
            stop: clumpgen::fill::StopReason::CoverReached,
            repair_discs: 0,
            inside_tolerance: 0.0,
            mass_floor: 1.0,
            prior: "uniform".into(),
        },
        discs,
        target: props,
        achieved: props,
        residuals: clumpgen::massfit::Residuals {
            mass_rel: 0.0,
            centroid_rel: 0.0,
            inertia_rel: 0.0,
        },
        cover: CoverRecord {
            value: 1.0,
            bound: 0.0,
            union_area: union,
        },
        shape: Shape {
            area: union,
            perimeter: 2.0 * PI * r_eq,
            j: 0.5 * PI * r_eq.powi(4),
            principal_angle: 0.0,
            r_eq,
            aspect_ratio: 1.0,
            circularity: 1.0,
            solidity: 1.0,
        },
        lattice: None,
    }
}

fn template_text(t: &Template, file: &str) -> Result<String, StabilityError> {
    t.to_json(file).map_err(|e| StabilityError::Setup {
        case: file.into(),
        reason: e.to_string(),
    })
}

/// Case 2, radius ratio 1:20 inside one bonded clump: a Si3N4 member of radius R = 2 mm with
/// 24 members of r = 0.1 mm around it, each overlapping it by r/2 (improved-ORC members
/// overlap by design and get reference gaps), intra-clump parallel bonds (k̄n = E/(R + r),
/// strengths 600 MPa). The clump moves at (0.5, −3) m/s spinning at 200 rad/s and hits a
/// floor wall rim-first (a small member is squeezed between the wall and the large one);
/// restitution 0.5, friction 0.5. Checks: a 1:20 radius (1:400 mass) ratio in one bonded body
/// under impact.
pub fn ratio_1_20(quick: bool) -> Result<CaseSpec, StabilityError> {
    let steps = n(quick, 20_000, 200_000);
    let (rho, e) = SI3N4;
    let (big, r) = (2e-3, 1e-4);
    let mut members = vec![[0.0, 0.0, big]];
    for k in 0..24 {
        let a = k as f64 / 24.0 * 2.0 * PI;
        let d = big + 0.5 * r;
        members.push([d * a.cos(), d * a.sin(), r]);
    }
    let tpl = hand_template("ratio-1-20", &members, rho);
    let file = "ratio-1-20.json";
    let mut s = scene(
        "ratio_1_20",
        "Bonded clump of one 2 mm and 24 0.1 mm Si3N4 discs (radius ratio 1:20) hitting a \
         floor at 3 m/s while spinning; stability suite case 2",
        steps,
    );
    s["materials"] = json!([
        material("si3n4", Some(rho), e, 0.5, Some(0.5)),
        material("steel", None, e, 0.5, Some(0.5))
    ]);
    s["bond_groups"] = json!([bond_group("intra", e, big + r, 600e6)]);
    // The lowest small member (at −90°) is 2 µm above the floor.
    let y = big + 1.5 * r + 2e-6;
    s["bodies"] = json!({"clumps": [{"template": file, "material": "si3n4", "mode": "bonded",
        "bond_group": "intra",
        "placements": [{"x": 0.0, "y": y, "velocity": [0.5, -3.0], "omega": 200.0}]}]});
    s["walls"] = json!([wall(
        "floor",
        [-0.01, 0.0],
        [0.01, 0.0],
        "steel",
        [0.0, 0.0]
    )]);
    Ok(spec(
        "ratio_1_20",
        "bonded clump, radius ratio 1:20, impact at 3 m/s",
        s,
        steps,
        vec![(file.into(), template_text(&tpl, file)?)],
    ))
}

/// Case 3, nearly coincident members: a clump of three Si3N4 discs of radii r, r/2, r/10
/// (r = 0.5 mm) whose centres lie within 7e-4 r of each other (tiny lever arms; the r/10
/// member has 1e-4 of the large one's rotational inertia), as a rigid clump (`bonded` false)
/// or a bonded clump (near-zero-length intra bonds whose axes are set by separations of
/// 1e-3 r, k̄n = E/(1.5 r), strengths 600 MPa). A free disc of radius r hits it obliquely at
/// 2 m/s (restitution 0.8, friction 0.5, so the clump is spun).
pub fn coincident(quick: bool, bonded: bool) -> Result<CaseSpec, StabilityError> {
    let steps = n(quick, 20_000, 200_000);
    let (rho, e) = SI3N4;
    let r = 5e-4;
    let members = [
        [0.0, 0.0, r],
        [7e-4 * r, 0.0, 0.5 * r],
        [3.5e-4 * r, 6e-4 * r, 0.1 * r],
    ];
    let tpl = hand_template("coincident", &members, rho);
    let file = "coincident.json";
    let (name, mode) = if bonded {
        ("coincident_bonded", "bonded")
    } else {
        ("coincident_rigid", "rigid")
    };
    let mut s = scene(
        name,
        "Clump of three Si3N4 discs (r, r/2, r/10) with centres within 7e-4 r, hit obliquely \
         by a free disc at 2 m/s; stability suite case 3",
        steps,
    );
    s["materials"] = json!([material("si3n4", Some(rho), e, 0.5, Some(0.8))]);
    let mut clump = json!({"template": file, "material": "si3n4", "mode": mode,
        "placements": [{"x": 0.0, "y": 0.0}]});
    if bonded {
        s["bond_groups"] = json!([bond_group("intra", e, 1.5 * r, 600e6)]);
        clump["bond_group"] = json!("intra");
    }
    s["bodies"] = json!({
        "discs": [{"material": "si3n4", "velocity": [2.0, 0.0],
                   "discs": [[-(3.75f64.sqrt() * r + 1e-6), 0.5 * r, r]]}],
        "clumps": [clump]
    });
    Ok(spec(
        name,
        if bonded {
            "bonded clump of nearly coincident discs (r, r/2, r/10), hit at 2 m/s"
        } else {
            "rigid clump of nearly coincident discs (r, r/2, r/10), hit at 2 m/s"
        },
        s,
        steps,
        vec![(file.into(), template_text(&tpl, file)?)],
    ))
}

/// Case 6, a parallel bond between discs of radius ratio 10: four pairs of a fixed Si3N4 disc
/// (R = 1 mm) and a free one (r = 0.1 mm) bonded at their contact (R̄ = r, Ā = 2rt,
/// Ī = (2/3)r³t; k̄n = E/(R + r); σ̄c = c̄ = 600 MPa). Loads applied suddenly (dynamic peak ≈
/// 2× static), undamped: (A) tension F = 0.4 σ̄c Ā; (B) shear F = 0.1 σ̄c Ā at the small disc's
/// centre, whose couple F·r gives the bond a bending stress 3F/Ā = 0.3 σ̄c; (C) a torque
/// 0.4 σ̄c Ī/R̄ (bending); (D) a wall pushing the small disc sideways at 1 m/s until the bond
/// breaks, then pushing the loose disc on. A to C stay short of breaking, D breaks.
pub fn bond_ratio_10(quick: bool) -> CaseSpec {
    let steps = n(quick, 20_000, 200_000);
    let (rho, e) = SI3N4;
    let (big, r, pitch, sc) = (1e-3, 1e-4, 5e-3, 600e6);
    let area = 2.0 * r * T;
    let second = 2.0 / 3.0 * r.powi(3) * T;
    let x = big + r;
    let mut s = scene(
        "bond_ratio_10",
        "Parallel bonds between a fixed 1 mm and a free 0.1 mm Si3N4 disc (radius ratio 10) \
         loaded in tension, shear and bending, and one sheared by a wall until it breaks; \
         stability suite case 6",
        steps,
    );
    s["materials"] = json!([
        material("si3n4", Some(rho), e, 0.5, None),
        material("steel", None, e, 0.5, None)
    ]);
    s["bond_groups"] = json!([bond_group("ratio10", e, big + r, sc)]);
    let fixed: Vec<[f64; 3]> = (0..4).map(|k| [0.0, k as f64 * pitch, big]).collect();
    let small: Vec<[f64; 3]> = (0..4).map(|k| [x, k as f64 * pitch, r]).collect();
    s["bodies"] = json!({"discs": [
        {"material": "si3n4", "fixed": true, "discs": fixed},
        {"material": "si3n4", "discs": small}
    ]});
    s["auto_bonds"] = json!([{"bond_group": "ratio10", "tolerance": 1e-3 * r}]);
    // Disc ids: 0-3 the fixed discs, 4-7 the small ones.
    s["loads"] = json!([
        {"disc": 4, "force": [0.4 * sc * area, 0.0], "torque": 0.0},
        {"disc": 5, "force": [0.0, 0.1 * sc * area], "torque": 0.0},
        {"disc": 6, "force": [0.0, 0.0], "torque": 0.4 * sc * second / r}
    ]);
    let yd = 3.0 * pitch + r + 1e-7;
    s["walls"] = json!([wall(
        "pusher",
        [big + 4.0 * r, yd],
        [big + 0.3 * r, yd],
        "steel",
        [0.0, -1.0]
    )]);
    spec(
        "bond_ratio_10",
        "parallel bonds, radius ratio 10: tension, shear, bending (short of breaking), one sheared to break",
        s,
        steps,
        Vec::new(),
    )
}

/// Case 7, a near-degenerate grain outline: an ellipse of semi-axes 2 mm × 0.1 mm (aspect
/// ratio 20, 96 points) → `clumpgen::make_template` (improved ORC, clumpgen's defaults:
/// cover 0.95, radii 0.02–1 r_eq, ≤ 64 discs, mass floor 1e-3) for Si3N4, placed as a rigid
/// clump and as a bonded clump (k̄n = E/(2 r̄) at the members' mean radius r̄, strengths
/// 600 MPa), tilted 0.2 rad, 10 nm above a floor and moving down at 1 m/s (as after a drop
/// of 5 cm), under gravity (restitution 0.5, friction 0.5). The improved-ORC members' masses go
/// down to the mass floor (1e-3 of a uniform disc's), so the bonded clump's automatic step is
/// ~100× smaller than the rigid one's: its quick run covers the first ~60 ns of the impact,
/// its full run (1e6 steps) about 3 µs. The outline and the template are written beside the scenes
/// (`dem clump sliver-ar20.csv` remakes the template).
pub fn sliver(dir: &Path, quick: bool) -> Result<Vec<CaseSpec>, StabilityError> {
    let (rho, e) = SI3N4;
    let (a, b) = (2.0, 0.1); // mm
    let mut outline = String::from("# sliver of aspect ratio 20 (ellipse 2 mm x 0.1 mm), stability suite case 7\n# units: mm\nx,y\n");
    for k in 0..96 {
        let t = k as f64 / 96.0 * 2.0 * PI;
        outline.push_str(&format!("{},{}\n", a * t.cos(), b * t.sin()));
    }
    let ol_name = "sliver-ar20.csv";
    let ol_path = dir.join(ol_name);
    clumpgen::io::write_atomic(&ol_path, outline.as_bytes()).map_err(|source| {
        StabilityError::Io {
            file: ol_path.display().to_string(),
            source,
        }
    })?;
    let setup = |reason: String| StabilityError::Setup {
        case: "sliver".into(),
        reason,
    };
    let ol = read_outline(&ol_path, &ReadOptions::default()).map_err(|e| setup(e.to_string()))?;
    let params = ClumpParams {
        density: rho,
        thickness: T,
        ..ClumpParams::default()
    };
    let tpl = make_template(&ol, &params).map_err(|e| setup(e.to_string()))?;
    let file = "sliver-ar20.json";
    let text = template_text(&tpl, file)?;
    let r_mean = tpl.discs.iter().map(|d| d.r).sum::<f64>() / tpl.discs.len() as f64;
    let angle: f64 = 0.2;
    let (sn, cs) = angle.sin_cos();
    let lowest = tpl
        .discs
        .iter()
        .map(|d| sn * d.x + cs * d.y - d.r)
        .fold(f64::INFINITY, f64::min);
    let y = -lowest + 1e-8;
    let mut out = Vec::new();
    for bonded in [false, true] {
        let name = if bonded {
            "sliver_bonded"
        } else {
            "sliver_rigid"
        };
        // The bonded clump's step is ~100× smaller: its full run is longer, to cover the
        // whole impact of the grain (contact time ~π√(m/k) ≈ 0.3 µs).
        let steps = n(quick, 20_000, if bonded { 1_000_000 } else { 200_000 });
        let mut s = scene(
            name,
            "Sliver grain (aspect ratio 20, improved-ORC template) dropped tilted onto a floor \
             under gravity; stability suite case 7",
            steps,
        );
        s["materials"] = json!([
            material("si3n4", Some(rho), e, 0.5, Some(0.5)),
            material("steel", None, e, 0.5, Some(0.5))
        ]);
        let mut clump = json!({"template": file, "material": "si3n4",
            "mode": if bonded { "bonded" } else { "rigid" },
            "placements": [{"x": 0.0, "y": y, "angle": angle, "velocity": [0.0, -1.0]}]});
        if bonded {
            s["bond_groups"] = json!([bond_group("intra", e, 2.0 * r_mean, 600e6)]);
            clump["bond_group"] = json!("intra");
        }
        s["bodies"] = json!({"clumps": [clump]});
        s["walls"] = json!([wall(
            "floor",
            [-0.01, 0.0],
            [0.01, 0.0],
            "steel",
            [0.0, 0.0]
        )]);
        s["gravity"] = json!([0.0, -9.81]);
        out.push(spec(
            name,
            if bonded {
                "sliver grain (aspect 20), improved ORC as a bonded clump, dropped"
            } else {
                "sliver grain (aspect 20) as a rigid clump, dropped"
            },
            s,
            steps,
            vec![(file.into(), text.clone())],
        ));
    }
    Ok(out)
}
