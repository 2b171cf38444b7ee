//! Parking: a held body taken out of Rapier's active set (disabled for one step,
//! enabled again at the next pre-step), so that it costs what a sleeping body costs.

use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

use super::{key, SpeedUpState};
use crate::logic::WorldMut;
use crate::WorldView;

/// A held body's way out of Rapier's active set. Rapier keeps a body turned fixed in
/// its active set (its island manager returns early for fixed bodies), where it costs
/// far more than a sleeping body (`docs/ARCHITECTURE.md`, §7); disabling a body is the
/// one public way to take it out, and re-enabling a fixed body does not put it back.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) enum Park {
    /// Fixed, still in Rapier's active set.
    #[default]
    Active,
    /// Disabled for this one step: Rapier takes it out of its active set.
    Parking,
    /// Enabled again, fixed, out of Rapier's active set: it costs what a sleeping
    /// body costs.
    Parked,
}

impl SpeedUpState {
    /// Moves held bodies on their way out of Rapier's active set: those disabled at
    /// the last pre-step are enabled again (now parked), and the candidates chosen at
    /// the last analysis are disabled for one step, after checking them again against
    /// the world as it is now (the user may have changed them since). O(parking
    /// bodies + candidates' pairs).
    pub(super) fn park(
        &mut self,
        world: &mut WorldMut,
        user_passive: &dyn Fn(RigidBodyHandle) -> bool,
    ) {
        self.parked_now.clear();
        for h in std::mem::take(&mut self.parking_now) {
            let Some(held) = self.held.get_mut(&key(h)) else {
                continue;
            };
            if held.park == Park::Parking {
                held.park = Park::Parked;
                match world.bodies.get_mut(h) {
                    Some(rb) if !user_passive(h) => {
                        rb.set_enabled(true);
                        self.parked_now.push(h);
                    }
                    _ => {}
                }
            }
        }
        for h in std::mem::take(&mut self.to_park) {
            let Some(held) = self.held.get_mut(&key(h)) else {
                continue;
            };
            let parkable = held.park == Park::Active
                && world
                    .bodies
                    .get(h)
                    .is_some_and(|rb| rb.is_fixed() && rb.is_enabled())
                && world.impulse_joints.attached_joints(h).next().is_none()
                && world.multibody_joints.rigid_body_link(h).is_none();
            if parkable {
                held.park = Park::Parking;
                self.unparked.remove(&key(h));
                self.parking_now.push(h);
                if let Some(rb) = world.bodies.get_mut(h) {
                    rb.set_enabled(false);
                }
            }
        }
    }

    /// Chooses the held bodies to park at the next pre-step: in Rapier's active set,
    /// without joints, and whose every collider pair has a fixed partner and neither
    /// touches nor intersects (so that disabling the body for a step changes no
    /// contact, no event and no neighbour): the first
    /// [`hold_budget`](super::hold::hold_budget) of them in handle order, the others
    /// at the next analyses (a parking is a write Rapier answers as it answers a
    /// fixation). O(active held bodies × their pairs).
    pub(super) fn choose_parking(&mut self, view: &WorldView) {
        self.to_park.clear();
        let budget = super::hold::hold_budget(view.islands.num_active_bodies());
        for k in &self.unparked {
            let Some(held) = self.held.get(k) else {
                continue;
            };
            if held.park != Park::Active || self.to_release.contains(&held.handle) {
                continue;
            }
            let h = held.handle;
            let Some(rb) = view.bodies.get(h) else {
                continue;
            };
            // Held bodies are fixated awake, so an `Active` one is in Rapier's active set.
            if !rb.is_fixed() || !rb.is_enabled() {
                continue;
            }
            if view.impulse_joints.attached_joints(h).next().is_some()
                || view.multibody_joints.rigid_body_link(h).is_some()
            {
                continue;
            }
            let fixed_partner = |c: ColliderHandle| {
                view.colliders.get(c).is_some_and(|co| {
                    co.parent()
                        .is_none_or(|p| view.bodies.get(p).is_some_and(|b| b.is_fixed()))
                })
            };
            let quiet = rb.colliders().iter().all(|&c| {
                view.narrow_phase.contact_pairs_with(c).all(|p| {
                    let other = crate::coherence::pairs::other_collider(p, c);
                    !p.has_any_active_contact() && fixed_partner(other)
                }) && view
                    .narrow_phase
                    .intersection_pairs_with(c)
                    .next()
                    .is_none()
            });
            if quiet {
                self.to_park.push(h);
                if self.to_park.len() >= budget {
                    break;
                }
            }
        }
    }

    /// Whether a held body is out of Rapier's active set or on its way (disabled for
    /// this step by the layer, not by the user). O(log held).
    pub fn is_parked(&self, h: RigidBodyHandle) -> bool {
        self.held
            .get(&key(h))
            .is_some_and(|held| held.park != Park::Active)
    }

    /// The held bodies the layer disabled for this step to take them out of Rapier's
    /// active set (they are enabled again at the next pre-step; one released since is
    /// enabled already, and not listed). O(log held) per item.
    pub fn parking(&self) -> impl Iterator<Item = RigidBodyHandle> + '_ {
        self.parking_now.iter().copied().filter(|&h| {
            self.held
                .get(&key(h))
                .is_some_and(|held| held.park == Park::Parking)
        })
    }

    /// The held bodies the last pre-step enabled again after their step out of
    /// Rapier's active set: Rapier pairs their colliders anew in this step, so a
    /// sensor widened meanwhile may find them inside. O(1) per item.
    pub(crate) fn parked_now(&self) -> &[RigidBodyHandle] {
        &self.parked_now
    }
}
