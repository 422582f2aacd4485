//! Jacobi's last multiplier, Liouville's theorem and the two-degree-of-freedom quadrature
//! [Ardema 15.6, eqs. 15.37–15.55].
//!
//! * A **multiplier** of `ẋ = X(t, x)` in `ℝᵐ` is a function `M(t, x)` with (non-autonomous form
//!   of [Ardema eq. 15.42])
//!
//!   ```math
//!   \frac{\partial M}{\partial t} + \sum_{r=1}^{m} \frac{\partial (M X_r)}{\partial x_r} = 0 ;
//!   ```
//!
//!   [`multiplier_residual`] (any vector field) and [`hamiltonian_multiplier_residual`] (Hamilton's
//!   equations with non-conservative forces) return the left side by AD. Hamiltonian flows have
//!   `M = 1` (Liouville); the damped pendulum `θ̈ = −sin θ − c θ̇` has `M = e^{ct}`.
//! * **Liouville's formula**: the Jacobian `Φ = ∂x(t)/∂x(t₀)` of the flow obeys the variational
//!   equations `Φ̇ = A Φ`, `A = ∂X/∂x`, hence `d ln det Φ / dt = tr A = div X`, and for a multiplier
//!   `M(t, x(t)) det Φ(t) = M(t₀, x₀)`. [`variational_flow`] integrates the state, `Φ` and
//!   `∫ div X dt` together.
//! * **Two degrees of freedom** with integrals `H = h`, `F = a` [Ardema eqs. 15.46–15.52]: with the
//!   momenta solved as `p_i = f_i(q; h, a)`, the form `K = ∫ f₁ dq₁ + f₂ dq₂` is exact and the
//!   remaining integrals are
//!
//!   ```math
//!   \frac{\partial K}{\partial a} = \beta \quad\text{(orbit)},\qquad \frac{\partial K}{\partial h} = t - t_0 \quad\text{(time)} ;
//!   ```
//!
//!   [`two_dof_quadrature`] evaluates both between two points of configuration space by
//!   double-exponential quadrature, differentiating under the integral sign by AD.

use crate::ad::{lift, GradDual, PhaseDual, PhaseDual64};
use crate::brackets::partial_t;
use crate::error::{all_finite, finite, Error, Result};
use crate::hamiltonian::{Hamiltonian, PhaseFunction};
use crate::phase::{check_phase, PhaseMatrix};
use crate::special::double_double::compensated_add;
use nalgebra::{Const, SMatrix, SVector};
use num_dual::{first_derivative, Dual, DualNum};
use std::cell::Cell;

/// A vector field `X(t, x)` on `ℝᴹ` (the right side of `ẋ = X`), written once for every dual type.
pub trait VectorField<const M: usize> {
    /// `X(t, x)`.
    fn field<D: DualNum<f64> + Copy>(&self, t: D, x: &SVector<D, M>) -> SVector<D, M>;
}

/// A scalar function `M(t, x)` on `ℝ × ℝᴹ` (a candidate multiplier), written once for every dual
/// type.
pub trait ScalarField<const M: usize> {
    /// `M(t, x)`.
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, x: &SVector<D, M>) -> D;
}

fn check_point<const M: usize>(t: f64, x: &SVector<f64, M>) -> Result<()> {
    finite("t", t)?;
    all_finite("x", x.as_slice())
}

/// Divergence `div X = Σ_r ∂X_r/∂x_r = tr ∂X/∂x` by AD: the rate `d ln det Φ/dt` of the flow's
/// volume (Liouville's formula).
pub fn divergence<X: VectorField<M> + ?Sized, const M: usize>(
    field: &X,
    t: f64,
    x: &SVector<f64, M>,
) -> Result<f64> {
    check_point(t, x)?;
    let xd: SVector<GradDual<f64, f64, Const<M>>, M> =
        SVector::from_fn(|i, _| GradDual::variable(x[i], i));
    let y = field.field(GradDual::from_re(t), &xd);
    let div = (0..M).map(|r| y[r].eps()[r]).sum::<f64>();
    finite(format_args!("div X at t = {t}, x = {x:?}"), div)
}

/// Residual of the multiplier equation `∂M/∂t + Σ_r ∂(M X_r)/∂x_r` [Ardema eq. 15.42] at `(t, x)`,
/// by AD; zero (to rounding) everywhere iff `M` is a Jacobi multiplier of `ẋ = X(t, x)`.
///
/// ```
/// use hamilton_jacobi::hamilton_jacobi::{multiplier_residual, ScalarField, VectorField};
/// use hamilton_jacobi::{DualNum, nalgebra::SVector};
/// /// Damped pendulum θ̈ = −sin θ − c θ̇ with c = 0.2, and the multiplier e^{ct}.
/// struct Damped;
/// impl VectorField<2> for Damped {
///     fn field<D: DualNum<f64> + Copy>(&self, _t: D, x: &SVector<D, 2>) -> SVector<D, 2> {
///         SVector::from([x[1], -x[0].sin() - x[1] * 0.2])
///     }
/// }
/// struct Exp;
/// impl ScalarField<2> for Exp {
///     fn eval<D: DualNum<f64> + Copy>(&self, t: D, _x: &SVector<D, 2>) -> D { (t * 0.2).exp() }
/// }
/// let r = multiplier_residual(&Damped, &Exp, 1.5, &SVector::from([2.0, 0.5])).unwrap();
/// assert!(r.abs() < 1e-15);
/// ```
pub fn multiplier_residual<X, S, const M: usize>(
    field: &X,
    multiplier: &S,
    t: f64,
    x: &SVector<f64, M>,
) -> Result<f64>
where
    X: VectorField<M> + ?Sized,
    S: ScalarField<M> + ?Sized,
{
    check_point(t, x)?;
    let xd: SVector<GradDual<f64, f64, Const<M>>, M> =
        SVector::from_fn(|i, _| GradDual::variable(x[i], i));
    let td = GradDual::from_re(t);
    let m = multiplier.eval(td, &xd);
    let y = field.field(td, &xd);
    let div: f64 = (0..M).map(|r| (m * y[r]).eps()[r]).sum();
    let mt = first_derivative(|s: Dual<f64, f64>| multiplier.eval(s, &lift(x)), t).1;
    finite(
        format_args!("multiplier residual at t = {t}, x = {x:?}"),
        mt + div,
    )
}

/// Divergence of Hamilton's equations `ẋ = (∂H/∂p, −∂H/∂q + Q^nc)` over phase space,
/// `tr A = Σ_r ∂Q^nc_r/∂p_r` (the Hamiltonian part is divergence-free: Liouville's theorem
/// [Ardema 16.4]).
pub fn hamiltonian_divergence<H: Hamiltonian<N> + ?Sized, const N: usize>(
    h: &H,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<f64> {
    let a = h.tangent_matrix(t, q, p)?;
    finite("tr A", a.qq.trace() + a.pp.trace())
}

/// Residual of the multiplier equation for Hamilton's equations (with the system's
/// non-conservative forces): `∂M/∂t + Σ_r ∂(M q̇_r)/∂q_r + ∂(M ṗ_r)/∂p_r` at `(t, q, p)`, by AD.
pub fn hamiltonian_multiplier_residual<H, F, const N: usize>(
    h: &H,
    multiplier: &F,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<f64>
where
    H: Hamiltonian<N> + ?Sized,
    F: PhaseFunction<N> + ?Sized,
{
    check_phase(t, q, p)?;
    let qd: SVector<PhaseDual64<N>, N> = SVector::from_fn(|i, _| PhaseDual::coordinate(q[i], i));
    let pd: SVector<PhaseDual64<N>, N> = SVector::from_fn(|i, _| PhaseDual::momentum(p[i], i));
    let td = PhaseDual::from_re(t);
    let m = multiplier.eval(td, &qd, &pd);
    let (qdot, pdot) = h.vector_field_generic(td, &qd, &pd);
    let div: f64 = (0..N)
        .map(|r| (m * qdot[r]).dq()[r] + (m * pdot[r]).dp()[r])
        .sum();
    let mt = partial_t(multiplier, t, q, p)?;
    finite(
        format_args!("multiplier residual at t = {t}, q = {q:?}, p = {p:?}"),
        mt + div,
    )
}

/// The end state of [`variational_flow`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VariationalFlow<const N: usize> {
    /// Coordinates at the end time.
    pub q: SVector<f64, N>,
    /// Momenta at the end time.
    pub p: SVector<f64, N>,
    /// Jacobian of the flow map `Φ = ∂(q, p)(t₁)/∂(q, p)(t₀)`.
    pub jacobian: PhaseMatrix<N>,
    /// `∫ tr A dt` along the computed motion: by Liouville's formula `det Φ = exp` of it.
    pub divergence_integral: f64,
}

/// Integrate Hamilton's equations together with the variational equations `Φ̇ = A(t, q, p) Φ`,
/// `Φ(t₀) = I`, and the Liouville rate `d(ln det Φ)/dt = tr A`, by the classical fourth-order
/// Runge–Kutta method with `steps` equal steps over `duration` (negative for backward
/// integration). `A` is the AD tangent map ([`Hamiltonian::tangent_matrix`], including the
/// non-conservative forces).
///
/// Because `Φ` is advanced with the same stages as the state, it is exactly the Jacobian of the
/// discrete Runge–Kutta map (internal differentiation), so `det Φ` differs from the exact
/// `exp ∫ tr A dt` only by the method's volume error, `O(duration · Δt⁴)`.
///
/// Errors: [`Error::NonFinite`] for NaN/∞ input or a non-finite state on the way;
/// [`Error::OutOfDomain`] for `steps = 0`.
pub fn variational_flow<H: Hamiltonian<N> + ?Sized, const N: usize>(
    h: &H,
    t0: f64,
    q0: &SVector<f64, N>,
    p0: &SVector<f64, N>,
    duration: f64,
    steps: usize,
) -> Result<VariationalFlow<N>> {
    check_phase(t0, q0, p0)?;
    finite("duration", duration)?;
    if steps == 0 {
        return Err(Error::out_of_domain("steps", 0.0, "{1, 2, …}"));
    }
    let dt = duration / steps as f64;
    // The right side of the augmented system (q, p, Φ, ℓ).
    let rhs = |t: f64, q: &SVector<f64, N>, p: &SVector<f64, N>, phi: &PhaseMatrix<N>| {
        let (qd, pd) = h.vector_field(t, q, p)?;
        let a = h.tangent_matrix(t, q, p)?;
        Ok::<_, Error>((qd, pd, a.mul(phi), a.qq.trace() + a.pp.trace()))
    };
    let axpy = |x: &PhaseMatrix<N>, s: f64, y: &PhaseMatrix<N>| PhaseMatrix {
        qq: x.qq + y.qq * s,
        qp: x.qp + y.qp * s,
        pq: x.pq + y.pq * s,
        pp: x.pp + y.pp * s,
    };
    let (mut q, mut p, mut phi, mut ell) = (*q0, *p0, PhaseMatrix::identity(), 0.0);
    // Compensation terms of the summed updates (rounding then grows like √n ε instead of n ε).
    let (mut cq, mut cp, mut cphi, mut cell) = (
        SVector::<f64, N>::zeros(),
        SVector::<f64, N>::zeros(),
        PhaseMatrix::<N> {
            qq: SMatrix::zeros(),
            qp: SMatrix::zeros(),
            pq: SMatrix::zeros(),
            pp: SMatrix::zeros(),
        },
        0.0,
    );
    for k in 0..steps {
        let t = t0 + dt * k as f64;
        let (q1, p1, f1, l1) = rhs(t, &q, &p, &phi)?;
        let (q2, p2, f2, l2) = rhs(
            t + 0.5 * dt,
            &(q + q1 * (0.5 * dt)),
            &(p + p1 * (0.5 * dt)),
            &axpy(&phi, 0.5 * dt, &f1),
        )?;
        let (q3, p3, f3, l3) = rhs(
            t + 0.5 * dt,
            &(q + q2 * (0.5 * dt)),
            &(p + p2 * (0.5 * dt)),
            &axpy(&phi, 0.5 * dt, &f2),
        )?;
        let (q4, p4, f4, l4) = rhs(t + dt, &(q + q3 * dt), &(p + p3 * dt), &axpy(&phi, dt, &f3))?;
        let w = dt / 6.0;
        let dphi = axpy(&axpy(&axpy(&f1, 2.0, &f2), 2.0, &f3), 1.0, &f4);
        compensated_add(
            q.as_mut_slice(),
            cq.as_mut_slice(),
            ((q1 + (q2 + q3) * 2.0 + q4) * w).as_slice(),
        );
        compensated_add(
            p.as_mut_slice(),
            cp.as_mut_slice(),
            ((p1 + (p2 + p3) * 2.0 + p4) * w).as_slice(),
        );
        for (x, (c, d)) in [
            (&mut phi.qq, (&mut cphi.qq, dphi.qq)),
            (&mut phi.qp, (&mut cphi.qp, dphi.qp)),
            (&mut phi.pq, (&mut cphi.pq, dphi.pq)),
            (&mut phi.pp, (&mut cphi.pp, dphi.pp)),
        ] {
            compensated_add(x.as_mut_slice(), c.as_mut_slice(), (d * w).as_slice());
        }
        compensated_add(
            std::slice::from_mut(&mut ell),
            std::slice::from_mut(&mut cell),
            &[(l1 + 2.0 * (l2 + l3) + l4) * w],
        );
    }
    if !phi.is_finite() {
        return Err(Error::NonFinite {
            what: "flow Jacobian Φ".into(),
            value: phi.max_abs(),
        });
    }
    Ok(VariationalFlow {
        q,
        p,
        jacobian: phi,
        divergence_integral: finite("∫ tr A dt", ell)?,
    })
}

/// The momenta of a two-degree-of-freedom system solved from two integrals, `p_i = f_i(q; h, a)`
/// (`h` the energy, `a` the second integral), written once for every dual type
/// [Ardema eqs. 15.46–15.50].
pub trait TwoDofMomenta {
    /// `(f₁, f₂)(q; h, a)`.
    fn momenta<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 2>, h: D, a: D) -> SVector<D, 2>;
}

/// Result of [`two_dof_quadrature`] along a path from `q⁰` to `q¹`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoDofQuadrature {
    /// `K(q¹) − K(q⁰) = ∫ f₁ dq₁ + f₂ dq₂`.
    pub k: f64,
    /// Orbit equation: `∂K/∂a` between the end points, `β(q¹) − β(q⁰)`; zero iff both points lie on
    /// the same motion [Ardema eq. 15.51].
    pub dk_da: f64,
    /// Time equation: `∂K/∂h` between the end points, the time `t₁ − t₀` to travel between them
    /// [Ardema eq. 15.52].
    pub dk_dh: f64,
    /// Exactness defect `max |∂f₁/∂q₂ − ∂f₂/∂q₁|` over the quadrature nodes (AD); zero for momenta
    /// that really come from two integrals in involution.
    pub exactness_defect: f64,
    /// Sum of the quadrature's error estimates for the three integrals.
    pub error_estimate: f64,
}

/// Evaluate `K = ∫ f₁ dq₁ + f₂ dq₂` and its derivatives `∂K/∂a` (orbit equation) and `∂K/∂h`
/// (time equation) along the polygonal path through `path` (at least two points) in configuration
/// space [Ardema eqs. 15.46–15.52].
///
/// Each segment `q(s) = A + s (B − A)`, `s ∈ [0, 1]`, is integrated by the double-exponential rule
/// (`quadrature::double_exponential`); the integrand is evaluated once per node in a gradient dual
/// number over `(h, a)`, so the derivatives are taken under the integral sign exactly. The path must
/// stay inside the domain of `f` (e.g. avoid the turning points where `p_r = 0`): every node with a
/// non-finite value is an error, not a silent zero. Since the form is exact, the result depends only
/// on the end points within one branch of `f`.
///
/// Errors: [`Error::NonFinite`] for NaN/∞ input or a node outside the domain of `f`;
/// [`Error::InvalidInput`] for fewer than two points; [`Error::NotConverged`] if the quadrature's
/// error estimate exceeds `1e−8` of the integrand's scale.
pub fn two_dof_quadrature<F: TwoDofMomenta + ?Sized>(
    f: &F,
    h: f64,
    a: f64,
    path: &[SVector<f64, 2>],
) -> Result<TwoDofQuadrature> {
    finite("energy h", h)?;
    finite("integral a", a)?;
    if path.len() < 2 {
        return Err(Error::invalid(
            "path",
            format!("needs at least two points, got {}", path.len()),
        ));
    }
    for (k, x) in path.iter().enumerate() {
        all_finite(format_args!("path[{k}]"), x.as_slice())?;
    }
    let mut out = TwoDofQuadrature {
        k: 0.0,
        dk_da: 0.0,
        dk_dh: 0.0,
        exactness_defect: 0.0,
        error_estimate: 0.0,
    };
    type G2 = GradDual<f64, f64, Const<2>>;
    for seg in path.windows(2) {
        let (qa, qb) = (seg[0], seg[1]);
        let dq = qb - qa;
        let bad: Cell<Option<(f64, f64)>> = Cell::new(None);
        let defect = Cell::new(0.0f64);
        // Integrand f(q(s))·dq/ds with its (h, a)-gradient; records non-finite nodes.
        let integrand = |s: f64| -> (f64, f64, f64) {
            let q = qa + dq * s;
            let ha = SVector::from([G2::variable(h, 0), G2::variable(a, 1)]);
            let p = f.momenta(&q.map(G2::from_re), ha[0], ha[1]);
            let v = p[0] * dq[0] + p[1] * dq[1];
            let (val, dh, da) = (*v.value(), v.eps()[0], v.eps()[1]);
            if !(val.is_finite() && dh.is_finite() && da.is_finite()) && bad.get().is_none() {
                bad.set(Some((s, if val.is_finite() { dh + da } else { val })));
            }
            (val, dh, da)
        };
        let scale = {
            let (v, dh, da) = integrand(0.5);
            v.abs().max(dh.abs()).max(da.abs()).max(f64::MIN_POSITIVE)
        };
        let target = 1e-15 * scale;
        let rk = quadrature::double_exponential::integrate(
            |s| {
                let q = qa + dq * s;
                let qd: SVector<G2, 2> = SVector::from_fn(|i, _| G2::variable(q[i], i));
                let jac = f.momenta(&qd, G2::from_re(h), G2::from_re(a));
                let d = (jac[0].eps()[1] - jac[1].eps()[0]).abs();
                if d.is_finite() {
                    defect.set(defect.get().max(d));
                }
                integrand(s).0
            },
            0.0,
            1.0,
            target,
        );
        let rh = quadrature::double_exponential::integrate(|s| integrand(s).1, 0.0, 1.0, target);
        let ra = quadrature::double_exponential::integrate(|s| integrand(s).2, 0.0, 1.0, target);
        if let Some((s, value)) = bad.get() {
            return Err(Error::NonFinite {
                what: format!(
                    "momenta f(q; h, a) on the path at q = {:?} (outside their domain: a turning \
                     point or forbidden region on the path?)",
                    qa + dq * s
                ),
                value,
            });
        }
        let err = rk.error_estimate + rh.error_estimate + ra.error_estimate;
        if err.is_nan() || err > 1e-8 * scale {
            return Err(Error::NotConverged {
                what: format!(
                    "double-exponential quadrature on the segment {qa:?} → {qb:?} (end-point \
                     singularity?)"
                ),
                iterations: (rk.num_function_evaluations
                    + rh.num_function_evaluations
                    + ra.num_function_evaluations) as usize,
                residual: err,
            });
        }
        out.k += rk.integral;
        out.dk_dh += rh.integral;
        out.dk_da += ra.integral;
        out.error_estimate += err;
        out.exactness_defect = out.exactness_defect.max(defect.get());
    }
    Ok(out)
}
