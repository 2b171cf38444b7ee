//! Sphere pile: the many-body settling scene behind the overhead benchmark.
//!
//! `n` spheres of radius 0.5 fall from a 3D grid into an open-topped box and settle
//! into a pile a few layers deep, giving a large, dense contact graph that starts
//! empty, grows while the spheres land, churns while they settle and then goes
//! quiet — the full life cycle a contact-graph layer has to keep up with.
//!
//! Why it is built this way:
//! - The floor is about `sqrt(n / 4)` diameters across per side ([`floor_cells`]), so
//!   one square-packed layer holds about `n / 4` spheres and the pile is a few layers
//!   deep for any `n` (1,000 and 5,000 alike), not a single sheet nor a tall column.
//! - The drop grid sits entirely over the floor with at least 0.2 m between sphere
//!   surfaces, so no sphere starts in contact and no sphere can land outside. Its
//!   lowest layer is 1 m above the floor, so everything has landed within about a
//!   second and the pile has settled within ~3–5 simulated seconds.
//! - The ground and the four walls are five colliders on one fixed body,
//!   `"container"`: a single named body that tests and snapshots can refer to.
//! - A tiny jitter (±0.05 m per axis) breaks the grid's symmetry so the spheres pile up
//!   instead of landing in perfect columns. It comes from a seeded xorshift generator
//!   (no `rand` crate), so a given `(n, seed)` always builds the same world.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::jitter::Jitter;
use super::{new_world, Scene};

/// Radius of every sphere.
pub const RADIUS: Real = 0.5;
/// Half thickness of the container's floor and walls.
pub const WALL_HALF_THICKNESS: Real = 0.5;
/// Minimum distance between the centres of neighbouring spheres in the drop grid.
pub const DROP_SPACING: Real = 1.2;
/// Height of the lowest drop layer's centres above the floor.
pub const DROP_FIRST_Y: Real = 1.5;
/// Largest jitter applied to each coordinate of a drop position.
pub const JITTER: Real = 0.05;

/// Number of sphere diameters across each side of the floor for `n` spheres:
/// `ceil(sqrt(n / 4))`, at least 2.
pub fn floor_cells(n: usize) -> usize {
    let cells = ((n as f64) / 4.0).sqrt().ceil() as usize;
    cells.max(2)
}

/// Inner half width of the container (its inside spans `-h..h` in x and z) for `n`
/// spheres. The floor's top face is at `y = 0`.
pub fn inner_half_width(n: usize) -> Real {
    floor_cells(n) as Real * RADIUS
}

/// Height of the container's walls (from the floor's top face) for `n` spheres: one
/// metre above the highest drop position.
pub fn wall_height(n: usize) -> Real {
    let (_, _, layers) = drop_grid(n);
    DROP_FIRST_Y + (layers.saturating_sub(1)) as Real * DROP_SPACING + 1.0
}

/// Drop grid for `n` spheres: (columns per side, column spacing, number of layers).
fn drop_grid(n: usize) -> (usize, Real, usize) {
    let width = 2.0 * inner_half_width(n);
    let per_side = ((width / DROP_SPACING).floor() as usize).max(1);
    let spacing = width / per_side as Real;
    let per_layer = per_side * per_side;
    let layers = n.div_ceil(per_layer).max(1);
    (per_side, spacing, layers)
}

/// Builds a pile of `n` spheres dropped into a fixed container, with drop-position
/// jitter seeded by `seed`. `scene.bodies` holds only `"container"` (the fixed body
/// carrying the floor and the four walls); the spheres are all the other bodies of
/// `scene.world.bodies`, inserted layer by layer from the bottom.
pub fn sphere_pile(n: usize, seed: u64) -> Scene {
    pile(n, seed, "sphere_pile", |_| ColliderBuilder::ball(RADIUS))
}

/// Half extent of the boxes of [`mixed_pile`]: their faces are as far from their
/// centre as a sphere's surface less 0.1 m, so that the drop grid's gaps hold.
pub const MIXED_BOX_HALF: Real = 0.4;

/// The pile of [`sphere_pile`] with every second body a box: balls (radius
/// [`RADIUS`]) and axis-aligned cubes (half extent [`MIXED_BOX_HALF`]) alternate in
/// insertion order, dropped from the same grid. Boxes rest on faces and stack, balls
/// roll into the gaps: a pile with both Rapier's ball and box manifolds, part of which
/// Rapier can put to sleep. Bodies as in [`sphere_pile`].
pub fn mixed_pile(n: usize, seed: u64) -> Scene {
    pile(n, seed, "mixed_pile", |i| {
        if i % 2 == 0 {
            ColliderBuilder::ball(RADIUS)
        } else {
            ColliderBuilder::cuboid(MIXED_BOX_HALF, MIXED_BOX_HALF, MIXED_BOX_HALF)
        }
    })
}

/// The container and `n` bodies from the drop grid, the `i`-th with `shape(i)`.
fn pile(
    n: usize,
    seed: u64,
    name: &'static str,
    shape: impl Fn(usize) -> ColliderBuilder,
) -> Scene {
    let mut world = new_world();
    let h = inner_half_width(n);
    let t = WALL_HALF_THICKNESS;
    let height = wall_height(n);
    let outer = h + 2.0 * t; // walls overlap the floor's edge and each other's ends

    let container = world.insert_body(RigidBodyBuilder::fixed());
    let parts = [
        // floor, top face at y = 0
        (Vector::new(0.0, -t, 0.0), Vector::new(outer, t, outer)),
        // walls at x = ±(h + t) and z = ±(h + t)
        (
            Vector::new(-(h + t), height / 2.0, 0.0),
            Vector::new(t, height / 2.0, outer),
        ),
        (
            Vector::new(h + t, height / 2.0, 0.0),
            Vector::new(t, height / 2.0, outer),
        ),
        (
            Vector::new(0.0, height / 2.0, -(h + t)),
            Vector::new(h, height / 2.0, t),
        ),
        (
            Vector::new(0.0, height / 2.0, h + t),
            Vector::new(h, height / 2.0, t),
        ),
    ];
    for (centre, half) in parts {
        world.insert_collider(
            ColliderBuilder::cuboid(half.x, half.y, half.z).translation(centre),
            Some(container),
        );
    }

    let (per_side, spacing, _) = drop_grid(n);
    let mut rng = Jitter::new(seed, JITTER);
    for i in 0..n {
        let layer = i / (per_side * per_side);
        let in_layer = i % (per_side * per_side);
        let (ix, iz) = (in_layer % per_side, in_layer / per_side);
        let x = -h + spacing * (ix as Real + 0.5) + rng.next();
        let z = -h + spacing * (iz as Real + 0.5) + rng.next();
        let y = DROP_FIRST_Y + layer as Real * DROP_SPACING + rng.next();
        world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(x, y, z)),
            shape(i),
        );
    }

    Scene {
        name,
        world,
        bodies: vec![("container", container)],
        script: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pile_of_200_settles_inside_the_container() {
        let n = 200;
        let mut scene = sphere_pile(n, 1);
        let container = scene.body("container").unwrap();
        assert_eq!(scene.bodies.len(), 1);
        assert_eq!(scene.world.bodies.len(), n + 1);
        assert_eq!(scene.world.bodies[container].colliders().len(), 5);
        scene.run_plain(0, 500);

        let h = inner_half_width(n);
        // 200 spheres on an 8 x 8 floor: about 3 to 4 layers.
        let max_y = 5.0 * RADIUS * 2.0;
        let mut top: Real = 0.0;
        let mut speed_sum = 0.0;
        for (handle, body) in scene.world.bodies.iter() {
            if handle == container {
                continue;
            }
            let p = body.translation();
            let lim = h - RADIUS + 0.02;
            assert!(
                p.x.abs() <= lim && p.z.abs() <= lim,
                "sphere outside: {p:?}"
            );
            assert!(p.y >= RADIUS - 0.02 && p.y < max_y, "sphere height: {p:?}");
            top = top.max(p.y);
            speed_sum += body.linvel().length();
        }
        // Settled: several layers deep and nearly at rest.
        assert!(top > 2.0 * 2.0 * RADIUS, "pile too flat, top = {top}");
        let mean_speed = speed_sum / n as Real;
        assert!(mean_speed < 0.05, "not settled, mean speed {mean_speed}");
    }

    #[test]
    fn mixed_pile_alternates_balls_and_boxes_and_stays_in_the_container() {
        let n = 200;
        let mut scene = mixed_pile(n, 1);
        let container = scene.body("container").unwrap();
        let shapes: Vec<bool> = scene
            .world
            .bodies
            .iter()
            .filter(|(h, _)| *h != container)
            .map(|(_, b)| {
                scene.world.colliders[b.colliders()[0]]
                    .shape()
                    .as_ball()
                    .is_some()
            })
            .collect();
        assert_eq!(shapes.len(), n);
        assert_eq!(shapes.iter().filter(|b| **b).count(), n / 2);
        assert!(shapes.iter().step_by(2).all(|b| *b));
        // The drop grid's gaps hold for boxes too (faces, axis-aligned).
        let (_, spacing, _) = drop_grid(n);
        assert!(spacing - 2.0 * JITTER - RADIUS - MIXED_BOX_HALF >= 0.1);
        scene.run_plain(0, 500);
        let h = inner_half_width(n);
        for (handle, body) in scene.world.bodies.iter() {
            if handle == container {
                continue;
            }
            let p = body.translation();
            assert!(
                p.x.abs() < h && p.z.abs() < h && p.y > 0.0,
                "body outside: {p:?}"
            );
        }
    }

    #[test]
    fn drop_grid_is_separated_and_over_the_floor() {
        for n in [1, 7, 200, 1000, 5000] {
            let (per_side, spacing, layers) = drop_grid(n);
            assert!(spacing >= DROP_SPACING);
            assert!(per_side * per_side * layers >= n);
            assert!(spacing - 2.0 * (RADIUS + JITTER) >= 0.1);
            let h = inner_half_width(n);
            // The outermost centres, jittered, leave room for a radius to the walls.
            assert!(spacing * 0.5 - JITTER - RADIUS >= 0.0, "n = {n}");
            assert!(
                (spacing * per_side as Real - 2.0 * h).abs() < 1e-4,
                "n = {n}"
            );
            assert!(wall_height(n) > DROP_FIRST_Y + (layers - 1) as Real * DROP_SPACING);
        }
        assert_eq!(floor_cells(1000), 16);
        assert_eq!(floor_cells(5000), 36);
    }

    #[test]
    fn same_seed_same_world_other_seed_other_world() {
        let pos = |s: &Scene| {
            s.world
                .bodies
                .iter()
                .map(|(_, b)| b.translation())
                .collect::<Vec<_>>()
        };
        let a = sphere_pile(50, 7);
        let b = sphere_pile(50, 7);
        let c = sphere_pile(50, 8);
        assert_eq!(pos(&a), pos(&b));
        assert_ne!(pos(&a), pos(&c));
    }
}
