//! Hamilton–Jacobi theory (SPEC M47, M48, M52–M57): the Hamilton–Jacobi equation, complete
//! integrals and the motion they generate (Jacobi's theorem).

pub mod complete;

pub use complete::{completeness, hj_residual, CompleteIntegral, ElementConvention, Elements};
