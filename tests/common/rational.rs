//! Exact rational arithmetic on i128 and the pendulum's energy series `h(J)` by reverting the
//! exact action in rationals (an oracle shared by the normal-form tests).

/// Exact rationals on i128 (reduced; every operation checked).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Q(pub i128, pub i128);
pub fn gcd(a: i128, b: i128) -> i128 {
    let (mut a, mut b) = (a.abs(), b.abs());
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a.max(1)
}
impl Q {
    pub fn new(n: i128, d: i128) -> Q {
        let g = gcd(n, d) * d.signum();
        Q(n / g, d / g)
    }
    pub fn int(n: i128) -> Q {
        Q(n, 1)
    }
    pub fn add(self, o: Q) -> Q {
        let g = gcd(self.1, o.1);
        let l = (self.1 / g).checked_mul(o.1).unwrap();
        let n = self
            .0
            .checked_mul(l / self.1)
            .unwrap()
            .checked_add(o.0.checked_mul(l / o.1).unwrap())
            .unwrap();
        Q::new(n, l)
    }
    pub fn neg(self) -> Q {
        Q(-self.0, self.1)
    }
    pub fn mul(self, o: Q) -> Q {
        let g1 = gcd(self.0, o.1);
        let g2 = gcd(o.0, self.1);
        Q::new(
            (self.0 / g1).checked_mul(o.0 / g2).unwrap(),
            (self.1 / g2).checked_mul(o.1 / g1).unwrap(),
        )
    }
    pub fn f64(self) -> f64 {
        self.0 as f64 / self.1 as f64
    }
}
pub fn series_mul(a: &[Q], b: &[Q]) -> Vec<Q> {
    let n = a.len();
    let mut out = vec![Q::int(0); n];
    for i in 0..n {
        for j in 0..n - i {
            out[i + j] = out[i + j].add(a[i].mul(b[j]));
        }
    }
    out
}

/// `h(J) = E + 1` of the pendulum to `J^m`, by reverting the exact action
/// `J = (8/π)[E(k) − (1 − k²)K(k)] = 4 Σ_j (b_j − a_j + a_{j−1}) k^{2j}`, `h = 2k²`,
/// `2K/π = Σ a_j k^{2j}`, `a_j = (C(2j, j)/4^j)²`, `2E/π = Σ b_j k^{2j}`, `b_j = −a_j/(2j − 1)`
/// (DLMF 19.5.1–2), in exact rational arithmetic.
pub fn pendulum_energy_series(m: usize) -> Vec<Q> {
    let mut a = vec![Q::int(1)];
    for j in 1..=m {
        // C(2j, j)/4^j = C(2j−2, j−1)/4^{j−1} · (2j − 1)/(2j)
        let r = Q::new(2 * j as i128 - 1, 2 * j as i128);
        let prev = a[j - 1];
        // a_j = (c_j)², c_j = c_{j−1} r
        a.push(prev.mul(r).mul(r));
    }
    let b: Vec<Q> = (0..=m)
        .map(|j| {
            if j == 0 {
                Q::int(1)
            } else {
                a[j].mul(Q::new(-1, 2 * j as i128 - 1))
            }
        })
        .collect();
    // J(h) = Σ c_j h^j, c_j = 4 (b_j − a_j + a_{j−1}) / 2^j
    let mut c = vec![Q::int(0); m + 1];
    for j in 1..=m {
        c[j] = Q::int(4)
            .mul(b[j].add(a[j].neg()).add(a[j - 1]))
            .mul(Q::new(1, 1i128 << j));
    }
    assert_eq!(c[1], Q::int(1));
    // Reversion h(J) = Σ d_k J^k: [J^k] Σ_j c_j h^j = 0 for k ≥ 2.
    let mut d = vec![Q::int(0); m + 1];
    d[1] = Q::int(1);
    for k in 2..=m {
        let mut pow = d.clone();
        let mut s = Q::int(0);
        for cj in c.iter().take(k + 1).skip(2) {
            pow = series_mul(&pow, &d);
            s = s.add(cj.mul(pow[k]));
        }
        d[k] = s.neg();
    }
    d
}
