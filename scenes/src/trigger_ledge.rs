//! Trigger ledge: a ball rolls along a table-top, through a trigger volume, off the
//! ledge and onto a floor below.
//!
//! It is the scene for trigger volumes: in about 250 steps one body enters a trigger,
//! leaves it, loses its support, falls and lands, so a single run shows
//! `SensorStarted`, `SensorStopped`, a `ContactStopped` with the table and a `ContactStarted` with
//! the floor, in that order. The trigger is a cuboid *sensor* collider on its own
//! fixed body (so it has a body handle for names, and the layer makes the sensor a
//! `Sensor` node); it floats a little above the table-top so that it never overlaps
//! the table itself, only the ball rolling under it. The ball starts resting on the
//! table with an initial velocity of 2 m/s along +x; friction turns the slide into a
//! roll within a few steps, and a rolling ball does not fall asleep, so `can_sleep`
//! keeps its default. All sizes are chosen so the events are well apart in time
//! (entry at step 38, exit at step 100, leaving the table at step 168, landing at
//! step 221).

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderBuilder, RigidBodyBuilder};

use super::{new_world, Scene};

/// Height of the table-top (the top face of the table).
pub const TABLE_TOP: Real = 2.0;
/// The table spans `x` in `[-TABLE_HALF_X, TABLE_HALF_X]`; the ledge is at `+TABLE_HALF_X`.
pub const TABLE_HALF_X: Real = 1.25;
/// Radius of the ball.
pub const BALL_RADIUS: Real = 0.2;
/// Initial `x` of the ball's centre.
pub const BALL_START_X: Real = -1.0;
/// Initial speed of the ball along +x, in m/s.
pub const BALL_SPEED: Real = 2.0;
/// The trigger spans `x` in `[-TRIGGER_HALF_X, TRIGGER_HALF_X]`.
pub const TRIGGER_HALF_X: Real = 0.25;
/// The trigger's bottom face, a little above the table-top (it never overlaps the table).
pub const TRIGGER_BOTTOM: Real = TABLE_TOP + 0.1;
/// Height of the floor's top face.
pub const FLOOR_TOP: Real = 0.0;

/// Builds the scene. Bodies: `"table"`, `"floor"` and `"trigger"` (fixed; the trigger's
/// only collider is a sensor) and `"ball"` (dynamic, moving at [`BALL_SPEED`] along +x).
pub fn trigger_ledge() -> Scene {
    let mut world = new_world();

    let (table, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, TABLE_TOP - 0.25, 0.0)),
        ColliderBuilder::cuboid(TABLE_HALF_X, 0.25, 1.0),
    );
    // Wide enough that the ball still rolls on it long after landing.
    let (floor, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(0.0, FLOOR_TOP - 0.5, 0.0)),
        ColliderBuilder::cuboid(10.0, 0.5, 3.0),
    );
    let trigger_half_y = 0.35;
    let (trigger, _) = world.insert(
        RigidBodyBuilder::fixed().translation(Vector::new(
            0.0,
            TRIGGER_BOTTOM + trigger_half_y,
            0.0,
        )),
        ColliderBuilder::cuboid(TRIGGER_HALF_X, trigger_half_y, 1.0).sensor(true),
    );
    let (ball, _) = world.insert(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(BALL_START_X, TABLE_TOP + BALL_RADIUS, 0.0))
            .linvel(Vector::new(BALL_SPEED, 0.0, 0.0)),
        ColliderBuilder::ball(BALL_RADIUS),
    );

    Scene {
        name: "trigger_ledge",
        world,
        bodies: vec![
            ("table", table),
            ("floor", floor),
            ("trigger", trigger),
            ("ball", ball),
        ],
        script: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_util::{collider, touching};

    /// Steps 1..=300 (1-based): when the ball was inside the trigger, when it last
    /// touched the table, when it first touched the floor.
    struct Story {
        inside: Vec<u64>,
        last_on_table: Option<u64>,
        first_on_floor: Option<u64>,
        min_x_inside: Real,
        max_x_inside: Real,
    }

    fn run(scene: &mut Scene) -> Story {
        let (trigger, ball) = (collider(scene, "trigger"), collider(scene, "ball"));
        let (table, floor) = (collider(scene, "table"), collider(scene, "floor"));
        let hb = scene.body("ball").unwrap();
        let mut s = Story {
            inside: Vec::new(),
            last_on_table: None,
            first_on_floor: None,
            min_x_inside: Real::MAX,
            max_x_inside: Real::MIN,
        };
        for step in 1..=300u64 {
            scene.world.step();
            let x = scene.world.bodies[hb].translation().x;
            if scene.world.intersection_pair(trigger, ball) == Some(true) {
                s.inside.push(step);
                s.min_x_inside = s.min_x_inside.min(x);
                s.max_x_inside = s.max_x_inside.max(x);
            }
            if touching(scene, ball, table) {
                s.last_on_table = Some(step);
            }
            if s.first_on_floor.is_none() && touching(scene, ball, floor) {
                s.first_on_floor = Some(step);
            }
        }
        s
    }

    #[test]
    fn the_ball_crosses_the_trigger_then_falls_onto_the_floor() {
        let mut scene = trigger_ledge();
        assert_eq!(scene.world.integration_parameters.dt, 0.01);
        let s = run(&mut scene);

        // One contiguous stay in the trigger, entered and left well within the run.
        assert!(!s.inside.is_empty(), "the ball never entered the trigger");
        let (enter, exit) = (s.inside[0], *s.inside.last().unwrap());
        assert_eq!(s.inside.len() as u64, exit - enter + 1, "one stay only");
        assert!((10..80).contains(&enter), "entered at step {enter}");
        assert!(exit < 150, "left at step {exit}");
        let reach = TRIGGER_HALF_X + BALL_RADIUS;
        assert!(s.min_x_inside > -reach - 0.05 && s.max_x_inside < reach + 0.05);

        // Then it leaves the table, and lands on the floor.
        let off = s.last_on_table.expect("the ball touched the table");
        let land = s.first_on_floor.expect("the ball never landed");
        assert!(
            exit < off && off < land,
            "exit {exit}, off {off}, land {land}"
        );
        assert!(land <= 260, "landed at step {land}");

        let w = &scene.world;
        let ball = w.bodies[scene.body("ball").unwrap()].translation();
        assert!(ball.x > TABLE_HALF_X, "ball x = {}", ball.x);
        assert!(
            (ball.y - (FLOOR_TOP + BALL_RADIUS)).abs() < 0.02,
            "ball y = {}",
            ball.y
        );
        assert!(ball.z.abs() < 0.01, "ball drifted sideways: {ball:?}");
    }

    #[test]
    fn names_and_determinism() {
        let a = trigger_ledge();
        assert_eq!(
            a.bodies.iter().map(|b| b.0).collect::<Vec<_>>(),
            ["table", "floor", "trigger", "ball"]
        );
        for name in ["table", "floor", "trigger"] {
            assert!(a.world.bodies[a.body(name).unwrap()].is_fixed(), "{name}");
        }
        assert!(a.world.colliders[collider(&a, "trigger")].is_sensor());
        assert!(!a.world.colliders[collider(&a, "table")].is_sensor());
        let mut a = a;
        let mut b = trigger_ledge();
        a.run_plain(0, 200);
        b.run_plain(0, 200);
        for (name, h) in &a.bodies {
            let hb = b.body(name).unwrap();
            assert_eq!(a.world.bodies[*h].position(), b.world.bodies[hb].position());
        }
    }
}
