//! Unresponsive held bodies: a held body that a contact should have moved.
//!
//! A body held by the speed-ups' fixation is a fixed body to Rapier, so no contact
//! can move it. The speed-ups release held bodies that a fast body or a moving
//! scripted body is about to reach; a *slow* push (a body pushed by a constant force,
//! a box creeping sideways) is not seen coming, and the held body stops the pusher as
//! a wall would, where a sleeping Rapier pile would wake and be pushed.
//!
//! The measure: what the pusher brought that gravity and its contacts' impulses do not
//! explain (its lost momentum, a user's push), less the part along gravity, projected
//! on the impulse into the held body, over the pusher's weight or load. A held body is
//! unresponsive when that exceeds [`MonitorConfig::unresponsive_push`] in
//! [`PRESS_STEPS`] checks in a row (a push is sustained; an imbalance or an impact is
//! not); one violation per episode. The derivation, what it was chosen over and what
//! it does not cover: `docs/ARCHITECTURE.md` ("Unresponsive held bodies").
//!
//! # Cost
//! Nothing while the speed-ups hold no body (or are off). Otherwise O(edges of the
//! refreshed bodies) to find the awake bodies touching a held one, plus O(their
//! contact pairs) to read the impulses, plus O(pressed held bodies).

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::RigidBodyHandle;

use super::{Ctx, MonitorConfig, Peaks, Violation, ViolationKind};
use crate::coherence::pairs::other_collider;
use crate::graph::EdgeKind;

/// The unit of weight without gravity, m/s².
const STANDARD_GRAVITY: Real = 9.81;

/// Steps in a row a held body must be pressed over the threshold to be unresponsive:
/// a push is sustained, a solver's imbalance in a pile at rest flickers.
pub(crate) const PRESS_STEPS: u32 = 3;

#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Unresponsive {
    /// The held bodies pressed over the threshold at the last check (open episodes),
    /// with the body pressing it hardest and its measure, in handle order.
    pressed: Vec<(RigidBodyHandle, RigidBodyHandle, Real)>,
    /// How many checks in a row each pressed body has been pressed (parallel to
    /// `pressed`).
    #[cfg_attr(feature = "serde", serde(default))]
    streak: Vec<u32>,
    /// The pressed bodies whose streak reached [`PRESS_STEPS`] (the episodes
    /// reported), as `pressed`.
    #[cfg_attr(feature = "serde", serde(default))]
    confirmed: Vec<(RigidBodyHandle, RigidBodyHandle, Real)>,
    /// Scratch: the pushes on held bodies of one awake body.
    #[cfg_attr(feature = "serde", serde(skip))]
    per: Vec<(RigidBodyHandle, Vector)>,
}

/// The measure of one held body's push (see the module docs): the part of the
/// pusher's `unexplained` push that goes into the held body (along the push `j` it
/// puts on it) and not down (along `down`, gravity's unit direction or zero), over
/// `unit`.
pub(crate) fn measure(unexplained: Vector, j: Vector, down: Vector, unit: Real) -> Real {
    let len = j.length();
    if !(len > 0.0) {
        return 0.0;
    }
    let along_down = unexplained.dot(down).max(0.0);
    let across = (unexplained - down * along_down).dot(j / len).max(0.0);
    if unit > 0.0 {
        across / unit
    } else if across > 0.0 {
        Real::INFINITY
    } else {
        0.0
    }
}

/// The friction impulse of a solver contact on collider 1's body, in world space, as
/// Rapier writes it back after the solve (`warmstart_tangent_world`, the impulse the
/// solver's last substep ended on). Taken as it is: scaled up to the step's total
/// (`tangent_impulse` over `warmstart_tangent_impulse`) it balanced resting bodies
/// worse in the sphere pile.
fn friction(data: &rapier3d::geometry::ContactData) -> Vector {
    data.warmstart_tangent_world
}

impl Unresponsive {
    pub(crate) fn forget(&mut self, h: RigidBodyHandle) {
        let keep: Vec<bool> = self
            .pressed
            .iter()
            .map(|(p, by, _)| *p != h && *by != h)
            .collect();
        let mut i = 0;
        self.streak.retain(|_| {
            i += 1;
            keep[i - 1]
        });
        self.pressed.retain(|(p, by, _)| *p != h && *by != h);
        self.confirmed.retain(|(p, by, _)| *p != h && *by != h);
    }

    /// The held bodies pressed over the threshold in the last [`PRESS_STEPS`]
    /// checks or more (the open episodes), with the body pressing each hardest and
    /// its measure, in handle order. O(1).
    pub(crate) fn pressed(&self) -> &[(RigidBodyHandle, RigidBodyHandle, Real)] {
        &self.confirmed
    }

    // Long: the measure's terms (module doc) are summed in one pass over each pusher's contact pairs.
    pub(crate) fn check(
        &mut self,
        ctx: &Ctx,
        config: &MonitorConfig,
        held: &dyn Fn(RigidBodyHandle) -> bool,
        out: &mut Vec<Violation>,
        peaks: &mut Peaks,
    ) {
        let before = std::mem::take(&mut self.pressed);
        let before_streak = std::mem::take(&mut self.streak);
        self.confirmed.clear();
        // Only the speed-ups' fixation holds a body fixed: nothing to look at while it
        // holds none.
        let holding = ctx
            .layer
            .speedups()
            .is_some_and(|s| s.fixated().next().is_some());
        if !holding {
            return;
        }
        let view = ctx.view;
        let graph = ctx.layer.graph();
        let dt = view.dt;
        let g_len = view.gravity.length();
        let (down, g) = if g_len.is_finite() && g_len > 0.0 {
            (view.gravity / g_len, g_len)
        } else {
            (Vector::ZERO, STANDARD_GRAVITY)
        };
        if !(dt.is_finite() && dt > 0.0) {
            return;
        }
        // A held body: one the caller holds that is fixed in Rapier (fixated).
        let is_held = |h: RigidBodyHandle| {
            view.bodies
                .get(h)
                .is_some_and(|rb| rb.is_fixed() && rb.is_enabled())
                && held(h)
        };
        let mut pressed: Vec<(RigidBodyHandle, RigidBodyHandle, Real)> = Vec::new();
        for &n in ctx.layer.coherence().refreshed_nodes() {
            let Some(node) = graph.node(n) else { continue };
            if !node.kind().is_simulated() {
                continue;
            }
            let Some(h) = node.body() else { continue };
            let Some(rb) = view.bodies.get(h) else {
                continue;
            };
            if !rb.is_dynamic() || !rb.is_enabled() || rb.is_sleeping() || held(h) {
                continue;
            }
            // Only a body next to a held one reads its pairs.
            let next_to_held = graph.neighbors(n).any(|(m, _, e)| {
                e.kind() == EdgeKind::Physical && graph.body_of(m).is_some_and(is_held)
            });
            if !next_to_held {
                continue;
            }
            let mass = rb.mass();
            if !(mass.is_finite() && mass > 0.0) {
                continue;
            }
            // One pass over the pusher's pairs: every pair's normal impulse on the
            // pusher (summed into `pushed`, their lengths into `load`), and the pushes
            // on the held bodies it touches.
            self.per.clear();
            let mut pushed = Vector::ZERO;
            let mut load: Real = 0.0;
            for &c in rb.colliders() {
                for pair in view.narrow_phase.contact_pairs_with(c) {
                    let other = other_collider(pair, c);
                    // The contact pushes collider 2's body along the normal (which
                    // points from collider 1 to collider 2), collider 1's against it.
                    let mut j = Vector::ZERO;
                    for m in pair.solver_manifolds() {
                        let impulse: Real = m.points.iter().map(|pt| pt.data.impulse).sum();
                        j += m.data.normal * impulse;
                        for pt in &m.points {
                            j -= friction(&pt.data);
                        }
                    }
                    if !j.is_finite() {
                        continue;
                    }
                    let on_other = if pair.collider2 == other { j } else { -j };
                    pushed -= on_other;
                    let held_other = view
                        .colliders
                        .get(other)
                        .and_then(|co| co.parent())
                        .filter(|&p| p != h && is_held(p));
                    match held_other {
                        Some(p) => match self.per.iter_mut().find(|(q, _)| *q == p) {
                            Some((_, acc)) => *acc += on_other,
                            None => self.per.push((p, on_other)),
                        },
                        None => load += j.length(),
                    }
                }
            }
            // What the pusher brings that gravity and its other contacts do not: its
            // momentum lost and the user's push (see the module docs).
            let unexplained = -(view.gravity * (mass * dt) + pushed);
            let unit = (mass * g * dt).max(load);
            for &(p, j) in &self.per {
                let value = measure(unexplained, j, down, unit);
                if config.unresponsive_push > 0.0 {
                    peaks.unresponsive = peaks.unresponsive.max(value / config.unresponsive_push);
                }
                if value > config.unresponsive_push {
                    pressed.push((p, h, value));
                }
            }
        }
        // Scratch only: left empty between checks, as a restored layer has it.
        self.per.clear();
        // One entry per held body, its largest measure, in handle order (ties to the
        // pusher with the smaller handle).
        pressed.sort_by(|a, b| {
            a.0.into_raw_parts()
                .cmp(&b.0.into_raw_parts())
                .then(b.2.total_cmp(&a.2))
                .then(a.1.into_raw_parts().cmp(&b.1.into_raw_parts()))
        });
        pressed.dedup_by_key(|(p, _, _)| *p);
        for &(p, by, value) in &pressed {
            let was = before
                .iter()
                .position(|(q, _, _)| *q == p)
                .map_or(0, |i| before_streak[i]);
            // A second check of the same step saw no new step of the push.
            let streak = if ctx.fresh {
                was.saturating_add(1)
            } else {
                was.max(1)
            };
            self.streak.push(streak);
            if streak >= PRESS_STEPS {
                self.confirmed.push((p, by, value));
            }
            if streak == PRESS_STEPS && (ctx.fresh || was < PRESS_STEPS) {
                out.push(Violation {
                    step: ctx.step,
                    kind: ViolationKind::Unresponsive,
                    body: p,
                    node: graph.node_of_body(p),
                    value,
                });
            }
        }
        self.pressed = pressed;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOWN: Vector = Vector::new(0.0, -1.0, 0.0);
    const G: Real = 9.81;
    const DT: Real = 0.01;

    #[test]
    fn what_is_explained_or_points_down_measures_nothing() {
        let unit = G * DT;
        let sideways = Vector::new(1.0, 0.0, 0.0);
        // A resting pusher: gravity and its contacts explain everything.
        assert_eq!(measure(Vector::ZERO, sideways, DOWN, unit), 0.0);
        // A body landing on the held one: its lost momentum points down.
        assert_eq!(measure(DOWN * 0.44, DOWN * 0.5, DOWN, unit), 0.0);
        // A push away from the held body is not a push into it.
        assert_eq!(measure(-sideways * 0.3, sideways, DOWN, unit), 0.0);
        // No push on it at all.
        assert_eq!(measure(sideways * 0.3, Vector::ZERO, DOWN, unit), 0.0);
    }

    #[test]
    fn a_push_across_gravity_measures_the_speed_it_takes() {
        // A 1 kg box driven at 0.3 m/s and stopped by a held box.
        let x = Vector::new(1.0, 0.0, 0.0);
        let v = measure(x * 0.3, x * 0.3, DOWN, G * DT);
        assert!((v - 0.3 / (G * DT)).abs() < 1e-4, "{v}");
        assert!(v > MonitorConfig::default().unresponsive_push);
        // Driven down a 45° slope into it: the part along gravity is dropped, the
        // rest projected on the push it puts on the held body.
        let slope = Vector::new(1.0, -1.0, 0.0).normalize();
        let d = measure(slope * 0.3, x, DOWN, G * DT);
        assert!((d - 0.3 * slope.x / (G * DT)).abs() < 1e-4, "{d}");
        // Up is not explained either.
        let up = measure(Vector::new(0.0, 0.3, 0.0), Vector::Y, DOWN, G * DT);
        assert!((up - v).abs() < 1e-4);
        // The same push on a loaded pusher measures against its load.
        let loaded = measure(x * 0.3, x, DOWN, 10.0 * G * DT);
        assert!((loaded - v / 10.0).abs() < 1e-4, "{loaded}");
    }

    #[test]
    fn without_gravity_nothing_is_dropped() {
        let v = measure(DOWN * 0.3, DOWN, Vector::ZERO, G * DT);
        assert!((v - 0.3 / (G * DT)).abs() < 1e-4, "{v}");
        assert_eq!(measure(Vector::X, Vector::X, DOWN, 0.0), Real::INFINITY);
        assert_eq!(measure(Vector::ZERO, Vector::X, DOWN, 0.0), 0.0);
    }
}
