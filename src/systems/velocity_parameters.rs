use crate::constraints::QuasiVelocities;
use crate::lagrangian::Lagrangian;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// A holonomic system described by non-holonomic velocity parameters [Hamel art. 241]
/// (SPEC T20):
///
/// ```math
/// T = \tfrac12\big[\dot q_1^2 + 2q_1\dot q_1\dot q_2 + (1 + q_1^2)\dot q_2^2\big]
///   = \tfrac12(\omega_1^2 + \omega_2^2),\qquad \omega_1 = \dot q_1 + q_1\dot q_2,\quad
///   \omega_2 = \dot q_2 ,
/// ```
///
/// Hamel's equations `ω̇₁ − ω₁ω₂ = K₁`, `ω̇₂ + ω₁² = K₂ − q₁K₁`; force-free from
/// `ω(0) = (c, 0)`: `ω₁ = c sech(ct)`, `ω₂ = −c tanh(ct)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct HamelVelocityParameters;

impl Lagrangian<2> for HamelVelocityParameters {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        (v[0] * v[0] + q[0] * v[0] * v[1] * 2.0 + (q[0] * q[0] + 1.0) * v[1] * v[1]) * 0.5
    }
}

impl QuasiVelocities<2> for HamelVelocityParameters {
    fn constrained(&self) -> usize {
        0
    }
    fn matrix<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        SMatrix::from_row_slice(&[D::one(), q[0], D::zero(), D::one()])
    }
}
