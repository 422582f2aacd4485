#[cfg(doc)]
use crate::error::Error;
use crate::error::{finite, positive, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::SVector;
use num_dual::DualNum;

/// Bead on a hoop of radius `a` spinning at the constant rate `ω` about its vertical diameter;
/// `θ` measured from the bottom [Ardema 8.2]:
///
/// ```math
/// L = \tfrac12 m a^2 (\dot\theta^2 + \omega^2 \sin^2\theta) + m g a \cos\theta .
/// ```
///
/// The Jacobi integral `h = ½ma²θ̇² − ½ma²ω² sin²θ − mga cos θ` is conserved while `T + V` is not
/// (`T₀ = ½ma²ω² sin²θ ≠ 0`). Relative equilibrium `cos θ* = g/(aω²)` if `aω² > g`, small-oscillation
/// frequency `ω sin θ*`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BeadOnHoop {
    m: f64,
    a: f64,
    g: f64,
    omega: f64,
}

impl BeadOnHoop {
    /// Bead of mass `m > 0` on a hoop of radius `a > 0`, gravity `g`, spin `ω`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ parameters, or when a coefficient of `L` (`ma²`, `ma²ω²`,
    /// `mga`) overflows; [`Error::OutOfDomain`] for `m ≤ 0` or `a ≤ 0`.
    pub fn new(m: f64, a: f64, g: f64, omega: f64) -> Result<Self> {
        let bead = Self {
            m: positive("mass m", m)?,
            a: positive("radius a", a)?,
            g: finite("g", g)?,
            omega: finite("ω", omega)?,
        };
        let ma2 = finite("coefficient m a²", bead.m * bead.a * bead.a)?;
        finite("coefficient m a² ω²", ma2 * bead.omega * bead.omega)?;
        finite("coefficient m g a", bead.m * bead.g * bead.a)?;
        Ok(bead)
    }

    /// Energy `T + V = ½ma²(θ̇² + ω² sin²θ) − mga cos θ` in the rotating description (`T`
    /// including the `ω² sin²θ` part); not conserved [Ardema 8.2].
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ arguments or an energy that overflows.
    pub fn energy(&self, theta: f64, theta_dot: f64) -> Result<f64> {
        let theta = finite("θ", theta)?;
        let theta_dot = finite("θ̇", theta_dot)?;
        let ma2 = self.m * self.a * self.a;
        finite(
            "energy T + V",
            0.5 * ma2 * (theta_dot * theta_dot + (self.omega * theta.sin()).powi(2))
                - self.m * self.g * self.a * theta.cos(),
        )
    }

    /// The relative equilibrium `θ* = acos(g/(aω²))` and its small-oscillation frequency
    /// `ω sin θ*`; `None` if `aω² ≤ g` (only the bottom is stable).
    pub fn relative_equilibrium(&self) -> Option<(f64, f64)> {
        let c = self.g / (self.a * self.omega * self.omega);
        (c < 1.0 && c.is_finite()).then(|| {
            let th = c.acos();
            (th, self.omega.abs() * th.sin())
        })
    }
}

impl Lagrangian<1> for BeadOnHoop {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 1>, v: &SVector<D, 1>) -> D {
        let ma2 = self.m * self.a * self.a;
        let s = q[0].sin();
        (v[0] * v[0] + s * s * (self.omega * self.omega)) * (0.5 * ma2)
            + q[0].cos() * (self.m * self.g * self.a)
    }
}
