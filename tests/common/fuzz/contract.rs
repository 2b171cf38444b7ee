//! Checks 2 and 3 of `tests/fuzz_operations.rs`: the listener contract of `events`,
//! checked event by event by a checker of our own (the shared `ContractLog` of
//! `tests/common` runs beside it), and what a filtered subscription must receive.

use std::collections::{HashMap, HashSet};
use std::fmt::Write as _;

use rapier_contact_graph::{
    ContactLayer, EdgeKind, Event, EventKind, Filter, NodeId, NodeKind, Rule,
};

/// The listener contract, checked event by event (our own checker).
pub(super) struct Contract {
    /// Whether the checked stream carries the proximity kinds (the base subscriber
    /// of touching mode does not: its touches are checked without proximity spans).
    proximity: bool,
    /// Whether it carries contact and sensor spans (starts and stops).
    touches: bool,
    sensors: bool,
    /// Whether the layer runs a monitor (else a monitor event is a failure).
    monitor: bool,
    prox: HashSet<(NodeId, NodeId)>,
    touch: HashSet<(NodeId, NodeId)>,
    inside: HashSet<(NodeId, NodeId)>,
    asleep: HashMap<NodeId, bool>,
    ticks: HashMap<NodeId, u64>,
}

/// What was in force during a step: the rules, and the passive bodies' nodes.
#[derive(Default)]
pub(super) struct InForce {
    pub(super) rules: Vec<Rule>,
    pub(super) passive: HashSet<NodeId>,
}

impl Contract {
    /// A checker of the events `base` admits.
    pub(super) fn new(base: &Filter, monitor: bool) -> Self {
        let k = base.kinds_set();
        let both = |a, b| k.contains(a) && k.contains(b);
        Self {
            proximity: both(EventKind::ProximityStarted, EventKind::ProximityStopped),
            touches: both(EventKind::ContactStarted, EventKind::ContactStopped),
            sensors: both(EventKind::SensorStarted, EventKind::SensorStopped),
            monitor,
            prox: HashSet::new(),
            touch: HashSet::new(),
            inside: HashSet::new(),
            asleep: HashMap::new(),
            ticks: HashMap::new(),
        }
    }

    pub(super) fn check(
        &mut self,
        ev: &Event,
        step: u64,
        layer: &ContactLayer,
        in_force: &InForce,
    ) -> Result<(), String> {
        use EventKind::*;
        let bad = |m: &str| Err(format!("contract: {m}: {ev:?}"));
        if ev.step != step {
            return bad(&format!(
                "event of step {} delivered after step {step}",
                ev.step
            ));
        }
        let g = layer.graph();
        let is_end = matches!(ev.kind, ProximityStopped | ContactStopped | SensorStopped);
        for n in [Some(ev.node1), ev.node2].into_iter().flatten() {
            if !is_end && in_force.passive.contains(&n) {
                return bad("names a passive body");
            }
        }
        let pair_ignored = |a: NodeId, b: NodeId| in_force.rules.iter().any(|r| r.ignores(a, b));
        match ev.kind {
            ProximityStarted | ProximityPersisted | ProximityStopped | ContactStarted
            | ContactPersisted | ContactStopped => {
                let Some(b) = ev.node2 else {
                    return bad("pair event without b");
                };
                let k = (ev.node1, b);
                if ev.node1.index() >= b.index() {
                    return bad("pair event does not name A (smaller slot) first");
                }
                if !is_end && pair_ignored(ev.node1, b) {
                    return bad("Begin/Persist for a pair a rule in force ignores");
                }
                match ev.kind {
                    ProximityStarted => {
                        if !self.prox.insert(k) {
                            return bad("ProximityStarted twice");
                        }
                    }
                    ProximityPersisted => {
                        if !self.prox.contains(&k) {
                            return bad("ProximityPersisted without Begin");
                        }
                    }
                    ProximityStopped => {
                        if self.touch.contains(&k) {
                            return bad("proximity ends inside a touch");
                        }
                        if !self.prox.remove(&k) {
                            return bad("ProximityStopped without Begin");
                        }
                    }
                    ContactStarted => {
                        if self.proximity && !self.prox.contains(&k) {
                            return bad("touch outside proximity");
                        }
                        if !self.touch.insert(k) {
                            return bad("ContactStarted twice");
                        }
                    }
                    ContactPersisted => {
                        if !self.touch.contains(&k) {
                            return bad("ContactPersisted without Begin");
                        }
                    }
                    ContactStopped => {
                        if !self.touch.remove(&k) {
                            return bad("ContactStopped without Begin");
                        }
                    }
                    _ => unreachable!(),
                }
                if matches!(ev.kind, ProximityPersisted | ContactPersisted) {
                    let awake = |n| g.node(n).is_some_and(|n| n.is_awake());
                    if !awake(ev.node1) && !awake(b) {
                        return bad("Persist for a pair without an awake body");
                    }
                }
            }
            SensorStarted | SensorStopped => {
                let Some(b) = ev.node2 else {
                    return bad("trigger event without b");
                };
                if ev.kind == SensorStarted {
                    if pair_ignored(ev.node1, b) {
                        return bad("SensorStarted for a pair a rule in force ignores");
                    }
                    if !self.inside.insert((ev.node1, b)) {
                        return bad("Enter twice");
                    }
                } else if !self.inside.remove(&(ev.node1, b)) {
                    return bad("Exit without Enter");
                }
            }
            TimerTick => {
                let last = self.ticks.entry(ev.node1).or_insert(0);
                if ev.tick != *last + 1 {
                    return bad("ticks skip");
                }
                *last = ev.tick;
            }
            FellAsleep | WokeUp => {
                let now_awake = ev.kind == WokeUp;
                if self.asleep.insert(ev.node1, !now_awake) == Some(!now_awake) {
                    return bad("FellAsleep or WokeUp twice");
                }
                if g.node(ev.node1).is_some_and(|n| n.is_awake() != now_awake) {
                    return bad("sleep event disagrees with the node's awake flag");
                }
            }
            Violation | Repaired => {
                if !self.monitor {
                    return bad("monitor event without a monitor");
                }
                if ev.node2.is_some() || ev.violation.is_none() {
                    return bad("monitor event names two nodes, or no violation");
                }
            }
        }
        Ok(())
    }

    /// The open spans against the graph.
    pub(super) fn agrees_with(&self, layer: &ContactLayer) -> Result<(), String> {
        let g = layer.graph();
        let (mut prox, mut touch, mut inside) = (HashSet::new(), HashSet::new(), HashSet::new());
        for (_, e) in g.edges() {
            match e.kind() {
                EdgeKind::Physical => {
                    if e.is_proximate() {
                        prox.insert((e.a(), e.b()));
                    }
                    if e.is_touching() {
                        touch.insert((e.a(), e.b()));
                    }
                }
                EdgeKind::Geometric => {
                    let t_is_a = g.node(e.a()).is_some_and(|n| n.kind() == NodeKind::Sensor);
                    inside.insert(if t_is_a {
                        (e.a(), e.b())
                    } else {
                        (e.b(), e.a())
                    });
                }
                _ => {}
            }
        }
        let mut out = String::new();
        // Spans of kinds the stream does not carry are not followed.
        if !self.proximity {
            prox.clear();
        }
        if !self.touches {
            touch.clear();
        }
        if !self.sensors {
            inside.clear();
        }
        for (what, graph, stream) in [
            ("proximity", &prox, &self.prox),
            ("touch", &touch, &self.touch),
            ("trigger", &inside, &self.inside),
        ] {
            let mut only_graph: Vec<_> = graph.difference(stream).collect();
            let mut only_stream: Vec<_> = stream.difference(graph).collect();
            only_graph.sort();
            only_stream.sort();
            if !only_graph.is_empty() || !only_stream.is_empty() {
                let _ = writeln!(
                    out,
                    "  {what} spans: graph only {only_graph:?}, events only {only_stream:?}"
                );
            }
        }
        if out.is_empty() {
            Ok(())
        } else {
            Err(format!("open spans differ from the graph:\n{out}"))
        }
    }
}

fn member_of_any(n: NodeId, set: &[NodeId], layer: &ContactLayer) -> bool {
    set.contains(&n)
        || layer
            .graph()
            .neighbors(n)
            .any(|(m, _, e)| e.kind() == EdgeKind::Structural && set.contains(&m))
}

/// What a filtered subscription must receive (our own reading of `Filter`'s docs):
/// the kinds, and, when restricted, events involving anything named by any
/// restriction (nodes with their members, bodies in `body1`/`body2`, colliders in
/// `collider1`/`collider2`).
pub(super) fn matches(filter: &Filter, ev: &Event, layer: &ContactLayer) -> bool {
    if !filter.kinds_set().contains(ev.kind) {
        return false;
    }
    let restricted =
        filter.nodes().is_some() || filter.bodies().is_some() || filter.colliders().is_some();
    if !restricted {
        return true;
    }
    let by_node = filter.nodes().is_some_and(|set| {
        member_of_any(ev.node1, set, layer)
            || ev.node2.is_some_and(|b| member_of_any(b, set, layer))
    });
    let by_body = filter.bodies().is_some_and(|set| {
        [ev.body1, ev.body2]
            .into_iter()
            .flatten()
            .any(|h| set.contains(&h))
    });
    let by_collider = filter.colliders().is_some_and(|set| {
        [ev.collider1, ev.collider2]
            .into_iter()
            .flatten()
            .any(|c| set.contains(&c))
    });
    by_node || by_body || by_collider
}
