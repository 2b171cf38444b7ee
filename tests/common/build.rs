//! World-building shorthands: the few setups the tests share, spelled once. Each
//! inserts into a `PhysicsWorld` with Rapier's own calls and returns the handles
//! Rapier issued; a position is anything that converts into a `Vector`
//! (`[x, y, z]` too). Values that matter to a test stay in the test: these builders
//! fix only the shapes every caller uses alike.

use rapier3d::prelude::*;

/// The height of the [`ground`]'s top face (its box, 1 m high, centred at the origin).
pub const GROUND_TOP: Real = 0.5;

/// A fixed ground body at the origin with a 10 m × 1 m × 10 m box (its top at
/// [`GROUND_TOP`]): the floor of most small tests.
pub fn ground(world: &mut PhysicsWorld) -> (RigidBodyHandle, ColliderHandle) {
    world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    )
}

/// The [`ground`] box as static geometry: a parentless collider.
pub fn static_ground(world: &mut PhysicsWorld) -> ColliderHandle {
    world.insert_collider(ColliderBuilder::cuboid(5.0, 0.5, 5.0), None)
}

/// A new world (Rapier's default gravity and `dt`) with a [`ground`]; returns the
/// ground body.
pub fn world_with_ground() -> (PhysicsWorld, RigidBodyHandle) {
    let mut world = PhysicsWorld::new();
    let (ground, _) = ground(&mut world);
    (world, ground)
}

/// The fuzz arena's floor: a fixed body at y = -0.25 with a 6 m × 0.5 m × 6 m box
/// (its top at y = 0).
pub fn arena_floor(world: &mut PhysicsWorld) -> (RigidBodyHandle, ColliderHandle) {
    world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.25, 0.0)),
        ColliderBuilder::cuboid(3.0, 0.25, 3.0),
    )
}

/// A dynamic body at `at` (for a collider of the test's own).
pub fn dynamic_at(at: impl Into<Vector>) -> RigidBodyBuilder {
    RigidBodyBuilder::dynamic().translation(at.into())
}

/// A fixed body at `at` (for a collider of the test's own).
pub fn fixed_at(at: impl Into<Vector>) -> RigidBodyBuilder {
    RigidBodyBuilder::fixed().translation(at.into())
}

/// A dynamic ball of `radius` at `at`.
pub fn ball_at(
    world: &mut PhysicsWorld,
    at: impl Into<Vector>,
    radius: Real,
) -> (RigidBodyHandle, ColliderHandle) {
    world.insert(dynamic_at(at), ColliderBuilder::ball(radius))
}

/// A dynamic cube of half extent `half` at `at`.
pub fn box_at(
    world: &mut PhysicsWorld,
    at: impl Into<Vector>,
    half: Real,
) -> (RigidBodyHandle, ColliderHandle) {
    world.insert(dynamic_at(at), ColliderBuilder::cuboid(half, half, half))
}

/// A fixed cube of half extent `half` at `at` (a post, a block).
pub fn fixed_box_at(
    world: &mut PhysicsWorld,
    at: impl Into<Vector>,
    half: Real,
) -> (RigidBodyHandle, ColliderHandle) {
    world.insert(fixed_at(at), ColliderBuilder::cuboid(half, half, half))
}

/// On an [`arena_floor`]: a multibody chain of two balls (radius 0.25), its root at
/// y = 1 and its link at y = 0.5 hinged about z, and a free ball overlapping the
/// link; returns the root and the link.
pub fn multibody_chain(world: &mut PhysicsWorld) -> (RigidBodyHandle, RigidBodyHandle) {
    arena_floor(world);
    let root = ball_at(world, [0.0, 1.0, 0.0], 0.25).0;
    let link = ball_at(world, [0.0, 0.5, 0.0], 0.25).0;
    world
        .insert_multibody_joint(root, link, chain_joint())
        .unwrap();
    ball_at(world, [0.0, 0.5, 0.0], 0.25); // overlaps the link
    (root, link)
}

/// The hinge of [`multibody_chain`]: revolute about z, the link 0.6 m below.
pub fn chain_joint() -> RevoluteJointBuilder {
    RevoluteJointBuilder::new(Vector::Z).local_anchor2(Vector::new(0.0, 0.6, 0.0))
}

/// A 0.25 m ball at (-2, 0.5, 0) flying at 6 m/s along +x: thrown at a body resting at
/// the origin (a held body is released when it is hit).
pub fn hammer(world: &mut PhysicsWorld) -> RigidBodyHandle {
    let h = world.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(-2.0, 0.5, 0.0))
            .linvel(Vector::new(6.0, 0.0, 0.0)),
    );
    world.insert_collider(ColliderBuilder::ball(0.25), Some(h));
    h
}

/// What Rapier says touches a body: the owners of the colliders in its contact pairs
/// with an active contact.
pub fn rapier_touching(
    world: &PhysicsWorld,
    body: RigidBodyHandle,
) -> std::collections::BTreeSet<String> {
    let mut out = std::collections::BTreeSet::new();
    for &c in world.bodies[body].colliders() {
        for pair in world.narrow_phase.contact_pairs_with(c) {
            if !pair.has_any_active_contact() {
                continue;
            }
            let other = if pair.collider1 == c {
                pair.collider2
            } else {
                pair.collider1
            };
            let t = match world.colliders[other].parent() {
                Some(b) if b == body => continue,
                Some(b) => rapier_contact_graph::Touching::Body(b),
                None => rapier_contact_graph::Touching::Collider(other),
            };
            out.insert(format!("{t:?}"));
        }
    }
    out
}

/// A stack of `n` dynamic cubes of half extent `half`, the lowest resting at `base`
/// (its centre), each next one `2 * half` above; returns them from the bottom up.
pub fn stack_of_boxes(
    world: &mut PhysicsWorld,
    base: impl Into<Vector>,
    n: usize,
    half: Real,
) -> Vec<RigidBodyHandle> {
    let base = base.into();
    (0..n)
        .map(|i| box_at(world, base + Vector::Y * (2.0 * half * i as Real), half).0)
        .collect()
}

/// Throws a heavy ball (radius 0.35 m, density 4, CCD) at 8 m/s along +x, from
/// x = −3 m at 0.8 m height: into the side of `rcg_scenes::box_pile`'s piles.
pub fn throw_heavy_ball(world: &mut PhysicsWorld) -> RigidBodyHandle {
    let body = RigidBodyBuilder::dynamic()
        .translation(Vector::new(-3.0, 0.8, 0.0))
        .linvel(Vector::new(8.0, 0.0, 0.0))
        .ccd_enabled(true);
    world
        .insert(body, ColliderBuilder::ball(0.35).density(4.0))
        .0
}

/// On a [`ground`]: a floor of `side` × `side` cubes of half extent `half`, side by
/// side and touching, one layer deep, centred on the origin; returns the world and
/// the cubes in insertion order.
pub fn floor_of_boxes(side: usize, half: Real) -> (PhysicsWorld, Vec<RigidBodyHandle>) {
    let (mut world, _) = world_with_ground();
    let start = -(side as Real - 1.0) * half;
    let boxes = (0..side * side)
        .map(|i| {
            let (x, z) = ((i % side) as Real, (i / side) as Real);
            let at = [
                start + 2.0 * half * x,
                GROUND_TOP + half,
                start + 2.0 * half * z,
            ];
            box_at(&mut world, at, half).0
        })
        .collect();
    (world, boxes)
}

/// A slab (1.2 m × 0.2 m × 1.2 m, `density`) over the middle of a [`floor_of_boxes`]
/// of cubes of half extent `half`, 5 cm above it, coming down at `speed`.
pub fn slab_over_floor(
    world: &mut PhysicsWorld,
    half: Real,
    density: Real,
    speed: Real,
) -> RigidBodyHandle {
    let y = GROUND_TOP + 2.0 * half + 0.05 + 0.1;
    world
        .insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, y, 0.0))
                .linvel(Vector::new(0.0, -speed, 0.0)),
            ColliderBuilder::cuboid(0.6, 0.1, 0.6).density(density),
        )
        .0
}
