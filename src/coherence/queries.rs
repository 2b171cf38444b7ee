//! What the analysis of the last step found: refreshed and removed nodes and edges,
//! sleep and kind changes, its counters; and its settings.

use crate::graph::{Edge, EdgeId, NodeId};

use super::*;

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
    /// [`AWAKE_BODIES_PER_VERIFIED_SLOT`] bodies Rapier integrated in the last step,
    /// between [`VERIFY_IDLE_PER_STEP`] and [`VERIFY_PER_STEP`]; a kind with at most
    /// [`VERIFY_PER_STEP`] slots is checked whole every step. The check's cost so
    /// follows Rapier's own (a large sleeping or held scene pays for two slots of each
    /// kind per step, a scene of 512 awake bodies or more for 32), and so does the
    /// time it takes to find a change no Rapier list tells (see
    /// [`crate::ContactLayer::request_full_sync`]): `slots / budget` steps. O(1).
    pub fn verify_budget(&self) -> usize {
        (self.integrated / AWAKE_BODIES_PER_VERIFIED_SLOT)
            .clamp(VERIFY_IDLE_PER_STEP, VERIFY_PER_STEP)
    }

    /// Whether `bodies` can be the body set of the world the last update analysed, as
    /// far as an O(1) look tells (see `Error::ForeignWorld` for what it can and cannot
    /// tell): `false` only when the set holds as many bodies as that world did and its
    /// first body is stored elsewhere (another world, or a copy). `true` before the
    /// first update and after a restore (no mark yet), and for a set whose count
    /// changed since (the same world edited: its storage may have grown and moved).
    /// Reads the mark [`Coherence::same_world`] takes at every update. O(1) (the first
    /// occupied slot).
    pub(crate) fn bodies_match(&self, bodies: &rapier3d::prelude::RigidBodySet) -> bool {
        let Some((first_body, _)) = *self.world_mark else {
            return true;
        };
        if self.known_bodies != Some(bodies.len()) {
            return true;
        }
        // As `same_world` takes it.
        let now = bodies
            .iter()
            .next()
            .map_or(0, |(_, b)| b as *const _ as usize);
        now == first_body
    }

    /// [`Self::bodies_match`] for a collider set. O(1).
    pub(crate) fn colliders_match(&self, colliders: &rapier3d::prelude::ColliderSet) -> bool {
        let Some((_, first_collider)) = *self.world_mark else {
            return true;
        };
        if self.known_colliders != colliders.len() {
            return true;
        }
        let now = colliders
            .iter()
            .next()
            .map_or(0, |(_, c)| c as *const _ as usize);
        now == first_collider
    }

    /// Whether the world's body and collider sets both can be the analysed world's
    /// ([`Self::bodies_match`], [`Self::colliders_match`]). O(1).
    pub(crate) fn world_matches(&self, view: &WorldView) -> bool {
        self.bodies_match(view.bodies) && self.colliders_match(view.colliders)
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
    /// an address means nothing in another process). O(triggers).
    #[cfg(feature = "serde")]
    pub(crate) fn rebind_trigger_shapes(
        &mut self,
        graph: &ContactGraph,
        colliders: &rapier3d::prelude::ColliderSet,
    ) {
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
