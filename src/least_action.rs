//! Geodesics of the Jacobi metric by direct minimisation (SPEC M12) [Ardema 4.5, eqs. 4.38–4.44]:
//! the path of energy `h` between two fixed configurations `q_A`, `q_B` as the minimiser of the
//! discretised Jacobi energy over the interior nodes, with `argmin`'s L-BFGS and gradients by AD.
//!
//! With nodes `q_0 = q_A, q_1, …, q_n = q_B` at equal steps `1/n` of a parameter `λ ∈ [0, 1]` and
//! midpoints `q̄_k = ½(q_k + q_{k+1})`, the discrete energy and length are
//!
//! ```math
//! E_n = n \sum_{k=0}^{n-1} G(\bar q_k)(\Delta q_k, \Delta q_k),\qquad
//! \ell_n = \sum_{k=0}^{n-1} \sqrt{G(\bar q_k)(\Delta q_k, \Delta q_k)} ,
//! ```
//!
//! `G = 2(h − V) a` the Jacobi metric ([`jacobi_metric`](crate::action::jacobi_metric)). The
//! continuous energy `∫ G(q′, q′) dλ ≥ (∫ √G(q′, q′) dλ)²` is least, with equality, on the
//! geodesics at constant speed, so its minimisers are the length-minimising paths of Jacobi's
//! principle parametrised proportionally to the Jacobi length, i.e. to the Maupertuis action
//! `∫ 2T dt` along the motion. The midpoint rule makes the nodes second-order accurate in `1/n`.
//! A minimiser exists where the straight start lies in a convex part of the region `V < h` free
//! of conjugate points (short arcs); the path must stay in `V < h`.

use crate::action::Metric;
use crate::ad::{phase_gradient, PhaseDual};
use crate::error::{all_finite, Error, Result};
use crate::lagrangian::NaturalSystem;
use argmin::core::{CostFunction, Executor, Gradient, State, TerminationReason, TerminationStatus};
use argmin::solver::linesearch::MoreThuenteLineSearch;
use argmin::solver::quasinewton::LBFGS;
use nalgebra::{DVector, SVector};

/// A geodesic of the Jacobi metric from [`jacobi_geodesic`].
#[derive(Clone, Debug, PartialEq)]
pub struct Geodesic<const N: usize> {
    /// The nodes `q_0 = q_A, …, q_n = q_B`.
    pub nodes: Vec<SVector<f64, N>>,
    /// The discrete Jacobi length `ℓ_n` (module docs), the Maupertuis action `∫ 2T dt` of the
    /// motion to second order in `1/n`.
    pub length: f64,
    /// The discrete energy `E_n` at the minimum.
    pub energy: f64,
    /// L-BFGS iterations.
    pub iterations: u64,
    /// The Euclidean norm of the gradient of `E_n` at the returned nodes.
    pub gradient: f64,
}

/// The discrete Jacobi energy over the interior nodes (flattened, `N` per node).
struct JacobiEnergy<'a, S, const N: usize> {
    metric: &'a Metric<S, N>,
    start: SVector<f64, N>,
    end: SVector<f64, N>,
    segments: usize,
}

impl<S: NaturalSystem<N>, const N: usize> JacobiEnergy<'_, S, N> {
    fn node(&self, x: &DVector<f64>, k: usize) -> SVector<f64, N> {
        if k == 0 {
            self.start
        } else if k == self.segments {
            self.end
        } else {
            SVector::from_fn(|i, _| x[(k - 1) * N + i])
        }
    }

    /// `G(q̄)(Δq, Δq)` of one segment and its gradients with respect to both ends.
    fn segment(
        &self,
        a: &SVector<f64, N>,
        b: &SVector<f64, N>,
    ) -> (f64, SVector<f64, N>, SVector<f64, N>) {
        phase_gradient(
            |a: &SVector<PhaseDual<f64, f64, _>, N>, b: &SVector<PhaseDual<f64, f64, _>, N>| {
                let mid = (a + b) * PhaseDual::from_re(0.5);
                let d = b - a;
                self.metric.squared_norm(&mid, &d)
            },
            a,
            b,
        )
    }

    /// `(E_n, ∇E_n)`; `Err` where a midpoint leaves the region of motion.
    fn value_and_gradient(&self, x: &DVector<f64>) -> Result<(f64, DVector<f64>)> {
        let n = self.segments as f64;
        let mut e = 0.0;
        let mut g = DVector::zeros(x.len());
        for k in 0..self.segments {
            let (a, b) = (self.node(x, k), self.node(x, k + 1));
            self.metric.checked_conformal_factor(&((a + b) * 0.5))?;
            let (v, ga, gb) = self.segment(&a, &b);
            e += n * v;
            for i in 0..N {
                if k > 0 {
                    g[(k - 1) * N + i] += n * ga[i];
                }
                if k + 1 < self.segments {
                    g[k * N + i] += n * gb[i];
                }
            }
        }
        all_finite("gradient of the discrete Jacobi energy", g.as_slice())?;
        Ok((crate::error::finite("discrete Jacobi energy", e)?, g))
    }
}

impl<S: NaturalSystem<N>, const N: usize> CostFunction for JacobiEnergy<'_, S, N> {
    type Param = DVector<f64>;
    type Output = f64;
    fn cost(&self, x: &DVector<f64>) -> std::result::Result<f64, argmin::core::Error> {
        Ok(self.value_and_gradient(x)?.0)
    }
}

impl<S: NaturalSystem<N>, const N: usize> Gradient for JacobiEnergy<'_, S, N> {
    type Param = DVector<f64>;
    type Gradient = DVector<f64>;
    fn gradient(&self, x: &DVector<f64>) -> std::result::Result<DVector<f64>, argmin::core::Error> {
        Ok(self.value_and_gradient(x)?.1)
    }
}

/// The geodesic of the Jacobi metric `metric` from `start` to `end` with `segments` segments,
/// by L-BFGS on the discrete Jacobi energy (module docs) from the straight path, to a gradient
/// norm of `√(nε)` relative to the energy of the straight path (at most 10⁴ iterations).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ in the ends; [`Error::InvalidInput`] for `segments` outside
/// `2..=10_000`; [`Error::OutOfDomain`] for an end outside the region of motion `V < h`;
/// [`Error::NotConverged`] when the minimisation fails, leaves the region of motion, or stops
/// with a gradient above its tolerance.
pub fn jacobi_geodesic<S: NaturalSystem<N>, const N: usize>(
    metric: &Metric<S, N>,
    start: &SVector<f64, N>,
    end: &SVector<f64, N>,
    segments: usize,
) -> Result<Geodesic<N>> {
    if !(2..=10_000).contains(&segments) {
        return Err(Error::invalid(
            "segments",
            format!("{segments}: expected 2 to 10000"),
        ));
    }
    metric.checked_conformal_factor(start)?;
    metric.checked_conformal_factor(end)?;
    let problem = JacobiEnergy {
        metric,
        start: *start,
        end: *end,
        segments,
    };
    let x0 = DVector::from_iterator(
        (segments - 1) * N,
        (1..segments).flat_map(|k| {
            let s = k as f64 / segments as f64;
            (start * (1.0 - s) + end * s)
                .iter()
                .copied()
                .collect::<Vec<_>>()
        }),
    );
    let (e0, _) = problem.value_and_gradient(&x0)?;
    let scale = e0.abs().max(f64::MIN_POSITIVE);
    // Stopping rule: ‖∇E_n‖₂ ≤ √(nε)·E_n(x₀). A step of size |g|/λ_max, λ_max ≈ 4n·E_n the
    // largest Hessian eigenvalue, changes E_n by g²/λ_max, which must exceed the rounding ε·E_n
    // of E_n for the line search to see it: below √(4nε)·E_n the energies cannot be compared.
    // The node error the rule leaves is ≲ ‖H⁻¹‖·|g| ≈ n·|g|/(π²E_n), λ_min ≈ π²E_n/n, i.e.
    // ≲ n^{3/2}√ε/π², far below the O(n⁻²) discretisation error for the n of interest. A run
    // that stalls at rounding level is accepted up to 10²·tolerance.
    let tolerance = (segments as f64 * f64::EPSILON).sqrt() * scale;
    let stall = 16.0 * f64::EPSILON * scale;
    let mut x = x0;
    let mut iterations = 0_u64;
    let mut status = String::from("not started");
    // L-BFGS restarted every `CHUNK` iterations from its best point, so that a line search that
    // fails at rounding level (or steps out of the region `V < h`) ends the minimisation at the
    // last accepted point instead of losing it.
    const CHUNK: u64 = 200;
    while iterations < 10_000 {
        let solver = LBFGS::new(MoreThuenteLineSearch::new(), 12)
            .with_tolerance_grad(tolerance)
            .and_then(|s| s.with_tolerance_cost(stall))
            .map_err(|e| not_converged(format!("L-BFGS set-up: {e}"), 0, f64::NAN))?;
        let run = Executor::new(
            JacobiEnergy {
                metric,
                start: *start,
                end: *end,
                segments,
            },
            solver,
        )
        .configure(|s| s.param(x.clone()).max_iters(CHUNK))
        .run();
        let res = match run {
            Ok(res) => res,
            Err(e) => {
                status = format!("line search failed: {e}");
                break;
            }
        };
        let state = res.state();
        iterations += state.get_iter();
        if let Some(best) = state.get_best_param() {
            x = best.clone();
        }
        status = format!("{:?}", state.get_termination_status());
        if !matches!(
            state.get_termination_status(),
            TerminationStatus::Terminated(TerminationReason::MaxItersReached)
        ) {
            break;
        }
    }
    let (energy, g) = problem.value_and_gradient(&x)?;
    let gradient = g.norm();
    if gradient > 1e2 * tolerance {
        return Err(not_converged(
            format!("L-BFGS on the discrete Jacobi energy ({status})"),
            iterations as usize,
            gradient,
        ));
    }
    let nodes: Vec<SVector<f64, N>> = (0..=segments).map(|k| problem.node(&x, k)).collect();
    let length = nodes
        .windows(2)
        .map(|w| {
            metric
                .squared_norm(&((w[0] + w[1]) * 0.5), &(w[1] - w[0]))
                .sqrt()
        })
        .sum();
    Ok(Geodesic {
        nodes,
        length,
        energy,
        iterations,
        gradient,
    })
}

fn not_converged(what: String, iterations: usize, residual: f64) -> Error {
    Error::NotConverged {
        what,
        iterations,
        residual,
    }
}
