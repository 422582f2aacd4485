//! Perturbation models of the two-body problem, written once generic over [`DualNum`] and usable
//! both in the element engines of [`variation`](super::variation) and in Cartesian
//! integration.
//!
//! Per unit mass, with `r = q` the position relative to the central body and `v = p` its
//! velocity, the perturbed motion is
//!
//! ```math
//! \dot q = p,\qquad \dot p = -\frac{\mu q}{|q|^3} - \nabla U(t, q) + f(t, q, p),
//! ```
//!
//! that is, Hamilton's equations of `H = |p|²/2 − μ/|q| + U(t, q)` with the non-conservative
//! generalized force `f` ([`Hamiltonian::generalized_force`](crate::Hamiltonian::generalized_force),
//! [Ardema eq. 15.18]).
//!
//! # Sign convention of the disturbing function
//! `U` is a *potential energy* per unit mass, added to `H`, so that the perturbing force is
//! `R = −∂U/∂q` as in [`DisturbingFunction`] and in Ardema's planetary equations
//! `Σ_s [γ_j, γ_s] γ̇_s = −∂U*/∂γ_j` [Ardema eqs. 18.22–18.24]. Astrodynamics texts write the
//! geopotential and the "disturbing function" with the opposite sign (the force is `+∇R`,
//! Vallado 2013 §8.6–8.7; Kaula 1966 §1.2; Murray & Dermott 1999 §6.2); here `U = −R`.
//!
//! # Models
//! * [`J2`]: the oblateness term of the geopotential (conservative).
//! * [`ThirdBody`]: a point mass, fixed or on a circular orbit, with the indirect term
//!   (conservative, time-dependent in the circular case).
//! * [`LinearDrag`]: `f = −k v`; [`ConstantThrust`]: a constant acceleration in the inertial or
//!   in the radial–transverse–normal (RTN) frame (non-conservative, [`MomentumForce`]).
//! * [`ExpressionDisturbingFunction`]: `R(t, q)` written as an expression (a scene's
//!   `disturbing_function`), entering as `U = −R`.
//! * [`Sum`] adds models; [`NoForce`] and [`NoPotential`] are the empty ones. A user's own
//!   disturbing function or force implements [`DisturbingFunction`] / [`MomentumForce`] (or is
//!   written in one line with [`disturbing_function!`](crate::disturbing_function) /
//!   [`momentum_force!`](crate::momentum_force)).
//! * [`PerturbedTwoBody`]: the Cartesian system `H = |p|²/2 − μ/|q| + U` with force `f`, in
//!   the plane or in space, a [`Separable`] system (so every crate integrator runs it; the
//!   explicit splittings refuse it when `f` is present) and, without `f`, a [`PerturbedKepler`]
//!   system for Wisdom–Holman and a [`Parametric`] one in the parameters of `U`.
//!
//! # References
//! * D. A. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., Microcosm (2013),
//!   §8.6 (third-body and drag accelerations), §8.7 (geopotential, eq. 8-19 for `J₂`).
//! * W. M. Kaula, *Theory of Satellite Geodesy*, Blaisdell (1966), §1.2.
//! * C. D. Murray & S. F. Dermott, *Solar System Dynamics*, Cambridge (1999), §6.2, eq. 6.44
//!   (direct and indirect parts of the disturbing function).

use super::variation::{DisturbingFunction, GradientForce, MomentumForce, ParametricDisturbance};
use crate::error::{all_finite, finite, non_negative, positive, Error, Result};
use crate::expression::ExpressionDisturbingFunction;
use crate::hamiltonian::{Parametric, PerturbedKepler, Separable};
use crate::systems::{CentralPotential, InverseDistance};
use nalgebra::{SVector, Vector3};
use num_dual::DualNum;

// ---------------------------------------------------------------------------------------------
// Combinators and empty models
// ---------------------------------------------------------------------------------------------

/// The zero disturbing function `U = 0` (a force-only perturbation).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoPotential;

impl<const N: usize> DisturbingFunction<N> for NoPotential {
    fn disturbing_function<D: DualNum<f64> + Copy>(&self, _t: D, _q: &SVector<D, N>) -> D {
        D::from(0.0)
    }
}

/// The zero force `f = 0` (a conservative perturbation). As the force of a
/// [`PerturbedTwoBody`] it makes the system conservative (`generalized_force` is `None`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NoForce;

impl<const N: usize> MomentumForce<N> for NoForce {
    fn force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, N>,
        _p: &SVector<D, N>,
    ) -> SVector<D, N> {
        SVector::zeros()
    }
}

/// The sum of two models: `U = U_A + U_B` for disturbing functions, `f = f_A + f_B` for forces.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sum<A, B>(pub A, pub B);

impl<A: DisturbingFunction<N>, B: DisturbingFunction<N>, const N: usize> DisturbingFunction<N>
    for Sum<A, B>
{
    fn disturbing_function<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D {
        self.0.disturbing_function(t, q) + self.1.disturbing_function(t, q)
    }
}

impl<A: MomentumForce<N>, B: MomentumForce<N>, const N: usize> MomentumForce<N> for Sum<A, B> {
    fn force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> SVector<D, N> {
        self.0.force(t, q, p) + self.1.force(t, q, p)
    }
}

/// Define a disturbing function `U(t, q)` in one line: a struct (with optional parameters) and its
/// [`DisturbingFunction`] implementation, the body written with [`DualNum`] operations.
///
/// ```
/// use hamilton_jacobi::disturbing_function;
/// use hamilton_jacobi::perturbation::variation::DisturbingFunction;
/// use hamilton_jacobi::nalgebra::SVector;
///
/// disturbing_function!(
///     /// A uniform field along x: U = g·x.
///     pub Uniform<3> { g: f64 } |s, _t, q| q[0] * s.g
/// );
/// let u = Uniform { g: 0.5 };
/// assert_eq!(u.disturbing_function(0.0, &SVector::from([2.0, 0.0, 0.0])), 1.0);
/// ```
#[macro_export]
macro_rules! disturbing_function {
    ($(#[$meta:meta])* $vis:vis $name:ident < $n:literal > { $($field:ident : $fty:ty),* $(,)? }
        |$s:ident, $t:ident, $q:ident| $body:expr) => {
        $(#[$meta])*
        #[derive(Clone, Debug, PartialEq)]
        $vis struct $name { $(#[allow(missing_docs)] pub $field: $fty),* }
        $crate::disturbing_function!(@impl $name $n |$s, $t, $q| $body);
    };
    ($(#[$meta:meta])* $vis:vis $name:ident < $n:literal > |$s:ident, $t:ident, $q:ident| $body:expr) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        $vis struct $name;
        $crate::disturbing_function!(@impl $name $n |$s, $t, $q| $body);
    };
    (@impl $name:ident $n:literal |$s:ident, $t:ident, $q:ident| $body:expr) => {
        impl $crate::perturbation::variation::DisturbingFunction<$n> for $name {
            #[inline]
            #[allow(unused_variables)]
            fn disturbing_function<D: $crate::DualNum<f64> + Copy>(
                &self,
                $t: D,
                $q: &$crate::nalgebra::SVector<D, $n>,
            ) -> D {
                let $s = self;
                $body
            }
        }
    };
}

/// Define a perturbing force `f(t, q, p)` in one line: a struct (with optional parameters) and its
/// [`MomentumForce`] implementation, the body written with [`DualNum`] operations.
///
/// ```
/// use hamilton_jacobi::momentum_force;
/// use hamilton_jacobi::perturbation::variation::MomentumForce;
/// use hamilton_jacobi::nalgebra::SVector;
///
/// momentum_force!(
///     /// Quadratic drag f = −c |v| v.
///     pub QuadraticDrag<3> { c: f64 } |s, _t, _q, p| p * (p.dot(p).sqrt() * -s.c)
/// );
/// let f = QuadraticDrag { c: 2.0 }.force(0.0, &SVector::zeros(), &SVector::from([3.0, 4.0, 0.0]));
/// assert_eq!(f, SVector::from([-30.0, -40.0, 0.0]));
/// ```
#[macro_export]
macro_rules! momentum_force {
    ($(#[$meta:meta])* $vis:vis $name:ident < $n:literal > { $($field:ident : $fty:ty),* $(,)? }
        |$s:ident, $t:ident, $q:ident, $p:ident| $body:expr) => {
        $(#[$meta])*
        #[derive(Clone, Debug, PartialEq)]
        $vis struct $name { $(#[allow(missing_docs)] pub $field: $fty),* }
        $crate::momentum_force!(@impl $name $n |$s, $t, $q, $p| $body);
    };
    ($(#[$meta:meta])* $vis:vis $name:ident < $n:literal > |$s:ident, $t:ident, $q:ident, $p:ident| $body:expr) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        $vis struct $name;
        $crate::momentum_force!(@impl $name $n |$s, $t, $q, $p| $body);
    };
    (@impl $name:ident $n:literal |$s:ident, $t:ident, $q:ident, $p:ident| $body:expr) => {
        impl $crate::perturbation::variation::MomentumForce<$n> for $name {
            #[inline]
            #[allow(unused_variables)]
            fn force<D: $crate::DualNum<f64> + Copy>(
                &self,
                $t: D,
                $q: &$crate::nalgebra::SVector<D, $n>,
                $p: &$crate::nalgebra::SVector<D, $n>,
            ) -> $crate::nalgebra::SVector<D, $n> {
                let $s = self;
                $body
            }
        }
    };
}

// ---------------------------------------------------------------------------------------------
// J2
// ---------------------------------------------------------------------------------------------

/// The `J₂` (oblateness) term of the potential of an axisymmetric central body whose symmetry
/// axis is `z`, as a potential energy per unit mass:
///
/// ```math
/// U_{J_2}(q) = \frac{\mu}{r}\,J_2\Big(\frac{R}{r}\Big)^2 P_2\Big(\frac{z}{r}\Big)
/// = \frac{\mu J_2 R^2}{2 r^3}\Big(\frac{3z^2}{r^2} - 1\Big),\qquad P_2(x) = \tfrac12(3x^2 - 1).
/// ```
///
/// This is minus the `n = 2` zonal term of the geopotential
/// `Φ = (μ/r)[1 − Σ_n J_n (R/r)ⁿ P_n(sin φ)]` (force `+∇Φ`; Vallado 2013 eq. 8-19 with
/// `sin φ = z/r`; Kaula 1966 eq. 1.31), so that `−∇U_{J₂}` is the `J₂` acceleration. For
/// `J₂ > 0` (an oblate body) the force pulls towards the equatorial plane.
///
/// A disturbing function in space (`N = 3`, `q = (x, y, z)`) and in the equatorial plane
/// (`N = 2`, `q = (x, y)` embedded as `(x, y, 0)`, where `U_{J₂} = −μJ₂R²/(2r³)`): the plane
/// `z = 0` is invariant, and to first order in `J₂` the line of apsides of an equatorial orbit
/// advances at the rate `ϖ̇ = Ω̇ + ω̇ = 3nJ₂R²/(2p²)` (`n` the mean motion, `p` the semi-latus
/// rectum; Vallado 2013 eqs. 9-41 at `i = 0`). No other dimension:
///
/// ```compile_fail
/// use hamilton_jacobi::perturbation::forces::J2;
/// use hamilton_jacobi::perturbation::variation::DisturbingFunction;
/// use hamilton_jacobi::nalgebra::SVector;
/// let j2 = J2::new(1.0, 1e-3, 1.0).unwrap();
/// j2.disturbing_function(0.0, &SVector::<f64, 4>::from([1.0, 0.0, 0.0, 0.0]));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct J2 {
    mu: f64,
    j2: f64,
    radius: f64,
}

impl J2 {
    /// `J₂` of a body of gravitational parameter `μ > 0` and reference radius `R > 0`; `J₂` finite
    /// (either sign: `J₂ < 0` is a prolate body).
    pub fn new(mu: f64, j2: f64, radius: f64) -> Result<Self> {
        Ok(Self {
            mu: positive("gravitational parameter μ", mu)?,
            j2: finite("J₂", j2)?,
            radius: positive("reference radius R", radius)?,
        })
    }
    /// `μ`.
    pub fn mu(&self) -> f64 {
        self.mu
    }
    /// `J₂`.
    pub fn j2(&self) -> f64 {
        self.j2
    }
    /// `R`.
    pub fn radius(&self) -> f64 {
        self.radius
    }

    /// `c (3z²/r² − 1)/r³`, the one formula of `U_{J₂} = (μJ₂R²/2) (3z²/r² − 1)/r³` with its
    /// constant factor `c`; `z = 0` in the plane (`N = 2`).
    #[inline]
    fn zonal<D: DualNum<f64> + Copy, const N: usize>(q: &SVector<D, N>, c: f64) -> D {
        let r2 = q.dot(q);
        let r = r2.sqrt();
        let shape = if N == 3 {
            q[2] * q[2] / r2 * 3.0 - 1.0
        } else {
            D::from(-1.0)
        };
        shape / (r2 * r) * c
    }
}

/// `U_{J₂}` in the plane (`N = 2`) and in space (`N = 3`), with `J₂` as the differentiable
/// parameter of the model.
macro_rules! j2_in_dimension {
    ($($n:literal),*) => {$(
        impl DisturbingFunction<$n> for J2 {
            #[inline]
            fn disturbing_function<D: DualNum<f64> + Copy>(
                &self,
                _t: D,
                q: &SVector<D, $n>,
            ) -> D {
                Self::zonal(q, 0.5 * self.mu * self.radius * self.radius * self.j2)
            }
        }

        impl ParametricDisturbance<$n, 1> for J2 {
            const NAMES: [&'static str; 1] = ["J2"];
            fn parameters(&self) -> SVector<f64, 1> {
                SVector::from([self.j2])
            }
            #[inline]
            fn disturbing_function_with<D: DualNum<f64> + Copy>(
                &self,
                k: &SVector<D, 1>,
                _t: D,
                q: &SVector<D, $n>,
            ) -> D {
                Self::zonal(q, 0.5 * self.mu * self.radius * self.radius) * k[0]
            }
        }
    )*};
}

j2_in_dimension!(2, 3);

// ---------------------------------------------------------------------------------------------
// Third body
// ---------------------------------------------------------------------------------------------

/// Where the third body is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ThirdBodyPath {
    /// At rest at `position` (relative to the central body).
    Fixed {
        /// Position `q₃`.
        position: Vector3<f64>,
    },
    /// On a circle of radius `ρ` about the central body at the angular rate `ν`, in the plane of
    /// inclination `I` to `xy` through the `x` axis:
    /// `q₃(t) = ρ (cos θ, sin θ cos I, sin θ sin I)`, `θ = θ₀ + ν t`.
    Circular {
        /// Radius `ρ > 0`.
        radius: f64,
        /// Angular rate `ν` (any sign; `√((μ + μ₃)/ρ³)` for a Keplerian circle).
        rate: f64,
        /// Inclination `I` of the orbit plane.
        inclination: f64,
        /// Phase `θ₀` at `t = 0`.
        phase: f64,
    },
}

/// The disturbing function of a third body of gravitational parameter `μ₃` at `q₃(t)`, relative to
/// the central body, as a potential energy per unit mass [Murray & Dermott 1999 eq. 6.44;
/// Vallado 2013 §8.6.3]:
///
/// ```math
/// U_3(t, q) = -\mu_3\Big(\frac{1}{|q_3 - q|} - \frac{q\cdot q_3}{|q_3|^3}\Big).
/// ```
///
/// The first term is the direct attraction; the second (the indirect term, included when
/// `indirect` is set) removes the acceleration `μ₃q₃/|q₃|³` of the central body, which the
/// frame centred on it does not feel. The force is
/// `−∇U₃ = μ₃[(q₃ − q)/|q₃ − q|³ − q₃/|q₃|³]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThirdBody {
    mu3: f64,
    path: ThirdBodyPath,
    indirect: bool,
}

impl ThirdBody {
    /// A third body of parameter `μ₃ ≥ 0` on `path`, with or without the indirect term.
    ///
    /// # Errors
    /// Non-finite or negative `μ₃`, a non-finite or zero fixed position, a non-positive radius,
    /// a non-finite rate, inclination or phase.
    pub fn new(mu3: f64, path: ThirdBodyPath, indirect: bool) -> Result<Self> {
        let mu3 = non_negative("third-body parameter μ₃", mu3)?;
        match path {
            ThirdBodyPath::Fixed { position } => {
                all_finite("third-body position q₃", position.as_slice())?;
                if position.norm() == 0.0 {
                    return Err(Error::invalid(
                        "third-body position q₃",
                        "q₃ = 0 coincides with the central body",
                    ));
                }
            }
            ThirdBodyPath::Circular {
                radius,
                rate,
                inclination,
                phase,
            } => {
                positive("third-body orbit radius ρ", radius)?;
                finite("third-body angular rate ν", rate)?;
                finite("third-body orbit inclination I", inclination)?;
                finite("third-body phase θ₀", phase)?;
            }
        }
        Ok(Self {
            mu3,
            path,
            indirect,
        })
    }

    /// The position `q₃(t)` of the third body, in any dual type.
    pub fn position<D: DualNum<f64> + Copy>(&self, t: D) -> SVector<D, 3> {
        match self.path {
            ThirdBodyPath::Fixed { position } => position.map(D::from),
            ThirdBodyPath::Circular {
                radius,
                rate,
                inclination,
                phase,
            } => {
                let (s, c) = (t * rate + phase).sin_cos();
                let (si, ci) = inclination.sin_cos();
                SVector::<D, 3>::new(c * radius, s * (radius * ci), s * (radius * si))
            }
        }
    }
}

impl DisturbingFunction<3> for ThirdBody {
    #[inline]
    fn disturbing_function<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 3>) -> D {
        let q3 = self.position(t);
        let d = q3 - q;
        let direct = d.dot(&d).sqrt().recip();
        let u = if self.indirect {
            let r3sq = q3.dot(&q3);
            direct - q.dot(&q3) / (r3sq * r3sq.sqrt())
        } else {
            direct
        };
        u * (-self.mu3)
    }
}

// ---------------------------------------------------------------------------------------------
// Non-conservative forces
// ---------------------------------------------------------------------------------------------

/// Linear drag `f = −k v`, `k ≥ 0` (per unit mass; `k = ρ C_D A/(2m) |v|` frozen at a reference
/// speed gives the linearised form of Vallado 2013 eq. 8-28 in a non-rotating atmosphere).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinearDrag {
    k: f64,
}

impl LinearDrag {
    /// Drag coefficient `k ≥ 0` (finite).
    pub fn new(k: f64) -> Result<Self> {
        Ok(Self {
            k: non_negative("drag coefficient k", k)?,
        })
    }
    /// `k`.
    pub fn k(&self) -> f64 {
        self.k
    }
}

impl<const N: usize> MomentumForce<N> for LinearDrag {
    #[inline]
    fn force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> SVector<D, N> {
        p * D::from(-self.k)
    }
}

/// The frame in which a thrust acceleration is constant.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ThrustFrame {
    /// Components along the inertial `x, y, z`.
    Inertial,
    /// Components along the radial `R̂ = q/|q|`, transverse `T̂ = N̂ × R̂` and orbit-normal
    /// `N̂ = (q × p)/|q × p|` unit vectors (Vallado 2013 §3.3, RSW frame; undefined for
    /// rectilinear motion `q × p = 0`, where the force is NaN).
    Rtn,
}

/// A constant thrust acceleration `f` (per unit mass), with components fixed in the inertial frame
/// or in the RTN frame of the current osculating orbit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstantThrust {
    components: Vector3<f64>,
    frame: ThrustFrame,
}

impl ConstantThrust {
    /// Thrust with finite `components` in `frame`.
    pub fn new(components: Vector3<f64>, frame: ThrustFrame) -> Result<Self> {
        all_finite("thrust components", components.as_slice())?;
        Ok(Self { components, frame })
    }
    /// The components.
    pub fn components(&self) -> Vector3<f64> {
        self.components
    }
    /// The frame.
    pub fn frame(&self) -> ThrustFrame {
        self.frame
    }
}

impl MomentumForce<3> for ConstantThrust {
    #[inline]
    fn force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
        p: &SVector<D, 3>,
    ) -> SVector<D, 3> {
        let c = self.components;
        match self.frame {
            ThrustFrame::Inertial => c.map(D::from),
            ThrustFrame::Rtn => {
                let rhat = q / q.dot(q).sqrt();
                let h = q.cross(p);
                let nhat = h / h.dot(&h).sqrt();
                let that = nhat.cross(&rhat);
                rhat * D::from(c[0]) + that * D::from(c[1]) + nhat * D::from(c[2])
            }
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The Cartesian system
// ---------------------------------------------------------------------------------------------

/// The perturbed two-body problem in Cartesian coordinates, per unit mass, in the plane
/// (`N = 2`) or in space (`N = 3`, the default):
///
/// ```math
/// H = \tfrac12|p|^2 - \frac{\mu}{|q|} + U(t, q)
/// ```
///
/// with the generalized force `f(t, q, p)` (absent when the system is built by
/// [`PerturbedTwoBody::conservative`]): the equations of motion `q̈ = −μq/|q|³ − ∇U + f` of
/// Cowell's formulation (Vallado 2013 ch. 8).
///
/// As a [`Separable`] system (`T = |p|²/2`, `V = −μ/|q| + U`) it runs under every integrator of
/// [`crate::integrate`] (explicit splittings refuse a system with `f` by a typed error); without
/// `f` it is also the "Kepler + R" shape [`PerturbedKepler`] (`H₁ = U`) that
/// [`WisdomHolman`](crate::integrate::WisdomHolman) and the SABA methods split, and
/// [`Parametric`] in the parameters of a [`ParametricDisturbance`].
///
/// ```
/// use hamilton_jacobi::perturbation::forces::{PerturbedTwoBody, J2};
/// use hamilton_jacobi::integrate::{integrate, Fixed, Problem, WisdomHolman};
/// use hamilton_jacobi::nalgebra::SVector;
/// // Kepler + J₂ in the equatorial plane, 100 Wisdom–Holman steps over one period.
/// let sys = PerturbedTwoBody::<_, _, 2>::conservative(1.0, J2::new(1.0, 1e-3, 1.0)?)?;
/// let (q0, p0) = (SVector::from([1.0, 0.0]), SVector::from([0.0, 1.0]));
/// let problem = Problem::new(&sys, 0.0, q0, p0, std::f64::consts::TAU)?;
/// let run = integrate(&problem, &Fixed::new(WisdomHolman::WH, 100)?, &mut ())?;
/// assert!((run.last.q.norm() - 1.0).abs() < 1e-2);
/// # Ok::<(), hamilton_jacobi::Error>(())
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PerturbedTwoBody<U, F = NoForce, const N: usize = 3> {
    kepler: InverseDistance,
    potential: U,
    force: Option<F>,
}

impl<U: DisturbingFunction<N>, const N: usize> PerturbedTwoBody<U, NoForce, N> {
    /// `H = |p|²/2 − μ/|q| + U`, `μ > 0`.
    pub fn conservative(mu: f64, potential: U) -> Result<Self> {
        Ok(Self {
            kepler: InverseDistance::new(mu)?,
            potential,
            force: None,
        })
    }
}

impl<U: DisturbingFunction<N>, F: MomentumForce<N>, const N: usize> PerturbedTwoBody<U, F, N> {
    /// `H = |p|²/2 − μ/|q| + U` with the non-conservative force `f`, `μ > 0`.
    pub fn with_force(mu: f64, potential: U, force: F) -> Result<Self> {
        Ok(Self {
            kepler: InverseDistance::new(mu)?,
            potential,
            force: Some(force),
        })
    }
    /// `μ`.
    pub fn mu(&self) -> f64 {
        self.kepler.mu()
    }
    /// The disturbing function `U`.
    pub fn potential(&self) -> &U {
        &self.potential
    }
    /// The force `f`, if any.
    pub fn force(&self) -> Option<&F> {
        self.force.as_ref()
    }
    /// The total perturbing acceleration `−∇U + f` at `(t, q, p)` (by AD), in any dual type:
    /// what enters the momentum equation `ṗ = −μq/|q|³ + R` [Ardema 18.1].
    pub fn perturbing_acceleration<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> SVector<D, N> {
        let g = GradientForce(&self.potential).force(t, q, p);
        match &self.force {
            Some(f) => g + f.force(t, q, p),
            None => g,
        }
    }
}

impl<U: DisturbingFunction<N>, F: MomentumForce<N>, const N: usize> MomentumForce<N>
    for PerturbedTwoBody<U, F, N>
{
    fn force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> SVector<D, N> {
        self.perturbing_acceleration(t, q, p)
    }
}

impl<U: DisturbingFunction<N> + ?Sized, const N: usize> DisturbingFunction<N> for &U {
    fn disturbing_function<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D {
        (**self).disturbing_function(t, q)
    }
}

impl<F: MomentumForce<N> + ?Sized, const N: usize> MomentumForce<N> for &F {
    fn force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> SVector<D, N> {
        (**self).force(t, q, p)
    }
}

impl<U: DisturbingFunction<N>, F: MomentumForce<N>, const N: usize> Separable<N>
    for PerturbedTwoBody<U, F, N>
{
    #[inline]
    fn kinetic<D: DualNum<f64> + Copy>(&self, _t: D, p: &SVector<D, N>) -> D {
        p.dot(p) * 0.5
    }
    #[inline]
    fn potential<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D {
        self.kepler.potential(q.dot(q).sqrt()) + self.potential.disturbing_function(t, q)
    }
    #[inline]
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> Option<SVector<D, N>> {
        self.force.as_ref().map(|f| f.force(t, q, p))
    }
}

/// The conservative perturbed two-body system is differentiable in the parameters of its
/// disturbing function: `H(k; q, p) = |p|²/2 − μ/|q| + U(k; t, q)`.
impl<U: ParametricDisturbance<N, M>, const N: usize, const M: usize> Parametric<N, M>
    for PerturbedTwoBody<U, NoForce, N>
{
    const NAMES: [&'static str; M] = U::NAMES;
    fn parameters(&self) -> SVector<f64, M> {
        self.potential.parameters()
    }
    #[inline]
    fn hamiltonian_with<D: DualNum<f64> + Copy>(
        &self,
        k: &SVector<D, M>,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> D {
        self.kinetic(t, p)
            + self.kepler.potential(q.dot(q).sqrt())
            + self.potential.disturbing_function_with(k, t, q)
    }
}

/// "Kepler + R" with `H₁ = U`: the Wisdom–Holman splitting into the exact Kepler flow and kicks
/// by `−∇U`.
impl<U: DisturbingFunction<N>, const N: usize> PerturbedKepler<N>
    for PerturbedTwoBody<U, NoForce, N>
{
    fn mu(&self) -> f64 {
        self.kepler.mu()
    }
    #[inline]
    fn perturbation<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D {
        self.potential.disturbing_function(t, q)
    }
}

/// A disturbing function `R(t, q)` given by an expression, in the sign of celestial mechanics
/// (force `+∇R`), as the potential energy `U = −R` of this module.
impl<const N: usize> DisturbingFunction<N> for ExpressionDisturbingFunction<N> {
    #[inline]
    fn disturbing_function<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D {
        -self.eval(t, q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ad::gradient;

    /// `−∇U_{J₂}` against the textbook acceleration (Vallado 2013 eq. 8-30):
    /// `a = −(3μJ₂R²/(2r⁵)) [x(1 − 5z²/r²), y(1 − 5z²/r²), z(3 − 5z²/r²)]`, in space and, with
    /// `z = 0`, in the equatorial plane, where also `U_{J₂} = −μJ₂R²/(2r³)`. Agreement to a few
    /// ulps of `|a|` (one AD pass vs. a hand formula, each ~10 roundings).
    #[test]
    fn j2_acceleration_matches_vallado() {
        let (mu, j2, rr) = (1.3, 1.08e-3, 0.9);
        let u = J2::new(mu, j2, rr).unwrap();
        let vallado = |q: Vector3<f64>| {
            let r = q.norm();
            let z2 = q[2] * q[2] / (r * r);
            let c = -1.5 * mu * j2 * rr * rr / r.powi(5);
            Vector3::new(
                q[0] * (1.0 - 5.0 * z2),
                q[1] * (1.0 - 5.0 * z2),
                q[2] * (3.0 - 5.0 * z2),
            ) * c
        };
        let q = SVector::<f64, 3>::new(0.7, -0.4, 0.55);
        let (_, g) = gradient(
            |x| u.disturbing_function(crate::ad::GradDual::from_re(0.0), x),
            &q,
        );
        let a = vallado(q);
        assert!(
            (-g - a).amax() < 8.0 * f64::EPSILON * a.amax(),
            "{:e}",
            (-g - a).amax()
        );
        // The equatorial plane.
        let q2 = SVector::<f64, 2>::new(0.7, -0.4);
        let (v2, g2) = gradient(
            |x| u.disturbing_function(crate::ad::GradDual::from_re(0.0), x),
            &q2,
        );
        let a = vallado(Vector3::new(q2[0], q2[1], 0.0));
        assert!(a[2] == 0.0);
        assert!(
            (-g2 - a.xy()).amax() < 8.0 * f64::EPSILON * a.amax(),
            "{:e}",
            (-g2 - a.xy()).amax()
        );
        let r = q2.norm();
        let closed = -0.5 * mu * j2 * rr * rr / (r * r * r);
        assert!((v2 - closed).abs() < 4.0 * f64::EPSILON * closed.abs());
    }

    /// The third-body force `μ₃[(q₃ − q)/|q₃ − q|³ − q₃/|q₃|³]` by AD, and its tidal limit
    /// `μ₃(3 q̂₃(q̂₃·q) − q)/ρ³` for `|q| ≪ ρ` (relative error `O(|q|/ρ)`).
    #[test]
    fn third_body_force_and_tidal_limit() {
        let q3 = Vector3::new(0.0, 200.0, 30.0);
        let tb = ThirdBody::new(2.0, ThirdBodyPath::Fixed { position: q3 }, true).unwrap();
        let q = Vector3::new(0.8, -0.3, 0.2);
        let f = GradientForce(tb).force(0.0, &q, &Vector3::zeros());
        let d = q3 - q;
        let exact = (d / d.norm().powi(3) - q3 / q3.norm().powi(3)) * 2.0;
        assert!((f - exact).amax() < 1e-12 * exact.amax());
        let rho = q3.norm();
        let qh = q3 / rho;
        let tidal = (qh * (3.0 * qh.dot(&q)) - q) * (2.0 / rho.powi(3));
        // Next term ∝ (|q|/ρ): 0.9/202 ≈ 4.5e−3, times a coefficient ≲ 5.
        assert!((f - tidal).amax() < 2.5e-2 * tidal.amax());
        // Circular path: position and rate.
        let c = ThirdBody::new(
            1.0,
            ThirdBodyPath::Circular {
                radius: 10.0,
                rate: 0.1,
                inclination: 0.3,
                phase: 0.2,
            },
            true,
        )
        .unwrap();
        let p = c.position(5.0);
        assert!((p.norm() - 10.0).abs() < 1e-14 * 10.0);
        assert!((p[2] / p[1] - 0.3f64.tan()).abs() < 1e-14);
    }

    #[test]
    fn rtn_thrust_frame() {
        let th = ConstantThrust::new(Vector3::new(1.0, 2.0, 3.0), ThrustFrame::Rtn).unwrap();
        let q = Vector3::new(2.0, 0.0, 0.0);
        let p = Vector3::new(0.0, 1.0, 0.0);
        let f = th.force(0.0, &q, &p);
        assert!((f - Vector3::new(1.0, 2.0, 3.0)).amax() < 1e-15);
        let drag = LinearDrag::new(0.5).unwrap();
        assert_eq!(
            MomentumForce::<3>::force(&drag, 0.0, &q, &p),
            Vector3::new(0.0, -0.5, 0.0)
        );
    }

    #[test]
    fn bad_parameters_are_rejected() {
        assert!(J2::new(0.0, 1e-3, 1.0).is_err());
        assert!(J2::new(1.0, f64::NAN, 1.0).is_err());
        assert!(J2::new(1.0, f64::INFINITY, 1.0).is_err());
        assert!(J2::new(1.0, 1e-3, -1.0).is_err());
        assert!(ThirdBody::new(
            -1.0,
            ThirdBodyPath::Fixed {
                position: Vector3::x()
            },
            true
        )
        .is_err());
        assert!(ThirdBody::new(
            1.0,
            ThirdBodyPath::Fixed {
                position: Vector3::zeros()
            },
            true
        )
        .is_err());
        assert!(ThirdBody::new(
            1.0,
            ThirdBodyPath::Circular {
                radius: 0.0,
                rate: 1.0,
                inclination: 0.0,
                phase: 0.0
            },
            true
        )
        .is_err());
        assert!(LinearDrag::new(-0.1).is_err());
        assert!(
            ConstantThrust::new(Vector3::new(f64::NAN, 0.0, 0.0), ThrustFrame::Inertial).is_err()
        );
        assert!(PerturbedTwoBody::<_, NoForce, 3>::conservative(-1.0, NoPotential).is_err());
        assert!(PerturbedTwoBody::<_, NoForce, 2>::conservative(0.0, NoPotential).is_err());
        assert!(PerturbedTwoBody::<_, _, 2>::with_force(
            f64::NAN,
            NoPotential,
            LinearDrag::new(0.1).unwrap()
        )
        .is_err());
    }
}
