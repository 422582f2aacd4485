//! Order reduction with the energy integral: Whittaker's method
//! [Ardema 15.6, eqs. 15.31–15.36].
//!
//! For an autonomous, conservative Hamiltonian the energy integral `H(q, p) = h` is solved for one
//! coordinate,
//!
//! ```math
//! q_i = \varphi(q_{r \ne i},\, p_1 \dots p_N;\, h),
//! ```
//!
//! and the conjugate momentum `p_i` is taken as the independent variable. Dividing Hamilton's
//! equations by `ṗ_i = −∂H/∂q_i` and using the implicit-function derivatives
//! `∂φ/∂x = −(∂H/∂x)/(∂H/∂q_i)` gives a Hamiltonian system of `N − 1` degrees of freedom in which
//! `φ` plays the role of the Hamiltonian and `p_i` that of time:
//!
//! ```math
//! \frac{dq_r}{dp_i} = \frac{\partial\varphi}{\partial p_r},\qquad
//! \frac{dp_r}{dp_i} = -\frac{\partial\varphi}{\partial q_r},\qquad r \ne i,
//! ```
//!
//! while the time follows by one quadrature of
//!
//! ```math
//! \frac{dt}{dp_i} = \frac{1}{\dot p_i} = -\frac{1}{\partial H/\partial q_i}.
//! ```
//!
//! The reduction is singular where `∂H/∂q_i = 0` (a fold of the energy surface over the remaining
//! variables, i.e. where `p_i` stops being monotonic in time); there every method of
//! [`Whittaker`] returns [`Error::Singular`].
//!
//! States keep all `N` slots: the reduced variables sit in the slots `r ≠ i`; the slot `q_i` carries
//! the eliminated coordinate (on input, the starting guess of the Newton solve for `φ`) and the slot
//! `p_i` the independent variable.

use crate::ad::lift;
use crate::error::{all_finite, finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::implicit::{lift_scalar_root, newton_converged};
use crate::phase::check_phase;
use nalgebra::SVector;
use num_dual::{first_derivative, second_derivative, Dual, Dual2, DualNum};

const MAX_ITER: usize = 60;

/// Whittaker's reduction of an autonomous Hamiltonian on the energy surface `H = h`, eliminating the
/// coordinate `q_i` and taking its conjugate momentum `p_i` as the independent variable (see the
/// [module docs](self)).
///
/// # Example
/// ```
/// use hamilton_jacobi::hamiltonian;
/// use hamilton_jacobi::hamilton_jacobi::Whittaker;
/// use hamilton_jacobi::nalgebra::SVector;
/// // H = ½(p_x² + p_y²) + g x + ½ k² y² [Ardema 15.6], g = 2, k = 3.
/// hamiltonian!(Fall<2> |_s, _t, q, p| p.dot(p) * 0.5 + q[0] * 2.0 + q[1] * q[1] * 4.5);
/// let w = Whittaker::new(Fall, 10.0, 0).unwrap();
/// let (q, p) = (SVector::from([0.0, 0.5]), SVector::from([0.4, -0.3]));
/// // x = φ = (h − ½|p|² − ½k²y²)/g
/// let x = w.eliminated_coordinate(&q, &p).unwrap();
/// assert!((x - (10.0 - 0.125 - 1.125) / 2.0).abs() < 1e-15);
/// let rates = w.reduced_field(&q, &p).unwrap();
/// assert!((rates.dq[1] - 0.3 / 2.0).abs() < 1e-15);      // dy/dp_x = ∂φ/∂p_y = −p_y/g
/// assert!((rates.dp[1] - 9.0 * 0.5 / 2.0).abs() < 1e-15); // dp_y/dp_x = −∂φ/∂y = k² y/g
/// assert!((rates.dt + 0.5).abs() < 1e-15);                 // dt/dp_x = −1/g
/// ```
#[derive(Clone, Debug)]
pub struct Whittaker<H, const N: usize> {
    hamiltonian: H,
    energy: f64,
    index: usize,
}

/// Rates of the reduced system with respect to the independent momentum `p_i`, in all `N` slots.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReducedRates<const N: usize> {
    /// `dq/dp_i`: `∂φ/∂p_r` for `r ≠ i`; in slot `i` the rate `q̇_i/ṗ_i = −(∂H/∂p_i)/(∂H/∂q_i)` of the
    /// eliminated coordinate along the motion (so that integrating all slots carries a consistent
    /// `q_i`, the starting guess for the next solve).
    pub dq: SVector<f64, N>,
    /// `dp/dp_i`: `−∂φ/∂q_r` for `r ≠ i`, and `1` in slot `i`.
    pub dp: SVector<f64, N>,
    /// `dt/dp_i = −1/(∂H/∂q_i)`.
    pub dt: f64,
    /// The eliminated coordinate `q_i = φ` at the point.
    pub eliminated: f64,
}

impl<H: Hamiltonian<N>, const N: usize> Whittaker<H, N> {
    /// The reduction of `hamiltonian` on the energy surface `H = energy`, eliminating `q_index` and
    /// taking `p_index` as the independent variable (`index` counts from 0).
    ///
    /// [`Error::OutOfDomain`] for `index ≥ N`, [`Error::NonFinite`] for a non-finite energy.
    pub fn new(hamiltonian: H, energy: f64, index: usize) -> Result<Self> {
        finite("energy h", energy)?;
        if index >= N {
            return Err(Error::out_of_domain(
                "eliminated coordinate index",
                index as f64,
                format!("{{0, …, {}}}", N.saturating_sub(1)),
            ));
        }
        Ok(Self {
            hamiltonian,
            energy,
            index,
        })
    }

    /// The energy `h`.
    pub fn energy(&self) -> f64 {
        self.energy
    }

    /// The index `i` of the eliminated coordinate and of the independent momentum.
    pub fn index(&self) -> usize {
        self.index
    }

    /// The full Hamiltonian.
    pub fn hamiltonian(&self) -> &H {
        &self.hamiltonian
    }

    /// The eliminated coordinate `q_i = φ(q_{r≠i}, p; h)` solving `H = h` by Newton's method with
    /// the AD derivative `∂H/∂q_i`, started from `q[i]` (the guess; the root nearest to it along
    /// the Newton path is returned, which selects the branch).
    ///
    /// `H` is evaluated at `t = 0`. Errors: [`Error::NonFinite`] for NaN/∞ input;
    /// [`Error::InvalidInput`] if the Hamiltonian has non-conservative forces or `∂H/∂t ≠ 0` at the
    /// point (no energy integral); [`Error::Singular`] if
    /// `∂H/∂q_i` vanishes at the root (see [`Whittaker::reduced_field`]);
    /// [`Error::NotConverged`] if Newton fails (e.g. no root on this branch).
    pub fn eliminated_coordinate(&self, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<f64> {
        self.solve(q, p).map(|(u, _)| u)
    }

    /// The reduced vector field `(dq_r/dp_i, dp_r/dp_i) = (∂φ/∂p_r, −∂φ/∂q_r)` and the time rate
    /// `dt/dp_i = −1/(∂H/∂q_i)` at the point of the energy surface above `(q_{r≠i}, p)`.
    ///
    /// The derivatives of `φ` are those of the implicit function,
    /// `∂φ/∂x = −(∂H/∂x)/(∂H/∂q_i)` [Ardema eqs. 15.33–15.35], from one AD gradient of `H` at the
    /// root. [`Error::Singular`] where `∂H/∂q_i = 0`: at a simple zero of `∂H/∂q_i` the energy surface
    /// folds over the reduced variables, `p_i` is stationary in time and the rates are infinite. A
    /// root is declared singular when `∂H/∂q_i` is zero to rounding relative to `∇H`, or when the
    /// rounding-level residual cannot separate it from a fold (Kantorovich's condition
    /// `2 |∂²H/∂q_i²| · 4ε·scale < (∂H/∂q_i)² / 16` fails).
    pub fn reduced_field(
        &self,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<ReducedRates<N>> {
        let (u, hqi) = self.solve(q, p)?;
        let i = self.index;
        let mut qs = *q;
        qs[i] = u;
        let (_, hq, hp) = self.hamiltonian.gradient(0.0, &qs, p);
        let mut dq = hp / -hqi;
        let mut dp = hq / hqi;
        dq[i] = -hp[i] / hqi;
        dp[i] = 1.0;
        let dt = -1.0 / hqi;
        all_finite("dq/dp_i", dq.as_slice())?;
        all_finite("dp/dp_i", dp.as_slice())?;
        Ok(ReducedRates {
            dq,
            dp,
            dt: finite("dt/dp_i", dt)?,
            eliminated: u,
        })
    }

    /// Time rate `dt/dp_i = 1/ṗ_i = −1/(∂H/∂q_i)` on the energy surface; integrated over `p_i` it
    /// recovers `t` [Ardema eq. 15.36].
    pub fn time_rate(&self, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<f64> {
        let (_, hqi) = self.solve(q, p)?;
        finite("dt/dp_i", -1.0 / hqi)
    }

    /// The full phase point `(q, p)` on the energy surface: `q` with slot `i` replaced by `φ`.
    pub fn lift(
        &self,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        let mut qs = *q;
        qs[self.index] = self.eliminated_coordinate(q, p)?;
        Ok((qs, *p))
    }

    /// The reduced system as a [`Hamiltonian`] in its own right: `K(τ, q, p) = φ(q_{r≠i}, p_{r≠i},
    /// p_i = τ; h)` with the "time" `τ = p_i`. Its Hamilton's equations in the slots `r ≠ i` are the
    /// reduced equations; the slots `(q_i, p_i)` are inert (their rates vanish, and the value in
    /// slot `q_i` only serves as the Newton guess). All the crate's machinery (brackets, tangent
    /// maps, canonicity certificates) applies to it; its derivatives come from `φ` evaluated in
    /// dual numbers by implicit AD (the real root, then frozen-derivative Newton steps in the dual
    /// type, exact to every order carried — see [`crate::implicit`]).
    pub fn reduced_hamiltonian(&self) -> ReducedHamiltonian<'_, H, N> {
        ReducedHamiltonian(self)
    }

    /// Reject time-dependent or non-conservative Hamiltonians at the point (`H` is evaluated at
    /// `t = 0`).
    fn check_autonomous(&self, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<()> {
        if self.hamiltonian.generalized_force(0.0, q, p).is_some() {
            return Err(Error::invalid(
                "Hamiltonian",
                "has non-conservative forces: there is no energy integral to reduce with",
            ));
        }
        let ht = self.hamiltonian.partial_t(0.0, q, p)?;
        if ht != 0.0 {
            return Err(Error::invalid(
                "Hamiltonian",
                format!("depends on time (∂H/∂t = {ht:e}): there is no energy integral"),
            ));
        }
        Ok(())
    }

    /// Newton on `H(q with q_i = u, p) − h = 0` from `u = q[i]`; returns `(u, ∂H/∂q_i)` at the root.
    fn solve(&self, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<(f64, f64)> {
        check_phase(0.0, q, p)?;
        self.check_autonomous(q, p)?;
        let i = self.index;
        let h = self.energy;
        let eval = |u: f64| -> (f64, f64) {
            first_derivative(
                |ud: Dual<f64, f64>| {
                    let mut qd: SVector<Dual<f64, f64>, N> = lift(q);
                    qd[i] = ud;
                    self.hamiltonian.hamiltonian(Dual::from(0.0), &qd, &lift(p))
                },
                u,
            )
        };
        let what = "Whittaker reduction: H = h solved for the eliminated coordinate";
        let mut u = q[i];
        let (mut hv, mut hu) = eval(u);
        let mut previous_step = f64::INFINITY;
        let mut iterations = 0;
        loop {
            let r = hv - h;
            if !r.is_finite() || !hu.is_finite() {
                return Err(Error::NotConverged {
                    what: format!("{what} (H not finite at q_i = {u})"),
                    iterations,
                    residual: r.abs(),
                });
            }
            let scale = h.abs().max(hv.abs());
            if hu == 0.0 {
                if r.abs() <= 4.0 * f64::EPSILON * scale {
                    // At a root: the regularity check below reports the singularity.
                    break;
                }
                // ∂²H/∂q_i² = 0 too: H does not (locally) depend on q_i at all, and H = h cannot
                // be solved for it; otherwise the guess is a stationary point of H in q_i.
                if self.second_partial(q, p, u) == 0.0 {
                    return Err(self.singular(u, q, p, 0.0));
                }
                return Err(Error::NotConverged {
                    what: format!("{what} (∂H/∂q_i = 0 at q_i = {u}, a stationary point of H: start from another guess)"),
                    iterations,
                    residual: r.abs(),
                });
            }
            let du = r / hu;
            if newton_converged(r.abs(), scale, du.abs(), u.abs(), previous_step) {
                let un = u - du;
                let (hn, hun) = eval(un);
                if (hn - h).abs() <= r.abs() && hun.is_finite() {
                    (u, hv, hu) = (un, hn, hun);
                }
                break;
            }
            if iterations >= MAX_ITER {
                return Err(Error::NotConverged {
                    what: what.into(),
                    iterations,
                    residual: r.abs(),
                });
            }
            previous_step = du.abs();
            let mut lambda = 1.0;
            loop {
                let un = u - du * lambda;
                let (hn, hun) = eval(un);
                if (hn - h).is_finite()
                    && hun.is_finite()
                    && ((hn - h).abs() < r.abs() || lambda < 1e-9)
                {
                    (u, hv, hu) = (un, hn, hun);
                    break;
                }
                if lambda < 1e-9 {
                    return Err(Error::NotConverged {
                        what: format!("{what} (every step from q_i = {u} leaves the domain)"),
                        iterations,
                        residual: r.abs(),
                    });
                }
                lambda *= 0.5;
            }
            iterations += 1;
        }
        // Regularity of the root: ∂H/∂q_i against the gradient and against the fold test.
        let mut qs = *q;
        qs[i] = u;
        let (_, hq, hp) = self.hamiltonian.gradient(0.0, &qs, p);
        let grad = hq.amax().max(hp.amax());
        let huu = self.second_partial(q, p, u);
        let scale = h.abs().max(hv.abs());
        let rcond = if grad > 0.0 { hu.abs() / grad } else { 0.0 };
        let fold = hu * hu <= 128.0 * huu.abs() * 4.0 * f64::EPSILON * scale;
        if rcond <= 64.0 * f64::EPSILON || fold {
            return Err(self.singular(u, q, p, rcond));
        }
        Ok((u, hu))
    }

    /// `∂²H/∂q_i²` at `q_i = u` (AD, second-order dual).
    fn second_partial(&self, q: &SVector<f64, N>, p: &SVector<f64, N>, u: f64) -> f64 {
        let i = self.index;
        second_derivative(
            |ud: Dual2<f64, f64>| {
                let mut qd: SVector<Dual2<f64, f64>, N> = lift(q);
                qd[i] = ud;
                self.hamiltonian
                    .hamiltonian(Dual2::from(0.0), &qd, &lift(p))
            },
            u,
        )
        .2
    }

    fn singular(&self, u: f64, q: &SVector<f64, N>, p: &SVector<f64, N>, rcond: f64) -> Error {
        let mut qs = *q;
        qs[self.index] = u;
        Error::Singular {
            what: format!(
                "Whittaker reduction: ∂H/∂q_{} (the energy surface folds over the reduced variables)",
                self.index
            ),
            at: format!("q = {qs:?}, p = {p:?}, h = {}", self.energy),
            rcond,
        }
    }
}

/// The reduced Hamiltonian `K = φ` of a [`Whittaker`] reduction, with the independent momentum as
/// time (see [`Whittaker::reduced_hamiltonian`]). Where the real solve fails it evaluates to NaN;
/// the checked methods of [`Hamiltonian`] then report [`Error::NonFinite`], and
/// [`Whittaker::reduced_field`] gives the cause.
#[derive(Clone, Copy, Debug)]
pub struct ReducedHamiltonian<'a, H, const N: usize>(&'a Whittaker<H, N>);

impl<H: Hamiltonian<N>, const N: usize> Hamiltonian<N> for ReducedHamiltonian<'_, H, N> {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        tau: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> D {
        let w = self.0;
        let i = w.index;
        let nan = || {
            q.iter()
                .chain(p.iter())
                .fold(tau * f64::NAN, |a, &x| a + x * f64::NAN)
        };
        // The slots (q_i, p_i) are inert: p_i is replaced by the time τ, q_i by the root.
        let mut pt = *p;
        pt[i] = tau;
        let qr = q.map(|x| x.re());
        let pr = pt.map(|x| x.re());
        let Ok((u0, hu)) = w.solve(&qr, &pr) else {
            return nan();
        };
        // The root's derivatives by the implicit function theorem; only its derivative parts
        // matter for slot i (the dependence on the inert q_i is dropped).
        lift_scalar_root(u0, hu, |u| {
            let mut qd = *q;
            qd[i] = u;
            w.hamiltonian.hamiltonian(D::from(0.0), &qd, &pt) - w.energy
        })
        .unwrap_or_else(|_| nan())
    }
}
