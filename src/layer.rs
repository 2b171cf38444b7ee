//! The layer a Rapier user adds: one call per step keeps the contact graph, the marks
//! and the contact groups in step with the world.
//!
//! # Example
//! ```
//! use rapier3d::prelude::*;
//! use rapier_contact_graph::{ContactLayer, NodeKind};
//!
//! let mut world = PhysicsWorld::new();
//! world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
//! let (ball, _) = world.insert(
//!     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.2, 0.0)),
//!     ColliderBuilder::ball(0.5),
//! );
//! let mut layer = ContactLayer::new();
//! for _ in 0..60 {
//!     layer.step(&mut world);
//! }
//! let node = layer.graph().try_node_of_body(ball).unwrap();
//! assert_eq!(layer.graph().node(node).unwrap().kind(), NodeKind::Rigid);
//! assert!(layer.is_supported(node).unwrap(), "the ball rests on the ground");
//! layer.validate(&world).unwrap();
//! ```

use rapier3d::prelude::{ColliderHandle, PhysicsWorld, RigidBodyHandle};

use crate::coherence::{Coherence, RemovedNode, WalkCounters};
use crate::graph::{ContactGraph, Edge, EdgeId, NodeId, NodeKind};
use crate::groups::{GroupStats, Groups};
use crate::{Result, WorldView};

/// Statistics of one step.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StepStats {
    /// The step's index (1 for the first analysed step).
    pub step: u64,
    /// Live nodes.
    pub nodes: usize,
    /// Live edges.
    pub edges: usize,
    /// Bodies awake after the step.
    pub awake_bodies: usize,
    /// What the pair walk read.
    pub walk: WalkCounters,
    /// Group statistics.
    pub groups: GroupStats,
}

/// The contact graph layer.
///
/// Observe-only: it sets no hook or event flag on any collider and passes Rapier no
/// hooks, so attaching it changes nothing in Rapier's results (tested bit for bit).
#[derive(Clone, Debug, Default)]
pub struct ContactLayer {
    graph: ContactGraph,
    groups: Groups,
    coherence: Coherence,
    stats: StepStats,
    /// The gravity of the last analysed world.
    gravity: rapier3d::math::Vector,
}

impl ContactLayer {
    /// A layer with an empty graph; the first update fills it from the world.
    pub fn new() -> Self {
        Self::default()
    }

    /// Runs one Rapier step on `world`, then the analysis ([`Self::analyze`]).
    ///
    /// Cost: Rapier's step, plus the analysis: O(pairs of awake bodies + members of the
    /// rebuilt groups), plus O(bodies + colliders) on a step where their count changed.
    pub fn step(&mut self, world: &mut PhysicsWorld) -> StepStats {
        world.step();
        self.analyze(WorldView::from(&*world))
    }

    /// The post-step analysis alone, for users who step Rapier themselves (their own
    /// `PhysicsPipeline::step` or `PhysicsWorld::step_with_events`). Call it once after
    /// every step.
    pub fn analyze(&mut self, view: WorldView) -> StepStats {
        self.gravity = view.gravity;
        self.coherence
            .update(&mut self.graph, &mut self.groups, &view);
        self.groups
            .rebuild(&mut self.graph, self.coherence.step(), &|g, n| {
                g.node(n).is_some_and(|n| n.kind().is_insulator())
            });
        self.stats = StepStats {
            step: self.coherence.step(),
            nodes: self.graph.node_count(),
            edges: self.graph.edge_count(),
            awake_bodies: view.islands.num_active_bodies(),
            walk: self.coherence.counters(),
            groups: self.groups.stats(),
        };
        self.stats
    }

    /// The contact graph.
    pub fn graph(&self) -> &ContactGraph {
        &self.graph
    }

    /// The contact groups.
    pub fn groups(&self) -> &Groups {
        &self.groups
    }

    /// The statistics of the last step.
    pub fn stats(&self) -> StepStats {
        self.stats
    }

    /// The index of the last analysed step.
    pub fn current_step(&self) -> u64 {
        self.coherence.step()
    }

    /// Edges refreshed in the last step (their marks are valid), in the deterministic
    /// order of [`Coherence::touched_edges`].
    pub fn touched_edges(&self) -> impl Iterator<Item = (EdgeId, &Edge)> + '_ {
        self.coherence
            .touched_edges()
            .iter()
            .filter_map(|&id| Some((id, self.graph.edge(id)?)))
    }

    /// Edges removed in the last step with a node that left the world, each with a
    /// final `Vanished` mark for the state it had.
    pub fn removed_edges(&self) -> &[Edge] {
        self.coherence.removed_edges()
    }

    /// Nodes removed in the last step.
    pub fn removed_nodes(&self) -> &[RemovedNode] {
        self.coherence.removed_nodes()
    }

    /// Counters and lists of the last analysis.
    pub fn coherence(&self) -> &Coherence {
        &self.coherence
    }

    /// The analysis state, for its settings ([`Coherence::set_scan_policy`], ...).
    pub fn coherence_mut(&mut self) -> &mut Coherence {
        &mut self.coherence
    }

    /// Turns the per-edge contact details on (the default) or off; see
    /// [`Coherence::set_contact_details`]. A scene that needs only the marks, the
    /// touching state and the groups pays less per contact pair with them off.
    /// Support queries need the details (the contact normals).
    pub fn set_contact_details(&mut self, on: bool) {
        self.coherence.set_contact_details(on);
    }

    /// Asks for a full scan of bodies and colliders at the next update. Needed only
    /// after changing a *sleeping or fixed* body in place in a way Rapier does not
    /// wake it for (e.g. its type); adding and removing bodies is detected.
    pub fn request_full_sync(&mut self) {
        self.coherence.request_full_sync();
    }

    /// The node of a body. O(1).
    pub fn node_of_body(&self, body: RigidBodyHandle) -> Result<NodeId> {
        self.graph.try_node_of_body(body)
    }

    /// The node of a collider: its parent body's node, or its own for a parentless
    /// collider. O(1).
    pub fn node_of_collider(
        &self,
        world: &PhysicsWorld,
        collider: ColliderHandle,
    ) -> Result<NodeId> {
        let c = world
            .colliders
            .get(collider)
            .ok_or(crate::Error::UnknownCollider(collider))?;
        match c.parent() {
            Some(b) => self.graph.try_node_of_body(b),
            None => self
                .graph
                .node_of_static_collider(collider)
                .ok_or(crate::Error::UnknownCollider(collider)),
        }
    }

    /// Whether a node is supported against the gravity of the last analysed world
    /// (see [`ContactGraph::try_is_supported`]; any upward push counts). O(degree).
    pub fn is_supported(&self, node: NodeId) -> Result<bool> {
        self.graph.try_is_supported(node, self.gravity, 0.0)
    }

    /// Whether `node` is of a given kind; an error for a stale id. O(1).
    pub fn kind_of(&self, node: NodeId) -> Result<NodeKind> {
        Ok(self.graph.try_node(node)?.kind())
    }

    /// Checks every invariant: the graph's own ([`ContactGraph::validate`]), the
    /// groups', and the graph against the world — one node per body and per static
    /// collider with the right kind, an edge with proximity for every Rapier pair of
    /// two nodes that Table 2 allows, the touching state equal to Rapier's, and no
    /// proximate edge without its Rapier pair. O(nodes + edges + Rapier pairs).
    pub fn validate(&self, world: &PhysicsWorld) -> Result<()> {
        crate::validate::validate_layer(self, &WorldView::from(world))
    }

    /// [`Self::validate`] for a world given by its parts.
    pub fn validate_view(&self, view: &WorldView) -> Result<()> {
        crate::validate::validate_layer(self, view)
    }
}
