//! A snapshot's bytes: `(magic, format, world stamp, in step, state)`, the format
//! checked before anything past it is read.

use std::fmt;

use serde::de::{self, SeqAccess, Visitor};
use serde::ser::SerializeTupleStruct;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use super::LayerSnapshot;
use crate::coherence::Coherence;
use crate::events::{Event, EventBus};
use crate::graph::ContactGraph;
use crate::groups::Groups;
use crate::logic::Logic;
use crate::monitor::LayerMonitor;
use crate::speedups::SpeedUpState;
use crate::{Error, NodeId, StepStats};

/// The snapshot format this build writes and reads. Bumped by any change of the
/// layer's state that older builds could not read (the CHANGELOG says which).
pub const SNAPSHOT_FORMAT: u32 = 9;

/// The first field of every snapshot ("RCGL" in little-endian bytes).
const SNAPSHOT_MAGIC: u32 = u32::from_le_bytes(*b"RCGL");

/// Everything a layer holds but its subscriptions. Built by `ContactLayer::to_state`.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub(crate) struct LayerState {
    pub(crate) graph: ContactGraph,
    pub(crate) groups: Groups,
    pub(crate) coherence: Coherence,
    pub(crate) logic: Logic,
    pub(crate) bus: SavedBus,
    pub(crate) stats: StepStats,
    pub(crate) gravity: rapier3d::math::Vector,
    pub(crate) colliders_seen: usize,
    pub(crate) ticks: Vec<(NodeId, u64)>,
    pub(crate) events: Vec<Event>,
    pub(crate) speedups: Option<SpeedUpState>,
    pub(crate) monitor: Option<LayerMonitor>,
    pub(crate) monitor_events: Vec<Event>,
    pub(crate) monitor_restore: Option<LayerMonitor>,
}

/// A layer's event bus as a snapshot holds it: no subscriptions, counters kept.
/// (`EventBus::clone` forgets the counters; cloning this keeps them, so
/// `LayerState` can derive `Clone`.)
#[derive(Debug, Serialize, Deserialize)]
#[serde(transparent)]
pub(crate) struct SavedBus(pub(crate) EventBus);

impl Clone for SavedBus {
    fn clone(&self) -> Self {
        SavedBus(self.0.without_subscriptions())
    }
}

impl Serialize for LayerSnapshot {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        let mut t = s.serialize_tuple_struct("LayerSnapshot", 5)?;
        t.serialize_field(&SNAPSHOT_MAGIC)?;
        t.serialize_field(&SNAPSHOT_FORMAT)?;
        t.serialize_field(&self.world)?;
        t.serialize_field(&self.in_step)?;
        t.serialize_field(&self.state)?;
        t.end()
    }
}

impl<'de> Deserialize<'de> for LayerSnapshot {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        struct SnapshotVisitor;
        impl<'de> Visitor<'de> for SnapshotVisitor {
            type Value = LayerSnapshot;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a rapier-contact-graph layer snapshot")
            }
            fn visit_seq<A: SeqAccess<'de>>(
                self,
                mut seq: A,
            ) -> std::result::Result<LayerSnapshot, A::Error> {
                let magic: u32 = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(0, &self))?;
                if magic != SNAPSHOT_MAGIC {
                    return Err(de::Error::custom(
                        "not a rapier-contact-graph layer snapshot (wrong magic number)",
                    ));
                }
                let found: u32 = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(1, &self))?;
                if found != SNAPSHOT_FORMAT {
                    return Err(de::Error::custom(Error::SnapshotFormat {
                        found,
                        expected: SNAPSHOT_FORMAT,
                    }));
                }
                let world = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(2, &self))?;
                let in_step = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(3, &self))?;
                let state = seq
                    .next_element()?
                    .ok_or_else(|| de::Error::invalid_length(4, &self))?;
                Ok(LayerSnapshot {
                    world,
                    in_step,
                    state,
                })
            }
        }
        d.deserialize_tuple_struct("LayerSnapshot", 5, SnapshotVisitor)
    }
}
