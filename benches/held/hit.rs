//! `--hit STEP`: the bin hit mid-run by a heavy ball, in both worlds of the held bench.
//!
//! Before step `STEP` the heavy ball of `rcg_scenes::disturb::bin_hit` (radius 0.5 m,
//! 10× the pile's density, 10 m/s at 30° below the horizontal, from over the `-x`
//! wall; its geometry follows the bin's size) is thrown into both worlds, outside the
//! timed steps. At the end, the bodies of the pile (every dynamic body at the start)
//! that moved more than [`MOVED`] from the hit to the end are counted in each world,
//! and the ball's final `x` and speed read: the same observables as the lab's
//! `bin_hit` scene, on the bench's one seed.

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{PhysicsWorld, RigidBodyHandle, RigidBodyType};
use rcg_lab::disturb::positions;
use rcg_scenes::disturb::{bin_hit, Action};

use super::{median, spread};

/// A pile body counts as displaced when it moved farther than this from the hit to
/// the end, m (the lab's threshold).
pub const MOVED: Real = 0.01;

/// The scenes `--hit` applies to: the bins (mixed, or spheres), at any size.
pub fn applies_to(scene: &str) -> bool {
    scene.starts_with("mixed") || scene.starts_with("spheres")
}

/// The throw and what it needs: the pile, its positions at the hit and the balls.
pub struct Hit {
    /// The step before which the ball is thrown.
    pub at: usize,
    action: Action,
    pile: Vec<RigidBodyHandle>,
    /// Positions of the pile at the hit, `[stock, held]`.
    before: [Vec<Vector>; 2],
    /// The thrown ball in each world, `[stock, held]`.
    ball: [Option<RigidBodyHandle>; 2],
}

/// What the hit did in one world.
#[derive(Clone, Copy, Debug)]
pub struct Outcome {
    /// Pile bodies displaced more than [`MOVED`] from the hit to the end.
    pub displaced: usize,
    /// The ball's final `x` (the throw runs along `+x`), m.
    pub ball_x: f64,
    /// The ball's final speed, m/s.
    pub ball_speed: f64,
}

impl Hit {
    /// The hit before step `at` into the bin `world` was built as (before its first
    /// step: every dynamic body is the pile's).
    pub fn new(at: usize, world: &PhysicsWorld) -> Hit {
        let pile: Vec<RigidBodyHandle> = world
            .bodies
            .iter()
            .filter(|(_, rb)| rb.is_dynamic())
            .map(|(h, _)| h)
            .collect();
        Hit {
            at,
            action: bin_hit::action(pile.len()),
            pile,
            before: [Vec::new(), Vec::new()],
            ball: [None, None],
        }
    }

    /// Before step `i` of both worlds: at the hit, records the pile's positions and
    /// throws the ball into each. Untimed. O(pile) at the hit, O(1) otherwise.
    pub fn before_step(&mut self, i: usize, worlds: [&mut PhysicsWorld; 2]) {
        if i != self.at {
            return;
        }
        for (k, w) in worlds.into_iter().enumerate() {
            self.before[k] = positions(w, &self.pile);
            self.ball[k] = self.action.throw_into(w);
        }
    }

    /// The ball of world `k` (0 stock, 1 held), once thrown.
    pub fn ball(&self, k: usize) -> Option<RigidBodyHandle> {
        self.ball[k]
    }

    /// What the hit did in world `k` (0 stock, 1 held) by now; `None` before the hit.
    pub fn outcome(&self, k: usize, world: &PhysicsWorld) -> Option<Outcome> {
        let ball = world.bodies.get(self.ball[k]?)?;
        let after = positions(world, &self.pile);
        let displaced = self.before[k]
            .iter()
            .zip(&after)
            .filter(|(b, a)| {
                // A missing body (NaN) counts as displaced, as in the lab.
                let d = (**a - **b).length();
                d > MOVED || d.is_nan()
            })
            .count();
        Some(Outcome {
            displaced,
            ball_x: ball.translation().x as f64,
            ball_speed: ball.linvel().length() as f64,
        })
    }
}

/// The floor of a held world hit by the ball: the ball inserted into `floor` where the
/// held world has it, fixed if `fixed` (held), else with its velocity (`floor_of`
/// copies the pile only).
pub fn add_ball(floor: &mut PhysicsWorld, held: &PhysicsWorld, hit: &Hit, fixed: bool) {
    let Some(b) = hit.ball(1).and_then(|h| held.bodies.get(h)) else {
        return;
    };
    if let Some(h) = hit.action.throw_into(floor) {
        let fb = &mut floor.bodies[h];
        fb.set_position(*b.position(), false);
        if fixed {
            fb.set_body_type(RigidBodyType::Fixed, false);
        } else {
            fb.set_linvel(b.linvel(), false);
            fb.set_angvel(b.angvel(), false);
        }
    }
}

/// The hit's lines of a scene: per world the bodies displaced from the hit to the
/// end and the ball's end, over the runs (min / median / max; the runs are
/// deterministic, so they agree), the CPU time from the hit on as a ratio, and the
/// speed target on the whole run (held at most half of stock's time). `runs`: per run the outcomes `[stock, held]`
/// and the step times `(stock, held)`.
pub fn print(at: usize, runs: &[([Outcome; 2], (&[f64], &[f64]))], whole: &[f64]) {
    let of = |k: usize, f: fn(&Outcome) -> f64| spread(runs.iter().map(|r| f(&r.0[k])).collect());
    println!(
        "  hit before step {at}: displaced > {:.0} cm, hit to end   stock {}   held {}",
        MOVED * 100.0,
        of(0, |o| o.displaced as f64),
        of(1, |o| o.displaced as f64)
    );
    println!(
        "  ball at the end         x m stock {}   held {}   speed m/s stock {}   held {}",
        of(0, |o| o.ball_x),
        of(1, |o| o.ball_x),
        of(0, |o| o.ball_speed),
        of(1, |o| o.ball_speed)
    );
    let from = |v: &[f64]| v[at.min(v.len())..].iter().sum::<f64>();
    println!(
        "  from the hit held/stock  {}   (stock {:.3} s, held {:.3} s, first run)",
        spread(runs.iter().map(|r| from(r.1 .1) / from(r.1 .0)).collect()),
        from(runs[0].1 .0),
        from(runs[0].1 .1)
    );
    let m = median(whole.to_vec());
    println!(
        "  target: whole run ≥ {SPEED_TARGET:.0}× faster than stock (held/stock ≤ {:.2})   {} (median {m:.3})",
        1.0 / SPEED_TARGET,
        if m * SPEED_TARGET <= 1.0 { "met" } else { "NOT met" }
    );
}

/// The target: with the hit mid-run, the held world still runs the bin at least this
/// many times faster than stock over the whole run.
pub const SPEED_TARGET: f64 = 2.0;
