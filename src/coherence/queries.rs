//! What the analysis of the last step found: refreshed and removed nodes and edges,
//! sleep and kind changes, its counters; and its settings.

use rapier3d::prelude::{ColliderSet, RigidBodySet};

use crate::graph::{Edge, EdgeId, NodeId, Storage};

use super::*;

/// Bodies (colliders) from the start of a set that a query looks at to tell the
/// analysed world from another ([`Coherence::bodies_match`]).
pub(crate) const WORLD_WITNESSES: usize = 8;

/// The verdict of the world's witnesses, each "the same world" (`Some(true)`),
/// "another" (`Some(false)`) or nothing (`None`): one "the same" wins (the same world
/// edited may have moved a few lists or shapes, a copy has moved them all), else one
/// "another" decides, else nothing tells and the world answers. O(witnesses).
fn same_world_by(witnesses: impl Iterator<Item = Option<bool>>) -> bool {
    let mut another = false;
    for same in witnesses.flatten() {
        if same {
            return true;
        }
        another = true;
    }
    !another
}

impl Coherence {
    /// Sets the step counter (tests of counters at the end of their range).
    #[cfg(test)]
    pub(crate) fn set_step_for_test(&mut self, step: u64) {
        self.step = step;
    }

    /// Bodies that Rapier integrated in the last step: its active set without the fixed
    /// bodies it keeps there (a body turned fixed stays in Rapier's active set until it
    /// is disabled or removed). O(1).
    pub fn integrated_bodies(&self) -> usize {
        self.integrated
    }

    /// Slots of each kind (graph nodes, Rapier body slots, Rapier collider slots, and
    /// colliders' `COLLISION_EVENTS` flags under touching tracking) the round-robin
    /// verification checks in the next step: one per
    /// `AWAKE_BODIES_PER_VERIFIED_SLOT` bodies Rapier integrated in the last step,
    /// between `VERIFY_IDLE_PER_STEP` and `VERIFY_PER_STEP`; a kind with at most
    /// `VERIFY_PER_STEP` slots is checked whole every step. The check's cost so
    /// follows Rapier's own (a large sleeping or held scene pays for two slots of each
    /// kind per step, a scene of 512 awake bodies or more for 32), and so does the
    /// time it takes to find a change no Rapier list tells (see
    /// [`crate::LayerAnalysisMut::request_full_sync`]): `slots / budget` steps. O(1).
    pub fn verify_budget(&self) -> usize {
        (self.integrated / AWAKE_BODIES_PER_VERIFIED_SLOT)
            .clamp(VERIFY_IDLE_PER_STEP, VERIFY_PER_STEP)
    }

    /// Whether `bodies` can be the body set of the world the last update analysed (see
    /// `Error::ForeignWorld` for what this can and cannot tell). Two looks, which must
    /// both say "another" for `false`:
    /// - the set's storage: as many bodies as that world had, its first body stored
    ///   where that world's was (the mark [`Coherence::same_world`] takes at every
    ///   update; the same world moved keeps it);
    /// - the first bodies of the set (up to [`WORLD_WITNESSES`]) that the layer has
    ///   read with colliders: one whose collider list is where the layer read it says
    ///   "the same world"; otherwise one whose list has the length the layer read but
    ///   is elsewhere says "another" (a list is an allocation of its own, which
    ///   neither a move of the world nor the growth of Rapier's storage moves, and
    ///   which another world, or a copy, has elsewhere; a list of another length may
    ///   have moved when it grew, and tells nothing).
    ///
    /// When no body can be looked at, nothing tells: `true`, as before the first
    /// update and after a restore (nothing to compare). O(1): a few slots from the
    /// start of the set.
    pub(crate) fn bodies_match(&self, graph: &ContactGraph, bodies: &RigidBodySet) -> bool {
        let Some((first_body, _)) = *self.world_mark else {
            return true;
        };
        // As `same_world` takes it.
        let first = bodies
            .iter()
            .next()
            .map_or(0, |(_, b)| b as *const _ as usize);
        let counted = self.known_bodies == Some(bodies.len());
        if counted && first == first_body {
            return true;
        }
        // Each witness a body the layer read: its list where it was tells "the same
        // world" (whatever its length); at the length read but elsewhere, "another"
        // (a list that changed length may have moved when it grew).
        let witnesses = bodies
            .iter()
            .filter(|(_, rb)| !rb.colliders().is_empty())
            .take(WORLD_WITNESSES)
            .map(|(h, rb)| {
                let read = graph.node(graph.node_of_body(h)?)?.storage.list;
                let now = Storage::list_of(rb);
                if read.0 == 0 {
                    None
                } else if read.0 == now.0 {
                    Some(true)
                } else {
                    (read.1 == now.1).then_some(false)
                }
            });
        same_world_by(witnesses)
    }

    /// [`Self::bodies_match`] for a collider set: the first colliders of the set (up to
    /// [`WORLD_WITNESSES`]) that the layer has read (a body's first collider, static
    /// geometry, a sensor) must have their shape where the layer read it (a shape is an
    /// allocation of its own; a copy of the set made with `clone` shares it, and so do
    /// colliders built from one shared shape). O(1).
    pub(crate) fn colliders_match(&self, graph: &ContactGraph, colliders: &ColliderSet) -> bool {
        let Some((_, first_collider)) = *self.world_mark else {
            return true;
        };
        let first = colliders
            .iter()
            .next()
            .map_or(0, |(_, c)| c as *const _ as usize);
        let counted = self.known_colliders == colliders.len();
        if counted && first == first_collider {
            return true;
        }
        // Each witness a collider the layer read for its node: its shape where it was
        // tells "the same world", elsewhere "another".
        let witnesses = colliders.iter().take(WORLD_WITNESSES).map(|(h, c)| {
            let owner = match c.parent() {
                Some(body) => graph.node_of_body(body),
                None if c.is_sensor() => graph.node_of_sensor(h),
                None => graph.node_of_static_collider(h),
            }?;
            let (named, shape) = graph.node(owner)?.storage.shape;
            (named == Some(h) && shape != 0).then(|| shape == Storage::shape_of(c))
        });
        same_world_by(witnesses)
    }

    /// Whether the world's body and collider sets both can be the analysed world's
    /// ([`Self::bodies_match`], [`Self::colliders_match`]). O(1).
    pub(crate) fn world_matches(&self, graph: &ContactGraph, view: &WorldView) -> bool {
        self.bodies_match(graph, view.bodies) && self.colliders_match(graph, view.colliders)
    }

    /// The index of the last analysed step (0 before the first).
    pub fn step(&self) -> u64 {
        self.step
    }

    /// Edges refreshed in the last step: their marks are valid. In a deterministic
    /// order: Rapier's pair order, then the edges found vanished.
    pub fn touched_edges(&self) -> &[EdgeId] {
        &self.touched
    }

    /// Takes the addresses of the triggers' shapes from `colliders` (after a restore:
    /// an address means nothing in another process), and forgets where the last world
    /// stored its first body and collider (the world restored against may be a copy,
    /// or from another process: the mark is taken again at the next update, and
    /// queries compare nothing until then; see `Error::ForeignWorld`). O(triggers).
    #[cfg(feature = "serde")]
    pub(crate) fn rebind_trigger_shapes(
        &mut self,
        graph: &ContactGraph,
        colliders: &rapier3d::prelude::ColliderSet,
    ) {
        *self.world_mark = None;
        for (n, st) in self.trigger_states.iter_mut() {
            if let Some(NodeSource::Sensor(c)) = graph.node(*n).map(|x| x.source()) {
                if let Some(co) = colliders.get(c) {
                    st.shape = TriggerState::of(co).shape;
                }
            }
        }
    }

    /// Edges removed in the last step because one of their nodes left the world, with
    /// their final state (marks `Vanished` where they were on).
    pub fn removed_edges(&self) -> &[Edge] {
        &self.removed_edges
    }

    /// Nodes removed in the last step.
    pub fn removed_nodes(&self) -> &[RemovedNode] {
        &self.removed_nodes
    }

    /// Nodes created in the last step.
    pub fn created_nodes(&self) -> &[NodeId] {
        &self.created
    }

    /// Nodes refreshed in the last step (awake now or at the update before).
    pub fn refreshed_nodes(&self) -> &[NodeId] {
        &self.walk
    }

    /// Bodies that fell asleep (`false`) or woke up (`true`) in the last step, in the
    /// order they were refreshed.
    pub fn sleep_changes(&self) -> &[(NodeId, bool)] {
        &self.sleep_changes
    }

    /// Node kind changes seen in the last step.
    pub fn kind_changes(&self) -> usize {
        self.kind_changes
    }

    /// Counters of the last pair walk.
    pub fn counters(&self) -> WalkCounters {
        self.counters
    }

    /// Whether the per-edge contact details (relative pose and its change flag, closest
    /// distance, deepest penetration, normal impulse, deepest normal) are maintained.
    pub fn contact_details(&self) -> bool {
        !self.skip_details
    }

    /// Whether the edges hold this step's contact details: the details are on and the
    /// last update tracked proximity (touching tracking copies none; read them from
    /// Rapier with `ContactLayer::contact_details`). What the graph's own support
    /// queries and a standalone monitor read. O(1).
    pub fn details_kept(&self) -> bool {
        !self.skip_details && self.tracking() == super::Tracking::Proximity
    }

    /// Turns the per-edge contact details on (the default) or off. Off, each collider
    /// pair costs only its proximity, touching state and contact count; the details
    /// keep their last values and support queries see no normals.
    pub(crate) fn set_contact_details(&mut self, on: bool) {
        self.skip_details = !on;
    }

    /// Chooses how pairs are found (see [`ScanPolicy`]).
    pub(crate) fn set_scan_policy(&mut self, policy: ScanPolicy) {
        self.scan = policy;
    }

    /// Asks for a full scan of bodies and colliders at the next update, which also
    /// refreshes every node (pairs and triggers read again): after changing a sleeping
    /// or fixed body, or static geometry, in place (moving it, its type, a sensor
    /// flag), which Rapier does not report. That update costs O(nodes + pairs).
    pub(crate) fn request_full_sync(&mut self) {
        self.force_full_sync = true;
    }
}
