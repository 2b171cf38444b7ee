//! The paper's speed-ups (§7) as switches on a stock Rapier world.
//!
//! # How each switch is realised
//! - **groups**: the paper's traversal drives the sleep decision and the statistics.
//! - **sleepy**: the layer owns sleeping. Each awake body's kinetic energy per unit
//!   mass is tracked; after `sleepy_steps` steps under `sleepy_energy` the body is
//!   *sleepy*. A contact group whose bodies are all sleepy is put to sleep — through
//!   Rapier's own whole-island sleep: the layer makes the group's bodies sleep-eligible
//!   (Rapier's activation thresholds), every other body never eligible, and Rapier
//!   puts an island to sleep exactly when all its bodies are eligible. Rapier is thus
//!   never left with a partly sleeping island (a partly sleeping island sinks under
//!   gravity: `docs/rapier-notes.md`), and it keeps splitting its islands, which it only does for
//!   islands holding eligible bodies. Waking is Rapier's: a body touching or pushing
//!   the island, or a user change, wakes it as a whole; a woken body's rest count
//!   starts again.
//! - **cache**: Rapier's contact recycling and warm start, both on; off, both off.
//! - **tweak**: `num_solver_iterations` = `tweak_iterations` instead of `iterations`.
//! - **reduce** and **zero**: `modify_solver_contacts` ([`crate::logic::hooks`]), with the hook
//!   flag on the colliders concerned only (all dynamic colliders for reduce, sleepy
//!   bodies' colliders for zero). A flagged pair is never contact-recycled: that is
//!   part of these switches' real cost in Rapier, and the DIKU run measures it.
//! - **damp**: Rapier's linear damping on every dynamic body (originals restored when
//!   the switch goes off).
//! - **subgroup**: sleepy bodies insulate groups in the traversal. In Rapier the solver
//!   couples an island whatever the groups say, so subgrouping alone changes which
//!   bodies are judged together (statistics, sleep decisions), and its effect on motion
//!   comes with fixation.
//! - **fixate**: a sleepy body is held immovable: its type becomes fixed, so it leaves
//!   Rapier's islands and costs nothing while awake bodies rest on it (the paper's
//!   "inverse mass and inertia tensor to zero"). It is released — type, linear and
//!   angular velocity restored exactly — when a touching body that is not sleepy moves
//!   faster than `release_speed`. Multibody members are never fixated: Rapier asserts
//!   that a multibody's links other than the root are dynamic. A fixation is decided
//!   at the analysis and applied at the next pre-step, so the pre-step checks the body
//!   again (still dynamic, enabled, in no multibody), and it releases a held body that
//!   the user joined to a multibody as a link meanwhile (O(held bodies), only while
//!   the world has a multibody).
//!
//! # Held bodies
//! A fixated body costs nothing while held. Rapier keeps a body turned fixed in its
//! active set (its island manager returns early for fixed bodies, and fixed bodies
//! belong to no island that could sleep), where a settled pile of 500 held boxes
//! costs about 70 times what stock Rapier's sleeping pile costs
//! (`docs/rapier-notes.md`). So a held body is *parked*: once none of its collider
//! pairs has a partner that is not fixed, and none touches or intersects anything,
//! it is disabled for one step (Rapier takes a disabled body out of its active set)
//! and enabled again at the next pre-step (Rapier does not put an enabled fixed body
//! back). Its pose is untouched (a disabled body does not move), no contact or
//! intersection of it starts or stops (it had none, and only fixed partners, whose
//! pairs with a fixed body Rapier does not compute), and nothing else wakes. A body
//! with joints is never parked (disabling it disables its joints). Its release is
//! the same as before: type and velocities restored exactly; Rapier puts it back
//! into its active set. A held body is reported as `FellAsleep` when fixated and
//! `WokeUp` when released, and [`crate::StepStats::awake_bodies`] counts only what
//! Rapier integrates.
//!
//! Rejected for fixation: locked axes with zeroed velocity (`docs/rapier-notes.md`: holds a body
//! bit-identically and keeps its contacts). It keeps the body in the solver, so it
//! saves nothing, which is the point of the switch.
//!
//! # Cost
//! Per step, O(awake bodies) for the energy tracking, plus O(changes) Rapier writes.
//! A full pass over the bodies only when the configuration or the body count changes.

mod config;

pub use config::SpeedUps;

use std::collections::BTreeMap;

use rapier3d::dynamics::{RigidBodyActivation, RigidBodyType};
use rapier3d::math::{Pose, Vector};
use rapier3d::prelude::{ActiveHooks, ColliderHandle, RigidBodyHandle};

use crate::coherence::details::resting_supports;
use crate::graph::{ContactGraph, EdgeKind, NodeId, NodeKind, NodeSource};
use crate::logic::hooks::ContactMods;
use crate::logic::WorldMut;
use crate::WorldView;

/// A body held by fixation, with what it had before.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Held {
    handle: RigidBodyHandle,
    linvel: Vector,
    angvel: Vector,
    /// What supported it against gravity when it was fixated (see
    /// [`SpeedUpState::fixation_supported`]).
    supports: Vec<Supporter>,
    /// Where it is on the way out of Rapier's active set (see "Held bodies" above).
    #[cfg_attr(feature = "serde", serde(default))]
    park: Park,
    /// What it added to the support watch when it was last judged
    /// ([`SpeedUpState::watch_of`]): taken off again when it is judged anew or
    /// released.
    #[cfg_attr(feature = "serde", serde(default))]
    watched: Vec<(NodeId, Option<Pose>)>,
}

impl Held {
    /// Gives the body back to the simulation exactly as it was held: dynamic, with its
    /// velocities, and enabled again if the layer disabled it for this step (unless
    /// the user made it passive meanwhile). The body, if it still exists.
    fn give_back<'w>(
        &self,
        world: &'w mut WorldMut,
        user_passive: &dyn Fn(RigidBodyHandle) -> bool,
    ) -> Option<&'w mut rapier3d::dynamics::RigidBody> {
        let rb = world.bodies.get_mut(self.handle)?;
        if self.park == Park::Parking && !user_passive(self.handle) {
            rb.set_enabled(true);
        }
        rb.set_body_type(RigidBodyType::Dynamic, true);
        rb.set_linvel(self.linvel, true);
        rb.set_angvel(self.angvel, true);
        Some(rb)
    }
}

/// A held body's way out of Rapier's active set. Rapier keeps a body turned fixed in
/// its active set (its island manager returns early for fixed bodies), where it costs
/// about 70 times what a sleeping body costs; disabling a body is the one public way
/// to take it out, and re-enabling a fixed body does not put it back.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
enum Park {
    /// Fixed, still in Rapier's active set.
    #[default]
    Active,
    /// Disabled for this one step: Rapier takes it out of its active set.
    Parking,
    /// Enabled again, fixed, out of Rapier's active set: it costs what a sleeping
    /// body costs.
    Parked,
}

/// One thing that held a body against gravity when it was fixated.
#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Supporter {
    node: NodeId,
    /// For static geometry (a fixed body or a parentless collider): its pose then. It
    /// supports only while it has not moved.
    pose: Option<Pose>,
}

/// The smallest cosine between a contact's push and "up" that the fixation memory
/// counts as support: a side contact with a sliver of upward normal does not hold a
/// body up.
const MIN_SUPPORT_COS: f32 = 0.1;

/// How far apart a support may be and still hold a body: Rapier's default contact
/// prediction distance (a resting body hovers within it).
pub(crate) const SUPPORT_GAP: f32 = 0.002;

/// Whether a held body rests on something now: a contact Rapier computes (against
/// bodies that are not fixed) that pushes it up, read from Rapier's narrow phase
/// (see [`resting_supports`]). O(its contact pairs).
fn rests_now(graph: &ContactGraph, view: &WorldView, h: RigidBodyHandle, up: Vector) -> bool {
    let Some(n) = graph.node_of_body(h) else {
        return false;
    };
    let mut found = Vec::new();
    resting_supports(graph, view, n, up, MIN_SUPPORT_COS, SUPPORT_GAP, &mut found);
    !found.is_empty()
}

/// A pose as bits, for ordering (`None` first).
fn pose_bits(p: Option<Pose>) -> Option<[u32; 7]> {
    p.map(|p| {
        let (t, r) = (p.translation, p.rotation);
        [t.x, t.y, t.z, r.x, r.y, r.z, r.w].map(f32::to_bits)
    })
}

/// The pose of a static supporter: its body's, or its collider's if it has no body.
fn static_pose(graph: &ContactGraph, view: &WorldView, n: NodeId) -> Option<Pose> {
    match graph.node(n)?.source() {
        NodeSource::Body(h) => view.bodies.get(h).map(|rb| *rb.position()),
        NodeSource::StaticCollider(c) => view.colliders.get(c).map(|co| *co.position()),
        _ => None,
    }
}

/// Per-body rest tracking, indexed by body slot.
#[derive(Clone, Copy, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Rest {
    generation: u32,
    steps: u32,
    sleepy: bool,
    /// Sleep-eligibility currently written into Rapier.
    eligible: bool,
}

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
    /// Eligibility changes to write in the pre-step.
    eligibility: Vec<(RigidBodyHandle, bool)>,
    /// Fixations and releases to apply in the pre-step.
    to_fix: Vec<(RigidBodyHandle, Vec<Supporter>)>,
    to_release: Vec<RigidBodyHandle>,
    /// Held bodies to take out of Rapier's active set in the pre-step (see "Held
    /// bodies").
    #[cfg_attr(feature = "serde", serde(default))]
    to_park: Vec<RigidBodyHandle>,
    /// Held bodies still in Rapier's active set (`Park::Active`), the candidates for
    /// parking: the choice costs O(these), not O(held).
    #[cfg_attr(feature = "serde", serde(default))]
    unparked: std::collections::BTreeSet<(u32, u32)>,
    /// Held bodies disabled for this step on their way out of the active set
    /// (`Park::Parking`).
    #[cfg_attr(feature = "serde", serde(default))]
    parking_now: Vec<RigidBodyHandle>,
    /// Held bodies enabled again by the last pre-step after their step out
    /// (`Park::Parked` since): Rapier pairs their colliders anew in this step.
    #[cfg_attr(feature = "serde", serde(default))]
    parked_now: Vec<RigidBodyHandle>,
    /// Fixations (`false`) and releases (`true`) applied by the last pre-step, in
    /// order: the analysis reports them as sleep and wake.
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
    /// "Up" at the last evaluation.
    support_up: Vector,
    /// The distinct static (with their pose then) and scripted supporters of the held
    /// bodies, each with the number of held bodies that watch it (their
    /// [`Held::watched`]), sorted by node and pose: a change of any of them
    /// re-evaluates.
    support_watch: Vec<(NodeId, Option<Pose>, u32)>,
    /// Tweak and reduce stand down (the monitor's repair of a deep penetration).
    pub(crate) suspend_thinning: bool,
    /// Colliders flagged for `modify_solver_contacts`, with their former flags.
    flagged: BTreeMap<(u32, u32), (ColliderHandle, ActiveHooks)>,
    /// Bodies whose colliders need (true) or lose (false) the zero flag.
    zero_flags: Vec<(RigidBodyHandle, bool)>,
    damped: BTreeMap<(u32, u32), (RigidBodyHandle, f32)>,
    stats: SpeedUpStats,
    /// Bodies whose sleepy state changed in the last tracking (subgrouping regroups them).
    pub(crate) sleepy_changed: Vec<RigidBodyHandle>,
    /// The sleep thresholds of each body before the speed-ups first changed them
    /// (see [`remember_activation`]): restored as they were.
    #[cfg_attr(feature = "serde", serde(default))]
    activations: BTreeMap<(u32, u32), (RigidBodyHandle, [f32; 3])>,
    /// The user's solver iterations, contact recycling and warm-start coefficient
    /// when the speed-ups started: restored as they were.
    #[cfg_attr(feature = "serde", serde(default))]
    user_params: Option<(usize, bool, f32)>,
    /// Switched off: the next pre-step restores the world, then the state is dropped.
    detached: bool,
    restored: bool,
}

/// What [`SpeedUpState::support_changed`] found: what the support memory must judge
/// again.
#[derive(Debug)]
enum SupportChange {
    /// Nothing it depends on changed; `partial`: a partial evaluation would apply (for
    /// newly held bodies found unsupported).
    Nothing {
        /// Whether [`SpeedUpState::evaluate_support_from`] applies.
        partial: bool,
    },
    /// Only touches of held bodies began or ended, or held bodies were released: the
    /// held ends of the touches, in edge order (the released bodies are in
    /// `SpeedUpState::released`).
    Touches(Vec<(u32, u32)>),
    /// Held bodies were removed, a node removed, gravity turned, a static supporter
    /// moved or a scripted one moves (or no partial evaluation applies).
    Everything,
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

/// Spreads "supported" from the bases up: `links` holds (supporter, dependent) index
/// pairs (sorted here), `queue` the supported bases. O(links · log links).
fn propagate_support(links: &mut [(usize, usize)], supported: &mut [bool], mut queue: Vec<usize>) {
    links.sort_unstable();
    while let Some(j) = queue.pop() {
        let from = links.partition_point(|&(s, _)| s < j);
        for &(_, d) in links[from..].iter().take_while(|&&(s, _)| s == j) {
            if !supported[d] {
                supported[d] = true;
                queue.push(d);
            }
        }
    }
}

/// The unit vector against gravity (zero without gravity).
fn up_of(g: Vector) -> Vector {
    if g.length() > 0.0 {
        -g / g.length()
    } else {
        Vector::ZERO
    }
}

fn key(h: RigidBodyHandle) -> (u32, u32) {
    h.into_raw_parts()
}

fn eligible_activation(a: &mut RigidBodyActivation, dt: f32) {
    a.normalized_linear_threshold = f32::MAX;
    a.angular_threshold = f32::MAX;
    // Two steps: a body woken by Rapier (timer reset) cannot fall asleep again in the
    // same step, before the layer has seen it wake.
    a.time_until_sleep = 2.0 * dt;
}

/// Records a body's sleep thresholds before the speed-ups first change them. O(log n).
fn remember_activation(
    saved: &mut BTreeMap<(u32, u32), (RigidBodyHandle, [f32; 3])>,
    h: RigidBodyHandle,
    rb: &rapier3d::dynamics::RigidBody,
) {
    let a = rb.activation();
    saved.entry(key(h)).or_insert((
        h,
        [
            a.normalized_linear_threshold,
            a.angular_threshold,
            a.time_until_sleep,
        ],
    ));
}

fn never_activation(a: &mut RigidBodyActivation) {
    a.normalized_linear_threshold = -1.0;
    a.angular_threshold = -1.0;
}

impl SpeedUpState {
    pub(crate) fn new(config: SpeedUps) -> Self {
        Self {
            config,
            dirty: true,
            known_bodies: usize::MAX,
            known_colliders: usize::MAX,
            rest: Vec::new(),
            eligibility: Vec::new(),
            to_fix: Vec::new(),
            to_release: Vec::new(),
            to_park: Vec::new(),
            unparked: Default::default(),
            parking_now: Vec::new(),
            parked_now: Vec::new(),
            hold_changes: Vec::new(),
            held: BTreeMap::new(),
            unsupported: Default::default(),
            rest_based: Default::default(),
            support_partial_ok: false,
            support_dirty: true,
            released: Vec::new(),
            newly_held: Vec::new(),
            dependents: Default::default(),
            support_up: Vector::ZERO,
            support_watch: Vec::new(),
            suspend_thinning: false,
            flagged: BTreeMap::new(),
            zero_flags: Vec::new(),
            damped: BTreeMap::new(),
            activations: BTreeMap::new(),
            user_params: None,
            stats: SpeedUpStats::default(),
            sleepy_changed: Vec::new(),
            detached: false,
            restored: false,
        }
    }

    pub(crate) fn reconfigure(&mut self, config: SpeedUps) {
        self.config = config;
        self.dirty = true;
        self.detached = false;
        self.restored = false;
    }

    pub(crate) fn detach(&mut self) {
        self.detached = true;
        self.restored = false;
    }

    /// The colliders flagged for contact modification, with their former flags.
    pub(crate) fn modify_flagged(&self) -> &BTreeMap<(u32, u32), (ColliderHandle, ActiveHooks)> {
        &self.flagged
    }

    pub(crate) fn is_detached(&self) -> bool {
        self.detached
    }

    /// Detached and the world restored: the state can be dropped.
    pub(crate) fn is_idle(&self) -> bool {
        self.detached && self.restored
    }

    /// Undoes everything the speed-ups changed in the world.
    fn restore(
        &mut self,
        world: &mut WorldMut,
        mods: &mut ContactMods,
        user_passive: &dyn Fn(RigidBodyHandle) -> bool,
    ) {
        for (_, held) in std::mem::take(&mut self.held) {
            held.give_back(world, user_passive);
        }
        self.dependents.clear();
        self.set_modify_flags(world, &[]);
        for (_, (h, original)) in std::mem::take(&mut self.damped) {
            if let Some(rb) = world.bodies.get_mut(h) {
                rb.set_linear_damping(original);
            }
        }
        // The user's own sleep thresholds and solver parameters, as they were.
        for (_, (h, [linear, angular, time])) in std::mem::take(&mut self.activations) {
            if let Some(rb) = world.bodies.get_mut(h) {
                let a = rb.activation_mut();
                a.normalized_linear_threshold = linear;
                a.angular_threshold = angular;
                a.time_until_sleep = time;
            }
        }
        if let Some((iterations, recycling, warmstart)) = self.user_params.take() {
            let p = &mut *world.integration_parameters;
            p.num_solver_iterations = iterations;
            p.contact_recycling = recycling;
            p.warmstart_coefficient = warmstart;
        }
        mods.reduce_depth = None;
        mods.zero = false;
        mods.sleepy.clear();
        self.rest.clear();
        self.eligibility.clear();
        self.to_fix.clear();
        self.to_release.clear();
        self.to_park.clear();
        self.unparked.clear();
        self.parking_now.clear();
        self.parked_now.clear();
        self.unsupported.clear();
        self.rest_based.clear();
        self.released.clear();
        self.support_partial_ok = false;
        self.zero_flags.clear();
        self.restored = true;
    }

    /// The configuration.
    pub fn config(&self) -> &SpeedUps {
        &self.config
    }

    /// The counters of the last step.
    pub fn stats(&self) -> SpeedUpStats {
        self.stats
    }

    /// Records a held body, and its supporters in the dependents index. O(its
    /// supporters · log).
    fn hold(&mut self, held: Held) {
        let k = key(held.handle);
        self.dependents
            .extend(held.supports.iter().map(|s| (s.node, k)));
        if let Some(old) = self.held.insert(k, held) {
            self.forget_dependents(k, &old);
        }
    }

    /// Forgets a held body's record, and its supporters in the dependents index.
    /// O(its supporters · log).
    fn unhold(&mut self, k: (u32, u32)) -> Option<Held> {
        let held = self.held.remove(&k)?;
        self.forget_dependents(k, &held);
        Some(held)
    }

    /// Builds the indexes left out of snapshots (the dependents index) from the held
    /// records; the restore calls it. O(held bodies' supporters · log).
    pub(crate) fn reindex(&mut self) {
        self.dependents = self.dependents_of_records();
    }

    /// The dependents index as the held records give it. O(held bodies' supporters ·
    /// log).
    fn dependents_of_records(&self) -> std::collections::BTreeSet<(NodeId, (u32, u32))> {
        self.held
            .iter()
            .flat_map(|(k, held)| held.supports.iter().map(move |s| (s.node, *k)))
            .collect()
    }

    fn forget_dependents(&mut self, k: (u32, u32), held: &Held) {
        for s in &held.supports {
            self.dependents.remove(&(s.node, k));
        }
    }

    fn rest_of(&self, h: RigidBodyHandle) -> Option<&Rest> {
        let (i, g) = key(h);
        self.rest.get(i as usize).filter(|r| r.generation == g)
    }

    fn rest_mut(&mut self, h: RigidBodyHandle) -> &mut Rest {
        let (i, g) = key(h);
        let i = i as usize;
        if self.rest.len() <= i {
            self.rest.resize(i + 1, Rest::default());
        }
        let r = &mut self.rest[i];
        if r.generation != g {
            *r = Rest {
                generation: g,
                ..Rest::default()
            };
        }
        r
    }

    /// Whether a body is sleepy (at rest for `sleepy_steps` steps). O(1).
    pub fn is_sleepy(&self, h: RigidBodyHandle) -> bool {
        self.rest_of(h).is_some_and(|r| r.sleepy) || self.is_fixated(h)
    }

    /// Whether a body is held by fixation. O(log fixated).
    pub fn is_fixated(&self, h: RigidBodyHandle) -> bool {
        self.held.contains_key(&key(h))
    }

    /// The bodies held by fixation, in handle order.
    pub fn fixated(&self) -> impl Iterator<Item = RigidBodyHandle> + '_ {
        self.held.values().map(|h| h.handle)
    }

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
        let dt = world.integration_parameters.dt;
        let params = &mut *world.integration_parameters;
        if self.user_params.is_none() {
            self.user_params = Some((
                params.num_solver_iterations,
                params.contact_recycling,
                params.warmstart_coefficient,
            ));
        }
        // The monitor's repair of a contact going deep: the solver at full strength
        // for a while (no tweak, no reduce, warm start and recycling on, twice the
        // iterations).
        let thin = !self.suspend_thinning;
        params.num_solver_iterations = if !thin {
            2 * c.iterations
        } else if c.tweak {
            c.tweak_iterations
        } else {
            c.iterations
        };
        let cache = c.cache || !thin;
        // On: the user's own recycling and warm start (recorded above), or both fully
        // on for the monitor's repair; off: both off.
        let (recycling, warmstart) = match self.user_params {
            Some((_, recycling, warmstart)) if thin => (recycling, warmstart),
            _ => (true, 1.0),
        };
        params.contact_recycling = cache && recycling;
        params.warmstart_coefficient = if cache { warmstart } else { 0.0 };
        mods.reduce_depth = (c.reduce && thin).then_some(c.reduce_depth);
        mods.zero = c.zero;

        let counts_changed = world.bodies.len() != self.known_bodies
            || world.colliders.len() != self.known_colliders;
        if self.dirty || counts_changed {
            self.dirty = false;
            self.known_bodies = world.bodies.len();
            self.known_colliders = world.colliders.len();
            let bodies = &*world.bodies;
            self.activations.retain(|_, (h, _)| bodies.contains(*h));
            let mut dynamic: Vec<RigidBodyHandle> = world
                .bodies
                .iter()
                .filter(|(_, b)| b.is_dynamic())
                .map(|(h, _)| h)
                .collect();
            dynamic.sort_by_key(|h| key(*h));
            for &h in &dynamic {
                let eligible = self.rest_of(h).is_some_and(|r| r.eligible);
                let rb = &mut world.bodies[h];
                // The layer owns sleeping: never eligible unless it says so.
                if !eligible {
                    remember_activation(&mut self.activations, h, rb);
                    never_activation(rb.activation_mut());
                }
                if c.damp {
                    self.damped
                        .entry(key(h))
                        .or_insert((h, rb.linear_damping()));
                    if rb.linear_damping() != c.damping {
                        rb.set_linear_damping(c.damping);
                    }
                }
            }
            if !c.damp {
                for (_, (h, original)) in std::mem::take(&mut self.damped) {
                    if let Some(rb) = world.bodies.get_mut(h) {
                        rb.set_linear_damping(original);
                    }
                }
            }
            // Reduce: the contact-modification flag on every dynamic collider.
            let mut want: Vec<ColliderHandle> = Vec::new();
            if c.reduce {
                for &h in &dynamic {
                    want.extend(world.bodies[h].colliders().iter().copied());
                }
            }
            if c.zero {
                for &h in &dynamic {
                    if self.is_sleepy(h) {
                        want.extend(world.bodies[h].colliders().iter().copied());
                    }
                }
            }
            want.sort_by_key(|c| c.into_raw_parts());
            want.dedup();
            self.set_modify_flags(world, &want);
            self.zero_flags.clear();
        } else if c.zero && !c.reduce && !self.zero_flags.is_empty() {
            for (h, on) in std::mem::take(&mut self.zero_flags) {
                let Some(rb) = world.bodies.get(h) else {
                    continue;
                };
                let colliders: Vec<ColliderHandle> = rb.colliders().to_vec();
                for ch in colliders {
                    self.flag_one(world, ch, on);
                }
            }
        }
        self.zero_flags.clear();

        // Written in handle order: Rapier records modified bodies in the order they
        // are written, and that order reaches its islands and solver. The decisions
        // come in group and neighbour order, which depends on the order the graph
        // learnt its edges in (Rapier's pairs or its events): sorted, the same
        // decisions give the same world whatever the tracking. (Stable: a body
        // decided twice keeps its last decision.)
        self.eligibility.sort_by_key(|(h, _)| key(*h));
        self.to_release.sort_by_key(|h| key(*h));
        self.to_fix.sort_by_key(|(h, _)| key(*h));
        for (h, eligible) in std::mem::take(&mut self.eligibility) {
            if let Some(rb) = world.bodies.get_mut(h) {
                if rb.is_dynamic() {
                    remember_activation(&mut self.activations, h, rb);
                    if eligible {
                        eligible_activation(rb.activation_mut(), dt);
                    } else {
                        never_activation(rb.activation_mut());
                    }
                }
            }
        }
        // A held body is fixed in Rapier, and Rapier asserts that a multibody's links
        // other than the root are dynamic: one the user joined to a multibody as a
        // link since it was fixated is released now, before Rapier's step.
        if !self.held.is_empty() && world.multibody_joints.multibodies().next().is_some() {
            for held in self.held.values() {
                let link = world.multibody_joints.rigid_body_link(held.handle);
                if link.is_some_and(|l| l.id != 0) && !self.to_release.contains(&held.handle) {
                    self.to_release.push(held.handle);
                    self.stats.releases = self.stats.releases.saturating_add(1);
                }
            }
        }
        self.hold_changes.clear();
        for h in std::mem::take(&mut self.to_release) {
            if let Some(held) = self.unhold(key(h)) {
                self.hold_changes.push((h, true));
                self.unparked.remove(&key(h));
                if let Some(rb) = held.give_back(world, user_passive) {
                    remember_activation(&mut self.activations, h, rb);
                    never_activation(rb.activation_mut());
                }
                self.released.push(held);
                let r = self.rest_mut(h);
                r.steps = 0;
                r.sleepy = false;
                r.eligible = false;
                mods.set_sleepy(h, false);
            }
        }
        for (h, supports) in std::mem::take(&mut self.to_fix) {
            let Some(rb) = world.bodies.get_mut(h) else {
                continue;
            };
            // Checked again now: the fixation was decided at the last analysis, and the
            // user may have changed the body since. A multibody member is never fixated
            // (a link must stay dynamic: Rapier asserts it; `decide` skips `Link` nodes
            // already), nor a disabled (passive) body.
            if !rb.is_dynamic()
                || !rb.is_enabled()
                || world.multibody_joints.rigid_body_link(h).is_some()
            {
                continue;
            }
            let held = Held {
                handle: h,
                linvel: rb.linvel(),
                angvel: rb.angvel(),
                supports,
                park: Park::Active,
                watched: Vec::new(),
            };
            rb.set_body_type(RigidBodyType::Fixed, false);
            self.hold(held);
            self.unparked.insert(key(h));
            self.newly_held.push(key(h));
            self.hold_changes.push((h, false));
        }
        self.park(world, user_passive);
        // Bodies removed while held are forgotten: looked for when the body count
        // changed (O(held)); a body removed and another inserted between two steps
        // leaves a stale entry until the count changes, which is harmless (handles
        // carry their generation, and every use of a held handle checks it exists).
        self.stats.parked = self.held.len().saturating_sub(self.unparked.len());
        if !counts_changed {
            self.stats.fixated = self.held.len();
            return;
        }
        let gone: Vec<(u32, u32)> = self
            .held
            .iter()
            .filter(|(_, h)| !world.bodies.contains(h.handle))
            .map(|(k, _)| *k)
            .collect();
        for k in gone {
            self.unhold(k);
            self.unparked.remove(&k);
            self.support_dirty = true;
        }
        self.stats.fixated = self.held.len();
    }

    /// Moves held bodies on their way out of Rapier's active set: those disabled at
    /// the last pre-step are enabled again (now parked), and the candidates chosen at
    /// the last analysis are disabled for one step, after checking them again against
    /// the world as it is now (the user may have changed them since). O(parking
    /// bodies + candidates' pairs).
    fn park(&mut self, world: &mut WorldMut, user_passive: &dyn Fn(RigidBodyHandle) -> bool) {
        self.parked_now.clear();
        for h in std::mem::take(&mut self.parking_now) {
            let Some(held) = self.held.get_mut(&key(h)) else {
                continue;
            };
            if held.park == Park::Parking {
                held.park = Park::Parked;
                match world.bodies.get_mut(h) {
                    Some(rb) if !user_passive(h) => {
                        rb.set_enabled(true);
                        self.parked_now.push(h);
                    }
                    _ => {}
                }
            }
        }
        for h in std::mem::take(&mut self.to_park) {
            let Some(held) = self.held.get_mut(&key(h)) else {
                continue;
            };
            let parkable = held.park == Park::Active
                && world
                    .bodies
                    .get(h)
                    .is_some_and(|rb| rb.is_fixed() && rb.is_enabled())
                && world.impulse_joints.attached_joints(h).next().is_none()
                && world.multibody_joints.rigid_body_link(h).is_none();
            if parkable {
                held.park = Park::Parking;
                self.unparked.remove(&key(h));
                self.parking_now.push(h);
                if let Some(rb) = world.bodies.get_mut(h) {
                    rb.set_enabled(false);
                }
            }
        }
    }

    /// Chooses the held bodies to park at the next pre-step: in Rapier's active set,
    /// without joints, and whose every collider pair has a fixed partner and neither
    /// touches nor intersects (so that disabling the body for a step changes no
    /// contact, no event and no neighbour). O(active held bodies × their pairs).
    fn choose_parking(&mut self, view: &WorldView) {
        self.to_park.clear();
        for k in &self.unparked {
            let Some(held) = self.held.get(k) else {
                continue;
            };
            if held.park != Park::Active || self.to_release.contains(&held.handle) {
                continue;
            }
            let h = held.handle;
            let Some(rb) = view.bodies.get(h) else {
                continue;
            };
            // Held bodies are fixated awake, so an `Active` one is in Rapier's active set.
            if !rb.is_fixed() || !rb.is_enabled() {
                continue;
            }
            if view.impulse_joints.attached_joints(h).next().is_some()
                || view.multibody_joints.rigid_body_link(h).is_some()
            {
                continue;
            }
            let fixed_partner = |c: ColliderHandle| {
                view.colliders.get(c).is_some_and(|co| {
                    co.parent()
                        .is_none_or(|p| view.bodies.get(p).is_some_and(|b| b.is_fixed()))
                })
            };
            let quiet = rb.colliders().iter().all(|&c| {
                view.narrow_phase.contact_pairs_with(c).all(|p| {
                    let other = crate::coherence::pairs::other_collider(p, c);
                    !p.has_any_active_contact() && fixed_partner(other)
                }) && view
                    .narrow_phase
                    .intersection_pairs_with(c)
                    .next()
                    .is_none()
            });
            if quiet {
                self.to_park.push(h);
            }
        }
    }

    /// Whether a held body is out of Rapier's active set or on its way (disabled for
    /// this step by the layer, not by the user). O(log held).
    pub fn is_parked(&self, h: RigidBodyHandle) -> bool {
        self.held
            .get(&key(h))
            .is_some_and(|held| held.park != Park::Active)
    }

    /// The held bodies the layer disabled for this step to take them out of Rapier's
    /// active set (they are enabled again at the next pre-step). O(1) per item.
    pub fn parking(&self) -> impl Iterator<Item = RigidBodyHandle> + '_ {
        self.parking_now.iter().copied()
    }

    /// The held bodies the last pre-step enabled again after their step out of
    /// Rapier's active set: Rapier pairs their colliders anew in this step, so a
    /// sensor widened meanwhile may find them inside. O(1) per item.
    pub(crate) fn parked_now(&self) -> &[RigidBodyHandle] {
        &self.parked_now
    }

    fn set_modify_flags(&mut self, world: &mut WorldMut, want: &[ColliderHandle]) {
        let current: Vec<(u32, u32)> = self.flagged.keys().copied().collect();
        for k in current {
            let keep = want
                .binary_search_by_key(&k, |c| c.into_raw_parts())
                .is_ok();
            if !keep {
                if let Some((ch, _)) = self.flagged.get(&k).copied() {
                    self.flag_one(world, ch, false);
                }
            }
        }
        for &ch in want {
            self.flag_one(world, ch, true);
        }
    }

    fn flag_one(&mut self, world: &mut WorldMut, ch: ColliderHandle, on: bool) {
        let k = ch.into_raw_parts();
        let Some(col) = world.colliders.get_mut(ch) else {
            self.flagged.remove(&k);
            return;
        };
        if on {
            self.flagged.entry(k).or_insert((ch, col.active_hooks()));
            let f = col.active_hooks() | ActiveHooks::MODIFY_SOLVER_CONTACTS;
            if f != col.active_hooks() {
                col.set_active_hooks(f);
            }
        } else if let Some((_, original)) = self.flagged.remove(&k) {
            let f = (col.active_hooks() - ActiveHooks::MODIFY_SOLVER_CONTACTS)
                | (original & ActiveHooks::MODIFY_SOLVER_CONTACTS);
            if f != col.active_hooks() {
                col.set_active_hooks(f);
            }
        }
    }

    /// Tracks the refreshed bodies' energy (before the groups are rebuilt, so that
    /// subgrouping sees this step's sleepy bodies). O(refreshed bodies).
    pub(crate) fn track(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        refreshed: &[NodeId],
        woke: &[(NodeId, bool)],
        mods: &mut ContactMods,
    ) {
        if self.detached {
            return;
        }
        self.sleepy_changed.clear();
        self.stats.sleepy = 0;
        self.stats.fixations = 0;
        self.stats.releases = 0;
        if refreshed.is_empty() && woke.is_empty() {
            return;
        }
        let c = self.config.clone();
        for &(n, awake) in woke {
            if awake {
                if let Some(h) = graph.body_of(n) {
                    let r = self.rest_mut(h);
                    r.steps = 0;
                    let was = std::mem::replace(&mut r.sleepy, false);
                    if was {
                        mods.set_sleepy(h, false);
                        self.zero_flags.push((h, false));
                        self.sleepy_changed.push(h);
                    }
                }
            }
        }
        for &n in refreshed {
            let Some(node) = graph.node(n) else { continue };
            let NodeSource::Body(h) = node.source() else {
                continue;
            };
            if !node.kind().is_simulated() || !node.is_awake() {
                continue;
            }
            let Some(rb) = view.bodies.get(h) else {
                continue;
            };
            let mass = rb.mass();
            let ke = if mass > 0.0 {
                rb.kinetic_energy() / mass
            } else {
                0.0
            };
            let at_rest = ke.is_finite() && ke < c.sleepy_energy;
            let r = self.rest_mut(h);
            r.steps = if at_rest {
                r.steps.saturating_add(1)
            } else {
                0
            };
            let sleepy = r.steps >= c.sleepy_steps;
            if sleepy != r.sleepy {
                r.sleepy = sleepy;
                mods.set_sleepy(h, sleepy);
                self.zero_flags.push((h, sleepy));
                self.sleepy_changed.push(h);
            }
            if sleepy {
                self.stats.sleepy = self.stats.sleepy.saturating_add(1);
            }
        }
    }

    /// Decides sleep eligibility and fixation after the groups were rebuilt.
    /// O(awake groups' members + fast bodies' contacts).
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
        // An idle step (nothing refreshed, touched or removed, no awake group): no
        // eligibility and no fixation or release to decide; what the support memory
        // depends on (gravity, static supporters' poses) is looked at as always.
        if refreshed.is_empty()
            && touched.is_empty()
            && removed.is_empty()
            && !nodes_removed
            && groups.iter_awake().next().is_none()
        {
            if self.config.fixate {
                let up = up_of(view.gravity);
                self.decide_support(graph, view, up, changes);
            }
            return;
        }
        let c = self.config.clone();
        let mut want: Vec<(RigidBodyHandle, bool)> = Vec::new();
        if c.sleepy {
            if c.groups {
                // The awake groups only: O(their members), not O(the slots the groups
                // have used), which a settled, held scene would pay every step. (Their
                // order does not matter: each body is in one group, and the pre-step
                // writes the decisions in handle order.)
                for (_, g) in groups.iter_awake() {
                    let from = want.len();
                    want.extend(
                        g.bodies
                            .iter()
                            .filter_map(|&n| graph.body_of(n))
                            .map(|h| (h, false)),
                    );
                    let all = want[from..].iter().all(|&(h, _)| self.is_sleepy(h));
                    if all {
                        for w in &mut want[from..] {
                            w.1 = true;
                        }
                    }
                }
                // Sleepy bodies outside any group (insulated by subgrouping) decide alone.
                for &n in refreshed {
                    if let Some(node) = graph.node(n) {
                        if node.kind().is_simulated() && node.group().is_none() {
                            if let Some(h) = node.body() {
                                want.push((h, self.is_sleepy(h)));
                            }
                        }
                    }
                }
            } else {
                for &n in refreshed {
                    if let Some(h) = graph.body_of(n) {
                        want.push((h, self.is_sleepy(h)));
                    }
                }
            }
        }
        for (h, eligible) in want {
            // Most decisions are those of the last step: the body is looked up in
            // Rapier only when its eligibility changes (a body without a record is
            // not eligible).
            if self.rest_of(h).is_some_and(|r| r.eligible) == eligible {
                continue;
            }
            if view.bodies.get(h).is_none_or(|b| !b.is_dynamic()) {
                continue;
            }
            let r = self.rest_mut(h);
            if r.eligible != eligible {
                r.eligible = eligible;
                self.eligibility.push((h, eligible));
            }
        }

        if c.fixate {
            let up = up_of(view.gravity);
            // Release: a fast, non-sleepy body touching a held one (none to look for
            // while nothing is held).
            for &n in refreshed.iter().filter(|_| !self.held.is_empty()) {
                let Some(node) = graph.node(n) else { continue };
                if !node.kind().is_simulated() || !node.is_awake() {
                    continue;
                }
                let Some(h) = node.body() else { continue };
                if self.is_sleepy(h) {
                    continue;
                }
                let Some(rb) = view.bodies.get(h) else {
                    continue;
                };
                if rb.linvel().length() <= c.release_speed {
                    continue;
                }
                for (m, _, e) in graph.neighbors(n) {
                    if e.kind() != EdgeKind::Physical || !e.is_touching() {
                        continue;
                    }
                    if let Some(mh) = graph.body_of(m) {
                        if self.is_fixated(mh) && !self.to_release.contains(&mh) {
                            self.to_release.push(mh);
                            self.stats.releases = self.stats.releases.saturating_add(1);
                        }
                    }
                }
            }
            // Fixate: every sleepy awake simulated body, with what holds it up now.
            let mut found = Vec::new();
            for &n in refreshed {
                let Some(node) = graph.node(n) else { continue };
                if node.kind() != NodeKind::Dynamic || !node.is_awake() {
                    continue;
                }
                let Some(h) = node.body() else { continue };
                if self.rest_of(h).is_some_and(|r| r.sleepy) && !self.is_fixated(h) {
                    let supports = if up.is_finite() && up != Vector::ZERO {
                        resting_supports(
                            graph,
                            view,
                            n,
                            up,
                            MIN_SUPPORT_COS,
                            SUPPORT_GAP,
                            &mut found,
                        );
                        found
                            .iter()
                            .map(|&m| Supporter {
                                node: m,
                                pose: graph
                                    .node(m)
                                    .filter(|s| s.kind() == NodeKind::Fixed)
                                    .and_then(|_| static_pose(graph, view, m)),
                            })
                            .collect()
                    } else {
                        Vec::new()
                    };
                    self.to_fix.push((h, supports));
                    self.stats.fixations = self.stats.fixations.saturating_add(1);
                }
            }
            self.decide_support(graph, view, up, changes);
        }
    }

    /// The support memory after the decisions (see [`Self::fixation_supported`]), with
    /// `up` against gravity ([`up_of`]): judged again when something it depends on
    /// changed ([`Self::support_changed`]): in part when only touches of held bodies
    /// began or ended or held bodies were released ([`Self::evaluate_support_from`]),
    /// in full otherwise; else only
    /// the newly held bodies, unless one of them is unsupported; then the held bodies
    /// to park are chosen.
    fn decide_support(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        up: Vector,
        changes: &StepChanges,
    ) {
        match self.support_changed(graph, view, up, changes) {
            SupportChange::Everything => self.evaluate_support(graph, view, up),
            SupportChange::Touches(mut keys) => {
                // Bodies held since the last evaluation are judged with the touched
                // ones, their static supporters watched from now on.
                keys.extend_from_slice(&self.newly_held);
                self.watch_newly_held(graph);
                self.evaluate_support_from(graph, view, up, keys);
            }
            SupportChange::Nothing { partial } => {
                if !self.newly_held.is_empty() && !self.judge_newly_held(graph, view) {
                    if partial {
                        let keys = self.newly_held.clone();
                        self.watch_newly_held(graph);
                        self.evaluate_support_from(graph, view, up, keys);
                    } else {
                        self.evaluate_support(graph, view, up);
                    }
                }
            }
        }
        self.newly_held.clear();
        self.choose_parking(view);
    }

    /// Judges the bodies held since the last evaluation alone, when nothing else
    /// changed: each is supported by a base of its own or by a remembered held
    /// supporter that is supported. Returns false (a full evaluation is needed) when
    /// one of them is not supported, since what rested on it may have lost its support
    /// too. O(new bodies × their supporters).
    fn judge_newly_held(&mut self, graph: &ContactGraph, view: &WorldView) -> bool {
        let up = self.support_up;
        let new = std::mem::take(&mut self.newly_held);
        let mut all = true;
        for &k in &new {
            let Some(held) = self.held.get(&k) else {
                continue;
            };
            let resting = rests_now(graph, view, held.handle, up);
            if resting {
                // As a full evaluation would: a later partial one judges it again.
                self.rest_based.insert(k);
            }
            let ok = resting
                || held.supports.iter().any(|s| {
                    let Some(node) = graph.node(s.node) else {
                        return false;
                    };
                    match node.body().filter(|&mh| self.held.contains_key(&key(mh))) {
                        Some(mh) => !new.contains(&key(mh)) && !self.unsupported.contains(&key(mh)),
                        None => self.static_support_holds(graph, view, node, s),
                    }
                });
            if !ok {
                all = false;
                break;
            }
        }
        self.newly_held = new;
        if all {
            self.watch_newly_held(graph);
        }
        all
    }

    /// Watches the static and scripted supporters of the bodies held since the last
    /// evaluation from now on ([`Self::rewatch`]). O(their supporters · log watch).
    fn watch_newly_held(&mut self, graph: &ContactGraph) {
        let new = std::mem::take(&mut self.newly_held);
        for k in &new {
            self.rewatch(graph, k);
        }
        self.newly_held = new;
    }

    /// The static and scripted supporters of a held body that the support memory
    /// watches (held supporters are not watched: their release judges again what
    /// rests on them). O(its supporters).
    fn watch_of(&self, graph: &ContactGraph, held: &Held) -> Vec<(NodeId, Option<Pose>)> {
        let mut out = Vec::new();
        for s in &held.supports {
            let Some(node) = graph.node(s.node) else {
                continue;
            };
            if node.body().is_some_and(|h| self.held.contains_key(&key(h))) {
                continue;
            }
            let watched = match node.kind() {
                NodeKind::Fixed => s.pose.is_some(),
                NodeKind::Kinematic => true,
                _ => false,
            };
            if watched {
                out.push((s.node, s.pose));
            }
        }
        out
    }

    /// Counts `entries` into the support watch (`add`) or out of it. O(entries · log
    /// watch), plus a shift where an entry appears or goes.
    fn watch_count(&mut self, entries: &[(NodeId, Option<Pose>)], add: bool) {
        for &(n, pose) in entries {
            let bits = pose_bits(pose);
            let at = self
                .support_watch
                .binary_search_by(|&(m, p, _)| m.cmp(&n).then_with(|| pose_bits(p).cmp(&bits)));
            match (at, add) {
                (Ok(i), true) => {
                    let c = &mut self.support_watch[i].2;
                    *c = c.saturating_add(1);
                }
                (Err(i), true) => self.support_watch.insert(i, (n, pose, 1)),
                (Ok(i), false) => {
                    let c = &mut self.support_watch[i].2;
                    *c = c.saturating_sub(1);
                    if *c == 0 {
                        self.support_watch.remove(i);
                    }
                }
                (Err(_), false) => {}
            }
        }
    }

    /// Replaces what held body `k` adds to the support watch by what it adds now.
    /// O(its supporters · log watch).
    fn rewatch(&mut self, graph: &ContactGraph, k: &(u32, u32)) {
        let Some(held) = self.held.get(k) else { return };
        let now = self.watch_of(graph, held);
        let Some(held) = self.held.get_mut(k) else {
            return;
        };
        let before = std::mem::replace(&mut held.watched, now.clone());
        self.watch_count(&before, false);
        self.watch_count(&now, true);
    }

    /// Whether a held body has a remembered supporter that holds it up by itself: one
    /// that is not a held body and still supports ([`Self::static_support_holds`]).
    /// O(its supporters).
    fn holds_alone(&self, graph: &ContactGraph, view: &WorldView, held: &Held) -> bool {
        held.supports.iter().any(|s| {
            graph.node(s.node).is_some_and(|node| {
                !node.body().is_some_and(|h| self.held.contains_key(&key(h)))
                    && self.static_support_holds(graph, view, node, s)
            })
        })
    }

    /// Whether a supporter that is not a held body still supports: static geometry
    /// where it was, a scripted body not moving. (A simulated supporter supports only
    /// through a touching contact now.)
    fn static_support_holds(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        node: &crate::graph::Node,
        s: &Supporter,
    ) -> bool {
        match node.kind() {
            NodeKind::Fixed => s.pose.is_some() && static_pose(graph, view, s.node) == s.pose,
            NodeKind::Kinematic => node
                .body()
                .and_then(|mh| view.bodies.get(mh))
                .is_some_and(|rb| !crate::world::moves(rb)),
            _ => false,
        }
    }

    /// What the support memory must judge again since its last evaluation: everything
    /// when held bodies were removed from the world, "up" turned, a node was removed,
    /// a static supporter moved or a scripted one moves (or no partial judgement
    /// applies); the held ends when only touching contacts of held bodies began or
    /// ended or held bodies were released; nothing else. A
    /// touch that ended is a touched edge marked `Vanished` under proximity tracking,
    /// and a removed edge that was touching under touching tracking (which keeps an
    /// edge only while it touches) or when a kind change dropped it: both are looked
    /// at, so that both trackings decide the same.
    /// O(touched and removed edges + distinct static and scripted supporters).
    fn support_changed(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        up: Vector,
        changes: &StepChanges,
    ) -> SupportChange {
        let StepChanges {
            touched,
            removed,
            nodes_removed,
            step,
            ..
        } = *changes;
        if self.support_dirty || nodes_removed || up != self.support_up {
            return SupportChange::Everything;
        }
        let held_key = |n: NodeId| {
            graph
                .body_of(n)
                .map(key)
                .filter(|k| self.held.contains_key(k))
        };
        // The held ends of touches that began or ended (an edge's two ends in order).
        let mut keys = Vec::new();
        let mut note = |a: NodeId, b: NodeId| {
            let (ka, kb) = (held_key(a), held_key(b));
            keys.extend(ka.into_iter().chain(kb));
        };
        for e in touched.iter().filter_map(|&e| graph.edge(e)) {
            if e.kind() == EdgeKind::Physical
                && matches!(
                    e.touching_mark(step),
                    Some(crate::graph::Transition::New | crate::graph::Transition::Vanished)
                )
            {
                note(e.a(), e.b());
            }
        }
        for e in removed {
            if e.kind() == EdgeKind::Physical && e.cache().touching_old {
                note(e.a(), e.b());
            }
        }
        // A static supporter moved, or a scripted one moves: everything. A watched
        // supporter no longer of the kind it was watched as (retyped in place) changes
        // nothing by itself, as before, but rules out a partial evaluation.
        let mut retyped = false;
        for &(n, pose, _) in &self.support_watch {
            let node = graph.node(n);
            let moved = match pose {
                Some(p) => {
                    retyped |= node.is_none_or(|x| x.kind() != NodeKind::Fixed);
                    static_pose(graph, view, n) != Some(p)
                }
                None => {
                    retyped |= node.is_none_or(|x| x.kind() != NodeKind::Kinematic);
                    graph
                        .body_of(n)
                        .and_then(|h| view.bodies.get(h))
                        .is_none_or(crate::world::moves)
                }
            };
            if moved {
                return SupportChange::Everything;
            }
        }
        let partial = !retyped && self.support_partial_ok && up.is_finite() && up != Vector::ZERO;
        match (keys.is_empty() && self.released.is_empty(), partial) {
            (true, _) => SupportChange::Nothing { partial },
            (false, false) => SupportChange::Everything,
            (false, true) => SupportChange::Touches(keys),
        }
    }

    /// Whether a body held by fixation is still supported against gravity: `None` for
    /// a body that is not held. O(1) (evaluated once per step, after the decisions).
    ///
    /// Why this is needed: a fixated body is fixed in Rapier, and Rapier computes no
    /// contacts between two fixed bodies, so neither Rapier nor the graph knows what a
    /// fixated body rests on once its neighbours are fixed too. What supported it
    /// when it was fixated is remembered, and the support still holds while one of
    /// those supporters still does: static geometry; a scripted body that is not
    /// moving; a held body that is itself supported (recursively); or any touching
    /// contact that pushes it up now (Rapier computes those with the bodies that are
    /// not fixed). A chain of fixated bodies is judged through the chain, so taking
    /// the bottom of a fixated pile away leaves the bodies above it unsupported.
    pub fn fixation_supported(&self, h: RigidBodyHandle) -> Option<bool> {
        let k = key(h);
        self.held
            .contains_key(&k)
            .then(|| !self.unsupported.contains(&k))
    }

    /// The bodies held by fixation whose support is gone, in handle order. O(their
    /// number).
    pub fn unsupported_fixated(&self) -> impl Iterator<Item = RigidBodyHandle> + '_ {
        self.unsupported
            .iter()
            .filter_map(|k| self.held.get(k).map(|h| h.handle))
    }

    /// The supporters remembered for a body held by fixation (what held it against
    /// gravity when it was fixated), in the order found; `None` for a body that is not
    /// held. O(1).
    pub fn fixation_supporters(&self, h: RigidBodyHandle) -> Option<Vec<NodeId>> {
        self.held
            .get(&key(h))
            .map(|held| held.supports.iter().map(|s| s.node).collect())
    }

    /// Re-evaluates [`Self::fixation_supported`] for every held body: the least fixed
    /// point of "supported" — a held body is supported if something supports it now
    /// (a touching contact that pushes it up, computed by Rapier against bodies that
    /// are not fixed), if a remembered static supporter is still where it was, or a
    /// remembered scripted supporter is not moving; or if a remembered supporter is a
    /// held body that is supported. Computed from the bases up (a cycle of held bodies
    /// resting on each other supports nothing by itself). O(held bodies + their
    /// remembered supporters).
    fn evaluate_support(&mut self, graph: &ContactGraph, view: &WorldView, up: Vector) {
        self.support_dirty = false;
        self.support_up = up;
        self.support_watch.clear();
        self.released.clear();
        let keys: Vec<(u32, u32)> = self.held.keys().copied().collect();
        for k in &keys {
            if let Some(held) = self.held.get_mut(k) {
                held.watched.clear();
            }
            self.rewatch(graph, k);
        }
        self.unsupported.clear();
        self.rest_based.clear();
        self.support_partial_ok = true;
        if !(up.is_finite() && up != Vector::ZERO) || keys.is_empty() {
            return;
        }
        let (supported, resting) =
            self.judge_support(graph, view, up, &keys, self.held.values(), &BTreeMap::new());
        self.apply_judgement(&keys, &supported, &resting);
    }

    /// Judges the held bodies `judged` (sorted keys of held bodies; `records`, their
    /// held records in the same order): "supported" as the least fixed point from the
    /// bases up (see [`Self::fixation_supported`]), a held supporter outside `judged`
    /// counting as supported. Returns, per judged body, whether it is supported and
    /// whether it rests on a contact Rapier computes now. O(judged bodies × their
    /// contact pairs and remembered supporters).
    fn judge_support<'h>(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        up: Vector,
        judged: &[(u32, u32)],
        records: impl Iterator<Item = &'h Held>,
        rests: &BTreeMap<(u32, u32), bool>,
    ) -> (Vec<bool>, Vec<bool>) {
        // Judged bodies by index (keys are sorted: a held supporter is found by binary
        // search); "supporter i holds up dependent j" as pairs, sorted into ranges.
        let index = |k: (u32, u32)| judged.binary_search(&k).ok();
        // Only a partial judgement has held supporters outside the judged bodies.
        let partial = judged.len() < self.held.len();
        let mut supported = vec![false; judged.len()];
        let mut resting = vec![false; judged.len()];
        let mut links: Vec<(usize, usize)> = Vec::new();
        let mut queue: Vec<usize> = Vec::new();
        for (i, held) in records.enumerate() {
            if graph.node_of_body(held.handle).is_none() {
                continue;
            }
            let mut base = match rests.get(&key(held.handle)) {
                Some(&r) => r,
                None => rests_now(graph, view, held.handle, up),
            };
            resting[i] = base;
            for s in &held.supports {
                if base {
                    break;
                }
                let Some(node) = graph.node(s.node) else {
                    continue;
                };
                match node.body().map(key) {
                    Some(mk) => match index(mk) {
                        Some(j) => links.push((j, i)),
                        None if partial && self.held.contains_key(&mk) => base = true,
                        None => base = self.static_support_holds(graph, view, node, s),
                    },
                    None => base = self.static_support_holds(graph, view, node, s),
                }
            }
            if base {
                supported[i] = true;
                queue.push(i);
            }
        }
        propagate_support(&mut links, &mut supported, queue);
        (supported, resting)
    }

    /// Records a judgement ([`Self::judge_support`]) of the held bodies `judged` in
    /// the unsupported and resting sets. O(judged · log held).
    fn apply_judgement(&mut self, judged: &[(u32, u32)], supported: &[bool], resting: &[bool]) {
        for (i, k) in judged.iter().enumerate() {
            if supported[i] {
                self.unsupported.remove(k);
            } else {
                self.unsupported.insert(*k);
            }
            if resting[i] {
                self.rest_based.insert(*k);
            } else {
                self.rest_based.remove(k);
            }
        }
    }

    /// Judges the support memory again after touches of held bodies began or ended or
    /// held bodies were released, and nothing else it depends on changed
    /// ([`Self::support_changed`]): only the held bodies whose status those changes
    /// can change. "Supported" is a least fixed point, so this is the delete-and-
    /// rederive of incremental fixed points: the bodies that may have *lost* their
    /// support are `changed` (the held ends of the touches), those resting on a
    /// contact Rapier computes at the last evaluation (such a contact can end without
    /// a touch ending) and those that remember a released body; they are judged with
    /// everything that remembers one of them as a supporter, transitively, except
    /// through a body that has a base of its own now (a computed resting contact, or
    /// static or scripted support that still holds): that one is supported whatever
    /// else changed. The unsupported bodies can only *gain* support, and are judged
    /// too. Every other held body is supported, as before: its support runs through
    /// bases that did not change and held bodies outside the set. The judged bodies'
    /// watched supporters are counted again, the released bodies' taken off. The same
    /// result as [`Self::evaluate_support`], watch included (checked against it after
    /// every partial evaluation in debug builds). O(the judged bodies × (their contact
    /// pairs + their entries in the dependents index · log)); the index is kept
    /// between steps ([`Self::hold`]).
    fn evaluate_support_from(
        &mut self,
        graph: &ContactGraph,
        view: &WorldView,
        up: Vector,
        changed: Vec<(u32, u32)>,
    ) {
        use std::collections::BTreeSet;
        // The released bodies are held no more: their records leave the sets and the
        // watch, and what rested on them is judged again.
        let released = std::mem::take(&mut self.released);
        for r in &released {
            let k = key(r.handle);
            if !self.held.contains_key(&k) {
                self.unsupported.remove(&k);
                self.rest_based.remove(&k);
            }
            self.watch_count(&r.watched, false);
        }
        let node_of = |k: &(u32, u32)| {
            self.held
                .get(k)
                .and_then(|held| graph.node_of_body(held.handle))
        };
        let dependents_of = |n: NodeId| {
            self.dependents
                .range((n, (0, 0))..=(n, (u32::MAX, u32::MAX)))
                .map(|&(_, d)| d)
        };
        // Bodies that may have lost their support: the held ends of the touches, those
        // resting on a computed contact at the last evaluation (it may have ended), and
        // what remembered a released body.
        let mut maybe_lost: BTreeSet<(u32, u32)> = changed.into_iter().collect();
        maybe_lost.extend(self.rest_based.iter().copied());
        for r in &released {
            if let Some(n) = graph.node_of_body(r.handle) {
                maybe_lost.extend(dependents_of(n));
            }
        }
        // Whether a held body rests on a contact Rapier computes now, read once.
        let mut rests: BTreeMap<(u32, u32), bool> = BTreeMap::new();
        let mut based = |k: &(u32, u32)| {
            self.held.get(k).is_some_and(|held| {
                *rests
                    .entry(*k)
                    .or_insert_with(|| rests_now(graph, view, held.handle, up))
                    || self.holds_alone(graph, view, held)
            })
        };
        // What rests on a body that may have lost its support is judged again with it,
        // transitively; a body with a base of its own now (a computed resting contact,
        // static geometry in place, a scripted body at rest) is supported whatever else
        // changed, so nothing loses its support through it and its dependents are left
        // out. Unsupported bodies can only gain support: judged, but what rests on
        // them was supported through something else or is unsupported itself.
        let mut judged: BTreeSet<(u32, u32)> = maybe_lost.clone();
        judged.extend(self.unsupported.iter().copied());
        let mut stack: Vec<NodeId> = maybe_lost
            .iter()
            .filter(|k| !based(k))
            .filter_map(node_of)
            .collect();
        while let Some(n) = stack.pop() {
            for d in dependents_of(n) {
                if judged.insert(d) && !based(&d) {
                    stack.extend(node_of(&d));
                }
            }
        }
        let judged: Vec<(u32, u32)> = judged
            .into_iter()
            .filter(|k| self.held.contains_key(k))
            .collect();
        let records = judged.iter().filter_map(|k| self.held.get(k));
        let (supported, resting) = self.judge_support(graph, view, up, &judged, records, &rests);
        self.apply_judgement(&judged, &supported, &resting);
        for k in &judged {
            self.rewatch(graph, k);
        }
        self.support_dirty = false;
        self.support_up = up;
        #[cfg(debug_assertions)]
        {
            debug_assert_eq!(
                self.dependents_of_records(),
                self.dependents,
                "the dependents index is stale"
            );
            let mut full = self.clone();
            full.evaluate_support(graph, view, up);
            debug_assert_eq!(
                full.unsupported, self.unsupported,
                "the partial support evaluation differs from the full one"
            );
            debug_assert_eq!(
                full.support_watch, self.support_watch,
                "the support watch differs from a full evaluation's"
            );
        }
    }

    /// Wakes a body for the monitor's repair: releases it if fixated, and starts its
    /// rest count again (not sleepy, not sleep-eligible), so that its group is not put
    /// back to sleep before it has moved. O(1).
    pub(crate) fn repair_wake(&mut self, h: RigidBodyHandle, mods: &mut ContactMods) {
        if self.is_fixated(h) && !self.to_release.contains(&h) {
            self.to_release.push(h);
            self.stats.releases = self.stats.releases.saturating_add(1);
        }
        self.to_fix.retain(|(f, _)| *f != h);
        let r = self.rest_mut(h);
        r.steps = 0;
        let was_sleepy = std::mem::replace(&mut r.sleepy, false);
        let was_eligible = std::mem::replace(&mut r.eligible, false);
        if was_sleepy {
            mods.set_sleepy(h, false);
            self.zero_flags.push((h, false));
        }
        if was_eligible {
            self.eligibility.push((h, false));
        }
    }

    /// The bodies the next pre-step releases from fixation.
    pub(crate) fn pending_releases(&self) -> &[RigidBodyHandle] {
        &self.to_release
    }
}
