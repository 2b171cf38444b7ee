//! Release: what frees a held body, and how far a release reaches.
//!
//! A held body is a fixed body to Rapier, so a contact can never move it: the layer
//! must free it *before* the contact is solved, and free with it whatever the
//! disturbance reaches, as Rapier wakes a sleeping island whole (paper §7, fixation).
//! - **Reach**: a body moving faster than `release_speed`, and any moving kinematic
//!   body, frees the held bodies whose broad-phase boxes lie within its motion over
//!   the next steps ([`REACH_STEPS`]), read from Rapier's broad phase; without one (a
//!   hand-built [`WorldView`]) the held bodies it touches.
//! - **Group**: a released body frees every held body it touched when it was held, or
//!   that touched it, transitively ([`super::SpeedUps::release_group`]): the held part of its
//!   contact group wakes whole.
//! - **Support**: a held body whose remembered support is gone is released.
//! - **Owner**: a held body the user turned into another type is the user's again.
//!
//! Cost: O(fast bodies × (log bodies + boxes met)) per step while anything is held;
//! O(released bodies × their links · log) per release.

use std::collections::BTreeSet;

use rapier3d::parry::bounding_volume::BoundingVolume;
use rapier3d::parry::query::DefaultQueryDispatcher;
use rapier3d::prelude::{QueryFilter, QueryFilterFlags, RigidBodyHandle};

use super::{key, SpeedUpState};
use crate::graph::{ContactGraph, EdgeKind, NodeId, NodeKind};
use crate::WorldView;

/// How many steps ahead a moving body's reach is looked at: the release is decided
/// after one step and applied before the next, so the body moves one step before
/// the released bodies are dynamic, and one more while Rapier solves their contact.
pub(crate) const REACH_STEPS: f32 = 2.0;

impl SpeedUpState {
    /// Queues a held body's release (once). O(pending releases).
    pub(super) fn queue_release(&mut self, h: RigidBodyHandle) {
        if self.is_fixated(h) && !self.to_release.contains(&h) {
            self.to_release.push(h);
            self.stats.releases = self.stats.releases.saturating_add(1);
        }
    }

    /// Frees the held bodies that a moving body is about to reach (see the module
    /// doc): each refreshed body faster than `release_speed` that is not sleepy, and
    /// each moving kinematic body. O(such bodies × (log bodies + boxes met)).
    pub(super) fn release_reached(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        refreshed: &[NodeId],
    ) {
        if self.held.is_empty() {
            return;
        }
        let mut hit: Vec<RigidBodyHandle> = Vec::new();
        for &n in refreshed {
            let Some(node) = graph.node(n) else { continue };
            let Some(h) = node.body() else { continue };
            let Some(rb) = view.bodies.get(h) else {
                continue;
            };
            let moving = match node.kind() {
                k if k.is_simulated() => {
                    node.is_awake()
                        && !self.is_sleepy(h)
                        && rb.linvel().length() > self.config.release_speed
                }
                NodeKind::Kinematic => crate::world::moves(rb),
                _ => false,
            };
            if !moving {
                continue;
            }
            match view.broad_phase {
                Some(bp) => {
                    let reach = (rb.linvel().length()
                        + rb.angvel().length() * body_radius(view, rb))
                        * view.dt
                        * REACH_STEPS;
                    let filter = QueryFilter::from(
                        QueryFilterFlags::ONLY_FIXED | QueryFilterFlags::EXCLUDE_SENSORS,
                    );
                    let query = bp.as_query_pipeline(
                        &DefaultQueryDispatcher,
                        view.bodies,
                        view.colliders,
                        filter,
                    );
                    for &c in rb.colliders() {
                        let Some(co) = view.colliders.get(c) else {
                            continue;
                        };
                        let aabb = co.compute_aabb().loosened(reach);
                        hit.extend(
                            query
                                .intersect_aabb_conservative(aabb)
                                .filter_map(|(_, other)| other.parent())
                                .filter(|&p| p != h && self.is_fixated(p)),
                        );
                    }
                }
                // No broad phase to ask: the held bodies it touches.
                None => {
                    for (m, _, e) in graph.neighbors(n) {
                        if e.kind() == EdgeKind::Physical && e.is_touching() {
                            hit.extend(graph.body_of(m).filter(|&mh| self.is_fixated(mh)));
                        }
                    }
                }
            }
        }
        for h in hit {
            self.queue_release(h);
        }
    }

    /// Spreads the queued releases through the held bodies' links, transitively (see
    /// [`super::SpeedUps::release_group`]). O(released bodies × their links · log).
    pub(super) fn spread_releases(&mut self) {
        if !self.config.release_group || self.to_release.is_empty() {
            return;
        }
        let mut queue: Vec<(u32, u32)> = self.to_release.iter().map(|&h| key(h)).collect();
        let mut seen: BTreeSet<(u32, u32)> = queue.iter().copied().collect();
        while let Some(k) = queue.pop() {
            let Some(held) = self.held.get(&k) else {
                continue;
            };
            let forward = held.links.iter().map(|&h| key(h));
            let back = self
                .linked
                .range((k, (0, 0))..=(k, (u32::MAX, u32::MAX)))
                .map(|&(_, held)| held);
            let next: Vec<(u32, u32)> = forward
                .chain(back)
                .filter(|m| self.held.contains_key(m))
                .collect();
            for m in next {
                if seen.insert(m) {
                    let h = self.held[&m].handle;
                    self.to_release.push(h);
                    self.stats.releases = self.stats.releases.saturating_add(1);
                    queue.push(m);
                }
            }
        }
    }

    /// Releases the held bodies whose remembered support is gone (a supporter removed,
    /// moved or released from under them): they fall as a sleeping body falls when
    /// what it rests on goes. O(unsupported bodies · log held).
    pub(super) fn release_unsupported(&mut self) {
        let gone: Vec<RigidBodyHandle> = self
            .unsupported
            .iter()
            .filter_map(|k| self.held.get(k).map(|held| held.handle))
            .collect();
        for h in gone {
            self.queue_release(h);
        }
    }

    /// Releases the refreshed held bodies that are no longer fixed in Rapier: the user
    /// gave them another type, and they are the user's again (the release keeps the
    /// type and velocities the user set, see [`super::hold::Held::give_back`]), with
    /// what they touched as for any release. O(refreshed bodies · log held).
    pub(super) fn yield_to_owner(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        refreshed: &[NodeId],
    ) {
        if self.held.is_empty() {
            return;
        }
        for &n in refreshed {
            let Some(h) = graph.body_of(n) else { continue };
            if self.is_fixated(h) && view.bodies.get(h).is_some_and(|rb| !rb.is_fixed()) {
                self.queue_release(h);
            }
        }
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
