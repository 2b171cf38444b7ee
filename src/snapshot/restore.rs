//! Taking a snapshot and restoring a layer from one.

use std::collections::BTreeMap;

use super::checks::check_state;
use super::stamp::{mismatch, WorldStamp};
use super::LayerSnapshot;
use crate::logic::{IgnorePredicate, Logic, Rule};
use crate::{ContactLayer, Error, NodeId, Result, WorldView};

/// Resolves the predicate of a predicate rule, given the rule's node and members.
pub type PredicateResolver<'a> = &'a mut dyn FnMut(NodeId, &[NodeId]) -> Option<IgnorePredicate>;

impl ContactLayer {
    /// The layer's state as a [`LayerSnapshot`], stamped with `world` (the world the
    /// layer analysed, at the same moment: serialise both together). Subscriptions and
    /// rule predicates are not part of it (see [`crate::snapshot`]).
    ///
    /// Take it after a step ([`Self::step`], or [`Self::analyze`]); any other moment
    /// between two of the layer's calls works too. Cost: O(nodes + edges + groups +
    /// rules + timers + speed-up records) to copy the state, plus O(bodies + colliders
    /// + joints) for the world's stamp, plus one `validate` against the world (O(nodes
    /// + edges + Rapier pairs)) whose verdict the snapshot keeps: a layer that was in
    /// step with its world must be in step with it again when restored.
    ///
    /// # Example
    /// See [`crate::snapshot`].
    pub fn snapshot<'w>(&self, world: impl Into<WorldView<'w>>) -> LayerSnapshot {
        let view = world.into();
        LayerSnapshot {
            world: WorldStamp::of(&view),
            in_step: self.validate(&view).is_ok(),
            state: self.to_state(),
        }
    }

    /// A layer from a snapshot, against the world saved with it (Rapier's own
    /// snapshot, deserialised). The pair continues exactly as the original pair would.
    /// The restored layer has no subscriptions: subscribe again.
    ///
    /// Errors, with the snapshot left as it was:
    /// - [`Error::SnapshotMismatch`]: `world` is not the world the snapshot was taken
    ///   with (another scene, or the same one at another step);
    /// - [`Error::Invariant`]: the snapshot's state is inconsistent (corrupted bytes
    ///   that still decoded);
    /// - [`Error::UnboundPredicate`]: the snapshot holds a predicate rule; use
    ///   [`Self::restore_with`].
    ///
    /// A snapshot of another format does not get here: its deserialisation fails
    /// with [`Error::SnapshotFormat`]'s message.
    ///
    /// Cost: O(nodes + edges + group members + rules + timers + speed-up records) to
    /// copy and check the state, plus O(bodies + colliders + joints) for the world's
    /// stamp.
    ///
    /// # Example
    /// See [`crate::snapshot`]; a wrong world is refused:
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::{ContactLayer, Error};
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.5));
    /// let mut layer = ContactLayer::new();
    /// layer.step(&mut world);
    /// let snap = layer.snapshot(&world);
    /// layer.step(&mut world); // the world moves on: it is no longer the saved one
    /// assert!(matches!(ContactLayer::restore(&snap, &world), Err(Error::SnapshotMismatch(_))));
    /// ```
    pub fn restore<'w>(
        snapshot: &LayerSnapshot,
        world: impl Into<WorldView<'w>>,
    ) -> Result<ContactLayer> {
        Self::restore_with(snapshot, world, &mut |_, _| None)
    }

    /// [`Self::restore`], giving back the predicates of the snapshot's predicate rules:
    /// `bind(rule, members)` is called once per predicate rule, in node order, and
    /// returns its predicate, or `None` to refuse (then [`Error::UnboundPredicate`]
    /// names the rule). Rule nodes keep their ids across a snapshot, so a game can key
    /// its predicates by the node `add_rule` returned. Cost: as [`Self::restore`],
    /// plus the calls.
    ///
    /// # Example
    /// ```
    /// use std::sync::Arc;
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::{logic::IgnorePredicate, ContactLayer, Error, Rule};
    ///
    /// let mut world = PhysicsWorld::new();
    /// let (ball, _) = world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.5));
    /// let mut layer = ContactLayer::new();
    /// layer.step(&mut world);
    /// let node = layer.node_of_body(&world.bodies, ball).unwrap();
    /// let rule = layer.logic_mut().add_rule(Rule::ignore_if(&[node], |_, _| true)).unwrap();
    /// let snap = layer.snapshot(&world);
    ///
    /// assert_eq!(ContactLayer::restore(&snap, &world).unwrap_err(), Error::UnboundPredicate(rule));
    /// let ghost: IgnorePredicate = Arc::new(|_, _| true);
    /// let restored = ContactLayer::restore_with(&snap, &world, &mut |n, _members| {
    ///     (n == rule).then(|| ghost.clone())
    /// })
    /// .unwrap();
    /// assert!(restored.logic().rule(rule).unwrap().ignores(node, node));
    /// ```
    pub fn restore_with<'w>(
        snapshot: &LayerSnapshot,
        world: impl Into<WorldView<'w>>,
        bind: PredicateResolver<'_>,
    ) -> Result<ContactLayer> {
        let view = world.into();
        if WorldStamp::of(&view) != snapshot.world {
            return Err(Error::SnapshotMismatch(mismatch(snapshot, &view)));
        }
        let mut state = snapshot.state.clone();
        // The groups' positions and counts are not in the bytes: rebuilt from the
        // groups' lists (on any bytes), then checked with the rest.
        state.groups.reindex(&mut state.graph);
        state.graph.recount_geometric();
        if let Some(s) = &mut state.speedups {
            s.reindex(&view);
        }
        check_state(&state).map_err(|e| Error::Invariant(format!("snapshot: {e}")))?;
        bind_predicates(&mut state.logic, bind)?;
        let mut state = state;
        // What only this process knows (the addresses of shared shapes) is taken from
        // the world restored against.
        state
            .coherence
            .rebind_trigger_shapes(&state.graph, view.colliders);
        let layer = ContactLayer::from_state(state);
        // The state's own checks cannot see everything a corrupted snapshot can hold
        // (a count off by a few, an edge or node dropped): a layer that was in step
        // with its world when saved must pass `validate` against it again, or it is
        // refused. (One saved between a world edit and the next step is behind the
        // world on both sides, and catches up at its next step.) O(nodes + edges +
        // pairs).
        if snapshot.in_step {
            layer
                .validate(&view)
                .map_err(|e| Error::Invariant(format!("snapshot does not match the world: {e}")))?;
        }
        Ok(layer)
    }
}

/// Gives every predicate rule (in the rule map and in the hooks' table) its predicate.
fn bind_predicates(logic: &mut Logic, bind: PredicateResolver<'_>) -> Result<()> {
    let mut bound: BTreeMap<NodeId, IgnorePredicate> = BTreeMap::new();
    let mut resolve = |n: NodeId, members: &[NodeId]| -> Result<IgnorePredicate> {
        if let Some(p) = bound.get(&n) {
            return Ok(p.clone());
        }
        let p = bind(n, members).ok_or(Error::UnboundPredicate(n))?;
        bound.insert(n, p.clone());
        Ok(p)
    };
    for (&n, rule) in logic.rules.iter_mut() {
        if let Rule::Predicate { members, ignore } = rule {
            *ignore = resolve(n, members)?;
        }
    }
    for (n, rule) in logic.hooks.rules.entries_mut() {
        if let Rule::Predicate { members, ignore } = rule {
            *ignore = resolve(*n, members)?;
        }
    }
    Ok(())
}
