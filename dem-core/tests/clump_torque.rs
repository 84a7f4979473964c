//! A rigid clump (ORC) under a constant torque turns with angular acceleration T/I, I the
//! template's inertia about its mass centre; its members keep their offsets; under a force
//! through the mass centre it accelerates at F/m without turning.

use clumpgen::outline::{parse_outline, ReadOptions};
use clumpgen::template::{Method, Template};
use clumpgen::{make_template, ClumpParams};
use dem_core::clump::add_rigid_clump;
use dem_core::contact::LinearSpringDashpot;
use dem_core::{ContactLaws, ContactModel, ExternalLoad, Params, State, World};

/// An ellipse-like grain, 3 mm × 1.6 mm, with a dent so it is not symmetric.
fn template(method: Method) -> Template {
    let mut text = String::from("# units: mm\nx,y\n");
    let n = 72;
    for k in 0..n {
        let a = std::f64::consts::TAU * k as f64 / n as f64;
        let dent = 1.0 - 0.25 * (-(a - 1.0).powi(2) / 0.1).exp();
        text += &format!("{},{}\n", 1.5 * a.cos() * dent, 0.8 * a.sin() * dent);
    }
    let o = parse_outline(&text, "g", "g.csv", false, &ReadOptions::default()).expect("outline");
    let p = ClumpParams {
        method,
        density: 2650.0,
        thickness: 0.002,
        ..ClumpParams::default()
    };
    make_template(&o, &p).expect("template")
}

fn world(t: &Template) -> World {
    let mut st = State {
        thickness: 0.002,
        ..State::default()
    };
    add_rigid_clump(&mut st, t, 0.01, 0.02, 0.3, 0).expect("clump");
    let law = LinearSpringDashpot::elastic(1e6, 1e6, 0.5);
    World::new(
        st,
        Params::default(),
        ContactLaws::uniform(ContactModel::Linear(law)),
    )
}

#[test]
fn clump_under_torque_turns_at_t_over_i() {
    for method in [Method::Improved, Method::Orc] {
        let t = template(method);
        assert!(t.discs.len() > 3, "a real clump");
        let mut w = world(&t);
        let id = w.state.discs.id[0];
        let torque = 2e-6;
        w.loads.push(ExternalLoad {
            id,
            force: [0.0; 2],
            torque,
        });
        let dist = |w: &World| -> Vec<f64> {
            let d = &w.state.discs;
            (1..d.len())
                .map(|k| (d.x[k] - d.x[0]).hypot(d.y[k] - d.y[0]))
                .collect()
        };
        let d0 = dist(&w);
        let (x0, y0) = (w.state.clumps.x[0], w.state.clumps.y[0]);
        let steps = 2000;
        w.run(steps);
        let c = &w.state.clumps;
        let time = w.state.time;
        let alpha = c.omega[0] / time;
        let inertia = t.achieved.inertia_own;
        eprintln!(
            "{method:?}: alpha {alpha:.9e}, T/I {:.9e}",
            torque / inertia
        );
        assert!(
            (alpha * inertia / torque - 1.0).abs() < 1e-9,
            "{method:?}: {alpha}"
        );
        assert_eq!(c.inertia[0], inertia);
        // Pure torque: the mass centre does not move.
        assert!((c.x[0] - x0).abs() < 1e-15 && (c.y[0] - y0).abs() < 1e-15);
        // Rigid: member distances unchanged.
        for (a, b) in d0.iter().zip(dist(&w)) {
            assert!(
                (a - b).abs() < 1e-12 * a.max(1e-3),
                "member moved: {a} -> {b}"
            );
        }
        // Improved templates carry the grain's own inertia.
        if method == Method::Improved {
            assert!((t.achieved.inertia_own / t.target.inertia_own - 1.0).abs() < 1e-6);
        }
    }
}

#[test]
fn clump_under_central_force_accelerates_at_f_over_m() {
    let t = template(Method::Orc);
    let mut w = world(&t);
    let f = [3e-5, -1e-5];
    let m = w.state.clumps.m[0];
    // Split the force over two members so that its resultant passes off the centre, and
    // cancel the moment with a torque: the clump must translate without turning.
    let d = &w.state.discs;
    let (cx, cy) = (w.state.clumps.x[0], w.state.clumps.y[0]);
    let (rx, ry) = (d.x[0] - cx, d.y[0] - cy);
    w.loads.push(ExternalLoad {
        id: d.id[0],
        force: f,
        torque: -(rx * f[1] - ry * f[0]),
    });
    w.run(1000);
    let c = &w.state.clumps;
    let time = w.state.time;
    assert!((c.vx[0] / time / (f[0] / m) - 1.0).abs() < 1e-9);
    assert!((c.vy[0] / time / (f[1] / m) - 1.0).abs() < 1e-9);
    assert!(c.omega[0].abs() < 1e-12 * (f[0] / m) * time / 1e-3);
    assert!((m / t.achieved.mass - 1.0).abs() < 1e-12);
}
