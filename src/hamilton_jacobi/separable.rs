//! Separable conservative systems: the characteristic function as a sum of one-dimensional
//! quadratures, and the motion from Jacobi's theorem [Ardema 17.3–17.5,
//! eqs. 17.34–17.44].
//!
//! A system separates when the Hamilton–Jacobi equation `H(q, ∂K/∂q) = h` has a solution
//! `K = Σ_r K_r(q_r; c)` depending on `N` separation constants `c` (one of them the energy `h`):
//! each momentum is a function of its own coordinate, `p_r² = F_r(q_r; c)`, and
//!
//! ```math
//! K_r = \int \sqrt{F_r(q_r; c)}\\,dq_r, \qquad
//! \frac{\partial K}{\partial c_j} = \sum_r \int \frac{\partial F_r/\partial c_j}{2\sqrt{F_r}}\\,dq_r
//! = \beta_j + \delta_{j,h}\\,t .
//! ```
//!
//! Jacobi's theorem ([Ardema 17.2], `AlphaMomenta` convention, with `t − t₀` absorbed in `β_h`)
//! gives the motion implicitly; [`SeparatedMotion::state_at`] solves these `N` equations for the
//! coordinates. Each coordinate is either
//!
//! * **librating** between turning points (roots of `F_r`): the integrals run through the turning
//!   points in the substitution variable `s_r` of [`Libration`], unwrapped so that each
//!   increase of `s_r` by `π` is one passage between the turning points (the sign of `p_r` flips
//!   at each), or
//! * **ignorable** (`F_r` independent of `q_r`, [Ardema eqs. 17.40–17.44]): `K_r = p_r q_r` with
//!   the constant momentum `p_r = ±√F_r`.
//!
//! The Newton iteration on the unwrapped phases uses the integrands themselves as the Jacobian and
//! starts from the mean rates over a passage, so it reaches any time directly. Rotating
//! coordinates (no turning points, e.g. a pendulum above the separatrix) are not covered.

use super::liouville::LiouvilleSystem;
use crate::ad::gradient;
use crate::error::{all_finite, Error, Result};
use crate::special::turning_points::{interior_point, Factored, Libration, Node, Radicand};
use nalgebra::{SMatrix, SVector};
use num_dual::{Dual64, DualNum};
use std::f64::consts::PI;

/// A conservative system that separates in its coordinates (see the [module docs](self)).
pub trait SeparatedSystem<const N: usize> {
    /// The separated radicand `F_r(q_r; c) = p_r²` of coordinate `r`.
    fn radicand<D: DualNum<f64> + Copy>(&self, r: usize, q_r: D, c: &SVector<D, N>) -> D;
    /// The separation constants `c` of the state `(q, p)`.
    fn constants(&self, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<SVector<f64, N>>;
    /// Which constant is the energy (its conjugate is time). Default 0.
    fn energy_index(&self) -> usize {
        0
    }
    /// Whether coordinate `r` is ignorable (`F_r` does not depend on `q_r`). Default: none.
    fn ignorable(&self, _r: usize) -> bool {
        false
    }
    /// Interval searched for the turning points of coordinate `r` (the motion's own domain, e.g.
    /// `(0, ∞)` for a radius).
    fn search_bounds(&self, r: usize) -> (f64, f64);
}

/// `F_r(·; c)` of one coordinate as a [`Radicand`].
#[derive(Clone, Debug)]
pub struct CoordinateRadicand<S, const N: usize> {
    system: S,
    r: usize,
    c: SVector<f64, N>,
}

impl<S: SeparatedSystem<N>, const N: usize> Radicand for CoordinateRadicand<S, N> {
    fn radicand<D: DualNum<f64> + Copy>(&self, x: D) -> D {
        self.system.radicand(self.r, x, &self.c.map(D::from))
    }
}

/// One coordinate of a [`SeparatedMotion`].
#[derive(Clone, Debug)]
enum Coordinate<S, const N: usize> {
    Librating {
        libration: Libration<Factored<CoordinateRadicand<S, N>>>,
        /// `∫₀^π` of each constant's density over one passage.
        passage: SVector<f64, N>,
    },
    Ignorable {
        /// The constant momentum `p_r`.
        momentum: f64,
        /// `∂p_r/∂c_j = (∂F_r/∂c_j)/(2 p_r)`.
        rates: SVector<f64, N>,
    },
}

/// The motion of a [`SeparatedSystem`] through a given state, by Jacobi's theorem.
#[derive(Clone, Debug)]
pub struct SeparatedMotion<S, const N: usize> {
    system: S,
    constants: SVector<f64, N>,
    beta: SVector<f64, N>,
    coordinates: Vec<Coordinate<S, N>>,
}

impl<S: SeparatedSystem<N> + Clone, const N: usize> SeparatedMotion<S, N> {
    /// The motion through `(q, p)` at time `t₀`: separation constants, turning points of every
    /// librating coordinate, and the elements `β_j = ∂K/∂c_j − δ_{j,h} t₀`.
    pub fn new(system: S, t0: f64, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<Self> {
        all_finite("q", q.as_slice())?;
        all_finite("p", p.as_slice())?;
        let t0 = crate::error::finite("t₀", t0)?;
        let c = system.constants(q, p)?;
        all_finite("separation constants", c.as_slice())?;
        let e = system.energy_index();
        if e >= N {
            return Err(Error::out_of_domain(
                "energy index",
                e as f64,
                format!("0..{N}"),
            ));
        }
        let mut coordinates = Vec::with_capacity(N);
        let mut phases = SVector::<f64, N>::zeros();
        for r in 0..N {
            let rad = CoordinateRadicand {
                system: system.clone(),
                r,
                c,
            };
            // Consistency p_r² = F_r(q_r; c), relative to the size of F's terms: its value, p²,
            // and its sensitivities |q ∂F/∂q| and Σ|c_j ∂F/∂c_j| (F may be a difference of large
            // terms, and is 0 at a turning point).
            let f = rad.radicand(q[r]);
            let (_, dfdc) = radicand_gradient(&system, r, q[r], &c);
            let dfdq = rad.radicand(Dual64::from_re(q[r]).derivative()).eps;
            let scale = f
                .abs()
                .max(p[r] * p[r])
                .max((q[r] * dfdq).abs())
                .max(dfdc.component_mul(&c).abs().sum())
                .max(f64::MIN_POSITIVE);
            if (f - p[r] * p[r]).abs() > 1e-10 * scale {
                return Err(Error::invalid(
                    "state",
                    format!(
                        "p[{r}]² = {} but the separated radicand F_{r}(q_{r}; c) = {f}: the \
                         constants do not describe this state",
                        p[r] * p[r]
                    ),
                ));
            }
            if system.ignorable(r) {
                let (fv, df) = radicand_gradient(&system, r, q[r], &c);
                let momentum = p[r];
                if momentum == 0.0 || fv <= 0.0 {
                    return Err(Error::invalid(
                        "state",
                        format!("ignorable coordinate {r} has zero momentum"),
                    ));
                }
                coordinates.push(Coordinate::Ignorable {
                    momentum,
                    rates: df / (2.0 * momentum),
                });
                phases[r] = q[r];
                continue;
            }
            let (lo, hi) = system.search_bounds(r);
            // At a turning point (p = 0) the search starts from a point just inside.
            let inside = if p[r] != 0.0 {
                q[r]
            } else {
                interior_point(&rad, q[r], lo, hi)?
            };
            let libration = Libration::from_radicand(rad, inside, lo, hi)?;
            let s = libration.phase_with_momentum(q[r], p[r])?;
            phases[r] = if p[r] >= 0.0 { s } else { 2.0 * PI - s };
            let mut passage = SVector::<f64, N>::zeros();
            for j in 0..N {
                passage[j] = libration
                    .integrate_full(|n| density(&system, r, &c, n)[j])?
                    .value;
            }
            coordinates.push(Coordinate::Librating { libration, passage });
        }
        let mut motion = Self {
            system,
            constants: c,
            beta: SVector::zeros(),
            coordinates,
        };
        let k = motion.characteristic_gradient(&phases)?;
        let mut beta = k;
        beta[e] -= t0;
        motion.beta = beta;
        Ok(motion)
    }
}

impl<S: SeparatedSystem<N>, const N: usize> SeparatedMotion<S, N> {
    /// The separation constants `c`.
    pub fn constants(&self) -> &SVector<f64, N> {
        &self.constants
    }
    /// The elements `β` (with `β_h = −t₀` plus the energy derivative at the start).
    pub fn elements(&self) -> &SVector<f64, N> {
        &self.beta
    }
    /// The turning points of coordinate `r`, `None` if it is ignorable.
    pub fn turning_points(&self, r: usize) -> Option<(f64, f64)> {
        match self.coordinates.get(r)? {
            Coordinate::Librating { libration, .. } => Some((libration.lower(), libration.upper())),
            Coordinate::Ignorable { .. } => None,
        }
    }
    /// The time for one passage of coordinate `r` between its turning points
    /// (`∂/∂h ∫_{q₁}^{q₂} √F_r dq_r`; half the period of an uncoupled coordinate).
    pub fn passage(&self, r: usize) -> Option<SVector<f64, N>> {
        match self.coordinates.get(r)? {
            Coordinate::Librating { passage, .. } => Some(*passage),
            Coordinate::Ignorable { .. } => None,
        }
    }

    /// The actions `J_r`: `(1/π) ∫_{q₁}^{q₂} √F_r dq_r` of a librating coordinate (with the
    /// quadrature's error estimate), and the constant momentum `p_r` of an ignorable one (the
    /// action of an angle coordinate of period 2π) [Goldstein, Poole & Safko §10.6; Ardema
    /// §17.3].
    pub fn actions(&self) -> Result<SVector<crate::special::turning_points::Quadrature, N>> {
        let mut out = [crate::special::turning_points::Quadrature {
            value: 0.0,
            error: 0.0,
            evaluations: 0,
        }; N];
        for (r, coord) in self.coordinates.iter().enumerate() {
            out[r] = match coord {
                Coordinate::Librating { libration, .. } => {
                    libration.sqrt_integral()?.scale(1.0 / PI)
                }
                Coordinate::Ignorable { momentum, .. } => {
                    crate::special::turning_points::Quadrature {
                        value: *momentum,
                        error: 0.0,
                        evaluations: 0,
                    }
                }
            };
        }
        Ok(SVector::from(out))
    }

    /// The frequencies `ω_r = ∂H/∂J_r` of the torus. With `M_{rj} = ∂J_r/∂c_j` (the passage
    /// integrals over `π` of a librating coordinate, `∂p_r/∂c_j` of an ignorable one) the
    /// constants are functions of the actions with `∂c/∂J = M⁻¹`, and the energy is the
    /// constant [`SeparatedSystem::energy_index`], so `ω_r = (M⁻¹)_{h r}`. An error where `M`
    /// is singular (e.g. at a separatrix).
    pub fn frequencies(&self) -> Result<SVector<f64, N>> {
        let m = self.mean_jacobian().transpose();
        let inv = crate::phase::checked_inverse(&m, "∂J/∂c of the separated motion", || {
            format!("constants c = {:?}", self.constants)
        })?;
        let e = self.system.energy_index();
        Ok(SVector::from_fn(|r, _| inv[(e, r)]))
    }

    /// `∂K/∂c` at the unwrapped phases (librating coordinates) and coordinates (ignorable ones).
    fn characteristic_gradient(&self, u: &SVector<f64, N>) -> Result<SVector<f64, N>> {
        let mut k = SVector::<f64, N>::zeros();
        for (r, coord) in self.coordinates.iter().enumerate() {
            match coord {
                Coordinate::Ignorable { rates, .. } => k += rates * u[r],
                Coordinate::Librating { libration, passage } => {
                    let passages = (u[r] / PI).floor();
                    let within = (u[r] - passages * PI).clamp(0.0, PI);
                    k += passage * passages;
                    let odd = (passages as i64).rem_euclid(2) == 1;
                    for j in 0..N {
                        let f = |n: &Node| density(&self.system, r, &self.constants, n)[j];
                        k[j] += if odd {
                            passage[j] - libration.integrate_between(f, 0.0, PI - within)?.value
                        } else {
                            libration.integrate_between(f, 0.0, within)?.value
                        };
                    }
                }
            }
        }
        Ok(k)
    }

    /// `∂(∂K/∂c_j)/∂u_r`.
    fn jacobian(&self, u: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        let mut m = SMatrix::<f64, N, N>::zeros();
        for (r, coord) in self.coordinates.iter().enumerate() {
            let col = match coord {
                Coordinate::Ignorable { rates, .. } => *rates,
                Coordinate::Librating { libration, .. } => density(
                    &self.system,
                    r,
                    &self.constants,
                    &libration.node(fold(u[r])),
                ),
            };
            m.set_column(r, &col);
        }
        m
    }

    /// The mean rate of `∂K/∂c` per unit of each unknown (a passage's integral over `π`).
    fn mean_jacobian(&self) -> SMatrix<f64, N, N> {
        let mut m = SMatrix::<f64, N, N>::zeros();
        for (r, coord) in self.coordinates.iter().enumerate() {
            let col = match coord {
                Coordinate::Ignorable { rates, .. } => *rates,
                Coordinate::Librating { passage, .. } => passage / PI,
            };
            m.set_column(r, &col);
        }
        m
    }

    /// The state `(q, p)` at time `t`: solves `∂K/∂c = β + δ_h t` for the unwrapped phases by
    /// Newton (the Jacobian is the matrix of integrands), started from the mean rates.
    pub fn state_at(&self, t: f64) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        let t = crate::error::finite("t", t)?;
        // The shortest passage sets the phase resolution needed.
        let shortest = self
            .coordinates
            .iter()
            .filter_map(|c| match c {
                Coordinate::Librating { passage, .. } => {
                    Some(passage[self.system.energy_index()].abs())
                }
                Coordinate::Ignorable { .. } => None,
            })
            .filter(|v| *v > 0.0)
            .fold(f64::INFINITY, f64::min);
        if shortest.is_finite() {
            super::central::check_time_resolution(t, 2.0 * shortest)?;
        }
        let mut target = self.beta;
        target[self.system.energy_index()] += t;
        let scale = target.amax().max(self.mean_jacobian().amax() * PI);
        let mean = self.mean_jacobian();
        let mut u = solve_linear(&mean, &target).ok_or_else(|| Error::Singular {
            what: "mean Jacobian of the separated quadratures".into(),
            at: format!("constants {:?}", self.constants.as_slice()),
            rcond: 0.0,
        })?;
        let mut residual = self.characteristic_gradient(&u)? - target;
        for _ in 0..100 {
            if residual.amax() <= 16.0 * f64::EPSILON * scale {
                return Ok(self.state_from_phases(&u));
            }
            let jac = self.jacobian(&u);
            let step = solve_linear(&jac, &residual)
                .or_else(|| solve_linear(&mean, &residual))
                .ok_or_else(|| Error::Singular {
                    what: "Jacobian of the separated quadratures".into(),
                    at: format!("phases {:?}", u.as_slice()),
                    rcond: 0.0,
                })?;
            // Backtracking: a Newton step must not increase the residual.
            let mut lambda = 1.0;
            loop {
                let trial = u - step * lambda;
                let r = self.characteristic_gradient(&trial)? - target;
                if r.amax() < residual.amax() || lambda < 1e-6 {
                    u = trial;
                    residual = r;
                    break;
                }
                lambda *= 0.5;
            }
        }
        Err(Error::NotConverged {
            what: "Jacobi inversion of the separated quadratures".into(),
            iterations: 100,
            residual: residual.amax(),
        })
    }

    fn state_from_phases(&self, u: &SVector<f64, N>) -> (SVector<f64, N>, SVector<f64, N>) {
        let mut q = SVector::<f64, N>::zeros();
        let mut p = SVector::<f64, N>::zeros();
        for (r, coord) in self.coordinates.iter().enumerate() {
            match coord {
                Coordinate::Ignorable { momentum, .. } => {
                    q[r] = u[r];
                    p[r] = *momentum;
                }
                Coordinate::Librating { libration, .. } => {
                    let node = libration.node(fold(u[r]));
                    let passages = (u[r] / PI).floor() as i64;
                    q[r] = node.x;
                    p[r] = if passages.rem_euclid(2) == 0 {
                        node.sqrt_radicand()
                    } else {
                        -node.sqrt_radicand()
                    };
                }
            }
        }
        (q, p)
    }
}

/// `m x = b` by LU (`None` if singular).
fn solve_linear<const N: usize>(
    m: &SMatrix<f64, N, N>,
    b: &SVector<f64, N>,
) -> Option<SVector<f64, N>> {
    let lu = nalgebra::DMatrix::from_fn(N, N, |i, j| m[(i, j)]).lu();
    let x = lu.solve(&nalgebra::DVector::from_fn(N, |i, _| b[i]))?;
    x.iter()
        .all(|v| v.is_finite())
        .then(|| SVector::from_fn(|i, _| x[i]))
}

/// The unwrapped phase folded into `[0, π]` (the position it describes).
fn fold(u: f64) -> f64 {
    let w = u.rem_euclid(2.0 * PI);
    if w <= PI {
        w
    } else {
        2.0 * PI - w
    }
}

/// `F_r` and `∂F_r/∂c` at `q_r`.
fn radicand_gradient<S: SeparatedSystem<N>, const N: usize>(
    system: &S,
    r: usize,
    q_r: f64,
    c: &SVector<f64, N>,
) -> (f64, SVector<f64, N>) {
    gradient(|cd| system.radicand(r, From::from(q_r), cd), c)
}

/// The densities `(∂F_r/∂c_j)/(2√P)` of `∂K_r/∂c_j` in the substitution variable.
fn density<S: SeparatedSystem<N>, const N: usize>(
    system: &S,
    r: usize,
    c: &SVector<f64, N>,
    n: &Node,
) -> SVector<f64, N> {
    let (_, df) = radicand_gradient(system, r, n.x, c);
    df / (2.0 * n.reduced.sqrt())
}

/// A [`LiouvilleSystem`] as a [`SeparatedSystem`] in canonical variables (`p_s = U v_s q̇_s`,
/// `H = Σ p_s²/(2U v_s) + W/U`): constants `c = (h, γ₁, …, γ_{N−1})`, `γ_N = −Σ γ_s`, and
///
/// ```math
/// F_s(q_s; c) = p_s^2 = 2 v_s (h u_s − w_s + γ_s)
/// ```
///
/// [Ardema 8.4, eqs. 8.38–8.40; 17.5]. `bounds[s]` is the interval searched for the
/// turning points of `q_s`.
#[derive(Clone, Debug)]
pub struct LiouvilleSeparation<S, const N: usize> {
    system: S,
    bounds: [(f64, f64); N],
}

impl<S: LiouvilleSystem<N>, const N: usize> LiouvilleSeparation<S, N> {
    /// The separation of `system`, with turning-point search intervals `bounds`.
    pub fn new(system: S, bounds: [(f64, f64); N]) -> Result<Self> {
        for (s, (lo, hi)) in bounds.iter().enumerate() {
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(Error::invalid(
                    format!("search bounds of q[{s}]"),
                    format!("need finite lower < upper, got ({lo}, {hi})"),
                ));
            }
        }
        Ok(Self { system, bounds })
    }
}

impl<S: LiouvilleSystem<N>, const N: usize> SeparatedSystem<N> for LiouvilleSeparation<S, N> {
    fn radicand<D: DualNum<f64> + Copy>(&self, r: usize, q_r: D, c: &SVector<D, N>) -> D {
        let gamma = if r + 1 < N {
            c[r + 1]
        } else {
            -(1..N).fold(D::zero(), |acc, j| acc + c[j])
        };
        let s = &self.system;
        s.v(r, q_r) * 2.0 * (c[0] * s.u(r, q_r) - s.w(r, q_r) + gamma)
    }

    fn constants(&self, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<SVector<f64, N>> {
        let s = &self.system;
        let u: f64 = (0..N).map(|r| s.u(r, q[r])).sum();
        if u == 0.0 {
            return Err(Error::out_of_domain("U = Σ u_s", u, "U ≠ 0"));
        }
        let kinetic: f64 = (0..N).map(|r| p[r] * p[r] / (2.0 * s.v(r, q[r]))).sum();
        let w: f64 = (0..N).map(|r| s.w(r, q[r])).sum();
        let h = (kinetic + w) / u;
        let mut c = SVector::<f64, N>::zeros();
        c[0] = h;
        for r in 0..N.saturating_sub(1) {
            c[r + 1] = p[r] * p[r] / (2.0 * s.v(r, q[r])) - h * s.u(r, q[r]) + s.w(r, q[r]);
        }
        Ok(c)
    }

    fn search_bounds(&self, r: usize) -> (f64, f64) {
        self.bounds[r]
    }
}
