//! Leaf utilities, below the graph: generational ids and the sorted pair key
//! ([`id`]), the slot arena with free lists ([`arena`]), and the serde helpers that
//! write hash maps in a fixed order ([`serde_maps`], feature `serde`), and small
//! helpers over Rapier's types ([`rapier`]). Nothing here
//! imports from another module of the crate.

pub(crate) mod arena;
pub(crate) mod id;
pub(crate) mod rapier;
#[cfg(feature = "serde")]
pub(crate) mod serde_maps;
