//! Nodes: the entities of a scene (paper Table 1).
//!
//! One node per Rapier rigid body (its kind follows the body type and multibody
//! membership), one `Fixed` node per collider without a parent body (Rapier treats such
//! colliders as static geometry), and nodes for containers and logical entities.
//!
//! A node is a *persistent record*: it lives from the step its entity is seen until the
//! step its entity is gone. Per-step data (traversal stamps, awake flags) is kept in
//! the node for locality but is only meaningful for the step it was written in.

use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

use super::EdgeId;

/// The kinds of node of the paper's Table 1, as mapped onto Rapier (paper §2, Tables 1–2).
///
/// Body kinds take Rapier's names (`Dynamic`, `Fixed`, `Kinematic`; a sensor collider
/// is a `Sensor`); the paper's names (rigid, scripted, trigger volume) and letters are
/// in each variant's docs and in [`Self::letter`].
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum NodeKind {
    /// (R) a dynamic rigid body (the paper's *rigid* body; Rapier's
    /// `RigidBodyType::Dynamic`).
    Dynamic,
    /// (F) a fixed rigid body, or a collider without a parent body.
    Fixed,
    /// (S) a kinematic rigid body (the paper's *scripted* body; Rapier's
    /// kinematic body types).
    Kinematic,
    /// (L) a dynamic body that is a link of a Rapier multibody.
    Link,
    /// (C) a container of bodies rigidly attached.
    Composite,
    /// (M) a container of the links of one articulated mechanism.
    Multibody,
    /// (A) a user rule.
    Rule,
    /// (V) a sensor collider (the paper's *trigger volume*).
    Sensor,
    /// (T) a timer.
    Timer,
}

/// The three categories of Table 1.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Category {
    /// Bodies that interact physically: R, F, L, S.
    Physical,
    /// Containers of bodies: C, M.
    Container,
    /// Entities without physical influence: A, V, T.
    Logical,
}

impl NodeKind {
    /// The paper's symbol letter: R, F, L, S, C, M, A, V, T.
    pub const fn letter(self) -> char {
        match self {
            NodeKind::Dynamic => 'R',
            NodeKind::Fixed => 'F',
            NodeKind::Kinematic => 'S',
            NodeKind::Link => 'L',
            NodeKind::Composite => 'C',
            NodeKind::Multibody => 'M',
            NodeKind::Rule => 'A',
            NodeKind::Sensor => 'V',
            NodeKind::Timer => 'T',
        }
    }

    /// The category of the kind.
    pub const fn category(self) -> Category {
        match self {
            NodeKind::Dynamic | NodeKind::Fixed | NodeKind::Kinematic | NodeKind::Link => {
                Category::Physical
            }
            NodeKind::Composite | NodeKind::Multibody => Category::Container,
            NodeKind::Rule | NodeKind::Sensor | NodeKind::Timer => Category::Logical,
        }
    }

    /// Fixed and kinematic (the paper's scripted) bodies "behave as if they had infinite
    /// mass": they insulate contact groups (paper Fig. 8).
    pub const fn is_insulator(self) -> bool {
        matches!(self, NodeKind::Fixed | NodeKind::Kinematic)
    }

    /// Bodies moved by the solver: dynamic and link bodies.
    pub const fn is_simulated(self) -> bool {
        matches!(self, NodeKind::Dynamic | NodeKind::Link)
    }

    /// All kinds, in Table 1 order.
    pub const ALL: [NodeKind; 9] = [
        NodeKind::Dynamic,
        NodeKind::Fixed,
        NodeKind::Link,
        NodeKind::Kinematic,
        NodeKind::Composite,
        NodeKind::Multibody,
        NodeKind::Rule,
        NodeKind::Sensor,
        NodeKind::Timer,
    ];
}

/// What in the Rapier world (or in the layer) a node stands for.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum NodeSource {
    /// A rigid body.
    Body(RigidBodyHandle),
    /// A collider without a parent body (static geometry).
    StaticCollider(ColliderHandle),
    /// A sensor collider (a trigger volume).
    Sensor(ColliderHandle),
    /// A container derived from Rapier's joints.
    Container(ContainerSource),
    /// A node that only the layer knows (rules, timers, declared composites); the
    /// number is the layer's serial number for it.
    Layer(u64),
}

/// A node of the contact graph.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Node {
    pub(crate) kind: NodeKind,
    pub(crate) source: NodeSource,
    /// Incident edges, in insertion order.
    pub(crate) edges: Vec<EdgeId>,
    /// Awake in Rapier at the last update (dynamic or kinematic, not sleeping).
    pub(crate) awake: bool,
    /// The body's pose was not finite at the last update.
    pub(crate) non_finite: bool,
    /// The step of the last refresh of this node's state.
    pub(crate) seen_step: u64,
    /// Traversal stamp (per-step data).
    pub(crate) visit_stamp: u64,
    /// Index of the node's group in [`crate::Groups`] (per-step data for awake groups).
    pub(crate) group: Option<crate::GroupId>,
    /// The body is passive (disabled in Rapier): kept, but without edges.
    pub(crate) passive: bool,
    /// The step the node was created in.
    pub(crate) born_step: u64,
    /// For a trigger: the body carrying its sensor collider, if any.
    pub(crate) carrier: Option<RigidBodyHandle>,
    /// The sleep state last reported by a `FellAsleep` / `WokeUp` event (or the state
    /// the body was first seen in): events are sent only when it changes, so they
    /// alternate whatever happens in between (passive spells, fixation, retyping).
    pub(crate) reported_awake: Option<bool>,
    /// For a body: its number of colliders at the last full scan (a change refreshes
    /// the body: a fixed body losing or gaining a collider is otherwise never read).
    pub(crate) collider_count: u32,
    /// For a body: the signature of its collider list when last refreshed
    /// ([`crate::graph::mirror::colliders_sig`]; 0: not known yet).
    #[cfg_attr(feature = "serde", serde(default))]
    pub(crate) collider_sig: u64,
    /// For a body, under touching tracking: a signature of which of its colliders are
    /// disabled when last refreshed ([`crate::graph::mirror::disabled_sig`]; 0: none).
    /// Rapier drops a disabled collider's pairs and sends `Stopped` only for pairs
    /// that sent `Started`: a change re-counts the body's touching pairs.
    #[cfg_attr(feature = "serde", serde(default))]
    pub(crate) disabled_sig: u64,
    /// For a body, under touching tracking: a rescan counted a touching pair of it
    /// that sent no `Started` in that step (it may have begun before its colliders
    /// were flagged), so `disabled_sig` is kept for it. Conservative: never cleared.
    /// Only such bodies pay for the signature (one collider lookup per collider per
    /// refresh).
    #[cfg_attr(feature = "serde", serde(default))]
    pub(crate) pre_flag_touch: bool,
    /// For a body: held by the speed-ups' fixation (a fixed body in Rapier that the
    /// user made dynamic): its contacts with what stands still are frozen (see
    /// `graph/frozen.rs`).
    #[cfg_attr(feature = "serde", serde(default))]
    pub(crate) held: bool,
    /// The node's position in its group's member list (a hint checked on use;
    /// rebuilt on restore, see [`crate::Groups`]).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) group_slot: u32,
    /// How many of its edges are geometric (trigger volumes): under touching tracking
    /// only a body with one needs its edges looked at for one that vanished. Kept by
    /// the graph's edge insertion and removal; rebuilt on restore
    /// ([`crate::ContactGraph::recount_geometric`]).
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) geometric_edges: u32,
    /// Where Rapier kept what the node stands for when the layer last read it (see
    /// [`Storage`]). Addresses: not part of a snapshot.
    #[cfg_attr(feature = "serde", serde(skip))]
    pub(crate) storage: Storage,
}

/// Where Rapier keeps the objects a node stands for, as the layer last read them:
/// addresses that neither moving the world value nor the growth of Rapier's sets
/// changes (the body's collider list and a collider's shape are allocations of their
/// own), so that a set of another world, whose objects have the same handles, is told
/// from the analysed one (`Error::ForeignWorld`). Derived from the world like a lookup
/// cache: left out of snapshots and of `Debug`, and not carried to a copy of the graph
/// (a snapshot's state may be restored against another copy of the world); zero when
/// unknown, until the layer reads the object again.
#[derive(Default)]
pub(crate) struct Storage {
    /// A body's collider list: its address and length (0 without colliders).
    pub(crate) list: (usize, usize),
    /// One collider the node stands for (a body's first, a static collider, a
    /// sensor) and the address of its shape (0 when none).
    pub(crate) shape: (Option<rapier3d::prelude::ColliderHandle>, usize),
}

/// A copy knows nothing (see the type's docs).
impl Clone for Storage {
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl std::fmt::Debug for Storage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Storage")
    }
}

impl Storage {
    /// The shape address of a collider. O(1).
    pub(crate) fn shape_of(c: &rapier3d::geometry::Collider) -> usize {
        std::sync::Arc::as_ptr(&c.shared_shape().0) as *const () as usize
    }

    /// The address and length of a body's collider list (0 for an empty one, whose
    /// address means nothing). O(1).
    pub(crate) fn list_of(rb: &rapier3d::dynamics::RigidBody) -> (usize, usize) {
        let list = rb.colliders();
        if list.is_empty() {
            (0, 0)
        } else {
            (list.as_ptr() as usize, list.len())
        }
    }
}

impl Node {
    pub(crate) fn new(kind: NodeKind, source: NodeSource, born_step: u64) -> Self {
        Self {
            kind,
            source,
            edges: Vec::new(),
            awake: false,
            non_finite: false,
            seen_step: 0,
            visit_stamp: 0,
            group: None,
            passive: false,
            born_step,
            carrier: None,
            reported_awake: None,
            collider_count: 0,
            collider_sig: 0,
            disabled_sig: 0,
            pre_flag_touch: false,
            held: false,
            group_slot: 0,
            geometric_edges: 0,
            storage: Storage::default(),
        }
    }

    /// Held by the speed-ups' fixation (see `SpeedUps::hold`): a fixed body in
    /// Rapier that stands for a sleeping one; its contacts with what stands still are
    /// kept frozen ([`crate::ContactGraph::is_frozen`]). O(1).
    pub fn is_held(&self) -> bool {
        self.held
    }

    /// The node's kind.
    #[inline]
    pub fn kind(&self) -> NodeKind {
        self.kind
    }
    /// What the node stands for.
    #[inline]
    pub fn source(&self) -> NodeSource {
        self.source
    }
    /// The Rapier body of the node, if it is a body node.
    #[inline]
    pub fn body(&self) -> Option<RigidBodyHandle> {
        match self.source {
            NodeSource::Body(h) => Some(h),
            _ => None,
        }
    }
    /// The incident edges (both directions: edges are undirected). O(1).
    #[inline]
    pub fn edges(&self) -> &[EdgeId] {
        &self.edges
    }
    /// The number of incident edges.
    #[inline]
    pub fn degree(&self) -> usize {
        self.edges.len()
    }
    /// Whether the body was awake (moving, in Rapier's active set) at the last update.
    /// Always `false` for fixed bodies and non-body nodes.
    #[inline]
    pub fn is_awake(&self) -> bool {
        self.awake
    }
    /// Whether the body's pose was not finite at the last update. Such a body keeps its
    /// node and edges but takes part in no geometric test until its pose is finite again.
    #[inline]
    pub fn is_non_finite(&self) -> bool {
        self.non_finite
    }
    /// For a trigger node, the body carrying its sensor collider (`None` for a
    /// parentless sensor and for other nodes).
    #[inline]
    pub fn carrier(&self) -> Option<RigidBodyHandle> {
        self.carrier
    }
    /// The step the node was created in (0: before the first analysed step).
    #[inline]
    pub fn born_step(&self) -> u64 {
        self.born_step
    }
    /// Whether the body is disabled (the paper's *passive* body, §3.2: disabled in
    /// Rapier, by [`crate::LayerLogicMut::set_body_disabled`] or by the user): it keeps
    /// its node, handle and user data, but has no physical or geometric edge.
    #[inline]
    pub fn is_body_disabled(&self) -> bool {
        self.passive
    }
    /// The contact group the node is in since the last update (`None` for insulators,
    /// logical nodes and bodies not yet grouped).
    #[inline]
    pub fn group(&self) -> Option<crate::GroupId> {
        self.group
    }
}

/// What a container derived from Rapier's joints is keyed by.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ContainerSource {
    /// A Rapier multibody, keyed by its root body.
    Multibody(RigidBodyHandle),
    /// Bodies joined by impulse joints, not all fixed; keyed by the component's first
    /// body (smallest handle).
    Articulation(RigidBodyHandle),
    /// Bodies joined by fixed impulse joints only; keyed like an articulation.
    Composite(RigidBodyHandle),
}

impl ContainerSource {
    /// A total order key: variant, then the body's raw handle parts.
    fn order_key(self) -> (u8, u32, u32) {
        let (t, h) = match self {
            ContainerSource::Multibody(h) => (0, h),
            ContainerSource::Articulation(h) => (1, h),
            ContainerSource::Composite(h) => (2, h),
        };
        let (i, g) = h.into_raw_parts();
        (t, i, g)
    }
}

impl PartialOrd for ContainerSource {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        Some(self.cmp(other))
    }
}

impl Ord for ContainerSource {
    fn cmp(&self, other: &Self) -> std::cmp::Ordering {
        self.order_key().cmp(&other.order_key())
    }
}

impl ContainerSource {
    /// The node kind of the container: a composite, or a multibody.
    pub(crate) fn kind(self) -> NodeKind {
        match self {
            ContainerSource::Composite(_) => NodeKind::Composite,
            _ => NodeKind::Multibody,
        }
    }
}
