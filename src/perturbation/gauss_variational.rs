//! Gauss's variational equations: the rates of the osculating Kepler elements under an arbitrary
//! perturbing acceleration given in the RTN frame, in modified equinoctial elements (regular at
//! `e = 0` and `i = 0`) and in classical elements; small force models and the same motion as a
//! Cartesian [`Hamiltonian`](crate::Hamiltonian) with a non-conservative force, for cross-checks.
//!
//! # Frame
//! With `h = r × v`, the RTN (radial, transverse, normal) unit vectors are
//!
//! ```math
//! \hat r = \frac{r}{|r|},\qquad \hat n = \frac{h}{|h|},\qquad \hat t = \hat n \times \hat r,
//! ```
//!
//! and a perturbing acceleration `a_d` has components `(R, T, N) = (a_d·r̂, a_d·t̂, a_d·n̂)`
//! ([`inertial_to_rtn`], [`rtn_to_inertial`]; Vallado 2013 §3.3 calls the frame RSW). The frame
//! is undefined for `r = 0` and for rectilinear motion `h = 0`.
//!
//! # Modified equinoctial elements
//! For `(p, f, g, h, k, L)` (Walker, Ireland & Owens 1985; see
//! [`ModifiedEquinoctial`]) with `w = 1 + f cos L + g sin L`, `s² = 1 + h² + k²` and
//! `χ = h sin L − k cos L`, the osculating elements of `r̈ = −μr/|r|³ + a_d` obey
//!
//! ```math
//! \begin{aligned}
//! \dot p &= \frac{2p}{w}\sqrt{\frac p\mu}\, T, \\
//! \dot f &= \sqrt{\frac p\mu}\Big[R \sin L + \frac{(w+1)\cos L + f}{w}\,T - \frac{g\,\chi}{w}\,N\Big], \\
//! \dot g &= \sqrt{\frac p\mu}\Big[-R \cos L + \frac{(w+1)\sin L + g}{w}\,T + \frac{f\,\chi}{w}\,N\Big], \\
//! \dot h &= \sqrt{\frac p\mu}\,\frac{s^2 \cos L}{2w}\,N, \qquad
//! \dot k = \sqrt{\frac p\mu}\,\frac{s^2 \sin L}{2w}\,N, \\
//! \dot L &= \sqrt{\mu p}\Big(\frac wp\Big)^2 + \sqrt{\frac p\mu}\,\frac{\chi}{w}\,N
//! \end{aligned}
//! ```
//!
//! (Walker, Ireland & Owens 1985, in the form corrected by their 1986 erratum; the same equations
//! are in J. T. Betts, *Practical Methods for Optimal Control*, 2nd ed., SIAM 2010).
//! Nothing here is singular at `e = 0` or `i = 0`; the only singularity is `i = π`
//! (`h, k → ∞`), as for the elements themselves. [`gauss_modified_equinoctial`] is written for
//! any [`DualNum`], so its derivatives (e.g. for a variational equation) come by AD.
//!
//! These equations are `ċ = (∂Ψ/∂c)⁻¹ (v, −μr/|r|³ + a_d)` for the time-independent map
//! `c ↦ (r, v) = Ψ(c)` of [`ModifiedEquinoctial::to_state`]: the Kepler part of the field gives
//! the single term `√(μp)(w/p)²` in `L̇`, the perturbation the rest. The tests check both parts
//! against [`variation_of_constants_rhs`](super::variation::variation_of_constants_rhs) of the
//! general engine, which inverts the AD Jacobian of `Ψ`.
//!
//! # Classical elements
//! Gauss's planetary equations for an ellipse `(a, e, i, Ω, ω, M)` with `n = √(μ/a³)`,
//! `p = a(1 − e²)`, `h = √(μp)`, `r = p/(1 + e cos ν)`, `u = ω + ν`, `b = a√(1 − e²)`
//! (Vallado 2013 §9.3; Battin 1999 §10.4):
//!
//! ```math
//! \begin{aligned}
//! \dot a &= \frac{2a^2}{h}\Big(e \sin\nu\, R + \frac pr\, T\Big), &
//! \dot e &= \frac1h\big(p \sin\nu\, R + ((p + r)\cos\nu + re)\,T\big), \\
//! \dot i &= \frac{r\cos u}{h}\,N, &
//! \dot\Omega &= \frac{r \sin u}{h \sin i}\,N, \\
//! \dot\omega &= \frac{1}{he}\big(-p\cos\nu\, R + (p + r)\sin\nu\, T\big) - \frac{r \sin u \cos i}{h\sin i}\,N, &
//! \dot M &= n + \frac{b}{ahe}\big((p\cos\nu - 2re)\,R - (p + r)\sin\nu\, T\big).
//! \end{aligned}
//! ```
//!
//! `ω̇` and `Ṁ` contain `1/e`, `Ω̇` and `ω̇` contain `1/sin i`: at a circular or equatorial orbit
//! (`e < CIRCULAR_TOLERANCE`, `|sin i| < CIRCULAR_TOLERANCE`, the tolerance below which
//! [`state_to_classical`](crate::systems::kepler::elements::state_to_classical) sets `e = 0` or `Ω = 0`)
//! [`gauss_classical`] refuses with [`Error::Singular`]; use the modified equinoctial form.
//!
//! # Force models
//! The perturbing acceleration is any [`MomentumForce<3>`] (a force per unit mass `a_d(t, r, v)`,
//! written for any dual type): the models of [`forces`](super::forces) — linear drag, constant
//! thrust in the inertial or RTN frame, sums — and [`ExponentialDrag`]
//! `−½ρ(|r|) (C_D A/m) |v_rel| v_rel` in a rotating exponential atmosphere. The Cartesian system
//! with the same force, for the crate's integrators, is
//! [`PerturbedTwoBody`](super::forces::PerturbedTwoBody).
//!
//! # References
//! * M. J. H. Walker, B. Ireland & J. Owens, "A set of modified equinoctial orbit elements",
//!   *Celestial Mechanics* 36, 409–419 (1985), doi:10.1007/BF01227493, with the authors' erratum
//!   (1986).
//! * R. H. Battin, *An Introduction to the Mathematics and Methods of Astrodynamics*, rev. ed.,
//!   AIAA (1999), §10.4.
//! * D. A. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., Microcosm (2013),
//!   §3.3 (RSW frame), §8.6 (atmospheric drag, exponential atmosphere), §9.3 (Gauss's form of the
//!   VOP equations).

use nalgebra::{SVector, Vector3};
use num_dual::DualNum;

use super::ode::{ElementOde, ElementPair};
use super::variation::MomentumForce;
use crate::error::{all_finite, finite, non_negative, positive, Error, Lazy, Result};
use crate::special::kepler_equation::mean_to_true;
use crate::systems::kepler::elements::{Classical, ModifiedEquinoctial};
use crate::systems::kepler::orbit::CIRCULAR_TOLERANCE;

/// A 3-vector of any dual type.
pub type V3<D> = SVector<D, 3>;

fn check_mu(mu: f64) -> Result<f64> {
    positive("gravitational parameter μ", mu)
}

fn cross<D: DualNum<f64> + Copy>(a: &V3<D>, b: &V3<D>) -> V3<D> {
    V3::new(
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    )
}

fn dot<D: DualNum<f64> + Copy>(a: &V3<D>, b: &V3<D>) -> D {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn check_re<D: DualNum<f64> + Copy>(what: &str, x: &V3<D>) -> Result<()> {
    all_finite(what, &[x[0].re(), x[1].re(), x[2].re()])
}

// ---------------------------------------------------------------------------------------------
// RTN frame
// ---------------------------------------------------------------------------------------------

/// The RTN unit vectors `(r̂, t̂, n̂)`: `r̂ = r/|r|`, `n̂ = (r × v)/|r × v|`, `t̂ = n̂ × r̂`, in any
/// dual type.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ (real parts); [`Error::InvalidInput`] for `r = 0` or
/// rectilinear motion (`r × v = 0`), where the frame is undefined.
pub fn rtn_basis<D: DualNum<f64> + Copy>(r: &V3<D>, v: &V3<D>) -> Result<[V3<D>; 3]> {
    check_re("position r", r)?;
    check_re("velocity v", v)?;
    let rn = dot(r, r).sqrt();
    if rn.re() == 0.0 {
        return Err(Error::invalid(
            "position r",
            "r = 0: the RTN frame is undefined",
        ));
    }
    let hv = cross(r, v);
    let hn = dot(&hv, &hv).sqrt();
    if hn.re() == 0.0 {
        return Err(Error::invalid(
            "state (r, v)",
            "rectilinear motion (r × v = 0): the RTN frame is undefined",
        ));
    }
    if !(rn.re().is_finite() && hn.re().is_finite()) {
        return Err(Error::NonFinite {
            what: "|r| or |r × v| in the RTN frame".into(),
            value: f64::INFINITY,
        });
    }
    let rh = r / rn;
    let nh = hv / hn;
    let th = cross(&nh, &rh);
    Ok([rh, th, nh])
}

/// Components `(R, T, N) = (a·r̂, a·t̂, a·n̂)` of an inertial acceleration `a` in the RTN frame of
/// the state `(r, v)`, in any dual type.
///
/// # Errors
/// As [`rtn_basis`]; [`Error::NonFinite`] for a NaN/∞ acceleration.
pub fn inertial_to_rtn<D: DualNum<f64> + Copy>(r: &V3<D>, v: &V3<D>, a: &V3<D>) -> Result<V3<D>> {
    check_re("acceleration", a)?;
    let [rh, th, nh] = rtn_basis(r, v)?;
    Ok(V3::new(dot(a, &rh), dot(a, &th), dot(a, &nh)))
}

/// The inertial acceleration `R r̂ + T t̂ + N n̂` from its RTN components, in any dual type.
///
/// # Errors
/// As [`rtn_basis`]; [`Error::NonFinite`] for NaN/∞ components.
pub fn rtn_to_inertial<D: DualNum<f64> + Copy>(
    r: &V3<D>,
    v: &V3<D>,
    a_rtn: &V3<D>,
) -> Result<V3<D>> {
    check_re("RTN acceleration", a_rtn)?;
    let [rh, th, nh] = rtn_basis(r, v)?;
    Ok(rh * a_rtn[0] + th * a_rtn[1] + nh * a_rtn[2])
}

// ---------------------------------------------------------------------------------------------
// Gauss's equations in modified equinoctial elements
// ---------------------------------------------------------------------------------------------

/// The rates `(ṗ, ḟ, ġ, ḣ, k̇, L̇)` of the modified equinoctial elements under the perturbing
/// acceleration with RTN components `a_rtn = (R, T, N)`, in closed form (see the
/// [module docs](self); Walker, Ireland & Owens 1985 with the 1986 erratum), in any dual
/// type. The rates are returned in a [`ModifiedEquinoctial`] (field `l` holds `L̇`, including the
/// Keplerian `√(μp)(w/p)²`).
///
/// # Errors
/// [`Error::OutOfDomain`] / [`Error::NonFinite`] for `μ ≤ 0` or non-finite `μ`; as
/// [`ModifiedEquinoctial::validate`] (`p ≤ 0`, `w ≤ 0`, NaN/∞); [`Error::NonFinite`] for a NaN/∞
/// acceleration.
pub fn gauss_modified_equinoctial<D: DualNum<f64> + Copy>(
    mu: f64,
    el: &ModifiedEquinoctial<D>,
    a_rtn: &V3<D>,
) -> Result<ModifiedEquinoctial<D>> {
    let mu = check_mu(mu)?;
    el.validate()?;
    check_re("RTN acceleration (R, T, N)", a_rtn)?;
    let (sl, cl) = el.l.sin_cos();
    Ok(mee_rates(mu, el, sl, cl, a_rtn))
}

/// The closed form of [`gauss_modified_equinoctial`] for validated input, with
/// `(sin L, cos L)` already formed.
fn mee_rates<D: DualNum<f64> + Copy>(
    mu: f64,
    el: &ModifiedEquinoctial<D>,
    sl: D,
    cl: D,
    a_rtn: &V3<D>,
) -> ModifiedEquinoctial<D> {
    let (p, f, g, h, k) = (el.p, el.f, el.g, el.h, el.k);
    let (rr, tt, nn) = (a_rtn[0], a_rtn[1], a_rtn[2]);
    let w = f * cl + g * sl + 1.0;
    let s2 = h * h + k * k + 1.0;
    let chi = h * sl - k * cl;
    let sp = (p / mu).sqrt();
    let spw = sp / w;
    ModifiedEquinoctial {
        p: p * spw * tt * 2.0,
        f: sp * rr * sl + spw * (((w + 1.0) * cl + f) * tt - g * chi * nn),
        g: -sp * rr * cl + spw * (((w + 1.0) * sl + g) * tt + f * chi * nn),
        h: spw * s2 * cl * nn * 0.5,
        k: spw * s2 * sl * nn * 0.5,
        l: (p * p * p).recip().sqrt() * mu.sqrt() * w * w + spw * chi * nn,
    }
}

// ---------------------------------------------------------------------------------------------
// Gauss's planetary equations in classical elements
// ---------------------------------------------------------------------------------------------

/// The rates `(ȧ, ė, i̇, Ω̇, ω̇, Ṁ)` of the classical elements of an ellipse under the perturbing
/// acceleration with RTN components `a_rtn = (R, T, N)` (Gauss's planetary equations, see the
/// [module docs](self); Vallado 2013 §9.3, Battin 1999 §10.4), returned in a
/// [`Classical`] (field `mean_anomaly` holds `Ṁ`, including the mean motion `n`).
///
/// # Errors
/// [`Error::OutOfDomain`] / [`Error::NonFinite`] for `μ ≤ 0` and as [`Classical::validate`];
/// [`Error::OutOfDomain`] for `e ≥ 1` (the equations here are for ellipses);
/// [`Error::Singular`] for `e < CIRCULAR_TOLERANCE` (`ω̇`, `Ṁ` ∝ `1/e`) and for
/// `|sin i| < CIRCULAR_TOLERANCE` (`Ω̇`, `ω̇` ∝ `1/sin i`) — the reported `rcond` is `e` or
/// `|sin i|`, the factor by which the Jacobian of the classical element map degenerates there;
/// [`Error::NonFinite`] for a NaN/∞ acceleration.
pub fn gauss_classical(mu: f64, el: &Classical, a_rtn: &Vector3<f64>) -> Result<Classical> {
    let mu = check_mu(mu)?;
    el.validate()?;
    all_finite("RTN acceleration (R, T, N)", a_rtn.as_slice())?;
    let (a, e, i) = (el.a, el.e, el.i);
    if e >= 1.0 {
        return Err(Error::out_of_domain(
            "eccentricity e (Gauss's planetary equations in classical elements are written for \
             ellipses; use modified equinoctial elements)",
            e,
            "[0, 1)",
        ));
    }
    let at = || {
        format!(
            "(a, e, i, Ω, ω, M) = {:?}",
            [a, e, i, el.raan, el.argp, el.mean_anomaly]
        )
    };
    if e < CIRCULAR_TOLERANCE {
        return Err(Error::Singular {
            what: format!(
                "Gauss's planetary equations in classical elements (ω̇ and Ṁ contain 1/e; \
                 circular orbit, e < {CIRCULAR_TOLERANCE:e}: use modified equinoctial elements)"
            ),
            at: at(),
            rcond: e,
        });
    }
    let si = i.sin();
    if si.abs() < CIRCULAR_TOLERANCE {
        return Err(Error::Singular {
            what: format!(
                "Gauss's planetary equations in classical elements (Ω̇ and ω̇ contain 1/sin i; \
                 equatorial orbit, |sin i| < {CIRCULAR_TOLERANCE:e}: use modified equinoctial \
                 elements)"
            ),
            at: at(),
            rcond: si.abs(),
        });
    }
    let ci = i.cos();
    let nu = mean_to_true(el.mean_anomaly, e)?;
    let (sn, cn) = nu.sin_cos();
    let one_m_e2 = (1.0 - e) * (1.0 + e);
    let p = a * one_m_e2;
    let h = (mu * p).sqrt();
    let n = (mu / a).sqrt() / a;
    let r = p / (1.0 + e * cn);
    let (su, cu) = (el.argp + nu).sin_cos();
    let b = a * one_m_e2.sqrt();
    let (rr, tt, nn) = (a_rtn[0], a_rtn[1], a_rtn[2]);
    let rates = Classical {
        a: 2.0 * a * a / h * (e * sn * rr + p / r * tt),
        e: (p * sn * rr + ((p + r) * cn + r * e) * tt) / h,
        i: r * cu / h * nn,
        raan: r * su / (h * si) * nn,
        argp: (-p * cn * rr + (p + r) * sn * tt) / (h * e) - r * su * ci / (h * si) * nn,
        mean_anomaly: n + b / (a * h * e) * ((p * cn - 2.0 * r * e) * rr - (p + r) * sn * tt),
    };
    all_finite(
        Lazy(|f| write!(f, "classical element rates at {}", at())),
        &[
            rates.a,
            rates.e,
            rates.i,
            rates.raan,
            rates.argp,
            rates.mean_anomaly,
        ],
    )?;
    Ok(rates)
}

// ---------------------------------------------------------------------------------------------
// Force models
// ---------------------------------------------------------------------------------------------

/// Quadratic drag in an exponential atmosphere rotating rigidly about the z axis:
///
/// ```math
/// a_d = -\tfrac12\,\rho(|r|)\,B\,|v_{rel}|\,v_{rel},\qquad
/// \rho = \rho_0\,e^{-(|r| - r_0)/H},\qquad v_{rel} = v - \omega_\oplus \hat z \times r,
/// ```
///
/// with the ballistic coefficient `B = C_D A/m` (Vallado 2013 §8.6: the drag acceleration and
/// the exponential atmosphere). Units are the caller's: with lengths in km, `ρ` in kg/km³ and
/// `B` in km²/kg.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ExponentialDrag {
    rho0: f64,
    r0: f64,
    scale_height: f64,
    ballistic: f64,
    omega: f64,
}

impl ExponentialDrag {
    /// Density `ρ₀ ≥ 0` at the reference radius `r₀ > 0`, scale height `H > 0`, ballistic
    /// coefficient `B = C_D A/m ≥ 0`, atmosphere rotation rate `ω` about z (any finite value; 0
    /// for a non-rotating atmosphere).
    ///
    /// # Errors
    /// [`Error::NonFinite`] / [`Error::OutOfDomain`] naming the bad parameter.
    pub fn new(rho0: f64, r0: f64, scale_height: f64, ballistic: f64, omega: f64) -> Result<Self> {
        Ok(Self {
            rho0: non_negative("reference density ρ₀", rho0)?,
            r0: positive("reference radius r₀", r0)?,
            scale_height: positive("scale height H", scale_height)?,
            ballistic: non_negative("ballistic coefficient C_D A/m", ballistic)?,
            omega: finite("atmosphere rotation rate ω", omega)?,
        })
    }

    /// The density `ρ(|r|) = ρ₀ e^{−(|r| − r₀)/H}`.
    pub fn density<D: DualNum<f64> + Copy>(&self, radius: D) -> D {
        ((radius - self.r0) * (-1.0 / self.scale_height)).exp() * self.rho0
    }
}

impl MomentumForce<3> for ExponentialDrag {
    fn force<D: DualNum<f64> + Copy>(&self, _t: D, r: &V3<D>, v: &V3<D>) -> V3<D> {
        // ω ẑ × r = ω(−y, x, 0).
        let vrel = V3::new(v[0] + r[1] * self.omega, v[1] - r[0] * self.omega, v[2]);
        let rho = self.density(dot(r, r).sqrt());
        let speed = dot(&vrel, &vrel).sqrt();
        vrel * (rho * speed * (-0.5 * self.ballistic))
    }
}

/// Gauss's equations in modified equinoctial elements for a force model, as an [`ElementOde`]
/// with blocks `(p, f, g)` and `(h, k, L)`: the state from [`ModifiedEquinoctial::to_state`], the
/// force there, its RTN components ([`inertial_to_rtn`]) and [`gauss_modified_equinoctial`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaussEquations<F> {
    mu: f64,
    /// The perturbing acceleration.
    pub force: F,
}

impl<F: MomentumForce<3>> GaussEquations<F> {
    /// The equations for gravitational parameter `μ > 0` and the force model `force`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] / [`Error::OutOfDomain`] unless `μ > 0` is finite.
    pub fn new(mu: f64, force: F) -> Result<Self> {
        Ok(Self {
            mu: check_mu(mu)?,
            force,
        })
    }

    /// Gravitational parameter.
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// The element rates at `(t, el)` in any dual type (so the whole chain elements → state →
    /// force → RTN → rates can be differentiated): [`ModifiedEquinoctial::to_state`], the force
    /// there, [`inertial_to_rtn`] and [`gauss_modified_equinoctial`], with the elements validated
    /// and `sin L`, `cos L` formed once for the state and the rates.
    ///
    /// # Errors
    /// As [`ModifiedEquinoctial::to_state`], [`inertial_to_rtn`] (a NaN/∞ force is
    /// [`Error::NonFinite`]) and [`gauss_modified_equinoctial`].
    pub fn rates<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        el: &ModifiedEquinoctial<D>,
    ) -> Result<ModifiedEquinoctial<D>> {
        el.validate()?;
        let (sl, cl) = el.l.sin_cos();
        let (r, v) = el.state_at(self.mu, sl, cl)?;
        let acc = self.force.force(t, &r, &v);
        let a_rtn = inertial_to_rtn(&r, &v, &acc)?;
        check_re("RTN acceleration (R, T, N)", &a_rtn)?;
        Ok(mee_rates(self.mu, el, sl, cl, &a_rtn))
    }
}

/// Modified equinoctial elements from the blocks `(p, f, g)`, `(h, k, L)`.
pub fn mee_from_blocks<D: DualNum<f64> + Copy>(a: &V3<D>, b: &V3<D>) -> ModifiedEquinoctial<D> {
    ModifiedEquinoctial {
        p: a[0],
        f: a[1],
        g: a[2],
        h: b[0],
        k: b[1],
        l: b[2],
    }
}

/// The blocks `(p, f, g)`, `(h, k, L)` of modified equinoctial elements.
pub fn mee_to_blocks<D: DualNum<f64> + Copy>(el: &ModifiedEquinoctial<D>) -> (V3<D>, V3<D>) {
    (V3::new(el.p, el.f, el.g), V3::new(el.h, el.k, el.l))
}

impl<F: MomentumForce<3>> ElementOde<3> for GaussEquations<F> {
    fn rhs(&self, t: f64, a: &Vector3<f64>, b: &Vector3<f64>) -> Result<ElementPair<3>> {
        let rates = self.rates(t, &mee_from_blocks(a, b))?;
        Ok(mee_to_blocks(&rates))
    }
}

/// Gauss's planetary equations in classical elements for a force model, as an [`ElementOde`]
/// with blocks `(a, e, i)` and `(Ω, ω, M)`. Fails with [`Error::Singular`] at circular or
/// equatorial orbits ([`gauss_classical`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GaussClassical<F> {
    mu: f64,
    /// The perturbing acceleration.
    pub force: F,
}

impl<F: MomentumForce<3>> GaussClassical<F> {
    /// The equations for gravitational parameter `μ > 0` and the force model `force`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] / [`Error::OutOfDomain`] unless `μ > 0` is finite.
    pub fn new(mu: f64, force: F) -> Result<Self> {
        Ok(Self {
            mu: check_mu(mu)?,
            force,
        })
    }
}

impl<F: MomentumForce<3>> ElementOde<3> for GaussClassical<F> {
    fn rhs(&self, t: f64, a: &Vector3<f64>, b: &Vector3<f64>) -> Result<ElementPair<3>> {
        let el = Classical {
            a: a[0],
            e: a[1],
            i: a[2],
            raan: b[0],
            argp: b[1],
            mean_anomaly: b[2],
        };
        let (r, v) = el.to_state(self.mu)?;
        let acc = self.force.force(t, &r, &v);
        let a_rtn = inertial_to_rtn(&r, &v, &acc)?;
        let d = gauss_classical(self.mu, &el, &a_rtn)?;
        Ok((
            Vector3::new(d.a, d.e, d.i),
            Vector3::new(d.raan, d.argp, d.mean_anomaly),
        ))
    }
}
