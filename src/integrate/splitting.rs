//! Explicit splitting and composition methods for separable `H = T(p) + V(q)`, run by one
//! composition kernel over the `const` tables of [`coefficients`].
//!
//! The exact flows of the two parts are explicit:
//!
//! ```math
//! \varphi^{T}_{h}:\ q \mapsto q + h\,\nabla T(p)\ \text{(drift)},\qquad
//! \varphi^{V}_{h}:\ p \mapsto p - h\,\nabla V(q)\ \text{(kick)},
//! ```
//!
//! and a method is a word `Ψ_h = φ^{X_m}_{c_m h} ∘ … ∘ φ^{X_1}_{c_1 h}` in them (Hairer, Lubich &
//! Wanner, *Geometric Numerical Integration*, 2nd ed., Springer 2006, ch. II.5 and V.3,
//! doi:10.1007/3-540-30666-8; McLachlan & Quispel, "Splitting methods", Acta Numerica 11 (2002)
//! 341–434, doi:10.1017/S0962492902000053). Each sub-flow is the exact flow of a Hamiltonian, so
//! the step is symplectic for every table; symmetric words give time-reversible methods.
//!
//! Requirements on the system: [`Separable`] (a bound on the `OneStep` implementation, so that a
//! non-separable `H` does not compile), no non-conservative forces (a typed error), and `T`
//! independent of `t` for the nominal order (`V` may depend on `t`: the time advances with the
//! drifts, and the kicks see the current time).
//!
//! Cost per step: one AD gradient of `V` per kick and one of `T` per drift
//! ([`Work::gradients`](super::Work) counts both); [`Table::evaluations`] gives the numbers. The
//! compositions run drift–kick–drift Verlet with the half-drifts merged, so their `s` kicks per
//! step are exactly `s` force evaluations with no bookkeeping across steps. Kick–drift–kick
//! Verlet and Blanes–Moan begin and end with a kick at the same position; the stateless step
//! evaluates both (2 resp. 7 per step), where a long run with FSAL would need 1 resp. 6.

use super::coefficients::{self, Flow, Table};
use super::methods::{Construction, METHODS};
use super::sensitivity::Unparametrised;
use super::{OneStep, Work};
use crate::error::{Error, Result};
use crate::hamiltonian::{ParametricSeparable, Separable};
use nalgebra::SVector;
use num_dual::DualNum;

/// The two exact sub-flows of a splitting, for one dual type `D`.
pub(crate) trait SubFlows<D: DualNum<f64> + Copy, const N: usize> {
    /// The `A` flow over `h` from `(t, q, p)`: its increments `(Δq, Δp)`.
    fn flow_a(
        &mut self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        h: D,
    ) -> Result<(SVector<D, N>, SVector<D, N>)>;
    /// The `B` flow (a kick, `q` fixed) over `h` from `(t, q)`: its increment `Δp`.
    fn flow_b(&mut self, t: D, q: &SVector<D, N>, h: D) -> Result<SVector<D, N>>;
    /// Whether the `A` sub-step is the flow of a Hamiltonian, `φ_a ∘ φ_b = φ_{a+b}`, so that a
    /// long run may merge adjacent `A` sub-steps of consecutive steps (the kicks always are).
    fn a_composes(&self) -> bool {
        true
    }
}

/// A word in the two flows: the sub-steps `(flow, c)` of a composition, in the order applied,
/// each over `c·dt`.
pub(crate) trait Word {
    /// Call `f(flow, c)` for each sub-step in the order applied.
    fn for_each_sub_step<E>(
        &self,
        f: impl FnMut(Flow, f64) -> std::result::Result<(), E>,
    ) -> std::result::Result<(), E>;
}

impl Word for Table {
    #[inline]
    fn for_each_sub_step<E>(
        &self,
        f: impl FnMut(Flow, f64) -> std::result::Result<(), E>,
    ) -> std::result::Result<(), E> {
        Table::for_each_sub_step(self, f)
    }
}

/// The composition kernel: run `word` over the step `dt` from `(t, q, p)` and return the
/// accumulated increments `(Δq, Δp)`. The time seen by a sub-flow is `t` plus the `A`-time
/// elapsed before it.
#[inline]
pub(crate) fn compose<W: Word + ?Sized, D, F, const N: usize>(
    word: &W,
    flows: &mut F,
    t: D,
    q: &SVector<D, N>,
    p: &SVector<D, N>,
    dt: D,
) -> Result<(SVector<D, N>, SVector<D, N>)>
where
    D: DualNum<f64> + Copy,
    F: SubFlows<D, N>,
{
    let mut dq = SVector::<D, N>::zeros();
    let mut dp = SVector::<D, N>::zeros();
    let mut elapsed = D::from(0.0);
    word.for_each_sub_step(|flow, c| {
        if c == 0.0 {
            return Ok(());
        }
        let h = dt * c;
        match flow {
            Flow::A => {
                let (a, b) = flows.flow_a(t + elapsed, &(q + dq), &(p + dp), h)?;
                dq += a;
                dp += b;
                elapsed += h;
            }
            Flow::B => dp += flows.flow_b(t + elapsed, &(q + dq), h)?,
        }
        Ok(())
    })?;
    Ok((dq, dp))
}

/// Drift and kick of a [`ParametricSeparable`] system at parameters `k` given in the dual type of
/// the step, so that the step carries derivatives with respect to `k`; counting gradients.
struct ParametricFlows<'a, S, D, const M: usize> {
    system: &'a S,
    k: &'a SVector<D, M>,
    work: &'a mut Work,
}

impl<S, D, const N: usize, const M: usize> SubFlows<D, N> for ParametricFlows<'_, S, D, M>
where
    S: ParametricSeparable<N, M>,
    D: DualNum<f64> + Copy,
{
    #[inline]
    fn flow_a(
        &mut self,
        t: D,
        _q: &SVector<D, N>,
        p: &SVector<D, N>,
        h: D,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        self.work.gradients += 1;
        let (_, tp) = self.system.kinetic_gradient_with(self.k, t, p);
        Ok((tp * h, SVector::zeros()))
    }
    #[inline]
    fn flow_b(&mut self, t: D, q: &SVector<D, N>, h: D) -> Result<SVector<D, N>> {
        self.work.gradients += 1;
        let (_, vq) = self.system.potential_gradient_with(self.k, t, q);
        Ok(vq * (-h))
    }
}

/// An explicit splitting or composition method for separable `H = T(p) + V(q)`, defined by a
/// coefficient [`Table`].
///
/// ```
/// use hamilton_jacobi::integrate::{integrate, Fixed, Problem, Splitting};
/// use hamilton_jacobi::systems::Pendulum;
/// use hamilton_jacobi::nalgebra::SVector;
/// let pendulum = Pendulum::new(1.0).unwrap();
/// let problem = Problem::new(&pendulum, 0.0, SVector::from([1.0]), SVector::from([0.0]), 1.0).unwrap();
/// let run = integrate(&problem, &Fixed::new(Splitting::KAHAN_LI17, 10).unwrap(), &mut ()).unwrap();
/// assert_eq!(run.work.gradients, 10 * (17 + 18)); // 17 kicks and 18 drifts per step
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Splitting {
    table: &'static Table,
}

impl Splitting {
    /// Symplectic Euler, kick then drift: 1 stage, order 1 (`symplectic-euler-kd`).
    pub const SYMPLECTIC_EULER_KD: Self = Self::of(&coefficients::SYMPLECTIC_EULER_KD);
    /// Symplectic Euler, drift then kick: 1 stage, order 1 (`symplectic-euler-dk`).
    pub const SYMPLECTIC_EULER_DK: Self = Self::of(&coefficients::SYMPLECTIC_EULER_DK);
    /// Störmer–Verlet, kick–drift–kick: 1 stage, order 2 (`verlet-kdk`).
    pub const VERLET_KDK: Self = Self::of(&coefficients::VERLET_KDK);
    /// Störmer–Verlet, drift–kick–drift: 1 stage, order 2 (`verlet-dkd`).
    pub const VERLET_DKD: Self = Self::of(&coefficients::VERLET_DKD);
    /// Yoshida's triple jump: 3 stages, order 4 (`yoshida3`).
    pub const YOSHIDA3: Self = Self::of(&coefficients::YOSHIDA3);
    /// Suzuki's composition: 5 stages, order 4 (`suzuki5`).
    pub const SUZUKI5: Self = Self::of(&coefficients::SUZUKI5);
    /// Blanes–Moan `SRKN₆ᵇ`: 6 stages (7 kicks per stateless step), order 4 (`blanes-moan6`).
    pub const BLANES_MOAN6: Self = Self::of(&coefficients::BLANES_MOAN6);
    /// Yoshida, solution A: 7 stages, order 6 (`yoshida7`).
    pub const YOSHIDA7: Self = Self::of(&coefficients::YOSHIDA7);
    /// Kahan–Li: 9 stages, order 6 (`kahan-li9`).
    pub const KAHAN_LI9: Self = Self::of(&coefficients::KAHAN_LI9);
    /// Yoshida, solution D: 15 stages, order 8 (`yoshida15`).
    pub const YOSHIDA15: Self = Self::of(&coefficients::YOSHIDA15);
    /// Kahan–Li: 17 stages, order 8 (`kahan-li17`).
    pub const KAHAN_LI17: Self = Self::of(&coefficients::KAHAN_LI17);
    /// Sofroniou–Spaletta: 35 stages, order 10 (`sofroniou-spaletta35`).
    pub const SOFRONIOU_SPALETTA35: Self = Self::of(&coefficients::SOFRONIOU_SPALETTA35);

    const fn of(table: &'static Table) -> Self {
        Self { table }
    }

    /// Every shipped method, lowest order first: the splittings of
    /// [`METHODS`].
    pub fn all() -> Vec<Self> {
        METHODS
            .iter()
            .filter_map(|m| match m.construction {
                Construction::Splitting(t) => Some(Self::of(t)),
                _ => None,
            })
            .collect()
    }

    /// A method from a user's table; rejects tables that are not consistent (`Σ a ≠ 1` or
    /// `Σ b ≠ 1` beyond rounding, non-finite or empty coefficients, an even composition length).
    pub fn new(table: &'static Table) -> Result<Self> {
        check_table(table)?;
        Ok(Self::of(table))
    }

    /// The coefficient table.
    pub fn table(&self) -> &'static Table {
        self.table
    }
}

/// Consistency of a table: finite coefficients with `Σ a = Σ b = 1` (to 1e−13 relative to Σ|c|).
pub(crate) fn check_table(table: &Table) -> Result<()> {
    let empty = match table.scheme {
        coefficients::Scheme::Sequence { coefficients, .. } => coefficients.is_empty(),
        coefficients::Scheme::Composition { half } => half.is_empty(),
    };
    if empty {
        return Err(Error::invalid(
            format!("coefficient table {}", table.label()),
            "no coefficients",
        ));
    }
    let (mut a, mut b, mut scale) = (0.0, 0.0, 0.0f64);
    for (flow, c) in table.sub_steps() {
        if !c.is_finite() {
            return Err(Error::NonFinite {
                what: format!("coefficient of {}", table.label()),
                value: c,
            });
        }
        scale += c.abs();
        match flow {
            Flow::A => a += c,
            Flow::B => b += c,
        }
    }
    let tol = 1e-13 * scale.max(1.0);
    for (part, sum) in [("Σ a (A-flow weights)", a), ("Σ b (B-flow weights)", b)] {
        if (sum - 1.0).abs() > tol {
            return Err(Error::out_of_domain(
                format!("{} of {}", part, table.label()),
                sum,
                "1 (consistency)",
            ));
        }
    }
    Ok(())
}

impl<S: Separable<N>, const N: usize> OneStep<S, N> for Splitting {
    fn order(&self) -> u32 {
        self.table.order
    }
    fn name(&self) -> String {
        self.table.label()
    }
    #[inline]
    fn increment<D: DualNum<f64> + Copy>(
        &self,
        system: &S,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        dt: D,
        work: &mut Work,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        self.conservative(system, t, q, p)?;
        self.increment_at(
            &Unparametrised(system),
            &SVector::zeros(),
            t,
            q,
            p,
            dt,
            work,
        )
    }
}

impl Splitting {
    /// An error for a system with non-conservative forces, which a splitting does not integrate.
    fn conservative<S: Separable<N>, D: DualNum<f64> + Copy, const N: usize>(
        &self,
        system: &S,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> Result<()> {
        if <S as Separable<N>>::generalized_force(system, t, q, p).is_some() {
            return Err(Error::invalid(
                format!("{} on this system", self.table.label()),
                "explicit splitting integrates conservative H = T(p) + V(q) only; \
                 the system has non-conservative forces",
            ));
        }
        Ok(())
    }

    /// The increment of one step of a [`ParametricSeparable`] system at the parameters `k`, given
    /// in the step's number type (derivatives with respect to `k` travel with the state's); a
    /// [`Separable`] system is the one without parameters ([`Unparametrised`]), which
    /// [`OneStep::increment`] runs after checking that it has no non-conservative forces.
    ///
    /// # Errors
    /// None from the composition itself (the sub-flows are explicit).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn increment_at<S, D, const N: usize, const M: usize>(
        &self,
        system: &S,
        k: &SVector<D, M>,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        dt: D,
        work: &mut Work,
    ) -> Result<(SVector<D, N>, SVector<D, N>)>
    where
        S: ParametricSeparable<N, M>,
        D: DualNum<f64> + Copy,
    {
        let mut flows = ParametricFlows { system, k, work };
        compose(self.table, &mut flows, t, q, p, dt)
    }
}
