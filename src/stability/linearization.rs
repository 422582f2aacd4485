//! Linearisation of `ż = f(t, z)` about a reference motion by AD, and the reduction of a system
//! with cyclic coordinates to the variables in which a steady motion is an equilibrium
//! [Ardema 12.3, eqs. 12.12–12.15; Hamel art. 243–244] (SPEC M34).
//!
//! * Perturbations `η = z − z*` obey `η̇ = A η`, `A = ∂f/∂z (t, z*)`, the Jacobian of the one
//!   definition of `f` taken by forward-mode AD ([`linearize`]).
//! * A **steady motion** of a system whose state splits as `(q, p)` (Hamilton's equations, or
//!   the reduced equations `(q̇, ω̇)` of a non-holonomic system in quasi-velocities) is a motion on
//!   which some coordinates `q_c` change at constant rates and everything else is constant, the
//!   field not depending on the `q_c` (cyclic coordinates). In the remaining variables — chosen
//!   as [`Slot`]s — it is an equilibrium of the field [`Reduced`], which holds the other entries
//!   at their reference values; [`Reduced::cyclic_defect`] measures, by AD, how much the kept
//!   rates depend on the held entries (zero for truly cyclic coordinates).

use crate::ad::{lift, GradDual};
use crate::constraints::QuasiVelocities;
use crate::error::{all_finite, finite, Error, Result};
use crate::hamilton_jacobi::VectorField;
use crate::hamiltonian::Hamiltonian;
use crate::lagrangian::Lagrangian;
use crate::nonholonomic::BoltzmannHamel;
use nalgebra::{Const, SMatrix, SVector};
use num_dual::DualNum;

/// The Jacobian `A = ∂f/∂z` of a vector field at `(t, z)` by forward-mode AD (SPEC M34:
/// `linearize(rhs, y_ref, t)`).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ in `t`, `z`, the field or its Jacobian (outside the field's
/// domain).
pub fn linearize<X: VectorField<M> + ?Sized, const M: usize>(
    field: &X,
    t: f64,
    z: &SVector<f64, M>,
) -> Result<SMatrix<f64, M, M>> {
    finite("t", t)?;
    all_finite("z", z.as_slice())?;
    let zd: SVector<GradDual<f64, f64, Const<M>>, M> =
        SVector::from_fn(|i, _| GradDual::variable(z[i], i));
    let y = field.field(GradDual::from_re(t), &zd);
    let value = y.map(|x| *x.value());
    all_finite(format_args!("f at t = {t}, z = {z:?}"), value.as_slice())?;
    let a = SMatrix::<f64, M, M>::from_fn(|r, c| y[r].eps()[c]);
    all_finite(format_args!("∂f/∂z at t = {t}, z = {z:?}"), a.as_slice())?;
    Ok(a)
}

/// A first-order system on `ℝᴺ × ℝᴺ`, `(q̇, ṗ) = f(t, q, p)`, written once for every dual type
/// (the generic counterpart of [`FirstOrderSystem`](crate::integrate::FirstOrderSystem)).
/// Outside its domain the values are NaN.
pub trait SplitVectorField<const N: usize> {
    /// `(q̇, ṗ)` at `(t, q, p)`.
    #[allow(clippy::type_complexity)]
    fn split_field<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>);
}

/// Hamilton's equations with the system's non-conservative forces.
impl<H: Hamiltonian<N>, const N: usize> SplitVectorField<N> for H {
    fn split_field<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        self.vector_field_generic(t, q, p)
    }
}

/// The Boltzmann–Hamel equations in the state `(q, ω)`, the constrained quasi-velocities held at
/// zero (NaN where `b` or the free block of `∂²T/∂ω²` is singular, or the layout of the
/// quasi-velocities is inconsistent).
impl<L: Lagrangian<N>, Q: QuasiVelocities<N>, const N: usize> SplitVectorField<N>
    for BoltzmannHamel<L, Q, N>
{
    fn split_field<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        w: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        self.field_dual(t, q, w).unwrap_or_else(|_| {
            let nan = SVector::from_element(D::from(f64::NAN));
            (nan, nan)
        })
    }
}

/// One entry of a split state `(q, p)`: the coordinate `q_i` or the momentum (velocity,
/// quasi-velocity) `p_i`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Slot {
    /// `q_i`.
    Q(usize),
    /// `p_i`.
    P(usize),
}

/// The field of the `M` variables `slots` of a split system, the other entries of `(q, p)` held
/// at a reference state (see the [module docs](self)): a steady motion of the full system is an
/// equilibrium of this field.
#[derive(Clone, Debug)]
pub struct Reduced<'a, S: ?Sized, const N: usize, const M: usize> {
    system: &'a S,
    q: SVector<f64, N>,
    p: SVector<f64, N>,
    slots: [Slot; M],
}

impl<'a, S: SplitVectorField<N> + ?Sized, const N: usize, const M: usize> Reduced<'a, S, N, M> {
    /// The variables `slots` of `system`, the others held at their values in the reference
    /// state `(q, p)`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ in the reference state or in the field there;
    /// [`Error::InvalidInput`] for a slot out of range or repeated.
    pub fn new(
        system: &'a S,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        slots: [Slot; M],
    ) -> Result<Self> {
        all_finite("reference q", q.as_slice())?;
        all_finite("reference p", p.as_slice())?;
        for (k, s) in slots.iter().enumerate() {
            let i = match s {
                Slot::Q(i) | Slot::P(i) => *i,
            };
            if i >= N || slots[..k].contains(s) {
                return Err(Error::invalid(
                    "reduced variables",
                    format!("{s:?} is out of range (N = {N}) or repeated in {slots:?}"),
                ));
            }
        }
        let (qd, pd) = system.split_field(0.0, q, p);
        all_finite(
            format_args!("field at the reference state q = {q:?}, p = {p:?}"),
            qd.iter()
                .chain(pd.iter())
                .copied()
                .collect::<Vec<_>>()
                .as_slice(),
        )?;
        Ok(Self {
            system,
            q: *q,
            p: *p,
            slots,
        })
    }

    /// The reduced state of the reference: `z_k` = the entry `slots[k]` of `(q, p)`.
    pub fn state(&self) -> SVector<f64, M> {
        SVector::from_fn(|k, _| match self.slots[k] {
            Slot::Q(i) => self.q[i],
            Slot::P(i) => self.p[i],
        })
    }

    /// The full state `(q, p)` of the reduced state `z`.
    pub fn embed<D: DualNum<f64> + Copy>(
        &self,
        z: &SVector<D, M>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        let mut q: SVector<D, N> = lift(&self.q);
        let mut p: SVector<D, N> = lift(&self.p);
        for (k, s) in self.slots.iter().enumerate() {
            match *s {
                Slot::Q(i) => q[i] = z[k],
                Slot::P(i) => p[i] = z[k],
            }
        }
        (q, p)
    }

    /// How much the steady-motion reduction is violated at the reduced state `z`, by AD:
    /// `max |∂ż/∂h|` over the held entries `h` of `(q, p)` relative to `max(1, ‖∂ż/∂z‖_max)`
    /// (zero when the held coordinates are cyclic), and the largest rate `|ḣ|` of a held
    /// momentum (zero when the held momenta are at rest). Both vanish, to rounding, for a valid
    /// reduction.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ in `t`, `z` or the derivatives.
    pub fn cyclic_defect(&self, t: f64, z: &SVector<f64, M>) -> Result<(f64, f64)> {
        finite("t", t)?;
        all_finite("z", z.as_slice())?;
        let (q, p) = self.embed(z);
        // Derivatives with respect to all 2N entries, in two passes of N.
        let kept_rows =
            |qd: &SVector<_, N>, pd: &SVector<_, N>| -> Vec<GradDual<f64, f64, Const<N>>> {
                self.slots
                    .iter()
                    .map(|s| match *s {
                        Slot::Q(i) => qd[i],
                        Slot::P(i) => pd[i],
                    })
                    .collect()
            };
        let seed = |x: &SVector<f64, N>| -> SVector<GradDual<f64, f64, Const<N>>, N> {
            SVector::from_fn(|i, _| GradDual::variable(x[i], i))
        };
        let t_d = GradDual::from_re(t);
        let (qd1, pd1) = self
            .system
            .split_field(t_d, &seed(&q), &p.map(GradDual::from_re));
        let (qd2, pd2) = self
            .system
            .split_field(t_d, &q.map(GradDual::from_re), &seed(&p));
        let by_q = kept_rows(&qd1, &pd1);
        let by_p = kept_rows(&qd2, &pd2);
        let held_q: Vec<usize> = (0..N)
            .filter(|i| !self.slots.contains(&Slot::Q(*i)))
            .collect();
        let held_p: Vec<usize> = (0..N)
            .filter(|i| !self.slots.contains(&Slot::P(*i)))
            .collect();
        let mut kept_scale: f64 = 1.0;
        let mut held: f64 = 0.0;
        for (rows, held_entries) in [(&by_q, &held_q), (&by_p, &held_p)] {
            for row in rows.iter() {
                for i in 0..N {
                    let d = row.eps()[i].abs();
                    if held_entries.contains(&i) {
                        held = held.max(d);
                    } else {
                        kept_scale = kept_scale.max(d);
                    }
                }
            }
        }
        let rate = held_p
            .iter()
            .map(|&i| pd1[i].value().abs())
            .fold(0.0, f64::max);
        let defect = finite("cyclic defect", held / kept_scale)?;
        Ok((defect, finite("rate of a held momentum", rate)?))
    }
}

impl<S: SplitVectorField<N> + ?Sized, const N: usize, const M: usize> VectorField<M>
    for Reduced<'_, S, N, M>
{
    fn field<D: DualNum<f64> + Copy>(&self, t: D, z: &SVector<D, M>) -> SVector<D, M> {
        let (q, p) = self.embed(z);
        let (qd, pd) = self.system.split_field(t, &q, &p);
        SVector::from_fn(|k, _| match self.slots[k] {
            Slot::Q(i) => qd[i],
            Slot::P(i) => pd[i],
        })
    }
}
