//! The heavy symmetric top: its Hamiltonian in Euler angles, steady precession and, in
//! [`motion`], the Hamilton–Jacobi quadratures of its nutation.

pub mod motion;

use super::rigid_body::rotation::{check_chart, euler_chart_entry_points};
use super::rigid_body::HeavyRigidBody;
use super::{ExactFlow, Invariant, Invariants};
use crate::error::{finite, positive, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::lagrangian::{Natural, NaturalSystem};
use crate::phase::check_phase;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// Heavy symmetric top with a fixed point on its axis [Ardema 11.2, eqs. 11.9–11.26].
///
/// Coordinates are the 3-1-3 Euler angles `q = (φ, θ, ψ)` ([Ardema 11.1]: precession `φ` about the
/// vertical, nutation `θ` about the line of nodes, spin `ψ` about the figure axis), momenta
/// `p = (p_φ, p_θ, p_ψ)`. With `I` the transverse and `J` the axial moment of inertia about the
/// fixed point and `mgℓ` the weight times the distance of the mass centre from it,
///
/// ```math
/// L = \tfrac12 I (\dot\theta^2 + \dot\phi^2 \sin^2\theta)
///   + \tfrac12 J (\dot\psi + \dot\phi\cos\theta)^2 - mg\ell\cos\theta,
/// ```
///
/// and its Legendre transform [Ardema eq. 11.17]
///
/// ```math
/// H = \frac{p_\theta^2}{2I} + \frac{(p_\phi - p_\psi\cos\theta)^2}{2I\sin^2\theta}
///   + \frac{p_\psi^2}{2J} + mg\ell\cos\theta .
/// ```
///
/// `φ` and `ψ` are ignorable: `p_ψ = J ω_z` and `p_φ = I φ̇ sin²θ + p_ψ cos θ` are constant
/// [Ardema eqs. 11.15–11.16] and, with `H`, are the invariants ([`Invariants`]). The motion is
/// reduced to the cubic of [`motion`] and solved there by Hamilton–Jacobi quadratures
/// [Ardema 17.5], which also give the exact flow ([`ExactFlow`]).
///
/// # Coordinate singularity
/// The 3-1-3 chart is singular where `sin θ = 0`: the mass matrix has determinant `I² J sin²θ` and
/// `H` contains `1/sin²θ`. Every checked entry point ([`Hamiltonian::value`],
/// [`Hamiltonian::vector_field`], [`Invariants::invariants`], [`ExactFlow::exact_flow`], the
/// conversions below) refuses a state with `|sin θ| ≤ 2⁻⁵²` (θ within rounding of `0` or `π`)
/// with [`Error::Singular`]. A sleeping top exactly at `θ = 0` is not representable; start at a
/// small `θ` instead, e.g. `θ = 10⁻³`.
///
/// # One rigid body
/// The top is Lagrange's case of [`HeavyRigidBody`] (moments `(I, I, J)`, weight moment
/// `(0, 0, mgℓ)`): its mass matrix and Hamiltonian are that body's, `Bᵀ diag(I, I, J) B` and
/// `Σ Π_i²/(2I_i) + mgℓ cos θ`, which reduce to the forms above. Unlike [`HeavyRigidBody::new`],
/// [`HeavyTop::new`] admits any positive `I` and `J` (a model of the equations, also where
/// `J > 2I` is not realised by a body).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeavyTop {
    body: HeavyRigidBody,
    i: f64,
    j: f64,
    mgl: f64,
}

/// The two rates of steady precession at a fixed nutation angle [Ardema eq. 11.20].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SteadyPrecession {
    /// The fast rate `[γ + √(γ² − 2β cos θ₀)]/(2 cos θ₀)`; `None` at `cos θ₀ = 0`, where it is
    /// infinite.
    pub fast: Option<f64>,
    /// The slow rate `[γ − √(γ² − 2β cos θ₀)]/(2 cos θ₀) = β/[γ + √(γ² − 2β cos θ₀)]`.
    pub slow: f64,
}

/// Require a nutation angle `θ ∈ (0, π)`, the range of the 3-1-3 chart's `θ`
/// [Goldstein §4.4].
fn nutation_angle(theta: f64) -> Result<f64> {
    let theta = finite("nutation angle θ₀", theta)?;
    if theta > 0.0 && theta < std::f64::consts::PI {
        Ok(theta)
    } else {
        Err(Error::out_of_domain("nutation angle θ₀", theta, "(0, π)"))
    }
}

impl HeavyTop {
    /// Top with transverse moment of inertia `I > 0` and axial moment `J > 0` about the fixed
    /// point and `mgℓ > 0` (mass centre above the fixed point on the figure axis).
    pub fn new(i: f64, j: f64, mgl: f64) -> Result<Self> {
        let i = positive("transverse moment of inertia I", i)?;
        let j = positive("axial moment of inertia J", j)?;
        let mgl = positive("gravity moment mgℓ", mgl)?;
        Ok(Self {
            body: HeavyRigidBody::symmetric_top(i, j, mgl),
            i,
            j,
            mgl,
        })
    }

    /// The top as a [`HeavyRigidBody`] (Lagrange's case).
    pub fn rigid_body(&self) -> &HeavyRigidBody {
        &self.body
    }
    /// Transverse moment of inertia `I`.
    pub fn i(&self) -> f64 {
        self.i
    }
    /// Axial moment of inertia `J`.
    pub fn j(&self) -> f64 {
        self.j
    }
    /// Weight times distance of the mass centre from the fixed point, `mgℓ`.
    pub fn mgl(&self) -> f64 {
        self.mgl
    }
    /// `β = 2mgℓ/I`, the leading coefficient of the top's cubic [Ardema eq. 11.19].
    pub fn beta(&self) -> f64 {
        2.0 * self.mgl / self.i
    }
    /// `γ = p_ψ/I = J ω_z/I` for the spin `ω_z` [Ardema eq. 11.19].
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a NaN/∞ spin or a `γ` that overflows.
    pub fn gamma(&self, omega_z: f64) -> Result<f64> {
        let omega_z = finite("spin ω_z", omega_z)?;
        finite("γ = J ω_z/I", self.j * omega_z / self.i)
    }

    /// The Lagrangian `L = ½ q̇ᵀ a(θ) q̇ − mgℓ cos θ` [Ardema 11.2] as a [`crate::Lagrangian`], for
    /// Lagrange's equations, the Legendre machinery and Routh's reduction.
    pub fn as_lagrangian(&self) -> Natural<HeavyTop> {
        Natural(*self)
    }

    /// Canonical momenta `p = ∂L/∂q̇` from the Euler-angle rates [Ardema eqs. 11.15–11.16]:
    /// `p_φ = I φ̇ sin²θ + J(ψ̇ + φ̇ cos θ) cos θ`, `p_θ = I θ̇`, `p_ψ = J(ψ̇ + φ̇ cos θ)`.
    pub fn momenta(
        &self,
        theta: f64,
        theta_dot: f64,
        phi_dot: f64,
        psi_dot: f64,
    ) -> Result<SVector<f64, 3>> {
        let phi_dot = finite("φ̇", phi_dot)?;
        let omega_z = phi_dot * theta.cos() + finite("ψ̇", psi_dot)?;
        self.momenta_from_spin(theta, theta_dot, phi_dot, omega_z)
    }

    /// Canonical momenta from `(θ, θ̇, φ̇)` and the spin `ω_z = ψ̇ + φ̇ cos θ` [Ardema 11.2]:
    /// `p_ψ = J ω_z`, `p_φ = I φ̇ sin²θ + J ω_z cos θ`, `p_θ = I θ̇`.
    pub fn momenta_from_spin(
        &self,
        theta: f64,
        theta_dot: f64,
        phi_dot: f64,
        omega_z: f64,
    ) -> Result<SVector<f64, 3>> {
        let s = check_chart(theta)?;
        let (theta_dot, phi_dot) = (finite("θ̇", theta_dot)?, finite("φ̇", phi_dot)?);
        let p_psi = self.j * finite("spin ω_z", omega_z)?;
        let p = SVector::from([
            self.i * phi_dot * s * s + p_psi * theta.cos(),
            self.i * theta_dot,
            p_psi,
        ]);
        crate::error::all_finite("momenta", p.as_slice())?;
        Ok(p)
    }

    /// Euler-angle rates `(φ̇, θ̇, ψ̇) = ∂H/∂p` [Ardema eq. 11.16]:
    /// `φ̇ = (p_φ − p_ψ cos θ)/(I sin²θ)`, `θ̇ = p_θ/I`, `ψ̇ = p_ψ/J − cos θ · φ̇`.
    pub fn rates(&self, q: &SVector<f64, 3>, p: &SVector<f64, 3>) -> Result<SVector<f64, 3>> {
        Ok(self.vector_field(0.0, q, p)?.0)
    }

    /// The spin `ω_z = p_ψ/J` about the figure axis.
    pub fn spin(&self, p: &SVector<f64, 3>) -> Result<f64> {
        finite("spin ω_z", finite("p_ψ", p[2])? / self.j)
    }

    /// Steady precession at `θ₀` with spin `ω_z` [Ardema eq. 11.20]: the roots of
    /// `cos θ₀ φ̇² − γ φ̇ + β/2 = 0` (`θ̇ ≡ 0` needs `f(u₀) = f′(u₀) = 0` in the cubic),
    ///
    /// ```math
    /// \dot\phi = \frac{\gamma \pm \sqrt{\gamma^2 - 2\beta\cos\theta_0}}{2\cos\theta_0},
    /// ```
    ///
    /// computed without cancellation (the slow root as `β/[γ + √(γ² − 2β cos θ₀)]`). Requires
    /// `γ² ≥ 2β cos θ₀`, i.e. `|ω_z| ≥` [`HeavyTop::min_spin_for_steady_precession`]
    /// [Ardema eq. 11.21]; otherwise [`Error::OutOfDomain`].
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ or a rate that overflows; [`Error::OutOfDomain`] for
    /// `θ₀ ∉ (0, π)` or a spin below the least one; [`Error::Singular`] for `θ₀` within rounding
    /// of `0` or `π`.
    pub fn steady_precession(&self, theta0: f64, omega_z: f64) -> Result<SteadyPrecession> {
        check_chart(theta0)?;
        nutation_angle(theta0)?;
        let (beta, gamma) = (self.beta(), self.gamma(omega_z)?);
        let c = theta0.cos();
        let disc = gamma * gamma - 2.0 * beta * c;
        if disc < 0.0 {
            return Err(Error::out_of_domain(
                "spin ω_z",
                omega_z,
                format!(
                    "|ω_z| ≥ {} (no steady precession at θ₀ = {theta0} below this spin, \
                     [Ardema eq. 11.21])",
                    self.min_spin_for_steady_precession(theta0)?
                ),
            ));
        }
        // q = ½(γ + sgn γ · √disc): the root of larger magnitude is q/cos θ₀, the other β/(2q).
        let q = 0.5 * (gamma + disc.sqrt().copysign(gamma));
        let slow = finite("slow precession rate", 0.5 * beta / q)?;
        let fast = if c == 0.0 {
            None
        } else {
            Some(finite("fast precession rate", q / c)?)
        };
        Ok(SteadyPrecession { fast, slow })
    }

    /// The least spin for which steady precession at `θ₀` exists [Ardema eq. 11.21]:
    /// `ω_min = 2√(I mgℓ cos θ₀)/J` for `cos θ₀ > 0`, zero (every spin) otherwise.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ or an `ω_min` that overflows; [`Error::OutOfDomain`] for
    /// `θ₀ ∉ (0, π)` (the nutation angle of the 3-1-3 chart); [`Error::Singular`] for `θ₀` within
    /// rounding of `0` or `π`.
    pub fn min_spin_for_steady_precession(&self, theta0: f64) -> Result<f64> {
        check_chart(theta0)?;
        nutation_angle(theta0)?;
        let c = theta0.cos();
        if c > 0.0 {
            // √I·√(mgℓ cos θ₀) avoids overflow of the product for large I, mgℓ.
            finite(
                "least spin for steady precession",
                2.0 * (self.i.sqrt() * (self.mgl * c).sqrt()) / self.j,
            )
        } else {
            Ok(0.0)
        }
    }

    /// The critical spin of the sleeping top, `ω_c = 2√(I mgℓ)/J` [Ardema 11.2]: the vertical
    /// top is stable iff `J² ω_z² > 4 I mgℓ`. At `ω_c` the cubic has a triple root at `u = 1`
    /// (the time to reach it diverges, as at a separatrix).
    ///
    /// # Errors
    /// [`Error::NonFinite`] when `ω_c` overflows (e.g. `J` subnormal).
    pub fn critical_spin(&self) -> Result<f64> {
        // √I·√(mgℓ) avoids overflow of the product for large I, mgℓ.
        finite(
            "critical spin ω_c",
            2.0 * (self.i.sqrt() * self.mgl.sqrt()) / self.j,
        )
    }
}

impl NaturalSystem<3> for HeavyTop {
    /// `a = Bᵀ diag(I, I, J) B = [[I sin²θ + J cos²θ, 0, J cos θ], [0, I, 0], [J cos θ, 0, J]]`
    /// ([`HeavyRigidBody`]).
    fn mass<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        self.body.mass(t, q)
    }
    /// `V = mgℓ cos θ`.
    fn potential<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 3>) -> D {
        self.body.potential(t, q)
    }
}

impl Hamiltonian<3> for HeavyTop {
    /// [`HeavyRigidBody`]'s `Σ Π_i²/(2I_i) + w·γ` (struct docs).
    #[inline]
    fn hamiltonian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 3>, p: &SVector<D, 3>) -> D {
        self.body.hamiltonian(t, q, p)
    }

    euler_chart_entry_points!();
}

impl Invariants<3> for HeavyTop {
    /// Those of every heavy body, `energy` (H) and `p_phi` (vertical angular momentum)
    /// ([`HeavyRigidBody`]), and Lagrange's `p_psi` (axial angular momentum).
    fn invariants(
        &self,
        t: f64,
        q: &SVector<f64, 3>,
        p: &SVector<f64, 3>,
    ) -> Result<Vec<Invariant>> {
        let mut invariants = self.body.invariants(t, q, p)?;
        invariants.push(Invariant {
            name: "p_psi",
            value: p[2],
        });
        Ok(invariants)
    }
}

impl ExactFlow<3> for HeavyTop {
    /// By the Hamilton–Jacobi quadratures of [`motion::Nutation`]: `θ(t)` by inverting the
    /// time law, `φ(t)`, `ψ(t)` by the partial precession and spin integrals. Errors as
    /// [`motion::Nutation::from_state`] (chart singularity, orbit through the pole).
    fn exact_flow(
        &self,
        t0: f64,
        q0: &SVector<f64, 3>,
        p0: &SVector<f64, 3>,
        t: f64,
    ) -> Result<(SVector<f64, 3>, SVector<f64, 3>)> {
        check_phase(t0, q0, p0)?;
        let dt = finite("t", t)? - t0;
        motion::Nutation::from_state(self, q0, p0)?.propagate(q0, p0, dt)
    }
}
