//! Canonical (contact) transformations: generating functions of the four kinds, point
//! transformations, composition and inversion of maps, infinitesimal transformations and Lie
//! series (SPEC M49–M51, M61). Certification of any map is [`crate::brackets::certify`].

pub mod generating;

pub use generating::{CanonicalTransformation, GeneratingFunction, Kind, Transformed};
