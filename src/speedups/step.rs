//! The two entry points of a step that change the world or decide: the pre-step
//! (before Rapier's step) and the decisions (after the analysis), each a sequence of
//! phases kept in the files of their concerns, in an order the golden trajectories pin.

use rapier3d::prelude::RigidBodyHandle;

use super::{key, up_of, SpeedUpState, StepChanges};
use crate::graph::ContactGraph;
use crate::logic::hooks::ContactMods;
use crate::logic::WorldMut;
use crate::WorldView;

impl SpeedUpState {
    /// Applies the configuration and the queued changes to the world, before
    /// Rapier's step. O(changes), plus O(bodies + colliders) when the configuration or
    /// the body count changed.
    /// `user_passive` tells the bodies the user made passive through the layer: a held
    /// body on its way out of Rapier's active set is not enabled again behind their
    /// back.
    pub(crate) fn pre_step(
        &mut self,
        world: &mut WorldMut,
        mods: &mut ContactMods,
        user_passive: &dyn Fn(RigidBodyHandle) -> bool,
    ) {
        if self.detached {
            if !self.restored {
                self.restore(world, mods, user_passive);
            }
            return;
        }
        let c = self.config.clone();
        self.apply_solver_params(world, mods, &c);
        let counts_changed = self.apply_config_to_bodies(world, &c);
        self.sort_decisions();
        self.write_eligibility(world);
        self.release_joined(world);
        self.apply_releases(world, mods, user_passive);
        self.apply_fixations(world);
        self.park(world, user_passive);
        self.forget_removed(world, counts_changed);
    }

    /// Writes the last analysis' sleep eligibility and gives back the held bodies it
    /// released, in handle order, before anything else the next step writes (in the
    /// order the pre-step writes them): [`crate::ContactLayer::step`] calls it right
    /// after its analysis, so that the step that first solves released bodies pays
    /// only Rapier's part of the release; a hand-written loop's pre-step calls it
    /// first. O(decisions · log held).
    pub(crate) fn apply_decided(
        &mut self,
        world: &mut WorldMut,
        mods: &mut ContactMods,
        user_passive: &dyn Fn(RigidBodyHandle) -> bool,
    ) {
        if self.detached {
            return;
        }
        self.sort_decisions();
        self.write_eligibility(world);
        self.apply_releases(world, mods, user_passive);
    }

    /// Sorts the queued decisions into handle order. Rapier records modified bodies in
    /// the order they are written, and that order reaches its islands and solver. The
    /// decisions come in group and neighbour order, which depends on the order the
    /// graph learnt its edges in (Rapier's pairs or its events): sorted, the same
    /// decisions give the same world whatever the tracking. (Stable: a body decided
    /// twice keeps its last decision.) O(decisions · log).
    fn sort_decisions(&mut self) {
        self.eligibility.sort_by_key(|(h, _)| key(*h));
        self.to_release.sort_by_key(|h| key(*h));
        self.to_fix.sort_by_key(|f| key(f.handle));
    }

    /// Decides sleep eligibility and fixation after the groups were rebuilt: the
    /// releases in full, the fixations up to the pre-step's budget
    /// ([`super::hold::hold_budget`]). O(awake groups' members + fast bodies'
    /// contacts).
    pub(crate) fn decide(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        groups: &crate::Groups,
        changes: &StepChanges,
    ) {
        if self.detached {
            return;
        }
        let StepChanges {
            refreshed,
            touched,
            removed,
            nodes_removed,
            ..
        } = *changes;
        // An idle step (nothing refreshed, touched or removed, no release put off, no
        // awake group): no eligibility and no fixation or release to decide; what the
        // support memory depends on (gravity, static supporters' poses) is looked at
        // as always.
        if refreshed.is_empty()
            && touched.is_empty()
            && removed.is_empty()
            && !nodes_removed
            && self.later.is_empty()
            && groups.iter_awake().next().is_none()
        {
            if self.config.hold {
                let up = up_of(view.gravity);
                self.decide_support(graph, view, up, changes);
            }
            return;
        }
        let c = self.config.clone();
        let mut want = c
            .sleepy
            .then(|| self.wanted_eligibility(graph, groups, refreshed, &c));
        if c.hold {
            let up = up_of(view.gravity);
            self.decide_releases(graph, view, refreshed);
            self.settle_waves(view, changes.step);
            let deferred = self.decide_fixations(graph, view, refreshed, up);
            // A body whose fixation waits for a later pre-step stays awake meanwhile
            // (not sleep-eligible), so that it is held, not put to sleep by Rapier.
            if let (Some(want), false) = (&mut want, deferred.is_empty()) {
                for w in want.iter_mut().filter(|w| w.1) {
                    w.1 = deferred
                        .binary_search_by_key(&key(w.0), |&h| key(h))
                        .is_err();
                }
            }
            self.decide_support(graph, view, up, changes);
        }
        if let Some(want) = want {
            self.note_eligibility(view, want);
        }
    }
}
