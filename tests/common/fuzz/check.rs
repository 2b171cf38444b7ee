//! [`Harness::step`]: one step of the layer, then every check of
//! `tests/fuzz_operations.rs` (the twin, 1. `validate()` and the touching oracle, 2.
//! the event contract, 3. the subscriptions, 5. awake, passive and held flags against
//! Rapier, 4. the graph against a fresh layer's).

use std::collections::{HashMap, HashSet};

use rapier_contact_graph::rapier3d::prelude::*;
use rapier_contact_graph::{
    ContactLayer, Error, Event, KindSet, NodeId, NodeKind, Rule, WorldView,
};

use super::contract::{matches, InForce};
use super::derived::{derived, diff, given_back_keys, key_of, set_diff, Derived, Key};
use super::ops::raw;
use super::oracle::touching_agrees;
use super::{Asked, Harness};

impl Harness {
    fn in_force(&self) -> InForce {
        InForce {
            rules: self
                .rules
                .iter()
                .filter_map(|&r| self.layer.logic().rule(r).cloned())
                .collect(),
            passive: self
                .passive
                .values()
                .filter(|a| a.disabled && self.world.bodies.contains(a.handle))
                .filter_map(|a| self.layer.graph().try_node_of_body(a.handle).ok())
                .collect(),
        }
    }

    /// One step, then every check.
    pub fn step(&mut self) -> Result<(), String> {
        let mut in_force = self.in_force();
        self.layer.step(&mut self.world);
        // What the pre-step refused or undid (a body made passive that had become a
        // multibody member) was not passive during the step.
        for &(h, ref e) in self.layer.logic().refusals() {
            if !matches!(e, Error::Unsupported { .. }) {
                return Err(format!("refusal of {h:?} is not Unsupported: {e}"));
            }
            // A request of this step refused: nothing changed, what was asked before
            // stands, unless that was the layer's own passive, applied earlier: a
            // passive body joined to a multibody is made active again (so is one
            // refused with no request this step).
            let undone = Asked {
                handle: h,
                disabled: false,
                by_layer: true,
            };
            let now = match self.pending.get(&raw(h)) {
                Some(Some(before)) if before.by_layer && before.disabled => Some(undone),
                Some(&before) => before,
                None => Some(undone),
            };
            match now {
                Some(a) => self.passive.insert(raw(h), a),
                None => self.passive.remove(&raw(h)),
            };
            if let Ok(n) = self.layer.graph().try_node_of_body(h) {
                if !now.is_some_and(|a| a.disabled) {
                    in_force.passive.remove(&n);
                }
            }
            self.counters.refused += 1;
        }
        #[cfg(test)]
        {
            self.log.passive = in_force.passive.clone();
        }
        (self.added, self.removed) = (false, false);
        self.pending.clear();
        self.counters.steps += 1;
        if self.layer.analysis().coherence().tracking()
            == rapier_contact_graph::coherence::Tracking::Touching
        {
            self.counters.touching_steps += 1;
        }
        let step = self.layer.analysis().current_step();
        self.quarantined
            .extend(self.world.quarantine().bodies().iter().map(|&h| raw(h)));
        self.step_twin()
            .and_then(|()| self.check(step, &in_force))
            .map_err(|e| format!("after step {step}: {e}"))
    }

    fn check(&mut self, step: u64, in_force: &InForce) -> Result<(), String> {
        let layer = &self.layer;
        let world = &self.world;
        self.counters.max_nodes = self.counters.max_nodes.max(layer.graph().node_count());
        self.counters.sleeping_seen += world
            .bodies
            .iter()
            .filter(|(_, b)| b.is_sleeping() && !b.is_fixed())
            .count() as u64;

        // 1. validate(), and the touching oracle.
        layer
            .validate(&*world)
            .map_err(|e| format!("validate() failed: {e}"))?;
        self.counters.touching_pairs += touching_agrees(layer, world)?;
        // Under touching tracking no kind that needs every pair read is generated.
        if layer.analysis().coherence().tracking()
            == rapier_contact_graph::coherence::Tracking::Touching
        {
            if let Some(e) = layer
                .last_events()
                .iter()
                .find(|e| KindSet::NEEDS_EVERY_PAIR.contains(e.kind))
            {
                return Err(format!("under touching tracking: {e:?}"));
            }
        }

        // 2. The contract.
        let got: Vec<Event> = self.rx.try_iter().collect();
        let want: Vec<Event> = layer
            .last_events()
            .iter()
            .filter(|e| self.base.kinds_set().contains(e.kind))
            .copied()
            .collect();
        if got != want {
            return Err(format!(
                "the base subscriber ({:?}) got {} events, last_events() has {} of its kinds",
                self.base.kinds_set(),
                got.len(),
                want.len()
            ));
        }
        for ev in &got {
            self.counters.events += 1;
            self.counters.kinds_seen |= 1 << (ev.kind as u8);
            self.contract.check(ev, step, layer, in_force)?;
        }
        self.contract.agrees_with(layer)?;
        #[cfg(test)]
        {
            self.log.drain();
            self.log.agrees_with(layer);
        }
        // 3. Subscriptions.
        for s in &self.subs {
            let got: Vec<Event> = s.rx.try_iter().collect();
            let want: Vec<Event> = layer
                .last_events()
                .iter()
                .filter(|e| matches(&s.filter, e, layer))
                .copied()
                .collect();
            let want = if s.capacity > 0 && want.len() > s.capacity {
                &want[..s.capacity]
            } else {
                &want[..]
            };
            if got != want {
                return Err(format!(
                    "subscription {:?} (capacity {}, {:?}) got {:?}, expected {:?}",
                    s.id, s.capacity, s.filter, got, want
                ));
            }
        }

        // 5. Awake and passive flags against Rapier.
        let active: HashSet<RigidBodyHandle> = world.islands.active_bodies().collect();
        // Held bodies the speed-ups disabled for this one step to take them out of
        // Rapier's active set are not passive.
        let parking: HashSet<RigidBodyHandle> = layer
            .speedups()
            .map(|s| s.parking().collect())
            .unwrap_or_default();
        for (h, rb) in world.bodies.iter() {
            let enabled = rb.is_enabled() || parking.contains(&h);
            let n = layer
                .graph()
                .try_node_of_body(h)
                .map_err(|e| format!("body {h:?} has no node: {e}"))?;
            let node = layer.graph().node(n).ok_or("dead node")?;
            let want_awake = active.contains(&h) && node.kind() != NodeKind::Fixed;
            if node.is_awake() != want_awake {
                return Err(format!(
                    "node {n:?} of body {h:?} ({:?}) awake = {}, Rapier: active {}",
                    node.kind(),
                    node.is_awake(),
                    active.contains(&h)
                ));
            }
            if node.is_body_disabled() == enabled {
                return Err(format!(
                    "node {n:?} of body {h:?} passive = {}, Rapier enabled = {} (parking: {})",
                    node.is_body_disabled(),
                    rb.is_enabled(),
                    parking.contains(&h)
                ));
            }
            if let Some(a) = self.passive.get(&raw(h)) {
                if a.disabled == enabled && !self.quarantined.contains(&raw(h)) {
                    let by = if a.by_layer {
                        "set_body_disabled"
                    } else {
                        "the user's own set_enabled: disabled"
                    };
                    return Err(format!(
                        "body {h:?}: {by}({}) asked, Rapier enabled = {} (parking: {})",
                        a.disabled,
                        rb.is_enabled(),
                        parking.contains(&h)
                    ));
                }
            }
        }
        // Held bodies: fixed to Rapier; those on their step out of Rapier's active set
        // disabled too (what the speed-ups say they changed is what Rapier has).
        if let Some(s) = layer.speedups() {
            for h in s.fixated() {
                self.counters.held_seen += 1;
                self.counters.parked_seen += u64::from(s.is_parked(h));
            }
            for h in s.parking() {
                let rb = world
                    .bodies
                    .get(h)
                    .ok_or_else(|| format!("parking body {h:?} is not in the world"))?;
                if !s.is_fixated(h) || !rb.is_fixed() || rb.is_enabled() {
                    return Err(format!(
                        "parking body {h:?}: held {}, fixed {}, enabled {}",
                        s.is_fixated(h),
                        rb.is_fixed(),
                        rb.is_enabled()
                    ));
                }
            }
        }

        // 4. The graph against a fresh layer.
        self.compare_with_fresh()
    }

    fn compare_with_fresh(&self) -> Result<(), String> {
        let world = &self.world;
        let layer = &self.layer;
        let view = WorldView::from(world);
        // The fresh layer tracks what the layer tracked at this step (touching
        // tracking holds touching pairs only, and counts collider pairs as contacts).
        let mut fresh = ContactLayer::with_tracking(layer.analysis().coherence().tracking());
        // The feed "reached" this analysis (it had nothing to miss: the switch to
        // touching tracking reads the touching pairs).
        let _ = fresh.event_handler();
        fresh.analyze(view);
        fresh
            .validate(&view)
            .map_err(|e| format!("the fresh layer fails validate(): {e}"))?;

        // The screen of validate(): the layer's rules, disabled bodies.
        let ids: HashMap<Key, NodeId> = layer
            .graph()
            .nodes()
            .filter_map(|(id, n)| Some((key_of(n.source())?, id)))
            .collect();
        let rules: Vec<&Rule> = layer
            .graph()
            .nodes_of_kind(NodeKind::Rule)
            .filter_map(|(id, _)| layer.logic().rule(id))
            .collect();
        let disabled = |k: Key| match k {
            Key::Body(i, g) => world
                .bodies
                .get(RigidBodyHandle::from_raw_parts(i, g))
                .is_some_and(|b| !b.is_enabled()),
            _ => false,
        };
        let skip = |a: Key, b: Key| {
            if disabled(a) || disabled(b) {
                return true;
            }
            match (ids.get(&a), ids.get(&b)) {
                (Some(&x), Some(&y)) => rules.iter().any(|r| r.ignores(x, y)),
                _ => false,
            }
        };
        let mut mine = derived(layer, &skip);
        let mut theirs = derived(&fresh, &skip);
        // Bodies the speed-ups gave back after the analysis are dynamic in the world,
        // and held and fixed in the layer's graph as the step saw them, until the next
        // analysis: their kind, contacts and the containers they join (Rapier's
        // joints make containers of dynamic bodies) are compared from the next step
        // on.
        let given_back = given_back_keys(layer);
        if !given_back.is_empty() {
            for k in &given_back {
                if let (Some(m), Some(t)) = (mine.nodes.get(k), theirs.nodes.get_mut(k)) {
                    t.0 = m.0;
                }
            }
            // The containers they may join or leave, on either side, and everything
            // joined to those (a component's container is named by one of its bodies).
            let mut reached: HashSet<Key> = given_back.clone();
            loop {
                let before = reached.len();
                for e in mine.structural.iter().chain(&theirs.structural) {
                    if reached.contains(&e.0) || reached.contains(&e.1) {
                        reached.extend([e.0, e.1]);
                    }
                }
                if reached.len() == before {
                    break;
                }
            }
            let container = |k: &Key| matches!(k, Key::Container(..)) && reached.contains(k);
            let joins = |a: &Key, b: &Key| given_back.contains(a) || given_back.contains(b);
            for d in [&mut mine, &mut theirs] {
                d.structural
                    .retain(|e| !joins(&e.0, &e.1) && !container(&e.0) && !container(&e.1));
                d.nodes.retain(|k, _| !container(k));
                // Their contacts: Rapier pairs them anew in the next step.
                d.physical.retain(|e, _| !joins(&e.0, &e.1));
            }
        }
        Self::report_difference(mine, theirs)
    }

    /// Ok when the layer's graph is the fresh layer's, else what differs.
    fn report_difference(mine: Derived, theirs: Derived) -> Result<(), String> {
        if mine == theirs {
            return Ok(());
        }
        let mut out = String::new();
        diff("node", &mine.nodes, &theirs.nodes, &mut out);
        diff("physical edge", &mine.physical, &theirs.physical, &mut out);
        set_diff(
            "geometric edge",
            &mine.geometric,
            &theirs.geometric,
            &mut out,
        );
        set_diff(
            "structural edge",
            &mine.structural,
            &theirs.structural,
            &mut out,
        );
        Err(format!("the graph differs from a fresh layer's:\n{out}"))
    }
}
