//! Small helpers over Rapier's types: writes to colliders that Rapier would not
//! notice on its own, a pose's bits and finiteness, and the bodies the layer may
//! write to.

use rapier3d::geometry::Collider;

/// Makes Rapier's next narrow phase evaluate the collider's pairs again, even if
/// neither side moves. Rapier re-evaluates a pair only when a body of it is awake or a
/// collider carries a narrow-phase change flag, and `set_active_hooks` and
/// `set_active_collision_types` set none: a rule's hook flags, or a widening, on a
/// resting or fixed pair would otherwise wait until something moves. The collision
/// groups are changed and set back, which leaves them as they were and sets Rapier's
/// `GROUPS` change flag (narrow-phase update only; like any such change, Rapier wakes
/// the bodies the collider touches). O(1).
pub(crate) fn reevaluate_pairs(collider: &mut Collider) {
    let groups = collider.collision_groups();
    let mut other = groups;
    other.memberships = !groups.memberships;
    other.filter = !groups.filter;
    collider.set_collision_groups(other);
    collider.set_collision_groups(groups);
}

/// A pose as the bits of its translation and rotation: for exact comparison and
/// ordering. O(1).
pub(crate) fn pose_bits(p: &rapier3d::math::Pose) -> [u32; 7] {
    let (t, r) = (p.translation, p.rotation);
    [t.x, t.y, t.z, r.x, r.y, r.z, r.w].map(f32::to_bits)
}

/// Whether a pose's translation and rotation are finite. O(1).
pub(crate) fn pose_is_finite(p: &rapier3d::math::Pose) -> bool {
    p.translation.is_finite() && p.rotation.is_finite()
}

/// The body, to write to, unless it is disabled or its pose or velocity is not
/// finite. Such a body is Rapier's quarantine's: a body with non-finite state is
/// quarantined at the end of Rapier's step, and the disable is processed in the next.
/// A write in between flags the body modified, and Rapier then handles it before its
/// narrow phase has dropped the body's pairs (Rapier's island checks assert on that in
/// debug builds). The layer leaves such bodies alone. O(1).
pub(crate) fn live_body_mut(
    bodies: &mut rapier3d::dynamics::RigidBodySet,
    h: rapier3d::dynamics::RigidBodyHandle,
) -> Option<&mut rapier3d::dynamics::RigidBody> {
    let rb = bodies.get(h)?;
    let live = rb.is_enabled()
        && pose_is_finite(rb.position())
        && rb.linvel().is_finite()
        && rb.angvel().is_finite();
    if live {
        bodies.get_mut(h)
    } else {
        None
    }
}
