//! Hash maps and sets written to snapshots in a fixed order: equal maps give equal
//! bytes whatever their insertion history, and reading back refuses repeated keys.
//! Used through `#[serde(with = "...")]` on the state types of every layer.

use serde::de;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

/// A key with a total order, for writing hash maps in a fixed order.
pub(crate) trait SortKey {
    fn sort_key(&self) -> u64;
}

impl SortKey for crate::util::id::PairKey {
    fn sort_key(&self) -> u64 {
        self.to_bits()
    }
}

impl SortKey for rapier3d::prelude::ColliderHandle {
    fn sort_key(&self) -> u64 {
        let (i, g) = self.into_raw_parts();
        ((g as u64) << 32) | i as u64
    }
}

impl SortKey for rapier3d::prelude::RigidBodyHandle {
    fn sort_key(&self) -> u64 {
        let (i, g) = self.into_raw_parts();
        ((g as u64) << 32) | i as u64
    }
}

impl SortKey for crate::util::id::NodeId {
    fn sort_key(&self) -> u64 {
        let (i, g) = self.into_raw_parts();
        ((g as u64) << 32) | i as u64
    }
}

impl SortKey for crate::util::id::EdgeId {
    fn sort_key(&self) -> u64 {
        let (i, g) = self.into_raw_parts();
        ((g as u64) << 32) | i as u64
    }
}

/// A hash map written as its entries sorted by key (equal maps give equal bytes,
/// whatever their insertion history), read back refusing repeated keys.
pub(crate) mod sorted_map {
    use super::*;
    use std::collections::HashMap;
    use std::hash::{BuildHasher, Hash};

    pub(crate) fn serialize<K, V, H, S>(
        map: &HashMap<K, V, H>,
        s: S,
    ) -> std::result::Result<S::Ok, S::Error>
    where
        K: Serialize + SortKey,
        V: Serialize,
        S: Serializer,
    {
        let mut entries: Vec<(&K, &V)> = map.iter().collect();
        entries.sort_unstable_by_key(|(k, _)| k.sort_key());
        s.collect_seq(entries)
    }

    pub(crate) fn deserialize<'de, K, V, H, D>(
        d: D,
    ) -> std::result::Result<HashMap<K, V, H>, D::Error>
    where
        K: Deserialize<'de> + Eq + Hash,
        V: Deserialize<'de>,
        H: BuildHasher + Default,
        D: Deserializer<'de>,
    {
        let entries = Vec::<(K, V)>::deserialize(d)?;
        let n = entries.len();
        let mut map = HashMap::with_capacity_and_hasher(n, H::default());
        map.extend(entries);
        if map.len() != n {
            return Err(de::Error::custom("a map holds a key twice"));
        }
        Ok(map)
    }
}

/// A hash set written as its elements sorted, read back refusing repeats.
pub(crate) mod sorted_set {
    use super::*;
    use std::collections::HashSet;
    use std::hash::{BuildHasher, Hash};

    pub(crate) fn serialize<K, H, S>(
        set: &HashSet<K, H>,
        s: S,
    ) -> std::result::Result<S::Ok, S::Error>
    where
        K: Serialize + SortKey,
        S: Serializer,
    {
        let mut keys: Vec<&K> = set.iter().collect();
        keys.sort_unstable_by_key(|k| k.sort_key());
        s.collect_seq(keys)
    }

    pub(crate) fn deserialize<'de, K, H, D>(d: D) -> std::result::Result<HashSet<K, H>, D::Error>
    where
        K: Deserialize<'de> + Eq + Hash,
        H: BuildHasher + Default,
        D: Deserializer<'de>,
    {
        let keys = Vec::<K>::deserialize(d)?;
        let n = keys.len();
        let mut set = HashSet::with_capacity_and_hasher(n, H::default());
        set.extend(keys);
        if set.len() != n {
            return Err(de::Error::custom("a set holds an element twice"));
        }
        Ok(set)
    }
}
