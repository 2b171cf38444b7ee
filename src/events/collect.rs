//! Turning the marks of a step into events, at the safe point (paper Fig. 10).

use super::{Event, EventKind, KindSet};
use crate::graph::{ContactGraph, Edge, EdgeKind, NodeId, NodeKind, Transition};

/// Everything a step's events are made of.
pub(crate) struct StepMarks<'a> {
    pub step: u64,
    pub graph: &'a ContactGraph,
    pub removed_edges: &'a [Edge],
    pub touched: &'a [crate::EdgeId],
    pub sleep_changes: &'a [(NodeId, bool)],
    pub ticks: &'a [(NodeId, u64)],
    /// Nodes removed this step (their kinds and handles are no longer in the graph).
    pub removed_nodes: &'a [crate::coherence::RemovedNode],
    /// The world just analysed: touch events read their normal and impulse from its
    /// narrow phase when the edges do not keep them (`details` false).
    pub view: &'a crate::WorldView<'a>,
    /// Whether the edges' caches hold this step's contact details (proximity
    /// tracking with details on).
    pub details: bool,
}

impl StepMarks<'_> {
    /// The normal (from `a` to `b`, `a` the smaller slot) and the normal impulse of a
    /// touching pair: from its edge's cache when the step copied them (`live`, the
    /// pair's edge when the caller has it, else looked up), else read from Rapier's
    /// narrow phase (O(the pairs of the colliders of the node with fewer colliders),
    /// per touch event).
    fn contact(
        &self,
        a: NodeId,
        b: NodeId,
        live: Option<&Edge>,
    ) -> (rapier3d::math::Vector, rapier3d::math::Real) {
        let found = if self.details {
            live.or_else(|| {
                self.graph
                    .edge_by_key(crate::graph::PairKey::of(a, b))
                    .and_then(|e| self.graph.edge(e))
            })
            .map(|e| (e.cache().normal, e.cache().normal_impulse))
        } else {
            crate::coherence::details::read_details(self.graph, self.view, a, b)
                .map(|c| (c.normal, c.normal_impulse))
        };
        found.unwrap_or((rapier3d::math::Vector::ZERO, 0.0))
    }

    fn collider(&self, n: NodeId) -> Option<rapier3d::prelude::ColliderHandle> {
        let source = self.graph.node(n).map(|x| x.source()).or_else(|| {
            self.removed_nodes
                .iter()
                .find(|r| r.id == n)
                .map(|r| r.source)
        });
        match source? {
            crate::NodeSource::Sensor(c) | crate::NodeSource::StaticCollider(c) => Some(c),
            _ => None,
        }
    }
    fn kind(&self, n: NodeId) -> Option<NodeKind> {
        self.graph.node(n).map(|x| x.kind()).or_else(|| {
            self.removed_nodes
                .iter()
                .find(|r| r.id == n)
                .map(|r| r.kind)
        })
    }
    fn body(&self, n: NodeId) -> Option<rapier3d::prelude::RigidBodyHandle> {
        let node = self.graph.node(n);
        node.and_then(|x| x.body().or(x.carrier())).or_else(|| {
            self.removed_nodes
                .iter()
                .find(|r| r.id == n)
                .and_then(|r| match r.source {
                    crate::NodeSource::Body(h) => Some(h),
                    _ => None,
                })
        })
    }
}

/// Appends the step's events of the wanted kinds to `out`, in the documented order.
pub(crate) fn collect(m: &StepMarks, wanted: KindSet, out: &mut Vec<Event>) {
    if wanted.is_empty() {
        return;
    }
    let step = m.step;
    let body = |n: NodeId| m.body(n);
    let is_trigger = |n: NodeId| m.kind(n) == Some(NodeKind::Sensor);
    // `edge`: the edge of an edge event (in the graph, or a removed edge's record),
    // which names its collider pair. `live`: that edge when it is in the graph (the
    // pair's only edge): its details are read from it, without looking the pair up
    // (`StepMarks::contact`).
    let mut push = |kind: EventKind,
                    a: NodeId,
                    b: Option<NodeId>,
                    tick: u64,
                    edge: Option<&Edge>,
                    live: Option<&Edge>| {
        if wanted.contains(kind) {
            let mut e = Event::plain(step, kind, a, b, body(a), b.and_then(body), tick);
            // The collider pair the edge names, oriented as the event's nodes (the
            // edge's is *A* first; a sensor event's `node1` is the sensor, maybe *B*);
            // without one (an edge restored from an older snapshot), the colliders
            // the nodes stand for.
            match edge.and_then(|x| Some((x.a(), x.colliders()?))) {
                Some((ea, (c_a, c_b))) => {
                    (e.collider1, e.collider2) = if ea == a {
                        (Some(c_a), Some(c_b))
                    } else {
                        (Some(c_b), Some(c_a))
                    };
                }
                None => {
                    e.collider1 = m.collider(a);
                    e.collider2 = b.and_then(|b| m.collider(b));
                }
            }
            if let (EventKind::ContactStarted | EventKind::ContactPersisted, Some(b)) = (kind, b) {
                (e.normal, e.impulse) = m.contact(a, b, live);
            }
            out.push(e);
        }
    };
    let awake = |n: NodeId| m.graph.node(n).is_some_and(|n| n.is_awake());

    // 1. Ends of edges removed with a node (or made passive, or left a trigger).
    for e in m.removed_edges {
        edge_events(e, false, step, false, &is_trigger, &mut push);
    }
    // 2. Edge events in refresh order.
    for &id in m.touched {
        if let Some(e) = m.graph.edge(id) {
            let persist = awake(e.a()) || awake(e.b());
            edge_events(e, true, step, persist, &is_trigger, &mut push);
        }
    }
    // 3. Sleep and wake.
    for &(n, now_awake) in m.sleep_changes {
        let kind = if now_awake {
            EventKind::WokeUp
        } else {
            EventKind::FellAsleep
        };
        push(kind, n, None, 0, None, None);
    }
    // 4. Timers.
    for &(t, k) in m.ticks {
        push(EventKind::TimerTick, t, None, k, None, None);
    }
}

/// The events of edge `e` (`live`: it is in the graph, not a removed edge's record).
fn edge_events<'e>(
    e: &'e Edge,
    live: bool,
    step: u64,
    persist: bool,
    is_trigger: &dyn Fn(NodeId) -> bool,
    push: &mut impl FnMut(EventKind, NodeId, Option<NodeId>, u64, Option<&'e Edge>, Option<&'e Edge>),
) {
    let (a, b) = (e.a(), Some(e.b()));
    let live = live.then_some(e);
    let mut push = |kind, a, b, live| push(kind, a, b, 0, Some(e), live);
    match e.kind() {
        EdgeKind::Physical => {
            let p = e.proximity_mark(step);
            let t = e.touching_mark(step);
            if p == Some(Transition::New) {
                push(EventKind::ProximityStarted, a, b, live);
            }
            if t == Some(Transition::New) {
                push(EventKind::ContactStarted, a, b, live);
            }
            if persist && p == Some(Transition::Persistent) {
                push(EventKind::ProximityPersisted, a, b, live);
            }
            if persist && t == Some(Transition::Persistent) {
                push(EventKind::ContactPersisted, a, b, live);
            }
            if t == Some(Transition::Vanished) {
                push(EventKind::ContactStopped, a, b, live);
            }
            if p == Some(Transition::Vanished) {
                push(EventKind::ProximityStopped, a, b, live);
            }
        }
        EdgeKind::Geometric => {
            // A trigger edge: the trigger first, the body second.
            let (trigger, body) = if is_trigger(e.a()) {
                (e.a(), e.b())
            } else {
                (e.b(), e.a())
            };
            match e.proximity_mark(step) {
                Some(Transition::New) => push(EventKind::SensorStarted, trigger, Some(body), live),
                Some(Transition::Vanished) => {
                    push(EventKind::SensorStopped, trigger, Some(body), live)
                }
                _ => {}
            }
        }
        EdgeKind::Structural | EdgeKind::Logical => {}
    }
}
