//! Canonical (contact) transformations: generating functions of the four kinds, point
//! transformations, composition and inversion of maps, infinitesimal transformations and Lie
//! series [Ardema ch. 16, 18.3]. Certification of any map is [`crate::brackets::certify`]; the
//! three classical tests of canonicity are [`crate::brackets::exactness_defect`] (the definition:
//! `Σ p dq − Σ P dQ` closed), [`crate::brackets::liouville_determinant`] and the bracket matrices.

pub mod compose;
pub mod generating;
pub mod lie;
pub mod point;

pub use compose::{Compose, Inverse};
pub use generating::{CanonicalTransformation, GeneratingFunction, Kind, Transformed};
pub use lie::{lie_flow, Ict, LieSeries};
pub use point::{point_transformation, PointTransformation, TransformedLagrangian};
