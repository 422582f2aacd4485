//! The truth for the `J₂` theory: DOP853 on `q̈ = −μq/|q|³ − ∇U_{J₂}` in Encke's form, the
//! deviation from the Kepler orbit of a reference state, rectified every [`RECTIFY_EVERY`]
//! samples (shared by tests/j2_theory.rs and examples/j2_theory.rs).
//!
//! Cowell's form (DOP853 on `(q, p)` directly) carries the rounding of the whole orbit; at
//! `rtol = 10⁻¹³` its error after 100 orbits of the `a = 2` problem is `8·10⁻¹⁰` (`e = 0.1`) and
//! `4·10⁻⁸` (`e = 0.7`). The deviation equations carry it relative to the deviation.

use hamilton_jacobi::integrate::{integrate, Dop853, FirstOrderSystem, Problem};
use hamilton_jacobi::nalgebra::Vector3;
use hamilton_jacobi::perturbation::forces::J2;
use hamilton_jacobi::perturbation::variation::{GradientForce, MomentumForce};
use hamilton_jacobi::systems::kepler::drift;
use hamilton_jacobi::Result;

type V3 = Vector3<f64>;

/// Encke's formulation: the deviation `(δq, δp)` from the Kepler orbit `(q_K, p_K)(t)` of a
/// reference state, `δq̈ = μ(q_K/|q_K|³ − q/|q|³) − ∇U_{J₂}(q)`, `q = q_K + δq`.
struct Encke {
    mu: f64,
    j2: J2,
    q0: V3,
    p0: V3,
}

impl FirstOrderSystem<3> for Encke {
    fn field(&self, t: f64, dq: &V3, dp: &V3) -> Result<(V3, V3)> {
        let (kq, _) = drift(self.mu, &self.q0, &self.p0, t)?;
        let qk = self.q0 + kq;
        let q = qk + dq;
        // μ(q_K/r_K³ − q/r³) = (μ/r³)[((r/r_K)³ − 1) q_K − δq], with
        // (r/r_K)³ − 1 = s(3 + 3s + s²)/((1 + s)^{3/2} + 1), s = δq·(δq + 2q_K)/r_K²
        // (Battin 1999 §8.4): no cancellation, rounding relative to the deviation.
        let rk2 = qk.norm_squared();
        let s = dq.dot(&(dq + qk * 2.0)) / rk2;
        let w = (1.0 + s).powf(1.5);
        let ratio_m1 = s * (3.0 + 3.0 * s + s * s) / (w + 1.0);
        let r3 = rk2 * rk2.sqrt() * w;
        let kepler = (qk * ratio_m1 - dq) * (self.mu / r3);
        let pert = GradientForce(&self.j2).force(t, &q, &V3::zeros());
        Ok((*dp, kepler + pert))
    }
}

/// Samples between two rectifications of the Encke reference.
pub const RECTIFY_EVERY: usize = 8;

/// The positions at `times` (DOP853 at `rtol`, absolute tolerance `rtol·10⁻⁵` on the
/// deviation). The reference is the Kepler orbit of the state at every [`RECTIFY_EVERY`]-th
/// time: each rectification rounds the state (`≈ ε` in the energy, an along-track error
/// `≈ ε n t`), so it is done rarely; between them the deviation is carried across the samples.
pub fn truth(j2: J2, start: (V3, V3), times: &[f64], rtol: f64) -> Vec<V3> {
    let mu = j2.mu();
    let method = Dop853::new(rtol, rtol * 1e-5)
        .unwrap()
        .with_max_steps(10_000_000)
        .unwrap();
    let mut out = vec![start.0];
    let (mut q, mut p) = start;
    for chunk in times.windows(2).collect::<Vec<_>>().chunks(RECTIFY_EVERY) {
        let t0 = chunk[0][0];
        let sys = Encke {
            mu,
            j2,
            q0: q,
            p0: p,
        };
        let (mut dq, mut dp) = (V3::zeros(), V3::zeros());
        for w in chunk {
            let problem = Problem::new(&sys, w[0] - t0, dq, dp, w[1] - t0).unwrap();
            let rep = integrate(&problem, &method, &mut ()).unwrap();
            dq = rep.last.q;
            dp = rep.last.p;
            let (kq, _) = drift(mu, &q, &p, w[1] - t0).unwrap();
            out.push(q + kq + dq);
        }
        let t1 = chunk[chunk.len() - 1][1];
        let (kq, kp) = drift(mu, &q, &p, t1 - t0).unwrap();
        (q, p) = (q + kq + dq, p + kp + dp);
    }
    out
}
