//! The proptest generator of operation sequences: 20–60 operations, steps the most
//! frequent, with weights that keep the world busy but small, and what each
//! configuration adds or leaves out (tests only).

use super::{Call, Config, Op, Second, Ty, Who};
use proptest::prelude::*;
use proptest::strategy::{BoxedStrategy, Union};
use rapier_contact_graph::KindSet;

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

/// A mask of event kinds: under the configurations that want touching tracking in
/// effect, nine in ten leave out the kinds that need every pair read (a subscription
/// to one of them switches the layer to proximity tracking while it lives).
fn kinds(config: Config) -> BoxedStrategy<u16> {
    let touching = config.expects_touching() == Some(true);
    (any::<u16>(), 0u8..10)
        .prop_map(move |(m, d)| {
            if touching && d != 0 {
                m & !every_pair_bits()
            } else {
                m
            }
        })
        .boxed()
}

fn every_pair_bits() -> u16 {
    rapier_contact_graph::EventKind::ALL
        .iter()
        .filter(|k| KindSet::NEEDS_EVERY_PAIR.contains(**k))
        .fold(0, |m, k| m | 1 << (*k as u8))
}

fn who() -> impl Strategy<Value = Who> {
    prop_oneof![
        idx().prop_map(Who::Any),
        idx().prop_map(Who::Held),
        idx().prop_map(Who::Parked),
    ]
}

fn call() -> impl Strategy<Value = Call> {
    let v = || -4i8..=4;
    prop_oneof![
        3 => (v(), v(), v()).prop_map(|(x, y, z)| Call::Impulse { x, y, z }),
        2 => (v(), v(), v()).prop_map(|(x, y, z)| Call::Linvel { x, y, z }),
        2 => ty().prop_map(Call::Type),
        2 => any::<bool>().prop_map(Call::Enabled),
        1 => Just(Call::Sleep),
        2 => Just(Call::Wake),
        1 => any::<bool>().prop_map(|keep_colliders| Call::Remove { keep_colliders }),
    ]
}

/// The operations of the configuration: every world and layer operation; the
/// user's own calls (more often where bodies are held); the speed-ups switched only
/// where a preset runs (observe-only configurations stay observe-only); steps the
/// layer does not see and the second layer where [`Config::unseen_steps`] allows.
pub fn op(config: Config) -> impl Strategy<Value = Op> {
    let mut v = common_ops(config);
    let speedups = config.speedups().is_some();
    v.push((
        if speedups { 10 } else { 5 },
        (who(), call()).prop_map(|(w, c)| Op::User(w, c)).boxed(),
    ));
    if speedups {
        v.push((1, prop::option::of(0u8..128).prop_map(Op::SpeedUps).boxed()));
        v.push((1, Just(Op::Preset).boxed()));
        v.push((1, any::<bool>().prop_map(Op::Monitor).boxed()));
    }
    if config.unseen_steps() {
        v.push((2, (1u8..=3).prop_map(Op::Unseen).boxed()));
        v.push((1, Just(Op::Second(Second::Attach)).boxed()));
        v.push((1, Just(Op::Second(Second::Detach)).boxed()));
        v.push((
            3,
            (1u8..=5).prop_map(|n| Op::Second(Second::Step(n))).boxed(),
        ));
    }
    Union::new_weighted(v)
}

fn common_ops(config: Config) -> Vec<(u32, BoxedStrategy<Op>)> {
    vec![
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
            (kinds(config), 0u8..9, prop::option::of(idx()))
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
                kinds(config),
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
        (2, any::<bool>().prop_map(Op::Touching).boxed()),
        (1, Just(Op::FullSync).boxed()),
        (20, (1u8..=5).prop_map(Op::Step).boxed()),
        // Long runs let bodies settle and sleep, and the speed-ups hold them.
        (
            if config.speedups().is_some() { 6 } else { 2 },
            (20u8..=40).prop_map(Op::Step).boxed(),
        ),
    ]
}

/// Whether an operation lets an observe-only layer change motion (the twin is
/// dropped at the first one).
fn changes_motion(op: &Op) -> bool {
    matches!(
        op,
        Op::IgnorePair(..) | Op::IgnoreBetween(..) | Op::Passive(..) | Op::SpeedUps(Some(_))
    )
}

/// 20–60 operations of the configuration. Under observe-only configurations half of
/// the sequences have no operation that lets the layer change motion (rules,
/// passive bodies), so that the twin is compared all along.
pub fn ops(config: Config) -> impl Strategy<Value = Vec<Op>> {
    (any::<bool>(), prop::collection::vec(op(config), 20..=60)).prop_map(move |(pure, mut ops)| {
        if pure && config.observe_only() {
            ops.retain(|op| !changes_motion(op));
        }
        ops
    })
}
