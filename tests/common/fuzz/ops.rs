//! The operation language: what a sequence is made of, and the grid and indices that
//! keep every operation meaningful (see the module documentation of
//! `tests/fuzz_operations.rs`).

use rapier_contact_graph::rapier3d::prelude::*;
use rapier_contact_graph::{EventKind, KindSet, NodeId};

/// A body type to switch to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ty {
    Dynamic,
    Fixed,
    KinematicVelocity,
    KinematicPosition,
}

impl Ty {
    pub(super) fn rapier(self) -> RigidBodyType {
        match self {
            Ty::Dynamic => RigidBodyType::Dynamic,
            Ty::Fixed => RigidBodyType::Fixed,
            Ty::KinematicVelocity => RigidBodyType::KinematicVelocityBased,
            Ty::KinematicPosition => RigidBodyType::KinematicPositionBased,
        }
    }
}

/// Which body a user's own Rapier call goes to (index modulo the candidates; a
/// kind without candidates falls back to the next: parked, held, any).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Who {
    /// Any body, in Rapier's slot order.
    Any(u8),
    /// A body the layer holds (`LayerAnalysis::holds`: fixated by the speed-ups, or
    /// asleep in Rapier).
    Held(u8),
    /// A held body the speed-ups took out of Rapier's active set
    /// (`SpeedUpState::is_parked`: disabled for this step, or parked since).
    Parked(u8),
}

/// A user's own Rapier call on a body, as a Rapier user writes it (the layer is not
/// told).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Call {
    /// `RigidBody::apply_impulse(.., true)` (×0.5 N·s per unit mass).
    Impulse { x: i8, y: i8, z: i8 },
    /// `RigidBody::set_linvel(.., true)` (×0.5 m/s).
    Linvel { x: i8, y: i8, z: i8 },
    /// `RigidBody::set_body_type(.., true)`.
    Type(Ty),
    /// `RigidBody::set_enabled`.
    Enabled(bool),
    /// `RigidBody::sleep()`.
    Sleep,
    /// `RigidBody::wake_up(true)`.
    Wake,
    /// `RigidBodySet::remove` with the islands, colliders and joints (colliders kept
    /// as parentless ones with `keep_colliders`).
    Remove { keep_colliders: bool },
}

/// The second layer on the same world (two subsystems of a game taking turns).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Second {
    /// `ContactLayer::new()` (if there is none).
    Attach,
    /// `ContactLayer::detach`.
    Detach,
    /// n steps (1..=5) of the second layer's `step` instead of the first's.
    Step(u8),
}

/// One operation. Grid coordinates: x, z in -4..=4 (×0.5 m), y in 0..=6 (0.5 m +
/// ×0.5 m above the floor). Indices are taken modulo the live objects.
#[derive(Clone, Debug)]
pub enum Op {
    /// A dynamic ball of radius 0.25 + 0.1·(r % 4).
    Ball {
        x: i8,
        y: u8,
        z: i8,
        r: u8,
    },
    /// A dynamic box of half extent 0.25 + 0.1·(r % 4).
    Cube {
        x: i8,
        y: u8,
        z: i8,
        r: u8,
    },
    /// A fixed body with a box collider.
    FixedBody {
        x: i8,
        y: u8,
        z: i8,
    },
    /// A parentless solid collider (static geometry).
    Static {
        x: i8,
        y: u8,
        z: i8,
    },
    /// A kinematic body with a velocity (×0.5 m/s).
    Kinematic {
        x: i8,
        y: u8,
        z: i8,
        vx: i8,
        vz: i8,
        velocity_based: bool,
    },
    /// A sensor ball (radius 0.6) on a body, or parentless at (x, y, z).
    Sensor {
        on: Option<u8>,
        x: i8,
        y: u8,
        z: i8,
    },
    /// An extra solid ball collider on a body, offset by x·0.25 m.
    ExtraCollider {
        on: u8,
        x: i8,
    },
    RemoveBody(u8),
    RemoveCollider(u8),
    ToggleSensor(u8),
    /// `ColliderSet::set_parent`: moves a collider to another body, or detaches it.
    SetParent(u8, Option<u8>),
    /// In-place collider changes: collision groups (memberships, filter
    /// bits from the mask), solver groups, the enabled flag, the user's own hook and
    /// event flags, and the shape (a ball of radius 0.2 + 0.1·(r % 4)).
    CollisionGroups(u8, u8),
    SolverGroups(u8, u8),
    ColliderEnabled(u8, bool),
    UserHooks(u8, u8),
    UserEvents(u8, bool),
    SetShape(u8, u8),
    SetType(u8, Ty),
    Teleport {
        body: u8,
        x: i8,
        y: u8,
        z: i8,
    },
    /// Moves a parentless collider (skipped for attached ones).
    MoveStatic {
        collider: u8,
        x: i8,
        y: u8,
        z: i8,
    },
    /// Sets a body's linear velocity (×0.5 m/s), waking it.
    Velocity {
        body: u8,
        vx: i8,
        vy: i8,
        vz: i8,
    },
    Sleep(u8),
    Wake(u8),
    Passive(u8, bool),
    Joint {
        a: u8,
        b: u8,
        revolute: bool,
    },
    RemoveJoint(u8),
    Multibody {
        a: u8,
        b: u8,
    },
    RemoveMultibody(u8),
    /// `Rule::ignore_pair` of two candidate nodes (bodies, static colliders,
    /// triggers).
    IgnorePair(u8, u8),
    /// `Rule::ignore_between` of two sets of candidate nodes (bit i: candidate i).
    IgnoreBetween(u16, u16),
    RemoveRule(u8),
    /// Declares a composite of the dynamic (`Dynamic`) nodes selected by the mask.
    Composite(u16),
    RemoveComposite(u8),
    /// A timer of period 0.02·(p % 10 + 1) s.
    Timer(u8),
    RemoveTimer(u8),
    /// Subscribes to the kinds in the mask (bit = `EventKind as u8`), bounded to
    /// `capacity` events (0: unbounded), optionally filtered by one live node.
    Subscribe {
        kinds: u16,
        capacity: u8,
        node: Option<u8>,
    },
    /// Subscribes (unbounded) to the kinds in the mask, filtered by Rapier handle: a
    /// live body, a live collider, or both (`Filter::with_bodies`, `with_colliders`).
    SubscribeHandle {
        kinds: u16,
        body: Option<u8>,
        collider: Option<u8>,
    },
    Unsubscribe(u8),
    DropReceiver(u8),
    /// `speedups_mut().set(Some(rcg_lab::table5::combination(bits % 128)))`, or `None`.
    SpeedUps(Option<u8>),
    /// `set_tracking`: touching tracking (Rapier's events) or proximity tracking.
    Touching(bool),
    FullSync,
    /// n steps (1..=40).
    Step(u8),
    /// A user's own Rapier call on a body, held or parked ones included.
    User(Who, Call),
    /// n steps (1..=3) of Rapier's `PhysicsWorld::step`, which the layer does not see.
    Unseen(u8),
    /// A second layer on the same world.
    Second(Second),
    /// The monitor repairing (`MonitorMode::Repair`, default thresholds) or off.
    Monitor(bool),
    /// The configuration's preset speed-ups again (`speedups_mut().set(Some(preset))`); in
    /// a configuration without speed-ups, `speedups_mut().set(None)`.
    Preset,
}

pub(super) fn grid(x: i8, y: u8, z: i8) -> Vector {
    Vector::new(
        f32::from(x.clamp(-4, 4)) * 0.5,
        0.5 + f32::from(y % 7) * 0.5,
        f32::from(z.clamp(-4, 4)) * 0.5,
    )
}

pub(super) fn vel(v: i8) -> f32 {
    f32::from(v.clamp(-4, 4)) * 0.5
}

pub(super) fn raw(h: RigidBodyHandle) -> (u32, u32) {
    h.into_raw_parts()
}

pub(super) fn pick<T: Copy>(v: &[T], i: u8) -> Option<T> {
    if v.is_empty() {
        None
    } else {
        Some(v[usize::from(i) % v.len()])
    }
}

pub(super) fn pick_mask(v: &[NodeId], mask: u16) -> Vec<NodeId> {
    v.iter()
        .take(16)
        .enumerate()
        .filter(|(i, _)| mask & (1 << i) != 0)
        .map(|(_, &n)| n)
        .collect()
}

pub(super) fn kinds_of(mask: u16) -> KindSet {
    let kinds: Vec<EventKind> = EventKind::ALL
        .iter()
        .copied()
        .filter(|k| mask & (1 << (*k as u8)) != 0)
        .collect();
    KindSet::of(&kinds)
}
