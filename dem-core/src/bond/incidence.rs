//! Bond incidence by disc (compressed rows): for every disc, the bonds it belongs to in
//! increasing bond order, each with the side (i or j) the disc is on. The parallel bond stage
//! ([`super::split`]) uses it to add the contributions of the discs shared by several ranges
//! in bond order, exactly the sequence of additions of the one-thread scatter (which walks
//! the bonds in order and adds to i, then to j), so the bits are the same for any split.

use super::kernel::INTACT;

/// For disc k, entries `start[k]..start[k + 1]` of `entry`: `bond << 1 | side` (side 0: the
/// disc is the bond's i, 1: its j), increasing in bond order.
#[derive(Clone, Debug, Default)]
pub(super) struct Incidence {
    start: Vec<u32>,
    entry: Vec<u32>,
}

impl Incidence {
    /// Build for `n` discs (every index in `i` and `j` must be below `n`).
    pub fn new(i: &[u32], j: &[u32], n: usize) -> Incidence {
        let mut start = vec![0u32; n + 1];
        for &k in i.iter().chain(j) {
            start[k as usize + 1] += 1;
        }
        for k in 0..n {
            start[k + 1] += start[k];
        }
        let mut fill = start.clone();
        let mut entry = vec![0u32; i.len() + j.len()];
        // Bonds in order: each disc's entries come out increasing.
        for (b, (&a, &c)) in i.iter().zip(j).enumerate() {
            for (k, side) in [(a, 0), (c, 1)] {
                let f = &mut fill[k as usize];
                entry[*f as usize] = (b as u32) << 1 | side;
                *f += 1;
            }
        }
        Incidence { start, entry }
    }

    /// Number of discs it was built for.
    pub fn discs(&self) -> usize {
        self.start.len().saturating_sub(1)
    }

    /// Add to each disc of `discs` the contributions `o[b]` = (f_x, f_y, t_i, t_j) of its
    /// intact bonds (`status[b]` = [`INTACT`]): −(f_x, f_y) and +t_i when it is the bond's i,
    /// +(f_x, f_y) and +t_j when its j, in bond order: the additions the one-thread scatter
    /// (which walks the bonds in order and adds to i, then to j) makes to that disc. `fx`,
    /// `fy`, `tq` have [`Incidence::discs`] entries.
    pub fn add(
        &self,
        discs: &[u32],
        o: &[[f64; 4]],
        status: &[u8],
        fx: &mut [f64],
        fy: &mut [f64],
        tq: &mut [f64],
    ) {
        let n = self.discs();
        assert!(fx.len() == n && fy.len() == n && tq.len() == n);
        for &k in discs {
            let k = k as usize;
            let (a, b) = (self.start[k] as usize, self.start[k + 1] as usize);
            for &e in &self.entry[a..b] {
                let q = (e >> 1) as usize;
                if status[q] != INTACT {
                    continue;
                }
                let v = &o[q];
                if e & 1 == 0 {
                    fx[k] -= v[0];
                    fy[k] -= v[1];
                    tq[k] += v[2];
                } else {
                    fx[k] += v[0];
                    fy[k] += v[1];
                    tq[k] += v[3];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::kernel::scatter;
    use super::*;

    /// Adding every disc's contributions makes the additions of the serial bond-order
    /// scatter, bit for bit (one broken bond skipped; values chosen so that the order of
    /// additions changes the rounding); discs left out of the list are left as they are.
    #[test]
    fn adding_by_disc_gives_the_bond_order_scatter_bits() {
        let n = 9000;
        let nb = 3 * n;
        let mut seed = 12345u64;
        let mut rnd = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut i, mut j, mut o, mut status) = (vec![], vec![], vec![], vec![]);
        for b in 0..nb {
            let a = (b / 3) as u32;
            let c = ((a as usize + 1 + (rnd() * 40.0) as usize) % n) as u32;
            i.push(a);
            j.push(c);
            let s = 1e6 * (rnd() - 0.5);
            o.push([s, 1e-3 * rnd(), 3.0 * s, 1e7 * rnd()]);
            status.push(if b == 17 { INTACT + 1 } else { INTACT });
        }
        let base: Vec<f64> = (0..n).map(|_| rnd()).collect();
        // The one-thread path's scatter (`kernel::scatter`), over the bonds in `order`.
        let scatter = |order: &mut dyn Iterator<Item = usize>| {
            let (mut fx, mut fy, mut tq) = (base.clone(), base.clone(), base.clone());
            for b in order.filter(|&b| status[b] == INTACT) {
                let (a, c) = (i[b] as usize, j[b] as usize);
                scatter(&mut fx, &mut fy, &mut tq, a, c, &o[b]);
            }
            (fx, fy, tq)
        };
        let (sx, sy, st) = scatter(&mut (0..nb));
        let inc = Incidence::new(&i, &j, n);
        let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        let all: Vec<u32> = (0..n as u32).collect();
        let (mut gx, mut gy, mut gt) = (base.clone(), base.clone(), base.clone());
        inc.add(&all, &o, &status, &mut gx, &mut gy, &mut gt);
        assert_eq!(bits(&gx), bits(&sx));
        assert_eq!(bits(&gy), bits(&sy));
        assert_eq!(bits(&gt), bits(&st));
        let odd: Vec<u32> = (1..n as u32).step_by(2).collect();
        let (mut hx, mut hy, mut ht) = (base.clone(), base.clone(), base.clone());
        inc.add(&odd, &o, &status, &mut hx, &mut hy, &mut ht);
        for k in 0..n {
            let want = if k % 2 == 1 {
                [sx[k], sy[k], st[k]]
            } else {
                [base[k]; 3]
            };
            assert_eq!(
                [hx[k], hy[k], ht[k]].map(f64::to_bits),
                want.map(f64::to_bits)
            );
        }
        // And the order matters for these values (else the test would prove nothing).
        let (rx, ry, rt) = scatter(&mut (0..nb).rev());
        assert!(rx != sx || ry != sy || rt != st);
    }
}
