//! Release: what frees a held body, and how far a release reaches.
//!
//! A held body is a fixed body to Rapier, so a contact can never move it: the layer
//! must free it *before* the contact is solved, and free with it whatever the
//! disturbance reaches, as Rapier wakes a sleeping island whole (paper §7, fixation).
//! - **Reach**: a body moving faster than `release_speed` frees the held bodies it
//!   heads towards whose colliders' boxes lie within its motion over the next steps
//!   ([`REACH_STEPS`]), looked up in the layer's own tree of held bodies' boxes
//!   (`held_boxes.rs`); a moving kinematic body, all of them. Either also frees the
//!   held bodies jointed to it.
//! - **Group**: the release spreads from the bodies one moving body reached, in one
//!   walk, to the held bodies they touched when they were held, or that touched
//!   them, nearest first, as far as the moving body's momentum could set them moving
//!   ([`REACH_MASS_MARGIN`] × its momentum / `release_speed`, in kg of held
//!   bodies); a kinematic body's or the user's release has no bound: the held part
//!   of the contact group wakes whole ([`super::SpeedUps::release_group`]). What a
//!   spread reaches is given back nearest first, at most [`release_budget`] bodies
//!   a step; the rest at the next analyses.
//! - **Support**: a held body whose remembered support is gone is released, with
//!   what rests on it, transitively; when the world under it changed (a static
//!   supporter removed or moved, a body removed), the rest of its held group
//!   follows, given back as a spread is.
//! - **Owner**: a held body the user turned into another type is the user's again,
//!   its group with it; one the user reached for mutably (any write through
//!   `get_mut`, `bodies[h]` or `iter_mut`, which Rapier flags) is the user's from the
//!   next step on. Rapier drops an impulse, force or velocity written to a fixed
//!   body, so that write itself is lost (`docs/ARCHITECTURE.md`, rule 4).
//!
//! Cost: O(fast bodies × (log held boxes + held boxes met)) per step while anything
//! is held; O(released bodies × their links · log) per release.

use std::collections::BTreeSet;

use rapier3d::data::HasModifiedFlag;
use rapier3d::parry::bounding_volume::BoundingVolume;
use rapier3d::prelude::{RigidBodyHandle, RigidBodySet};

use super::{key, SpeedUpState};
use crate::graph::{ContactGraph, EdgeKind, NodeId, NodeKind};
use crate::WorldView;

/// How many steps ahead a moving body's reach is looked at: the release is decided
/// after one step and applied before the next, so the body moves one step before
/// the released bodies are dynamic, and one more while Rapier solves their contact.
pub(crate) const REACH_STEPS: f32 = 2.0;

/// How much more held mass a disturbance releases than its momentum could set moving
/// at `release_speed`: a margin, since a push spreads sideways through a pile and
/// its contacts carry it on. Calibrated on the disturbance scenes
/// (`docs/results.md`, "One spread per disturbance").
pub(crate) const REACH_MASS_MARGIN: f32 = 3.0;

/// The most held bodies a step releases through a release's spread (rule 2) beyond
/// the bodies released directly: [`RELEASE_BUDGET_SHARE`]'s share of the world's
/// dynamic bodies (held ones included), at least [`RELEASE_BUDGET_MIN`]. Rapier
/// answers a released body by pairing its colliders anew and computing their contacts
/// from nothing, at about the cost of stepping the body awake, so a wave released
/// whole cost its step about twice an awake step of the pile; spread nearest first
/// over a few steps, each step's share adds about a quarter. O(1).
pub(crate) fn release_budget(dynamic: usize) -> usize {
    RELEASE_BUDGET_MIN.max(dynamic / RELEASE_BUDGET_SHARE)
}

/// The least number of spread releases a step applies when that many are pending
/// (see [`release_budget`]).
pub(crate) const RELEASE_BUDGET_MIN: usize = 32;

/// The share of the world's dynamic bodies one step may release through a spread:
/// one in this many (see [`release_budget`]).
pub(crate) const RELEASE_BUDGET_SHARE: usize = 4;

/// A release decided this step: the held bodies one cause frees at once (one body the
/// user took back, or what one moving body reaches), and how far their spread may go:
/// the mass of held bodies, in kg, it may set moving (infinite: the whole held group).
type Seed = (Vec<RigidBodyHandle>, f32);

impl SpeedUpState {
    /// Decides this step's releases: the held bodies the user took back, those a
    /// moving body is about to reach, each cause's spread through the held group as
    /// far as its budget reaches. O(refreshed bodies + fast bodies × (log held + held
    /// boxes met) + released bodies × their links · log).
    pub(super) fn decide_releases(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        refreshed: &[NodeId],
    ) {
        if self.held.is_empty() {
            return;
        }
        let held = &self.held;
        let refreshed_held = refreshed
            .iter()
            .filter_map(|&n| graph.body_of(n))
            .filter(|&h| held.contains_key(&key(h)));
        self.held_boxes
            .refresh(view.bodies, view.colliders, refreshed_held);
        let mut seeds: Vec<Seed> = Vec::new();
        self.taken_back(graph, view, refreshed, &mut seeds);
        self.reached(graph, view, refreshed, &mut seeds);
        let dynamic = graph.count_of_kind(NodeKind::Dynamic)
            + graph.count_of_kind(NodeKind::Link)
            + self.held.len();
        self.spread_releases(view, seeds, release_budget(dynamic));
    }

    /// Queues the releases of `bodies` that are held and not queued yet, in the
    /// order given. O((queued + bodies) · log).
    pub(super) fn queue_releases(&mut self, bodies: impl IntoIterator<Item = RigidBodyHandle>) {
        let mut queued: BTreeSet<(u32, u32)> = self.to_release.iter().map(|&h| key(h)).collect();
        for h in bodies {
            if self.is_fixated(h) && queued.insert(key(h)) {
                self.to_release.push(h);
                self.stats.releases = self.stats.releases.saturating_add(1);
            }
        }
    }

    /// The held bodies a moving body is about to reach (see the module doc): each
    /// refreshed body faster than `release_speed` that is not sleepy, and each moving
    /// kinematic body, with the mass its momentum may set moving. O(such bodies ×
    /// (log held + held boxes met)).
    // Long: one sweep per moving body over what it reaches, its joints and its one spread.
    fn reached(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        refreshed: &[NodeId],
        seeds: &mut Vec<Seed>,
    ) {
        for &n in refreshed {
            let Some(node) = graph.node(n) else { continue };
            let Some(h) = node.body() else { continue };
            let Some(rb) = view.bodies.get(h) else {
                continue;
            };
            let simulated = node.kind().is_simulated();
            let moving = if simulated {
                self.moves_fast(node, h, rb)
            } else {
                node.kind() == NodeKind::Kinematic && crate::world::moves(rb)
            };
            if !moving {
                continue;
            }
            let speed = rb.linvel().length() + rb.angvel().length() * body_radius(view, rb);
            // A non-finite state is Rapier's quarantine's to handle: no reach to take.
            if !speed.is_finite() {
                continue;
            }
            let budget = if simulated {
                self.momentum_budget(rb.mass(), speed)
            } else {
                f32::INFINITY
            };
            let mut met = Vec::new();
            let reach = (speed * view.dt * REACH_STEPS).max(0.0);
            for &c in rb.colliders() {
                let Some(co) = view.colliders.get(c) else {
                    continue;
                };
                let aabb = co.compute_aabb().loosened(reach);
                met.extend(
                    self.held_boxes
                        .meeting(&aabb)
                        .filter(|&p| p != h && self.is_fixated(p))
                        .filter(|&p| !simulated || approaches(view, rb, p)),
                );
            }
            // What it drags by a joint.
            for (b1, b2, _, _) in view.impulse_joints.attached_joints(h) {
                let other = if b1 == h { b2 } else { b1 };
                if other != h && self.is_fixated(other) {
                    met.push(other);
                }
            }
            // One spread from all it reaches, with its whole momentum, in handle order
            // (the tree's order is not restored with a snapshot); what it releases
            // joins its wave.
            met.sort_by_key(|&h| key(h));
            met.dedup();
            if !met.is_empty() {
                self.waves.reached_from(h);
                seeds.push((met, budget));
            }
        }
    }

    /// Queues the seeds' releases at once, and the held bodies their spread reaches
    /// through the held bodies' links both ways, nearest first, while each seed's
    /// mass budget lasts (see the module doc), after those put off before, up to
    /// `budget` this step; the rest wait in [`SpeedUpState::later`]. O((released +
    /// put off) × their links · log).
    fn spread_releases(&mut self, view: &WorldView, seeds: Vec<Seed>, budget: usize) {
        let mut now: Vec<RigidBodyHandle> =
            seeds.iter().flat_map(|(b, _)| b.iter().copied()).collect();
        now.sort_by_key(|&h| key(h));
        let mut spread = std::mem::take(&mut self.later);
        if self.config.release_group {
            for (starts, budget) in &seeds {
                let mass = |b| held_mass(view.bodies, view.colliders, b);
                spread.extend(self.held_group_from(starts, *budget, mass));
            }
        }
        let mut seen: BTreeSet<(u32, u32)> = now.iter().map(|&h| key(h)).collect();
        spread.retain(|&h| self.is_fixated(h) && seen.insert(key(h)));
        self.later = spread.split_off(budget.min(spread.len()));
        self.queue_releases(now.into_iter().chain(spread));
    }

    /// The held mass, in kg, that a body of `mass` moving at `speed` may set moving:
    /// [`REACH_MASS_MARGIN`] × its momentum / `release_speed`; unbounded without a
    /// `release_speed`. O(1).
    fn momentum_budget(&self, mass: f32, speed: f32) -> f32 {
        let fast = self.config.release_speed;
        if fast > 0.0 {
            REACH_MASS_MARGIN * mass * speed / fast
        } else {
            f32::INFINITY
        }
    }

    /// `h` and the held bodies linked to it (those it touched when it was held, and
    /// those that touched it), transitively, nearest first, while `budget` kg of
    /// their `mass` lasts (infinite: the whole held group). O(bodies found × their
    /// links · log).
    fn held_group(
        &self,
        h: RigidBodyHandle,
        budget: f32,
        mass: impl Fn(RigidBodyHandle) -> f32,
    ) -> Vec<RigidBodyHandle> {
        self.held_group_from(&[h], budget, mass)
    }

    /// [`Self::held_group`] from several bodies at once, in one walk: `starts` (each
    /// once, in the order given), then the held bodies linked to them, nearest to any
    /// of them first. O(bodies found × their links · log).
    fn held_group_from(
        &self,
        starts: &[RigidBodyHandle],
        budget: f32,
        mass: impl Fn(RigidBodyHandle) -> f32,
    ) -> Vec<RigidBodyHandle> {
        let mut out = Vec::with_capacity(starts.len());
        let mut left = budget;
        let mut seen: BTreeSet<(u32, u32)> = BTreeSet::new();
        let mut queue = std::collections::VecDeque::new();
        for &h in starts {
            if seen.insert(key(h)) {
                left -= mass(h);
                out.push(h);
                queue.push_back(key(h));
            }
        }
        while let Some(k) = queue.pop_front() {
            let Some(held) = self.held.get(&k) else {
                continue;
            };
            let forward = held.links.iter().map(|&l| key(l));
            let back = self
                .linked
                .range((k, (0, 0))..=(k, (u32::MAX, u32::MAX)))
                .map(|&(_, held)| held);
            for m in forward.chain(back) {
                if left <= 0.0 {
                    return out;
                }
                let Some(next) = self.held.get(&m) else {
                    continue;
                };
                if seen.insert(m) {
                    left -= mass(next.handle);
                    out.push(next.handle);
                    queue.push_back(m);
                }
            }
        }
        out
    }

    /// Releases the held bodies whose remembered support is gone (a supporter removed,
    /// moved or released from under them), with what rests on them, transitively:
    /// they fall as a sleeping body falls when what it rests on goes. With `whole`
    /// (the world under them changed: a static supporter moved or removed, a body
    /// removed, gravity turned) and [`super::SpeedUps::release_group`], the rest of
    /// their held group follows from the next analysis on, nearest first, within
    /// [`release_budget`], as Rapier wakes a sleeping island whole when a collider
    /// touching it goes. O(released bodies × their dependents · log), plus O(group ×
    /// links · log) with `whole`.
    pub(super) fn release_unsupported(&mut self, graph: &ContactGraph, whole: bool) {
        let mut queue: Vec<(u32, u32)> = self.unsupported.iter().copied().collect();
        let mut seen: BTreeSet<(u32, u32)> = queue.iter().copied().collect();
        let mut out: Vec<RigidBodyHandle> = Vec::new();
        while let Some(k) = queue.pop() {
            let Some(held) = self.held.get(&k) else {
                continue;
            };
            out.push(held.handle);
            let Some(n) = graph.node_of_body(held.handle) else {
                continue;
            };
            for d in self.dependents_of(n) {
                if seen.insert(d) {
                    queue.push(d);
                }
            }
        }
        out.sort_by_key(|&h| key(h));
        if whole && self.config.release_group && !out.is_empty() {
            let group = self.held_group_from(&out, f32::INFINITY, |_| 0.0);
            self.later.extend_from_slice(&group[out.len()..]);
        }
        self.queue_releases(out);
    }

    /// The refreshed held bodies that are no longer fixed in Rapier, or that the user
    /// disabled (not the layer, on the way out of Rapier's active set): the user gave
    /// them another type or took them out of the simulation, and they are the user's
    /// again (the release keeps the type, velocities and enabled flag the user set,
    /// see [`super::hold::Held::give_back`]), their group with them. O(refreshed
    /// bodies · log held).
    fn taken_back(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        refreshed: &[NodeId],
        seeds: &mut Vec<Seed>,
    ) {
        for &n in refreshed {
            let Some(h) = graph.body_of(n) else { continue };
            let Some(held) = self.held.get(&key(h)) else {
                continue;
            };
            let parking = held.park == super::park::Park::Parking;
            if view
                .bodies
                .get(h)
                .is_some_and(|rb| !rb.is_fixed() || (!rb.is_enabled() && !parking))
            {
                seeds.push((vec![h], f32::INFINITY));
            }
        }
    }

    /// Notes which held bodies in Rapier's active set (`unparked`; a parked body is in
    /// no island) carry Rapier's modified flag after its step: Rapier's own island
    /// bookkeeping writes to bodies through `get_mut` (a removal or a disable moves
    /// another body into the gap of an island's list; a wake writes every body of a
    /// woken island), so those flags are not the user's. Also notes the world's body
    /// count. Called at the end of the analysis, whether
    /// [`super::SpeedUps::release_written`] is on or not (it may be switched on
    /// before the next pre-step). O(held bodies in Rapier's active set).
    pub(crate) fn note_flags(&mut self, bodies: &RigidBodySet) {
        self.bodies_noted = bodies.len();
        let flagged = self.unparked.iter().copied().filter(|&(i, g)| {
            let h = RigidBodyHandle::from_raw_parts(i, g);
            bodies.get(h).is_some_and(|rb| rb.has_modified_flag())
        });
        self.flagged_before_user = flagged.collect();
    }

    /// Queues the release of the held bodies the user wrote to since the last
    /// analysis (Rapier's modified flag, which its step clears, on a body not noted
    /// then: [`Self::note_flags`]; between steps the layer writes to a held body only
    /// to release it), still fixed and enabled: each alone, given back at this
    /// pre-step, so that the user's writes from the next one on reach a dynamic body;
    /// what it then does spreads as any moving body's motion does. (A body the user
    /// gave another type or disabled is [`Self::taken_back`]'s, its group with it.)
    /// Not after a step the layer did not see (`unseen`), whose flags are that
    /// step's; after a body was removed, only parked held bodies are looked at
    /// (Rapier's removal flags the body it moves in an island's list). Only with
    /// [`super::SpeedUps::release_written`]. O(held).
    pub(crate) fn release_written(&mut self, bodies: &RigidBodySet, unseen: bool) {
        if self.detached || unseen || !self.config.release_written || self.held.is_empty() {
            return;
        }
        let noted = &self.flagged_before_user;
        let removed = bodies.len() < self.bodies_noted;
        let unparked = &self.unparked;
        // The keys alone: a map's keys lie together, apart from the held records.
        let written: Vec<RigidBodyHandle> = self
            .held
            .keys()
            .filter(|k| noted.binary_search(k).is_err() && !(removed && unparked.contains(k)))
            .map(|&(i, g)| RigidBodyHandle::from_raw_parts(i, g))
            .filter(|&h| {
                bodies
                    .get(h)
                    .is_some_and(|rb| rb.has_modified_flag() && rb.is_fixed() && rb.is_enabled())
            })
            .collect();
        self.queue_releases(written);
    }

    /// Releases a held body for the monitor's repair of an unresponsive body (one the
    /// awake body `by` pushes into), spread through the held bodies it touched when it
    /// was held or that touched it when `release_group` is on, as far as the pusher's
    /// momentum could set them moving (the reach's bound, at `release_speed` at least:
    /// a slow push moves what it pushes, not a whole pile), each with its rest count
    /// started again (as [`Self::repair_wake`]). The bodies released, in handle order.
    /// O(released bodies × their links · log).
    pub(crate) fn repair_release_group(
        &mut self,
        h: RigidBodyHandle,
        by: RigidBodyHandle,
        world: &crate::logic::WorldMut,
        mods: &mut crate::logic::hooks::ContactMods,
    ) -> Vec<RigidBodyHandle> {
        let mut out = if self.config.release_group {
            let slowest = self.config.release_speed;
            let budget = match world.bodies.get(by) {
                Some(rb) if rb.is_dynamic() => {
                    self.momentum_budget(rb.mass(), rb.linvel().length().max(slowest))
                }
                _ => f32::INFINITY,
            };
            self.held_group(h, budget, |b| held_mass(world.bodies, world.colliders, b))
        } else {
            vec![h]
        };
        out.sort_by_key(|&b| key(b));
        self.queue_releases(out.iter().copied());
        for &b in &out {
            self.restart_rest(b, mods);
        }
        out
    }

    /// What a body about to be held touches now: the bodies at the other end of its
    /// touching physical edges that are dynamic or held, in handle order (see
    /// [`super::hold::Held::links`]). O(its edges).
    pub(super) fn links_now(&self, graph: &ContactGraph, n: NodeId) -> Vec<RigidBodyHandle> {
        let mut links: Vec<RigidBodyHandle> = graph
            .neighbors(n)
            .filter(|(_, _, e)| e.kind() == EdgeKind::Physical && e.is_touching())
            .filter_map(|(m, _, _)| {
                let node = graph.node(m)?;
                let h = node.body()?;
                (node.kind().is_simulated() || self.is_fixated(h)).then_some(h)
            })
            .collect();
        links.sort_by_key(|&h| key(h));
        links.dedup();
        links
    }
}

/// Whether a moving dynamic body heads towards a held one (their centres closing):
/// one rolling past or away does not release it. O(1).
fn approaches(view: &WorldView, rb: &rapier3d::prelude::RigidBody, held: RigidBodyHandle) -> bool {
    view.bodies
        .get(held)
        .is_some_and(|o| (o.translation() - rb.translation()).dot(rb.linvel()) > 0.0)
}

/// A held body's mass, from its colliders (Rapier gives a fixed body none). O(its
/// colliders).
fn held_mass(
    bodies: &rapier3d::prelude::RigidBodySet,
    colliders: &rapier3d::prelude::ColliderSet,
    h: RigidBodyHandle,
) -> f32 {
    bodies.get(h).map_or(0.0, |rb| {
        rb.colliders()
            .iter()
            .filter_map(|&c| colliders.get(c))
            .map(|co| co.mass())
            .sum()
    })
}

/// The distance from a body's centre of mass to the farthest point of its colliders'
/// boxes: how far a turn moves its surface per radian. O(its colliders).
fn body_radius(view: &WorldView, rb: &rapier3d::prelude::RigidBody) -> f32 {
    let centre = rb.center_of_mass();
    rb.colliders()
        .iter()
        .filter_map(|&c| view.colliders.get(c))
        .map(|co| {
            let aabb = co.compute_aabb();
            (aabb.center() - centre).length() + aabb.half_extents().length()
        })
        .fold(0.0, f32::max)
}
