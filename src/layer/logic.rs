//! The logic layer on the contact layer: rules, timers, passive bodies, containers
//! and trigger widening (paper §3.2, Table 1).

use rapier3d::prelude::RigidBodyHandle;

use crate::graph::{Category, EdgeKind, NodeId, NodeKind, NodeSource};
use crate::logic::Rule;
use crate::{Error, Result};

use super::ContactLayer;

impl ContactLayer {
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

    /// Adds a rule: a `Rule` node with a logical edge to each body it names. Pairs it
    /// ignores stop interacting at the next step (their bodies are woken so that resting
    /// pairs are released too), and their edges end. Every named node must be live and
    /// a body or trigger, else an error and nothing changes. O(members).
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
    /// let (f, g) = (layer.node_of_body(floor).unwrap(), layer.node_of_body(ghost).unwrap());
    /// layer.add_rule(Rule::ignore_pair(f, g)).unwrap();
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
            self.check_rule_member(m)?;
        }
        let serial = self.logic.serial();
        let node = self
            .graph
            .add_node(NodeKind::Rule, NodeSource::Layer(serial));
        for &m in &members {
            self.graph
                .ensure_edge(node, m, EdgeKind::Logical, self.coherence.step());
        }
        self.logic.rules.insert(node, rule);
        self.logic.rules_changed(&members, &self.graph);
        Ok(node)
    }

    /// Removes a rule; the pairs it ignored interact again from the next step.
    pub fn remove_rule(&mut self, rule: NodeId) -> Result<Rule> {
        let kind = self.graph.try_node(rule)?.kind();
        if kind != NodeKind::Rule {
            return Err(Error::WrongKind {
                node: rule,
                expected: "a rule",
            });
        }
        let r = self
            .logic
            .rules
            .remove(&rule)
            .ok_or(Error::StaleNode(rule))?;
        self.graph.remove_node(rule);
        let members = r.members();
        self.logic.rules_changed(&members, &self.graph);
        Ok(r)
    }

    /// The rule of a rule node.
    pub fn rule(&self, node: NodeId) -> Option<&Rule> {
        self.logic.rules.get(&node)
    }

    /// The number of colliders carrying hook flags set by the layer (0 without rules).
    pub fn flagged_colliders(&self) -> usize {
        self.logic.flagged_colliders()
    }

    /// Adds a timer of `period` simulated seconds; it ticks `TimerTick` events (tick 1
    /// one period after now). A period that is not finite and positive is an error.
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::ContactLayer;
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.integration_parameters.dt = 0.01;
    /// let mut layer = ContactLayer::new();
    /// let timer = layer.add_timer(0.25).unwrap();
    /// for _ in 0..100 {
    ///     layer.step(&mut world);
    /// }
    /// assert_eq!(layer.timer_ticks(timer).unwrap(), 4);
    /// assert!(layer.add_timer(-1.0).is_err());
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
        let serial = self.logic.serial();
        let node = self
            .graph
            .add_node(NodeKind::Timer, NodeSource::Layer(serial));
        self.logic.timers.add(node, period);
        Ok(node)
    }

    /// Removes a timer.
    pub fn remove_timer(&mut self, timer: NodeId) -> Result<()> {
        let kind = self.graph.try_node(timer)?.kind();
        if kind != NodeKind::Timer || !self.logic.timers.remove(timer) {
            return Err(Error::WrongKind {
                node: timer,
                expected: "a timer",
            });
        }
        self.graph.remove_node(timer);
        Ok(())
    }

    /// The ticks a timer has fired so far.
    pub fn timer_ticks(&self, timer: NodeId) -> Result<u64> {
        self.graph.try_node(timer)?;
        self.logic.timers.ticks(timer).ok_or(Error::WrongKind {
            node: timer,
            expected: "a timer",
        })
    }

    /// The period of a timer.
    pub fn timer_period(&self, timer: NodeId) -> Result<f64> {
        self.graph.try_node(timer)?;
        self.logic.timers.period(timer).ok_or(Error::WrongKind {
            node: timer,
            expected: "a timer",
        })
    }

    /// Simulated seconds analysed while a timer existed (the timers' clock).
    pub fn simulated_time(&self) -> f64 {
        self.logic.timers.time()
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
    /// - [`Error::UnknownBody`] for a body without node (removed, or not analysed yet);
    /// - [`Error::Unsupported`] for `disabled = true` on a dynamic multibody member (a
    ///   `Link` node at the last analysis): Rapier 0.36 does not carry a disabled
    ///   multibody member and panics in its next step. The body is left as it is.
    ///
    /// The pre-step checks again what the world holds by then: a queued change for a
    /// body that became a dynamic multibody member meanwhile is refused, and a passive
    /// body that became one is made active again. Both are reported by
    /// [`Self::refusals`] after that pre-step.
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
    /// layer.set_body_disabled(ball, true).unwrap();
    /// layer.step(&mut world);
    /// let node = layer.node_of_body(ball).unwrap(); // same node, same handle
    /// assert!(layer.graph().node(node).unwrap().is_body_disabled());
    /// assert_eq!(layer.graph().node(node).unwrap().degree(), 0);
    /// ```
    pub fn set_body_disabled(&mut self, body: RigidBodyHandle, disabled: bool) -> Result<()> {
        let node = self.graph.try_node_of_body(body)?;
        if disabled && self.graph.node(node).map(|n| n.kind()) == Some(NodeKind::Link) {
            return Err(Error::Unsupported {
                what: "set_body_disabled(true) on a multibody link",
                reason: "Rapier 0.36 panics in its next step on a disabled multibody \
                         root while its links are enabled, and does not disable a \
                         multibody with its members",
            });
        }
        self.logic.queue_passive(body, node, disabled);
        Ok(())
    }

    /// Renamed to [`Self::set_body_disabled`] (Rapier's word for a body out of the
    /// simulation is *disabled*); forwards to it.
    #[deprecated(since = "0.2.0", note = "renamed to set_body_disabled, Rapier's name")]
    pub fn set_passive(&mut self, body: RigidBodyHandle, passive: bool) -> Result<()> {
        self.set_body_disabled(body, passive)
    }

    /// What the last pre-step refused or undid because Rapier 0.36 would panic on it,
    /// each with the body and an [`Error::Unsupported`] saying why: a queued
    /// [`Self::set_body_disabled`] of a body that had become a dynamic multibody member, or a
    /// passive body that the user joined to a multibody (made active again). Empty
    /// almost always; cleared by every pre-step. O(1).
    pub fn refusals(&self) -> &[(RigidBodyHandle, Error)] {
        &self.logic.refusals
    }

    /// Declares bodies rigidly attached by the user (not by Rapier joints) as a
    /// `Composite` node with structural edges to them: contact groups then treat them as
    /// one. Members must be live dynamic bodies (`Dynamic`), else an error. O(members).
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
    /// let (na, nb) = (layer.node_of_body(a).unwrap(), layer.node_of_body(b).unwrap());
    /// layer.declare_composite(&[na, nb]).unwrap();
    /// layer.step(&mut world);
    /// let group = |n| layer.graph().node(n).unwrap().group();
    /// assert_eq!(group(na), group(nb), "one group through the composite");
    /// ```
    pub fn declare_composite(&mut self, bodies: &[NodeId]) -> Result<NodeId> {
        if bodies.is_empty() {
            return Err(Error::InvalidParameter {
                name: "bodies",
                reason: "a composite needs at least one body".into(),
            });
        }
        for &b in bodies {
            let kind = self.graph.try_node(b)?.kind();
            if kind != NodeKind::Dynamic {
                return Err(Error::WrongKind {
                    node: b,
                    expected: "a dynamic rigid body",
                });
            }
        }
        let serial = self.logic.serial();
        let node = self
            .graph
            .add_node(NodeKind::Composite, NodeSource::Layer(serial));
        for &b in bodies {
            self.graph
                .ensure_edge(node, b, EdgeKind::Structural, self.coherence.step());
            self.groups.disturb(&mut self.graph, b);
        }
        self.logic.declared.insert(node, bodies.to_vec());
        Ok(node)
    }

    /// Removes a declared composite (not one derived from joints).
    pub fn remove_composite(&mut self, composite: NodeId) -> Result<()> {
        self.graph.try_node(composite)?;
        let members = self
            .logic
            .declared
            .remove(&composite)
            .ok_or(Error::WrongKind {
                node: composite,
                expected: "a declared composite",
            })?;
        if let Some(g) = self.graph.node(composite).and_then(|n| n.group()) {
            self.groups.dissolve(&mut self.graph, g);
        }
        self.graph.remove_node(composite);
        for b in members {
            self.groups.disturb(&mut self.graph, b);
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
    /// [`Self::event_handler_with`] still receives only the sensor events the user's
    /// own types give; one wired by hand around [`Self::event_handler`] must check
    /// [`Self::user_event_filter`] (no other composition is supported). Sensors never
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
    /// `ActiveCollisionTypes::all()`.
    pub fn set_trigger_widening(&mut self, on: bool) {
        self.logic.widen_sensors = on;
    }

    /// The rules in force (for validation).
    pub(crate) fn rule_table(&self) -> &crate::logic::RuleTable {
        self.logic.hooks.table()
    }
}
