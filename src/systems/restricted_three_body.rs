//! The circular restricted three-body problem in the rotating frame [Szebehely, *Theory of
//! Orbits*, Academic Press 1967, §4.4 and §5.5; Meyer, Hall & Offin, *Introduction to Hamiltonian
//! Dynamical Systems*, 2nd ed., §3.2 and §5.2].
//!
//! Units: the distance of the primaries, their total mass and the inverse of their angular rate
//! are one; the primaries of masses `1 − μ` and `μ` sit at `(−μ, 0, 0)` and `(1 − μ, 0, 0)`.
//! With `p = v + ẑ × r`,
//!
//! ```text
//! H = ½|p|² + y p_x − x p_y − (1 − μ)/r₁ − μ/r₂,      r₁ = |r − (−μ, 0, 0)|, r₂ = |r − (1 − μ, 0, 0)|,
//! ```
//!
//! (`H = −C/2` with Jacobi's constant `C`), for the planar problem (`N = 2`, `z = p_z = 0`) and the
//! spatial one (`N = 3`). The triangular points L4, L5 at `(½ − μ, ±√3/2)` are linearly stable for
//! `27μ(1 − μ) < 1`, i.e. below Routh's ratio `μ_R = (1 − √(23/27))/2`: the characteristic
//! polynomial of the planar linearisation is `λ⁴ + λ² + (27/4)μ(1 − μ)`.

use crate::error::{finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use nalgebra::SVector;
use num_dual::DualNum;

/// The circular restricted three-body problem with mass ratio `μ` in the rotating frame (see the
/// [module docs](self)); `Hamiltonian<2>` (planar) and `Hamiltonian<3>` (spatial).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RestrictedThreeBody {
    mu: f64,
}

impl RestrictedThreeBody {
    /// The problem with mass ratio `μ = m₂/(m₁ + m₂) ∈ (0, 1)`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for `μ ∉ (0, 1)`.
    pub fn new(mu: f64) -> Result<Self> {
        let mu = finite("mass ratio μ", mu)?;
        if !(mu > 0.0 && mu < 1.0) {
            return Err(Error::out_of_domain("mass ratio μ", mu, "(0, 1)"));
        }
        Ok(Self { mu })
    }
    /// The mass ratio `μ`.
    pub fn mu(&self) -> f64 {
        self.mu
    }
    /// The planar state `(q, p)` of the triangular point L4 at `(½ − μ, √3/2)`, at rest in the
    /// rotating frame (`p = (−y, x)`).
    pub fn l4(&self) -> (SVector<f64, 2>, SVector<f64, 2>) {
        let (x, y) = (0.5 - self.mu, 0.75f64.sqrt());
        (SVector::from([x, y]), SVector::from([-y, x]))
    }
    /// `H` at the position `(x, y, z)` and momentum `(p_x, p_y, p_z)`.
    fn energy<D: DualNum<f64> + Copy>(&self, r: [D; 3], p: [D; 3]) -> D {
        let mu = self.mu;
        let [x, y, z] = r;
        let (x1, x2) = (x + mu, x - (1.0 - mu));
        let r1 = (x1 * x1 + y * y + z * z).sqrt();
        let r2 = (x2 * x2 + y * y + z * z).sqrt();
        (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) * 0.5 + y * p[0]
            - x * p[1]
            - r1.recip() * (1.0 - mu)
            - r2.recip() * mu
    }
}

impl Hamiltonian<2> for RestrictedThreeBody {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 2>,
        p: &SVector<D, 2>,
    ) -> D {
        let zero = D::from(0.0);
        self.energy([q[0], q[1], zero], [p[0], p[1], zero])
    }
}

impl Hamiltonian<3> for RestrictedThreeBody {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
        p: &SVector<D, 3>,
    ) -> D {
        self.energy([q[0], q[1], q[2]], [p[0], p[1], p[2]])
    }
}
