//! The paper's speed-ups (§7) as switches on a stock Rapier world.
//!
//! Each switch, how it is realised in Rapier, and what it costs the layer per step
//! (the design in full, held bodies and the rejected alternatives:
//! `docs/ARCHITECTURE.md`, §7 "The speed-ups in Rapier"):
//! - **groups**: the paper's traversal drives the sleep decision and the statistics.
//!   O(awake groups' members).
//! - **sleepy**: the layer owns sleeping. A body whose kinetic energy per unit mass
//!   stays under `sleepy_energy` for `sleepy_steps` steps is sleepy; a group of sleepy
//!   bodies sleeps through Rapier's whole-island sleep (the group's bodies made
//!   sleep-eligible, every other body never). O(awake bodies).
//! - **cache**: Rapier's contact recycling and warm start, both on; off, both off. O(1).
//! - **fewer_iterations**: `num_solver_iterations` = `fewer_iterations_count` instead
//!   of `iterations`. O(1).
//! - **deepest_contact_only**, **no_restitution_at_rest**: `modify_solver_contacts`
//!   ([`crate::logic::hooks`]) flagged on the colliders concerned only (dynamic ones;
//!   sleepy bodies' ones). O(flag changes).
//! - **viscous_damping**: Rapier's linear damping on every dynamic body, the originals restored
//!   when off. O(bodies) per configuration change.
//! - **insulate_sleepy**: sleepy bodies insulate groups in the traversal. O(1) per edge.
//! - **hold**: a sleepy body is held (body type fixed); a held body with only fixed
//!   partners is parked out of Rapier's active set; what held it up is remembered and
//!   judged again when it may be gone. It is released, type and velocities restored
//!   exactly, before a moving body reaches it, with as much of its held group as the
//!   disturbance can move, when its support goes, or when the user changes its type
//!   (`release.rs`); what a moving body released is not held again while that body
//!   still moves (`wave.rs`), nor is a sleepy body beside a group with a body still
//!   moving fast (`busy.rs`). O(refreshed bodies' contacts + fast bodies × log held
//!   + held bodies the step's changes reach).
//!
//! Per step, O(awake bodies) for the energy tracking, plus O(changes) Rapier writes;
//! a full pass over the bodies only when the configuration or the body count changes.

mod busy; // sleepy bodies beside a group still moving wait to be held
mod config;
mod held_boxes; // the held bodies' colliders in a tree of their own, for the reach
mod hold; // fixation: held records, hold decisions, holds and releases applied
mod lifecycle; // new, reconfigure, detach, and the restore of the user's world
mod park; // held bodies taken out of Rapier's active set
mod release; // what releases a held body, and how far a release reaches
mod sleep; // rest tracking, sleep-eligibility
mod solver; // solver parameters, damping, contact-modification flags
mod step; // the pre-step and the decisions as sequences of phases
mod support; // the support memory of held bodies, full judgement
mod support_partial; // what changed for the support memory, partial judgements
mod wave; // released bodies wait until what released them slowed down

pub use config::SpeedUps;
pub(crate) use support::SUPPORT_GAP;

use std::collections::BTreeMap;

use rapier3d::math::{Pose, Vector};
use rapier3d::prelude::{ActiveHooks, ColliderHandle, RigidBodyHandle};

use crate::graph::NodeId;

use hold::Held;
use sleep::Rest;

/// Counters of the speed-ups' work in the last step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpeedUpStats {
    /// Sleepy bodies among the awake ones.
    pub sleepy: usize,
    /// Bodies held by fixation.
    pub fixated: usize,
    /// Held bodies out of Rapier's active set (parked): they cost what a sleeping body
    /// costs. The others are fixed bodies Rapier still keeps in its active set.
    pub parked: usize,
    /// Fixations this step.
    pub fixations: usize,
    /// Releases this step.
    pub releases: usize,
}

/// The state of the speed-ups of a layer.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpeedUpState {
    config: SpeedUps,
    dirty: bool,
    known_bodies: usize,
    known_colliders: usize,
    rest: Vec<Rest>,
    /// Eligibility changes to write after the analysis (see
    /// [`Self::apply_decided`]) or in the pre-step.
    eligibility: Vec<(RigidBodyHandle, bool)>,
    /// Fixations to apply in the pre-step, releases after the analysis (see
    /// [`Self::apply_decided`]) or in the pre-step.
    to_fix: Vec<hold::ToFix>,
    to_release: Vec<RigidBodyHandle>,
    /// Held bodies a release's spread reached beyond this step's release budget,
    /// nearest first: released at the next analyses (see
    /// [`release::release_budget`]).
    #[cfg_attr(feature = "serde", serde(default))]
    later: Vec<RigidBodyHandle>,
    /// Held bodies to take out of Rapier's active set in the pre-step (see
    /// [`Self::park`]).
    #[cfg_attr(feature = "serde", serde(default))]
    to_park: Vec<RigidBodyHandle>,
    /// Held bodies still in Rapier's active set (`Park::Active`), the candidates for
    /// parking: the choice costs O(these), not O(held).
    #[cfg_attr(feature = "serde", serde(default))]
    unparked: std::collections::BTreeSet<(u32, u32)>,
    /// The held bodies in Rapier's active set that its last step left flagged as
    /// modified (its own island bookkeeping), in key order: their flag is not the
    /// user's write ([`Self::release_written`]).
    #[cfg_attr(feature = "serde", serde(default))]
    flagged_before_user: Vec<(u32, u32)>,
    /// The world's body count at the last analysis: a body removed since moved
    /// another in Rapier's island lists, which flags it.
    #[cfg_attr(feature = "serde", serde(default))]
    bodies_noted: usize,
    /// Held bodies disabled for this step on their way out of the active set
    /// (`Park::Parking`).
    #[cfg_attr(feature = "serde", serde(default))]
    parking_now: Vec<RigidBodyHandle>,
    /// Held bodies enabled again by the last pre-step after their step out
    /// (`Park::Parked` since): Rapier pairs their colliders anew in this step.
    #[cfg_attr(feature = "serde", serde(default))]
    parked_now: Vec<RigidBodyHandle>,
    /// Fixations (`false`) and releases (`true`) applied since the last analysis
    /// (after it, and by the pre-step), in order: the next analysis reports them as
    /// sleep and wake.
    #[cfg_attr(feature = "serde", serde(default))]
    pub(crate) hold_changes: Vec<(RigidBodyHandle, bool)>,
    held: BTreeMap<(u32, u32), Held>,
    /// Held bodies whose remembered support is gone (evaluated after each decision).
    unsupported: std::collections::BTreeSet<(u32, u32)>,
    /// Held bodies that the last evaluation found resting on a contact Rapier
    /// computes (`rests_now`): a partial evaluation judges them again, since such a
    /// contact can turn without a touch beginning or ending.
    #[cfg_attr(feature = "serde", serde(default))]
    rest_based: std::collections::BTreeSet<(u32, u32)>,
    /// Whether `unsupported` and `rest_based` hold a full evaluation's result (kept
    /// up to date by partial ones since): false when new (or restored from a snapshot
    /// without it), so that the first evaluation is a full one.
    #[cfg_attr(feature = "serde", serde(default))]
    support_partial_ok: bool,
    /// The support memory must be evaluated again in full: held bodies were removed
    /// from the world.
    support_dirty: bool,
    /// The records of the bodies released since the last evaluation: a partial one
    /// judges again what rested on them, and takes their watched supporters off.
    #[cfg_attr(feature = "serde", serde(default))]
    released: Vec<Held>,
    /// Bodies held since the last evaluation (judged alone when nothing else changed).
    newly_held: Vec<(u32, u32)>,
    /// "Supporter node → the held bodies that remember it", as (supporter, held key)
    /// pairs: the partial judgement's index, kept in step with every hold and release
    /// ([`Self::hold`], [`Self::unhold`]). Derived from the held records, so not
    /// saved: built again from them on restore ([`Self::reindex`]).
    #[cfg_attr(feature = "serde", serde(skip))]
    dependents: std::collections::BTreeSet<(NodeId, (u32, u32))>,
    /// "Body → the held bodies that touched it when they were held", as (body key,
    /// held key) pairs: the reverse of [`Held::links`], kept in step with every hold
    /// and release, so that a release spreads both ways. Derived, so not saved.
    #[cfg_attr(feature = "serde", serde(skip))]
    linked: std::collections::BTreeSet<((u32, u32), (u32, u32))>,
    /// "Up" at the last evaluation.
    support_up: Vector,
    /// The distinct static (with their pose then) and scripted supporters of the held
    /// bodies, each with the number of held bodies that watch it (their
    /// [`Held::watched`]), sorted by node and pose: a change of any of them
    /// re-evaluates.
    support_watch: Vec<(NodeId, Option<Pose>, u32)>,
    /// Fewer iterations and deepest contact only stand down (the monitor's repair of a deep penetration).
    pub(crate) suspend_thinning: bool,
    /// Colliders flagged for `modify_solver_contacts`, with their former flags.
    flagged: BTreeMap<(u32, u32), (ColliderHandle, ActiveHooks)>,
    /// Bodies whose colliders need (true) or lose (false) the no-restitution flag.
    zero_flags: Vec<(RigidBodyHandle, bool)>,
    damped: BTreeMap<(u32, u32), (RigidBodyHandle, f32)>,
    stats: SpeedUpStats,
    /// Bodies whose sleepy state changed in the last tracking (subgrouping regroups them).
    pub(crate) sleepy_changed: Vec<RigidBodyHandle>,
    /// The sleep thresholds of each body before the speed-ups first changed them
    /// (see [`sleep::remember_activation`]): restored as they were.
    #[cfg_attr(feature = "serde", serde(default))]
    activations: BTreeMap<(u32, u32), (RigidBodyHandle, [f32; 3])>,
    /// The user's solver iterations, contact recycling and warm-start coefficient
    /// when the speed-ups started: restored as they were.
    #[cfg_attr(feature = "serde", serde(default))]
    user_params: Option<(usize, bool, f32)>,
    /// The solver iterations the layer last wrote: a different value in the world
    /// means the user set their own since.
    #[cfg_attr(feature = "serde", serde(default))]
    iterations_written: Option<usize>,
    /// The contact recycling and warm start the layer last wrote: a world whose
    /// values differ was changed by the user since, and those are the user's own.
    #[cfg_attr(feature = "serde", serde(default))]
    cache_written: Option<(bool, f32)>,
    /// The released bodies that wait, before they may be held again, until what
    /// released them has slowed down ([`wave`]).
    waves: wave::Waves,
    /// The held bodies' colliders by their boxes, for the reach (`held_boxes.rs`);
    /// left out of snapshots, rebuilt from `held`.
    #[cfg_attr(feature = "serde", serde(skip))]
    held_boxes: held_boxes::HeldBoxes,
    /// Switched off: the next pre-step restores the world, then the state is dropped.
    detached: bool,
    restored: bool,
}

/// What the analysis of a step changed, as the decisions read it.
#[derive(Clone, Copy, Debug)]
pub(crate) struct StepChanges<'a> {
    /// The nodes refreshed (awake now or at the last update, created, asked for).
    pub refreshed: &'a [NodeId],
    /// The edges refreshed, in the analysis' order.
    pub touched: &'a [crate::graph::EdgeId],
    /// The records of the edges removed.
    pub removed: &'a [crate::graph::Edge],
    /// Whether a node was removed.
    pub nodes_removed: bool,
    /// The step's index.
    pub step: u64,
}

/// The unit vector against gravity (zero without gravity).
fn up_of(g: Vector) -> Vector {
    if g.length() > 0.0 {
        -g / g.length()
    } else {
        Vector::ZERO
    }
}

/// A body's handle as a map key: (index, generation).
fn key(h: RigidBodyHandle) -> (u32, u32) {
    h.into_raw_parts()
}
