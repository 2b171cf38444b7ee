//! The logic layer on the contact layer (paper §3.2, Table 1): rules, timers,
//! passive bodies, containers and trigger widening, behind two small views in the
//! style of Rapier's sets: [`LayerLogic`] (`layer.logic()`) reads, [`LayerLogicMut`]
//! (`layer.logic_mut()`) changes. Rules and composites are named by Rapier handles
//! ([`RuleMember`]); their node forms (`add_rule`, `declare_composite_nodes`) take
//! node ids. A rule, a timer and a composite are themselves nodes: their node id is
//! their handle.

use rapier3d::prelude::{ColliderHandle, RigidBodyHandle, RigidBodySet};

use crate::graph::{Category, EdgeKind, NodeId, NodeKind, NodeSource};
use crate::logic::Rule;
use crate::{Error, Result, WorldView};

use super::ContactLayer;

/// What a rule names, by Rapier handle or by node: a body, a collider (a sensor
/// names its trigger; another collider its body, or itself if parentless), or a node
/// (a body or trigger node of the last analysed step). `From` each, so that the
/// `ignore_*` calls of [`LayerLogicMut`] take handles as they are.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RuleMember {
    /// A rigid body.
    Body(RigidBodyHandle),
    /// A collider: a sensor (its trigger node), or a collider standing for its body
    /// (a parentless collider stands for itself).
    Collider(ColliderHandle),
    /// A node of the graph (the node form).
    Node(NodeId),
}

impl From<RigidBodyHandle> for RuleMember {
    fn from(h: RigidBodyHandle) -> Self {
        RuleMember::Body(h)
    }
}

impl From<ColliderHandle> for RuleMember {
    fn from(c: ColliderHandle) -> Self {
        RuleMember::Collider(c)
    }
}

impl From<NodeId> for RuleMember {
    fn from(n: NodeId) -> Self {
        RuleMember::Node(n)
    }
}

/// The logic layer read: rules, timers, refusals ([`ContactLayer::logic`]).
#[derive(Clone, Copy, Debug)]
pub struct LayerLogic<'a> {
    layer: &'a ContactLayer,
}

/// The logic layer changed: rules, timers, passive bodies, composites, trigger
/// widening ([`ContactLayer::logic_mut`]). Changes to the graph show at once (a new
/// rule's node and edges); what touches the Rapier world is applied in the next
/// pre-step (see [`crate::logic`], "When changes take effect").
#[derive(Debug)]
pub struct LayerLogicMut<'a> {
    layer: &'a mut ContactLayer,
}

impl ContactLayer {
    /// The logic layer, read: rules, timers, the last pre-step's refusals (see
    /// [`LayerLogic`]). O(1).
    pub fn logic(&self) -> LayerLogic<'_> {
        LayerLogic { layer: self }
    }

    /// The logic layer, changed: rules, timers, passive bodies, composites, trigger
    /// widening (see [`LayerLogicMut`]). O(1).
    pub fn logic_mut(&mut self) -> LayerLogicMut<'_> {
        LayerLogicMut { layer: self }
    }

    fn check_rule_member(&self, n: NodeId) -> Result<()> {
        let node = self.graph.try_node(n)?;
        if node.kind().category() != Category::Physical && node.kind() != NodeKind::Sensor {
            return Err(Error::WrongKind {
                node: n,
                expected: "a body or a trigger (rules apply to those)",
            });
        }
        Ok(())
    }

    /// The node a rule member names, checked against the world. O(1).
    fn node_of_member(&self, view: &WorldView, m: RuleMember) -> Result<NodeId> {
        match m {
            RuleMember::Body(h) => self.node_of_body(view.bodies, h),
            RuleMember::Collider(c) => self.node_of_collider(view, c),
            RuleMember::Node(n) => Ok(n),
        }
    }

    /// The nodes of rule members, checked against the world (which is checked once).
    /// O(members).
    fn nodes_of_members<M: Into<RuleMember> + Copy>(
        &self,
        view: &WorldView,
        members: &[M],
    ) -> Result<Vec<NodeId>> {
        self.check_world(view)?;
        members
            .iter()
            .map(|&m| self.node_of_member(view, m.into()))
            .collect()
    }

    /// The rules in force (for validation).
    pub(crate) fn rule_table(&self) -> &crate::logic::RuleTable {
        self.logic.hooks.table()
    }
}

impl<'a> LayerLogic<'a> {
    /// The rule of a rule node; `None` for any other node. O(log rules).
    pub fn rule(&self, node: NodeId) -> Option<&'a Rule> {
        self.layer.logic.rules.get(&node)
    }

    /// The ticks a timer has fired so far. O(log timers).
    pub fn timer_ticks(&self, timer: NodeId) -> Result<u64> {
        self.layer.graph.try_node(timer)?;
        self.layer
            .logic
            .timers
            .ticks(timer)
            .ok_or(Error::WrongKind {
                node: timer,
                expected: "a timer",
            })
    }

    /// The period of a timer. O(log timers).
    pub fn timer_period(&self, timer: NodeId) -> Result<f64> {
        self.layer.graph.try_node(timer)?;
        self.layer
            .logic
            .timers
            .period(timer)
            .ok_or(Error::WrongKind {
                node: timer,
                expected: "a timer",
            })
    }

    /// Simulated seconds analysed while a timer existed (the timers' clock). O(1).
    pub fn simulated_time(&self) -> f64 {
        self.layer.logic.timers.time()
    }

    /// What the last pre-step refused or undid because Rapier 0.36 would panic on it,
    /// each with the body and an [`Error::Unsupported`] saying why: a queued
    /// [`LayerLogicMut::set_body_disabled`] of a body that had become a dynamic multibody member, or a
    /// passive body that the user joined to a multibody (made active again). Empty
    /// almost always; cleared by every pre-step. O(1).
    pub fn refusals(&self) -> &'a [(RigidBodyHandle, Error)] {
        &self.layer.logic.refusals
    }

    /// Whether sensors' collision types are widened (see
    /// [`LayerLogicMut::set_trigger_widening`]). O(1).
    pub fn trigger_widening(&self) -> bool {
        self.layer.logic.widen_sensors
    }
}

impl LayerLogicMut<'_> {
    /// "Ignore this pair": `a` and `b` (bodies, colliders or nodes, see
    /// [`RuleMember`]) stop interacting at the next step, as [`Self::add_rule`] says;
    /// returns the rule's node (its handle for [`Self::remove_rule`]). `world` is a
    /// `&PhysicsWorld` or a [`WorldView`] of one's own sets. Errors, with nothing
    /// changed: `Err(ForeignWorld)` for another world, `Err(UnknownBody)` /
    /// `Err(UnknownCollider)` for a handle the world lacks, `Err(UnseenBody)` /
    /// `Err(UnseenCollider)` for one inserted since the last step, `Err(WrongKind)` for
    /// a node that is no body or trigger. O(1).
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::ContactLayer;
    ///
    /// let mut world = PhysicsWorld::new();
    /// let (floor, _) = world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
    /// let (ghost, _) = world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
    ///     ColliderBuilder::ball(0.5),
    /// );
    /// let mut layer = ContactLayer::new();
    /// layer.step(&mut world);
    /// let rule = layer.logic_mut().ignore_pair(&world, floor, ghost).unwrap();
    /// for _ in 0..100 {
    ///     layer.step(&mut world);
    /// }
    /// assert!(world.bodies[ghost].translation().y < -1.0, "it fell through the floor");
    /// layer.logic_mut().remove_rule(rule).unwrap();
    /// ```
    pub fn ignore_pair<'w>(
        &mut self,
        world: impl Into<WorldView<'w>>,
        a: impl Into<RuleMember>,
        b: impl Into<RuleMember>,
    ) -> Result<NodeId> {
        let view = world.into();
        let nodes = self.layer.nodes_of_members(&view, &[a.into(), b.into()])?;
        self.add_rule(Rule::ignore_pair(nodes[0], nodes[1]))
    }

    /// "Ignore interactions between group X and group Y" by handles (or nodes): see
    /// [`Self::ignore_pair`] for the errors. O(|x| + |y|).
    pub fn ignore_between<'w, X, Y>(
        &mut self,
        world: impl Into<WorldView<'w>>,
        x: &[X],
        y: &[Y],
    ) -> Result<NodeId>
    where
        X: Into<RuleMember> + Copy,
        Y: Into<RuleMember> + Copy,
    {
        let view = world.into();
        let x = self.layer.nodes_of_members(&view, x)?;
        let y = self.layer.nodes_of_members(&view, y)?;
        self.add_rule(Rule::ignore_between(&x, &y))
    }

    /// A user predicate over the pairs involving `members` (by handles or nodes; see
    /// [`Self::ignore_pair`] for the errors). The predicate is asked with the pair's
    /// nodes, from inside Rapier's step ([`Rule::ignore_if`]); the graph's
    /// `body_of` gives their handles back. O(members).
    pub fn ignore_if<'w, M: Into<RuleMember> + Copy>(
        &mut self,
        world: impl Into<WorldView<'w>>,
        members: &[M],
        ignore: impl Fn(NodeId, NodeId) -> bool + Send + Sync + 'static,
    ) -> Result<NodeId> {
        let view = world.into();
        let nodes = self.layer.nodes_of_members(&view, members)?;
        self.add_rule(Rule::ignore_if(&nodes, ignore))
    }

    /// Adds a rule given by nodes (the node form of [`Self::ignore_pair`],
    /// [`Self::ignore_between`] and [`Self::ignore_if`]): a `Rule` node with a logical
    /// edge to each body it names. Pairs it ignores stop interacting at the next step
    /// (their bodies are woken so that resting pairs are released too), and their
    /// edges end. Every named node must be live and a body or trigger, else an error
    /// and nothing changes. The node answers as of the last analysed step (a body
    /// removed since still has one). O(members).
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::{ContactLayer, Rule};
    ///
    /// let mut world = PhysicsWorld::new();
    /// let (floor, _) = world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
    /// let (ghost, _) = world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
    ///     ColliderBuilder::ball(0.5),
    /// );
    /// let mut layer = ContactLayer::new();
    /// layer.step(&mut world);
    /// let f = layer.node_of_body(&world.bodies, floor).unwrap();
    /// let g = layer.node_of_body(&world.bodies, ghost).unwrap();
    /// layer.logic_mut().add_rule(Rule::ignore_pair(f, g)).unwrap();
    /// for _ in 0..100 {
    ///     layer.step(&mut world);
    /// }
    /// assert!(world.bodies[ghost].translation().y < -1.0, "it fell through the floor");
    /// ```
    pub fn add_rule(&mut self, rule: Rule) -> Result<NodeId> {
        let members = rule.members();
        if members.is_empty() {
            return Err(Error::InvalidParameter {
                name: "rule",
                reason: "names no node".into(),
            });
        }
        for &m in &members {
            self.layer.check_rule_member(m)?;
        }
        let serial = self.layer.logic.serial();
        let node = self
            .layer
            .graph
            .add_node(NodeKind::Rule, NodeSource::Layer(serial));
        for &m in &members {
            self.layer
                .graph
                .ensure_edge(node, m, EdgeKind::Logical, self.layer.coherence.step());
        }
        self.layer.logic.rules.insert(node, rule);
        self.layer.logic.rules_changed(&members, &self.layer.graph);
        Ok(node)
    }

    /// Removes a rule (by the node its `add_rule` or `ignore_*` returned); the pairs it
    /// ignored interact again from the next step. `Err(StaleNode)` for a removed
    /// node, `Err(WrongKind)` for a node that is not a rule. O(members).
    pub fn remove_rule(&mut self, rule: NodeId) -> Result<Rule> {
        let kind = self.layer.graph.try_node(rule)?.kind();
        if kind != NodeKind::Rule {
            return Err(Error::WrongKind {
                node: rule,
                expected: "a rule",
            });
        }
        let r = self
            .layer
            .logic
            .rules
            .remove(&rule)
            .ok_or(Error::StaleNode(rule))?;
        self.layer.graph.remove_node(rule);
        let members = r.members();
        self.layer.logic.rules_changed(&members, &self.layer.graph);
        Ok(r)
    }

    /// Adds a timer of `period` simulated seconds; it ticks `TimerTick` events (tick 1
    /// one period after now). A period that is not finite and positive is an error.
    /// O(log timers).
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::ContactLayer;
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.integration_parameters.dt = 0.01;
    /// let mut layer = ContactLayer::new();
    /// let timer = layer.logic_mut().add_timer(0.25).unwrap();
    /// for _ in 0..100 {
    ///     layer.step(&mut world);
    /// }
    /// assert_eq!(layer.logic().timer_ticks(timer).unwrap(), 4);
    /// assert!(layer.logic_mut().add_timer(-1.0).is_err());
    /// ```
    pub fn add_timer(&mut self, period: f64) -> Result<NodeId> {
        if !period.is_finite() || period < crate::logic::MIN_TIMER_PERIOD {
            return Err(Error::InvalidParameter {
                name: "period",
                reason: format!(
                    "must be finite and at least {} s, got {period}",
                    crate::logic::MIN_TIMER_PERIOD
                ),
            });
        }
        let serial = self.layer.logic.serial();
        let node = self
            .layer
            .graph
            .add_node(NodeKind::Timer, NodeSource::Layer(serial));
        self.layer.logic.timers.add(node, period);
        Ok(node)
    }

    /// Removes a timer. `Err(StaleNode)` for a removed node, `Err(WrongKind)` for a
    /// node that is not a timer. O(log timers).
    pub fn remove_timer(&mut self, timer: NodeId) -> Result<()> {
        let kind = self.layer.graph.try_node(timer)?.kind();
        if kind != NodeKind::Timer || !self.layer.logic.timers.remove(timer) {
            return Err(Error::WrongKind {
                node: timer,
                expected: "a timer",
            });
        }
        self.layer.graph.remove_node(timer);
        Ok(())
    }

    /// Disables a body (or enables it again) without deallocating it, as Rapier's
    /// `RigidBody::set_enabled(false)` but guarded (the paper's *passive* body, §3.2): it
    /// keeps its node, handle and user data, but takes part in nothing. Rapier's enabled
    /// flag is cleared in the pre-step, its edges end at the next analysis, and no
    /// event names it while passive. Its impulse joints are disabled while it is
    /// passive (`JointEnabled::Disabled`), joints added later included, and enabled
    /// again in the pre-step once both their bodies are active: Rapier 0.36 panics on an
    /// enabled joint between a disabled body and a fixed or disabled one, and its own
    /// `DisabledByAttachedBody` marks are undone whenever the other body is inserted or
    /// enabled. A joint the user disabled stays disabled. The guard runs in the
    /// layer's pre-step: a Rapier step the layer does not see (the user's own
    /// `world.step()`) has none, and a joint added to a passive body just before it
    /// makes Rapier panic as it would without the layer. O(1).
    ///
    /// # Errors
    /// - [`Error::UnknownBody`] for a body `bodies` lacks (removed: at once, as every
    ///   call that takes the world answers), [`Error::UnseenBody`] for one inserted
    ///   since the last step, [`Error::ForeignWorld`] for a set of another world;
    /// - [`Error::Unsupported`] for `disabled = true` on a dynamic multibody member (a
    ///   `Link` node at the last analysis): Rapier 0.36 does not carry a disabled
    ///   multibody member and panics in its next step. The body is left as it is.
    ///
    /// The pre-step checks again what the world holds by then: a queued change for a
    /// body that became a dynamic multibody member meanwhile is refused, and a passive
    /// body that became one is made active again. Both are reported by
    /// [`LayerLogic::refusals`] after that pre-step.
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::ContactLayer;
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
    /// let (ball, _) = world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
    ///     ColliderBuilder::ball(0.5),
    /// );
    /// let mut layer = ContactLayer::new();
    /// layer.step(&mut world);
    /// layer.logic_mut().set_body_disabled(&world.bodies, ball, true).unwrap();
    /// layer.step(&mut world);
    /// let node = layer.node_of_body(&world.bodies, ball).unwrap(); // same node, same handle
    /// assert!(layer.graph().node(node).unwrap().is_body_disabled());
    /// assert_eq!(layer.graph().node(node).unwrap().degree(), 0);
    /// ```
    pub fn set_body_disabled(
        &mut self,
        bodies: &RigidBodySet,
        body: RigidBodyHandle,
        disabled: bool,
    ) -> Result<()> {
        let node = self.layer.node_of_body(bodies, body)?;
        if disabled && self.layer.graph.node(node).map(|n| n.kind()) == Some(NodeKind::Link) {
            return Err(Error::Unsupported {
                what: "set_body_disabled(true) on a multibody link",
                reason: "Rapier 0.36 panics in its next step on a disabled multibody \
                         root while its links are enabled, and does not disable a \
                         multibody with its members",
            });
        }
        self.layer.logic.queue_passive(body, node, disabled);
        Ok(())
    }

    /// Declares bodies rigidly attached by the user (not by Rapier joints) as a
    /// `Composite` node with structural edges to them: contact groups then treat them as
    /// one. Returns the composite's node (its handle for [`Self::remove_composite`]).
    /// Members must be dynamic bodies of `world` the layer has seen; errors, with
    /// nothing changed: `Err(ForeignWorld)`, `Err(UnknownBody)` for a body the world
    /// lacks, `Err(UnseenBody)` for one inserted since the last step, `Err(WrongKind)`
    /// for a body that is not dynamic, `Err(InvalidParameter)` for no body. The node
    /// form is [`Self::declare_composite_nodes`]. O(members).
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::ContactLayer;
    ///
    /// let mut world = PhysicsWorld::new();
    /// let a = world.insert(RigidBodyBuilder::dynamic(), ColliderBuilder::ball(0.5)).0;
    /// let b = world.insert(
    ///     RigidBodyBuilder::dynamic().translation(Vector::new(5.0, 0.0, 0.0)),
    ///     ColliderBuilder::ball(0.5),
    /// ).0;
    /// let mut layer = ContactLayer::new();
    /// layer.step(&mut world);
    /// layer.logic_mut().declare_composite(&world, &[a, b]).unwrap();
    /// layer.step(&mut world);
    /// assert_eq!(layer.group_of_body(&world.bodies, a).unwrap().len(), 2, "one group through the composite");
    /// ```
    pub fn declare_composite<'w>(
        &mut self,
        world: impl Into<WorldView<'w>>,
        bodies: &[RigidBodyHandle],
    ) -> Result<NodeId> {
        let view = world.into();
        let nodes = self.layer.nodes_of_members(&view, bodies)?;
        self.declare_composite_nodes(&nodes)
    }

    /// [`Self::declare_composite`] by nodes: members must be live dynamic bodies
    /// (`Dynamic`) as of the last analysed step, else an error (`Err(StaleNode)`,
    /// `Err(WrongKind)`) and nothing changes. O(members).
    ///
    pub fn declare_composite_nodes(&mut self, bodies: &[NodeId]) -> Result<NodeId> {
        if bodies.is_empty() {
            return Err(Error::InvalidParameter {
                name: "bodies",
                reason: "a composite needs at least one body".into(),
            });
        }
        for &b in bodies {
            let kind = self.layer.graph.try_node(b)?.kind();
            if kind != NodeKind::Dynamic {
                return Err(Error::WrongKind {
                    node: b,
                    expected: "a dynamic rigid body",
                });
            }
        }
        let serial = self.layer.logic.serial();
        let node = self
            .layer
            .graph
            .add_node(NodeKind::Composite, NodeSource::Layer(serial));
        for &b in bodies {
            self.layer.graph.ensure_edge(
                node,
                b,
                EdgeKind::Structural,
                self.layer.coherence.step(),
            );
            self.layer.groups.disturb(&mut self.layer.graph, b);
        }
        self.layer.logic.declared.insert(node, bodies.to_vec());
        Ok(node)
    }

    /// Removes a declared composite (not one derived from joints); its bodies are
    /// regrouped at the next analysis. O(members).
    pub fn remove_composite(&mut self, composite: NodeId) -> Result<()> {
        self.layer.graph.try_node(composite)?;
        let members = self
            .layer
            .logic
            .declared
            .remove(&composite)
            .ok_or(Error::WrongKind {
                node: composite,
                expected: "a declared composite",
            })?;
        if let Some(g) = self.layer.graph.node(composite).and_then(|n| n.group()) {
            self.layer.groups.dissolve(&mut self.layer.graph, g);
        }
        self.layer.graph.remove_node(composite);
        for b in members {
            self.layer.groups.disturb(&mut self.layer.graph, b);
        }
        Ok(())
    }

    /// Opt-in: widens the collision types of sensor colliders to all body-type pairs,
    /// so that triggers on fixed, kinematic and dynamic bodies see bodies of every type
    /// (the paper's trigger volumes, §3.2), or leaves sensors as the user built them
    /// (`false`, the default: a trigger then sees what Rapier's own sensor pairs give,
    /// by default a sensor sees dynamic bodies only, or any body if it is carried by a
    /// dynamic one). Set it before the first step.
    ///
    /// What it changes for the user: the sensors' `active_collision_types()` read the
    /// widened types while the layer is attached (`detach` gives the user's back, and
    /// so does switching it off), and Rapier reports more sensor pairs; a user's own
    /// event handler composed with
    /// [`ContactLayer::event_handler_with`] still receives only the sensor events the user's
    /// own types give; one wired by hand around [`ContactLayer::event_handler`] must check
    /// [`LayerAnalysis::user_event_filter`](super::LayerAnalysis::user_event_filter) (no other composition is supported). Sensors never
    /// push bodies, but widening is not observe-only: a widened sensor pairs with the
    /// kinematic bodies inside it, which keeps them awake where plain Rapier lets them
    /// sleep, and widening a sensor Rapier has already stepped makes Rapier evaluate
    /// its pairs again, which wakes the bodies it touches (so trajectories can part
    /// from plain Rapier's). A second layer on the same world sees one layer's
    /// widening as a sensor changed in place (call its `request_full_sync`).
    ///
    /// Widening happens in the pre-step before a sensor's first Rapier step. Rapier
    /// pairs colliders that do not move only when they appear, so a sensor that was
    /// stepped before the layer saw it does not see fixed bodies already inside it;
    /// attach the layer before the first step, or build such sensors with
    /// `ActiveCollisionTypes::all()`. O(1).
    pub fn set_trigger_widening(&mut self, on: bool) {
        self.layer.logic.widen_sensors = on;
    }
}
