//! The twin of observe-only configurations: a plain Rapier world given the same world
//! operations and stepped by Rapier alone (`PhysicsWorld::step`, no hooks, no event
//! handler). The crate promises that a layer without rules, passive bodies, speed-ups
//! or monitor changes no trajectory bit, though it adds `COLLISION_EVENTS` to
//! colliders and, with widening, changes sensors' collision types: after every step
//! the two worlds must agree bit for bit: poses, velocities, body types, enabled
//! and sleep flags.
//!
//! Widened sensors (`set_trigger_widening`, the proximity configuration) are a
//! documented change of the sensors' collision types: before each step the twin's
//! colliders get the types the layer gave the world's (widened, or given back when a
//! sensor turns solid), set as the layer sets them (its collision groups changed and
//! set back, so that Rapier evaluates its pairs again),
//! so that the twin is the plain Rapier world *with the same settings*, and what is
//! compared is what the layer does beyond them. (What the widened types do to Rapier's own results is a question of
//! its own: `limit_*widen*` in `tests/fuzz_regressions_tracking.rs`.)

use rapier_contact_graph::rapier3d::prelude::*;

use super::Harness;

/// What is compared of a body: its handle, pose, velocities, and state bits.
type BodyBits = ((u32, u32), [u32; 13], [bool; 4], u8);

fn body_bits(world: &PhysicsWorld) -> Vec<BodyBits> {
    world
        .bodies
        .iter()
        .map(|(h, rb)| {
            let p = rb.position();
            let (v, w) = (rb.linvel(), rb.angvel());
            let bits = [
                p.translation.x,
                p.translation.y,
                p.translation.z,
                p.rotation.x,
                p.rotation.y,
                p.rotation.z,
                p.rotation.w,
                v.x,
                v.y,
                v.z,
                w.x,
                w.y,
                w.z,
            ]
            .map(f32::to_bits);
            let flags = [
                rb.is_sleeping(),
                rb.is_enabled(),
                rb.is_fixed(),
                rb.is_kinematic(),
            ];
            (h.into_raw_parts(), bits, flags, rb.colliders().len() as u8)
        })
        .collect()
}

impl Harness {
    /// Applies a world operation to the world and, while there is one, to the twin.
    /// The handles `f` uses are the world's: the twin's are the same, as both sets
    /// saw the same insertions and removals.
    pub(super) fn both(&mut self, f: impl Fn(&mut PhysicsWorld)) {
        f(&mut self.world);
        if let Some(t) = &mut self.twin {
            f(t);
        }
    }

    /// The layer may change motion from now on (a rule, a passive body, the
    /// speed-ups): the twin is dropped.
    pub(super) fn diverge(&mut self) {
        if self.twin.take().is_some() && self.trace {
            eprintln!("  (the twin is dropped: the layer may change motion)");
        }
    }

    /// Steps the twin with Rapier alone, after the world's step (whoever made it),
    /// and compares the two.
    pub(super) fn step_twin(&mut self) -> Result<(), String> {
        let Some(t) = &mut self.twin else {
            return Ok(());
        };
        let widened: Vec<_> = self
            .world
            .colliders
            .iter()
            // No operation sets collision types: a difference is the layer's widening,
            // or its giving back a collider turned solid.
            .filter(|(c, col)| {
                t.colliders
                    .get(*c)
                    .is_some_and(|tc| tc.active_collision_types() != col.active_collision_types())
            })
            .map(|(c, col)| (c, col.active_collision_types()))
            .collect();
        // The layer's own `COLLISION_EVENTS` writes: one added to a collider Rapier
        // already stepped (after a step the layer did not see) changes trajectories,
        // a documented limit
        // (`limit_flags_added_after_an_unseen_step_change_no_trajectory` in
        // `tests/fuzz_regressions_unseen.rs`), so while
        // the harness steers clear of what is open or documented the twin gets them
        // too, at the same time (the user's own writes reach both worlds already).
        if self.steer {
            let flags: Vec<_> = self
                .world
                .colliders
                .iter()
                .filter(|(c, col)| {
                    t.colliders.get(*c).is_some_and(|tc| {
                        tc.active_events().contains(ActiveEvents::COLLISION_EVENTS)
                            != col.active_events().contains(ActiveEvents::COLLISION_EVENTS)
                    })
                })
                .map(|(c, col)| (c, col.active_events()))
                .collect();
            for (c, events) in flags {
                t.colliders[c].set_active_events(events);
            }
        }
        for (c, types) in widened {
            let tc = &mut t.colliders[c];
            tc.set_active_collision_types(types);
            // As the layer does it: Rapier evaluates the collider's pairs again
            // (collision groups changed and set back), which wakes what it touches.
            let groups = tc.collision_groups();
            let flipped =
                InteractionGroups::new(!groups.memberships, !groups.filter, groups.test_mode);
            tc.set_collision_groups(flipped);
            tc.set_collision_groups(groups);
        }
        t.step();
        self.counters.twin_steps += 1;
        let (mine, theirs) = (body_bits(&self.world), body_bits(t));
        if mine == theirs {
            return Ok(());
        }
        if mine.len() != theirs.len() {
            return Err(format!(
                "the plain twin has {} bodies, the world {}",
                theirs.len(),
                mine.len()
            ));
        }
        let first = mine
            .iter()
            .zip(&theirs)
            .find(|(a, b)| a != b)
            .map(|(a, b)| format!("body {:?}: world {a:?}, twin {b:?}", a.0));
        Err(format!(
            "trajectories differ from the plain Rapier twin: {}",
            first.unwrap_or_default()
        ))
    }
}
