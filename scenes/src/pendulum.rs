//! Pendulum and wall: a three-link Rapier multibody pendulum released from horizontal
//! swings down and strikes a fixed wall.
//!
//! It is the scene for containers (the paper's `Multibody` node, Table 1's M) and for
//! contacts of articulated bodies: the links are joined by Rapier *multibody* joints
//! (reduced coordinates), so the layer sees one multibody whose dynamic links are
//! `Link` nodes with structural edges to a `Multibody` container, and the links hit
//! the wall within about 80 steps. The anchor is a fixed body without a collider at
//! the pivot; fixed bodies insulate, so the container holds the three links only. The
//! chain starts straight along +x from the pivot and swings down through the vertical
//! to the −x side, where the wall stands one half chain length from the pivot. The
//! joints disable contacts between the two bodies they join (neighbouring links meet
//! at the joint and would otherwise push each other apart); the ground is far below
//! the swinging chain and only makes the picture complete.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RevoluteJointBuilder, RigidBodyBuilder};

use super::{new_world, Scene};

/// Number of links in the chain.
pub const LINKS: usize = 3;
/// Half length of each link (a cuboid along x).
pub const LINK_HALF: Real = 0.3;
/// Half thickness of each link.
pub const LINK_THICK: Real = 0.05;
/// Density of the links (kg/m³, about wood's): with Rapier's default density of 1 a
/// link would weigh 6 g, and the default joint damping of Rapier's multibody joints
/// (0.1 per angular degree of freedom) would let it creep down instead of swing.
pub const LINK_DENSITY: Real = 1000.0;
/// The pivot (the anchor body's position).
pub const PIVOT: [Real; 3] = [0.0, 3.0, 0.0];
/// The wall's face towards the pendulum is the plane `x = WALL_FACE_X`.
pub const WALL_FACE_X: Real = -0.9;

/// The names of the links, from the pivot outwards.
const NAMES: [&str; LINKS] = ["l0", "l1", "l2"];

/// Builds the scene. Bodies: `"anchor"` (fixed, no collider, at [`PIVOT`]), the dynamic
/// links `"l0"` (hinged on the anchor) to `"l2"` (the free end), `"wall"` and
/// `"ground"` (fixed). Joints: revolute multibody joints about `z`, contacts between
/// joined bodies disabled.
pub fn pendulum_wall() -> Scene {
    let mut world = new_world();

    let (ground, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, -0.5, 0.0)),
        ColliderBuilder::cuboid(5.0, 0.5, 5.0),
    );
    let [px, py, pz] = PIVOT;
    let wall_half_y = 0.5 * (py + 0.5);
    let (wall, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(WALL_FACE_X - 0.1, wall_half_y, pz)),
        ColliderBuilder::cuboid(0.1, wall_half_y, 1.0),
    );
    let anchor = world.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(px, py, pz)));

    let mut bodies = vec![("anchor", anchor)];
    let mut parent = anchor;
    for (i, name) in NAMES.iter().enumerate() {
        let x = px + LINK_HALF * (2 * i + 1) as Real;
        let (link, _) = world.insert(
            RigidBodyBuilder::dynamic().translation(Vector::new(x, py, pz)),
            ColliderBuilder::cuboid(LINK_HALF, LINK_THICK, LINK_THICK).density(LINK_DENSITY),
        );
        // The parent's anchor: the anchor body's origin, or the previous link's +x end.
        let anchor1 = if i == 0 {
            Vector::ZERO
        } else {
            Vector::new(LINK_HALF, 0.0, 0.0)
        };
        let joint = RevoluteJointBuilder::new(Vector::Z)
            .local_anchor1(anchor1)
            .local_anchor2(Vector::new(-LINK_HALF, 0.0, 0.0))
            .contacts_enabled(false);
        world
            .insert_multibody_joint(parent, link, joint)
            .expect("a chain has no cycle");
        bodies.push((*name, link));
        parent = link;
    }
    bodies.push(("wall", wall));
    bodies.push(("ground", ground));

    Scene {
        name: "pendulum_wall",
        world,
        bodies,
        script: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::{collider, touching};
    use rapier3d::prelude::ColliderHandle;

    #[test]
    fn the_chain_swings_into_the_wall() {
        let mut scene = pendulum_wall();
        assert_eq!(scene.world.integration_parameters.dt, 0.01);
        let wall = collider(&scene, "wall");
        let last = collider(&scene, "l2");
        let links: Vec<ColliderHandle> = NAMES.iter().map(|n| collider(&scene, n)).collect();
        let mut first_hit = None;
        let mut last_link_hit = None;
        for step in 1..=150u64 {
            scene.world.step();
            if first_hit.is_none() && links.iter().any(|&l| touching(&scene, l, wall)) {
                first_hit = Some(step);
            }
            if last_link_hit.is_none() && touching(&scene, last, wall) {
                last_link_hit = Some(step);
            }
            // The joints hold: l0's hinge end stays at the pivot.
            let l0 = &scene.world.bodies[scene.body("l0").unwrap()];
            let hinge = l0.position() * Vector::new(-LINK_HALF, 0.0, 0.0);
            let pivot = Vector::from(PIVOT);
            assert!(
                (hinge - pivot).length() < 0.02,
                "step {step}: hinge at {hinge:?}"
            );
        }
        let first = first_hit.expect("no link touched the wall in 150 steps");
        let last_hit = last_link_hit.expect("the last link never touched the wall");
        assert!(first >= 20, "hit the wall too early, at step {first}");
        assert!(last_hit <= 150);
        // Nothing went through the wall.
        for name in NAMES {
            let p = scene.world.bodies[scene.body(name).unwrap()].translation();
            assert!(
                p.x > WALL_FACE_X - 0.05,
                "{name} went through the wall: {p:?}"
            );
        }
    }

    #[test]
    fn names_structure_and_determinism() {
        let a = pendulum_wall();
        assert_eq!(
            a.bodies.iter().map(|b| b.0).collect::<Vec<_>>(),
            ["anchor", "l0", "l1", "l2", "wall", "ground"]
        );
        assert!(a.world.bodies[a.body("anchor").unwrap()]
            .colliders()
            .is_empty());
        assert_eq!(a.world.multibody_joints.multibodies().count(), 1);
        let mb = a.world.multibody_joints.multibodies().next().unwrap();
        assert_eq!(
            mb.num_links(),
            LINKS + 1,
            "the fixed anchor is the root link"
        );
        let mut a = a;
        let mut b = pendulum_wall();
        a.run_plain(0, 120);
        b.run_plain(0, 120);
        for (name, h) in &a.bodies {
            let hb = b.body(name).unwrap();
            assert_eq!(a.world.bodies[*h].position(), b.world.bodies[hb].position());
        }
    }
}
