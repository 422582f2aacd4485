//! The Hénon–Heiles Hamiltonian (M. Hénon & C. Heiles, "The applicability of the third integral
//! of motion: some numerical experiments", *Astron. J.* 69, 73–79 (1964)):
//!
//! ```text
//! H = ½(p_x² + p_y² + x² + y²) + x²y − y³/3,
//! ```
//!
//! two oscillators of equal frequency in 1:1 resonance with a cubic coupling; the escape energy is
//! `1/6`. The standard test of resonant (Gustavson) normal forms.

use crate::hamiltonian::Hamiltonian;
use nalgebra::SVector;
use num_dual::DualNum;

/// `H = ½(p_x² + p_y² + x² + y²) + x²y − y³/3`, `q = (x, y)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HenonHeiles;

impl Hamiltonian<2> for HenonHeiles {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 2>,
        p: &SVector<D, 2>,
    ) -> D {
        let (x, y) = (q[0], q[1]);
        (p[0] * p[0] + p[1] * p[1] + x * x + y * y) * 0.5 + x * x * y - y * y * y * (1.0 / 3.0)
    }
}
