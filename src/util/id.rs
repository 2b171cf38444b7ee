//! Identifiers: generational node and edge ids, and the sorted-pair key.
//!
//! Why generational ids: a user holds a `NodeId` across steps while bodies come and go.
//! Slots are recycled through a free list (Box2D v3 style), so a bare index could
//! silently name a newer node; the generation makes a stale id fail loudly
//! ([`crate::Error::StaleNode`]) instead. Both ids are `#[repr(transparent)]` over a
//! `u64` (index in the low half, generation in the high half), the way Rapier wraps its
//! arena indices.
//!
//! Why [`PairKey`]: the paper (§2) asks that "edges are bidirectional and uniquely
//! determined by the two nodes they run between", with the smaller index known as *A*.
//! Packing the sorted pair of slot indices into one `u64` (as Avian does) gives a
//! hashable, totally ordered key with no allocation; generations are not part of the
//! key because an edge never outlives either of its nodes.

use std::fmt;

/// Packs a slot index and a generation.
#[inline]
const fn pack(index: u32, generation: u32) -> u64 {
    ((generation as u64) << 32) | index as u64
}

macro_rules! generational_id {
    ($(#[$meta:meta])* $name:ident, $letter:literal) => {
        $(#[$meta])*
        #[repr(transparent)]
        #[derive(Copy, Clone, PartialEq, Eq, Hash, PartialOrd, Ord)]
        #[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
        pub struct $name(u64);

        impl $name {
            /// Builds an id from its slot index and generation.
            #[inline]
            pub const fn from_raw_parts(index: u32, generation: u32) -> Self {
                Self(pack(index, generation))
            }
            /// The slot index (stable while the item lives; reused after removal).
            #[inline]
            pub const fn index(self) -> u32 {
                self.0 as u32
            }
            /// The generation of the slot when this id was issued.
            #[inline]
            pub const fn generation(self) -> u32 {
                (self.0 >> 32) as u32
            }
            /// Index and generation.
            #[inline]
            pub const fn into_raw_parts(self) -> (u32, u32) {
                (self.index(), self.generation())
            }
        }

        impl fmt::Debug for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "{}{}v{}", $letter, self.index(), self.generation())
            }
        }

        impl fmt::Display for $name {
            fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                fmt::Debug::fmt(self, f)
            }
        }
    };
}

generational_id!(
    /// A node of the contact graph: a body, a container or a logical entity.
    ///
    /// Valid until the node is removed; a removed node's id is reported as
    /// [`crate::Error::StaleNode`] by every `try_` query.
    NodeId,
    "n"
);

generational_id!(
    /// An edge of the contact graph. Valid until the edge is removed (the obsolete
    /// test, or removal of one of its nodes).
    EdgeId,
    "e"
);

/// The unordered pair of two node slots, sorted and packed into a `u64`:
/// `(min << 32) | max`. The paper's *A* is the smaller index.
///
/// # Example
/// ```
/// use rapier_contact_graph::PairKey;
/// let k = PairKey::new(7, 3);
/// assert_eq!(k, PairKey::new(3, 7));
/// assert_eq!(k.a(), 3);
/// assert_eq!(k.b(), 7);
/// ```
#[repr(transparent)]
#[derive(Copy, Clone, PartialEq, Eq, Hash, PartialOrd, Ord, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PairKey(u64);

impl PairKey {
    /// The key of the pair `{i, j}`, whatever the order of the arguments.
    #[inline]
    pub const fn new(i: u32, j: u32) -> Self {
        let (a, b) = if i <= j { (i, j) } else { (j, i) };
        Self(((a as u64) << 32) | b as u64)
    }
    /// The key of two nodes.
    #[inline]
    pub const fn of(a: NodeId, b: NodeId) -> Self {
        Self::new(a.index(), b.index())
    }
    /// The smaller slot index (the paper's *A*).
    #[inline]
    pub const fn a(self) -> u32 {
        (self.0 >> 32) as u32
    }
    /// The larger slot index (the paper's *B*).
    #[inline]
    pub const fn b(self) -> u32 {
        self.0 as u32
    }
    /// The packed value.
    #[inline]
    pub const fn to_bits(self) -> u64 {
        self.0
    }
}

/// A deterministic hasher for [`PairKey`]s and other `u64` keys.
///
/// `std`'s `RandomState` seeds differ per process; the graph never *iterates* its hash
/// map (iteration goes through the slot arrays), but a fixed hasher also keeps memory
/// layout and timings reproducible between runs. The mixing is the 64-bit finaliser of
/// MurmurHash3, enough for keys that are packed indices; a key of several words (a
/// pair of collider handles) has each word folded in after the state so far is
/// multiplied and rotated (as `FxHasher` does), so that no two words cancel.
#[derive(Default, Clone, Copy)]
pub struct PairHasher(u64);

impl PairHasher {
    /// Folds one word into the state; the first word of a key is taken as it is.
    #[inline]
    fn fold(&mut self, word: u64) {
        self.0 = self.0.wrapping_mul(0x9e37_79b9_7f4a_7c15).rotate_left(26) ^ word;
    }
}

impl std::hash::Hasher for PairHasher {
    #[inline]
    fn finish(&self) -> u64 {
        let mut x = self.0;
        x ^= x >> 33;
        x = x.wrapping_mul(0xff51_afd7_ed55_8ccd);
        x ^= x >> 33;
        x = x.wrapping_mul(0xc4ce_b9fe_1a85_ec53);
        x ^ (x >> 33)
    }
    #[inline]
    fn write(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 = self.0.rotate_left(8) ^ b as u64;
        }
    }
    #[inline]
    fn write_u64(&mut self, i: u64) {
        self.fold(i);
    }
    #[inline]
    fn write_u32(&mut self, i: u32) {
        self.fold(i as u64);
    }
}

/// `BuildHasher` for [`PairHasher`].
pub type PairBuildHasher = std::hash::BuildHasherDefault<PairHasher>;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pair_key_is_unordered_and_sorted() {
        let k = PairKey::new(10, 2);
        assert_eq!(k, PairKey::new(2, 10));
        assert_eq!((k.a(), k.b()), (2, 10));
        assert_ne!(PairKey::new(1, 2), PairKey::new(2, 3));
        assert!(PairKey::new(0, u32::MAX).a() == 0);
    }

    #[test]
    fn ids_round_trip() {
        let n = NodeId::from_raw_parts(5, 9);
        assert_eq!(n.into_raw_parts(), (5, 9));
        assert_eq!(format!("{n:?}"), "n5v9");
        assert_ne!(n, NodeId::from_raw_parts(5, 10));
    }

    #[test]
    fn hasher_spreads_neighbouring_keys() {
        use std::hash::BuildHasher;
        let b = PairBuildHasher::default();
        let h = |k: PairKey| b.hash_one(k);
        assert_ne!(h(PairKey::new(0, 1)), h(PairKey::new(0, 2)));
        assert_ne!(h(PairKey::new(0, 1)) & 0xff, h(PairKey::new(1, 2)) & 0xff);
    }

    #[test]
    fn hasher_keeps_the_words_of_a_key_apart() {
        use std::hash::BuildHasher;
        let b = PairBuildHasher::default();
        type Raw = ((u32, u32), (u32, u32));
        let h = |k: Raw| b.hash_one(k);
        // Swapped words, and words whose exclusive or is the same.
        assert_ne!(h(((1, 0), (2, 0))), h(((2, 0), (1, 0))));
        assert_ne!(h(((1, 0), (2, 0))), h(((0, 0), (3, 0))));
        assert_ne!(h(((1, 5), (2, 5))), h(((1, 6), (2, 6))));
        // A one-word key hashes as before: the word, then the finaliser.
        let mut one = PairHasher::default();
        std::hash::Hasher::write_u64(&mut one, 42);
        assert_eq!(one.0, 42);
    }
}
