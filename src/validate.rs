//! `validate()`: every invariant of the layer, including the graph against Rapier.
//!
//! Meant for tests and debugging (the test suite runs it after every step). It walks
//! everything — all bodies, colliders, Rapier pairs, nodes, edges and groups — so it
//! costs O(world), unlike the per-step upkeep.

use std::collections::{HashMap, HashSet};

use rapier3d::prelude::RigidBodyHandle;

use crate::graph::mirror::{is_static_collider_node, kind_of_body};
use crate::graph::validate::edge_allowed;
use crate::graph::{EdgeKind, NodeKind, PairBuildHasher, PairKey};
use crate::{ContactLayer, Error, Result, WorldView};

fn fail<T>(msg: String) -> Result<T> {
    Err(Error::Invariant(msg))
}

/// What `validate()` holds against the world: the layer's graph, the world, and the
/// rules in force.
struct Check<'a> {
    layer: &'a ContactLayer,
    graph: &'a crate::ContactGraph,
    view: &'a WorldView<'a>,
    screen: crate::coherence::Screen<'a>,
    /// Bodies the speed-ups gave back after the analysis ([`ContactLayer::step`]
    /// releases at once): the graph shows them as the step saw them (held, fixed,
    /// sleepy) until the next analysis reads them, and so does the check.
    given_back: HashSet<RigidBodyHandle>,
}

pub(crate) fn validate_layer(layer: &ContactLayer, view: &WorldView) -> Result<()> {
    let graph = layer.graph();
    graph.validate()?;
    // Nothing analysed yet: no graph to hold against the world.
    if layer.analysis().current_step() == 0 {
        return Ok(());
    }
    let check = Check {
        layer,
        graph,
        view,
        screen: crate::coherence::Screen {
            rules: layer.rule_table(),
            force: &[],
        },
        given_back: layer.analysis().given_back().into_iter().collect(),
    };
    check.nodes()?;
    check.contacts()?;
    check.triggers()?;
    check.containers()?;
    if let Some(s) = layer.speedups() {
        s.check_held_boxes(view).or_else(fail)?;
    }
    check.groups()
}

impl Check<'_> {
    /// The node of a collider's owner (body or static collider).
    fn owner(&self, c: rapier3d::prelude::ColliderHandle) -> Option<crate::NodeId> {
        crate::graph::mirror::collider_owner(self.graph, self.view, c)
    }

    /// Whether a pair is screened: by a passive end, or by a rule that Rapier applied
    /// (it asks the filter hooks only where a collider carries the flag). A
    /// rule-screened pair must then be one Rapier filtered: no contact, no
    /// intersection.
    fn screened(
        &self,
        (a, b): (crate::NodeId, crate::NodeId),
        (c1, c2): (
            rapier3d::prelude::ColliderHandle,
            rapier3d::prelude::ColliderHandle,
        ),
        sensor_pair: bool,
        active: bool,
    ) -> Result<bool> {
        let (graph, view, screen) = (self.graph, self.view, &self.screen);
        let passive = |n| {
            graph
                .node(n)
                .is_some_and(|n: &crate::Node| n.is_body_disabled())
        };
        if passive(a) || passive(b) {
            return Ok(true);
        }
        if !screen.rule_screens(graph, view, (a, b), (c1, c2), sensor_pair) {
            return Ok(false);
        }
        if active {
            let kind = |n| graph.node(n).map(|n: &crate::Node| (n.kind(), n.source()));
            return fail(format!(
                "a rule screens the pair {c1:?}–{c2:?} of nodes {a} ({:?})–{b} ({:?}), but \
                 Rapier collides it (are the layer's hooks given to Rapier's step?)",
                kind(a),
                kind(b)
            ));
        }
        Ok(true)
    }

    /// Nodes against bodies and static colliders; held flags against the speed-ups.
    fn nodes(&self) -> Result<()> {
        let (layer, graph, view) = (self.layer, self.graph, self.view);
        // Nodes against bodies and static colliders.
        let mut physical_nodes = 0usize;
        for (h, rb) in view.bodies.iter() {
            let Some(id) = graph.node_of_body(h) else {
                return fail(format!("body {h:?} has no node"));
            };
            let node = graph.try_node(id)?;
            let kind = node.kind();
            if self.given_back.contains(&h) && node.is_held() {
                physical_nodes += 1;
                continue;
            }
            if node.is_held() != layer.fixates(h) {
                return fail(format!(
                    "node {id:?} of body {h:?} is held = {}, the speed-ups say {}",
                    node.is_held(),
                    !node.is_held()
                ));
            }
            let want = kind_of_body(view, h, rb);
            if kind != want {
                return fail(format!(
                    "node {id:?} of body {h:?} is {kind:?}, body is {want:?}"
                ));
            }
            physical_nodes += 1;
        }
        for (h, _) in view.colliders.iter() {
            if is_static_collider_node(view, h) {
                if graph.node_of_static_collider(h).is_none() {
                    return fail(format!("static collider {h:?} has no node"));
                }
                physical_nodes += 1;
            }
        }
        let graph_physical: usize = [
            NodeKind::Dynamic,
            NodeKind::Fixed,
            NodeKind::Kinematic,
            NodeKind::Link,
        ]
        .iter()
        .map(|k| graph.count_of_kind(*k))
        .sum();
        if graph_physical != physical_nodes {
            return fail(format!(
                "{graph_physical} body nodes for {physical_nodes} bodies and static colliders"
            ));
        }

        Ok(())
    }

    /// Rapier pairs against physical edges: each Rapier pair that Table 2 allows and
    /// nothing screens has its proximate edge with Rapier's touching state (and,
    /// under touching tracking, its count of touching collider pairs); no proximate
    /// edge without its Rapier pair but the frozen ones.
    fn contacts(&self) -> Result<()> {
        let (layer, graph, view) = (self.layer, self.graph, self.view);
        // Touching tracking keeps touching edges only, each counting its touching collider
        // pairs.
        let touching_only =
            layer.analysis().coherence().tracking() == crate::coherence::Tracking::Touching;
        let mut touching_counts: HashMap<PairKey, u32, PairBuildHasher> = HashMap::default();
        let mut rapier_pairs: HashMap<PairKey, bool, PairBuildHasher> = HashMap::default();
        for pair in view.narrow_phase.contact_pairs() {
            if touching_only && !pair.has_any_active_contact() {
                continue;
            }
            let sensor = |c| view.colliders.get(c).is_none_or(|c| c.is_sensor());
            if sensor(pair.collider1) || sensor(pair.collider2) {
                continue;
            }
            let (Some(n1), Some(n2)) = (self.owner(pair.collider1), self.owner(pair.collider2))
            else {
                return fail(format!(
                    "Rapier pair {:?}–{:?} has a collider without node",
                    pair.collider1, pair.collider2
                ));
            };
            let (k1, k2) = (graph.try_node(n1)?.kind(), graph.try_node(n2)?.kind());
            if n1 == n2
                || !edge_allowed(EdgeKind::Physical, k1, k2)
                || self.screened(
                    (n1, n2),
                    (pair.collider1, pair.collider2),
                    false,
                    pair.has_any_active_contact(),
                )?
            {
                continue;
            }
            *rapier_pairs.entry(PairKey::of(n1, n2)).or_insert(false) |=
                pair.has_any_active_contact();
            if touching_only {
                *touching_counts.entry(PairKey::of(n1, n2)).or_insert(0) += 1;
            }
        }
        for (&key, &touching) in &rapier_pairs {
            let Some(eid) = graph.edge_by_key(key) else {
                return fail(format!(
                    "Rapier pair of nodes {}–{} has no edge",
                    key.a(),
                    key.b()
                ));
            };
            let e = graph.try_edge(eid)?;
            if e.kind() != EdgeKind::Physical || !e.is_proximate() {
                return fail(format!("edge {eid:?} of a Rapier pair is not proximate"));
            }
            if e.is_touching() != touching {
                return fail(format!(
                    "edge {eid:?} touching = {}, Rapier says {touching}",
                    e.is_touching()
                ));
            }
            if touching_only {
                let want = touching_counts.get(&key).copied().unwrap_or(0);
                if e.cache().collider_pairs != want {
                    return fail(format!(
                        "edge {eid:?} counts {} touching collider pairs, Rapier has {want}",
                        e.cache().collider_pairs
                    ));
                }
            }
        }
        for (eid, e) in graph.edges() {
            if e.kind() == EdgeKind::Physical
                && e.is_proximate()
                && !rapier_pairs.contains_key(&PairKey::of(e.a(), e.b()))
                && !graph.is_frozen(e)
            {
                return fail(format!("edge {eid:?} is proximate without a Rapier pair"));
            }
        }

        Ok(())
    }

    /// Triggers: one node per sensor, a geometric edge per intersecting trigger–body
    /// pair.
    fn triggers(&self) -> Result<()> {
        let (graph, view) = (self.graph, self.view);
        // Triggers: one node per sensor, a geometric edge per intersecting trigger–body pair.
        let mut inside: HashMap<PairKey, (), PairBuildHasher> = HashMap::default();
        for (h, c) in view.colliders.iter() {
            if c.is_sensor() && graph.node_of_sensor(h).is_none() {
                return fail(format!("sensor {h:?} has no trigger node"));
            }
        }
        for (c1, c2, intersecting) in view.narrow_phase.intersection_pairs() {
            if !intersecting {
                continue;
            }
            let (s1, s2) = (
                view.colliders.get(c1).is_some_and(|c| c.is_sensor()),
                view.colliders.get(c2).is_some_and(|c| c.is_sensor()),
            );
            let (sensor, other) = match (s1, s2) {
                (true, false) => (c1, c2),
                (false, true) => (c2, c1),
                _ => continue,
            };
            let (Some(t), Some(b)) = (graph.node_of_sensor(sensor), self.owner(other)) else {
                return fail(format!(
                    "trigger pair {c1:?}–{c2:?} has a collider without node"
                ));
            };
            if self.screened((t, b), (sensor, other), true, intersecting)? {
                continue;
            }
            inside.insert(PairKey::of(t, b), ());
        }
        for (eid, e) in graph.edges() {
            if e.kind() == EdgeKind::Geometric && !inside.contains_key(&PairKey::of(e.a(), e.b())) {
                return fail(format!(
                    "geometric edge {eid:?} without an intersecting Rapier pair"
                ));
            }
        }
        for key in inside.keys() {
            let ok = graph
                .edge_by_key(*key)
                .and_then(|e| graph.edge(e))
                .is_some_and(|e| e.kind() == EdgeKind::Geometric && e.is_proximate());
            if !ok {
                return fail(format!(
                    "nodes {}–{} intersect in Rapier but have no geometric edge",
                    key.a(),
                    key.b()
                ));
            }
        }

        Ok(())
    }

    /// Containers against Rapier's joints.
    fn containers(&self) -> Result<()> {
        let (graph, view) = (self.graph, self.view);
        // Containers against Rapier's joints: one container node per multibody and per
        // joined component, holding exactly its dynamic bodies.
        // A body given back counts as the analysis saw it: fixed if its node is.
        let seen_fixed = |h| {
            self.given_back.contains(&h)
                && graph
                    .node_of_body(h)
                    .and_then(|n| graph.node(n))
                    .is_some_and(|n| n.kind() == NodeKind::Fixed)
        };
        let want = crate::logic::containers::desired(view, &seen_fixed);
        let mut containers = 0usize;
        for (id, n) in graph.nodes() {
            let crate::NodeSource::Container(source) = n.source() else {
                continue;
            };
            containers += 1;
            let Some(members) = want.get(&source) else {
                return fail(format!(
                    "container {id} ({source:?}) stands for no joints in Rapier"
                ));
            };
            let mut have: Vec<(u32, u32)> = graph
                .neighbors(id)
                .filter(|(_, _, e)| e.kind() == EdgeKind::Structural)
                .filter_map(|(m, _, _)| graph.body_of(m))
                .map(|h| h.into_raw_parts())
                .collect();
            have.sort_unstable();
            let wanted: Vec<(u32, u32)> = members.iter().map(|h| h.into_raw_parts()).collect();
            if have != wanted {
                return fail(format!(
                    "container {id} ({source:?}) holds bodies {have:?}, Rapier's joints join \
                 {wanted:?}"
                ));
            }
        }
        if containers != want.len() {
            return fail(format!(
                "Rapier's joints make {} containers, the graph has {containers}",
                want.len()
            ));
        }

        Ok(())
    }

    /// Groups, when computed: each as a from-scratch traversal would build it.
    fn groups(&self) -> Result<()> {
        let (layer, graph) = (self.layer, self.graph);
        // Groups (when computed).
        if !layer.grouping() {
            return if layer.groups().is_empty() {
                Ok(())
            } else {
                fail("groups off but groups kept".into())
            };
        }
        let groups = layer.groups();
        // Each group as a from-scratch traversal would build it (members pointing back,
        // edges, insulators, counts, sleep, connectivity; no joining edge between two).
        // A body given back was sleepy when the step was analysed (held bodies are).
        let sleepy_insulates = layer.speedups().is_some_and(|s| s.config().insulate_sleepy);
        let insulates = |n| {
            layer.analysis().insulates(n)
                || (sleepy_insulates
                    && graph
                        .body_of(n)
                        .is_some_and(|h| self.given_back.contains(&h)))
        };
        groups.verify(graph, &insulates).map_err(Error::Invariant)?;
        let mut pointing: HashMap<crate::GroupId, usize, PairBuildHasher> = HashMap::default();
        for (id, node) in graph.nodes() {
            let simulated = node.kind().is_simulated();
            if simulated
                && node.is_awake()
                && !node.is_body_disabled()
                && node.group().is_none()
                && !insulates(id)
            {
                return fail(format!("awake body {id:?} has no group"));
            }
            if let Some(gid) = node.group() {
                let Some(g) = groups.get(gid) else {
                    return fail(format!("node {id:?} points to dead group {gid:?}"));
                };
                // Every member points back (`verify`), so a node pointing to a group
                // that does not hold it makes the group's pointer count exceed its size.
                let n = pointing.entry(gid).or_insert(0usize);
                *n += 1;
                if *n > g.bodies.len() {
                    return fail(format!(
                        "node {id:?} points to group {gid:?} not holding it"
                    ));
                }
            }
        }
        Ok(())
    }
}
