//! ORC grains: discs merged into one rigid clump (Ashmawy et al. 2003; S0, Ye & Xu 2010) with
//! the ORC mass properties, i.e. the sums over the member discs with overlaps counted as they
//! are (S0: "mass is summed disc by disc, overlaps counted twice"):
//!
//! M = Σ m_i,  x_c = Σ m_i x_i / M,  I_c = Σ (I_i + m_i |x_i − x_c|²)  (parallel-axis theorem),
//!
//! with m_i, I_i = m_i r_i²/2 the member discs' own values. Used by the specimen generator and
//! by scenes that load a specimen file's rigid clumps.

use crate::state::{State, FREE};

/// ORC mass properties of the discs at indices `members`: (mass, centroid, inertia about the
/// centroid).
pub fn orc_props(st: &State, members: &[usize]) -> (f64, [f64; 2], f64) {
    let d = &st.discs;
    let m: f64 = members.iter().map(|&k| d.m[k]).sum();
    let cx = members.iter().map(|&k| d.m[k] * d.x[k]).sum::<f64>() / m;
    let cy = members.iter().map(|&k| d.m[k] * d.y[k]).sum::<f64>() / m;
    let inertia = members
        .iter()
        .map(|&k| {
            let (dx, dy) = (d.x[k] - cx, d.y[k] - cy);
            d.inertia[k] + d.m[k] * (dx * dx + dy * dy)
        })
        .sum();
    (m, [cx, cy], inertia)
}

/// Make the free discs at indices `members` one rigid clump with the ORC properties, at
/// orientation 0 (body frame = current positions about the centroid), moving with the members'
/// total momentum and angular momentum. Returns the clump index, or `None` when `members` is
/// empty, names a disc twice or a disc already in a clump.
pub fn make_rigid_clump(st: &mut State, members: &[usize], name: &str) -> Option<usize> {
    let n = st.discs.len();
    let mut seen = std::collections::HashSet::new();
    if members.is_empty()
        || members
            .iter()
            .any(|&k| k >= n || st.discs.body[k] != FREE || !seen.insert(k))
    {
        return None;
    }
    let (m, [cx, cy], inertia) = orc_props(st, members);
    let d = &st.discs;
    let vx = members.iter().map(|&k| d.m[k] * d.vx[k]).sum::<f64>() / m;
    let vy = members.iter().map(|&k| d.m[k] * d.vy[k]).sum::<f64>() / m;
    let l: f64 = members
        .iter()
        .map(|&k| {
            let (rx, ry) = (d.x[k] - cx, d.y[k] - cy);
            d.inertia[k] * d.omega[k] + d.m[k] * (rx * (d.vy[k] - vy) - ry * (d.vx[k] - vx))
        })
        .sum();
    let omega = l / inertia;
    let cl = &mut st.clumps;
    let c = cl.len();
    if cl.member_start.is_empty() {
        cl.member_start.push(0);
    }
    cl.x.push(cx);
    cl.y.push(cy);
    cl.theta.push(0.0);
    cl.vx.push(vx);
    cl.vy.push(vy);
    cl.omega.push(omega);
    cl.m.push(m);
    cl.inertia.push(inertia);
    cl.fx.push(0.0);
    cl.fy.push(0.0);
    cl.torque.push(0.0);
    cl.template.push(name.to_string());
    let d = &mut st.discs;
    for &k in members {
        let (ox, oy) = (d.x[k] - cx, d.y[k] - cy);
        cl.members.push(d.id[k]);
        cl.offset_x.push(ox);
        cl.offset_y.push(oy);
        d.body[k] = c as u32;
        d.theta[k] = 0.0;
        d.vx[k] = vx - omega * oy;
        d.vy[k] = vy + omega * ox;
        d.omega[k] = omega;
    }
    cl.member_start.push(cl.members.len() as u32);
    Some(c)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn two_discs_clump_has_summed_mass_and_parallel_axis_inertia() {
        let mut st = State::default();
        st.discs.push_uniform(0.0, 0.0, 1.0, 1.0, 1.0, 0);
        st.discs.push_uniform(3.0, 0.0, 2.0, 1.0, 1.0, 0);
        let (m1, m2) = (st.discs.m[0], st.discs.m[1]);
        let c = make_rigid_clump(&mut st, &[0, 1], "g").unwrap();
        let cl = &st.clumps;
        assert_eq!(cl.m[c], m1 + m2);
        let xc = 3.0 * m2 / (m1 + m2);
        assert!((cl.x[c] - xc).abs() < 1e-12);
        let i = 0.5 * m1 + m1 * xc * xc + 0.5 * m2 * 4.0 + m2 * (3.0 - xc).powi(2);
        assert!((cl.inertia[c] - i).abs() < 1e-12 * i);
        assert_eq!(st.discs.body, vec![0, 0]);
        // A disc cannot join two clumps.
        assert!(make_rigid_clump(&mut st, &[1], "h").is_none());
    }
}
