//! The proptest generator of operation sequences: 20–60 operations, steps the most
//! frequent, with weights that keep the world busy but small (tests only).

use super::{Op, Ty};
use proptest::prelude::*;
use proptest::strategy::Union;

fn xz() -> impl Strategy<Value = i8> {
    -4i8..=4
}
fn y() -> impl Strategy<Value = u8> {
    0u8..=6
}
fn idx() -> impl Strategy<Value = u8> {
    any::<u8>()
}
/// A sparse node mask: one to three bits among the first twelve.
fn mask() -> impl Strategy<Value = u16> {
    prop::collection::vec(0u16..12, 1..=3).prop_map(|v| v.iter().fold(0, |m, b| m | 1 << b))
}
fn ty() -> impl Strategy<Value = Ty> {
    prop_oneof![
        Just(Ty::Dynamic),
        Just(Ty::Fixed),
        Just(Ty::KinematicVelocity),
        Just(Ty::KinematicPosition)
    ]
}

pub fn op() -> impl Strategy<Value = Op> {
    Union::new_weighted(vec![
        (
            8,
            (xz(), y(), xz(), 0u8..4)
                .prop_map(|(x, y, z, r)| Op::Ball { x, y, z, r })
                .boxed(),
        ),
        (
            5,
            (xz(), y(), xz(), 0u8..4)
                .prop_map(|(x, y, z, r)| Op::Cube { x, y, z, r })
                .boxed(),
        ),
        (
            2,
            (xz(), y(), xz())
                .prop_map(|(x, y, z)| Op::FixedBody { x, y, z })
                .boxed(),
        ),
        (
            2,
            (xz(), y(), xz())
                .prop_map(|(x, y, z)| Op::Static { x, y, z })
                .boxed(),
        ),
        (
            2,
            (xz(), y(), xz(), -2i8..=2, -2i8..=2, any::<bool>())
                .prop_map(|(x, y, z, vx, vz, velocity_based)| Op::Kinematic {
                    x,
                    y,
                    z,
                    vx,
                    vz,
                    velocity_based,
                })
                .boxed(),
        ),
        (
            3,
            (prop::option::of(idx()), xz(), y(), xz())
                .prop_map(|(on, x, y, z)| Op::Sensor { on, x, y, z })
                .boxed(),
        ),
        (
            2,
            (idx(), -2i8..=2)
                .prop_map(|(on, x)| Op::ExtraCollider { on, x })
                .boxed(),
        ),
        (3, idx().prop_map(Op::RemoveBody).boxed()),
        (2, idx().prop_map(Op::RemoveCollider).boxed()),
        (1, idx().prop_map(Op::ToggleSensor).boxed()),
        (
            2,
            (idx(), prop::option::of(idx()))
                .prop_map(|(c, b)| Op::SetParent(c, b))
                .boxed(),
        ),
        (
            1,
            (idx(), any::<u8>())
                .prop_map(|(c, m)| Op::CollisionGroups(c, m))
                .boxed(),
        ),
        (
            1,
            (idx(), any::<u8>())
                .prop_map(|(c, m)| Op::SolverGroups(c, m))
                .boxed(),
        ),
        (
            1,
            (idx(), any::<bool>())
                .prop_map(|(c, on)| Op::ColliderEnabled(c, on))
                .boxed(),
        ),
        (
            1,
            (idx(), any::<u8>())
                .prop_map(|(c, m)| Op::UserHooks(c, m))
                .boxed(),
        ),
        (
            1,
            (idx(), any::<bool>())
                .prop_map(|(c, on)| Op::UserEvents(c, on))
                .boxed(),
        ),
        (
            1,
            (idx(), any::<u8>())
                .prop_map(|(c, r)| Op::SetShape(c, r))
                .boxed(),
        ),
        (
            3,
            (idx(), ty()).prop_map(|(i, t)| Op::SetType(i, t)).boxed(),
        ),
        (
            3,
            (idx(), xz(), y(), xz())
                .prop_map(|(body, x, y, z)| Op::Teleport { body, x, y, z })
                .boxed(),
        ),
        (
            1,
            (idx(), xz(), y(), xz())
                .prop_map(|(collider, x, y, z)| Op::MoveStatic { collider, x, y, z })
                .boxed(),
        ),
        (
            3,
            (idx(), -4i8..=4, -4i8..=4, -4i8..=4)
                .prop_map(|(body, vx, vy, vz)| Op::Velocity { body, vx, vy, vz })
                .boxed(),
        ),
        (2, idx().prop_map(Op::Sleep).boxed()),
        (1, idx().prop_map(Op::Wake).boxed()),
        (
            3,
            (idx(), any::<bool>())
                .prop_map(|(i, on)| Op::Passive(i, on))
                .boxed(),
        ),
        (
            3,
            (idx(), idx(), any::<bool>())
                .prop_map(|(a, b, revolute)| Op::Joint { a, b, revolute })
                .boxed(),
        ),
        (1, idx().prop_map(Op::RemoveJoint).boxed()),
        (
            2,
            (idx(), idx())
                .prop_map(|(a, b)| Op::Multibody { a, b })
                .boxed(),
        ),
        (1, idx().prop_map(Op::RemoveMultibody).boxed()),
        (
            3,
            (idx(), idx())
                .prop_map(|(a, b)| Op::IgnorePair(a, b))
                .boxed(),
        ),
        (
            2,
            (mask(), mask())
                .prop_map(|(x, y)| Op::IgnoreBetween(x, y))
                .boxed(),
        ),
        (2, idx().prop_map(Op::RemoveRule).boxed()),
        (1, mask().prop_map(Op::Composite).boxed()),
        (1, idx().prop_map(Op::RemoveComposite).boxed()),
        (1, any::<u8>().prop_map(Op::Timer).boxed()),
        (1, idx().prop_map(Op::RemoveTimer).boxed()),
        (
            2,
            (any::<u16>(), 0u8..9, prop::option::of(idx()))
                .prop_map(|(kinds, capacity, node)| Op::Subscribe {
                    kinds,
                    capacity,
                    node,
                })
                .boxed(),
        ),
        (
            1,
            (
                any::<u16>(),
                prop::option::of(idx()),
                prop::option::of(idx()),
            )
                .prop_map(|(kinds, body, collider)| Op::SubscribeHandle {
                    kinds,
                    body,
                    collider,
                })
                .boxed(),
        ),
        (1, idx().prop_map(Op::Unsubscribe).boxed()),
        (1, idx().prop_map(Op::DropReceiver).boxed()),
        (2, prop::option::of(0u8..128).prop_map(Op::SpeedUps).boxed()),
        (2, any::<bool>().prop_map(Op::Touching).boxed()),
        (1, Just(Op::FullSync).boxed()),
        (20, (1u8..=5).prop_map(Op::Step).boxed()),
        (2, (20u8..=40).prop_map(Op::Step).boxed()),
    ])
}

/// Half of the sequences start with `Touching(true)`: they run in touching mode
/// (`Harness::with_mode`), with touching tracking in effect until an operation
/// switches it to proximity.
pub fn ops() -> impl Strategy<Value = Vec<Op>> {
    (any::<bool>(), prop::collection::vec(op(), 20..=60)).prop_map(|(touching, mut ops)| {
        if touching {
            ops.insert(0, Op::Touching(true));
        }
        ops
    })
}
