//! What the layer reads of a Rapier world.
//!
//! Chosen: the layer *takes the parts* through a borrowed [`WorldView`], so it works
//! with a `PhysicsWorld` (`WorldView::from(&world)`) and with users who drive
//! `PhysicsPipeline::step` on their own sets (bevy_rapier style) alike. For the common
//! case [`crate::ContactLayer::step`] takes `&mut PhysicsWorld` and runs Rapier's step
//! itself.
//!
//! Rejected: owning the `PhysicsWorld` inside the layer. It would hide Rapier's public
//! fields behind our API and force every user call through a wrapper.

use rapier3d::math::Vector;
use rapier3d::prelude::{
    BroadPhaseBvh, ColliderSet, ImpulseJointSet, IslandManager, MultibodyJointSet, NarrowPhase,
    PhysicsWorld, RigidBodyHandle, RigidBodySet,
};

/// Borrowed parts of a Rapier world, read after a step.
#[derive(Clone, Copy)]
pub struct WorldView<'a> {
    /// Gravity (for "is supported" queries and the monitor).
    pub gravity: Vector,
    /// The time step of the last step, in seconds.
    pub dt: f32,
    /// Rigid bodies.
    pub bodies: &'a RigidBodySet,
    /// Colliders.
    pub colliders: &'a ColliderSet,
    /// The narrow phase (its contact pairs become physical edges).
    pub narrow_phase: &'a NarrowPhase,
    /// The broad phase, if at hand. Not read by the layer: the speed-ups look a
    /// moving body's reach up among the held bodies' own boxes (see
    /// `SpeedUps::release_speed`). Kept so that views built by hand still compile.
    pub broad_phase: Option<&'a BroadPhaseBvh>,
    /// Islands (the active set tells which bodies are awake).
    pub islands: &'a IslandManager,
    /// Impulse joints.
    pub impulse_joints: &'a ImpulseJointSet,
    /// Multibody joints.
    pub multibody_joints: &'a MultibodyJointSet,
    /// The bodies Rapier's NaN quarantine reset and disabled in the last step
    /// (`world.quarantine().bodies()`; empty if unknown). The monitor reports each as
    /// an escape.
    pub quarantined: &'a [RigidBodyHandle],
}

impl<'a> From<&'a PhysicsWorld> for WorldView<'a> {
    fn from(w: &'a PhysicsWorld) -> Self {
        Self {
            gravity: w.gravity,
            dt: w.integration_parameters.dt,
            bodies: &w.bodies,
            colliders: &w.colliders,
            narrow_phase: &w.narrow_phase,
            broad_phase: Some(&w.broad_phase),
            islands: &w.islands,
            impulse_joints: &w.impulse_joints,
            multibody_joints: &w.multibody_joints,
            quarantined: w.quarantine().bodies(),
        }
    }
}

impl<'a> From<&'a mut PhysicsWorld> for WorldView<'a> {
    fn from(w: &'a mut PhysicsWorld) -> Self {
        Self::from(&*w)
    }
}

/// A view given by reference (it is `Copy`): the calls taking `impl Into<WorldView>`
/// accept `&view` as they accept `&world`.
impl<'a> From<&WorldView<'a>> for WorldView<'a> {
    fn from(v: &WorldView<'a>) -> Self {
        *v
    }
}

/// Whether a body has any velocity at all (a scripted body that moves cannot hold a
/// body still). O(1).
#[inline]
pub(crate) fn moves(rb: &rapier3d::prelude::RigidBody) -> bool {
    rb.linvel() != Vector::ZERO || rb.angvel() != Vector::ZERO
}
