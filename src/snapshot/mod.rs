//! Snapshot and restore of the layer, beside Rapier's own world snapshot (feature
//! `serde`, on by default).
//!
//! [`ContactLayer::snapshot`](crate::ContactLayer::snapshot) captures the layer's state (graph, groups, rules, timers,
//! speed-ups, monitor, counters) as a [`LayerSnapshot`]; [`ContactLayer::restore`](crate::ContactLayer::restore)
//! rebuilds a layer from it against the restored `PhysicsWorld`, and the pair then
//! continues **bit for bit** as the original would. Subscriptions are not saved
//! (subscribe again), and predicate rules come back through
//! [`ContactLayer::restore_with`](crate::ContactLayer::restore_with). A snapshot carries a format number
//! ([`SNAPSHOT_FORMAT`], checked first) and a stamp of its world (another world is
//! refused). Use a serde format that keeps `f32` bit for bit and infinities (bincode;
//! not JSON). Design and Rapier's own snapshot: `docs/ARCHITECTURE.md` ("Snapshots").
//!
//! ```
//! use rapier3d::prelude::*;
//! use rapier_contact_graph::{events::Filter, ContactLayer, LayerSnapshot};
//!
//! let mut world = PhysicsWorld::new();
//! world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
//! let (ball, _) = world.insert(
//!     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 3.0, 0.0)),
//!     ColliderBuilder::ball(0.5),
//! );
//! let mut layer = ContactLayer::new();
//! for _ in 0..50 {
//!     layer.step(&mut world);
//! }
//! // Save: Rapier's world and the layer, with any serde format (bincode here).
//! let bytes = bincode::serialize(&(&world, &layer.snapshot(&world))).unwrap();
//!
//! // Load: the world first, then the layer against it.
//! let (mut world2, snap): (PhysicsWorld, LayerSnapshot) = bincode::deserialize(&bytes).unwrap();
//! let mut layer2 = ContactLayer::restore(&snap, &world2).unwrap();
//!
//! // Subscriptions are not part of a snapshot: subscribe again.
//! let (events, events2) = (layer.subscribe(Filter::all()), layer2.subscribe(Filter::all()));
//! for _ in 0..100 {
//!     layer.step(&mut world);
//!     layer2.step(&mut world2);
//! }
//! let y = |w: &PhysicsWorld| w.bodies[ball].translation().y.to_bits();
//! assert_eq!(y(&world), y(&world2), "bit for bit");
//! assert_eq!(events.try_iter().collect::<Vec<_>>(), events2.try_iter().collect::<Vec<_>>());
//! ```
//!
//! Files: `format.rs` (the bytes' layout), `stamp.rs` (the world's digest),
//! `restore.rs` (taking and restoring), `checks.rs` (a deserialised state's checks).
//!
//! Cost: taking is O(nodes + edges + groups + rules + timers + speed-up records) plus
//! O(bodies + colliders + joints) for the stamp; restoring adds the checks, O(nodes +
//! edges + group members); serialising sorts hash maps, O(k log k) for k entries.

mod checks;
mod format;
mod restore;
mod stamp;
#[cfg(test)]
mod tests;

pub use format::SNAPSHOT_FORMAT;
pub(crate) use format::{LayerState, SavedBus};
pub use restore::PredicateResolver;

use crate::logic::Rule;
use crate::NodeId;
use stamp::WorldStamp;

/// The state of a [`ContactLayer`](crate::ContactLayer) at one moment, with a stamp of the world it belongs
/// to. Serialise it with any serde format that keeps `f32` bit for bit (see the
/// [module docs](self)); restore it with [`ContactLayer::restore`](crate::ContactLayer::restore).
#[derive(Debug, Clone)]
pub struct LayerSnapshot {
    world: WorldStamp,
    /// Whether the layer passed `validate` against the world when the snapshot was
    /// taken (false when the world was edited after the layer's last step).
    in_step: bool,
    state: LayerState,
}

impl LayerSnapshot {
    /// The saved state, to corrupt in tests.
    #[cfg(test)]
    pub(crate) fn state_mut(&mut self) -> &mut LayerState {
        &mut self.state
    }

    /// The index of the last step the layer had analysed. O(1).
    pub fn step(&self) -> u64 {
        self.state.coherence.step()
    }

    /// The predicate rules a restore must give back, as `(rule node, members)` in
    /// node order (see [`ContactLayer::restore_with`](crate::ContactLayer::restore_with)). O(rules).
    pub fn predicate_rules(&self) -> Vec<(NodeId, Vec<NodeId>)> {
        let mut out: Vec<(NodeId, Vec<NodeId>)> = Vec::new();
        let table = self.state.logic.hooks.rules.entries().iter();
        for (n, r) in self
            .state
            .logic
            .rules
            .iter()
            .chain(table.map(|(n, r)| (n, r)))
        {
            if let Rule::Predicate { members, .. } = r {
                if !out.iter().any(|(m, _)| m == n) {
                    out.push((*n, members.clone()));
                }
            }
        }
        out.sort_by_key(|(n, _)| *n);
        out
    }
}
