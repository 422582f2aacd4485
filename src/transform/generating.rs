//! Canonical transformations from generating functions of the four classical kinds (SPEC M49, M51,
//! §0.5; [Ardema 16.2, eqs. 16.4–16.18]).
//!
//! | kind | arguments `(x, y)` | relations |
//! |---|---|---|
//! | F1 | `(q, Q)` | `p = ∂F/∂q`, `P = −∂F/∂Q` |
//! | F2 | `(q, P)` | `p = ∂F/∂q`, `Q = ∂F/∂P` |
//! | F3 | `(p, Q)` | `q = −∂F/∂p`, `P = −∂F/∂Q` |
//! | F4 | `(p, P)` | `q = −∂F/∂p`, `Q = ∂F/∂P` |
//!
//! In every case the new Hamiltonian is `K(t, Q, P) = H + ∂F/∂t` [Ardema eq. 16.39] (Jacobi's
//! theorem, M51), available as a [`Hamiltonian`] through [`CanonicalTransformation::transform`].
//!
//! **Solving the implicit relations.** The forward map solves `s ∂F/∂x (x, y) = (other old
//! variable)` for the new argument `y`, the inverse solves `s′ ∂F/∂y (x, y) = (other new variable)`
//! for `x`, both by damped Newton with the AD mixed Hessian `B = ∂²F/∂x∂y`
//! ([`crate::implicit`]); derivatives of the maps (their exact Jacobians) come from the same
//! solver in dual arithmetic.
//!
//! **Singular generators (SPEC X4).** A generator is usable only where `B` is regular and the map
//! can be computed to the requested accuracy. After every solve the relative rounding error of the
//! result is estimated from the second derivatives `A = F_kk`, `B = F_ku`, `C = F_uu` (known
//! argument `k`, solved argument `u`):
//!
//! $$ \delta u \approx \varepsilon\, |B^{-1}| (|A||k| + |B||u| + |b|),\qquad
//!    \delta o \approx \varepsilon (|B^{\mathsf T}||k| + |C||u| + |o|) + |C|\,\delta u $$
//!
//! (componentwise, with absolute values of the matrices and vectors, so that the estimate does not
//! depend on the units of the individual variables), and a result whose estimate, relative to the
//! size of the result, exceeds the tolerance (default `1e−8`) is refused with [`Error::Singular`],
//! carrying the point and `rcond = ε/relative error`. This catches a singular mixed Hessian
//! (`det B = 0`: `F₁ = ½mωq² cot Q` at `q = 0`) and generators whose second derivatives blow up so
//! that the result is formed by cancellation (`F₁ = ½mωq² cot Q` at `Q → kπ`; the free-fall `F₁` at
//! `t → 0`, where the identity map has no type-1 generator; the oscillator's principal function at
//! the focal point `ωτ → π`, where `B = −ω/sin ωτ`). **What to do there:** switch kind — near the identity use an F2
//! (`F₂ = q·P + …`) or F3 generator, near the exchange map an F1 or F4 one; the Legendre relations
//! `F₂ = F₁ + Q·P`, `F₃ = F₁ − q·p`, `F₄ = F₁ + Q·P − q·p` translate between them.

use crate::ad::{phase_gradient, phase_hessian, real_parts, PhaseDual};
use crate::brackets::{certify, Certificate, PhaseMap};
use crate::error::{positive, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::implicit::{self, ImplicitSystem};
use crate::phase::{check_phase, checked_inverse};
use nalgebra::SVector;
use num_dual::{Dual, DualNum};

/// The four classical kinds of generating function (SPEC §0.5).
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
/// # Example: the oscillator's angle variables, `F₁ = ½ m ω q² cot Q` (SPEC T5)
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
    tolerance: f64,
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

impl<G: GeneratingFunction<N>, const N: usize> CanonicalTransformation<G, N> {
    /// The transformation generated by `generator`, with the default accuracy tolerance `1e−8`
    /// (relative rounding error above which a result is refused as singular).
    pub fn new(generator: G) -> Self {
        Self {
            generator,
            tolerance: 1e-8,
        }
    }

    /// Change the accuracy tolerance (must be positive and finite).
    pub fn with_tolerance(mut self, tolerance: f64) -> Result<Self> {
        self.tolerance = positive("tolerance", tolerance)?;
        Ok(self)
    }

    /// The generating function.
    pub fn generator(&self) -> &G {
        &self.generator
    }

    /// The kind of the generating function.
    pub fn kind(&self) -> Kind {
        self.generator.kind()
    }

    /// Forward map `(q, p) ↦ (Q, P)` in any number type (exact derivatives through the solve).
    pub fn forward_generic<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        self.solve_side(t, q, p, true)
    }

    /// Inverse map `(Q, P) ↦ (q, p)` in any number type.
    pub fn inverse_generic<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        big_q: &SVector<D, N>,
        big_p: &SVector<D, N>,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        self.solve_side(t, big_q, big_p, false)
    }

    /// The map from one side to the other: from the given pair take the generator's argument `k`
    /// on this side and the conjugate value `b` it must reproduce, solve the relation for the
    /// argument `u` on the other side, and evaluate the other side's conjugate value.
    fn solve_side<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        first: &SVector<D, N>,
        second: &SVector<D, N>,
        forward: bool,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        let kind = self.kind();
        let (known_is_q, unknown_is_q) = if forward {
            (kind.old_argument_is_q(), kind.new_argument_is_q())
        } else {
            (kind.new_argument_is_q(), kind.old_argument_is_q())
        };
        let (k, b) = split(known_is_q, first, second);
        let (fr, sr) = (real_parts(first), real_parts(second));
        self.generator.check_point(t.re(), &fr, &sr, forward)?;
        let guess = if forward {
            self.generator.forward_guess(t.re(), &fr, &sr)
        } else {
            self.generator.inverse_guess(t.re(), &fr, &sr)
        };
        let (same, other) = split(unknown_is_q, &fr, &sr);
        // The generator's own guess first (if any), then the new/old variable of the same letter,
        // the other one, and zero; a fixed array (this runs on every evaluation of K).
        let zero = SVector::zeros();
        let (starts, count) = match guess {
            Some(g) => ([g, same, other, zero], 4),
            None => ([same, other, zero, zero], 3),
        };
        let what = kind.map_name(forward);
        let relation = Relation {
            generator: &self.generator,
            forward,
        };
        let (u, _) = implicit::solve(&relation, t, &k, &b, &starts[..count], what)?;
        let (x, y) = if forward { (k, u) } else { (u, k) };
        let (fx, fy) = partials(&self.generator, t, &x, &y);
        let out = if forward {
            fy * D::from(kind.s_new())
        } else {
            fx * D::from(kind.s_old())
        };
        self.check_precision(
            t.re(),
            &real_parts(&x),
            &real_parts(&y),
            &real_parts(&b),
            &real_parts(&out),
            forward,
            what,
        )?;
        Ok(split(unknown_is_q, &u, &out))
    }

    /// Estimate the relative rounding error of a solved map (see the [module docs](self)) and
    /// refuse the result if it exceeds the tolerance.
    #[allow(clippy::too_many_arguments)]
    fn check_precision(
        &self,
        t: f64,
        x: &SVector<f64, N>,
        y: &SVector<f64, N>,
        target: &SVector<f64, N>,
        output: &SVector<f64, N>,
        forward: bool,
        what: &str,
    ) -> Result<()> {
        let at = || format!("t = {t}, x = {x:?}, y = {y:?}");
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
        // Componentwise (Skeel-type) first-order error bounds: invariant under a change of units of
        // the individual variables, and unbounded where |B⁻¹| or the generator blows up.
        let eps = f64::EPSILON;
        let (ka, ua, ta, oa) = (k.abs(), u.abs(), target.abs(), output.abs());
        let (aa, ba, ca, bia) = (a.abs(), b.abs(), c.abs(), binv.abs());
        let du = bia * (aa * ka + ba * ua + ta) * eps;
        let dout = (ba.transpose() * ka + ca * ua + oa) * eps + ca * du;
        // Relative to the size of each result block. A block that came out exactly zero has no
        // relative accuracy; its error is measured against the overall size of the point instead
        // (a zero formed by cancelling huge terms — the oscillator's principal function exactly at
        // its focal point — is then refused, a zero of ordinary size is not).
        let overall = ka.amax().max(ua.amax()).max(ta.amax()).max(oa.amax());
        let relative = |d: &SVector<f64, N>, v: &SVector<f64, N>| {
            let dn = d.amax();
            if dn == 0.0 {
                0.0
            } else if v.amax() > 0.0 {
                dn / v.amax()
            } else {
                dn / overall
            }
        };
        let rel = relative(&du, &ua).max(relative(&dout, &oa));
        if rel.is_finite() && rel <= self.tolerance {
            Ok(())
        } else {
            Err(Error::Singular {
                what: format!(
                    "{what} (estimated relative error {rel:.1e} above the tolerance {:.1e}: near a \
                     caustic, a focal point or a blow-up of the generator; switch to a generator of \
                     another kind)",
                    self.tolerance
                ),
                at: format!("t = {t}, x = {x:?}, y = {y:?}"),
                rcond: if rel.is_finite() { eps / rel } else { 0.0 },
            })
        }
    }

    /// Forward map `(q, p) ↦ (Q, P)` with input validation and singularity checks.
    pub fn forward(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        check_phase(t, q, p)?;
        self.forward_generic(t, q, p)
    }

    /// Inverse map `(Q, P) ↦ (q, p)` with input validation and singularity checks.
    pub fn inverse(
        &self,
        t: f64,
        big_q: &SVector<f64, N>,
        big_p: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        check_phase(t, big_q, big_p)?;
        self.inverse_generic(t, big_q, big_p)
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

    /// The transformed Hamiltonian `K(t, Q, P) = H(t, q, p) + ∂F/∂t` (Jacobi's theorem, M51), a
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
