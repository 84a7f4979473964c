//! Energy conservation law across a frictional contact that opens: when two discs separate,
//! the contact's tangential spring history is reset, and the elastic energy it held must be
//! booked (as friction dissipation), or the balance E_now + dissipated − E₀ loses it. With a
//! tangential dashpot the spring is left holding the dashpot's force at slip,
//! |k_s u_s| ≈ c_t |v_t|, independent of Δt, so the loss is large and does not vanish with Δt.
//! The slip itself is booked as the energy the reset takes out of the spring,
//! ½ k_s (u₁² − u_slip²); the former f_max |Δu_s| over-counted it when a tangential dashpot
//! acts (the balance error of this impact was 0.16; with the slip booked as the trapezoid
//! ½ k_s (u_old + u_slip)(u₁ − u_slip) and the dashpots booked with mean velocities, 1.8e-4).

use dem_core::contact::{LinearSpringDashpot, NormalDamping};
use dem_core::{ContactLaws, ContactModel, Params, State, World};

#[test]
fn energy_of_tangential_spring_at_opening_is_booked() {
    let r = 0.01;
    let mut st = State::default();
    st.discs.push_uniform(0.0, 0.0, r, 2500.0, 0.01, 0);
    st.discs
        .push_uniform(2.0 * r + 1e-5, 0.002, r, 2500.0, 0.01, 0);
    // Oblique impact: approach at 0.5 m/s, slide at 2 m/s.
    st.discs.vx[1] = -0.5;
    st.discs.vy[1] = 2.0;
    let law = LinearSpringDashpot {
        kn: 1e5,
        ks: 5e4,
        damping: NormalDamping::from_restitution(0.9),
        shear_damping: 1.0,
        mu: 0.3,
    };
    let params = Params {
        reorder_every: 0,
        dt_factor: 0.005,
        ..Params::default()
    };
    let mut w = World::new(st, params, ContactLaws::uniform(ContactModel::Linear(law)));
    let mut touched = false;
    let mut opened = false;
    for _ in 0..20_000 {
        w.step();
        let now = w.contacts().next().is_some();
        touched |= now;
        if touched && !now {
            opened = true;
            break;
        }
    }
    assert!(opened, "the contact must close and open");
    w.run(10);
    let e = w.energy();
    eprintln!("{e:?}");
    // Friction is negative here: the slip resets extend the spring against the dashpot.
    assert!(e.friction != 0.0 && e.damping > 0.0);
    assert!(
        e.balance_error.abs() < 1e-3,
        "balance error {:.3e}",
        e.balance_error
    );
}
