//! Composition and inversion of maps of phase space.
//!
//! Canonical maps form a group: the composition of two canonical maps and the inverse of one are
//! canonical (`(MN)ᵀJ(MN) = Nᵀ(MᵀJM)N = J`). [`Compose`] and [`Inverse`] are again [`PhaseMap`]s,
//! written generically, so their Jacobians — and so their certificates — come from AD.

use crate::ad::{lift, real_parts, real_times};
use crate::brackets::{jacobian, PhaseMap};
use crate::error::{Error, Result};
use crate::implicit::{lift_root, newton_converged};
use crate::phase::check_phase;
use nalgebra::SVector;
use num_dual::DualNum;

/// The composition `second ∘ first` (apply `first`, then `second`, at the same time `t`).
#[derive(Clone, Copy, Debug)]
pub struct Compose<A, B>(pub A, pub B);

impl<A: PhaseMap<N>, B: PhaseMap<N>, const N: usize> PhaseMap<N> for Compose<A, B> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        let (q1, p1) = self.0.apply(t, q, p);
        self.1.apply(t, &q1, &p1)
    }
}

/// The inverse of any invertible map, by Newton's method on `M(z) = w` with the exact AD Jacobian;
/// derivatives of the inverse follow from frozen-Jacobian steps in the dual type
/// ([`lift_root`]). The starting point is `w` itself unless a guess is set.
#[derive(Clone, Copy, Debug)]
pub struct Inverse<M, const N: usize> {
    map: M,
    guess: Option<(SVector<f64, N>, SVector<f64, N>)>,
}

impl<M: PhaseMap<N>, const N: usize> Inverse<M, N> {
    /// The inverse of `map`.
    pub fn new(map: M) -> Self {
        Self { map, guess: None }
    }

    /// Start Newton's method from `(q, p)` instead of the image point (selects a branch).
    pub fn with_guess(mut self, q: SVector<f64, N>, p: SVector<f64, N>) -> Result<Self> {
        check_phase(0.0, &q, &p)?;
        self.guess = Some((q, p));
        Ok(self)
    }

    /// Solve `M(t, z) = (big_q, big_p)` for `z = (q, p)`, in any number type.
    pub fn solve<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        big_q: &SVector<D, N>,
        big_p: &SVector<D, N>,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        const MAX_ITER: usize = 60;
        let tr = t.re();
        let (wq, wp) = (real_parts(big_q), real_parts(big_p));
        let residual = |q: &SVector<f64, N>, p: &SVector<f64, N>| {
            let (a, b) = self.map.apply(tr, q, p);
            (a - wq, b - wp)
        };
        let amax = |a: &SVector<f64, N>, b: &SVector<f64, N>| a.amax().max(b.amax());
        let (mut q, mut p) = self.guess.unwrap_or((wq, wp));
        let (mut rq, mut rp) = residual(&q, &p);
        let mut iterations = 0;
        let mut previous_step = (f64::INFINITY, f64::INFINITY);
        let inv = loop {
            let at = || format!("t = {tr}, q = {q:?}, p = {p:?}");
            if !amax(&rq, &rp).is_finite() {
                return Err(Error::NotConverged {
                    what: format!("inverse map (residual not finite at {})", at()),
                    iterations,
                    residual: f64::NAN,
                });
            }
            let inv = jacobian(&self.map, tr, &q, &p)?
                .checked_inverse("Jacobian of the map to invert", at)?;
            let (dq, dp) = inv.apply(&rq, &rp);
            // Each block (coordinates, momenta) must have converged on its own scale: the two may
            // carry very different units.
            let block_converged = |r: &SVector<f64, N>,
                                   w: &SVector<f64, N>,
                                   d: &SVector<f64, N>,
                                   z: &SVector<f64, N>,
                                   prev: f64| {
                newton_converged(
                    r.amax(),
                    w.amax().max((r + w).amax()),
                    d.amax(),
                    z.amax(),
                    prev,
                )
            };
            if block_converged(&rq, &wq, &dq, &q, previous_step.0)
                && block_converged(&rp, &wp, &dp, &p, previous_step.1)
            {
                let (qn, pn) = (q - dq, p - dp);
                let (aq, ap) = residual(&qn, &pn);
                if aq.amax() <= rq.amax() && ap.amax() <= rp.amax() {
                    (q, p) = (qn, pn);
                }
                break inv;
            }
            if iterations >= MAX_ITER {
                return Err(Error::NotConverged {
                    what: "inverse map".into(),
                    iterations,
                    residual: amax(&rq, &rp),
                });
            }
            previous_step = (dq.amax(), dp.amax());
            let mut lambda = 1.0;
            loop {
                let (qn, pn) = (q - dq * lambda, p - dp * lambda);
                let (aq, ap) = residual(&qn, &pn);
                if amax(&aq, &ap) < amax(&rq, &rp) || lambda < 1e-9 {
                    (q, p, rq, rp) = (qn, pn, aq, ap);
                    break;
                }
                lambda *= 0.5;
            }
            iterations += 1;
        };
        lift_root(
            (lift(&q), lift(&p)),
            |(qd, pd)| {
                let (a, b) = self.map.apply(t, qd, pd);
                Ok((a - big_q, b - big_p))
            },
            |(ra, rb)| {
                (
                    real_times(&inv.qq, ra) + real_times(&inv.qp, rb),
                    real_times(&inv.pq, ra) + real_times(&inv.pp, rb),
                )
            },
        )
    }
}

impl<M: PhaseMap<N>, const N: usize> PhaseMap<N> for Inverse<M, N> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        self.solve(t, q, p).unwrap_or_else(|_| {
            let nan = q.iter().fold(D::from(f64::NAN), |a, &x| a + x * f64::NAN);
            (SVector::from_element(nan), SVector::from_element(nan))
        })
    }
}
