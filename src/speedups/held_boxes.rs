//! The held bodies' boxes: a bounding-volume tree over the colliders of held bodies
//! alone, in which a moving body's reach is looked up (`release.rs`). Rapier's broad
//! phase holds every collider, so a reach looked up there meets the whole moving pile
//! around a falling body before the few held bodies in it; this tree meets only the
//! held ones.
//!
//! Kept in step with the held records: a body's boxes are put in when it is held and
//! taken out when it is released, and read again when a held body is refreshed. A
//! held body does not move (Rapier steps it as a fixed body); one the user moves in
//! place is refreshed, as everywhere in the layer, by a requested full sync. Left out
//! of snapshots: built from the held records when a snapshot is restored.
//!
//! Cost: O(colliders · log boxes) per body put in or taken out; a query O(log boxes +
//! boxes met).

use std::collections::BTreeMap;

use rapier3d::parry::bounding_volume::Aabb;
use rapier3d::parry::partitioning::Bvh;
use rapier3d::prelude::{ColliderHandle, ColliderSet, RigidBodyHandle, RigidBodySet};

/// A box of the tree: its leaf, its collider, the held body.
pub(super) type Entry = (usize, ColliderHandle, RigidBodyHandle);

/// The colliders of held bodies, by the boxes they take up.
#[derive(Clone, Default)]
pub(super) struct HeldBoxes {
    /// The tree; a leaf's index is its collider's index in Rapier's collider set.
    bvh: Bvh,
    /// Each leaf's collider and the held body it belongs to, by leaf index.
    leaves: Vec<Option<(ColliderHandle, RigidBodyHandle)>>,
    /// Each body's leaves, by the body's key.
    of_body: BTreeMap<(u32, u32), Vec<u32>>,
}

impl HeldBoxes {
    /// The tree of the held records' bodies, built anew (a restored state).
    /// O(held · colliders · log).
    pub(super) fn of<T: HeldHandle>(
        held: &BTreeMap<(u32, u32), T>,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
    ) -> Self {
        let mut boxes = Self::default();
        for h in held.values().map(HeldHandle::handle) {
            boxes.put(bodies, colliders, h);
        }
        boxes
    }

    /// Reads again the boxes of `refreshed`, the held bodies refreshed this step.
    /// O(refreshed · colliders · log boxes).
    pub(super) fn refresh(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        refreshed: impl IntoIterator<Item = RigidBodyHandle>,
    ) {
        for h in refreshed {
            self.reread(bodies, colliders, h);
        }
    }

    /// Reads again the boxes of the held bodies whose colliders are not those the
    /// tree holds (a collider added to or removed from a held body; the pre-step
    /// looks when the collider count changed, as the graph does). O(held ·
    /// colliders), plus O(colliders · log boxes) per body read again.
    pub(super) fn resync(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        held: impl IntoIterator<Item = RigidBodyHandle>,
    ) {
        for h in held {
            let kept = self
                .of_body
                .get(&super::key(h))
                .map_or(&[][..], Vec::as_slice);
            let same = boxes_of(bodies, colliders, h)
                .map(|(c, _)| c.into_raw_parts().0)
                .eq(kept.iter().copied())
                && kept.iter().all(|&l| {
                    self.leaves
                        .get(l as usize)
                        .copied()
                        .flatten()
                        .is_some_and(|(c, _)| colliders.get(c).is_some())
                });
            if !same {
                self.reread(bodies, colliders, h);
            }
        }
    }

    /// Reads a held body's boxes again. O(colliders · log boxes).
    fn reread(&mut self, bodies: &RigidBodySet, colliders: &ColliderSet, h: RigidBodyHandle) {
        self.take_out(h);
        self.put(bodies, colliders, h);
    }

    /// The boxes a tree built anew from `held` would hold, as [`Self::entries`] gives
    /// them, body by body (not in leaf order), without building it. O(held ·
    /// colliders).
    pub(super) fn expected<'a, T: HeldHandle>(
        held: &'a BTreeMap<(u32, u32), T>,
        bodies: &'a RigidBodySet,
        colliders: &'a ColliderSet,
    ) -> impl Iterator<Item = Entry> + 'a {
        held.values().map(HeldHandle::handle).flat_map(move |h| {
            boxes_of(bodies, colliders, h).map(move |(c, _)| (c.into_raw_parts().0 as usize, c, h))
        })
    }

    /// The held bodies with a collider whose box meets `aabb`, once per collider met,
    /// in the tree's order. O(log boxes + boxes met).
    pub(super) fn meeting<'a>(
        &'a self,
        aabb: &'a Aabb,
    ) -> impl Iterator<Item = RigidBodyHandle> + 'a {
        self.bvh
            .intersect_aabb(aabb)
            .filter_map(|leaf| self.leaves.get(leaf as usize).copied().flatten())
            .map(|(_, h)| h)
    }

    /// The boxes, each as (leaf, collider, body), in leaf order. O(leaf slots).
    pub(super) fn entries(&self) -> impl Iterator<Item = Entry> + '_ {
        self.leaves
            .iter()
            .enumerate()
            .filter_map(|(i, e)| e.map(|(c, h)| (i, c, h)))
    }

    /// Puts in the boxes of a held body's colliders (see [`boxes_of`]). O(colliders ·
    /// log boxes).
    pub(super) fn put(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        h: RigidBodyHandle,
    ) {
        let mut mine = Vec::new();
        for (c, aabb) in boxes_of(bodies, colliders, h) {
            let leaf = c.into_raw_parts().0;
            let slot = leaf as usize;
            if self.leaves.len() <= slot {
                self.leaves.resize(slot + 1, None);
            }
            // A leaf left by a removed collider whose index Rapier gave to this one.
            if let Some((_, old)) = self.leaves[slot] {
                if let Some(list) = self.of_body.get_mut(&super::key(old)) {
                    list.retain(|&l| l != leaf);
                }
                self.bvh.remove(leaf);
            }
            self.bvh.insert(aabb, leaf);
            self.leaves[slot] = Some((c, h));
            mine.push(leaf);
        }
        if !mine.is_empty() {
            self.of_body.entry(super::key(h)).or_default().extend(mine);
        }
    }

    /// Takes out a body's boxes. O(its leaves · log boxes).
    pub(super) fn take_out(&mut self, h: RigidBodyHandle) {
        for leaf in self.of_body.remove(&super::key(h)).unwrap_or_default() {
            self.bvh.remove(leaf);
            if let Some(slot) = self.leaves.get_mut(leaf as usize) {
                *slot = None;
            }
        }
    }

    /// Checks the tree against `held`: every leaf belongs to a held body, and every
    /// body's leaves are its own. O(boxes · log held).
    #[cfg(test)]
    pub(super) fn consistent<T>(&self, held: &BTreeMap<(u32, u32), T>) -> bool {
        let listed: usize = self.of_body.values().map(Vec::len).sum();
        self.of_body.iter().all(|(k, ls)| {
            held.contains_key(k)
                && ls.iter().all(|&l| {
                    self.leaves
                        .get(l as usize)
                        .copied()
                        .flatten()
                        .is_some_and(|(_, h)| super::key(h) == *k)
                })
        }) && self.entries().count() == listed
    }

    /// How many boxes the tree holds. O(leaf slots).
    #[cfg(test)]
    fn len(&self) -> usize {
        self.entries().count()
    }
}

/// The colliders of body `h` the tree holds, with their boxes: not sensors (a reach
/// passes through them), and finite. O(its colliders).
fn boxes_of<'a>(
    bodies: &'a RigidBodySet,
    colliders: &'a ColliderSet,
    h: RigidBodyHandle,
) -> impl Iterator<Item = (ColliderHandle, Aabb)> + 'a {
    let mine = bodies.get(h).map_or(&[][..], |rb| rb.colliders());
    mine.iter().filter_map(move |&c| {
        let co = colliders.get(c)?;
        let aabb = co.compute_aabb();
        (!co.is_sensor() && aabb.mins.is_finite() && aabb.maxs.is_finite()).then_some((c, aabb))
    })
}

/// The boxes, not the tree's shape: a tree built anew from the same boxes (a
/// restored state) prints the same.
impl std::fmt::Debug for HeldBoxes {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_list().entries(self.entries()).finish()
    }
}

/// A held record's body (the tree is generic over the record, for its tests).
pub(super) trait HeldHandle {
    /// The held body.
    fn handle(&self) -> RigidBodyHandle;
}

impl HeldHandle for super::hold::Held {
    fn handle(&self) -> RigidBodyHandle {
        self.handle
    }
}

impl HeldHandle for RigidBodyHandle {
    fn handle(&self) -> RigidBodyHandle {
        *self
    }
}

#[cfg(test)]
mod tests {
    use super::{BTreeMap, HeldBoxes};
    use rapier3d::prelude::*;

    fn world() -> (PhysicsWorld, Vec<RigidBodyHandle>) {
        let mut w = PhysicsWorld::default();
        let mut hs = Vec::new();
        for i in 0..4 {
            let at = Vector::new(i as f32 * 2.0, 0.0, 0.0);
            let h = w.bodies.insert(RigidBodyBuilder::fixed().translation(at));
            let co = ColliderBuilder::cuboid(0.5, 0.5, 0.5);
            w.colliders.insert_with_parent(co, h, &mut w.bodies);
            hs.push(h);
        }
        (w, hs)
    }

    fn keyed(hs: &[RigidBodyHandle]) -> BTreeMap<(u32, u32), RigidBodyHandle> {
        hs.iter().map(|&h| (super::super::key(h), h)).collect()
    }

    fn around(x: f32) -> Aabb {
        Aabb::new(
            Vector::new(x - 0.1, -0.1, -0.1),
            Vector::new(x + 0.1, 0.1, 0.1),
        )
    }

    #[test]
    fn a_query_meets_the_held_boxes_it_overlaps_and_no_other() {
        let (w, hs) = world();
        let held = keyed(&hs[..3]);
        let boxes = HeldBoxes::of(&held, &w.bodies, &w.colliders);
        assert_eq!(boxes.len(), 3);
        assert_eq!(boxes.meeting(&around(2.0)).collect::<Vec<_>>(), vec![hs[1]]);
        assert_eq!(boxes.meeting(&around(1.0)).count(), 0);
        // The fourth body is fixed but not held.
        assert_eq!(boxes.meeting(&around(6.0)).count(), 0);
        assert!(boxes.consistent(&held));
        let mut expected: Vec<_> = HeldBoxes::expected(&held, &w.bodies, &w.colliders).collect();
        expected.sort_by_key(|e| e.0);
        assert!(expected.into_iter().eq(boxes.entries()));
    }

    #[test]
    fn bodies_go_in_when_held_and_out_when_released() {
        let (w, hs) = world();
        let mut boxes = HeldBoxes::default();
        boxes.put(&w.bodies, &w.colliders, hs[0]);
        boxes.put(&w.bodies, &w.colliders, hs[3]);
        assert_eq!(boxes.len(), 2);
        boxes.take_out(hs[0]);
        // A held body refreshed is read again, not doubled.
        boxes.refresh(&w.bodies, &w.colliders, [hs[3]]);
        assert_eq!(boxes.len(), 1);
        assert!(boxes.consistent(&keyed(&hs[3..])));
        let all = Aabb::new(Vector::splat(-10.0), Vector::splat(10.0));
        assert_eq!(boxes.meeting(&all).collect::<Vec<_>>(), vec![hs[3]]);
        assert_eq!(boxes.meeting(&around(0.0)).count(), 0);
    }

    #[test]
    fn a_collider_added_to_or_removed_from_a_held_body_is_read_at_the_resync() {
        let (mut w, hs) = world();
        let held = keyed(&hs[..2]);
        let mut boxes = HeldBoxes::of(&held, &w.bodies, &w.colliders);
        let far = ColliderBuilder::ball(0.5).translation(Vector::new(0.0, 5.0, 0.0));
        let added = w.colliders.insert_with_parent(far, hs[0], &mut w.bodies);
        boxes.resync(&w.bodies, &w.colliders, hs[..2].iter().copied());
        let up = Aabb::new(Vector::new(-0.1, 4.9, -0.1), Vector::new(0.1, 5.1, 0.1));
        assert_eq!(boxes.meeting(&up).collect::<Vec<_>>(), vec![hs[0]]);
        w.remove_collider(added);
        boxes.resync(&w.bodies, &w.colliders, hs[..2].iter().copied());
        assert_eq!(boxes.meeting(&up).count(), 0);
        let anew = HeldBoxes::of(&held, &w.bodies, &w.colliders);
        assert!(boxes.entries().eq(anew.entries()));
    }

    #[test]
    fn a_tree_built_anew_prints_as_the_one_kept_in_step() {
        let (w, hs) = world();
        let mut kept = HeldBoxes::default();
        for &h in hs.iter().rev() {
            kept.put(&w.bodies, &w.colliders, h);
        }
        kept.take_out(hs[1]);
        let mut held = keyed(&hs);
        held.remove(&super::super::key(hs[1]));
        let anew = HeldBoxes::of(&held, &w.bodies, &w.colliders);
        assert_eq!(format!("{kept:?}"), format!("{anew:?}"));
    }
}
