//! The support memory's partial judgements: what changed since its last evaluation,
//! the newly held bodies judged alone, and the delete-and-rederive after touches of
//! held bodies began or ended.

use std::collections::{BTreeMap, BTreeSet};

use rapier3d::math::Vector;

use super::hold::Held;
use super::support::{rests_now, static_pose, SupportChange};
use super::{key, SpeedUpState, StepChanges};
use crate::graph::{ContactGraph, EdgeKind, NodeId, NodeKind};
use crate::WorldView;

impl SpeedUpState {
    /// What the support memory must judge again since its last evaluation: everything
    /// when held bodies were removed from the world, "up" turned, a node was removed,
    /// a static supporter moved or a scripted one moves (or no partial judgement
    /// applies); the held ends when only touching contacts of held bodies began or
    /// ended or held bodies were released; nothing else. A
    /// touch that ended is a touched edge marked `Vanished` under proximity tracking,
    /// and a removed edge that was touching under touching tracking (which keeps an
    /// edge only while it touches) or when a kind change dropped it: both are looked
    /// at, so that both trackings decide the same.
    /// O(touched and removed edges + distinct static and scripted supporters).
    pub(super) fn support_changed(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        up: Vector,
        changes: &StepChanges,
    ) -> SupportChange {
        let StepChanges { nodes_removed, .. } = *changes;
        if nodes_removed || up != self.support_up {
            return SupportChange::Everything { world: true };
        }
        if self.support_dirty {
            return SupportChange::Everything { world: false };
        }
        let keys = self.touch_ends(graph, changes);
        let Some(retyped) = self.watch_retyped(graph, view) else {
            return SupportChange::Everything { world: true };
        };
        let partial = !retyped && self.support_partial_ok && up.is_finite() && up != Vector::ZERO;
        match (keys.is_empty() && self.released.is_empty(), partial) {
            (true, _) => SupportChange::Nothing { partial },
            (false, false) => SupportChange::Everything { world: false },
            (false, true) => SupportChange::Touches(keys),
        }
    }

    /// Judges the bodies held since the last evaluation alone, when nothing else
    /// changed: each is supported by a base of its own or by a remembered held
    /// supporter that is supported. Returns false (a full evaluation is needed) when
    /// one of them is not supported, since what rested on it may have lost its support
    /// too. O(new bodies × their supporters).
    pub(super) fn judge_newly_held(&mut self, graph: &ContactGraph, view: &WorldView) -> bool {
        let up = self.support_up;
        let new = std::mem::take(&mut self.newly_held);
        let mut all = true;
        for &k in &new {
            let Some(held) = self.held.get(&k) else {
                continue;
            };
            let resting = rests_now(graph, view, held.handle, up);
            if resting {
                // As a full evaluation would: a later partial one judges it again.
                self.rest_based.insert(k);
            }
            let ok = resting
                || held.supports.iter().any(|s| {
                    let Some(node) = graph.node(s.node) else {
                        return false;
                    };
                    match node.body().filter(|&mh| self.held.contains_key(&key(mh))) {
                        Some(mh) => !new.contains(&key(mh)) && !self.unsupported.contains(&key(mh)),
                        None => self.static_support_holds(graph, view, node, s),
                    }
                });
            if !ok {
                all = false;
                break;
            }
        }
        self.newly_held = new;
        if all {
            self.watch_newly_held(graph);
        }
        all
    }

    /// Judges the support memory again after touches of held bodies began or ended or
    /// held bodies were released, and nothing else it depends on changed
    /// ([`Self::support_changed`]): only the held bodies whose status those changes
    /// can change. "Supported" is a least fixed point, so this is the delete-and-
    /// rederive of incremental fixed points: the bodies that may have *lost* their
    /// support are `changed` (the held ends of the touches), those resting on a
    /// contact Rapier computes at the last evaluation (such a contact can end without
    /// a touch ending) and those that remember a released body; they are judged with
    /// everything that remembers one of them as a supporter, transitively, except
    /// through a body that has a base of its own now (a computed resting contact, or
    /// static or scripted support that still holds): that one is supported whatever
    /// else changed. The unsupported bodies can only *gain* support, and are judged
    /// too. Every other held body is supported, as before: its support runs through
    /// bases that did not change and held bodies outside the set. The judged bodies'
    /// watched supporters are counted again, the released bodies' taken off. The same
    /// result as [`Self::evaluate_support`], watch included (checked against it after
    /// every partial evaluation in debug builds). O(the judged bodies × (their contact
    /// pairs + their entries in the dependents index · log)); the index is kept
    /// between steps ([`Self::hold`]).
    pub(super) fn evaluate_support_from(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        up: Vector,
        changed: Vec<(u32, u32)>,
    ) {
        let released = self.forget_released();
        let mut rests: BTreeMap<(u32, u32), bool> = BTreeMap::new();
        let maybe_lost = self.maybe_lost(graph, changed, &released);
        let judged = self.judged_from(graph, view, up, maybe_lost, &mut rests);
        let records = judged.iter().filter_map(|k| self.held.get(k));
        let (supported, resting) = self.judge_support(graph, view, up, &judged, records, &rests);
        self.apply_judgement(&judged, &supported, &resting);
        for k in &judged {
            self.rewatch(graph, k);
        }
        self.support_dirty = false;
        self.support_up = up;
        #[cfg(debug_assertions)]
        self.check_against_full(graph, view, up);
    }

    /// Takes the records of the bodies released since the last evaluation: held no
    /// more, they leave the sets and the watch. O(released · log).
    fn forget_released(&mut self) -> Vec<Held> {
        // The released bodies are held no more: their records leave the sets and the
        // watch, and what rested on them is judged again.
        let released = std::mem::take(&mut self.released);
        for r in &released {
            let k = key(r.handle);
            if !self.held.contains_key(&k) {
                self.unsupported.remove(&k);
                self.rest_based.remove(&k);
            }
            self.watch_count(&r.watched, false);
        }
        released
    }

    /// The held bodies that remember node `n` as a supporter, from the dependents
    /// index. O(log + their number).
    pub(super) fn dependents_of(&self, n: NodeId) -> impl Iterator<Item = (u32, u32)> + '_ {
        self.dependents
            .range((n, (0, 0))..=(n, (u32::MAX, u32::MAX)))
            .map(|&(_, d)| d)
    }

    /// The bodies that may have lost their support: the held ends of the touches
    /// (`changed`), those resting on a computed contact at the last evaluation, and
    /// what remembered a `released` body. O(their number · log).
    fn maybe_lost(
        &self,
        graph: &ContactGraph,
        changed: Vec<(u32, u32)>,
        released: &[Held],
    ) -> BTreeSet<(u32, u32)> {
        // Bodies that may have lost their support: the held ends of the touches, those
        // resting on a computed contact at the last evaluation (it may have ended), and
        // what remembered a released body.
        let mut maybe_lost: BTreeSet<(u32, u32)> = changed.into_iter().collect();
        maybe_lost.extend(self.rest_based.iter().copied());
        for r in released {
            if let Some(n) = graph.node_of_body(r.handle) {
                maybe_lost.extend(self.dependents_of(n));
            }
        }
        maybe_lost
    }

    /// The held bodies a partial judgement judges, sorted: `maybe_lost`, what rests
    /// on them transitively except through a body with a base of its own now, and the
    /// unsupported bodies. `rests` records whether a body rests on a contact Rapier
    /// computes now, read once. O(the judged bodies × (their contact pairs + their
    /// entries in the dependents index · log)).
    fn judged_from(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        up: Vector,
        maybe_lost: BTreeSet<(u32, u32)>,
        rests: &mut BTreeMap<(u32, u32), bool>,
    ) -> Vec<(u32, u32)> {
        let node_of = |k: &(u32, u32)| {
            self.held
                .get(k)
                .and_then(|held| graph.node_of_body(held.handle))
        };
        // Whether a held body rests on a contact Rapier computes now, read once.
        let mut based = |k: &(u32, u32)| {
            self.held.get(k).is_some_and(|held| {
                *rests
                    .entry(*k)
                    .or_insert_with(|| rests_now(graph, view, held.handle, up))
                    || self.holds_alone(graph, view, held)
            })
        };
        // What rests on a body that may have lost its support is judged again with it,
        // transitively; a body with a base of its own now (a computed resting contact,
        // static geometry in place, a scripted body at rest) is supported whatever else
        // changed, so nothing loses its support through it and its dependents are left
        // out. Unsupported bodies can only gain support: judged, but what rests on
        // them was supported through something else or is unsupported itself.
        let mut judged: BTreeSet<(u32, u32)> = maybe_lost.clone();
        judged.extend(self.unsupported.iter().copied());
        let mut stack: Vec<NodeId> = maybe_lost
            .iter()
            .filter(|k| !based(k))
            .filter_map(node_of)
            .collect();
        while let Some(n) = stack.pop() {
            for d in self.dependents_of(n) {
                if judged.insert(d) && !based(&d) {
                    stack.extend(node_of(&d));
                }
            }
        }
        judged
            .into_iter()
            .filter(|k| self.held.contains_key(k))
            .collect()
    }

    /// Checks a partial evaluation against a full one, and the dependents index
    /// against the held records (debug builds). O(a full evaluation).
    #[cfg(debug_assertions)]
    fn check_against_full(&self, graph: &ContactGraph, view: &WorldView, up: Vector) {
        debug_assert_eq!(
            self.dependents_of_records(),
            self.dependents,
            "the dependents index is stale"
        );
        let mut full = self.clone();
        full.evaluate_support(graph, view, up);
        debug_assert_eq!(
            full.unsupported, self.unsupported,
            "the partial support evaluation differs from the full one"
        );
        debug_assert_eq!(
            full.support_watch, self.support_watch,
            "the support watch differs from a full evaluation's"
        );
    }

    /// The held ends of the physical touches that began or ended in the step (an
    /// edge's two ends in order). O(touched and removed edges).
    fn touch_ends(&self, graph: &ContactGraph, changes: &StepChanges) -> Vec<(u32, u32)> {
        let StepChanges {
            touched,
            removed,
            step,
            ..
        } = *changes;
        let held_key = |n: NodeId| {
            graph
                .body_of(n)
                .map(key)
                .filter(|k| self.held.contains_key(k))
        };
        // The held ends of touches that began or ended (an edge's two ends in order).
        let mut keys = Vec::new();
        let mut note = |a: NodeId, b: NodeId| {
            let (ka, kb) = (held_key(a), held_key(b));
            keys.extend(ka.into_iter().chain(kb));
        };
        for e in touched.iter().filter_map(|&e| graph.edge(e)) {
            if e.kind() == EdgeKind::Physical
                && matches!(
                    e.touching_mark(step),
                    Some(crate::graph::Transition::New | crate::graph::Transition::Vanished)
                )
            {
                note(e.a(), e.b());
            }
        }
        for e in removed {
            if e.kind() == EdgeKind::Physical && e.cache().touching_old {
                note(e.a(), e.b());
            }
        }
        keys
    }

    /// Whether a watched supporter was retyped in place (`Some(true)`: it rules out a
    /// partial evaluation), or `None` when a static one moved or a scripted one moves.
    /// O(distinct static and scripted supporters).
    fn watch_retyped(&self, graph: &ContactGraph, view: &WorldView) -> Option<bool> {
        // A static supporter moved, or a scripted one moves: everything. A watched
        // supporter no longer of the kind it was watched as (retyped in place) changes
        // nothing by itself, as before, but rules out a partial evaluation.
        let mut retyped = false;
        for &(n, pose, _) in &self.support_watch {
            let node = graph.node(n);
            let moved = match pose {
                Some(p) => {
                    retyped |= node.is_none_or(|x| x.kind() != NodeKind::Fixed);
                    static_pose(graph, view, n) != Some(p)
                }
                None => {
                    retyped |= node.is_none_or(|x| x.kind() != NodeKind::Kinematic);
                    graph
                        .body_of(n)
                        .and_then(|h| view.bodies.get(h))
                        .is_none_or(crate::world::moves)
                }
            };
            if moved {
                return None;
            }
        }
        Some(retyped)
    }
}
