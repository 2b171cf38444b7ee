//! Waves: the bodies a moving body released wait to be held again until it has
//! slowed down, as a woken Rapier island stays awake while one of its bodies moves
//! (paper §7, fixation).
//!
//! Without them a released body still at rest was held again `sleepy_steps` after its
//! release, before the push that released it had reached it through the bodies
//! between: held, it stopped that push as a wall would (`docs/ARCHITECTURE.md`,
//! "Releasing held bodies", *Waves*).

use std::collections::{BTreeMap, BTreeSet};

use rapier3d::prelude::RigidBodyHandle;

use super::{key, SpeedUpState};
use crate::WorldView;

/// A wave of released bodies still waiting.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Wave {
    /// Its members, in the order they joined.
    members: Vec<RigidBodyHandle>,
    /// Its sources, the moving bodies whose reach released its members: it waits
    /// while one of them moves.
    sources: Vec<RigidBodyHandle>,
    /// The step at which it last grew.
    grew: u64,
}

/// The waves of released bodies still waiting.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(super) struct Waves {
    /// Body key → its wave.
    of: BTreeMap<(u32, u32), u32>,
    /// The waves by number.
    by_id: BTreeMap<u32, Wave>,
    /// The next wave's number.
    next: u32,
    /// The waves of the bodies that reached held ones since the last releases were
    /// applied: those releases join them.
    via: BTreeSet<u32>,
    /// The bodies that reached held ones since then: the releases' sources.
    from: Vec<RigidBodyHandle>,
    /// The step of the last analysis that looked at the waves.
    now: u64,
}

/// How long a wave waits at most after it last grew, in rests (`sleepy_steps`): long
/// enough for a push to cross a pile (the waves of the disturbance scenes end within
/// it), bounded so that a source that never stops (a turning kinematic fan) does not
/// keep what it once released awake for good.
pub(crate) const WAVE_MAX_RESTS: u64 = 20;

impl Waves {
    /// Whether a body waits for its wave to end before it may be held again.
    /// O(log members).
    pub(super) fn waits(&self, h: RigidBodyHandle) -> bool {
        self.of.contains_key(&key(h))
    }

    /// Notes a moving body whose reach releases held bodies: it is a source of their
    /// wave, and a wave it belongs to takes them in. O(log members + sources noted).
    pub(super) fn reached_from(&mut self, h: RigidBodyHandle) {
        if let Some(&w) = self.of.get(&key(h)) {
            self.via.insert(w);
        }
        if !self.from.contains(&h) {
            self.from.push(h);
        }
    }

    /// Makes the bodies released now one wave with the sources noted since the last
    /// call, merged with the waves of those sources. Releases nothing reached (the
    /// support's, the user's) wait for nothing. O((released + members merged) · log).
    pub(super) fn join(&mut self, released: &[RigidBodyHandle]) {
        let via = std::mem::take(&mut self.via);
        let mut sources = std::mem::take(&mut self.from);
        if released.is_empty() || sources.is_empty() {
            return;
        }
        let id = match via.first() {
            Some(&w) => w,
            None => {
                let w = self.next;
                self.next = self.next.wrapping_add(1);
                w
            }
        };
        let mut wave = self.by_id.remove(&id).unwrap_or(Wave {
            members: Vec::new(),
            sources: Vec::new(),
            grew: self.now,
        });
        let mut joining: Vec<RigidBodyHandle> = released.to_vec();
        for w in via.iter().skip(1) {
            if let Some(merged) = self.by_id.remove(w) {
                joining.extend(merged.members);
                sources.extend(merged.sources);
            }
        }
        for h in joining {
            match self.of.insert(key(h), id) {
                Some(old) if old == id => {}
                Some(old) => {
                    // A member of a wave not merged (released again): it leaves it.
                    if let Some(o) = self.by_id.get_mut(&old) {
                        o.members.retain(|&x| x != h);
                    }
                    wave.members.push(h);
                }
                None => wave.members.push(h),
            }
        }
        wave.grew = self.now;
        for h in sources {
            if !wave.sources.contains(&h) {
                wave.sources.push(h);
            }
        }
        self.by_id.insert(id, wave);
    }

    /// Ends, at step `now`, the waves none of whose sources `moves`, and those that
    /// last grew more than `max_steps` ago: their members may be held again.
    /// O(sources + members of the waves ended · log).
    fn settle(&mut self, now: u64, max_steps: u64, moves: impl Fn(RigidBodyHandle) -> bool) {
        self.now = now;
        let ended: Vec<u32> = self
            .by_id
            .iter()
            .filter(|(_, w)| {
                now.saturating_sub(w.grew) > max_steps || !w.sources.iter().any(|&h| moves(h))
            })
            .map(|(&id, _)| id)
            .collect();
        for id in ended {
            for h in self
                .by_id
                .remove(&id)
                .map(|w| w.members)
                .unwrap_or_default()
            {
                if self.of.get(&key(h)) == Some(&id) {
                    self.of.remove(&key(h));
                }
            }
        }
    }
}

impl SpeedUpState {
    /// Ends, at step `now`, the waves whose sources slowed down (none dynamic and
    /// faster than `release_speed`, nor a moving kinematic body) or that last grew
    /// more than [`WAVE_MAX_RESTS`] rests ago. O(sources of the waiting waves + members
    /// of those ended · log).
    pub(super) fn settle_waves(&mut self, view: &WorldView, now: u64) {
        let fast = self.config.release_speed;
        let max = WAVE_MAX_RESTS.saturating_mul(u64::from(self.config.sleepy_steps));
        self.waves.settle(now, max, |h| {
            view.bodies.get(h).is_some_and(|rb| {
                if rb.is_dynamic() {
                    rb.linvel().length() > fast
                } else {
                    rb.is_kinematic() && crate::world::moves(rb)
                }
            })
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn h(i: u32) -> RigidBodyHandle {
        RigidBodyHandle::from_raw_parts(i, 0)
    }

    #[test]
    fn released_bodies_wait_while_a_source_moves_and_not_after() {
        let mut w = Waves::default();
        w.reached_from(h(0));
        w.join(&[h(1), h(2)]);
        assert!(w.waits(h(1)) && w.waits(h(2)) && !w.waits(h(0)));
        w.settle(0, 100, |b| b == h(0));
        assert!(w.waits(h(1)), "the source still moves");
        w.settle(0, 100, |_| false);
        assert!(!w.waits(h(1)) && !w.waits(h(2)));
        assert!(w.by_id.is_empty() && w.of.is_empty());
    }

    #[test]
    fn a_wave_waits_at_most_its_bound_after_it_last_grew() {
        let mut w = Waves::default();
        w.settle(10, 100, |_| true);
        w.reached_from(h(0));
        w.join(&[h(1)]);
        w.settle(110, 100, |_| true);
        assert!(
            w.waits(h(1)),
            "100 steps after it grew, its source still moving"
        );
        // It grows at step 110: the bound counts from then.
        w.reached_from(h(1));
        w.join(&[h(2)]);
        w.settle(210, 100, |_| true);
        assert!(w.waits(h(1)) && w.waits(h(2)));
        w.settle(211, 100, |_| true);
        assert!(!w.waits(h(1)) && !w.waits(h(2)));
        assert!(w.by_id.is_empty());
    }

    #[test]
    fn a_release_nothing_reached_waits_for_nothing() {
        let mut w = Waves::default();
        w.join(&[h(1)]);
        assert!(!w.waits(h(1)));
        // Sources noted without a release are dropped at the next join.
        w.reached_from(h(0));
        w.join(&[]);
        w.join(&[h(2)]);
        assert!(!w.waits(h(2)));
    }

    #[test]
    fn a_member_that_reaches_more_brings_them_into_its_wave() {
        let mut w = Waves::default();
        w.reached_from(h(0));
        w.join(&[h(1)]);
        w.reached_from(h(9));
        w.join(&[h(5)]);
        // h(1), of the first wave, releases h(2): the wave of h(9) is not merged.
        w.reached_from(h(1));
        w.join(&[h(2)]);
        assert_eq!(w.of[&key(h(2))], w.of[&key(h(1))]);
        assert_ne!(w.of[&key(h(5))], w.of[&key(h(1))]);
        // The first wave waits while h(1) moves, though h(0) stopped.
        w.settle(0, 100, |b| b == h(1) || b == h(9));
        assert!(w.waits(h(2)) && w.waits(h(5)));
        w.settle(0, 100, |b| b == h(9));
        assert!(!w.waits(h(1)) && !w.waits(h(2)) && w.waits(h(5)));
    }

    #[test]
    fn two_waves_one_source_reaches_from_merge() {
        let mut w = Waves::default();
        w.reached_from(h(0));
        w.join(&[h(1)]);
        w.reached_from(h(9));
        w.join(&[h(2)]);
        // Members of both waves reach held bodies in one step: one wave.
        w.reached_from(h(1));
        w.reached_from(h(2));
        w.join(&[h(3)]);
        let one = w.of[&key(h(3))];
        assert!([h(1), h(2), h(3)].iter().all(|&b| w.of[&key(b)] == one));
        assert_eq!(w.by_id.len(), 1);
        w.settle(0, 100, |b| b == h(9));
        assert!(w.waits(h(1)), "a source of the merged wave still moves");
        w.settle(0, 100, |_| false);
        assert!(w.of.is_empty());
    }
}
