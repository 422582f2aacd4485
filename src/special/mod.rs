//! Special functions of analytical dynamics, apart from any system: Kepler's equation on every
//! conic and its anomalies, and the quadratures through turning points of `∫ √F` and `∫ 1/√F`
//! (libration and radial motion).

pub mod elliptic;
pub mod kepler_equation;
pub mod turning_points;
