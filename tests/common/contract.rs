//! A logging subscriber that checks the listener contract of `events` as it logs
//! (Jolt's contract-checking contact listener, in spirit).
#![allow(dead_code)]

use std::collections::{HashMap, HashSet};

use crossbeam_channel::Receiver;
use rapier_contact_graph::{ContactLayer, Event, EventKind, Filter, NodeId};

/// Receives every event and checks the contract; panics on the first violation.
pub struct ContractLog {
    rx: Receiver<Event>,
    /// Whether the stream carries the proximity kinds (touching tracking's
    /// subscribers leave them out: their touches have no proximity spans).
    proximity: bool,
    pub events: Vec<Event>,
    prox: HashSet<(NodeId, NodeId)>,
    touch: HashSet<(NodeId, NodeId)>,
    inside: HashSet<(NodeId, NodeId)>,
    asleep: HashMap<NodeId, bool>,
    ticks: HashMap<NodeId, u64>,
    last_step: u64,
    /// Pairs no event may name (excluded by a rule).
    pub excluded: HashSet<(NodeId, NodeId)>,
    /// Nodes that are passive: only ends may name them.
    pub passive: HashSet<NodeId>,
}

fn key(a: NodeId, b: Option<NodeId>) -> (NodeId, NodeId) {
    let b = b.expect("pair event without b");
    if a.index() <= b.index() {
        (a, b)
    } else {
        (b, a)
    }
}

impl ContractLog {
    pub fn attach(layer: &mut ContactLayer) -> Self {
        Self::attach_with(layer, Filter::all())
    }

    /// A log of the events `filter` admits; without the proximity kinds, touches are
    /// checked without proximity spans.
    pub fn attach_with(layer: &mut ContactLayer, filter: Filter) -> Self {
        let proximity = filter
            .kinds_set()
            .contains(rapier_contact_graph::EventKind::ProximityStarted);
        Self {
            proximity,
            rx: layer.subscribe(filter),
            events: Vec::new(),
            prox: HashSet::new(),
            touch: HashSet::new(),
            inside: HashSet::new(),
            asleep: HashMap::new(),
            ticks: HashMap::new(),
            last_step: 0,
            excluded: HashSet::new(),
            passive: HashSet::new(),
        }
    }

    /// Drains the channel, checking each event; returns how many arrived.
    pub fn drain(&mut self) -> usize {
        let mut n = 0;
        while let Ok(ev) = self.rx.try_recv() {
            self.check(&ev);
            self.events.push(ev);
            n += 1;
        }
        n
    }

    fn check(&mut self, ev: &Event) {
        use EventKind::*;
        assert!(ev.step >= self.last_step, "steps go backwards: {ev:?}");
        self.last_step = ev.step;
        let is_end = matches!(ev.kind, ProximityStopped | ContactStopped | SensorStopped);
        let is_monitor = matches!(ev.kind, Violation | Repaired);
        for n in [Some(ev.node1), ev.node2].into_iter().flatten() {
            assert!(
                is_end || is_monitor || !self.passive.contains(&n),
                "event naming passive node {n:?}: {ev:?}"
            );
        }
        match ev.kind {
            ProximityStarted | ProximityPersisted | ProximityStopped | ContactStarted
            | ContactPersisted | ContactStopped => {
                let k = key(ev.node1, ev.node2);
                assert_eq!(
                    k,
                    (ev.node1, ev.node2.unwrap()),
                    "pair events name A first: {ev:?}"
                );
                assert!(
                    !self.excluded.contains(&k),
                    "event for an excluded pair: {ev:?}"
                );
                match ev.kind {
                    ProximityStarted => assert!(self.prox.insert(k), "Begin twice: {ev:?}"),
                    ProximityPersisted => {
                        assert!(self.prox.contains(&k), "Persist without Begin: {ev:?}")
                    }
                    ProximityStopped => {
                        assert!(
                            !self.touch.contains(&k),
                            "proximity ends inside a touch: {ev:?}"
                        );
                        assert!(self.prox.remove(&k), "End without Begin: {ev:?}")
                    }
                    ContactStarted => {
                        assert!(
                            !self.proximity || self.prox.contains(&k),
                            "touch outside proximity: {ev:?}"
                        );
                        assert!(self.touch.insert(k), "ContactStarted twice: {ev:?}")
                    }
                    ContactPersisted => assert!(
                        self.touch.contains(&k),
                        "ContactPersisted without Begin: {ev:?}"
                    ),
                    ContactStopped => assert!(
                        self.touch.remove(&k),
                        "ContactStopped without Begin: {ev:?}"
                    ),
                    _ => unreachable!(),
                }
            }
            SensorStarted => assert!(
                self.inside.insert((ev.node1, ev.node2.unwrap())),
                "Enter twice: {ev:?}"
            ),
            SensorStopped => assert!(
                self.inside.remove(&(ev.node1, ev.node2.unwrap())),
                "Exit without Enter: {ev:?}"
            ),
            TimerTick => {
                let last = self.ticks.entry(ev.node1).or_insert(0);
                assert_eq!(ev.tick, *last + 1, "ticks skip: {ev:?}");
                *last = ev.tick;
            }
            FellAsleep => {
                let was = self.asleep.insert(ev.node1, true);
                assert_ne!(was, Some(true), "FellAsleep twice: {ev:?}");
            }
            WokeUp => {
                let was = self.asleep.insert(ev.node1, false);
                assert_ne!(was, Some(false), "WokeUp twice: {ev:?}");
            }
            Violation | Repaired => {
                assert!(
                    ev.violation.is_some(),
                    "monitor event without a kind: {ev:?}"
                );
                assert!(
                    ev.node2.is_none() && ev.body1.is_some(),
                    "names one body: {ev:?}"
                );
                assert!(ev.value.is_finite(), "measure not finite: {ev:?}");
            }
        }
    }

    /// Pairs currently in proximity per the stream.
    pub fn open_proximity(&self) -> usize {
        self.prox.len()
    }
    /// Pairs currently touching per the stream.
    pub fn open_touch(&self) -> usize {
        self.touch.len()
    }
    /// Bodies currently inside triggers per the stream.
    pub fn open_inside(&self) -> usize {
        self.inside.len()
    }

    /// Checks the stream's open spans against the graph: every open proximity span is
    /// a proximate edge, every open touch a touching edge, every open trigger stay a
    /// geometric edge, and the other way round.
    pub fn agrees_with(&self, layer: &ContactLayer) {
        use rapier_contact_graph::EdgeKind;
        let g = layer.graph();
        let mut prox = HashSet::new();
        let mut touch = HashSet::new();
        let mut inside = HashSet::new();
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
                    let (t, b) = if g.node(e.a()).unwrap().kind()
                        == rapier_contact_graph::NodeKind::Sensor
                    {
                        (e.a(), e.b())
                    } else {
                        (e.b(), e.a())
                    };
                    inside.insert((t, b));
                }
                _ => {}
            }
        }
        if !self.proximity {
            prox.clear();
        }
        assert_eq!(
            prox,
            self.prox,
            "proximity spans vs graph at step {}",
            layer.analysis().current_step()
        );
        assert_eq!(
            touch,
            self.touch,
            "touch spans vs graph at step {}",
            layer.analysis().current_step()
        );
        assert_eq!(
            inside,
            self.inside,
            "trigger spans vs graph at step {}",
            layer.analysis().current_step()
        );
    }
}
