//! Pictures of the contact graph.

pub mod dot;
pub mod text;
