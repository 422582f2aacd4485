//! Canonical transformations from generating functions of the four classical kinds
//! [Ardema 16.2–16.5, eqs. 16.4–16.39].
//!
//! | kind | arguments `(x, y)` | relations |
//! |---|---|---|
//! | F1 | `(q, Q)` | `p = ∂F/∂q`, `P = −∂F/∂Q` |
//! | F2 | `(q, P)` | `p = ∂F/∂q`, `Q = ∂F/∂P` |
//! | F3 | `(p, Q)` | `q = −∂F/∂p`, `P = −∂F/∂Q` |
//! | F4 | `(p, P)` | `q = −∂F/∂p`, `Q = ∂F/∂P` |
//!
//! In every case the new Hamiltonian is `K(t, Q, P) = H + ∂F/∂t` [Ardema eq. 16.39] (Jacobi's
//! theorem), available as a [`Hamiltonian`] through [`CanonicalTransformation::transform`].
//!
//! **Solving the implicit relations.** The forward map solves `s ∂F/∂x (x, y) = (other old
//! variable)` for the new argument `y`, the inverse solves `s′ ∂F/∂y (x, y) = (other new variable)`
//! for `x`, both by damped Newton with the AD mixed Hessian `B = ∂²F/∂x∂y`
//! ([`crate::implicit`]); derivatives of the maps (their exact Jacobians) come from the same
//! solver in dual arithmetic.
//!
//! **Sheets.** The relation `{(q, p, Q, P)}` a generator defines is a Lagrangian submanifold of
//! the product space, which may project onto either side more than once [Arnold, *Mathematical
//! Methods of Classical Mechanics*, §47–48; Goldstein §9.1]: for `F₁ = ½ m ω q² cot Q` both `(q, p)`
//! and `(−q, −p)` satisfy `p = ∂F₁/∂q`, `P = −∂F₁/∂Q` at the same `(Q, P)`, and every `Q + kπ`
//! satisfies them at the same `(q, p)`. Which root a map returns is its [`Sheet`]: the first root
//! Newton reaches ([`Sheet::First`], right for single-sheeted generators), the unique root accepted
//! by a predicate on `(t, q, p, Q, P)` ([`Sheet::satisfying`]), or the root on the branch through a
//! reference point of the relation, followed by continuation ([`Sheet::through`]). A predicate
//! that accepts none of the roots found, or more than one, is refused with
//! [`Error::NoRootOnSheet`] listing every candidate. The generator may declare its sheet
//! ([`GeneratingFunction::sheet`]); [`CanonicalTransformation::with_sheet`] replaces it and
//! [`CanonicalTransformation::forward_on`] / [`CanonicalTransformation::inverse_on`] take one per
//! call.
//!
//! **Conditioning (caustics, focal points, blow-ups).** Where the projection of the relation onto
//! the generator's arguments folds (a caustic: `det B = 0`, e.g. `F₁ = ½mωq² cot Q` at `q = 0`,
//! `Q = kπ`), or where the generator's second derivatives blow up, the map is formed by amplifying
//! rounding errors. After every solve the first-order rounding error of the result is estimated
//! from the second derivatives `A = F_kk`, `B = F_ku`, `C = F_uu` (known argument `k`, target
//! `b`, solved argument `u`, output `o`), componentwise so that it does not depend on units:
//!
//! ```math
//! \delta u = \varepsilon\, |B^{-1}| (|A||k| + |B||u| + |b|) + |B^{-1}||r|,\qquad
//! \delta o = \varepsilon (|B^{\mathsf T}||k| + |C||u| + |o|) + |C|\,\delta u
//! ```
//!
//! (the inputs and the generator's derivatives each carry a relative rounding `ε`; Newton's
//! correction propagates them through `B⁻¹`; `r` is the residual left at the root, polished by
//! Newton steps while they reduce it). Each block is measured against its size at the point,
//! `S_u = |u| + |B⁻¹A||k| + |B⁻¹||b|` and `S_o = |o| + |Bᵀ − CB⁻¹A||k| + |CB⁻¹||b|` — its value
//! plus the first-order contributions of the inputs through the exact derivatives of the map, so
//! that a block crossing zero (the oscillator's `p` at a turning point) is not mistaken for a loss
//! of accuracy. The **condition number** of the map at the point is
//!
//! ```math
//! \kappa = \max\Big(\frac{\|\delta u\|_\infty}{\varepsilon \|S_u\|_\infty},
//! \frac{\|\delta o\|_\infty}{\varepsilon \|S_o\|_\infty}, \kappa_2(\hat B)\Big),
//! ```
//!
//! with `κ₂(B̂) = σ_max/σ_min` of the Newton Jacobian `B` after two-sided equilibration (by SVD), so
//! that the error of each block is about `κ ε` times its size (error ≈ condition × rounding;
//! Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., §1.6 and §7.2). A result
//! with `κ` above the threshold (default [`DEFAULT_MAX_CONDITION`] `= 10⁶`: at most six of the
//! sixteen digits lost, relative error below `2.2·10⁻¹⁰`) is refused with
//! [`Error::IllConditioned`], naming the threshold and the measured condition; a singular `B` or a
//! non-finite second derivative is [`Error::Singular`]. The measured `κ` and the error bounds are
//! returned by [`CanonicalTransformation::forward_on`] / [`CanonicalTransformation::inverse_on`].
//! Examples: `F₁ = ½mωq² cot Q` mapping `(q, p)` forward near `Q = π` (`κ ≈ π/(π − Q)`: `P` is
//! formed from `sin Q` of a `Q` known only to `ε π`), the free-fall `F₁` at `t → 0` (the identity
//! has no type-1 generator), the oscillator's principal function at its focal point `ωτ → π`
//! (`B = −ω/sin ωτ`). **What to do there:** switch kind — near the identity use an F2
//! (`F₂ = q·P + …`) or F3 generator, near the exchange map an F1 or F4 one; the Legendre relations
//! `F₂ = F₁ + Q·P`, `F₃ = F₁ − q·p`, `F₄ = F₁ + Q·P − q·p` translate between them.

use crate::ad::{phase_gradient, phase_hessian, real_parts, PhaseDual};
use crate::brackets::{certify, Certificate, PhaseMap};
use crate::error::{finite, positive, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::implicit::{self, ImplicitSystem, Root};
use crate::phase::{check_phase, checked_inverse};
use nalgebra::{SMatrix, SVector};
use num_dual::{Dual, DualNum};
use std::fmt;
use std::sync::Arc;

/// The default largest condition number of a map accepted by [`CanonicalTransformation`]:
/// `10⁶`, i.e. a relative error of at most `10⁶ ε ≈ 2.2·10⁻¹⁰` (see the [module docs](self)).
pub const DEFAULT_MAX_CONDITION: f64 = 1e6;

/// A point `(q, p, Q, P)` at time `t` of the relation a generating function defines.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelationPoint<const N: usize> {
    /// Time.
    pub t: f64,
    /// Old coordinates.
    pub q: SVector<f64, N>,
    /// Old momenta.
    pub p: SVector<f64, N>,
    /// New coordinates.
    pub big_q: SVector<f64, N>,
    /// New momenta.
    pub big_p: SVector<f64, N>,
}

/// A predicate on the points of a relation selecting one sheet.
pub type SheetPredicate<const N: usize> = dyn Fn(&RelationPoint<N>) -> bool + Send + Sync;

/// Which root of a multi-sheeted relation a map returns (see the [module docs](self)).
#[derive(Clone)]
pub enum Sheet<const N: usize> {
    /// The first root damped Newton reaches from the default starting points (the generator's
    /// guess, the variable of the same letter, the other one, zero). Right for single-sheeted
    /// generators; for multi-sheeted ones it may return any sheet.
    First,
    /// The unique root, among those Newton reaches from the default starting points and their
    /// negatives, whose point of the relation satisfies `predicate`.
    Satisfying {
        /// The sheet in words, for error messages (e.g. `"q sin Q > 0, −π < Q ≤ π"`).
        description: String,
        /// Accepts the points on the sheet.
        predicate: Arc<SheetPredicate<N>>,
    },
    /// The sheet through a reference point of the relation: the root is continued from the
    /// reference along the straight segment to the point ([`implicit::continue_root`]).
    Through(RelationPoint<N>),
}

impl<const N: usize> Sheet<N> {
    /// The sheet of points accepted by `predicate`, described in words by `description`.
    pub fn satisfying(
        description: impl Into<String>,
        predicate: impl Fn(&RelationPoint<N>) -> bool + Send + Sync + 'static,
    ) -> Self {
        Sheet::Satisfying {
            description: description.into(),
            predicate: Arc::new(predicate),
        }
    }

    /// The sheet through the reference point `reference` of the relation (all of its entries
    /// must be finite; that it lies on the relation is checked when the map is evaluated).
    pub fn through(reference: RelationPoint<N>) -> Result<Self> {
        check_phase(reference.t, &reference.q, &reference.p)?;
        check_phase(reference.t, &reference.big_q, &reference.big_p)?;
        Ok(Sheet::Through(reference))
    }
}

impl<const N: usize> fmt::Display for Sheet<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Sheet::First => write!(f, "first root found"),
            Sheet::Satisfying { description, .. } => write!(f, "{description}"),
            Sheet::Through(r) => write!(
                f,
                "through (q, p, Q, P) = ({:?}, {:?}, {:?}, {:?}) at t = {:e}",
                r.q.as_slice(),
                r.p.as_slice(),
                r.big_q.as_slice(),
                r.big_p.as_slice(),
                r.t
            ),
        }
    }
}

impl<const N: usize> fmt::Debug for Sheet<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Sheet({self})")
    }
}

/// The image of a point under a [`CanonicalTransformation`] with the accuracy of the solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Image<const N: usize> {
    /// Image coordinates (`Q` for the forward map, `q` for the inverse).
    pub q: SVector<f64, N>,
    /// Image momenta (`P` for the forward map, `p` for the inverse).
    pub p: SVector<f64, N>,
    /// The condition number `κ` of the map at the point (see the [module docs](self)).
    pub condition: f64,
    /// Estimated first-order rounding errors (max-norm) of the coordinate and momentum blocks.
    pub error: [f64; 2],
}

/// The four classical kinds of generating function, Ardema's `W₁`–`W₄` [Ardema 16.4].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Kind {
    /// `F1(q, Q, t)`: `p = ∂F/∂q`, `P = −∂F/∂Q`.
    F1,
    /// `F2(q, P, t)`: `p = ∂F/∂q`, `Q = ∂F/∂P`.
    F2,
    /// `F3(p, Q, t)`: `q = −∂F/∂p`, `P = −∂F/∂Q`.
    F3,
    /// `F4(p, P, t)`: `q = −∂F/∂p`, `Q = ∂F/∂P`.
    F4,
}

impl Kind {
    /// The generator's old argument `x` is `q` (F1, F2) rather than `p` (F3, F4).
    pub fn old_argument_is_q(self) -> bool {
        matches!(self, Kind::F1 | Kind::F2)
    }
    /// The generator's new argument `y` is `Q` (F1, F3) rather than `P` (F2, F4).
    pub fn new_argument_is_q(self) -> bool {
        matches!(self, Kind::F1 | Kind::F3)
    }
    /// Sign `s` in (other old variable) `= s ∂F/∂x`.
    fn s_old(self) -> f64 {
        if self.old_argument_is_q() {
            1.0
        } else {
            -1.0
        }
    }
    /// Sign `s′` in (other new variable) `= s′ ∂F/∂y`.
    fn s_new(self) -> f64 {
        if self.new_argument_is_q() {
            -1.0
        } else {
            1.0
        }
    }
    /// Name of one direction of the map, for error messages (static: no allocation per solve).
    fn map_name(self, forward: bool) -> &'static str {
        match (self, forward) {
            (Kind::F1, true) => "forward map of the type-1 generator",
            (Kind::F2, true) => "forward map of the type-2 generator",
            (Kind::F3, true) => "forward map of the type-3 generator",
            (Kind::F4, true) => "forward map of the type-4 generator",
            (Kind::F1, false) => "inverse map of the type-1 generator",
            (Kind::F2, false) => "inverse map of the type-2 generator",
            (Kind::F3, false) => "inverse map of the type-3 generator",
            (Kind::F4, false) => "inverse map of the type-4 generator",
        }
    }
}

/// A generating function `F(t, x, y)` of a given [`Kind`], written once for every dual type.
///
/// `x` is the old argument (`q` or `p`) and `y` the new one (`Q` or `P`) as in the table of the
/// [module docs](self).
///
/// # Example: the oscillator's angle variables, `F₁ = ½ m ω q² cot Q` [Ardema 16.5]
/// ```
/// use hamilton_jacobi::transform::{CanonicalTransformation, GeneratingFunction, Kind};
/// use hamilton_jacobi::{DualNum, nalgebra::SVector};
/// struct AngleVariables { m: f64, omega: f64 }
/// impl GeneratingFunction<1> for AngleVariables {
///     fn kind(&self) -> Kind { Kind::F1 }
///     fn generator<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 1>, big_q: &SVector<D, 1>) -> D {
///         q[0] * q[0] * (0.5 * self.m * self.omega) / big_q[0].tan()
///     }
/// }
/// let ct = CanonicalTransformation::new(AngleVariables { m: 2.0, omega: 3.0 });
/// let (big_q, big_p) = ct.forward(0.0, &SVector::from([0.5]), &SVector::from([1.2])).unwrap();
/// assert!((big_q[0] - 1.19028994968253).abs() < 1e-14);
/// assert!((big_p[0] - 0.87).abs() < 1e-15);
/// ```
pub trait GeneratingFunction<const N: usize> {
    /// The kind (which arguments `F` takes and which relations hold).
    fn kind(&self) -> Kind;

    /// `F(t, x, y)`.
    fn generator<D: DualNum<f64> + Copy>(&self, t: D, x: &SVector<D, N>, y: &SVector<D, N>) -> D;

    /// Starting guess for the new argument `y` in the forward solve; `None` (default) tries the
    /// old variable of the same letter, then the other one, then zero.
    fn forward_guess(
        &self,
        _t: f64,
        _q: &SVector<f64, N>,
        _p: &SVector<f64, N>,
    ) -> Option<SVector<f64, N>> {
        None
    }

    /// Starting guess for the old argument `x` in the inverse solve; `None` (default) tries the
    /// new variable of the same letter, then the other one, then zero.
    fn inverse_guess(
        &self,
        _t: f64,
        _big_q: &SVector<f64, N>,
        _big_p: &SVector<f64, N>,
    ) -> Option<SVector<f64, N>> {
        None
    }

    /// Refuse, before any solve, a point where the map is undefined (default: accept every
    /// point). `first` and `second` are the given pair, `(q, p)` for the forward map
    /// (`forward = true`) and `(Q, P)` for the inverse.
    ///
    /// # Errors
    /// A typed error naming the point ([`Error::Singular`] for a coordinate singularity).
    fn check_point(
        &self,
        _t: f64,
        _first: &SVector<f64, N>,
        _second: &SVector<f64, N>,
        _forward: bool,
    ) -> Result<()> {
        Ok(())
    }
    /// The sheet of the relation the maps follow unless told otherwise
    /// ([`CanonicalTransformation::with_sheet`]); default [`Sheet::First`].
    fn sheet(&self) -> Sheet<N> {
        Sheet::First
    }
}

/// Condition number of a solved map and the estimated errors of its coordinate and momentum
/// blocks.
#[derive(Clone, Copy, Debug)]
struct Accuracy {
    condition: f64,
    error: [f64; 2],
}

/// `(∂F/∂x, ∂F/∂y)` in the number type `D`.
fn partials<G: GeneratingFunction<N> + ?Sized, D: DualNum<f64> + Copy, const N: usize>(
    g: &G,
    t: D,
    x: &SVector<D, N>,
    y: &SVector<D, N>,
) -> (SVector<D, N>, SVector<D, N>) {
    let (_, fx, fy) = phase_gradient(|a, b| g.generator(PhaseDual::from_re(t), a, b), x, y);
    (fx, fy)
}

/// The generator's relation for one direction of the map, with known argument `a`, target `b`
/// and unknown `u`: forward `s ∂F/∂x (t, x = a, y = u) − b = 0` (unknown: the new argument),
/// inverse `s′ ∂F/∂y (t, x = u, y = a) − b = 0` (unknown: the old argument).
struct Relation<'a, G: ?Sized> {
    generator: &'a G,
    forward: bool,
}
impl<const N: usize, G: GeneratingFunction<N> + ?Sized> ImplicitSystem<N> for Relation<'_, G> {
    fn residual<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        a: &SVector<D, N>,
        b: &SVector<D, N>,
        u: &SVector<D, N>,
    ) -> SVector<D, N> {
        let kind = self.generator.kind();
        if self.forward {
            let (fx, _) = partials(self.generator, t, a, u);
            fx * D::from(kind.s_old()) - b
        } else {
            let (_, fy) = partials(self.generator, t, u, a);
            fy * D::from(kind.s_new()) - b
        }
    }
}

/// A canonical transformation defined by a generating function: forward and inverse maps, their
/// exact Jacobians, the transformed Hamiltonian, certification.
///
/// See the [module docs](self) for the relations, the solver and the treatment of singular
/// generators.
#[derive(Clone, Debug)]
pub struct CanonicalTransformation<G, const N: usize> {
    generator: G,
    max_condition: f64,
    sheet: Sheet<N>,
}

/// Split `(q, p)` into the generator's old argument `x` and the other old variable.
fn split<T: Copy, const N: usize>(
    x_is_q: bool,
    q: &SVector<T, N>,
    p: &SVector<T, N>,
) -> (SVector<T, N>, SVector<T, N>) {
    if x_is_q {
        (*q, *p)
    } else {
        (*p, *q)
    }
}

/// `κ₂ = σ_max/σ_min` of `m` after scaling every column, then every row, to unit max-norm
/// (invariant under the units of the variables and of the equations); `∞` if singular.
fn equilibrated_condition<const N: usize>(m: &SMatrix<f64, N, N>) -> f64 {
    let mut s = *m;
    for mut c in s.column_iter_mut() {
        let n = c.amax();
        if n > 0.0 {
            c /= n;
        }
    }
    for mut r in s.row_iter_mut() {
        let n = r.amax();
        if n > 0.0 {
            r /= n;
        }
    }
    // A dynamic matrix: nalgebra's SVD of a static matrix needs a type-level dimension bound.
    let sv = nalgebra::DMatrix::from_fn(N, N, |i, j| s[(i, j)]).singular_values();
    let (max, min) = (sv.max(), sv.min());
    if min > 0.0 && max.is_finite() {
        max / min
    } else {
        f64::INFINITY
    }
}

impl<G: GeneratingFunction<N>, const N: usize> CanonicalTransformation<G, N> {
    /// The transformation generated by `generator`, following the generator's sheet
    /// ([`GeneratingFunction::sheet`]) and refusing results whose condition number exceeds
    /// [`DEFAULT_MAX_CONDITION`].
    pub fn new(generator: G) -> Self {
        let sheet = generator.sheet();
        Self {
            generator,
            max_condition: DEFAULT_MAX_CONDITION,
            sheet,
        }
    }

    /// Change the accuracy tolerance, the relative error above which a result is refused (must be
    /// positive and finite): the same as [`Self::with_max_condition`]`(tolerance / ε)`.
    pub fn with_tolerance(self, tolerance: f64) -> Result<Self> {
        let tolerance = positive("tolerance", tolerance)?;
        self.with_max_condition(tolerance / f64::EPSILON)
    }

    /// Change the largest condition number accepted (finite, at least 1); results with a larger
    /// condition are refused with [`Error::IllConditioned`].
    pub fn with_max_condition(mut self, max_condition: f64) -> Result<Self> {
        let c = finite("largest condition number", max_condition)?;
        if c < 1.0 {
            return Err(Error::out_of_domain(
                "largest condition number",
                c,
                "[1, ∞)",
            ));
        }
        self.max_condition = c;
        Ok(self)
    }

    /// The largest condition number accepted.
    pub fn max_condition(&self) -> f64 {
        self.max_condition
    }

    /// Follow `sheet` instead of the generator's own (see the [module docs](self)).
    pub fn with_sheet(mut self, sheet: Sheet<N>) -> Self {
        self.sheet = sheet;
        self
    }

    /// The sheet the maps follow.
    pub fn sheet(&self) -> &Sheet<N> {
        &self.sheet
    }

    /// The generating function.
    pub fn generator(&self) -> &G {
        &self.generator
    }

    /// The kind of the generating function.
    pub fn kind(&self) -> Kind {
        self.generator.kind()
    }

    /// Forward map `(q, p) ↦ (Q, P)` in any number type (exact derivatives through the solve),
    /// on the transformation's sheet.
    pub fn forward_generic<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        self.solve_side(t, q, p, true, &self.sheet)
            .map(|(a, b, _)| (a, b))
    }

    /// Inverse map `(Q, P) ↦ (q, p)` in any number type, on the transformation's sheet.
    pub fn inverse_generic<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        big_q: &SVector<D, N>,
        big_p: &SVector<D, N>,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        self.solve_side(t, big_q, big_p, false, &self.sheet)
            .map(|(a, b, _)| (a, b))
    }

    /// The real root of the relation on `sheet`, with known argument `k` and target `b`.
    #[allow(clippy::too_many_arguments)]
    fn root_on_sheet(
        &self,
        relation: &Relation<'_, G>,
        t: f64,
        (first, second): (&SVector<f64, N>, &SVector<f64, N>),
        (k, b): (&SVector<f64, N>, &SVector<f64, N>),
        forward: bool,
        sheet: &Sheet<N>,
        what: &str,
    ) -> Result<Root<N>> {
        let kind = self.kind();
        let (known_is_q, unknown_is_q) = if forward {
            (kind.old_argument_is_q(), kind.new_argument_is_q())
        } else {
            (kind.new_argument_is_q(), kind.old_argument_is_q())
        };
        let guess = if forward {
            self.generator.forward_guess(t, first, second)
        } else {
            self.generator.inverse_guess(t, first, second)
        };
        let (same, other) = split(unknown_is_q, first, second);
        // The generator's own guess first (if any), then the new/old variable of the same letter,
        // the other one, and zero; a fixed array (this runs on every evaluation of K).
        let zero = SVector::zeros();
        let (starts, count) = match guess {
            Some(g) => ([g, same, other, zero], 4),
            None => ([same, other, zero, zero], 3),
        };
        match sheet {
            Sheet::First => implicit::solve_real(relation, t, k, b, &starts[..count], what),
            Sheet::Through(r) => {
                let (rf, rs, ri1, ri2) = if forward {
                    (&r.q, &r.p, &r.big_q, &r.big_p)
                } else {
                    (&r.big_q, &r.big_p, &r.q, &r.p)
                };
                let (k0, b0) = split(known_is_q, rf, rs);
                let (u0, o0) = split(unknown_is_q, ri1, ri2);
                // The reference must satisfy both halves of the relation (the continuation checks
                // the one it solves): the other side's conjugate value to √ε of its terms.
                let (x0, y0) = if forward { (k0, u0) } else { (u0, k0) };
                let (fx, fy) = partials(&self.generator, r.t, &x0, &y0);
                let o = if forward {
                    fy * kind.s_new()
                } else {
                    fx * kind.s_old()
                };
                let scale = o.amax().max(o0.amax());
                let on_relation = (o - o0).amax() <= f64::EPSILON.sqrt() * scale;
                if !on_relation {
                    return Err(Error::invalid(
                        format!("reference point of the sheet ({what})"),
                        format!(
                            "it does not satisfy the relation: the generator gives {:?} where the \
                             reference has {:?}",
                            o.as_slice(),
                            o0.as_slice()
                        ),
                    ));
                }
                implicit::continue_root(relation, (r.t, &k0, &b0, &u0), (t, k, b), what)
            }
            Sheet::Satisfying {
                description,
                predicate,
            } => {
                // The default starts and their negatives (a reflected sheet is the common case).
                let mut all = [zero; 8];
                let mut n = 0;
                for s in starts[..count].iter().chain(starts[..count].iter()) {
                    let s = if n < count { *s } else { -s };
                    if n >= count && s.amax() == 0.0 {
                        n += 1;
                        continue;
                    }
                    all[n] = s;
                    n += 1;
                }
                let (roots, first_error) = implicit::roots_real(relation, t, k, b, &all[..n], what);
                if roots.is_empty() {
                    return Err(first_error
                        .unwrap_or_else(|| Error::invalid(what, "no starting point given")));
                }
                let point = |root: &Root<N>| {
                    let (x, y) = if forward { (*k, root.u) } else { (root.u, *k) };
                    let (fx, fy) = partials(&self.generator, t, &x, &y);
                    let out = if forward {
                        fy * kind.s_new()
                    } else {
                        fx * kind.s_old()
                    };
                    let (iq, ip) = split(unknown_is_q, &root.u, &out);
                    let (q, p, big_q, big_p) = if forward {
                        (*first, *second, iq, ip)
                    } else {
                        (iq, ip, *first, *second)
                    };
                    (
                        RelationPoint {
                            t,
                            q,
                            p,
                            big_q,
                            big_p,
                        },
                        iq.iter().chain(ip.iter()).copied().collect::<Vec<f64>>(),
                    )
                };
                let mut on_sheet = Vec::with_capacity(roots.len());
                let mut candidates = Vec::with_capacity(roots.len());
                for root in &roots {
                    let (rp, image) = point(root);
                    if predicate(&rp) {
                        on_sheet.push(*root);
                    }
                    candidates.push(image);
                }
                match on_sheet.as_slice() {
                    [one] => Ok(*one),
                    _ => Err(Error::NoRootOnSheet {
                        what: what.into(),
                        at: format!(
                            "t = {t:e}, {} = {:?}, {} = {:?}",
                            if forward { "q" } else { "Q" },
                            first.as_slice(),
                            if forward { "p" } else { "P" },
                            second.as_slice()
                        ),
                        sheet: description.clone(),
                        problem: if on_sheet.is_empty() {
                            "no root".into()
                        } else {
                            "more than one root".into()
                        },
                        candidates,
                    }),
                }
            }
        }
    }

    /// The map from one side to the other: from the given pair take the generator's argument `k`
    /// on this side and the conjugate value `b` it must reproduce, solve the relation for the
    /// argument `u` on the other side (on `sheet`), evaluate the other side's conjugate value,
    /// and check the conditioning.
    fn solve_side<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        first: &SVector<D, N>,
        second: &SVector<D, N>,
        forward: bool,
        sheet: &Sheet<N>,
    ) -> Result<(SVector<D, N>, SVector<D, N>, Accuracy)> {
        let kind = self.kind();
        let (known_is_q, unknown_is_q) = if forward {
            (kind.old_argument_is_q(), kind.new_argument_is_q())
        } else {
            (kind.new_argument_is_q(), kind.old_argument_is_q())
        };
        let (k, b) = split(known_is_q, first, second);
        let (fr, sr) = (real_parts(first), real_parts(second));
        self.generator.check_point(t.re(), &fr, &sr, forward)?;
        let (kr, br) = (real_parts(&k), real_parts(&b));
        let what = kind.map_name(forward);
        let relation = Relation {
            generator: &self.generator,
            forward,
        };
        let root = self.root_on_sheet(
            &relation,
            t.re(),
            (&fr, &sr),
            (&kr, &br),
            forward,
            sheet,
            what,
        )?;
        let root = implicit::polish(&relation, t.re(), &kr, &br, root);
        let u = implicit::refine(&relation, t, &k, &b, &root)?;
        let (x, y) = if forward { (k, u) } else { (u, k) };
        let (fx, fy) = partials(&self.generator, t, &x, &y);
        let out = if forward {
            fy * D::from(kind.s_new())
        } else {
            fx * D::from(kind.s_old())
        };
        // The residual left at the root (real parts).
        let residual = if forward {
            real_parts(&fx) * kind.s_old() - br
        } else {
            real_parts(&fy) * kind.s_new() - br
        };
        let accuracy = self.check_precision(
            t.re(),
            &real_parts(&x),
            &real_parts(&y),
            (&br, &residual),
            &real_parts(&out),
            forward,
            what,
        )?;
        let (a, c) = split(unknown_is_q, &u, &out);
        let accuracy = if unknown_is_q {
            accuracy
        } else {
            Accuracy {
                condition: accuracy.condition,
                error: [accuracy.error[1], accuracy.error[0]],
            }
        };
        Ok((a, c, accuracy))
    }

    /// Estimate the condition number of a solved map (see the [module docs](self)) and refuse the
    /// result if it exceeds the threshold. Returns the condition and the estimated errors of the
    /// solved argument and of the output (in that order).
    #[allow(clippy::too_many_arguments)]
    fn check_precision(
        &self,
        t: f64,
        x: &SVector<f64, N>,
        y: &SVector<f64, N>,
        (target, residual): (&SVector<f64, N>, &SVector<f64, N>),
        output: &SVector<f64, N>,
        forward: bool,
        what: &str,
    ) -> Result<Accuracy> {
        let at = || format!("t = {t:e}, x = {:?}, y = {:?}", x.as_slice(), y.as_slice());
        let (_, _, _, h) =
            phase_hessian(|a, b| self.generator.generator(From::from(t), a, b), x, y);
        if !h.is_finite() {
            return Err(Error::Singular {
                what: format!("{what}: second derivatives of the generator are not finite"),
                at: at(),
                rcond: 0.0,
            });
        }
        // Known argument k, solved argument u: A = F_kk, B = F_ku, C = F_uu.
        let (a, b, c, k, u) = if forward {
            (h.qq, h.qp, h.pp, x, y)
        } else {
            (h.pp, h.qp.transpose(), h.qq, y, x)
        };
        let binv = checked_inverse(&b, "mixed Hessian ∂²F/∂x∂y of the generator", || {
            format!("{} ({what})", at())
        })?;
        // Componentwise (Skeel-type) first-order error estimates: invariant under a change of units
        // of the individual variables, and unbounded where |B⁻¹| or the generator blows up.
        let eps = f64::EPSILON;
        let (ka, ua, ta, oa) = (k.abs(), u.abs(), target.abs(), output.abs());
        let (aa, ba, ca, bia) = (a.abs(), b.abs(), c.abs(), binv.abs());
        // The residual left by Newton adds its own error |B⁻¹||r| (a posteriori).
        let du = bia * (aa * ka + ba * ua + ta) * eps + bia * residual.abs();
        let dout = (ba.transpose() * ka + ca * ua + oa) * eps + ca * du;
        // The size of each block: its value plus the first-order contributions of the inputs
        // through the exact derivatives of the map, du/dk = −B⁻¹A, du/db = ±B⁻¹,
        // do/dk = ±(Bᵀ − CB⁻¹A), do/db = ±CB⁻¹.
        let binv_a = binv * a;
        let size_u = ua + binv_a.abs() * ka + bia * ta;
        let size_o = oa + (b.transpose() - c * binv_a).abs() * ka + (c * binv).abs() * ta;
        let relative = |d: &SVector<f64, N>, size: &SVector<f64, N>| {
            let dn = d.amax();
            if dn == 0.0 {
                0.0
            } else {
                dn / (eps * size.amax())
            }
        };
        let condition = relative(&du, &size_u)
            .max(relative(&dout, &size_o))
            .max(equilibrated_condition(&b));
        if condition.is_finite() && condition <= self.max_condition {
            Ok(Accuracy {
                condition,
                error: [du.amax(), dout.amax()],
            })
        } else {
            Err(Error::IllConditioned {
                what: format!(
                    "{what} (near a caustic, a focal point or a blow-up of the generator; \
                     switch to a generator of another kind)"
                ),
                at: at(),
                condition: if condition.is_nan() {
                    f64::INFINITY
                } else {
                    condition
                },
                threshold: self.max_condition,
            })
        }
    }

    /// Forward map `(q, p) ↦ (Q, P)` on the transformation's sheet, with input validation and
    /// conditioning checks.
    pub fn forward(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        check_phase(t, q, p)?;
        self.forward_generic(t, q, p)
    }

    /// Inverse map `(Q, P) ↦ (q, p)` on the transformation's sheet, with input validation and
    /// conditioning checks.
    pub fn inverse(
        &self,
        t: f64,
        big_q: &SVector<f64, N>,
        big_p: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        check_phase(t, big_q, big_p)?;
        self.inverse_generic(t, big_q, big_p)
    }

    /// Forward map `(q, p) ↦ (Q, P)` on the given sheet, with the condition number of the result
    /// and its estimated errors ([`Image`]).
    ///
    /// Errors: non-finite input; [`Error::NoRootOnSheet`] (naming every root found) if the sheet
    /// has no root or, for a predicate, more than one; [`Error::IllConditioned`] if the condition
    /// exceeds [`Self::max_condition`]; [`Error::Singular`] at a singular mixed Hessian;
    /// [`Error::NotConverged`] if Newton or the continuation from a reference fails.
    pub fn forward_on(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        sheet: &Sheet<N>,
    ) -> Result<Image<N>> {
        check_phase(t, q, p)?;
        let (a, b, acc) = self.solve_side(t, q, p, true, sheet)?;
        Ok(Image {
            q: a,
            p: b,
            condition: acc.condition,
            error: acc.error,
        })
    }

    /// Inverse map `(Q, P) ↦ (q, p)` on the given sheet, with the condition number of the result
    /// and its estimated errors; errors as [`Self::forward_on`].
    pub fn inverse_on(
        &self,
        t: f64,
        big_q: &SVector<f64, N>,
        big_p: &SVector<f64, N>,
        sheet: &Sheet<N>,
    ) -> Result<Image<N>> {
        check_phase(t, big_q, big_p)?;
        let (a, b, acc) = self.solve_side(t, big_q, big_p, false, sheet)?;
        Ok(Image {
            q: a,
            p: b,
            condition: acc.condition,
            error: acc.error,
        })
    }

    /// The forward map as a [`PhaseMap`] (NaN where the map is undefined or refused).
    pub fn forward_map(&self) -> ForwardMap<'_, G, N> {
        ForwardMap(self)
    }

    /// The inverse map as a [`PhaseMap`] (NaN where the map is undefined or refused).
    pub fn inverse_map(&self) -> InverseMap<'_, G, N> {
        InverseMap(self)
    }

    /// Exact Jacobian `∂(Q, P)/∂(q, p)` by implicit AD.
    pub fn jacobian(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<crate::PhaseMatrix<N>> {
        self.forward(t, q, p)?;
        crate::brackets::jacobian(&self.forward_map(), t, q, p)
    }

    /// Certify the forward map at a point ([`crate::brackets::certify`]).
    pub fn certify(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<Certificate<N>> {
        self.forward(t, q, p)?;
        certify(&self.forward_map(), t, q, p)
    }

    /// `∂F/∂t` at the generator's arguments corresponding to `(Q, P)`, in any number type.
    fn generator_rate<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        x: &SVector<D, N>,
        y: &SVector<D, N>,
    ) -> D {
        let td = Dual::new(t, D::one());
        let xd: SVector<Dual<D, f64>, N> = x.map(Dual::from_re);
        let yd: SVector<Dual<D, f64>, N> = y.map(Dual::from_re);
        self.generator.generator(td, &xd, &yd).eps
    }

    /// The transformed Hamiltonian `K(t, Q, P) = H(t, q, p) + ∂F/∂t` [Ardema eq. 16.39], a
    /// [`Hamiltonian`] in the new variables usable everywhere in the crate.
    pub fn transform<'a, H: Hamiltonian<N>>(&'a self, h: &'a H) -> Transformed<'a, G, H, N> {
        Transformed { ct: self, h }
    }
}

/// The forward map of a [`CanonicalTransformation`] as a [`PhaseMap`].
pub struct ForwardMap<'a, G, const N: usize>(&'a CanonicalTransformation<G, N>);
/// The inverse map of a [`CanonicalTransformation`] as a [`PhaseMap`].
pub struct InverseMap<'a, G, const N: usize>(&'a CanonicalTransformation<G, N>);

/// NaN carrying NaN in every derivative slot of `z` (a refused map must not look differentiable).
fn nan_like<D: DualNum<f64> + Copy, const N: usize>(z: &SVector<D, N>) -> D {
    z.iter().fold(D::from(f64::NAN), |a, &x| a + x * f64::NAN)
}

fn nan_pair<D: DualNum<f64> + Copy, const N: usize>(
    z: &SVector<D, N>,
) -> (SVector<D, N>, SVector<D, N>) {
    let nan = nan_like(z);
    (SVector::from_element(nan), SVector::from_element(nan))
}

impl<G: GeneratingFunction<N>, const N: usize> PhaseMap<N> for ForwardMap<'_, G, N> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        self.0
            .forward_generic(t, q, p)
            .unwrap_or_else(|_| nan_pair(q))
    }
}

impl<G: GeneratingFunction<N>, const N: usize> PhaseMap<N> for InverseMap<'_, G, N> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        self.0
            .inverse_generic(t, q, p)
            .unwrap_or_else(|_| nan_pair(q))
    }
}

/// The transformed Hamiltonian `K = H + ∂F/∂t` of a [`CanonicalTransformation`]
/// (see [`CanonicalTransformation::transform`]). NaN where the inverse map is refused; the checked
/// methods ([`Hamiltonian::vector_field`], …) then report a non-finite result.
pub struct Transformed<'a, G, H, const N: usize> {
    ct: &'a CanonicalTransformation<G, N>,
    h: &'a H,
}

impl<G: GeneratingFunction<N>, H: Hamiltonian<N>, const N: usize> Hamiltonian<N>
    for Transformed<'_, G, H, N>
{
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        big_q: &SVector<D, N>,
        big_p: &SVector<D, N>,
    ) -> D {
        match self.ct.inverse_generic(t, big_q, big_p) {
            Ok((q, p)) => {
                let kind = self.ct.kind();
                let (x, _) = split(kind.old_argument_is_q(), &q, &p);
                let (y, _) = split(kind.new_argument_is_q(), big_q, big_p);
                self.h.hamiltonian(t, &q, &p) + self.ct.generator_rate(t, &x, &y)
            }
            Err(_) => nan_like(big_p),
        }
    }
}
