//! The support memory of held bodies: what held each one up against gravity when it
//! was fixated, the watch over its static and scripted supporters, and the full
//! judgement of which held bodies are still supported.

use std::collections::BTreeMap;

use rapier3d::math::{Pose, Vector};
use rapier3d::prelude::RigidBodyHandle;

use super::hold::Held;
use super::{key, SpeedUpState, StepChanges};
use crate::coherence::details::resting_supports;
use crate::graph::{ContactGraph, NodeId, NodeKind, NodeSource};
use crate::WorldView;

/// One thing that held a body against gravity when it was fixated.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct Supporter {
    pub(super) node: NodeId,
    /// For static geometry (a fixed body or a parentless collider): its pose then. It
    /// supports only while it has not moved.
    pose: Option<Pose>,
}

/// The smallest cosine between a contact's push and "up" that the fixation memory
/// counts as support: a side contact with a sliver of upward normal does not hold a
/// body up.
const MIN_SUPPORT_COS: f32 = 0.1;

/// How far apart a support may be and still hold a body: Rapier's default contact
/// prediction distance (a resting body hovers within it).
pub(crate) const SUPPORT_GAP: f32 = 0.002;

/// Whether a held body rests on something now: a contact Rapier computes (against
/// bodies that are not fixed) that pushes it up, read from Rapier's narrow phase
/// (see [`resting_supports`]). O(its contact pairs).
pub(super) fn rests_now(
    graph: &ContactGraph,
    view: &WorldView,
    h: RigidBodyHandle,
    up: Vector,
) -> bool {
    let Some(n) = graph.node_of_body(h) else {
        return false;
    };
    let mut found = Vec::new();
    resting_supports(graph, view, n, up, MIN_SUPPORT_COS, SUPPORT_GAP, &mut found);
    !found.is_empty()
}

/// What holds node `n` up now (`up` against gravity; none without gravity): its
/// resting supports ([`resting_supports`], `found` its buffer), static ones with their
/// pose. O(its contact pairs).
pub(super) fn supporters_now(
    graph: &ContactGraph,
    view: &WorldView,
    n: NodeId,
    up: Vector,
    found: &mut Vec<NodeId>,
) -> Vec<Supporter> {
    if up.is_finite() && up != Vector::ZERO {
        resting_supports(graph, view, n, up, MIN_SUPPORT_COS, SUPPORT_GAP, found);
        found
            .iter()
            .map(|&m| Supporter {
                node: m,
                pose: graph
                    .node(m)
                    .filter(|s| s.kind() == NodeKind::Fixed)
                    .and_then(|_| static_pose(graph, view, m)),
            })
            .collect()
    } else {
        Vec::new()
    }
}

/// A pose as bits, for ordering (`None` first).
fn pose_bits(p: Option<Pose>) -> Option<[u32; 7]> {
    p.as_ref().map(crate::util::rapier::pose_bits)
}

/// The pose of a static supporter: its body's, or its collider's if it has no body.
pub(super) fn static_pose(graph: &ContactGraph, view: &WorldView, n: NodeId) -> Option<Pose> {
    match graph.node(n)?.source() {
        NodeSource::Body(h) => view.bodies.get(h).map(|rb| *rb.position()),
        NodeSource::StaticCollider(c) => view.colliders.get(c).map(|co| *co.position()),
        _ => None,
    }
}

/// What [`SpeedUpState::support_changed`] found: what the support memory must judge
/// again.
#[derive(Debug)]
pub(super) enum SupportChange {
    /// Nothing it depends on changed; `partial`: a partial evaluation would apply (for
    /// newly held bodies found unsupported).
    Nothing {
        /// Whether [`SpeedUpState::evaluate_support_from`] applies.
        partial: bool,
    },
    /// Only touches of held bodies began or ended, or held bodies were released: the
    /// held ends of the touches, in edge order (the released bodies are in
    /// `SpeedUpState::released`).
    Touches(Vec<(u32, u32)>),
    /// Held bodies were removed, a node removed, gravity turned, a static supporter
    /// moved or a scripted one moves (or no partial evaluation applies).
    Everything {
        /// Whether the world under the held bodies changed (a node removed, gravity
        /// turned, a static supporter moved or a scripted one moves), not only
        /// what the memory knows: a support lost then is released with its held
        /// group ([`SpeedUpState::release_unsupported`]).
        world: bool,
    },
}

/// Spreads "supported" from the bases up: `links` holds (supporter, dependent) index
/// pairs (sorted here), `queue` the supported bases. O(links · log links).
fn propagate_support(links: &mut [(usize, usize)], supported: &mut [bool], mut queue: Vec<usize>) {
    links.sort_unstable();
    while let Some(j) = queue.pop() {
        let from = links.partition_point(|&(s, _)| s < j);
        for &(_, d) in links[from..].iter().take_while(|&&(s, _)| s == j) {
            if !supported[d] {
                supported[d] = true;
                queue.push(d);
            }
        }
    }
}

impl SpeedUpState {
    /// The support memory after the decisions (see [`Self::fixation_supported`]), with
    /// `up` against gravity ([`super::up_of`]): judged again when something it depends on
    /// changed ([`Self::support_changed`]): in part when only touches of held bodies
    /// began or ended or held bodies were released ([`Self::evaluate_support_from`]),
    /// in full otherwise; else only
    /// the newly held bodies, unless one of them is unsupported; then the unsupported
    /// bodies are released (with their held group when the world under them changed)
    /// and the held bodies to park are chosen.
    pub(super) fn decide_support(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        up: Vector,
        changes: &StepChanges,
    ) {
        let change = self.support_changed(graph, view, up, changes);
        let world = matches!(change, SupportChange::Everything { world: true });
        match change {
            SupportChange::Everything { .. } => self.evaluate_support(graph, view, up),
            SupportChange::Touches(mut keys) => {
                // Bodies held since the last evaluation are judged with the touched
                // ones, their static supporters watched from now on.
                keys.extend_from_slice(&self.newly_held);
                self.watch_newly_held(graph);
                self.evaluate_support_from(graph, view, up, keys);
            }
            SupportChange::Nothing { partial } => {
                if !self.newly_held.is_empty() && !self.judge_newly_held(graph, view) {
                    if partial {
                        let keys = self.newly_held.clone();
                        self.watch_newly_held(graph);
                        self.evaluate_support_from(graph, view, up, keys);
                    } else {
                        self.evaluate_support(graph, view, up);
                    }
                }
            }
        }
        self.newly_held.clear();
        self.release_unsupported(graph, world);
        self.choose_parking(view);
    }

    /// The static and scripted supporters of a held body that the support memory
    /// watches (held supporters are not watched: their release judges again what
    /// rests on them). O(its supporters).
    fn watch_of(&self, graph: &ContactGraph, held: &Held) -> Vec<(NodeId, Option<Pose>)> {
        let mut out = Vec::new();
        for s in &held.supports {
            let Some(node) = graph.node(s.node) else {
                continue;
            };
            if node.body().is_some_and(|h| self.held.contains_key(&key(h))) {
                continue;
            }
            let watched = match node.kind() {
                NodeKind::Fixed => s.pose.is_some(),
                NodeKind::Kinematic => true,
                _ => false,
            };
            if watched {
                out.push((s.node, s.pose));
            }
        }
        out
    }

    /// Counts `entries` into the support watch (`add`) or out of it. O(entries · log
    /// watch), plus a shift where an entry appears or goes.
    pub(super) fn watch_count(&mut self, entries: &[(NodeId, Option<Pose>)], add: bool) {
        for &(n, pose) in entries {
            let bits = pose_bits(pose);
            let at = self
                .support_watch
                .binary_search_by(|&(m, p, _)| m.cmp(&n).then_with(|| pose_bits(p).cmp(&bits)));
            match (at, add) {
                (Ok(i), true) => {
                    let c = &mut self.support_watch[i].2;
                    *c = c.saturating_add(1);
                }
                (Err(i), true) => self.support_watch.insert(i, (n, pose, 1)),
                (Ok(i), false) => {
                    let c = &mut self.support_watch[i].2;
                    *c = c.saturating_sub(1);
                    if *c == 0 {
                        self.support_watch.remove(i);
                    }
                }
                (Err(_), false) => {}
            }
        }
    }

    /// Replaces what held body `k` adds to the support watch by what it adds now.
    /// O(its supporters · log watch).
    pub(super) fn rewatch(&mut self, graph: &ContactGraph, k: &(u32, u32)) {
        let Some(held) = self.held.get(k) else { return };
        let now = self.watch_of(graph, held);
        let Some(held) = self.held.get_mut(k) else {
            return;
        };
        let before = std::mem::replace(&mut held.watched, now.clone());
        self.watch_count(&before, false);
        self.watch_count(&now, true);
    }

    /// Watches the static and scripted supporters of the bodies held since the last
    /// evaluation from now on ([`Self::rewatch`]). O(their supporters · log watch).
    pub(super) fn watch_newly_held(&mut self, graph: &ContactGraph) {
        let new = std::mem::take(&mut self.newly_held);
        for k in &new {
            self.rewatch(graph, k);
        }
        self.newly_held = new;
    }

    /// Whether a held body has a remembered supporter that holds it up by itself: one
    /// that is not a held body and still supports ([`Self::static_support_holds`]).
    /// O(its supporters).
    pub(super) fn holds_alone(&self, graph: &ContactGraph, view: &WorldView, held: &Held) -> bool {
        held.supports.iter().any(|s| {
            graph.node(s.node).is_some_and(|node| {
                !node.body().is_some_and(|h| self.held.contains_key(&key(h)))
                    && self.static_support_holds(graph, view, node, s)
            })
        })
    }

    /// Whether a supporter that is not a held body still supports: static geometry
    /// where it was, a scripted body not moving. (A simulated supporter supports only
    /// through a touching contact now.)
    pub(super) fn static_support_holds(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        node: &crate::graph::Node,
        s: &Supporter,
    ) -> bool {
        match node.kind() {
            NodeKind::Fixed => s.pose.is_some() && static_pose(graph, view, s.node) == s.pose,
            NodeKind::Kinematic => node
                .body()
                .and_then(|mh| view.bodies.get(mh))
                .is_some_and(|rb| !crate::world::moves(rb)),
            _ => false,
        }
    }

    /// Whether a body held by fixation is still supported against gravity: `None` for
    /// a body that is not held. O(1) (evaluated once per step, after the decisions).
    ///
    /// Why this is needed: a fixated body is fixed in Rapier, and Rapier computes no
    /// contacts between two fixed bodies, so neither Rapier nor the graph knows what a
    /// fixated body rests on once its neighbours are fixed too. What supported it
    /// when it was fixated is remembered, and the support still holds while one of
    /// those supporters still does: static geometry; a scripted body that is not
    /// moving; a held body that is itself supported (recursively); or any touching
    /// contact that pushes it up now (Rapier computes those with the bodies that are
    /// not fixed). A chain of fixated bodies is judged through the chain, so taking
    /// the bottom of a fixated pile away leaves the bodies above it unsupported.
    pub fn fixation_supported(&self, h: RigidBodyHandle) -> Option<bool> {
        let k = key(h);
        self.held
            .contains_key(&k)
            .then(|| !self.unsupported.contains(&k))
    }

    /// The bodies held by fixation whose support is gone, in handle order. O(their
    /// number).
    pub fn unsupported_fixated(&self) -> impl Iterator<Item = RigidBodyHandle> + '_ {
        self.unsupported
            .iter()
            .filter_map(|k| self.held.get(k).map(|h| h.handle))
    }

    /// The supporters remembered for a body held by fixation (what held it against
    /// gravity when it was fixated), in the order found; `None` for a body that is not
    /// held. O(1).
    pub fn fixation_supporters(&self, h: RigidBodyHandle) -> Option<Vec<NodeId>> {
        self.held
            .get(&key(h))
            .map(|held| held.supports.iter().map(|s| s.node).collect())
    }

    /// Re-evaluates [`Self::fixation_supported`] for every held body: the least fixed
    /// point of "supported" — a held body is supported if something supports it now
    /// (a touching contact that pushes it up, computed by Rapier against bodies that
    /// are not fixed), if a remembered static supporter is still where it was, or a
    /// remembered scripted supporter is not moving; or if a remembered supporter is a
    /// held body that is supported. Computed from the bases up (a cycle of held bodies
    /// resting on each other supports nothing by itself). O(held bodies + their
    /// remembered supporters).
    pub(super) fn evaluate_support(&mut self, graph: &ContactGraph, view: &WorldView, up: Vector) {
        self.support_dirty = false;
        self.support_up = up;
        self.support_watch.clear();
        self.released.clear();
        let keys: Vec<(u32, u32)> = self.held.keys().copied().collect();
        for k in &keys {
            if let Some(held) = self.held.get_mut(k) {
                held.watched.clear();
            }
            self.rewatch(graph, k);
        }
        self.unsupported.clear();
        self.rest_based.clear();
        self.support_partial_ok = true;
        if !(up.is_finite() && up != Vector::ZERO) || keys.is_empty() {
            return;
        }
        let (supported, resting) =
            self.judge_support(graph, view, up, &keys, self.held.values(), &BTreeMap::new());
        self.apply_judgement(&keys, &supported, &resting);
    }

    /// Judges the held bodies `judged` (sorted keys of held bodies; `records`, their
    /// held records in the same order): "supported" as the least fixed point from the
    /// bases up (see [`Self::fixation_supported`]), a held supporter outside `judged`
    /// counting as supported. Returns, per judged body, whether it is supported and
    /// whether it rests on a contact Rapier computes now. O(judged bodies × their
    /// contact pairs and remembered supporters).
    pub(super) fn judge_support<'h>(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        up: Vector,
        judged: &[(u32, u32)],
        records: impl Iterator<Item = &'h Held>,
        rests: &BTreeMap<(u32, u32), bool>,
    ) -> (Vec<bool>, Vec<bool>) {
        // Judged bodies by index (keys are sorted: a held supporter is found by binary
        // search); "supporter i holds up dependent j" as pairs, sorted into ranges.
        let index = |k: (u32, u32)| judged.binary_search(&k).ok();
        // Only a partial judgement has held supporters outside the judged bodies.
        let partial = judged.len() < self.held.len();
        let mut supported = vec![false; judged.len()];
        let mut resting = vec![false; judged.len()];
        let mut links: Vec<(usize, usize)> = Vec::new();
        let mut queue: Vec<usize> = Vec::new();
        for (i, held) in records.enumerate() {
            if graph.node_of_body(held.handle).is_none() {
                continue;
            }
            let mut base = match rests.get(&key(held.handle)) {
                Some(&r) => r,
                None => rests_now(graph, view, held.handle, up),
            };
            resting[i] = base;
            for s in &held.supports {
                if base {
                    break;
                }
                let Some(node) = graph.node(s.node) else {
                    continue;
                };
                match node.body().map(key) {
                    Some(mk) => match index(mk) {
                        Some(j) => links.push((j, i)),
                        None if partial && self.held.contains_key(&mk) => base = true,
                        None => base = self.static_support_holds(graph, view, node, s),
                    },
                    None => base = self.static_support_holds(graph, view, node, s),
                }
            }
            if base {
                supported[i] = true;
                queue.push(i);
            }
        }
        propagate_support(&mut links, &mut supported, queue);
        (supported, resting)
    }

    /// Records a judgement ([`Self::judge_support`]) of the held bodies `judged` in
    /// the unsupported and resting sets. O(judged · log held).
    pub(super) fn apply_judgement(
        &mut self,
        judged: &[(u32, u32)],
        supported: &[bool],
        resting: &[bool],
    ) {
        for (i, k) in judged.iter().enumerate() {
            if supported[i] {
                self.unsupported.remove(k);
            } else {
                self.unsupported.insert(*k);
            }
            if resting[i] {
                self.rest_based.insert(*k);
            } else {
                self.rest_based.remove(k);
            }
        }
    }
}
