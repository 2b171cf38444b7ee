//! Pictures of the contact graph.

#[cfg(feature = "dot")]
pub mod dot;
pub mod text;
