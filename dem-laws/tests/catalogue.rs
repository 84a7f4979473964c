//! The composed laws against their closed forms, by time integration of a two-body impact,
//! for the 2D (T = f64) and 3D (T = Vector3) tangent types; and every bad-input error.
//!
//! The impact is the reduced one-body problem of two spheres along a fixed normal: overlap δ,
//! relative normal velocity v_n (> 0 separating) and tangential velocity v_t, effective mass
//! m*, integrated by leapfrog (= velocity Verlet): the law sees the half-step velocities and
//! the new overlap, like the solvers' force pass.

use dem_laws::{ContactLaw, GranularHistory, GranularLaw, Kin, Tangent};
use nalgebra::Vector3;

const M: f64 = 1e-3; // m* (kg)
const R: f64 = 1e-3; // R* (m)

struct Impact {
    /// Exit normal velocity / entry normal velocity.
    e: f64,
    /// Largest |E(t) − E(0)| / E(0) of kinetic + e_strain during the impact.
    energy_drift: f64,
}

/// Impact at normal speed v0 and tangential velocity vt0 with `steps` steps per
/// characteristic time √(m*/k), k the stiffness at the Hertz maximum overlap estimate.
fn impact<T: Tangent>(law: &GranularLaw, v0: f64, vt0: T, dt: f64) -> Impact {
    let mut h = GranularHistory::<T>::default();
    let (mut delta, mut vn, mut vt) = (0.0f64, -v0, vt0);
    let e0 = 0.5 * M * (v0 * v0 + vt0.dot(vt0));
    let mut drift: f64 = 0.0;
    let mut touched = false;
    for _ in 0..10_000_000 {
        let d_new = delta - vn * dt;
        let k = Kin {
            delta: d_new,
            vn,
            vt,
            m_eff: M,
            r_eff: R,
            dt,
        };
        let out = law.force::<true>(&k, &mut h);
        let vn_new = vn + out.f_n / M * dt;
        let vt_new = vt.add_scaled(out.f_t, dt / M);
        // Energy at the integer step: mean of the half-step velocities.
        let vnm = 0.5 * (vn + vn_new);
        let vtm = vt.add_scaled(vt_new, 1.0).scale(0.5);
        let en = 0.5 * M * (vnm * vnm + vtm.dot(vtm)) + out.e_strain;
        if d_new > 0.0 {
            touched = true;
            drift = drift.max((en - e0).abs() / e0);
        }
        if touched && d_new < 0.0 {
            // Exit: no force once δ < 0, so the last half-step velocity is the exit one.
            return Impact {
                e: vn / v0,
                energy_drift: drift,
            };
        }
        delta = d_new;
        vn = vn_new;
        vt = vt_new;
    }
    panic!("the impact did not end");
}

/// Restitution of a normal impact at speed v0 by RK4 on (δ, v_n) (the law's history copied
/// for the stages and committed at each new state), the exit velocity interpolated linearly
/// to δ = 0 within the last step. RK4 rather than leapfrog because the leapfrog dashpot
/// reads the half-step velocity, an O(Δt) lag that shows in e (8.5e-5 at 2000 steps per
/// √(m*/k) for the linear law at e = 0.1). Only for laws without adhesion.
fn restitution_rk4<T: Tangent>(law: &GranularLaw, v0: f64, vt: T, dt: f64) -> f64 {
    let mut h = GranularHistory::<T>::default();
    let acc = |h: &GranularHistory<T>, d: f64, v: f64| {
        let mut hc = *h;
        // The contact-phase equation, continued to δ ≤ 0 by its limit from above: the
        // dashpot force of the linear law jumps at δ = 0, and the closed form is that of
        // the contact phase, so a stage just outside must not see the jump (it would cost
        // O(Δt) in e).
        let k = Kin {
            delta: d.max(f64::MIN_POSITIVE),
            vn: v,
            vt,
            m_eff: M,
            r_eff: R,
            dt,
        };
        law.force::<false>(&k, &mut hc).f_n / M
    };
    let (mut d, mut v) = (0.0f64, -v0);
    let mut touched = false;
    for _ in 0..10_000_000 {
        // dδ/dt = −v_n, dv_n/dt = F_n/m*.
        let (k1d, k1v) = (-v, acc(&h, d, v));
        let (k2d, k2v) = (
            -(v + 0.5 * dt * k1v),
            acc(&h, d + 0.5 * dt * k1d, v + 0.5 * dt * k1v),
        );
        let (k3d, k3v) = (
            -(v + 0.5 * dt * k2v),
            acc(&h, d + 0.5 * dt * k2d, v + 0.5 * dt * k2v),
        );
        let (k4d, k4v) = (-(v + dt * k3v), acc(&h, d + dt * k3d, v + dt * k3v));
        let dn = d + dt / 6.0 * (k1d + 2.0 * k2d + 2.0 * k3d + k4d);
        let vn = v + dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
        if dn > 0.0 {
            touched = true;
        }
        if touched && dn <= 0.0 {
            let s = d / (d - dn);
            return (v + s * (vn - v)) / v0;
        }
        // Commit the history at the new state.
        let k = Kin {
            delta: dn,
            vn,
            vt,
            m_eff: M,
            r_eff: R,
            dt,
        };
        law.force::<false>(&k, &mut h);
        d = dn;
        v = vn;
    }
    panic!("the impact did not end");
}

fn law(json: &str) -> GranularLaw {
    GranularLaw::from_json(json, None).unwrap()
}

/// Contact time scale √(m*/k) for the stiffness k: dt = this / 2000.
fn dt_for(k: f64) -> f64 {
    (M / k).sqrt() / 2000.0
}

#[test]
fn undamped_impacts_conserve_energy() {
    // Hertz stiffness scale at v0 = 0.1: δ_max = (15 m v²/(16 E* √R))^{2/5}.
    let e_mod = 7e10f64;
    let nu = 0.33;
    let e_star = e_mod / (2.0 * (1.0 - nu * nu));
    let v0 = 0.1;
    let dmax = (15.0 * M * v0 * v0 / (16.0 * e_star * R.sqrt())).powf(0.4);
    let k_h = 2.0 * e_star * (R * dmax).sqrt();
    let cases = [
        (
            r#"{"normal": {"model": "hooke", "kn": 1e5},
                "tangential": {"model": "linear_history", "kt": 4e4, "mu": 1e9}}"#,
            1e5,
        ),
        (
            r#"{"normal": {"model": "hertz", "kn": 1e9},
                "tangential": {"model": "linear_history", "kt": 4e4, "mu": 1e9}}"#,
            1.5e9 * 1e-4f64.sqrt(),
        ),
        (
            r#"{"normal": {"model": "hertz/material", "E": 7e10, "nu": 0.33},
                "damping": {"model": "none"},
                "tangential": {"model": "linear_history", "kt": 4e4, "mu": 1e9}}"#,
            k_h,
        ),
        (
            r#"{"normal": {"model": "walton_braun", "k1": 1e5, "k2": 1e5},
                "tangential": {"model": "linear_history", "kt": 4e4, "mu": 1e9}}"#,
            1e5,
        ),
        (
            // The adhesive work −4πγR*δ is part of e_strain, so the energy is conserved.
            r#"{"normal": {"model": "dmt", "E": 7e10, "nu": 0.33, "gamma": 0.5},
                "tangential": {"model": "linear_history", "kt": 4e4, "mu": 1e9}}"#,
            k_h,
        ),
    ];
    for (json, k) in cases {
        let l = law(json);
        let dt = dt_for(k);
        let a = impact(&l, v0, 0.0f64, dt);
        let b = impact(&l, v0, Vector3::new(0.03, -0.04, 0.0), dt);
        let c = impact(&l, v0, 0.05f64, dt);
        println!(
            "{:?}: 2D normal e = {:.9}, drift {:.2e}; 3D oblique e = {:.9}, drift {:.2e}",
            l.normal, a.e, a.energy_drift, b.e, b.energy_drift
        );
        for i in [&a, &b, &c] {
            assert!((i.e - 1.0).abs() < 1e-6, "e = {}", i.e);
            assert!(i.energy_drift < 1e-6, "drift {}", i.energy_drift);
        }
    }
}

fn e_sweep(json_of: impl Fn(f64) -> String, k: f64, v0: f64) -> f64 {
    let mut worst: f64 = 0.0;
    for i in 0..=89 {
        let e = 0.1 + 0.01 * i as f64;
        let l = law(&json_of(e));
        let a = restitution_rk4(&l, v0, 0.0f64, dt_for(k));
        worst = worst.max((a - e).abs());
    }
    let l = law(&json_of(0.5));
    let b = restitution_rk4(&l, v0, Vector3::new(0.0, 0.01, 0.0), dt_for(k));
    worst.max((b - 0.5).abs())
}

#[test]
fn restitution_in_is_restitution_out() {
    let lin = |e: f64| {
        format!(
            r#"{{"normal": {{"model": "hooke", "kn": 1e5}},
                "damping": {{"model": "coeff_restitution", "e": {e}}},
                "tangential": {{"model": "linear_nohistory", "gamma_t": 0, "mu": 0.3}}}}"#
        )
    };
    let w = e_sweep(lin, 1e5, 0.1);
    println!("coeff_restitution, hooke: max |e_out − e| = {w:.2e}");
    assert!(w < 1e-7, "{w}");

    let e_star = 7e10 / (2.0 * (1.0 - 0.33f64 * 0.33));
    let v0 = 0.1;
    let dmax = (15.0 * M * v0 * v0 / (16.0 * e_star * R.sqrt())).powf(0.4);
    let k_h = 2.0 * e_star * (R * dmax).sqrt();
    // Plain hertz (k_n δ^{3/2}): the same dimensionless impact, so the same calibration.
    let hz = |e: f64| {
        format!(
            r#"{{"normal": {{"model": "hertz", "kn": 1e9}},
                "damping": {{"model": "coeff_restitution", "e": {e}}},
                "tangential": {{"model": "linear_nohistory", "gamma_t": 0, "mu": 0.3}}}}"#
        )
    };
    let w = e_sweep(hz, 2.5e6, v0);
    println!("coeff_restitution, hertz: max |e_out − e| = {w:.2e}");
    assert!(w < 1e-5, "hertz: {w}");
    for model in ["tsuji", "coeff_restitution"] {
        let hz = |e: f64| {
            format!(
                r#"{{"normal": {{"model": "hertz/material", "E": 7e10, "nu": 0.33}},
                    "damping": {{"model": "{model}", "e": {e}}},
                    "tangential": {{"model": "mindlin", "mu": 0.3}}}}"#
            )
        };
        let w = e_sweep(hz, k_h, v0);
        println!("{model}, hertz/material: max |e_out − e| = {w:.2e}");
        assert!(w < 1e-5, "{model}: {w}");
        // Velocity independent: the same e at 10× the speed.
        let l = law(&hz(0.3));
        let a = restitution_rk4(&l, 1.0, 0.0f64, dt_for(k_h * 10f64.powf(0.4)));
        assert!((a - 0.3).abs() < 1e-3, "{model} at 1 m/s: {a}");
    }
}

#[test]
fn walton_braun_restitution_is_sqrt_k1_over_k2() {
    let mut worst: f64 = 0.0;
    for &ratio in &[1.0, 1.5, 2.0, 4.0, 10.0, 100.0] {
        let json = format!(
            r#"{{"normal": {{"model": "walton_braun", "k1": 1e5, "k2": {}}},
                "tangential": {{"model": "linear_history", "kt": 4e4, "mu": 0.3}}}}"#,
            1e5 * ratio
        );
        let l = law(&json);
        let a = impact(&l, 0.1, 0.0f64, dt_for(1e5 * ratio));
        let b = impact(&l, 0.1, Vector3::zeros(), dt_for(1e5 * ratio));
        let c = restitution_rk4(&l, 0.1, 0.0f64, dt_for(1e5 * ratio));
        assert_eq!(a.e, b.e);
        worst = worst.max((a.e - (1.0 / ratio).sqrt()).abs());
        worst = worst.max((c - (1.0 / ratio).sqrt()).abs());
    }
    println!("walton_braun: max |e_out − √(k1/k2)| = {worst:.2e}");
    assert!(worst < 1e-6, "{worst}");
}

#[test]
fn adhesive_laws_reach_and_pull() {
    let jkr = law(
        r#"{"normal": {"model": "jkr", "E": 7e10, "nu": 0.33, "gamma": 0.5},
            "tangential": {"model": "mindlin/deresiewicz", "mu": 0.3}}"#,
    );
    let r = <GranularLaw as ContactLaw<f64>>::reach(&jkr, R);
    assert!(r > 0.0);
    assert_eq!(
        r,
        -dem_laws::jkr_critical_overlap(jkr.normal.material().unwrap().e_star, 0.5, R)
    );
    // Touch, then pull to just inside the neck: the force is tensile and the tangential
    // model still has a Coulomb load F_ne + 2 × 3πγR*.
    let mut h = GranularHistory::<Vector3<f64>>::default();
    let k = |delta: f64| Kin {
        delta,
        vn: 0.0,
        vt: Vector3::new(1e-3, 0.0, 0.0),
        m_eff: M,
        r_eff: R,
        dt: 1e-8,
    };
    jkr.force::<false>(&k(1e-8), &mut h);
    let o = jkr.force::<true>(&k(-0.9 * r), &mut h);
    assert!(o.f_n < 0.0 && o.f_t.norm() > 0.0);
    let o = jkr.force::<true>(&k(-1.1 * r), &mut h);
    assert_eq!(o.f_n, 0.0);
    assert_eq!(h, GranularHistory::default());

    let vdw = law(
        r#"{"normal": {"model": "hertz/material", "E": 7e10, "nu": 0.33},
            "tangential": {"model": "mindlin", "mu": 0.3},
            "vdw": {"hamaker": 6.5e-20, "cutoff": 1e-7}}"#,
    );
    assert_eq!(<GranularLaw as ContactLaw<f64>>::reach(&vdw, R), 1e-7);
    let mut h = GranularHistory::<f64>::default();
    let kin = Kin {
        delta: -1e-8,
        vn: 0.0,
        vt: 0.0,
        m_eff: M,
        r_eff: 0.5e-6,
        dt: 1e-9,
    };
    let o = vdw.force_pair::<true, f64>(&kin, 1e-6, 1e-6, &mut h);
    let f = dem_laws::sphere_sphere_force(6.5e-20, 1e-6, 1e-6, 1e-8);
    assert_eq!(o.f_n, -f);
    assert!(o.e_strain < 0.0);
    // The trait form takes R₁ = R₂ = 2R*: the same for this equal pair.
    assert_eq!(vdw.force::<true>(&kin, &mut h), o);
}

fn err(json: &str) -> String {
    match GranularLaw::from_json(json, Some("law.json")) {
        Ok(l) => panic!("accepted {json}: {l:?}"),
        Err(e) => {
            let s = e.to_string();
            assert!(s.starts_with("law.json: "), "{s}");
            s
        }
    }
}

const T: &str = r#""tangential": {"model": "mindlin", "mu": 0.3}"#;
const HM: &str = r#""normal": {"model": "hertz/material", "E": 7e10, "nu": 0.33}"#;

#[test]
fn the_example_of_the_brief_reads() {
    let l = law(
        r#"{"normal": {"model": "hertz/material", "E": 7e10, "nu": 0.33},
            "damping": {"model": "tsuji", "e": 0.5},
            "tangential": {"model": "mindlin", "mu": 0.3},
            "rolling": {"model": "elastic_plastic", "mu_r": 0.05},
            "vdw": {"hamaker": 6.5e-20, "h_min": 4e-10, "cutoff": 1e-7}}"#,
    );
    assert!(l.rolling.is_some() && l.vdw.is_some());
    let l = law(&format!(
        r#"{{{HM}, {T}, "rolling": {{"model": "constant_torque", "mu_r": 0.1}},
            "vdw": {{"hamaker": 1e-19, "cutoff": 1e-7, "length": 1e-3}}}}"#
    ));
    assert_eq!(l.vdw.unwrap().h_min, dem_laws::H_MIN_DEFAULT);
    assert_eq!(l.damping, dem_laws::Damping::None);
    // Rolling through the law, 2D and 3D.
    let mut h = GranularHistory::<f64>::default();
    let k = Kin {
        delta: 1e-6,
        vn: 0.0,
        vt: 0.0,
        m_eff: M,
        r_eff: R,
        dt: 1e-7,
    };
    let o = l.force::<false>(&k, &mut h);
    assert!(o.f_n > 0.0);
    let (m, d) = l.roll(&k, o.f_n, 2.0, &mut h);
    assert!((m + 0.1 * R * o.f_n).abs() < 1e-15 && d > 0.0);
    // No twisting model: no moment.
    assert_eq!(l.twist(&k, o.f_n, 1.0, &mut h), (0.0, 0.0));

    // Twisting (3D), Marshall: k_tw = ½ k_t a², elastic for a small spin.
    let l = law(&format!(
        r#"{{{HM}, {T}, "twisting": {{"model": "marshall"}}}}"#
    ));
    let mut h = GranularHistory::<Vector3<f64>>::default();
    let k = Kin {
        delta: 1e-6,
        vn: 0.0,
        vt: Vector3::zeros(),
        m_eff: M,
        r_eff: R,
        dt: 1e-7,
    };
    let o = l.force::<false>(&k, &mut h);
    let (m, d) = l.twist(&k, o.f_n, 1e-3, &mut h);
    let a = (R * 1e-6f64).sqrt();
    let kt = 8.0 * l.normal.material().unwrap().g_star * a;
    assert!((m + 0.5 * kt * a * a * 1e-10).abs() < 1e-12 * m.abs() && d == 0.0);
    // Out of contact the twist is forgotten.
    l.force::<false>(&Kin { delta: -1e-9, ..k }, &mut h);
    assert_eq!(l.twist(&k, o.f_n, 1e-3, &mut h), (0.0, 0.0));
    let l = law(&format!(
        r#"{{{HM}, {T}, "twisting": {{"model": "sds", "k_tw": 1e-3, "eta_tw": 0, "mu_tw": 1e-4}}}}"#
    ));
    assert_eq!(
        l.twisting,
        Some(dem_laws::Twisting::Sds {
            k_tw: 1e-3,
            eta_tw: 0.0,
            mu_tw: 1e-4
        })
    );
}

#[test]
fn every_bad_input_names_its_field() {
    let cases: Vec<(String, &str)> = vec![
        // Unknown model names list the known ones.
        (
            format!(r#"{{"normal": {{"model": "hertzz", "kn": 1}}, {T}}}"#),
            "normal.model",
        ),
        (
            format!(r#"{{{HM}, "damping": {{"model": "x"}}, {T}}}"#),
            "damping.model",
        ),
        (
            format!(r#"{{{HM}, "tangential": {{"model": "y", "mu": 1}}}}"#),
            "tangential.model",
        ),
        (
            format!(r#"{{{HM}, {T}, "rolling": {{"model": "z"}}}}"#),
            "rolling.model",
        ),
        // Restitution.
        (
            format!(r#"{{{HM}, "damping": {{"model": "tsuji", "e": 0}}, {T}}}"#),
            "damping.e",
        ),
        (
            format!(r#"{{{HM}, "damping": {{"model": "tsuji", "e": -0.5}}, {T}}}"#),
            "damping.e",
        ),
        (
            format!(r#"{{{HM}, "damping": {{"model": "coeff_restitution", "e": 1.01}}, {T}}}"#),
            "damping.e",
        ),
        // Poisson's ratio and modulus.
        (
            format!(r#"{{"normal": {{"model": "hertz/material", "E": 7e10, "nu": 0.5}}, {T}}}"#),
            "normal.nu",
        ),
        (
            format!(r#"{{"normal": {{"model": "jkr", "E": 1e9, "nu": -1, "gamma": 0.1}}, {T}}}"#),
            "normal.nu",
        ),
        (
            format!(r#"{{"normal": {{"model": "hertz/material", "E": 0, "nu": 0.3}}, {T}}}"#),
            "normal.E",
        ),
        (
            format!(r#"{{"normal": {{"model": "dmt", "E": -1, "nu": 0.3, "gamma": 1}}, {T}}}"#),
            "normal.E",
        ),
        (
            format!(r#"{{"normal": {{"model": "hooke", "kn": -1}}, {T}}}"#),
            "normal.kn",
        ),
        // Negative surface energy, Hamaker, μ.
        (
            format!(r#"{{"normal": {{"model": "jkr", "E": 1e9, "nu": 0.3, "gamma": -1}}, {T}}}"#),
            "normal.gamma",
        ),
        (
            format!(r#"{{"normal": {{"model": "dmt", "E": 1e9, "nu": 0.3, "gamma": -1}}, {T}}}"#),
            "normal.gamma",
        ),
        (
            format!(r#"{{{HM}, {T}, "vdw": {{"hamaker": -1e-20, "cutoff": 1e-7}}}}"#),
            "vdw.hamaker",
        ),
        (
            format!(r#"{{{HM}, {T}, "vdw": {{"hamaker": 1e-20, "cutoff": 1e-10}}}}"#),
            "vdw.cutoff",
        ),
        (
            format!(r#"{{{HM}, "tangential": {{"model": "mindlin", "mu": -0.1}}}}"#),
            "tangential.mu",
        ),
        (
            format!(r#"{{{HM}, {T}, "rolling": {{"model": "constant_torque", "mu_r": -1}}}}"#),
            "rolling.mu_r",
        ),
        (
            format!(
                r#"{{{HM}, {T}, "twisting": {{"model": "sds", "k_tw": -1, "eta_tw": 0, "mu_tw": 1}}}}"#
            ),
            "twisting.k_tw",
        ),
        (
            format!(r#"{{{HM}, {T}, "twisting": {{"model": "spin"}}}}"#),
            "twisting.model",
        ),
        // Missing fields.
        (
            format!(r#"{{{HM}, "damping": {{"model": "tsuji"}}, {T}}}"#),
            "damping.e",
        ),
        (
            format!(r#"{{"normal": {{"model": "hertz/material", "E": 1e9}}, {T}}}"#),
            "normal.nu",
        ),
        (
            format!(r#"{{"normal": {{"kn": 1e5}}, {T}}}"#),
            "normal.model",
        ),
        (format!(r#"{{{HM}}}"#), "tangential"),
        (
            format!(r#"{{{HM}, {T}, "vdw": {{"hamaker": 1e-20}}}}"#),
            "vdw.cutoff",
        ),
        // Unknown field, wrong type, model that needs E and nu, Walton–Braun k2 < k1.
        (
            format!(r#"{{{HM}, "tangential": {{"model": "mindlin", "mu": 0.3, "k": 1}}}}"#),
            "k",
        ),
        (
            format!(r#"{{{HM}, "damping": {{"model": "tsuji", "e": "half"}}, {T}}}"#),
            "damping",
        ),
        (
            format!(r#"{{"normal": {{"model": "hooke", "kn": 1e5}}, {T}}}"#),
            "tangential.model",
        ),
        (
            format!(r#"{{"normal": {{"model": "walton_braun", "k1": 2, "k2": 1}}, {T}}}"#),
            "normal.k2",
        ),
    ];
    for (json, field) in &cases {
        let s = err(json);
        println!("{s}");
        assert!(s.contains(field), "{field} not in: {s}");
    }
    // The known names are listed.
    let s = err(&format!(
        r#"{{"normal": {{"model": "hertzz", "kn": 1}}, {T}}}"#
    ));
    for name in ["hooke", "hertz/material", "dmt", "jkr", "walton_braun"] {
        assert!(s.contains(name), "{s}");
    }
    // NaN cannot be written in JSON, but a spec built in code can hold it.
    let spec = dem_laws::GranularSpec {
        normal: dem_laws::NormalSpec::HertzMaterial {
            e: f64::NAN,
            nu: 0.3,
        },
        damping: dem_laws::DampingSpec::None,
        tangential: dem_laws::TangentialSpec::Mindlin {
            mu: 0.3,
            xgammat: 0.0,
        },
        rolling: None,
        twisting: None,
        vdw: None,
        limit_damping: false,
    };
    let e = spec.build().unwrap_err();
    assert_eq!(e.path(), Some("normal.E"));
    assert!(e.to_string().contains("NaN"), "{e}");
    let spec = dem_laws::GranularSpec {
        normal: dem_laws::NormalSpec::HertzMaterial { e: 7e10, nu: 0.3 },
        damping: dem_laws::DampingSpec::Tsuji { e: f64::NAN },
        ..spec
    };
    assert_eq!(spec.build().unwrap_err().path(), Some("damping.e"));
    // A missing file names the file.
    let e = GranularLaw::from_json_file(std::path::Path::new("/nonexistent/law.json"))
        .unwrap_err()
        .to_string();
    assert!(e.contains("/nonexistent/law.json"), "{e}");
}

/// The energy terms of `Out` close the balance of a damped, sliding impact: the kinetic energy
/// lost equals the dashpot work (d_n, d_t booked with the mean of the half-step velocities)
/// plus the slip work e_fric, to the integration error.
fn energy_balance<T: Tangent>(law: &GranularLaw, vt0: T, dt: f64) -> (f64, f64) {
    let mut h = GranularHistory::<T>::default();
    let v0 = 0.1;
    let (mut delta, mut vn, mut vt) = (0.0f64, -v0, vt0);
    let e0 = 0.5 * M * (v0 * v0 + vt0.dot(vt0));
    let (mut dissipated, mut touched, mut stored) = (0.0, false, 0.0);
    for _ in 0..10_000_000 {
        let d_new = delta - vn * dt;
        let k = Kin {
            delta: d_new,
            vn,
            vt,
            m_eff: M,
            r_eff: R,
            dt,
        };
        let out = law.force::<true>(&k, &mut h);
        let vn_new = vn + out.f_n / M * dt;
        let vt_new = vt.add_scaled(out.f_t, dt / M);
        let vtm = vt.add_scaled(vt_new, 1.0).scale(0.5);
        dissipated += -out.d_n * 0.5 * (vn + vn_new) * dt - out.d_t.dot(vtm) * dt + out.e_fric;
        touched |= d_new > 0.0;
        // Past the JKR snap-off (reach = 0 for the other laws) the pair is free.
        if touched && d_new < -<GranularLaw as ContactLaw<T>>::reach(law, R) {
            // What the springs still held when the contact broke is lost with it.
            let e1 = 0.5 * M * (vn * vn + vt.dot(vt));
            return (e0 - e1, dissipated + stored);
        }
        stored = out.e_strain;
        delta = d_new;
        vn = vn_new;
        vt = vt_new;
    }
    panic!("the impact did not end");
}

#[test]
fn energy_terms_close_the_balance() {
    let cases = [
        r#"{"normal": {"model": "hooke", "kn": 1e5},
            "damping": {"model": "coeff_restitution", "e": 0.5},
            "tangential": {"model": "linear_history", "kt": 4e4, "mu": 1e9, "xgammat": 0}}"#,
        r#"{"normal": {"model": "hooke", "kn": 1e5},
            "damping": {"model": "none"},
            "tangential": {"model": "linear_history", "kt": 4e4, "mu": 0.1, "xgammat": 0}}"#,
        r#"{"normal": {"model": "hooke", "kn": 1e5},
            "damping": {"model": "coeff_restitution", "e": 0.5},
            "tangential": {"model": "linear_history", "kt": 4e4, "mu": 0.1, "xgammat": 0.5}}"#,
        r#"{"normal": {"model": "hooke", "kn": 1e5},
            "damping": {"model": "mass_velocity", "gamma": 50},
            "tangential": {"model": "linear_nohistory", "gamma_t": 0.5, "mu": 0.1}}"#,
        r#"{"normal": {"model": "walton_braun", "k1": 1e5, "k2": 3e5},
            "tangential": {"model": "linear_history", "kt": 4e4, "mu": 0.2}}"#,
        r#"{"normal": {"model": "hertz/material", "E": 1e8, "nu": 0.3},
            "damping": {"model": "tsuji", "e": 0.6},
            "tangential": {"model": "mindlin/deresiewicz", "mu": 0.2}}"#,
        r#"{"normal": {"model": "jkr", "E": 1e8, "nu": 0.3, "gamma": 0.05},
            "damping": {"model": "viscoelastic", "eta": 1e3},
            "tangential": {"model": "mindlin", "mu": 0.2, "xgammat": 0.3}}"#,
        r#"{"normal": {"model": "hertz/material", "E": 1e8, "nu": 0.3},
            "damping": {"model": "coeff_restitution", "e": 0.7},
            "tangential": {"model": "mindlin_rescale", "mu": 0.2, "xgammat": 0.3}}"#,
        r#"{"normal": {"model": "hertz/material", "E": 1e8, "nu": 0.3},
            "damping": {"model": "tsuji", "e": 0.7},
            "tangential": {"model": "mindlin_rescale/force", "mu": 0.2}}"#,
    ];
    for json in cases {
        let l = law(json);
        let dt = dt_for(3e5);
        for (lost, booked) in [
            energy_balance(&l, 0.08f64, dt),
            energy_balance(&l, Vector3::new(0.05, -0.06, 0.0), dt),
        ] {
            let rel = (lost - booked).abs() / lost;
            println!(
                "{:?} / {:?}: lost {lost:.6e}, booked {booked:.6e}, rel {rel:.1e}",
                l.normal, l.tangential
            );
            assert!(rel < 1e-4, "{rel}");
        }
    }
}

/// Every sub-model gives the same force in 3D along a fixed tangent axis as in 2D.
#[test]
fn the_3d_path_along_one_axis_is_the_2d_path() {
    let ax = Vector3::new(0.0, 0.6, -0.8);
    let tangentials = [
        r#"{"model": "linear_nohistory", "gamma_t": 0.5, "mu": 0.2}"#,
        r#"{"model": "linear_history", "kt": 4e4, "mu": 0.2, "xgammat": 0.3}"#,
        r#"{"model": "mindlin", "mu": 0.2, "xgammat": 0.3}"#,
        r#"{"model": "mindlin/deresiewicz", "mu": 0.2}"#,
        r#"{"model": "mindlin_rescale", "mu": 0.2, "xgammat": 0.3}"#,
        r#"{"model": "mindlin/force", "mu": 0.2, "xgammat": 0.3}"#,
        r#"{"model": "mindlin_rescale/force", "mu": 0.2}"#,
    ];
    let normals = [
        r#"{"model": "hertz/material", "E": 1e8, "nu": 0.3}"#,
        r#"{"model": "jkr", "E": 1e8, "nu": 0.3, "gamma": 0.05}"#,
        r#"{"model": "dmt", "E": 1e8, "nu": 0.3, "gamma": 0.05}"#,
    ];
    for n in normals {
        for t in tangentials {
            let l = law(&format!(
                r#"{{"normal": {n}, "damping": {{"model": "tsuji", "e": 0.5}}, "tangential": {t},
                    "rolling": {{"model": "elastic_plastic", "mu_r": 0.1}}}}"#
            ));
            let mut h2 = GranularHistory::<f64>::default();
            let mut h3 = GranularHistory::<Vector3<f64>>::default();
            for i in 0..400 {
                let s = i as f64 / 400.0;
                let delta = 2e-6 * (std::f64::consts::PI * s).sin();
                let vt = (6.0 * s).cos() * 0.05;
                let (vn, dt) = (-1e-3 * (std::f64::consts::PI * s).cos(), 1e-6);
                let k2 = Kin {
                    delta,
                    vn,
                    vt,
                    m_eff: M,
                    r_eff: R,
                    dt,
                };
                let k3 = Kin {
                    delta,
                    vn,
                    vt: ax * vt,
                    m_eff: M,
                    r_eff: R,
                    dt,
                };
                let a = l.force::<true>(&k2, &mut h2);
                let b = l.force::<true>(&k3, &mut h3);
                assert_eq!(a.f_n, b.f_n);
                let tol = 1e-12 * a.f_t.abs().max(1e-9);
                assert!(
                    (b.f_t - ax * a.f_t).norm() <= tol,
                    "{n} {t} step {i}: {a:?} {b:?}"
                );
                assert!((a.e_strain - b.e_strain).abs() <= 1e-12 * a.e_strain.abs().max(1e-15));
                let (m2, _) = l.roll(&k2, a.f_n, 3.0, &mut h2);
                let (m3, _) = l.roll(&k3, b.f_n, ax * 3.0, &mut h3);
                assert!((m3 - ax * m2).norm() <= 1e-12 * m2.abs().max(1e-15));
            }
        }
    }
}

#[test]
fn limit_damping_clips_the_linear_dashpot() {
    let json = |limit: bool| {
        format!(
            r#"{{"normal": {{"model": "hooke", "kn": 1e5}},
                "damping": {{"model": "coeff_restitution", "e": 0.3}},
                "tangential": {{"model": "linear_nohistory", "gamma_t": 0, "mu": 0.3}},
                "limit_damping": {limit}}}"#
        )
    };
    let free = restitution_rk4(&law(&json(false)), 0.1, 0.0f64, dt_for(1e5));
    let clipped = restitution_rk4(&law(&json(true)), 0.1, 0.0f64, dt_for(1e5));
    println!("hooke e = 0.3: unclipped {free:.6}, limit_damping {clipped:.6}");
    assert!((free - 0.3).abs() < 1e-7);
    // Clipped, the pair leaves once the force reaches 0, before δ = 0, faster.
    assert!(clipped > free + 0.01);
    // The clipped force is never attractive.
    let l = law(&json(true));
    let mut h = GranularHistory::<f64>::default();
    let k = Kin {
        delta: 1e-8,
        vn: 1.0,
        vt: 0.0,
        m_eff: M,
        r_eff: R,
        dt: 1e-7,
    };
    assert_eq!(l.force::<true>(&k, &mut h).f_n, 0.0);
}

/// An undamped JKR impact loses exactly the work of the neck from δ = 0 to the snap-off at
/// δ_c: e = √(1 − 2W/(m* v0²)), W = −∫_{δc}^0 F dδ (the loading and unloading above δ = 0
/// are elastic; the snap-in at δ = 0 costs nothing, the stored energy being 0 there).
#[test]
fn jkr_impact_loses_the_neck_work() {
    let json = r#"{"normal": {"model": "jkr", "E": 7e10, "nu": 0.33, "gamma": 0.5},
                   "tangential": {"model": "linear_history", "kt": 4e4, "mu": 1e9}}"#;
    let l = law(json);
    let e_star = l.normal.material().unwrap().e_star;
    let g = 0.5;
    let dc = dem_laws::jkr_critical_overlap(e_star, g, R);
    // W by Simpson's rule on the stable branch.
    let n = 20_000;
    let hs = -dc / n as f64;
    let mut w = 0.0;
    for i in 0..=n {
        let d = dc + i as f64 * hs;
        let a = dem_laws::jkr_contact_radius(e_star, g, R, d).unwrap();
        let c = if i == 0 || i == n {
            1.0
        } else if i % 2 == 1 {
            4.0
        } else {
            2.0
        };
        w -= c * dem_laws::jkr_force_of_radius(e_star, g, R, a);
    }
    w *= hs / 3.0;
    for v0 in [1e-3f64, 3e-3] {
        let e_th = (1.0 - 2.0 * w / (M * v0 * v0)).sqrt();
        let reach = <GranularLaw as ContactLaw<f64>>::reach(&l, R);
        let dt = dt_for(4e5) / 4.0;
        let mut h = GranularHistory::<f64>::default();
        let (mut delta, mut vn) = (0.0f64, -v0);
        let mut touched = false;
        let e = loop {
            let d_new = delta - vn * dt;
            let k = Kin {
                delta: d_new,
                vn,
                vt: 0.0,
                m_eff: M,
                r_eff: R,
                dt,
            };
            let out = l.force::<false>(&k, &mut h);
            touched |= d_new > 0.0;
            if touched && d_new < -reach {
                break vn / v0;
            }
            vn += out.f_n / M * dt;
            delta = d_new;
        };
        println!("JKR v0 = {v0}: e = {e:.6}, √(1 − 2W/mv²) = {e_th:.6}");
        assert!((e - e_th).abs() < 2e-5, "{e} vs {e_th}");
    }
}

/// Pure normal unloading at v_t = 0 from a₀ to a₁: F_t ∝ a (mindlin), ∝ a² (mindlin_rescale),
/// constant (mindlin/force), ∝ a (mindlin_rescale/force).
#[test]
fn mindlin_variants_under_normal_unloading() {
    for (name, power) in [
        ("mindlin", 1),
        ("mindlin_rescale", 2),
        ("mindlin/force", 0),
        ("mindlin_rescale/force", 1),
    ] {
        let l = law(&format!(
            r#"{{"normal": {{"model": "hertz/material", "E": 1e8, "nu": 0.3}},
                "tangential": {{"model": "{name}", "mu": 1e9}}}}"#
        ));
        let mut h = GranularHistory::<Vector3<f64>>::default();
        let kin = |delta: f64, vt: f64| Kin {
            delta,
            vn: 0.0,
            vt: Vector3::new(vt, 0.0, 0.0),
            m_eff: M,
            r_eff: R,
            dt: 1e-6,
        };
        let (d0, d1) = (4e-6, 1e-6);
        let f0 = l.force::<false>(&kin(d0, 1e-3), &mut h).f_t.x;
        let mut f1 = 0.0;
        for i in 1..=100 {
            f1 = l
                .force::<false>(&kin(d0 + (d1 - d0) * i as f64 / 100.0, 0.0), &mut h)
                .f_t
                .x;
        }
        let ratio = (d1 / d0).sqrt(); // a₁/a₀
        let want = f0 * ratio.powi(power);
        assert!(
            (f1 - want).abs() < 1e-12 * want.abs(),
            "{name}: {f1} vs {want}"
        );
    }
}
