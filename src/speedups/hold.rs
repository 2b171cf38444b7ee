//! Fixate: a sleepy body held immovable (its type made fixed), its release, and the
//! held records with the dependents index (supporter → held bodies) kept beside them.

use rapier3d::dynamics::RigidBodyType;
use rapier3d::math::{Pose, Vector};
use rapier3d::prelude::RigidBodyHandle;

use super::busy::beside_busy;
use super::park::Park;
use super::sleep::{never_activation, remember_activation};
use super::support::{supporters_now, Supporter};
use super::{key, SpeedUpState};
use crate::graph::{ContactGraph, NodeId, NodeKind};
use crate::logic::hooks::ContactMods;
use crate::logic::WorldMut;
use crate::WorldView;

/// A body held by fixation, with what it had before.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct Held {
    pub(super) handle: RigidBodyHandle,
    linvel: Vector,
    angvel: Vector,
    /// What supported it against gravity when it was fixated (see
    /// [`SpeedUpState::fixation_supported`]).
    pub(super) supports: Vec<Supporter>,
    /// Where it is on the way out of Rapier's active set (see [`Park`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub(super) park: Park,
    /// What it added to the support watch when it was last judged
    /// ([`SpeedUpState::watch_of`]): taken off again when it is judged anew or
    /// released.
    #[cfg_attr(feature = "serde", serde(default))]
    pub(super) watched: Vec<(NodeId, Option<Pose>)>,
    /// The bodies it touched when it was fixated (dynamic or held), in handle order:
    /// a release of one reaches the other ([`super::SpeedUps::release_group`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub(super) links: Vec<RigidBodyHandle>,
}

/// A body that may be held at the next pre-step: (its steps at rest, reversed so
/// that the longest rest sorts first; its key; its node; its handle).
type Candidate = (std::cmp::Reverse<u32>, (u32, u32), NodeId, RigidBodyHandle);

/// A fixation decided at the analysis, applied at the next pre-step.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct ToFix {
    pub(super) handle: RigidBodyHandle,
    /// What holds it up now.
    supports: Vec<Supporter>,
    /// What it touches now (see [`Held::links`]).
    links: Vec<RigidBodyHandle>,
}

impl Held {
    /// Gives the body back to the simulation exactly as it was held: dynamic, with its
    /// velocities, and enabled again if the layer disabled it for this step (unless
    /// the user made it passive meanwhile). A body the user gave another type
    /// meanwhile keeps the type and velocities the user set. The body, if it still
    /// exists.
    pub(super) fn give_back<'w>(
        &self,
        world: &'w mut WorldMut,
        user_passive: &dyn Fn(RigidBodyHandle) -> bool,
    ) -> Option<&'w mut rapier3d::dynamics::RigidBody> {
        let rb = world.bodies.get_mut(self.handle)?;
        if self.park == Park::Parking && !user_passive(self.handle) {
            rb.set_enabled(true);
        }
        if rb.is_fixed() {
            rb.set_body_type(RigidBodyType::Dynamic, true);
            rb.set_linvel(self.linvel, true);
            rb.set_angvel(self.angvel, true);
        }
        Some(rb)
    }
}

/// Whether Rapier cannot step a body fixed where it is joined: a multibody member
/// (link or root), or a body with an impulse joint to a disabled one. Such a body is
/// never held, and a held one is released ([`SpeedUpState::release_joined`]). O(its
/// joints).
fn joined_unsafely(world: &WorldMut, h: RigidBodyHandle) -> bool {
    world.multibody_joints.rigid_body_link(h).is_some()
        || world
            .impulse_joints
            .attached_joints(h)
            .any(|(b1, b2, _, _)| {
                let other = if b1 == h { b2 } else { b1 };
                world.bodies.get(other).is_some_and(|rb| !rb.is_enabled())
            })
}

impl SpeedUpState {
    /// Records a held body, and its supporters in the dependents index. O(its
    /// supporters · log).
    fn hold(&mut self, held: Held) {
        let k = key(held.handle);
        self.dependents
            .extend(held.supports.iter().map(|s| (s.node, k)));
        self.linked.extend(held.links.iter().map(|&l| (key(l), k)));
        if let Some(old) = self.held.insert(k, held) {
            self.forget_dependents(k, &old);
        }
    }

    /// Forgets a held body's record, and its supporters in the dependents index.
    /// O(its supporters · log).
    fn unhold(&mut self, k: (u32, u32)) -> Option<Held> {
        let held = self.held.remove(&k)?;
        self.held_boxes.take_out(held.handle);
        self.forget_dependents(k, &held);
        Some(held)
    }

    /// Builds the indexes left out of snapshots (the dependents and links indexes, the
    /// held bodies' boxes) from the held records; the restore calls it. O(held bodies'
    /// supporters, links and colliders · log).
    #[cfg_attr(not(feature = "serde"), allow(dead_code))] // only the snapshot restore calls it
    pub(crate) fn reindex(&mut self, view: &WorldView) {
        self.held_boxes = super::held_boxes::HeldBoxes::of(&self.held, view.bodies, view.colliders);
        self.dependents = self.dependents_of_records();
        self.linked = self
            .held
            .iter()
            .flat_map(|(k, held)| held.links.iter().map(move |&l| (key(l), *k)))
            .collect();
    }

    /// Checks the held bodies' boxes against the held records: every box of a live
    /// collider on its live body is one a tree built anew from the records holds (no
    /// box of a released body, none of a collider moved to another body). A box may
    /// be missing or stale meanwhile where the user changed a held body's colliders
    /// in place: read again when the collider or body count changes or the body is
    /// refreshed, as the graph reads such changes. O(held · colliders · log held).
    pub(crate) fn check_held_boxes(&self, view: &WorldView) -> Result<(), String> {
        let raw = |(l, c, h): super::held_boxes::Entry| (l, c.into_raw_parts(), key(h));
        let anew: std::collections::BTreeSet<_> =
            super::held_boxes::HeldBoxes::expected(&self.held, view.bodies, view.colliders)
                .map(raw)
                .collect();
        let live = |&(_, c, h): &super::held_boxes::Entry| {
            view.bodies.contains(h)
                && view
                    .colliders
                    .get(c)
                    .is_some_and(|co| co.parent() == Some(h))
        };
        match self.held_boxes.entries().filter(live).find(|&e| !anew.contains(&raw(e))) {
            None => Ok(()),
            Some((leaf, c, h)) => Err(format!(
                "the held bodies' boxes hold collider {c:?} of body {h:?} (leaf {leaf}), which the held records do not"
            )),
        }
    }

    /// The dependents index as the held records give it. O(held bodies' supporters ·
    /// log).
    pub(super) fn dependents_of_records(&self) -> std::collections::BTreeSet<(NodeId, (u32, u32))> {
        self.held
            .iter()
            .flat_map(|(k, held)| held.supports.iter().map(move |s| (s.node, *k)))
            .collect()
    }

    /// Takes a held body's supporters out of the dependents index. O(its supporters ·
    /// log).
    fn forget_dependents(&mut self, k: (u32, u32), held: &Held) {
        for s in &held.supports {
            self.dependents.remove(&(s.node, k));
        }
        for &l in &held.links {
            self.linked.remove(&(key(l), k));
        }
    }

    /// Whether a body is held by fixation. O(log fixated).
    pub fn is_fixated(&self, h: RigidBodyHandle) -> bool {
        self.held.contains_key(&key(h))
    }

    /// The bodies held by fixation, in handle order.
    pub fn fixated(&self) -> impl Iterator<Item = RigidBodyHandle> + '_ {
        self.held.values().map(|h| h.handle)
    }

    /// Wakes a body for the monitor's repair: releases it if fixated, and starts its
    /// rest count again ([`Self::restart_rest`]). O(pending releases · log).
    pub(crate) fn repair_wake(&mut self, h: RigidBodyHandle, mods: &mut ContactMods) {
        self.queue_releases([h]);
        self.restart_rest(h, mods);
    }

    /// Starts a body's rest count again (not sleepy, not sleep-eligible, no fixation
    /// pending), so that its group is not put back to sleep before it has moved.
    /// O(pending fixations).
    pub(super) fn restart_rest(&mut self, h: RigidBodyHandle, mods: &mut ContactMods) {
        self.to_fix.retain(|f| f.handle != h);
        let r = self.rest_mut(h);
        r.steps = 0;
        let was_sleepy = std::mem::replace(&mut r.sleepy, false);
        let was_eligible = std::mem::replace(&mut r.eligible, false);
        if was_sleepy {
            mods.set_sleepy(h, false);
            self.zero_flags.push((h, false));
        }
        if was_eligible {
            self.eligibility.push((h, false));
        }
    }

    /// The fixations decided at the last analysis, applied at the next pre-step.
    /// O(1) to make.
    pub(crate) fn pending_fixations(&self) -> impl Iterator<Item = RigidBodyHandle> + '_ {
        self.to_fix.iter().map(|t| t.handle)
    }

    /// The bodies given back to Rapier since the last analysis (see
    /// [`crate::LayerAnalysis::given_back`]). O(changes since the last analysis).
    pub(crate) fn given_back(&self) -> impl Iterator<Item = RigidBodyHandle> + '_ {
        self.hold_changes
            .iter()
            .filter(|&&(_, released)| released)
            .map(|&(h, _)| h)
    }

    /// The releases queued and not given back yet: those the last analysis decided,
    /// in a hand-written loop (its next pre-step gives them back;
    /// [`crate::ContactLayer::step`] does at once), and those asked for since. The
    /// bodies a release's spread put off past a step's release budget
    /// (`docs/ARCHITECTURE.md`, "Releasing held bodies") are queued by the next
    /// analyses, not listed here before. O(1).
    pub fn pending_releases(&self) -> &[RigidBodyHandle] {
        &self.to_release
    }

    /// Releases the held bodies the user joined since they were fixated to what Rapier
    /// cannot step with a fixed body ([`joined_unsafely`]): a multibody (as a link
    /// Rapier asserts it dynamic; as a root it breaks Rapier's islands and a passive
    /// one its solver), or, by an impulse joint, a disabled body (Rapier panics on a
    /// joint between a disabled and a fixed body). O(held bodies · their joints), only
    /// while the world has joints.
    pub(super) fn release_joined(&mut self, world: &WorldMut) {
        let jointed = !world.impulse_joints.is_empty()
            || world.multibody_joints.multibodies().next().is_some();
        if self.held.is_empty() || !jointed {
            return;
        }
        let joined: Vec<RigidBodyHandle> = self
            .held
            .values()
            .map(|held| held.handle)
            .filter(|&h| joined_unsafely(world, h))
            .collect();
        self.queue_releases(joined);
    }

    /// Applies the queued releases: each body given back as it was held, never
    /// sleep-eligible, its rest count started again; each noted in the hold changes
    /// the next analysis takes. O(releases · log held).
    pub(super) fn apply_releases(
        &mut self,
        world: &mut WorldMut,
        mods: &mut ContactMods,
        user_passive: &dyn Fn(RigidBodyHandle) -> bool,
    ) {
        let mut released = Vec::new();
        for h in std::mem::take(&mut self.to_release) {
            if let Some(held) = self.unhold(key(h)) {
                released.push(h);
                self.hold_changes.push((h, true));
                self.unparked.remove(&key(h));
                if let Some(rb) = held.give_back(world, user_passive) {
                    if rb.is_dynamic() {
                        remember_activation(&mut self.activations, h, rb);
                        never_activation(rb.activation_mut());
                    }
                }
                self.released.push(held);
                let r = self.rest_mut(h);
                r.steps = 0;
                r.sleepy = false;
                r.eligible = false;
                mods.set_sleepy(h, false);
            }
        }
        // Those put off by the release budget join the wave now: their release later
        // is the same disturbance's.
        let mut joining = released;
        joining.extend(self.later.iter().copied());
        self.waves.join(&joining);
    }

    /// Applies the queued fixations to the bodies that can still be held: each one's
    /// velocities recorded, its type made fixed. O(fixations · log held).
    pub(super) fn apply_fixations(&mut self, world: &mut WorldMut) {
        for ToFix {
            handle: h,
            supports,
            links,
        } in std::mem::take(&mut self.to_fix)
        {
            if joined_unsafely(world, h) {
                continue;
            }
            let Some(rb) = world.bodies.get_mut(h) else {
                continue;
            };
            // Checked again now: the fixation was decided at the last analysis, and the
            // user may have changed the body since. Never fixated: one Rapier cannot step
            // fixed ([`Self::release_joined`]), nor a disabled (passive) body.
            if !rb.is_dynamic() || !rb.is_enabled() {
                continue;
            }
            let held = Held {
                handle: h,
                linvel: rb.linvel(),
                angvel: rb.angvel(),
                supports,
                park: Park::Active,
                watched: Vec::new(),
                links,
            };
            rb.set_body_type(RigidBodyType::Fixed, false);
            self.held_boxes.put(world.bodies, world.colliders, h);
            self.hold(held);
            self.unparked.insert(key(h));
            self.newly_held.push(key(h));
            self.hold_changes.push((h, false));
        }
    }

    /// Forgets the bodies removed while held, and counts the held and parked bodies.
    /// O(held) when the body count changed, else O(1).
    pub(super) fn forget_removed(&mut self, world: &WorldMut, counts_changed: bool) {
        // Bodies removed while held are forgotten, and the held bodies' boxes read
        // again where their colliders changed: looked for when the body or collider
        // count changed (O(held)); a body removed and another inserted between two
        // steps leaves a stale entry until the count changes, which is harmless
        // (handles carry their generation, and every use of a held handle checks it
        // exists).
        self.stats.parked = self.held.len().saturating_sub(self.unparked.len());
        if !counts_changed {
            self.stats.fixated = self.held.len();
            return;
        }
        let gone: Vec<(u32, u32)> = self
            .held
            .iter()
            .filter(|(_, h)| !world.bodies.contains(h.handle))
            .map(|(k, _)| *k)
            .collect();
        for k in gone {
            self.unhold(k);
            self.unparked.remove(&k);
            self.support_dirty = true;
        }
        let held = self.held.values().map(|h| h.handle);
        self.held_boxes.resync(world.bodies, world.colliders, held);
        self.stats.fixated = self.held.len();
    }

    /// Queues the fixation of the sleepy awake dynamic bodies that are not held yet,
    /// with what holds them up now (`up` against gravity): at most [`hold_budget`]
    /// of them, those at rest the longest first (then in handle order). The others
    /// are returned in handle order: *deferred*, they stay awake and the next
    /// analyses decide them again, each waiting step moving them up the queue.
    /// O(refreshed bodies · log + queued bodies' contact pairs).
    pub(super) fn decide_fixations(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        refreshed: &[NodeId],
        up: Vector,
    ) -> Vec<RigidBodyHandle> {
        // Fixate: every sleepy awake simulated body, with what holds it up now.
        let mut candidates: Vec<Candidate> = Vec::new();
        // Sleepy bodies whose wave is not at rest yet, or beside a busy group, wait, as
        // deferred ones do.
        let mut waiting: Vec<RigidBodyHandle> = Vec::new();
        for &n in refreshed {
            let Some(node) = graph.node(n) else { continue };
            if node.kind() != NodeKind::Dynamic || !node.is_awake() {
                continue;
            }
            let Some(h) = node.body() else { continue };
            match self.rest_of(h) {
                Some(r) if r.sleepy && !self.is_fixated(h) => {
                    if self.waves.waits(h) {
                        waiting.push(h);
                    } else {
                        candidates.push((std::cmp::Reverse(r.steps), key(h), n, h));
                    }
                }
                _ => {}
            }
        }
        // The busy groups only when a body could be held.
        if !candidates.is_empty() {
            let busy = self.busy_groups(graph, view, refreshed);
            candidates.retain(|&(_, _, n, h)| {
                let beside = beside_busy(graph, n, &busy);
                if beside {
                    waiting.push(h);
                }
                !beside
            });
        }
        candidates.sort_unstable_by_key(|c| (c.0, c.1));
        candidates.dedup_by_key(|c| c.1);
        let budget =
            hold_budget(view.islands.num_active_bodies()).saturating_sub(self.to_fix.len());
        let mut deferred: Vec<RigidBodyHandle> = candidates
            .split_off(budget.min(candidates.len()))
            .into_iter()
            .map(|c| c.3)
            .collect();
        deferred.append(&mut waiting);
        deferred.sort_unstable_by_key(|&h| key(h));
        deferred.dedup();
        let mut found = Vec::new();
        for (_, _, n, h) in candidates {
            let supports = supporters_now(graph, view, n, up, &mut found);
            let links = self.links_now(graph, n);
            self.to_fix.push(ToFix {
                handle: h,
                supports,
                links,
            });
            self.stats.fixations = self.stats.fixations.saturating_add(1);
        }
        deferred
    }
}

/// How many fixations one pre-step applies at most, and how many held bodies it
/// parks at most, with `active` bodies in Rapier's active set (what its last step
/// integrated): [`HOLD_BUDGET_MIN`] or `active` / [`HOLD_BUDGET_SHARE`], whichever
/// is more. Rapier answers a body's change of type (or its disabling) by computing
/// its collider pairs anew in its next step and waking what touches it, so a pile
/// held all at once cost that step several times a normal one; bounded by a share
/// of what the step integrates anyway, a step's holds add a bounded fraction to it.
/// O(1).
pub(crate) fn hold_budget(active: usize) -> usize {
    HOLD_BUDGET_MIN.max(active / HOLD_BUDGET_SHARE)
}

/// The least number of fixations (and of parkings) a pre-step applies when that
/// many are pending (see [`hold_budget`]).
pub(crate) const HOLD_BUDGET_MIN: usize = 32;

/// The share of Rapier's active bodies one pre-step may fixate (and park): one in
/// this many (see [`hold_budget`]).
pub(crate) const HOLD_BUDGET_SHARE: usize = 16;
