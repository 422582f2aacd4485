//! Lagrangian systems, the Legendre transform, Lagrange's equations, Rayleigh dissipation,
//! the Jacobi integral and Routh's reduction — all derived by AD from `L` written once.
//!
//! * Lagrange's equations [Ardema 6.4, eq. 6.33] with the Rayleigh function of the sign opposite
//!   to [Ardema eqs. 6.37–6.38], `D = ½ q̇ᵀ d q̇ ≥ 0`, `Q^d = −∂D/∂q̇`:
//!   ```math
//!   E(t, q, \dot q, \ddot q) = \frac{d}{dt}\frac{\partial L}{\partial \dot q}
//!   - \frac{\partial L}{\partial q} - Q^{nc} + \frac{\partial D}{\partial \dot q} = 0 .
//!   ```
//! * Legendre transform [Ardema 15.1, eqs. 15.3–15.17]: `p = ∂L/∂q̇`,
//!   `H(t, q, p) = p·q̇ − L(t, q, q̇)` with `q̇` solving `∂L/∂q̇ = p` by Newton's method with the AD
//!   mass matrix `∂²L/∂q̇²`; for natural systems `T = ½ q̇ᵀ a q̇ + bᵀ q̇ + c` in closed form
//!   `H = ½ (p − b)ᵀ a⁻¹ (p − b) − c + V` [Ardema eq. 15.8] ([`NaturalSystem`]).
//! * Jacobi integral `h = q̇·∂L/∂q̇ − L = T₂ − T₀ + V` [Ardema 8.2, eqs. 8.9–8.19].
//! * Routhian `R = L − Σ_β C_β q̇_β` for ignorable coordinates [Ardema 8.3, eqs. 8.24–8.37].

use crate::ad::{lift, phase_gradient, phase_hessian, real_parts, PhaseDual};
use crate::error::{all_finite, finite, Error, Result};
use crate::hamiltonian::{checked_vector_field, Hamiltonian, PhaseFunction};
use crate::implicit::{self, ImplicitSystem};
use crate::phase::{check_phase, checked_inverse};
use nalgebra::{SMatrix, SVector};
use num_dual::{linalg::LU, Dual64, DualNum};

/// A Lagrangian system with `N` degrees of freedom, `L(t, q, q̇)` written once for every dual type.
///
/// # Requirements on the system
/// As for [`Hamiltonian`]: the body uses [`DualNum`] operations only. The Legendre transform
/// requires the mass matrix `∂²L/∂q̇²` to be non-singular where it is used.
///
/// # Reference
/// M. D. Ardema, *Analytical Dynamics*, Kluwer/Plenum 2005, §§6.1–6.4, 8.2–8.3 and 15.1.
pub trait Lagrangian<const N: usize> {
    /// The Lagrangian `L(t, q, q̇)`.
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        qdot: &SVector<D, N>,
    ) -> D;

    /// Non-conservative, non-dissipative generalized forces `Q^nc(t, q, q̇)` [Ardema eq. 6.33];
    /// `None` (default) for none.
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, N>,
        _qdot: &SVector<D, N>,
    ) -> Option<SVector<D, N>> {
        None
    }

    /// Rayleigh dissipation function `D(t, q, q̇) ≥ 0` in the crate convention,
    /// contributing `Q^d = −∂D/∂q̇`; `None` (default) for none. A book-sign function
    /// (`D_Ardema = −D`) must be negated before it is returned here.
    fn dissipation<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, N>,
        _qdot: &SVector<D, N>,
    ) -> Option<D> {
        None
    }

    /// `L(t, q, q̇)` on reals, NaN/∞ rejected.
    fn value(&self, t: f64, q: &SVector<f64, N>, qdot: &SVector<f64, N>) -> Result<f64> {
        check_state(t, q, qdot)?;
        let l = self.lagrangian(t, q, qdot);
        finite(format_args!("L at t = {t}, q = {q:?}, q̇ = {qdot:?}"), l)
    }

    /// Canonical momenta `p = ∂L/∂q̇` [Ardema eq. 15.3].
    fn momentum(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qdot: &SVector<f64, N>,
    ) -> Result<SVector<f64, N>> {
        check_state(t, q, qdot)?;
        let p = phase_gradient(|a, b| self.lagrangian(PhaseDual::from_re(t), a, b), q, qdot).2;
        finite_out("p = ∂L/∂q̇", t, q, qdot, p)
    }

    /// Mass matrix `∂²L/∂q̇²` (the `a` of [Ardema eq. 6.2] for natural systems).
    fn mass_matrix(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qdot: &SVector<f64, N>,
    ) -> Result<SMatrix<f64, N, N>> {
        check_state(t, q, qdot)?;
        let m = phase_hessian(|a, b| self.lagrangian(From::from(t), a, b), q, qdot)
            .3
            .pp;
        finite_out("mass matrix ∂²L/∂q̇²", t, q, qdot, m)
    }

    /// Generalized forces that do not derive from `L`: `Q^nc − ∂D/∂q̇` (zero if there are none).
    fn total_force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        qdot: &SVector<D, N>,
    ) -> SVector<D, N> {
        let mut f = self
            .generalized_force(t, q, qdot)
            .unwrap_or_else(SVector::zeros);
        if self.dissipation(t, q, qdot).is_some() {
            let (_, _, dd) = phase_gradient(
                |a, b| {
                    self.dissipation(PhaseDual::from_re(t), a, b)
                        .unwrap_or_else(|| From::from(0.0))
                },
                q,
                qdot,
            );
            f -= dd;
        }
        f
    }

    /// Residual of Lagrange's equations `E(t, q, q̇, q̈)` (see the [module docs](self)); zero on
    /// an actual motion.
    fn lagrange_residual(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qdot: &SVector<f64, N>,
        qddot: &SVector<f64, N>,
    ) -> Result<SVector<f64, N>> {
        all_finite("q̈", qddot.as_slice())?;
        let (lq, h, lvt) = self.second_order_terms(t, q, qdot)?;
        let e = h.pq * qdot + h.pp * qddot + lvt - lq - self.total_force(t, q, qdot);
        finite_out("Lagrange residual", t, q, qdot, e)
    }

    /// Accelerations `q̈` solving Lagrange's equations; [`Error::Singular`] if the mass matrix is.
    fn accelerations(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qdot: &SVector<f64, N>,
    ) -> Result<SVector<f64, N>> {
        let (lq, h, lvt) = self.second_order_terms(t, q, qdot)?;
        let rhs = lq - h.pq * qdot - lvt + self.total_force(t, q, qdot);
        let inv = checked_inverse(&h.pp, "mass matrix ∂²L/∂q̇²", || {
            format!("q = {q:?}, q̇ = {qdot:?}")
        })?;
        finite_out("q̈", t, q, qdot, inv * rhs)
    }

    /// `(∂L/∂q, Hessian of L over (q, q̇), ∂²L/∂t∂q̇)` — the ingredients of Lagrange's equations.
    #[doc(hidden)]
    fn second_order_terms(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qdot: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, crate::PhaseMatrix<N>, SVector<f64, N>)> {
        check_state(t, q, qdot)?;
        let (_, lq, _, h) = phase_hessian(|a, b| self.lagrangian(From::from(t), a, b), q, qdot);
        let td = Dual64::new(t, 1.0);
        let (_, _, lv) = phase_gradient(
            |a, b| self.lagrangian(PhaseDual::from_re(td), a, b),
            &lift::<Dual64, N>(q),
            &lift::<Dual64, N>(qdot),
        );
        let lvt = lv.map(|v| v.eps);
        if lq.iter().chain(lvt.iter()).all(|x| x.is_finite()) && h.is_finite() {
            Ok((lq, h, lvt))
        } else {
            Err(Error::NonFinite {
                what: format!("derivatives of L at t = {t}, q = {q:?}, q̇ = {qdot:?}"),
                value: f64::NAN,
            })
        }
    }

    /// Jacobi integral `h = q̇·∂L/∂q̇ − L` [Ardema eq. 8.12]; constant when `L` has no explicit `t`,
    /// the forces derive from a potential and the constraints are catastatic.
    fn jacobi_integral(&self, t: f64, q: &SVector<f64, N>, qdot: &SVector<f64, N>) -> Result<f64> {
        check_state(t, q, qdot)?;
        let (l, _, lv) =
            phase_gradient(|a, b| self.lagrangian(PhaseDual::from_re(t), a, b), q, qdot);
        let h = qdot.dot(&lv) - l;
        finite(
            format_args!("Jacobi integral at t = {t}, q = {q:?}, q̇ = {qdot:?}"),
            h,
        )
    }
}

/// Reject NaN/∞ in `(t, q, q̇)`, naming the component.
pub(crate) fn check_state<const N: usize>(
    t: f64,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
) -> Result<()> {
    finite("t", t)?;
    all_finite("q", q.as_slice())?;
    all_finite("q̇", qdot.as_slice())
}

/// Return `x` if all its entries are finite, else [`Error::NonFinite`] naming the quantity and state.
fn finite_out<X, const N: usize>(
    what: &str,
    t: f64,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
    x: X,
) -> Result<X>
where
    for<'a> &'a X: IntoIterator<Item = &'a f64>,
{
    let bad = (&x).into_iter().find(|v| !v.is_finite()).copied();
    match bad {
        None => Ok(x),
        Some(value) => Err(Error::NonFinite {
            what: format!(
                "{what} at t = {t}, q = {q:?}, q̇ = {qdot:?} (outside the system's domain?)"
            ),
            value,
        }),
    }
}

/// `L` seen as a phase function of `(q, q̇)` in the `(q, p)` slots.
struct LagrangianSlots<'a, L: ?Sized>(&'a L);
impl<const N: usize, L: Lagrangian<N> + ?Sized> PhaseFunction<N> for LagrangianSlots<'_, L> {
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> D {
        self.0.lagrangian(t, q, v)
    }
}

/// Solve `∂Φ/∂x_i (t, q, x) = y_i` for the `i` with `solve_for[i]` (the other `x_i` are held at
/// `y_i`), by Newton's method with the AD Hessian `∂²Φ/∂x²`, in any number type
/// ([`crate::implicit`]). Starts from zero on the solved slots (the natural guess for velocities
/// and momenta) and, if that fails (e.g. `L = q̇⁴/4`, whose mass matrix vanishes at `q̇ = 0`), from
/// `x = y` (unit mass).
pub(crate) fn solve_gradient_equation<F, D, const N: usize>(
    phi: &F,
    t: D,
    q: &SVector<D, N>,
    y: &SVector<D, N>,
    solve_for: &[bool; N],
    what: &str,
) -> Result<SVector<D, N>>
where
    F: PhaseFunction<N> + ?Sized,
    D: DualNum<f64> + Copy,
{
    let yr = real_parts(y);
    let starts = [
        SVector::from_fn(|i, _| if solve_for[i] { 0.0 } else { yr[i] }),
        yr,
    ];
    let system = GradientEquation {
        phi,
        solve_for: *solve_for,
    };
    Ok(implicit::solve(&system, t, q, y, &starts, what)?.0)
}

/// The Legendre transform of a Lagrangian, usable as a [`Hamiltonian`] everywhere in the crate.
///
/// `H(t, q, p) = p·q̇ − L(t, q, q̇)`, `q̇` solving `∂L/∂q̇ = p`; the forces `Q^nc − ∂D/∂q̇` of `L` are
/// carried over as the Hamiltonian's generalized forces, evaluated at `q̇(t, q, p)`. Where the
/// Newton solve fails the Hamiltonian evaluates to NaN and the checked methods
/// ([`Hamiltonian::vector_field`], [`Legendre::velocity`]) report the error.
#[derive(Clone, Debug)]
pub struct Legendre<L>(pub L);

impl<L> Legendre<L> {
    /// Velocities `q̇(t, q, p)` solving `∂L/∂q̇ = p`.
    pub fn velocity<const N: usize>(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<SVector<f64, N>>
    where
        L: Lagrangian<N>,
    {
        velocity_from_momentum(&self.0, t, q, p)
    }
}

/// The velocities `q̇` with `∂L/∂q̇(t, q, q̇) = p`: the inverse Legendre map of `lagrangian`, by
/// Newton's method with the AD mass matrix (as [`Legendre::velocity`]).
///
/// # Errors
/// [`Error::NonFinite`] for non-finite input; [`Error::Singular`] or [`Error::NotConverged`]
/// where the Newton solve fails (a singular mass matrix names the configuration).
pub fn velocity_from_momentum<L: Lagrangian<N> + ?Sized, const N: usize>(
    lagrangian: &L,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<SVector<f64, N>> {
    check_phase(t, q, p)?;
    solve_gradient_equation(
        &LagrangianSlots(lagrangian),
        t,
        q,
        p,
        &[true; N],
        "Legendre transform ∂L/∂q̇ = p",
    )
}

/// NaN with NaN in every derivative slot that `x` carries, so a failed inner solve cannot pass as a
/// value with zero derivatives.
fn nan<D: DualNum<f64> + Copy, const N: usize>(x: &SVector<D, N>) -> D {
    x.iter()
        .fold(D::from(f64::NAN), |acc, &xi| acc + xi * f64::NAN)
}

impl<const N: usize, L: Lagrangian<N>> Hamiltonian<N> for Legendre<L> {
    /// As the default, but a failed Legendre solve is reported with its cause
    /// ([`Error::Singular`], [`Error::NotConverged`]) rather than as a non-finite result.
    fn vector_field(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        self.velocity(t, q, p)?;
        checked_vector_field(self, t, q, p)
    }

    fn hamiltonian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, p: &SVector<D, N>) -> D {
        match solve_gradient_equation(&LagrangianSlots(&self.0), t, q, p, &[true; N], "Legendre") {
            Ok(v) => p.dot(&v) - self.0.lagrangian(t, q, &v),
            Err(_) => nan(p),
        }
    }

    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> Option<SVector<D, N>> {
        if self.0.generalized_force(t, q, p).is_none() && self.0.dissipation(t, q, p).is_none() {
            return None;
        }
        Some(
            match solve_gradient_equation(
                &LagrangianSlots(&self.0),
                t,
                q,
                p,
                &[true; N],
                "Legendre",
            ) {
                Ok(v) => self.0.total_force(t, q, &v),
                Err(_) => SVector::from_element(nan(p)),
            },
        )
    }
}

/// `H` seen as a phase function in the `(q, p)` slots.
struct HamiltonianSlots<'a, H: ?Sized>(&'a H);
impl<const N: usize, H: Hamiltonian<N> + ?Sized> PhaseFunction<N> for HamiltonianSlots<'_, H> {
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, p: &SVector<D, N>) -> D {
        self.0.hamiltonian(t, q, p)
    }
}

/// The inverse Legendre transform of a Hamiltonian: `L(t, q, q̇) = p·q̇ − H(t, q, p)` with `p`
/// solving `∂H/∂p = q̇` (requires `∂²H/∂p²` non-singular). The Hamiltonian's generalized forces
/// become the Lagrangian's `Q^nc`.
#[derive(Clone, Debug)]
pub struct InverseLegendre<H>(pub H);

impl<const N: usize, H: Hamiltonian<N>> Lagrangian<N> for InverseLegendre<H> {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> D {
        match solve_gradient_equation(
            &HamiltonianSlots(&self.0),
            t,
            q,
            v,
            &[true; N],
            "inverse Legendre",
        ) {
            Ok(p) => p.dot(v) - self.0.hamiltonian(t, q, &p),
            Err(_) => nan(v),
        }
    }

    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        v: &SVector<D, N>,
    ) -> Option<SVector<D, N>> {
        self.0.generalized_force(t, q, v)?;
        Some(
            match solve_gradient_equation(
                &HamiltonianSlots(&self.0),
                t,
                q,
                v,
                &[true; N],
                "inverse Legendre",
            ) {
                Ok(p) => self
                    .0
                    .generalized_force(t, q, &p)
                    .unwrap_or_else(SVector::zeros),
                Err(_) => SVector::from_element(nan(v)),
            },
        )
    }
}

/// A natural (holonomic) system: `T = ½ q̇ᵀ a(t, q) q̇ + b(t, q)ᵀ q̇ + c(t, q)` and potential `V(t, q)`
/// [Ardema 6.1, eqs. 6.2–6.6]; `a` symmetric positive definite.
///
/// [`Natural`] turns it into a [`Lagrangian`] and [`NaturalHamiltonian`] into the closed-form
/// Legendre transform `H = ½ (p − b)ᵀ a⁻¹ (p − b) − c + V` [Ardema eq. 15.8].
pub trait NaturalSystem<const N: usize> {
    /// Mass matrix `a(t, q)`.
    fn mass<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> SMatrix<D, N, N>;
    /// Gyroscopic (linear) coefficients `b(t, q)`; zero by default.
    fn linear<D: DualNum<f64> + Copy>(&self, _t: D, _q: &SVector<D, N>) -> SVector<D, N> {
        SVector::zeros()
    }
    /// Velocity-independent kinetic term `c(t, q)`; zero by default.
    fn constant_kinetic<D: DualNum<f64> + Copy>(&self, _t: D, _q: &SVector<D, N>) -> D {
        D::from(0.0)
    }
    /// Potential `V(t, q)`.
    fn potential<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D;
}

/// A [`NaturalSystem`] as a [`Lagrangian`]: `L = ½ q̇ᵀ a q̇ + bᵀ q̇ + c − V`.
#[derive(Clone, Debug)]
pub struct Natural<S>(pub S);

impl<const N: usize, S: NaturalSystem<N>> Lagrangian<N> for Natural<S> {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> D {
        let a = self.0.mass(t, q);
        (a * v).dot(v) * 0.5 + self.0.linear(t, q).dot(v) + self.0.constant_kinetic(t, q)
            - self.0.potential(t, q)
    }
}

/// A [`NaturalSystem`] as a [`Hamiltonian`], by the closed-form Legendre transform
/// `H = ½ (p − b)ᵀ a⁻¹ (p − b) − c + V`. NaN where `a` is singular.
#[derive(Clone, Debug)]
pub struct NaturalHamiltonian<S>(pub S);

impl<const N: usize, S: NaturalSystem<N>> Hamiltonian<N> for NaturalHamiltonian<S> {
    fn hamiltonian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, p: &SVector<D, N>) -> D {
        // Only the symmetric part of `a` enters T; use it here too so that L and H stay a pair.
        let a = self.0.mass(t, q);
        let a = (a + a.transpose()) * D::from(0.5);
        let w = p - self.0.linear(t, q);
        match LU::new(a) {
            Ok(lu) => {
                lu.solve(&w).dot(&w) * 0.5 - self.0.constant_kinetic(t, q) + self.0.potential(t, q)
            }
            Err(_) => nan(p),
        }
    }
}

/// Routh's procedure [Ardema 8.3]: a Lagrangian with `N` coordinates reduced to the `R` retained
/// ones by fixing the momenta `C_β = ∂L/∂q̇_β` of the ignorable coordinates `q_β`.
///
/// `R(t, q_a, q̇_a) = L − Σ_β C_β q̇_β` with `q̇_β` solving `∂L/∂q̇_β = C_β`; it is a [`Lagrangian`]
/// in the retained coordinates, whose equations are those of the reduced motion. The ignorable
/// velocities are recovered by [`Routhian::ignorable_velocities`] (`q̇_β = −∂R/∂C_β`).
///
/// `L` is evaluated with `q_β = 0`: it must not depend on the ignorable coordinates, and forces must
/// not act on them. Naming a coordinate that is not ignorable gives a meaningless reduction, which
/// [`Routhian::ignorability_defect`] detects at any state.
#[derive(Clone, Debug)]
pub struct Routhian<L, const N: usize, const R: usize> {
    lagrangian: L,
    retained: [usize; R],
    ignorable: Vec<usize>,
    momenta: Vec<f64>,
}

impl<L: Lagrangian<N>, const N: usize, const R: usize> Routhian<L, N, R> {
    /// Reduce `lagrangian` by the ignorable coordinates `ignorable` with momenta `momenta`.
    /// The retained coordinates are the others, in increasing order. Errors if the indices are out
    /// of range or repeated, if `R ≠ N − ignorable.len()`, or if a momentum is not finite.
    pub fn new(lagrangian: L, ignorable: &[usize], momenta: &[f64]) -> Result<Self> {
        all_finite("momenta", momenta)?;
        let mut seen = [false; N];
        for &i in ignorable {
            if i >= N || seen[i] {
                return Err(Error::invalid(
                    "ignorable",
                    format!("index {i} out of range 0..{N} or repeated"),
                ));
            }
            seen[i] = true;
        }
        if ignorable.len() != momenta.len() || N - ignorable.len() != R {
            return Err(Error::invalid(
                "ignorable",
                format!(
                    "{} ignorable coordinates with {} momenta cannot reduce {N} to {R}",
                    ignorable.len(),
                    momenta.len()
                ),
            ));
        }
        let mut retained = [0; R];
        for (slot, i) in retained.iter_mut().zip((0..N).filter(|i| !seen[*i])) {
            *slot = i;
        }
        Ok(Self {
            lagrangian,
            retained,
            ignorable: ignorable.to_vec(),
            momenta: momenta.to_vec(),
        })
    }

    /// Full `(q, y)` for the solve: `y_β = C_β` on ignorable slots, `q̇_a` on retained ones.
    fn embed<D: DualNum<f64> + Copy>(
        &self,
        q_a: &SVector<D, R>,
        v_a: &SVector<D, R>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        let mut q = SVector::<D, N>::zeros();
        let mut y = SVector::<D, N>::zeros();
        for (k, &i) in self.retained.iter().enumerate() {
            q[i] = q_a[k];
            y[i] = v_a[k];
        }
        for (&i, &c) in self.ignorable.iter().zip(&self.momenta) {
            y[i] = D::from(c);
        }
        (q, y)
    }

    fn full_velocity<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q_a: &SVector<D, R>,
        v_a: &SVector<D, R>,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        let (q, y) = self.embed(q_a, v_a);
        let mut solve_for = [false; N];
        for &i in &self.ignorable {
            solve_for[i] = true;
        }
        let v = solve_gradient_equation(
            &LagrangianSlots(&self.lagrangian),
            t,
            &q,
            &y,
            &solve_for,
            "Routhian ∂L/∂q̇_β = C_β",
        )?;
        Ok((q, v))
    }

    /// How far the named coordinates are from ignorable at a state: the largest of
    /// `|∂L/∂q_β|` and `|Q_β|` (non-conservative and dissipative forces on `q_β`), evaluated with
    /// `q_β = 0`. Zero (to rounding) for a valid reduction; the Routhian itself cannot check this
    /// at every evaluation.
    pub fn ignorability_defect(
        &self,
        t: f64,
        q_a: &SVector<f64, R>,
        v_a: &SVector<f64, R>,
    ) -> Result<f64> {
        check_state(t, q_a, v_a)?;
        let (q, v) = self.full_velocity(t, q_a, v_a)?;
        let (_, lq, _) = phase_gradient(
            |a, b| self.lagrangian.lagrangian(PhaseDual::from_re(t), a, b),
            &q,
            &v,
        );
        let f = self.lagrangian.total_force(t, &q, &v);
        let d = self
            .ignorable
            .iter()
            .map(|&i| lq[i].abs().max(f[i].abs()))
            .fold(0.0, f64::max);
        finite("ignorability defect", d)
    }

    /// Velocities of the ignorable coordinates, `q̇_β(t, q_a, q̇_a)`, in the order given to `new`.
    pub fn ignorable_velocities(
        &self,
        t: f64,
        q_a: &SVector<f64, R>,
        v_a: &SVector<f64, R>,
    ) -> Result<Vec<f64>> {
        check_state(t, q_a, v_a)?;
        let (_, v) = self.full_velocity(t, q_a, v_a)?;
        Ok(self.ignorable.iter().map(|&i| v[i]).collect())
    }
}

impl<L: Lagrangian<N>, const N: usize, const R: usize> Lagrangian<R> for Routhian<L, N, R> {
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q_a: &SVector<D, R>,
        v_a: &SVector<D, R>,
    ) -> D {
        match self.full_velocity(t, q_a, v_a) {
            Ok((q, v)) => {
                let cv = self
                    .ignorable
                    .iter()
                    .zip(&self.momenta)
                    .fold(D::from(0.0), |s, (&i, &c)| s + v[i] * c);
                self.lagrangian.lagrangian(t, &q, &v) - cv
            }
            Err(_) => nan(v_a),
        }
    }

    /// The retained components of the underlying `Q^nc − ∂D/∂q̇`, evaluated at the full state.
    /// Routh's reduction assumes these forces do not act on the ignorable coordinates (else `C_β`
    /// would not be constant); [`Routhian::ignorability_defect`] measures that.
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q_a: &SVector<D, R>,
        v_a: &SVector<D, R>,
    ) -> Option<SVector<D, R>> {
        let (q, y) = self.embed(q_a, v_a);
        if self.lagrangian.generalized_force(t, &q, &y).is_none()
            && self.lagrangian.dissipation(t, &q, &y).is_none()
        {
            return None;
        }
        Some(match self.full_velocity(t, q_a, v_a) {
            Ok((q, v)) => {
                let f = self.lagrangian.total_force(t, &q, &v);
                SVector::from_fn(|k, _| f[self.retained[k]])
            }
            Err(_) => SVector::from_element(nan(v_a)),
        })
    }
}
/// Residual `∂Φ/∂x_i (t, q, x) − y_i` on the slots with `solve_for[i]`, `x_i − y_i` on the others:
/// the gradient equation behind the Legendre transform (`Φ = L`, unknown `q̇`) and its inverse.
struct GradientEquation<'a, F: ?Sized, const N: usize> {
    phi: &'a F,
    solve_for: [bool; N],
}

impl<F: PhaseFunction<N> + ?Sized, const N: usize> ImplicitSystem<N>
    for GradientEquation<'_, F, N>
{
    fn residual<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        y: &SVector<D, N>,
        x: &SVector<D, N>,
    ) -> SVector<D, N> {
        let (_, _, g) = crate::ad::phase_gradient(
            |a, b| self.phi.eval(crate::ad::PhaseDual::from_re(t), a, b),
            q,
            x,
        );
        SVector::from_fn(|i, _| {
            if self.solve_for[i] {
                g[i] - y[i]
            } else {
                x[i] - y[i]
            }
        })
    }
}
