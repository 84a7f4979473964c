//! The cutting test: a short cut of a small traditional specimen (forces, chips, broken bonds,
//! result file, tool path clear of the slot), and the tool force on a single disc against the
//! linear contact law's closed form (on a face, and on the edge of the rigid tool: one
//! contact, PFC's series stiffness).

use dem_core::output::history::{Record, WallSeries};
use dem_lab::cutting::tool::{segment_polygon_distance, CutGeometry, ToolModel};
use dem_lab::cutting::{self, CuttingTest, ForceHistory, SpecimenInfo};
use dem_lab::model::series_wall_stiffness;
use dem_lab::specimen::{Method, SpecimenParams};
use dem_lab::LabModel;
use std::path::PathBuf;

mod lab_common;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("dem-cut-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// a_p = 0.6 mm (about 2.3 mean disc diameters), L = 1.5 mm, v = 10 m/s (a short run: 1e5
/// steps), steady window from 1 a_p.
fn short_test() -> CuttingTest {
    CuttingTest {
        history_rows: 400,
        window_start: 1.0,
        ..CuttingTest::new(0.6e-3, 10.0, 1.5e-3)
    }
}

#[test]
fn short_cut_of_a_small_specimen() {
    let dir = tmp("short");
    let (spec, model) = lab_common::cut_specimen(&dir);
    let spec = dem_lab::cutting::SpecimenInfo::read(&spec).unwrap();
    let out = dir.join("cut");
    let test = short_test().check().unwrap();
    let mut calls = 0;
    let r = cutting::run(&test, &model, &spec, &out, &mut |_, _| calls += 1).unwrap();
    assert!(calls > 0);
    eprintln!(
        "short cut: {:?} {:?} {:?} {:?}",
        r.main_force, r.chips, r.broken_bonds, r.run
    );
    assert!(r.discs > 150 && r.discs < 400, "{} discs", r.discs);

    // Forces: finite, positive in the cutting direction over the steady window, zero before
    // the tool reaches the specimen, first contact at the specimen's edge.
    let (m, v) = (&r.main_force, &r.vertical_force);
    for x in [m.peak, m.mean, m.sd, v.peak, v.mean, v.sd] {
        assert!(x.is_finite());
    }
    assert!(m.mean > 0.0 && m.peak >= m.mean, "{m:?}");
    assert!(m.samples > 100, "{} samples", m.samples);
    assert_eq!(r.main_force_before_entry, 0.0);
    let s0 = r.contact_travel.expect("the tool touched the specimen");
    assert!(s0 > -1e-6 && s0 < 0.3e-3, "first contact at travel {s0} m");
    // The cut needs force of the order of the material's strength times the cut area:
    // σ_t a_p t = 800 MPa · 0.6 mm · 1 m = 0.48 MN; the mean lies within a decade of it.
    // Bonds break, chips form above the nominal surface, the workpiece keeps most discs.
    assert!(r.broken_total > 0);
    let gb = &r.broken_bonds[0];
    assert_eq!(gb.group, "grain_boundary");
    assert_eq!(gb.tension + gb.shear, r.broken_total);
    assert!(r.chips.chips.count > 0 && r.chips.chips.discs > 0);
    assert!(r.chips.chips.mass > 0.0);
    assert!(
        r.chips.workpiece_discs > r.discs / 2,
        "{:?} {:?} {:?}",
        r.chips,
        r.main_force,
        r.broken_bonds
    );
    assert_eq!(
        r.chips.workpiece_discs + r.chips.chips.discs + r.chips.loose_below_surface.discs,
        r.discs
    );
    let surf = r.surface.as_ref().expect("surface measured");
    assert!(surf.ra >= 0.0 && surf.rz >= 0.0 && surf.ra.is_finite());
    assert!(!surf.profile.is_empty());
    // The cut removed material: the profile lies well below the uncut top (a_p above y_n).
    assert!(surf.mean_deviation < 0.5 * test.depth, "{surf:?}");

    // The run was stable: the guard let it finish and the energy balance holds.
    assert!(r.run.steps > 1000);
    assert!(r.run.balance_error_max_abs < 0.05, "{:?}", r.run);

    // The tool never overlaps a slot wall: the swept region clears them, and the final tool
    // walls are where the geometry says.
    let g = &r.geometry;
    assert!(g.slot_clearance() > 0.1 * test.depth);
    let scene = dem_core::scene::load(&out.join(cutting::SCENE_FILE)).unwrap();
    let world = dem_core::scene::build(&scene).unwrap();
    // Three slot walls and one rigid tool (a polyline: clearance end, edge, rake end).
    assert_eq!(world.state.walls.len(), 4);
    assert_eq!(g.tool.len(), 1);
    assert_eq!(world.state.walls[3].via.len(), 1);
    for w in world
        .state
        .walls
        .iter()
        .filter(|w| w.name.starts_with("slot"))
    {
        for t in &g.tool {
            let dx = g.travel_end - g.travel_start;
            for f in t.vertices().windows(2) {
                let (a, b) = (f[0], f[1]);
                let quad = [a, b, [b[0] + dx, b[1]], [a[0] + dx, a[1]]];
                assert!(
                    segment_polygon_distance(w.a, w.b, &quad) > 0.0,
                    "{}",
                    w.name
                );
            }
        }
    }

    // Files: the result JSON has the documented structure; the force CSV one row per
    // history row.
    let text = std::fs::read_to_string(out.join(cutting::RESULT_FILE)).unwrap();
    let j: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(j["schema"], cutting::RESULT_SCHEMA);
    for k in ["peak", "mean", "sd", "samples"] {
        assert!(j["main_force"][k].is_number(), "main_force.{k}");
        assert!(j["vertical_force"][k].is_number(), "vertical_force.{k}");
    }
    for k in [
        "chips",
        "broken_bonds",
        "surface",
        "residual_cracks",
        "window",
        "run",
    ] {
        assert!(!j[k].is_null(), "{k}");
    }
    assert!(j["chips"]["chips"]["count"].as_u64().unwrap() > 0);
    assert!(j["residual_cracks"]["count"].is_u64());
    let csv = std::fs::read_to_string(out.join(cutting::FORCES_FILE)).unwrap();
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("travel_m,time_s,main_N,vertical_N"));
    assert_eq!(lines.count(), r.run.history_rows);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A specimen file of one disc of radius r at (r, r) in `dir`, and Si3N4's model (E 310 GPa,
/// 800 MPa bonds, radius r).
fn one_disc(dir: &std::path::Path, r: f64) -> (PathBuf, LabModel) {
    let spec_path = dir.join("one.json");
    let spec = serde_json::json!({"schema": "dem.specimen/1", "units": "m",
        "discs": [{"material": "Si3N4", "discs": [[r, r, r]]}]});
    std::fs::write(&spec_path, spec.to_string()).unwrap();
    let p = SpecimenParams::new(
        Method::Traditional,
        4e-3,
        2e-3,
        r,
        r,
        3200.0,
        310e9,
        800e6,
        1,
    );
    (spec_path, LabModel::from_params(&p))
}

/// One disc of radius r pushed by the tool's rake face (slot walls removed from the scene):
/// in every step of contact the force on the tool is minus the force on the disc and equals the
/// linear law k_tool·δ (δ = r − distance from the disc centre to the rake face), along −x; the
/// main force read from the wall columns is +k_tool·δ.
#[test]
fn tool_force_on_a_single_disc() {
    let dir = tmp("single");
    let r = 0.1e-3;
    let (spec_path, model) = one_disc(&dir, r);
    // a_p = 1.2 r: the edge is 0.2 r below the disc centre, so the disc touches the rake
    // face (not the edge) and the clearance face stays clear for overlaps below 0.02 r.
    let test = CuttingTest {
        window_start: 0.0,
        local_damping: 0.0,
        tool: ToolModel::Segments,
        ..CuttingTest::new(1.2 * r, 1.0, 0.5 * r)
    }
    .check()
    .unwrap();
    let info = SpecimenInfo::read(&spec_path).unwrap();
    assert_eq!(info.extent, [0.0, 2.0 * r, 0.0, 2.0 * r]);
    let mut scene = cutting::scene(&test, &model, &info, 1).unwrap();
    scene.walls.retain(|w| !w.name.starts_with("slot"));
    let file = dir.join("one.scene.json");
    std::fs::write(&file, serde_json::to_string(&scene).unwrap()).unwrap();
    let mut w = dem_core::scene::build(&dem_core::scene::load(&file).unwrap()).unwrap();
    let k = test.tool_stiffness * model.contact_kn();
    let g = CutGeometry::new(&test, info.extent).unwrap();
    let rake = w.state.walls.iter().position(|w| w.name == "rake").unwrap();
    let clear = w
        .state
        .walls
        .iter()
        .position(|w| w.name == "clearance")
        .unwrap();
    let mut rows = vec![];
    let mut contacts = 0;
    while w.state.time < g.duration {
        let (xd, yd, xw) = (
            w.state.discs.x[0],
            w.state.discs.y[0],
            w.state.walls[rake].a[0],
        );
        w.step();
        let d = &w.state.discs;
        let delta = r - (xd - xw);
        let (fw, fc) = (w.state.walls[rake].force, w.state.walls[clear].force);
        assert_eq!(fc, [0.0, 0.0], "the clearance face stays clear");
        if delta > 0.0 {
            contacts += 1;
            let f = k * delta;
            assert!((d.fx[0] - f).abs() <= 1e-9 * f, "disc {} vs {f}", d.fx[0]);
            assert!((fw[0] + f).abs() <= 1e-9 * f, "tool {} vs {}", fw[0], -f);
            assert_eq!(fw[0], -d.fx[0]);
            assert!(fw[1].abs() <= 1e-12 * f && d.fy[0].abs() <= 1e-12 * f);
            assert!((yd - r).abs() < 1e-12);
        } else {
            assert_eq!(fw, [0.0, 0.0]);
        }
        rows.push(vec![w.state.time, fw[0], fw[1], fc[0], fc[1]]);
    }
    // An elastic impact on a free disc (no damping): contact lasts half a period π√(m/k),
    // about π/0.3 steps at dt = 0.3√(m/k); the disc leaves faster than the tool and is not
    // touched again.
    assert!(contacts >= 5, "{contacts} steps in contact");
    assert!(
        w.state.discs.vx[0] > test.speed,
        "the disc leaves faster than the tool"
    );
    // The force history the analysis reads: main = −(F_rake + F_clearance)·x̂ = +k·δ.
    let col = |k: usize| rows.iter().map(|r| r[k]).collect::<Vec<f64>>();
    let wall = |name: &str, k: usize| WallSeries {
        name: name.into(),
        fx: col(k),
        fy: col(k + 1),
        moment: vec![0.0; rows.len()],
    };
    let record = Record {
        time: col(0),
        walls: vec![wall("rake", 1), wall("clearance", 3)],
        ..Record::default()
    };
    let fh = ForceHistory::from_record(&record, &g).unwrap();
    let peak = fh.main.iter().copied().fold(0.0, f64::max);
    assert!(peak > 0.0);
    assert!(fh.main.iter().all(|&m| m >= 0.0));
    assert!(fh.vertical.iter().all(|&v| v == 0.0));
    assert_eq!(fh.main[0], 0.0);
    let _ = std::fs::remove_dir_all(&dir);
}

/// One disc pressed on the cutting edge (its centre in the exterior wedge where the edge vertex
/// is the tool's nearest point, overlap δ): the rigid tool gives one contact, along the line
/// from the edge to the disc centre, with the closed-form force K δ, K = 2 K_dd f/(1 + f)
/// (PFC's series stiffness, f = 10: 1.82 K_dd); the tool feels minus that force. The earlier
/// two-segment tool gives two contacts at the same point: 2 f K_dd δ, 11× the rigid tool's.
#[test]
fn a_disc_on_the_tool_edge_gets_one_contact() {
    let dir = tmp("edge");
    let r = 0.1e-3;
    let (spec_path, model) = one_disc(&dir, r);
    let info = SpecimenInfo::read(&spec_path).unwrap();
    let kdd = model.contact_kn();
    let mut forces = vec![];
    for tool in [ToolModel::Rigid, ToolModel::Segments] {
        let test = CuttingTest {
            local_damping: 0.0,
            window_start: 0.0,
            tool,
            ..CuttingTest::new(1.2 * r, 1.0, 0.5 * r)
        }
        .check()
        .unwrap();
        let mut scene = cutting::scene(&test, &model, &info, 1).unwrap();
        // Keep the tool alone, at rest.
        scene.walls.retain(|w| !w.name.starts_with("slot"));
        for w in &mut scene.walls {
            w.velocity = [0.0, 0.0];
        }
        let file = dir.join(format!("{tool:?}.scene.json"));
        std::fs::write(&file, serde_json::to_string(&scene).unwrap()).unwrap();
        let mut w = dem_core::scene::build(&dem_core::scene::load(&file).unwrap()).unwrap();
        let g = CutGeometry::new(&test, info.extent).unwrap();
        let e = g.edge_start;
        // Below and ahead of the edge, 40° under the horizontal: outside both faces' normal
        // strips (rake face up, clearance face back at 7°), so the edge is the nearest point.
        let u = [40f64.to_radians().cos(), -(40f64.to_radians().sin())];
        let delta = 0.01 * r;
        w.state.discs.x[0] = e[0] + u[0] * (r - delta);
        w.state.discs.y[0] = e[1] + u[1] * (r - delta);
        w.refresh();
        w.step();
        let d = &w.state.discs;
        let f = [d.fx[0], d.fy[0]];
        let fw = w
            .state
            .walls
            .iter()
            .fold([0.0, 0.0], |s, w| [s[0] + w.force[0], s[1] + w.force[1]]);
        // Equal and opposite, along u (the disc is pushed away from the edge).
        assert!(
            (f[0] + fw[0]).abs() <= 1e-12 * f[0].abs()
                && (f[1] + fw[1]).abs() <= 1e-12 * f[0].abs()
        );
        let mag = f[0].hypot(f[1]);
        assert!(
            (f[0] / mag - u[0]).abs() < 1e-9 && (f[1] / mag - u[1]).abs() < 1e-9,
            "{f:?}"
        );
        forces.push(mag / delta);
    }
    let k_rigid = series_wall_stiffness(kdd, 10.0);
    assert!((k_rigid / kdd - 20.0 / 11.0).abs() < 1e-12);
    assert!(
        (forces[0] - k_rigid).abs() <= 1e-6 * k_rigid,
        "rigid: {} vs {k_rigid}",
        forces[0]
    );
    let k_two = 2.0 * 10.0 * kdd;
    assert!(
        (forces[1] - k_two).abs() <= 1e-6 * k_two,
        "segments: {} vs {k_two}",
        forces[1]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A bad test or specimen is an error naming the field, not a panic.
#[test]
fn bad_input_is_an_error() {
    let t = CuttingTest {
        clearance_angle: 0.0,
        ..Default::default()
    };
    assert!(t
        .validate()
        .unwrap_err()
        .to_string()
        .contains("clearance_angle"));
    let t = CuttingTest {
        window_start: 20.0,
        ..Default::default()
    };
    assert!(t
        .validate()
        .unwrap_err()
        .to_string()
        .contains("window_start"));
    let dir = tmp("bad");
    let f = dir.join("not.json");
    std::fs::write(&f, "{\"schema\": \"dem.specimen/1\", \"discs\": []}").unwrap();
    assert!(SpecimenInfo::read(&f).is_err());
    assert!(SpecimenInfo::read(&dir.join("missing.json")).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

/// A cut stopped part-way (as if killed after its last checkpoint) and run again resumes from
/// that checkpoint and ends with the same bytes as an uninterrupted run: forces, history,
/// break log and final world; its run figures count both invocations.
#[test]
fn an_interrupted_cut_resumes_bit_identically() {
    use dem_lab::cutting::CuttingRunOptions;
    use dem_lab::LabError;
    let dir = tmp("resume");
    let (spec, model) = lab_common::cut_specimen(&dir);
    let spec = dem_lab::cutting::SpecimenInfo::read(&spec).unwrap();
    let test = CuttingTest {
        history_rows: 200,
        window_start: 1.0,
        ..CuttingTest::new(0.6e-3, 10.0, 1.0e-3)
    }
    .check()
    .unwrap();
    let (a, b) = (dir.join("a"), dir.join("b"));
    let ra = cutting::run(&test, &model, &spec, &a, &mut |_, _| {}).unwrap();
    assert_eq!(ra.run.invocations, 1);
    // No numbered checkpoint is left after a completed run.
    let left = |d: &std::path::Path| dem_core::output::driver::numbered_checkpoints(d).unwrap();
    assert!(left(&a).is_empty());
    // ... nor listed: every file the result and the summary name is there.
    for f in &ra.files {
        assert!(
            std::path::Path::new(f).is_file(),
            "result lists {f}, not on disk"
        );
    }
    let summary: dem_core::output::summary::RunSummary =
        serde_json::from_str(&std::fs::read_to_string(a.join("summary.json")).unwrap()).unwrap();
    for f in &summary.files {
        assert!(a.join(f).is_file(), "summary lists {f}, not on disk");
    }

    let stop = CuttingRunOptions {
        max_steps: Some(ra.run.steps / 2),
        ..CuttingRunOptions::default()
    };
    match cutting::run_with(&test, &model, &spec, &b, &stop, &mut |_, _| {}) {
        Err(LabError::Stopped { step, .. }) => assert_eq!(step, ra.run.steps / 2),
        other => panic!("expected a stop, got {:?}", other.map(|r| r.run)),
    }
    // Only the newest numbered checkpoint is kept; it lies before the stop.
    let ck = left(&b);
    assert_eq!(ck.len(), 1, "{ck:?}");
    assert!(ck[0].0 > 0 && ck[0].0 <= ra.run.steps / 2);

    let mut calls = 0;
    let rb = cutting::run(&test, &model, &spec, &b, &mut |_, _| calls += 1).unwrap();
    assert!(calls > 0);
    assert_eq!(rb.run.invocations, 2);
    assert!(left(&b).is_empty());
    for f in [cutting::FORCES_FILE, "history.csv", "breaks.csv"] {
        let (x, y) = (
            std::fs::read(a.join(f)).unwrap(),
            std::fs::read(b.join(f)).unwrap(),
        );
        assert!(x == y, "{f} differs after the resume");
    }
    assert_eq!(ra.main_force, rb.main_force);
    assert_eq!(ra.broken_total, rb.broken_total);
    assert_eq!(ra.run.steps, rb.run.steps);
    let world = |d: &std::path::Path| {
        let text = std::fs::read_to_string(d.join("ckpt-final.json")).unwrap();
        let v: serde_json::Value = serde_json::from_str(&text).unwrap();
        v["world"].to_string()
    };
    assert!(world(&a) == world(&b), "final worlds differ");
}
