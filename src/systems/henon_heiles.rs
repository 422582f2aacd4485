//! The Hénon–Heiles Hamiltonian (M. Hénon & C. Heiles, "The applicability of the third integral
//! of motion: some numerical experiments", *Astron. J.* 69, 73–79 (1964)):
//!
//! ```text
//! H = ½(p_x² + p_y²) + ½(x² + y²) + x²y − y³/3,
//! ```
//!
//! two oscillators of equal frequency in 1:1 resonance with a cubic coupling; the escape energy is
//! `1/6`. Separable (`T(p) + V(q)`), so the explicit splittings apply. The standard test of
//! resonant (Gustavson) normal forms and of chaos indicators: at `E = 1/12` the surface of
//! section `x = 0` is filled with invariant curves, at `E = 1/8` a large chaotic sea surrounds
//! the islands.

use crate::error::{finite, Error, Result};
use crate::hamiltonian::Separable;
use crate::phase::State;
use nalgebra::SVector;
use num_dual::DualNum;

/// `H = ½(p_x² + p_y²) + ½(x² + y²) + x²y − y³/3`, `q = (x, y)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HenonHeiles;

impl Separable<2> for HenonHeiles {
    fn kinetic<D: DualNum<f64> + Copy>(&self, _t: D, p: &SVector<D, 2>) -> D {
        (p[0] * p[0] + p[1] * p[1]) * 0.5
    }
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> D {
        let (x, y) = (q[0], q[1]);
        (x * x + y * y) * 0.5 + x * x * y - y * y * y * (1.0 / 3.0)
    }
}

impl HenonHeiles {
    /// The state at `t = 0` on the surface of section `x = 0` with `(y, p_y)` given and energy
    /// `E`, crossing it upwards: `p_x = +√(2E − p_y² − y² + 2y³/3)` (Hénon & Heiles 1964).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite argument; [`Error::OutOfDomain`] when `(y, p_y)`
    /// lies outside the energy's allowed region (`p_x² < 0`).
    pub fn section_start(energy: f64, y: f64, py: f64) -> Result<State<2>> {
        let (e, y, py) = (
            finite("energy E", energy)?,
            finite("y", y)?,
            finite("p_y", py)?,
        );
        let px2 = 2.0 * e - py * py - y * y + 2.0 * y * y * y / 3.0;
        if !(px2 >= 0.0 && px2.is_finite()) {
            return Err(Error::out_of_domain(
                "p_x² = 2E − p_y² − y² + 2y³/3 on the section x = 0",
                px2,
                "≥ 0 (a point of the section inside the energy's allowed region)",
            ));
        }
        State::new(
            0.0,
            SVector::from([0.0, y]),
            SVector::from([px2.sqrt(), py]),
        )
    }
}
