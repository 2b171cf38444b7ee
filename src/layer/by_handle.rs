//! Queries by Rapier handle: what touches a body, what holds it up, what is inside a
//! sensor, which sensors a body is in, and a body's contact group, each answered with
//! Rapier's own handles (node ids stay for what has no Rapier handle: rules, timers,
//! containers).
//!
//! Each query takes the set the handle belongs to, so that it can tell a body the layer
//! has not seen yet (inserted since the last step: no contacts yet, an empty answer)
//! from one that is not in the world (removed: an error), and a set of another world
//! from the one the layer analysed (`Error::ForeignWorld`, told in O(1); its docs say
//! exactly what the look can and cannot tell). The answers are as of the last analysed
//! step. Costs are stated on each method; `degree` is the number of edges of the
//! body's (or trigger's) node.

use rapier3d::geometry::ColliderSet;
use rapier3d::prelude::{ColliderHandle, RigidBodyHandle, RigidBodySet};

use crate::coherence::details::read_details;
use crate::graph::{ContactCache, EdgeKind, NodeId, NodeSource};
use crate::{ContactLayer, Error, Result, WorldView};

/// Something a body touches or a sensor holds, by Rapier handle: a body, or a
/// parentless collider (static geometry).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Touching {
    /// A rigid body (dynamic, kinematic or fixed).
    Body(RigidBodyHandle),
    /// A collider without a parent body.
    Collider(ColliderHandle),
}

impl ContactLayer {
    /// The node of a body in the world, `None` if the layer has not seen it yet; an
    /// error if the world has no such body, or `bodies` is another world's. O(1).
    pub(super) fn node_of_live_body(
        &self,
        bodies: &RigidBodySet,
        body: RigidBodyHandle,
    ) -> Result<Option<NodeId>> {
        if !self.coherence.bodies_match(&self.graph, bodies) {
            return Err(Error::ForeignWorld);
        }
        if !bodies.contains(body) {
            return Err(Error::UnknownBody(body));
        }
        Ok(self.graph.node_of_body(body))
    }

    /// `Err(ForeignWorld)` unless both of the world's sets can be those the layer last
    /// analysed (see [`Error::ForeignWorld`]). O(1).
    pub(crate) fn check_world(&self, view: &WorldView) -> Result<()> {
        if self.coherence.world_matches(&self.graph, view) {
            Ok(())
        } else {
            Err(Error::ForeignWorld)
        }
    }

    /// The nodes a node's geometric edges reach while they overlap (a trigger's
    /// contents, or the triggers a body is in), sorted. O(degree).
    fn inside_of(&self, n: NodeId) -> Vec<NodeId> {
        sorted(
            self.graph
                .neighbors(n)
                .filter(|(_, _, e)| e.kind() == EdgeKind::Geometric && e.is_proximate())
                .map(|(m, _, _)| m),
        )
    }

    /// The bodies and static colliders among `nodes`, in node order.
    fn touching_of(&self, nodes: Vec<NodeId>) -> Vec<Touching> {
        nodes
            .into_iter()
            .filter_map(|m| match self.graph.node(m)?.source() {
                NodeSource::Body(h) => Some(Touching::Body(h)),
                NodeSource::StaticCollider(c) => Some(Touching::Collider(c)),
                _ => None,
            })
            .collect()
    }

    /// The bodies and static colliders touching `body` (Rapier's contact pairs with
    /// an active contact), sorted by node. Empty for a body inserted since the last
    /// step; `Err(UnknownBody)` for a body `bodies` lacks, `Err(ForeignWorld)` for a set
    /// of another world ([`Error::ForeignWorld`]). O(degree).
    pub fn touching_body(
        &self,
        bodies: &RigidBodySet,
        body: RigidBodyHandle,
    ) -> Result<Vec<Touching>> {
        let Some(n) = self.node_of_live_body(bodies, body)? else {
            return Ok(Vec::new());
        };
        Ok(self.touching_of(sorted(self.graph.touching(n))))
    }

    /// What holds `body` up against the gravity of the last analysed world: the
    /// bodies and static colliders touching it through a contact whose normal pushes
    /// it upwards by more than `min_cos` of the unit push (0.0: any upward push),
    /// sorted by node. Empty if nothing does, or for a body inserted since the last
    /// step. The normals are read from Rapier's narrow phase (see
    /// [`Self::contact_details`]), so the answer needs neither proximity tracking nor
    /// the per-edge contact details. `world` is a `&PhysicsWorld` or a [`WorldView`]
    /// of one's own sets. `Err(UnknownBody)` for a body the world lacks,
    /// `Err(ForeignWorld)` for another world ([`Error::ForeignWorld`]),
    /// `Err(NonFinite)` for a NaN `min_cos`. O(degree × the body's contact pairs).
    pub fn supports_of_body<'w>(
        &self,
        world: impl Into<WorldView<'w>>,
        body: RigidBodyHandle,
        min_cos: f32,
    ) -> Result<Vec<Touching>> {
        if min_cos.is_nan() {
            return Err(Error::NonFinite("min_cos"));
        }
        let view = world.into();
        self.check_world(&view)?;
        let Some(n) = self.node_of_live_body(view.bodies, body)? else {
            return Ok(Vec::new());
        };
        let Some(up) = self.up() else {
            return Ok(Vec::new());
        };
        let supports = self
            .graph
            .touching(n)
            .filter(|&m| self.pushes_up(&view, n, m, up, min_cos));
        Ok(self.touching_of(sorted(supports)))
    }

    /// Whether `body` is grounded: held up against the gravity of the last analysed
    /// world by ground (a fixed or kinematic body, or a parentless collider) through
    /// a chain of supports. A support of a body is what [`Self::supports_of_body`]
    /// lists with `min_cos = 0.0`: something touching it through a contact whose
    /// normal pushes it upwards at all. The chain goes down from `body` through the
    /// dynamic bodies supporting it, theirs, and so on, until one rests on ground: a
    /// box on a box on the floor is grounded; a ball in the air, a box leaning only
    /// sideways on a wall, or a stack resting on a body that is itself in the air, is
    /// not. A fixed or kinematic `body` is grounded only if ground supports it in
    /// turn (a floor is not).
    ///
    /// Answers under either tracking, the default (touching tracking) included: the
    /// normals are read from Rapier's narrow phase (a body held by the speed-ups
    /// answers with the contacts it was held with). `Ok(false)` for a body inserted
    /// since the last step, and under zero or non-finite gravity. `world` is a
    /// `&PhysicsWorld` or a [`WorldView`] of one's own sets. `Err(UnknownBody)` for a
    /// body the world lacks (removed), `Err(ForeignWorld)` for another world
    /// ([`Error::ForeignWorld`]). O(Σ degree × contact pairs over the bodies of the
    /// chain), at most O(the touching edges of `body`'s contact group × their pairs).
    ///
    /// # Example
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier_contact_graph::ContactLayer;
    ///
    /// let mut world = PhysicsWorld::new();
    /// world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
    /// let cube = |y| (RigidBodyBuilder::dynamic().translation(Vector::new(0.0, y, 0.0)), ColliderBuilder::cuboid(0.5, 0.5, 0.5));
    /// let (lower, _) = { let (b, c) = cube(1.0); world.insert(b, c) };
    /// let (upper, _) = { let (b, c) = cube(2.0); world.insert(b, c) };
    /// let (flying, _) = { let (b, c) = cube(20.0); world.insert(b, c) };
    /// let mut layer = ContactLayer::new(); // touching tracking, the default
    /// for _ in 0..30 {
    ///     layer.step(&mut world);
    /// }
    /// assert!(layer.is_grounded(&world, lower).unwrap());
    /// assert!(layer.is_grounded(&world, upper).unwrap(), "through the lower box");
    /// assert!(!layer.is_grounded(&world, flying).unwrap());
    /// ```
    pub fn is_grounded<'w>(
        &self,
        world: impl Into<WorldView<'w>>,
        body: RigidBodyHandle,
    ) -> Result<bool> {
        let view = world.into();
        self.check_world(&view)?;
        let Some(start) = self.node_of_live_body(view.bodies, body)? else {
            return Ok(false);
        };
        let Some(up) = self.up() else {
            return Ok(false);
        };
        let mut seen = std::collections::HashSet::from([start]);
        let mut chain = vec![start];
        while let Some(n) = chain.pop() {
            for m in self.graph.touching(n) {
                if seen.contains(&m) || !self.pushes_up(&view, n, m, up, 0.0) {
                    continue;
                }
                let Some(kind) = self.graph.node(m).map(|x| x.kind()) else {
                    continue;
                };
                if kind.is_insulator() {
                    return Ok(true);
                }
                if kind.is_simulated() {
                    seen.insert(m);
                    chain.push(m);
                }
            }
        }
        Ok(false)
    }

    /// The unit vector against the gravity of the last analysed world; `None` under
    /// zero or non-finite gravity. O(1).
    fn up(&self) -> Option<rapier3d::math::Vector> {
        let scale = self.gravity.abs().max_element();
        (scale != 0.0 && scale.is_finite()).then(|| -(self.gravity / scale).normalize())
    }

    /// Whether `m` touches `n` through a contact whose normal pushes `n` along `up` by
    /// more than `min_cos` (the normal points from `n` towards `m`: it pushes `n`
    /// along -normal). O(the contact pairs of the node with fewer colliders).
    fn pushes_up(
        &self,
        view: &WorldView,
        n: NodeId,
        m: NodeId,
        up: rapier3d::math::Vector,
        min_cos: f32,
    ) -> bool {
        self.details_from(view, n, m)
            .is_some_and(|c| c.touching && (-c.normal).dot(up) > min_cos)
    }

    /// The details of the contact between `n` and `m` read from Rapier, with the
    /// normal and the push pointing from `n` towards `m` (Rapier's pair orientation
    /// follows the edge's, from the smaller slot to the larger). O(the contact pairs
    /// of the colliders of the node with fewer colliders).
    fn details_from(&self, view: &WorldView, n: NodeId, m: NodeId) -> Option<ContactCache> {
        // A held body's contact with what stands still: Rapier keeps the pair without
        // contacts; the edge keeps the contact it froze with (`graph/frozen.rs`).
        let frozen = self
            .graph
            .edge_by_key(crate::graph::PairKey::of(n, m))
            .and_then(|e| self.graph.edge(e))
            .filter(|e| self.graph.is_frozen(e))
            .map(|e| e.cache().clone());
        frozen
            .or_else(|| read_details(&self.graph, view, n, m))
            .map(|mut c| {
                if n.index() > m.index() {
                    c.normal = -c.normal;
                    c.push = -c.push;
                }
                c
            })
    }

    /// The contact between `body` and `other` as Rapier's narrow phase holds it now:
    /// closest distance (negative: penetration), deepest penetration, solver contact
    /// count, the sum of normal impulses, and the deepest contact's normal and the
    /// impulses' resultant (`push`), both pointing from `body` towards `other` (so
    /// `-push` is what `other` did to `body`): the crate's one normal convention
    /// ([`crate::events`], "Normals"), so `contact_details(w, b1, b2)` has the normal
    /// of the events naming `b1` as `body1` and `-normal` asked the other way round.
    /// Read on demand, whatever the tracking and whether per-edge details are kept.
    /// `Ok(None)` when Rapier has no contact pair between them (they are not near) or
    /// the layer has not seen one of them yet. `world` is a `&PhysicsWorld` or a
    /// [`WorldView`] of one's own sets. `Err(UnknownBody)` / `Err(UnknownCollider)` for
    /// a handle the world lacks, `Err(ForeignWorld)` for another world
    /// ([`Error::ForeignWorld`]). O(the contact pairs of `body`'s colliders).
    pub fn contact_details<'w>(
        &self,
        world: impl Into<WorldView<'w>>,
        body: RigidBodyHandle,
        other: Touching,
    ) -> Result<Option<ContactCache>> {
        let view = world.into();
        self.check_world(&view)?;
        let Some(n) = self.node_of_live_body(view.bodies, body)? else {
            return Ok(None);
        };
        let m = match other {
            Touching::Body(h) => self.node_of_live_body(view.bodies, h)?,
            Touching::Collider(c) => {
                if !view.colliders.contains(c) {
                    return Err(Error::UnknownCollider(c));
                }
                self.graph.node_of_static_collider(c)
            }
        };
        let Some(m) = m else {
            return Ok(None);
        };
        Ok(self.details_from(&view, n, m))
    }

    /// The bodies and static colliders inside a sensor collider (their colliders
    /// intersect it), sorted by node. Empty for a sensor inserted since the last step;
    /// `Err(UnknownCollider)` for a collider `colliders` lacks, `Err(NotASensor)` for
    /// one that is not a sensor (a collider of a body or static geometry), `Err(ForeignWorld)` for a set of another world
    /// ([`Error::ForeignWorld`]). O(degree of its trigger).
    pub fn sensor_contents(
        &self,
        colliders: &ColliderSet,
        sensor: ColliderHandle,
    ) -> Result<Vec<Touching>> {
        if !self.coherence.colliders_match(&self.graph, colliders) {
            return Err(Error::ForeignWorld);
        }
        match colliders.get(sensor) {
            None => return Err(Error::UnknownCollider(sensor)),
            Some(c) if !c.is_sensor() => return Err(Error::NotASensor(sensor)),
            Some(_) => {}
        }
        let Some(t) = self.graph.node_of_sensor(sensor) else {
            return Ok(Vec::new());
        };
        Ok(self.touching_of(self.inside_of(t)))
    }

    /// The sensor colliders `body` is inside (one of its colliders intersects them),
    /// sorted by node. Empty for a body inserted since the last step;
    /// `Err(UnknownBody)` for a body `bodies` lacks, `Err(ForeignWorld)` for a set of
    /// another world ([`Error::ForeignWorld`]). O(degree).
    pub fn sensors_containing(
        &self,
        bodies: &RigidBodySet,
        body: RigidBodyHandle,
    ) -> Result<Vec<ColliderHandle>> {
        let Some(n) = self.node_of_live_body(bodies, body)? else {
            return Ok(Vec::new());
        };
        Ok(self
            .inside_of(n)
            .into_iter()
            .filter_map(|m| match self.graph.node(m)?.source() {
                NodeSource::Sensor(c) => Some(c),
                _ => None,
            })
            .collect())
    }

    /// The bodies of `body`'s contact group (paper §4: bodies connected through
    /// touching contacts and joints, fixed and kinematic bodies insulating), itself
    /// included, in the group's member order (deterministic, not sorted). Empty for a
    /// body in no group (fixed, kinematic, passive, inserted since the last step, or
    /// groups off); `Err(UnknownBody)` for a body `bodies` lacks, `Err(ForeignWorld)`
    /// for a set of another world ([`Error::ForeignWorld`]). While the group's
    /// split is deferred ([`crate::Groups::deferred`]) it may also hold bodies that no
    /// longer touch this one;
    /// [`LayerAnalysisMut::settle_groups`](super::LayerAnalysisMut::settle_groups)
    /// finishes the split. O(group
    /// size).
    pub fn group_of_body(
        &self,
        bodies: &RigidBodySet,
        body: RigidBodyHandle,
    ) -> Result<Vec<RigidBodyHandle>> {
        let Some(n) = self.node_of_live_body(bodies, body)? else {
            return Ok(Vec::new());
        };
        let Some(g) = self.graph.node(n).and_then(|x| x.group()) else {
            return Ok(Vec::new());
        };
        let Some(group) = self.groups.get(g) else {
            return Ok(Vec::new());
        };
        Ok(group
            .bodies
            .iter()
            .filter_map(|&m| self.graph.body_of(m))
            .collect())
    }
}

/// The nodes, sorted (queries answer in node order, which is deterministic).
fn sorted(nodes: impl Iterator<Item = NodeId>) -> Vec<NodeId> {
    let mut v: Vec<NodeId> = nodes.collect();
    v.sort_unstable();
    v
}
