//! Gauss–Legendre collocation methods: implicit midpoint (`s = 1`) to order 12 (`s = 6`), for any
//! [`Hamiltonian`].
//!
//! # The method
//! With nodes `c_i` the roots of the shifted Legendre polynomial `P_s(2x − 1)`, `ℓ_j` the Lagrange
//! basis on them, `a_ij = ∫₀^{c_i} ℓ_j(τ) dτ` and `b_j = ∫₀¹ ℓ_j(τ) dτ`, one step of size `h` from
//! `y₀ = (q₀, p₀)` at `t₀` solves the stage equations for `Z_i = Y_i − y₀`
//!
//! ```math
//! Z_i = h \sum_{j=1}^{s} a_{ij}\, f\big(t_0 + c_j h,\ y_0 + Z_j\big),\qquad i = 1, \dots, s,
//! ```
//!
//! and returns `Δy = h Σ_j b_j f(t₀ + c_j h, y₀ + Z_j)`, where `f = (∂H/∂p, −∂H/∂q + Q^nc)`. The
//! method is the collocation method on the Gauss points: order `2s`, A-stable, symmetric, and
//! symplectic because its coefficients satisfy
//!
//! ```math
//! b_i a_{ij} + b_j a_{ji} - b_i b_j = 0 \quad\text{for all } i, j
//! ```
//!
//! [Hairer, Lubich & Wanner, *Geometric Numerical Integration*, 2nd ed., Springer 2006,
//! doi:10.1007/3-540-30666-8 — II.1.3 (collocation), Theorem II.1.5 (order), Theorem VI.4.3
//! (symplecticity); Butcher, *Numerical Methods for Ordinary Differential Equations*, 3rd ed.,
//! Wiley 2016, §342]. It conserves every quadratic first integral exactly (angular momentum,
//! the energy of a linear system; HLW Theorem IV.2.2). `s = 1` is the implicit midpoint rule
//! `y₁ = y₀ + h f(t₀ + h/2, (y₀ + y₁)/2)`, exported as [`ImplicitMidpoint`].
//!
//! # Coefficients
//! Tabulated to 25 significant digits (Rust rounds literals correctly, so each `f64` is the
//! correctly rounded exact coefficient), computed at 60 digits with mpmath (nodes: roots of the
//! shifted Legendre polynomial; `a_ij = ∫₀^{c_i} ℓ_j`, `b_j = ∫₀¹ ℓ_j` of the Lagrange basis
//! polynomials `ℓ_j`). The unit tests check them against the simplifying assumptions
//!
//! ```math
//! B(2s):\ \sum_i b_i c_i^{k-1} = \tfrac1k\ (k \le 2s),\quad
//! C(s):\ \sum_j a_{ij} c_j^{k-1} = \tfrac{c_i^k}{k}\ (k \le s),\quad
//! D(s):\ \sum_i b_i c_i^{k-1} a_{ij} = \tfrac{b_j}{k}(1 - c_j^k)\ (k \le s)
//! ```
//!
//! and the symplecticity condition, each to an a-priori rounding bound (≈ 1e−16 … 1e−15), and
//! against an independent double-precision computation (Newton on the Legendre recurrence,
//! weights `2/((1 − x²) P_s′(x)²)`, `a_ij` by `s`-point Gauss quadrature of `ℓ_j`).
//!
//! # Solving the stage equations
//! Simplified Newton [HLW VIII.6.1; Hairer & Wanner, *Solving ODEs II*, IV.8]: the `2Ns × 2Ns`
//! matrix `M = I − h (A ⊗ J_f(t₀, y₀))` is factorised once per step (LU with partial pivoting),
//! with `J_f = [[H_pq, H_pp], [−H_qq, −H_qp]]` from one AD Hessian of `H` (or the AD Jacobian of the
//! vector field when the system has non-conservative forces), and the iteration
//! `Z ← Z − M⁻¹ (Z − h (A ⊗ I) F(Z))` starts from the explicit first-order guess
//! `Z_i = h c_i f(t₀, y₀)`. With the change `ΔZ` measured in the max-norm of each half (`q`, `p`)
//! relative to the size of `Z` in that half (floored at `ε‖y₀‖`), the iteration stops when
//!
//! * `‖ΔZ‖ ≤ ε` — the correction is below one unit in the last place of `Z`; or
//! * the correction stopped decreasing (`‖ΔZ_k‖ ≥ ‖ΔZ_{k−1}‖`) below `√ε`: the round-off floor
//!   of the residual (HLW VIII.5–6).
//!
//! (The linear-convergence estimate `θ/(1 − θ)‖ΔZ_k‖ ≤ ε` of HLW VIII.6 is deliberately not used
//! as a stopping rule: it certifies the *next* iterate, but the increment is formed from the vector
//! field at the current one, which is off by `‖ΔZ_k‖`; stopping on it was measured to leave a
//! systematic `~1e−14` energy error per step on the pendulum. `θ` only serves to abandon an
//! iteration that cannot reach `ε` within the allowed iterations.)
//!
//! Iterating to round-off, not to the local error, is what keeps the computed map symplectic to
//! rounding level over long runs (HLW VIII.5). If the simplified iteration diverges, is too slow to
//! converge in the allowed iterations or its matrix is singular, the step is retried with full
//! Newton (Jacobians at the current stages every iteration) and then with fixed-point iteration
//! `Z ← h (A ⊗ I) F(Z)`; if all three fail the step is [`Error::NotConverged`]. The increment uses the
//! vector-field values of the last iteration (at an iterate within round-off of the root), so no
//! evaluations are spent after convergence.
//!
//! # Exact derivatives of the step
//! `increment` is generic over the dual type `D`. The stages are solved on the real parts; then,
//! with the **exact** Newton matrix `M* = I − h (A ⊗ I) diag(J_f(Y_j))` at the converged stages
//! factorised on reals, `D::NDERIV` Newton steps are taken in `D` arithmetic ([`lift_root`]).
//! With `m` the ideal of infinitesimal parts, the error obeys `e₊ = (I − M*⁻¹ M(Z)) e + O(e²)` with `M(Z*) − M* ∈ m` (real
//! parts agree), so after `k` steps it lies in `m^{k+1}`: every Taylor coefficient up to order
//! `NDERIV` of the stages — and of the increment — is exact (the pattern of [`crate::implicit`];
//! Griewank & Walther, *Evaluating Derivatives*, 2nd ed., SIAM 2008, §15.1). [`StepMap`] with
//! [`certify`](crate::brackets::certify) then gives the exact step Jacobian. (The simplified matrix
//! at `y₀` would not do: its real part differs from `M*` by `O(h²)`.) On `f64` (`NDERIV = 0`) none
//! of this runs.
//!
//! # Cost and memory
//! Per real step: 1 Hessian, `1 + s·k` gradients for `k` iterations (typically 3–5), one LU of
//! size `2Ns` (`(2Ns)³/3` flops) and `k` triangular solves. Measured on planar Kepler (e = 0.5,
//! `examples/gauss_timing.rs`): about 0.5, 0.9, 1.4, 2.3, 3.3, 4.7 µs per step for s = 1…6 at
//! h = 2π/2000 (RK4: 55 ns); the dense LU dominates for large s (the real eigen-transformation of
//! `A`, HLW VIII.6 / Hairer–Wanner IV.8, would cut it to `⌈s/2⌉` complex `2N × 2N` solves). Per dual step additionally `s`
//! Hessians, one more LU and `s·(NDERIV + 1)` dual gradients. The Newton matrix lives on the stack
//! as nested arrays `[[[[[[f64; N]; 2]; S]; N]; 2]; S]` (stable Rust cannot write `[f64; 2·N·S]`);
//! only when `2Ns > 64` (a matrix above 32 KiB) is it one heap allocation per step instead.
//!
//! [`StepMap`]: super::StepMap

use super::methods;
use super::{OneStep, Work};
use crate::ad::{lift, real_parts};
use crate::error::{finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::implicit::lift_root;
use crate::phase::{check_phase, PhaseMatrix};
use crate::vector_space::VectorSpace;
use nalgebra::SVector;
use num_dual::DualNum;

/// Largest number of stages tabulated (`s = 6`, order 12).
pub const MAX_STAGES: usize = 6;

/// Default cap on the iterations of each of the three solvers (simplified Newton, full Newton,
/// fixed point) in one step.
pub const DEFAULT_MAX_ITERATIONS: usize = 60;

/// Largest Newton matrix dimension `2Ns` kept on the stack (64² doubles = 32 KiB).
const STACK_DIM: usize = 64;

/// The `s`-stage Gauss–Legendre collocation method (order `2s`, symplectic, symmetric), for
/// `1 ≤ s ≤ 6`; see the [module docs](self).
///
/// ```
/// use hamilton_jacobi::integrate::{integrate, Fixed, Gauss, Problem};
/// use hamilton_jacobi::systems::Kepler2;
/// use hamilton_jacobi::nalgebra::SVector;
/// let kepler = Kepler2::new(1.0).unwrap();
/// let (q0, p0) = (SVector::from([0.5, 0.0]), SVector::from([0.0, 3f64.sqrt()]));
/// let problem = Problem::new(&kepler, 0.0, q0, p0, std::f64::consts::TAU).unwrap();
/// let run = integrate(&problem, &Fixed::new(Gauss::<3>::new().unwrap(), 100).unwrap(), &mut ()).unwrap();
/// // Back at periapsis after one period, to the order-6 error of 100 steps.
/// assert!((run.last.q - q0).amax() < 1e-6 && (run.last.p - p0).amax() < 1e-6);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gauss<const S: usize> {
    c: [f64; S],
    b: [f64; S],
    a: [[f64; S]; S],
    max_iterations: usize,
}

/// The implicit midpoint rule, `y₁ = y₀ + h f(t₀ + h/2, (y₀ + y₁)/2)`: Gauss–Legendre with one stage
/// (order 2). Construct with `ImplicitMidpoint::new()`.
pub type ImplicitMidpoint = Gauss<1>;

impl<const S: usize> Gauss<S> {
    /// The `S`-stage method; [`Error::OutOfDomain`] unless `1 ≤ S ≤ 6`.
    pub fn new() -> Result<Self> {
        if S == 0 || S > MAX_STAGES {
            return Err(Error::out_of_domain(
                "Gauss–Legendre stage count s",
                S as f64,
                "1 ≤ s ≤ 6",
            ));
        }
        let (c, b, a) = (NODES[S - 1], WEIGHTS[S - 1], COEFFICIENTS[S - 1]);
        Ok(Self {
            c: std::array::from_fn(|i| c[i]),
            b: std::array::from_fn(|i| b[i]),
            a: std::array::from_fn(|i| std::array::from_fn(|j| a[i][j])),
            max_iterations: DEFAULT_MAX_ITERATIONS,
        })
    }

    /// The same method with at most `n ≥ 1` iterations per solver and step.
    pub fn with_max_iterations(mut self, n: usize) -> Result<Self> {
        if n == 0 {
            return Err(Error::out_of_domain("maximum iterations", 0.0, "≥ 1"));
        }
        self.max_iterations = n;
        Ok(self)
    }

    /// Number of stages `s`.
    pub fn stages(&self) -> usize {
        S
    }

    /// Nodes `c_i`.
    pub fn nodes(&self) -> [f64; S] {
        self.c
    }

    /// Weights `b_i`.
    pub fn weights(&self) -> [f64; S] {
        self.b
    }

    /// Runge–Kutta matrix `a_ij` (row `i`).
    pub fn coefficients(&self) -> [[f64; S]; S] {
        self.a
    }

    /// `F_j = f(t + c_j h, y₀ + Z_j)` at every stage (`S` gradients).
    #[allow(clippy::too_many_arguments)]
    fn fields<H: Hamiltonian<N>, D: DualNum<f64> + Copy, const N: usize>(
        &self,
        system: &H,
        t: D,
        h: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        z: &Stages<D, N, S>,
        work: &mut Work,
    ) -> Stages<D, N, S> {
        work.gradients += S;
        let mut f = Stages::zero();
        for j in 0..S {
            let (fq, fp) =
                system.vector_field_generic(t + h * self.c[j], &(q + z.q[j]), &(p + z.p[j]));
            f.q[j] = fq;
            f.p[j] = fp;
        }
        f
    }

    /// The residual `r_i = Z_i − h Σ_j a_ij F_j` into the flat vector `x` (layout
    /// `[stage][q | p][component]`).
    fn residual<D: DualNum<f64> + Copy, const N: usize>(
        &self,
        h: D,
        z: &Stages<D, N, S>,
        f: &Stages<D, N, S>,
        x: &mut [D],
    ) {
        for i in 0..S {
            let (mut rq, mut rp) = (z.q[i], z.p[i]);
            for j in 0..S {
                let w = h * self.a[i][j];
                rq -= f.q[j] * w;
                rp -= f.p[j] * w;
            }
            for k in 0..N {
                x[2 * N * i + k] = rq[k];
                x[2 * N * i + N + k] = rp[k];
            }
        }
    }

    /// `M = I − h (A ⊗ I) diag(J_j)` into the row-major `2Ns × 2Ns` slice `m`; `jac` holds one
    /// matrix per stage, or a single one used for all.
    fn newton_matrix<const N: usize>(&self, h: f64, jac: &[PhaseMatrix<N>], m: &mut [f64]) {
        let n = 2 * N * S;
        for i in 0..S {
            for j in 0..S {
                let jf = &jac[if jac.len() == 1 { 0 } else { j }];
                let w = h * self.a[i][j];
                for (ha, hb, blk) in [
                    (0, 0, &jf.qq),
                    (0, 1, &jf.qp),
                    (1, 0, &jf.pq),
                    (1, 1, &jf.pp),
                ] {
                    for k in 0..N {
                        for l in 0..N {
                            let r = 2 * N * i + N * ha + k;
                            let c = 2 * N * j + N * hb + l;
                            m[r * n + c] = if r == c { 1.0 } else { 0.0 } - w * blk[(k, l)];
                        }
                    }
                }
            }
        }
    }

    /// Jacobians of the vector field at the real stages `y₀ + Z_j` (`S` Hessians).
    #[allow(clippy::too_many_arguments)]
    fn stage_jacobians<H: Hamiltonian<N>, const N: usize>(
        &self,
        system: &H,
        t0: f64,
        h: f64,
        q0: &SVector<f64, N>,
        p0: &SVector<f64, N>,
        z: &Stages<f64, N, S>,
        work: &mut Work,
    ) -> Result<[PhaseMatrix<N>; S]> {
        let mut jac = [PhaseMatrix::identity(); S];
        for (j, m) in jac.iter_mut().enumerate() {
            *m = field_jacobian(
                system,
                t0 + self.c[j] * h,
                &(q0 + z.q[j]),
                &(p0 + z.p[j]),
                work,
            )?;
        }
        Ok(jac)
    }

    /// One attempt at the real stage equations with the given solver. Returns the stages and the
    /// vector field at the last iterate, or why it failed.
    #[allow(clippy::too_many_arguments)]
    fn iterate<H: Hamiltonian<N>, const N: usize>(
        &self,
        mode: Mode,
        system: &H,
        t0: f64,
        h: f64,
        q0: &SVector<f64, N>,
        p0: &SVector<f64, N>,
        f0: &(SVector<f64, N>, SVector<f64, N>),
        jac0: Option<&PhaseMatrix<N>>,
        m: &mut [f64],
        work: &mut Work,
    ) -> std::result::Result<(Stages<f64, N, S>, Stages<f64, N, S>), Failure> {
        let n = 2 * N * S;
        let mut piv = [[[0usize; N]; 2]; S];
        let piv = piv.as_flattened_mut().as_flattened_mut();
        let mut xs = [[[0.0f64; N]; 2]; S];
        let x = xs.as_flattened_mut().as_flattened_mut();
        let fail = |iterations, residual, reason: &str| Failure {
            mode,
            iterations,
            residual,
            reason: reason.to_string(),
        };
        if let Mode::Simplified = mode {
            let Some(j0) = jac0 else {
                return Err(fail(0, f64::NAN, "no Jacobian at y₀"));
            };
            self.newton_matrix(h, std::slice::from_ref(j0), m);
            if !lu_factor(m, piv, n) {
                return Err(fail(0, f64::NAN, "singular Newton matrix"));
            }
        }
        // Explicit first-order guess Z_i = h c_i f(t₀, y₀) = h Σ_j a_ij f(t₀, y₀).
        let mut z = Stages::<f64, N, S> {
            q: std::array::from_fn(|i| f0.0 * (h * self.c[i])),
            p: std::array::from_fn(|i| f0.1 * (h * self.c[i])),
        };
        let eps = f64::EPSILON;
        let mut previous = f64::INFINITY;
        for k in 1..=self.max_iterations {
            let f = self.fields(system, t0, h, q0, p0, &z, work);
            if !f.is_finite() {
                return Err(fail(k - 1, previous, "vector field not finite at a stage"));
            }
            self.residual(h, &z, &f, x);
            match mode {
                Mode::Simplified => lu_solve(m, piv, n, x),
                Mode::Full => {
                    let jac = self
                        .stage_jacobians(system, t0, h, q0, p0, &z, work)
                        .map_err(|_| fail(k - 1, previous, "Hessian not finite at a stage"))?;
                    self.newton_matrix(h, &jac, m);
                    if !lu_factor(m, piv, n) {
                        return Err(fail(k - 1, previous, "singular Newton matrix"));
                    }
                    lu_solve(m, piv, n, x);
                }
                Mode::FixedPoint => {}
            }
            z.sub_flat(x);
            work.newton_iterations += 1;
            let e = scaled_norm(x, &z, q0, p0);
            if !e.is_finite() {
                return Err(fail(k, e, "iterates not finite"));
            }
            if e <= eps {
                return Ok((z, f));
            }
            if previous.is_finite() {
                let theta = e / previous;
                if theta >= 1.0 {
                    // No longer decreasing: the round-off floor if already small, else divergence.
                    return if previous <= eps.sqrt() {
                        Ok((z, f))
                    } else {
                        Err(fail(k, e, "diverging"))
                    };
                }
                // Give up early when linear convergence at rate θ cannot reach ε in time. The
                // rate is trusted only between corrections after the first: the first measures the
                // starting guess, whose error can be far from the contraction regime (`Z_q = 0`
                // exactly when `p₀ = 0`).
                let needed = (eps / e).ln() / theta.ln();
                if k >= 3
                    && mode != Mode::FixedPoint
                    && k as f64 + needed > self.max_iterations as f64
                {
                    return Err(fail(k, e, "converging too slowly"));
                }
            }
            previous = e;
        }
        Err(fail(
            self.max_iterations,
            previous,
            "iteration limit reached",
        ))
    }
}

/// Which solver an attempt uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    /// Newton matrix at `y₀`, factorised once.
    Simplified,
    /// Newton matrix at the current stages, every iteration.
    Full,
    /// `M = I`: `Z ← h (A ⊗ I) F(Z)`.
    FixedPoint,
}

/// Why one solver failed.
#[derive(Clone, Debug)]
struct Failure {
    mode: Mode,
    iterations: usize,
    residual: f64,
    reason: String,
}

/// Stage vectors `(q_i, p_i)`, `i = 1..S`.
#[derive(Clone, Copy, Debug)]
struct Stages<D: DualNum<f64> + Copy, const N: usize, const S: usize> {
    q: [SVector<D, N>; S],
    p: [SVector<D, N>; S],
}

impl<D: DualNum<f64> + Copy, const N: usize, const S: usize> Stages<D, N, S> {
    fn zero() -> Self {
        let z = SVector::from_element(D::from(0.0));
        Self {
            q: [z; S],
            p: [z; S],
        }
    }
    /// `self −= x` with `x` in the flat layout `[stage][q | p][component]`.
    fn sub_flat(&mut self, x: &[D]) {
        for i in 0..S {
            for k in 0..N {
                self.q[i][k] -= x[2 * N * i + k];
                self.p[i][k] -= x[2 * N * i + N + k];
            }
        }
    }
    /// The stages from the flat layout `[stage][q | p][component]`.
    fn from_flat(x: &[D]) -> Self {
        Self {
            q: std::array::from_fn(|i| SVector::from_fn(|k, _| x[2 * N * i + k])),
            p: std::array::from_fn(|i| SVector::from_fn(|k, _| x[2 * N * i + N + k])),
        }
    }
    /// The stages into the flat layout `[stage][q | p][component]`.
    fn write_flat(&self, x: &mut [D]) {
        for i in 0..S {
            for k in 0..N {
                x[2 * N * i + k] = self.q[i][k];
                x[2 * N * i + N + k] = self.p[i][k];
            }
        }
    }
    fn is_finite(&self) -> bool {
        self.q
            .iter()
            .chain(self.p.iter())
            .all(|v| v.iter().all(|x| x.re().is_finite()))
    }
    /// `Σ_j w_j v_j` for the `q` and `p` halves.
    fn weighted_sum(&self, w: &[f64; S]) -> (SVector<D, N>, SVector<D, N>) {
        let mut sq = SVector::from_element(D::from(0.0));
        let mut sp = sq;
        for ((vq, vp), &wj) in self.q.iter().zip(&self.p).zip(w) {
            sq += vq * D::from(wj);
            sp += vp * D::from(wj);
        }
        (sq, sp)
    }
}

impl<D: DualNum<f64> + Copy, const N: usize, const S: usize> VectorSpace for Stages<D, N, S> {
    type Scalar = D;
    fn all(&self, f: impl Fn(D) -> bool) -> bool {
        self.q.iter().chain(&self.p).all(|v| v.all(&f))
    }
    fn map(&self, f: impl Fn(D) -> D) -> Self {
        Self {
            q: self.q.map(|v| v.map(&f)),
            p: self.p.map(|v| v.map(&f)),
        }
    }
    fn zip_map(&self, v: &Self, f: impl Fn(D, D) -> D) -> Self {
        Self {
            q: std::array::from_fn(|i| self.q[i].zip_map(&v.q[i], &f)),
            p: std::array::from_fn(|i| self.p[i].zip_map(&v.p[i], &f)),
        }
    }
}

fn lift_stages<D: DualNum<f64> + Copy, const N: usize, const S: usize>(
    z: &Stages<f64, N, S>,
) -> Stages<D, N, S> {
    Stages {
        q: z.q.map(|v| lift(&v)),
        p: z.p.map(|v| lift(&v)),
    }
}

/// The size of a correction `x` relative to the stages `z`, half by half: `max(‖x_q‖/σ_q,
/// ‖x_p‖/σ_p)` in max-norms with `σ = max(‖Z‖, ‖x‖, ε‖y₀‖)` over that half (so the result is in
/// `[0, 1]` and scale-free). NaN if `x` is not finite.
fn scaled_norm<const N: usize, const S: usize>(
    x: &[f64],
    z: &Stages<f64, N, S>,
    q0: &SVector<f64, N>,
    p0: &SVector<f64, N>,
) -> f64 {
    if !x.iter().all(|v| v.is_finite()) {
        return f64::NAN;
    }
    let mut e: f64 = 0.0;
    for (half, (zs, y0)) in [(&z.q, q0), (&z.p, p0)].into_iter().enumerate() {
        let zmax = zs.iter().map(|v| v.amax()).fold(0.0, f64::max);
        let xmax = (0..S)
            .flat_map(|i| (0..N).map(move |k| x[2 * N * i + N * half + k].abs()))
            .fold(0.0, f64::max);
        if xmax > 0.0 {
            e = e.max(xmax / zmax.max(xmax).max(f64::EPSILON * y0.amax()));
        }
    }
    e
}

/// The Jacobian of the vector field at a real point, `J·Hess H` (one AD Hessian), or the AD
/// Jacobian of the whole field when non-conservative forces act there.
fn field_jacobian<H: Hamiltonian<N>, const N: usize>(
    system: &H,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
    work: &mut Work,
) -> Result<PhaseMatrix<N>> {
    work.hessians += 1;
    if system.generalized_force(t, q, p).is_none() {
        let hs = system.hessian(t, q, p)?;
        Ok(PhaseMatrix {
            qq: hs.pq,
            qp: hs.pp,
            pq: -hs.qq,
            pp: -hs.qp,
        })
    } else {
        system.tangent_matrix(t, q, p)
    }
}

/// In-place LU factorisation with partial pivoting of the row-major `n × n` matrix `a`
/// (`P A = L U`, unit `L` below the diagonal, rows swapped whole; `piv[k]` the row swapped with `k`).
/// `false` if a pivot is zero or not finite, or the pivots span more than `1/(n ε)` (numerically
/// singular).
fn lu_factor(a: &mut [f64], piv: &mut [usize], n: usize) -> bool {
    let (mut umax, mut umin) = (0.0f64, f64::INFINITY);
    for k in 0..n {
        let (mut p, mut big) = (k, a[k * n + k].abs());
        for i in k + 1..n {
            let v = a[i * n + k].abs();
            if v > big {
                (p, big) = (i, v);
            }
        }
        if !(big > 0.0 && big.is_finite()) {
            return false;
        }
        piv[k] = p;
        if p != k {
            for j in 0..n {
                a.swap(k * n + j, p * n + j);
            }
        }
        (umax, umin) = (umax.max(big), umin.min(big));
        let inv = 1.0 / a[k * n + k];
        for i in k + 1..n {
            let l = a[i * n + k] * inv;
            a[i * n + k] = l;
            if l != 0.0 {
                for j in k + 1..n {
                    a[i * n + j] -= l * a[k * n + j];
                }
            }
        }
    }
    umin > umax * n as f64 * f64::EPSILON
}

/// Solve `A x = b` in place (`x` holds `b` on entry) from the factors of [`lu_factor`]; real
/// factors, right-hand side in any dual type.
fn lu_solve<D: DualNum<f64> + Copy>(a: &[f64], piv: &[usize], n: usize, x: &mut [D]) {
    for (k, &pk) in piv.iter().enumerate().take(n) {
        if pk != k {
            x.swap(k, pk);
        }
    }
    for i in 0..n {
        let mut s = x[i];
        for j in 0..i {
            s -= x[j] * a[i * n + j];
        }
        x[i] = s;
    }
    for i in (0..n).rev() {
        let mut s = x[i];
        for j in i + 1..n {
            s -= x[j] * a[i * n + j];
        }
        x[i] = s / a[i * n + i];
    }
}

/// Run `f` with a zeroed row-major `2Ns × 2Ns` workspace: on the stack when `2Ns ≤ 64`, else one
/// heap allocation.
fn with_matrix<const N: usize, const S: usize, R>(f: impl FnOnce(&mut [f64]) -> R) -> R {
    if 2 * N * S <= STACK_DIM {
        on_stack::<N, S, R>(f)
    } else {
        let n = 2 * N * S;
        f(&mut vec![0.0; n * n])
    }
}

/// The stack workspace, in its own frame so that large `N` never reserves it.
#[inline(never)]
fn on_stack<const N: usize, const S: usize, R>(f: impl FnOnce(&mut [f64]) -> R) -> R {
    let mut m = [[[[[[0.0f64; N]; 2]; S]; N]; 2]; S];
    f(m.as_flattened_mut()
        .as_flattened_mut()
        .as_flattened_mut()
        .as_flattened_mut()
        .as_flattened_mut())
}

impl<H: Hamiltonian<N>, const N: usize, const S: usize> OneStep<H, N> for Gauss<S> {
    fn order(&self) -> u32 {
        2 * S as u32
    }

    fn name(&self) -> String {
        // `Gauss::<S>::new()` refuses S outside 1 ..= 6, so the entry exists.
        methods::GAUSS.get(S.wrapping_sub(1)).map_or_else(
            || methods::label(methods::GAUSS[0].family, S as u32, 2 * S as u32),
            |m| m.label(),
        )
    }

    /// One step (see the [module docs](self)). Errors: [`Error::NonFinite`] for a non-finite state
    /// or step size or a vector field that is not finite at the state; [`Error::NotConverged`] if
    /// the stage equations defeat all three solvers (the message names each failure);
    /// [`Error::Singular`] if the exact Newton matrix needed for dual arguments is singular.
    #[inline]
    fn increment<D: DualNum<f64> + Copy>(
        &self,
        system: &H,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        dt: D,
        work: &mut Work,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        let (t0, h) = (t.re(), dt.re());
        let (q0, p0) = (real_parts(q), real_parts(p));
        check_phase(t0, &q0, &p0)?;
        finite("step size h", h)?;
        // Unchecked kernel (the checked `vector_field` formats its error context eagerly, which
        // costs more than a small step); the checked version only to word the error.
        let f0 = system.vector_field_unchecked(t0, &q0, &p0);
        work.gradients += 1;
        if !(f0.0.iter().chain(f0.1.iter()).all(|x| x.is_finite())) {
            system.vector_field(t0, &q0, &p0)?;
            return Err(Error::NonFinite {
                what: format!("vector field at t = {t0}, q = {q0:?}, p = {p0:?}"),
                value: f64::NAN,
            });
        }
        with_matrix::<N, S, _>(|m| {
            // Real stages: simplified Newton, then full Newton, then fixed point.
            let jac0 = field_jacobian(system, t0, &q0, &p0, work).ok();
            let mut failures: Vec<Failure> = Vec::new();
            let mut solved = None;
            for mode in [Mode::Simplified, Mode::Full, Mode::FixedPoint] {
                match self.iterate(mode, system, t0, h, &q0, &p0, &f0, jac0.as_ref(), m, work) {
                    Ok(r) => {
                        solved = Some(r);
                        break;
                    }
                    Err(e) => failures.push(e),
                }
            }
            let Some((z, f)) = solved else {
                let what = failures
                    .iter()
                    .map(|e| format!("{:?}: {} (‖ΔZ‖ = {:e})", e.mode, e.reason, e.residual))
                    .collect::<Vec<_>>()
                    .join("; ");
                return Err(Error::NotConverged {
                    what: format!(
                        "{} stage equations at t = {t0}, q = {q0:?}, p = {p0:?}, h = {h} [{what}]",
                        OneStep::<H, N>::name(self)
                    ),
                    iterations: failures.iter().map(|e| e.iterations).sum(),
                    residual: failures.last().map_or(f64::NAN, |e| e.residual),
                });
            };
            if D::NDERIV == 0 {
                let (sq, sp) = f.weighted_sum(&self.b);
                return Ok((lift(&(sq * h)), lift(&(sp * h))));
            }
            // Dual refinement with the exact Newton matrix at the converged stages.
            let jac = self.stage_jacobians(system, t0, h, &q0, &p0, &z, work)?;
            self.newton_matrix(h, &jac, m);
            let n = 2 * N * S;
            let mut piv = [[[0usize; N]; 2]; S];
            let piv = piv.as_flattened_mut().as_flattened_mut();
            if !lu_factor(m, piv, n) {
                return Err(Error::Singular {
                    what: format!("{} Newton matrix", OneStep::<H, N>::name(self)),
                    at: format!("t = {t0}, q = {q0:?}, p = {p0:?}, h = {h}"),
                    rcond: 0.0,
                });
            }
            let mut xs = [[[D::from(0.0); N]; 2]; S];
            let x = xs.as_flattened_mut().as_flattened_mut();
            let zd = lift_root(
                lift_stages::<D, N, S>(&z),
                |zd| {
                    let fd = self.fields(system, t, dt, q, p, zd, work);
                    self.residual(dt, zd, &fd, x);
                    Ok(Stages::from_flat(x))
                },
                |r| {
                    let mut ys = [[[D::from(0.0); N]; 2]; S];
                    let y = ys.as_flattened_mut().as_flattened_mut();
                    r.write_flat(y);
                    lu_solve(m, piv, n, y);
                    Stages::from_flat(y)
                },
            )?;
            let fd = self.fields(system, t, dt, q, p, &zd, work);
            let (sq, sp) = fd.weighted_sum(&self.b);
            Ok((sq * dt, sp * dt))
        })
    }
}

// Tabulated coefficients: computed with mpmath at 60 digits, printed to 25 significant digits;
// verified in the tests below (and rebuilt independently in double precision).
/// Nodes `c_i` (roots of the shifted Legendre polynomial `P_s(2x − 1)`), `s = 1..=6` at index `s − 1`.
#[allow(clippy::excessive_precision)]
const NODES: [&[f64]; MAX_STAGES] = [
    &[0.5000000000000000000000000],
    &[0.2113248654051871177454256, 0.7886751345948128822545744],
    &[
        0.1127016653792583114820735,
        0.5000000000000000000000000,
        0.8872983346207416885179265,
    ],
    &[
        0.06943184420297371238802676,
        0.3300094782075718675986671,
        0.6699905217924281324013329,
        0.9305681557970262876119732,
    ],
    &[
        0.04691007703066800360118656,
        0.2307653449471584544818428,
        0.5000000000000000000000000,
        0.7692346550528415455181572,
        0.9530899229693319963988134,
    ],
    &[
        0.03376524289842398609384922,
        0.1693953067668677431693002,
        0.3806904069584015456847491,
        0.6193095930415984543152509,
        0.8306046932331322568306998,
        0.9662347571015760139061508,
    ],
];
/// Weights `b_i = ∫₀¹ ℓ_i(τ) dτ`.
#[allow(clippy::excessive_precision)]
const WEIGHTS: [&[f64]; MAX_STAGES] = [
    &[1.000000000000000000000000],
    &[0.5000000000000000000000000, 0.5000000000000000000000000],
    &[
        0.2777777777777777777777778,
        0.4444444444444444444444444,
        0.2777777777777777777777778,
    ],
    &[
        0.1739274225687269286865320,
        0.3260725774312730713134680,
        0.3260725774312730713134680,
        0.1739274225687269286865320,
    ],
    &[
        0.1184634425280945437571320,
        0.2393143352496832340206458,
        0.2844444444444444444444444,
        0.2393143352496832340206458,
        0.1184634425280945437571320,
    ],
    &[
        0.08566224618958517252014807,
        0.1803807865240693037849168,
        0.2339569672863455236949352,
        0.2339569672863455236949352,
        0.1803807865240693037849168,
        0.08566224618958517252014807,
    ],
];
/// Collocation coefficients `a_ij = ∫₀^{c_i} ℓ_j(τ) dτ`, row `i`.
#[allow(clippy::excessive_precision)]
const COEFFICIENTS: [&[&[f64]]; MAX_STAGES] = [
    &[&[0.5000000000000000000000000]],
    &[
        &[0.2500000000000000000000000, -0.03867513459481288225457439],
        &[0.5386751345948128822545744, 0.2500000000000000000000000],
    ],
    &[
        &[
            0.1388888888888888888888889,
            -0.03597666752493890345639547,
            9.789444015308326049580042e-3,
        ],
        &[
            0.3002631949808645924380249,
            0.2222222222222222222222222,
            -0.02248541720308681466024717,
        ],
        &[
            0.2679883337624694517281977,
            0.4804211119693833479008399,
            0.1388888888888888888888889,
        ],
    ],
    &[
        &[
            0.08696371128436346434326599,
            -0.02660418008499879331338513,
            0.01262746268940472451505688,
            -3.555149685795683156910982e-3,
        ],
        &[
            0.1881181174998680716506855,
            0.1630362887156365356567340,
            -0.02788042860247089522415111,
            6.735500594538155515398669e-3,
        ],
        &[
            0.1671919219741887731711333,
            0.3539530060337439665376191,
            0.1630362887156365356567340,
            -0.01419069493114114296415357,
        ],
        &[
            0.1774825722545226118434430,
            0.3134451147418683467984111,
            0.3526767575162718646268532,
            0.08696371128436346434326599,
        ],
    ],
    &[
        &[
            0.05923172126404727187856601,
            -0.01957036435907603749264321,
            0.01125440081864295555271624,
            -5.593793660812184876817722e-3,
            1.588112967865998539365242e-3,
        ],
        &[
            0.1281510056700452834961668,
            0.1196571676248416170103229,
            -0.02459211461964220038931825,
            0.01031828067068335740895395,
            -2.768994398769603044282631e-3,
        ],
        &[
            0.1137762880042246025287413,
            0.2600046516806415185924059,
            0.1422222222222222222222222,
            -0.02069031643095828457176014,
            4.687154523869941228390747e-3,
        ],
        &[
            0.1212324369268641468014147,
            0.2289960545789998766116918,
            0.3090365590640866448337627,
            0.1196571676248416170103229,
            -9.687563141950739739034828e-3,
        ],
        &[
            0.1168753295602285452177668,
            0.2449081289104954188974635,
            0.2731900436258014888917282,
            0.2588846996087592715132890,
            0.05923172126404727187856601,
        ],
    ],
    &[
        &[
            0.04283112309479258626007404,
            -0.01476372599719741247537259,
            9.325050706477751191438885e-3,
            -5.668858049483511900921256e-3,
            2.854433315099335130929286e-3,
            -8.127801712647621122991357e-4,
        ],
        &[
            0.09267349143037886318651229,
            0.09019039326203465189245838,
            -0.02030010229323958595249408,
            0.01036315624024642373071995,
            -4.887192928037671463414204e-3,
            1.355561055485061775517871e-3,
        ],
        &[
            0.08224792261284387380777165,
            0.1960321623332450060557598,
            0.1169784836431727618474676,
            -0.02048252774565609762985901,
            7.989991899662335797204421e-3,
            -2.075625784866334193595289e-3,
        ],
        &[
            0.08773787197445150671374336,
            0.1723907946244069679877123,
            0.2544394950320016213247942,
            0.1169784836431727618474676,
            -0.01565137580917570227084302,
            3.414323576741298712376420e-3,
        ],
        &[
            0.08430668513410011074463020,
            0.1852679794521069752483310,
            0.2235938110460990999642152,
            0.2542570695795851096474293,
            0.09019039326203465189245838,
            -7.011245240793690666364221e-3,
        ],
        &[
            0.08647502636084993463244721,
            0.1775263532089699686539875,
            0.2396258253358290355958564,
            0.2246319165798677725034963,
            0.1951445125212667162602893,
            0.04283112309479258626007404,
        ],
    ],
];

#[cfg(test)]
#[allow(clippy::needless_range_loop)]
mod tests {
    //! The tabulated coefficients against their defining conditions, each to an a-priori rounding
    //! bound (u = ε/2 the unit roundoff; a stored coefficient carries relative error ≤ u, a
    //! product of k stored factors ≤ (2k − 1)u, a sum of m terms adds ≤ (m − 1)u·Σ|terms|), and
    //! against an independent double-precision computation.
    use super::*;

    const U: f64 = f64::EPSILON / 2.0;

    /// `x^k` by repeated multiplication (relative error ≤ (k − 1)u on top of that of `x`).
    fn pow(x: f64, k: usize) -> f64 {
        (0..k).fold(1.0, |a, _| a * x)
    }

    #[test]
    fn tables_have_the_right_shapes() {
        for s in 1..=MAX_STAGES {
            assert_eq!(NODES[s - 1].len(), s);
            assert_eq!(WEIGHTS[s - 1].len(), s);
            assert_eq!(COEFFICIENTS[s - 1].len(), s);
            assert!(COEFFICIENTS[s - 1].iter().all(|r| r.len() == s));
        }
    }

    #[test]
    fn consistency_and_row_sums() {
        for s in 1..=MAX_STAGES {
            let (c, b, a) = (NODES[s - 1], WEIGHTS[s - 1], COEFFICIENTS[s - 1]);
            // Σ b = 1: s stored roundings (≤ u each, b > 0, Σ b = 1) + (s − 1)u of summation.
            let sb: f64 = b.iter().sum();
            assert!(
                (sb - 1.0).abs() <= (2 * s) as f64 * U,
                "s = {s}: Σb − 1 = {:e}",
                sb - 1.0
            );
            for i in 0..s {
                // Σ_j a_ij = c_i (C(1)): su Σ|a_ij| from the table and the sum, u c_i from c_i.
                let sa: f64 = a[i].iter().sum();
                let abs: f64 = a[i].iter().map(|x| x.abs()).sum();
                let tol = (s + 1) as f64 * U * abs + U * c[i];
                assert!(
                    (sa - c[i]).abs() <= tol,
                    "s = {s}, i = {i}: {:e} > {tol:e}",
                    sa - c[i]
                );
            }
        }
    }

    #[test]
    fn simplifying_assumptions_b2s_cs_ds() {
        for s in 1..=MAX_STAGES {
            let (c, b, a) = (NODES[s - 1], WEIGHTS[s - 1], COEFFICIENTS[s - 1]);
            // B(2s): Σ b_i c_i^{k−1} = 1/k. Each term ≤ 2k u relative, positive, sum (s − 1)u,
            // 1/k one rounding.
            for k in 1..=2 * s {
                let lhs: f64 = (0..s).map(|i| b[i] * pow(c[i], k - 1)).sum();
                let rhs = 1.0 / k as f64;
                let tol = (2 * k + s + 1) as f64 * U * rhs;
                assert!(
                    (lhs - rhs).abs() <= tol,
                    "B: s = {s}, k = {k}: {:e}",
                    lhs - rhs
                );
            }
            // C(s): Σ_j a_ij c_j^{k−1} = c_i^k / k (mixed signs: bound on Σ|terms|).
            for i in 0..s {
                for k in 1..=s {
                    let terms: Vec<f64> = (0..s).map(|j| a[i][j] * pow(c[j], k - 1)).collect();
                    let lhs: f64 = terms.iter().sum();
                    let rhs = pow(c[i], k) / k as f64;
                    let abs: f64 = terms.iter().map(|x| x.abs()).sum();
                    let tol = (2 * k + s + 1) as f64 * U * (abs + rhs);
                    assert!(
                        (lhs - rhs).abs() <= tol,
                        "C: s = {s}, i = {i}, k = {k}: {:e}",
                        lhs - rhs
                    );
                }
            }
            // D(s): Σ_i b_i c_i^{k−1} a_ij = b_j (1 − c_j^k) / k.
            for j in 0..s {
                for k in 1..=s {
                    let terms: Vec<f64> =
                        (0..s).map(|i| b[i] * pow(c[i], k - 1) * a[i][j]).collect();
                    let lhs: f64 = terms.iter().sum();
                    let rhs = b[j] * (1.0 - pow(c[j], k)) / k as f64;
                    let abs: f64 = terms.iter().map(|x| x.abs()).sum();
                    let tol =
                        (2 * k + s + 2) as f64 * U * (abs + b[j] * (1.0 + pow(c[j], k)) / k as f64);
                    assert!(
                        (lhs - rhs).abs() <= tol,
                        "D: s = {s}, j = {j}, k = {k}: {:e}",
                        lhs - rhs
                    );
                }
            }
        }
    }

    #[test]
    fn symplecticity_condition() {
        // b_i a_ij + b_j a_ji − b_i b_j = 0: three products of two stored numbers (≤ 3u each) and
        // two additions (≤ 2u): bound 5u Σ|terms|. In practice ~1e−17.
        let mut worst: f64 = 0.0;
        for s in 1..=MAX_STAGES {
            let (b, a) = (WEIGHTS[s - 1], COEFFICIENTS[s - 1]);
            for i in 0..s {
                for j in 0..s {
                    let m = b[i] * a[i][j] + b[j] * a[j][i] - b[i] * b[j];
                    let tol =
                        5.0 * U * ((b[i] * a[i][j]).abs() + (b[j] * a[j][i]).abs() + b[i] * b[j]);
                    assert!(m.abs() <= tol, "s = {s}, ({i}, {j}): {m:e} > {tol:e}");
                    worst = worst.max(m.abs());
                }
            }
        }
        assert!(worst <= 1e-16, "{worst:e}");
    }

    /// Legendre `P_s(x)` and `P_s′(x)` on `[−1, 1]` by the three-term recurrence.
    fn legendre(s: usize, x: f64) -> (f64, f64) {
        let (mut p0, mut p1) = (1.0, x);
        for k in 1..s {
            let p2 = ((2 * k + 1) as f64 * x * p1 - k as f64 * p0) / (k + 1) as f64;
            (p0, p1) = (p1, p2);
        }
        if s == 0 {
            return (1.0, 0.0);
        }
        (p1, s as f64 * (x * p1 - p0) / (x * x - 1.0))
    }

    #[test]
    fn independent_double_precision_construction_agrees() {
        for s in 1..=MAX_STAGES {
            // Nodes: Newton on P_s from Chebyshev-like guesses (Abramowitz & Stegun 22.16.6).
            let mut x: Vec<f64> = (0..s)
                .map(|i| {
                    let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (s as f64 + 0.5)).cos();
                    for _ in 0..100 {
                        let (p, dp) = legendre(s, x);
                        let dx = p / dp;
                        x -= dx;
                        if dx.abs() <= 1e-17 {
                            break;
                        }
                    }
                    x
                })
                .collect();
            x.sort_by(|u, v| v.partial_cmp(u).unwrap());
            let c: Vec<f64> = x.iter().map(|x| (1.0 - x) / 2.0).collect();
            // Weights 2/((1 − x²) P′(x)²) on [−1, 1], halved for [0, 1].
            let b: Vec<f64> = x
                .iter()
                .map(|&x| 1.0 / ((1.0 - x * x) * legendre(s, x).1.powi(2)))
                .collect();
            // a_ij = ∫₀^{c_i} ℓ_j = c_i Σ_k b_k ℓ_j(c_i c_k) (exact for degree s − 1 ≤ 2s − 1).
            let ell = |j: usize, t: f64| -> f64 {
                (0..s)
                    .filter(|&m| m != j)
                    .fold(1.0, |acc, m| acc * (t - c[m]) / (c[j] - c[m]))
            };
            // Budget: nodes to a few u, Lagrange basis ≤ 4s u times its Lebesgue constant (< 3
            // for s ≤ 6 Gauss nodes), quadrature sum s u: (16 s + 8) u covers it.
            let tol = (16 * s + 8) as f64 * U;
            for i in 0..s {
                assert!((c[i] - NODES[s - 1][i]).abs() <= tol, "c: s = {s}, i = {i}");
                assert!(
                    (b[i] - WEIGHTS[s - 1][i]).abs() <= tol,
                    "b: s = {s}, i = {i}"
                );
                for j in 0..s {
                    let aij = c[i] * (0..s).map(|k| b[k] * ell(j, c[i] * c[k])).sum::<f64>();
                    let d = (aij - COEFFICIENTS[s - 1][i][j]).abs();
                    assert!(d <= tol, "a: s = {s}, ({i}, {j}): {d:e}");
                }
            }
        }
    }

    #[test]
    fn lu_solves_a_small_system_with_pivoting() {
        // [[0, 2], [1, 1]] x = [2, 3] → x = [2, 1] (needs a row swap).
        let mut a = [0.0, 2.0, 1.0, 1.0];
        let mut piv = [0; 2];
        assert!(lu_factor(&mut a, &mut piv, 2));
        let mut x = [2.0, 3.0];
        lu_solve(&a, &piv, 2, &mut x);
        assert_eq!(x, [2.0, 1.0]);
        let mut singular = [1.0, 2.0, 2.0, 4.0];
        assert!(!lu_factor(&mut singular, &mut piv, 2));
    }
}
