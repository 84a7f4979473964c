//! Input checks of [`crate::World::try_new`].

use crate::contact::ContactLaws;
use crate::params::Params;
use crate::state::{State, FREE};

/// Bad input to [`crate::World::try_new`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum WorldError {
    #[error("disc {id}: {reason}")]
    Disc { id: u32, reason: String },
    #[error("clump {index}: {reason}")]
    Clump { index: usize, reason: String },
    #[error("material {material} has no contact law (the table has {n} materials)")]
    Material { material: u16, n: usize },
    #[error("periodic box: {0}")]
    Periodic(String),
    #[error("parameters: {0}")]
    Params(String),
    #[error("cannot set the time step: {0}")]
    TimeStep(String),
    #[error("{0}")]
    Restored(String),
}

pub(crate) fn validate(st: &State, p: &Params, laws: &ContactLaws) -> Result<(), WorldError> {
    let d = &st.discs;
    let n = d.len();
    let lens = [
        d.id.len(),
        d.y.len(),
        d.theta.len(),
        d.vx.len(),
        d.vy.len(),
        d.omega.len(),
        d.r.len(),
        d.m.len(),
        d.inertia.len(),
        d.fx.len(),
        d.fy.len(),
        d.torque.len(),
        d.body.len(),
        d.material.len(),
        d.group.len(),
        d.fixed.len(),
    ];
    if lens.iter().any(|&l| l != n) {
        return Err(WorldError::Params(
            "disc arrays have different lengths".into(),
        ));
    }
    let mut seen = vec![false; d.id.iter().map(|&i| i as usize + 1).max().unwrap_or(0)];
    let mut rmax = 0.0f64;
    for i in 0..n {
        let id = d.id[i];
        let bad = |reason: String| Err(WorldError::Disc { id, reason });
        if seen[id as usize] {
            return bad("duplicate id".into());
        }
        seen[id as usize] = true;
        if !(d.r[i] > 0.0 && d.r[i].is_finite()) {
            return bad(format!("radius {} must be positive", d.r[i]));
        }
        if !(d.m[i] > 0.0 && d.m[i].is_finite() && d.inertia[i] > 0.0 && d.inertia[i].is_finite()) {
            return bad(format!(
                "mass {} / inertia {} must be positive",
                d.m[i], d.inertia[i]
            ));
        }
        let vals = [d.x[i], d.y[i], d.theta[i], d.vx[i], d.vy[i], d.omega[i]];
        if vals.iter().any(|v| !v.is_finite()) {
            return bad("non-finite position or velocity".into());
        }
        if !laws.covers(d.material[i]) {
            return Err(WorldError::Material {
                material: d.material[i],
                n: laws.n_materials(),
            });
        }
        if d.body[i] != FREE && d.body[i] as usize >= st.clumps.len() {
            return bad(format!("body {} is not a clump", d.body[i]));
        }
        rmax = rmax.max(d.r[i]);
    }
    for w in &st.walls {
        if !laws.covers(w.material) {
            return Err(WorldError::Material {
                material: w.material,
                n: laws.n_materials(),
            });
        }
    }
    let cl = &st.clumps;
    if !cl.is_empty() && cl.member_start.len() != cl.len() + 1 {
        return Err(WorldError::Clump {
            index: 0,
            reason: "member_start has the wrong length".into(),
        });
    }
    // Every array of one length, member offsets rising to the member count (a checkpoint's
    // clumps arrive as the file has them: found by fuzzing, issue 20).
    let nc = cl.len();
    let per_clump = [
        cl.y.len(),
        cl.theta.len(),
        cl.vx.len(),
        cl.vy.len(),
        cl.omega.len(),
        cl.m.len(),
        cl.inertia.len(),
        cl.fx.len(),
        cl.fy.len(),
        cl.torque.len(),
    ];
    let nm = cl.members.len();
    if per_clump.iter().any(|&l| l != nc)
        || !(cl.template.is_empty() || cl.template.len() == nc)
        || cl.offset_x.len() != nm
        || cl.offset_y.len() != nm
        || (nc > 0
            && (cl.member_start[0] != 0
                || cl.member_start.windows(2).any(|w| w[0] > w[1])
                || cl.member_start[nc] as usize != nm))
    {
        return Err(WorldError::Clump {
            index: 0,
            reason: "clump arrays have different lengths or member offsets that do not fit".into(),
        });
    }
    let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
    if ![
        &cl.x,
        &cl.y,
        &cl.theta,
        &cl.vx,
        &cl.vy,
        &cl.omega,
        &cl.offset_x,
        &cl.offset_y,
    ]
    .iter()
    .all(|v| finite(v))
    {
        return Err(WorldError::Clump {
            index: 0,
            reason: "a clump position, velocity or member offset is not finite".into(),
        });
    }
    for c in 0..cl.len() {
        if !(cl.m[c] > 0.0 && cl.inertia[c] > 0.0) {
            return Err(WorldError::Clump {
                index: c,
                reason: "mass and inertia must be positive".into(),
            });
        }
        for q in cl.member_range(c) {
            let id = cl.members[q] as usize;
            if id >= seen.len() || !seen[id] {
                return Err(WorldError::Clump {
                    index: c,
                    reason: format!("member id {id} is not a disc"),
                });
            }
        }
    }
    if !(st.thickness > 0.0 && st.thickness.is_finite()) {
        return Err(WorldError::Params(format!(
            "thickness {} must be positive",
            st.thickness
        )));
    }
    let skin = p.skin.unwrap_or(0.0);
    if !(skin >= 0.0 && skin.is_finite()) {
        return Err(WorldError::Params(format!("skin {skin} must be ≥ 0")));
    }
    if let Some(dt) = p.dt_fixed {
        if !(dt > 0.0 && dt.is_finite()) {
            return Err(WorldError::Params(format!(
                "dt_fixed {dt} must be positive"
            )));
        }
    } else if !(p.dt_factor > 0.0 && p.dt_factor.is_finite()) {
        return Err(WorldError::Params(format!(
            "dt_factor {} must be positive",
            p.dt_factor
        )));
    }
    if !(p.local_damping >= 0.0 && p.local_damping < 1.0) {
        return Err(WorldError::Params(format!(
            "local_damping {} must be in [0, 1)",
            p.local_damping
        )));
    }
    if !(p.viscous_damping >= 0.0 && p.viscous_damping.is_finite()) {
        return Err(WorldError::Params(format!(
            "viscous_damping {} must be ≥ 0",
            p.viscous_damping
        )));
    }
    for a in 0..2 {
        if let Some(l) = st.periodic.length[a] {
            let need = 2.0 * (2.0 * rmax + p.skin.unwrap_or(0.2 * rmax));
            if !(l.is_finite() && l > need) {
                return Err(WorldError::Periodic(format!(
                    "length {l} on axis {a} must exceed 2 × (largest diameter + skin) = {need}"
                )));
            }
        }
    }
    Ok(())
}
