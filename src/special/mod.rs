//! Special functions of analytical dynamics, apart from any system: Kepler's equation on every
//! conic and its anomalies, the Stumpff functions and Kepler's equation in universal variables,
//! and the quadratures through turning points of `∫ √F` and `∫ 1/√F` (libration and radial
//! motion).

pub(crate) mod double_double;
pub mod elliptic;
pub mod kepler_equation;
pub mod stumpff;
pub mod turning_points;
