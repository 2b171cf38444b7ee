//! Events (paper §4, Table 3, plus sleep and wake) delivered on crossbeam channels.
//!
//! # The listener contract
//! - **When.** Events are generated once per step, at the end of the analysis: the
//!   paper's "safe point" (its second solution). Nothing is sent from inside Rapier's
//!   step, so a receiver may read the graph (through the layer) while handling events.
//! - **Which step.** Every event carries the index of the step it describes
//!   ([`crate::LayerAnalysis::current_step`] right after that step).
//! - **Pairs.** `node1` is the node with the smaller slot index (the paper's *A*),
//!   `node2` the other; for sensor events `node1` is the sensor. `body1` /
//!   `collider1` are `node1`'s; a pair touching through several collider pairs names
//!   one, chosen as [`Event::collider1`] says.
//! - **Normals** point from the first thing named to the second, as Rapier's manifold
//!   normal: an event's [`Event::normal`] from `node1` towards `node2`, an edge's
//!   [`ContactCache::normal`](crate::ContactCache::normal) from *A* to *B*,
//!   [`ContactLayer::contact_details(w, body, other)`](crate::ContactLayer::contact_details)
//!   from `body` towards `other` (`tests/normal_convention.rs`).
//! - **Lifecycle.** For a pair, every `ProximityStarted` is followed by zero or more
//!   `ProximityPersisted` and exactly one `ProximityStopped`; likewise
//!   `ContactStarted` / `ContactPersisted` / `ContactStopped`, nested inside the
//!   proximity span; `SensorStarted` and `SensorStopped` alternate. Removing a body (or making it
//!   passive) ends every span it is part of, in the step the layer sees it go.
//! - **Persisted events** are sent only for pairs with an awake body; the pairs of
//!   sleeping bodies are frozen (queries on the graph stay exact for them).
//! - **Order within a step** (deterministic: the same inputs give the same stream):
//!   1. ends of edges removed with a node (`ContactStopped`, `ProximityStopped`,
//!      `SensorStopped`), in removal order;
//!   2. edge events, edge by edge in the order the analysis refreshed them (Rapier's
//!      pair order, then vanished edges): `ProximityStarted`, `ContactStarted`,
//!      `ProximityPersisted`, `ContactPersisted`, `ContactStopped`, `ProximityStopped`;
//!      trigger edges give `SensorStarted` / `SensorStopped`;
//!   3. `FellAsleep` / `WokeUp`, in the order the bodies were refreshed;
//!   4. `TimerTick`, timers in slot order, ticks ascending;
//!   5. `Violation`, then `Repaired` (monitor on): by violation kind, then body
//!      handle.
//! - **Back-pressure.** A step never blocks. An unbounded subscription
//!   ([`crate::ContactLayer::subscribe`]) never drops. A bounded one
//!   ([`crate::ContactLayer::subscribe_bounded`]) drops the *newest* events that do
//!   not fit and counts them ([`EventBus::dropped`]). A subscription whose receiver
//!   was dropped is removed the first time an event for it cannot be delivered.
//! - **Cost.** Events of kinds nobody subscribed to are not generated.

mod bus;
pub(crate) mod collect;

pub use bus::{EventBus, SubscriptionId};

use rapier3d::math::{Real, Vector};
use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

use crate::graph::NodeId;

/// The largest capacity of a bounded subscription (crossbeam allocates it up front).
pub const MAX_CAPACITY: usize = 1 << 24;

/// The kinds of event.
///
/// Named as Rapier names its collision events (`CollisionEvent::Started` /
/// `Stopped`): `Contact*` for touching pairs (the paper's touch begin / end),
/// `Sensor*` for bodies entering and leaving a sensor collider (the paper's trigger
/// volume), `Proximity*` for narrow-phase pairs.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[repr(u8)]
pub enum EventKind {
    /// Two bodies came into close proximity (a Rapier narrow-phase pair appeared).
    ProximityStarted = 0,
    /// Two awake bodies stayed in close proximity.
    ProximityPersisted = 1,
    /// Two bodies left close proximity (or one was removed or disabled).
    ProximityStopped = 2,
    /// Two bodies started touching (Rapier's `CollisionEvent::Started` of a
    /// non-sensor pair; the paper's touch begin).
    ContactStarted = 3,
    /// Two bodies, one awake, kept touching.
    ContactPersisted = 4,
    /// Two bodies stopped touching (Rapier's `CollisionEvent::Stopped`; the paper's
    /// touch end).
    ContactStopped = 5,
    /// A body entered a sensor collider (Rapier's `CollisionEvent::Started` with a
    /// sensor; the paper's trigger enter).
    SensorStarted = 6,
    /// A body left a sensor collider (the paper's trigger exit).
    SensorStopped = 7,
    /// A timer's period elapsed.
    TimerTick = 8,
    /// A body fell asleep.
    FellAsleep = 9,
    /// A body woke up.
    WokeUp = 10,
    /// The plausibility monitor found a violation (paper §8):
    /// `node1` is the body's node, `violation` the kind, `value` the measure. Sent only
    /// with the layer's monitor in report or repair mode
    /// ([`crate::MonitorMut::set`]).
    Violation = 11,
    /// The monitor in repair mode acted to prevent a violation: `node1` is the body's
    /// node, `violation` the kind it prevents, `value` the measure when it acted
    /// (seconds unsupported; excess joules; for a deep penetration, the depth as a
    /// fraction of the limit).
    Repaired = 12,
}

impl EventKind {
    /// All kinds, in declaration order.
    pub const ALL: [EventKind; 13] = [
        EventKind::ProximityStarted,
        EventKind::ProximityPersisted,
        EventKind::ProximityStopped,
        EventKind::ContactStarted,
        EventKind::ContactPersisted,
        EventKind::ContactStopped,
        EventKind::SensorStarted,
        EventKind::SensorStopped,
        EventKind::TimerTick,
        EventKind::FellAsleep,
        EventKind::WokeUp,
        EventKind::Violation,
        EventKind::Repaired,
    ];

    const fn bit(self) -> u16 {
        1 << self as u8
    }
}

/// A set of event kinds.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, Default)]
pub struct KindSet(u16);

impl KindSet {
    /// No kind.
    pub const NONE: KindSet = KindSet(0);
    /// Every kind.
    pub const ALL: KindSet = KindSet((1 << EventKind::ALL.len()) - 1);
    /// Proximity started / persisted / stopped.
    pub const PROXIMITY: KindSet = KindSet(0b000_0000_0111);
    /// Contact started / persisted / stopped (the paper's touch begin / persist / end).
    pub const CONTACT: KindSet = KindSet(0b000_0011_1000);
    /// Sensor started / stopped (the paper's trigger enter / exit).
    pub const SENSOR: KindSet = KindSet(0b000_1100_0000);
    /// What Rapier's `ActiveEvents::COLLISION_EVENTS` gives: contact started / stopped
    /// and sensor started / stopped (`CollisionEvent::Started` / `Stopped`). The
    /// subscription for "who touches what" that costs least: unlike
    /// [`Self::CONTACT`], it leaves out `ContactPersisted`, which needs every pair
    /// read each step.
    pub const COLLISION_EVENTS: KindSet = KindSet(0b000_1110_1000);
    /// Fell asleep / woke up.
    pub const SLEEP: KindSet = KindSet(0b110_0000_0000);
    /// Violation / repaired (the plausibility monitor's).
    pub const MONITOR: KindSet = KindSet(0b1_1000_0000_0000);
    /// The kinds only proximity tracking produces (`Proximity*` and `ContactPersisted`):
    /// a subscription to one of them needs every pair read each step
    /// ([`crate::coherence::Tracking`]).
    pub const NEEDS_EVERY_PAIR: KindSet =
        KindSet(KindSet::PROXIMITY.0 | 1 << EventKind::ContactPersisted as u16);

    /// The set of the given kinds.
    pub fn of(kinds: &[EventKind]) -> KindSet {
        KindSet(kinds.iter().fold(0, |acc, k| acc | k.bit()))
    }
    /// Whether `kind` is in the set.
    #[inline]
    pub const fn contains(self, kind: EventKind) -> bool {
        self.0 & kind.bit() != 0
    }
    /// The union of two sets.
    #[inline]
    pub const fn union(self, other: KindSet) -> KindSet {
        KindSet(self.0 | other.0)
    }
    /// The kinds of `self` that are not in `other`.
    pub const fn without(self, other: KindSet) -> KindSet {
        KindSet(self.0 & !other.0)
    }
    /// Whether the set is empty.
    #[inline]
    pub const fn is_empty(self) -> bool {
        self.0 == 0
    }
    /// Whether the two sets share a kind.
    #[inline]
    pub const fn intersects(self, other: KindSet) -> bool {
        self.0 & other.0 != 0
    }
}

/// `KindSet::CONTACT | KindSet::SENSOR`, as Rapier's flags combine.
impl std::ops::BitOr for KindSet {
    type Output = KindSet;
    #[inline]
    fn bitor(self, other: KindSet) -> KindSet {
        self.union(other)
    }
}

impl std::ops::BitOrAssign for KindSet {
    #[inline]
    fn bitor_assign(&mut self, other: KindSet) {
        *self = self.union(other);
    }
}

/// `KindSet::CONTACT | EventKind::FellAsleep`.
impl std::ops::BitOr<EventKind> for KindSet {
    type Output = KindSet;
    #[inline]
    fn bitor(self, kind: EventKind) -> KindSet {
        KindSet(self.0 | kind.bit())
    }
}

/// `EventKind::ContactStarted | EventKind::ContactStopped`.
impl std::ops::BitOr for EventKind {
    type Output = KindSet;
    #[inline]
    fn bitor(self, other: EventKind) -> KindSet {
        KindSet(self.bit() | other.bit())
    }
}

impl From<EventKind> for KindSet {
    fn from(kind: EventKind) -> KindSet {
        KindSet(kind.bit())
    }
}

/// One event. `Copy`, at most 112 bytes: cheap to send (checked by a unit test).
///
/// The two things an event names are `1` and `2`, as Rapier's `collider1` /
/// `collider2` (the paper's *A* and *B*): [`Self::node1`] / [`Self::node2`], their
/// bodies [`Self::body1`] / [`Self::body2`] and colliders [`Self::collider1`] /
/// [`Self::collider2`]. Serialised events with the old names (`a` / `b`, `body_a` /
/// `body_b`, `collider_a` / `collider_b`) still load.
///
/// Equality and hashing compare `value` by its bits (a monitor measure is never NaN).
#[derive(Copy, Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Event {
    /// The step the event describes.
    pub step: u64,
    /// What happened.
    pub kind: EventKind,
    /// The pair's first node (the paper's *A*: the smaller slot index), the sensor,
    /// the timer, or the body that slept or woke.
    pub node1: NodeId,
    /// The pair's second node (the paper's *B*), or the body entering or leaving the
    /// sensor.
    pub node2: Option<NodeId>,
    /// The Rapier body of `node1`, if it is (or was) a body; for a sensor, the body
    /// carrying its sensor collider.
    pub body1: Option<RigidBodyHandle>,
    /// The Rapier body of `node2`, if it is (or was) a body.
    pub body2: Option<RigidBodyHandle>,
    /// `node1`'s collider in the collider pair the event is about, as Rapier's
    /// `CollisionEvent` names it (`collider1` / `collider2`, reordered so that
    /// `collider1` belongs to `node1`): for contact and proximity events a collider of
    /// `body1` (or the parentless collider `node1` is), for sensor events the sensor
    /// collider that fired. `None` for timer, sleep and monitor events.
    ///
    /// Two bodies touching through several collider pairs (compound bodies) are one
    /// pair of nodes; their events name one of those collider pairs, the same under
    /// either tracking and either pair walk: when the bodies start touching, the
    /// touching pair with the smallest handles (`collider1`'s index and generation
    /// first, then `collider2`'s); it stays named while it touches; if it stops while
    /// others still touch, the smallest of those; when the bodies stop touching, the
    /// pair named last (one of the last to stop). Proximity events name a pair in
    /// proximity the same way (the touching one while the bodies touch), sensor events
    /// the sensor and a collider of the body inside it. All of the pairs of two
    /// bodies: Rapier's narrow phase (`contact_pair`, `contact_pairs_with`).
    #[cfg_attr(feature = "serde", serde(default))]
    pub collider1: Option<ColliderHandle>,
    /// `node2`'s collider in the event's collider pair, as Rapier's `collider2`: a
    /// collider of `body2` (or the parentless collider `node2` is), or for a sensor
    /// event the collider that entered or left the sensor; see [`Self::collider1`].
    #[cfg_attr(feature = "serde", serde(default))]
    pub collider2: Option<ColliderHandle>,
    /// The tick count of a [`EventKind::TimerTick`] (1 for the first); 0 otherwise.
    pub tick: u64,
    /// For [`EventKind::Violation`] and [`EventKind::Repaired`]: the kind of
    /// violation; `None` otherwise.
    pub violation: Option<ViolationKind>,
    /// For [`EventKind::Violation`] and [`EventKind::Repaired`]: the measure (see
    /// `monitor::Violation::value`); 0 otherwise.
    pub value: Real,
    /// For [`EventKind::ContactStarted`] and [`EventKind::ContactPersisted`]: the
    /// normal of the deepest contact of the two bodies in the step (over all their
    /// collider pairs), a unit vector pointing from `node1` towards `node2` (`node2` is
    /// pushed along it; the crate's one convention, module docs "Normals"); zero for
    /// other kinds, or
    /// when Rapier had no contact point. Read from the edge's per-step details, or
    /// from Rapier's narrow phase when those are not kept (touching tracking, details
    /// off).
    #[cfg_attr(feature = "serde", serde(default))]
    pub normal: Vector,
    /// For [`EventKind::ContactStarted`] and [`EventKind::ContactPersisted`]: the sum
    /// of the normal impulses Rapier's solver applied to the pair's contacts in the
    /// step (N·s); 0 otherwise.
    #[cfg_attr(feature = "serde", serde(default))]
    pub impulse: Real,
}

impl Event {
    /// A pair, trigger, timer or sleep event (no monitor fields).
    pub(crate) fn plain(
        step: u64,
        kind: EventKind,
        node1: NodeId,
        node2: Option<NodeId>,
        body1: Option<RigidBodyHandle>,
        body2: Option<RigidBodyHandle>,
        tick: u64,
    ) -> Self {
        Self {
            step,
            kind,
            node1,
            node2,
            body1,
            body2,
            collider1: None,
            collider2: None,
            tick,
            violation: None,
            value: 0.0,
            normal: Vector::ZERO,
            impulse: 0.0,
        }
    }

    fn key(&self) -> impl PartialEq + std::hash::Hash + '_ {
        (
            self.step,
            self.kind,
            self.node1,
            self.node2,
            self.body1,
            self.body2,
            self.collider1,
            self.collider2,
            self.tick,
            self.violation,
            (
                self.value.to_bits(),
                self.normal.to_array().map(Real::to_bits),
                self.impulse.to_bits(),
            ),
        )
    }
}

impl PartialEq for Event {
    fn eq(&self, other: &Self) -> bool {
        self.key() == other.key()
    }
}

impl Eq for Event {}

impl std::hash::Hash for Event {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.key().hash(state)
    }
}

/// Which events a subscription receives: kinds, and optionally what they involve,
/// by Rapier handle or by node.
///
/// - [`Self::with_bodies`]: events naming one of the bodies in
///   [`Event::body1`] or [`Event::body2`]: its contacts, the sensors it enters and
///   leaves, its sleep, the monitor's reports on it, and the sensor events of
///   sensors it carries (a sensor event's `body1` is its carrier).
/// - [`Self::with_colliders`]: events naming one of the colliders in
///   [`Event::collider1`] or [`Event::collider2`]: a collider's contacts and
///   proximity (as Rapier's collision events name them), a sensor's events, the
///   sensor events of a collider entering or leaving a sensor. Two bodies touching
///   through several collider pairs send one event per change, naming one pair (see
///   [`Event::collider1`]): to follow every contact of a compound body, filter by its
///   body.
/// - [`Self::with_nodes`]: events whose `node1` or `node2` is one of the nodes, or a member
///   of one of them (a container node matches the events of its bodies); for what has
///   no Rapier handle (rules, timers, containers).
///
/// Restrictions add up: with several, an event passes if it involves anything any
/// of them names. Cost per event and subscription: O(log n) per restriction of n
/// handles; a node restriction adds O(degree) for container membership.
///
/// # Example
/// ```
/// use rapier3d::prelude::*;
/// use rapier_contact_graph::events::{EventKind, Filter, KindSet};
/// let f = Filter::kinds(KindSet::CONTACT).or_kind(EventKind::SensorStarted);
/// assert!(f.kinds_set().contains(EventKind::ContactStarted));
/// assert!(!f.kinds_set().contains(EventKind::ProximityStarted));
///
/// // The touches of one body, by its Rapier handle.
/// let mut bodies = RigidBodySet::new();
/// let ball = bodies.insert(RigidBodyBuilder::dynamic());
/// let touches_of_ball = Filter::kinds(KindSet::CONTACT).with_bodies(&[ball]);
/// assert_eq!(touches_of_ball.bodies(), Some(&[ball][..]));
/// ```
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Filter {
    kinds: KindSet,
    nodes: Option<Vec<NodeId>>,
    bodies: Option<Vec<RigidBodyHandle>>,
    colliders: Option<Vec<ColliderHandle>>,
}

impl Default for Filter {
    fn default() -> Self {
        Self::all()
    }
}

impl Filter {
    /// Every event.
    pub fn all() -> Self {
        Self::kinds(KindSet::ALL)
    }
    /// Events of the given kinds.
    pub fn kinds(kinds: KindSet) -> Self {
        Self {
            kinds,
            nodes: None,
            bodies: None,
            colliders: None,
        }
    }
    /// Restricts to events naming one of `bodies` (see the type's docs). O(n log n).
    pub fn with_bodies(mut self, bodies: &[RigidBodyHandle]) -> Self {
        self.bodies = Some(sorted_handles(bodies, RigidBodyHandle::into_raw_parts));
        self
    }
    /// Restricts to events naming one of `colliders` (see the type's docs).
    /// O(n log n).
    pub fn with_colliders(mut self, colliders: &[ColliderHandle]) -> Self {
        self.colliders = Some(sorted_handles(colliders, ColliderHandle::into_raw_parts));
        self
    }
    /// The body restriction, if any (sorted by index and generation).
    pub fn bodies(&self) -> Option<&[RigidBodyHandle]> {
        self.bodies.as_deref()
    }
    /// The collider restriction, if any (sorted by index and generation).
    pub fn colliders(&self) -> Option<&[ColliderHandle]> {
        self.colliders.as_deref()
    }
    /// Whether the event names one of the filter's bodies or colliders (`None`: the
    /// filter has neither restriction). O(log n).
    pub(crate) fn names_handle(&self, ev: &Event) -> Option<bool> {
        if self.bodies.is_none() && self.colliders.is_none() {
            return None;
        }
        let body = |h| holds(self.bodies.as_deref(), h, RigidBodyHandle::into_raw_parts);
        let collider = |c| holds(self.colliders.as_deref(), c, ColliderHandle::into_raw_parts);
        Some(body(ev.body1) || body(ev.body2) || collider(ev.collider1) || collider(ev.collider2))
    }
    /// Adds a kind.
    pub fn or_kind(mut self, kind: EventKind) -> Self {
        self.kinds = self.kinds.union(KindSet::of(&[kind]));
        self
    }
    /// Restricts to events involving one of `nodes` (or a member of one of them).
    /// O(n log n).
    pub fn with_nodes(mut self, nodes: &[NodeId]) -> Self {
        let mut v = nodes.to_vec();
        v.sort();
        v.dedup();
        self.nodes = Some(v);
        self
    }
    /// The kinds.
    pub fn kinds_set(&self) -> KindSet {
        self.kinds
    }
    /// The node restriction, if any (sorted).
    pub fn nodes(&self) -> Option<&[NodeId]> {
        self.nodes.as_deref()
    }
}

/// Handles sorted by index and generation, without repeats: a filter's restriction.
fn sorted_handles<H: Copy>(handles: &[H], raw: fn(H) -> (u32, u32)) -> Vec<H> {
    let mut v = handles.to_vec();
    v.sort_unstable_by_key(|&h| raw(h));
    v.dedup_by_key(|h| raw(*h));
    v
}

/// Whether a restriction sorted by [`sorted_handles`] holds the handle `h` names.
/// O(log n).
fn holds<H: Copy>(set: Option<&[H]>, h: Option<H>, raw: fn(H) -> (u32, u32)) -> bool {
    h.zip(set)
        .is_some_and(|(h, set)| set.binary_search_by_key(&raw(h), |&x| raw(x)).is_ok())
}

/// The kinds of plausibility violation (paper §8, Figs. 15 and 17; defined in `docs/ARCHITECTURE.md` §6), in report order.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ViolationKind {
    /// A held (sleeping or fixated) body without support for longer than the hang time.
    HangingSleeper,
    /// A contact group gained more kinetic energy than gravity could give it.
    Launch,
    /// A contact deeper than the allowed fraction of the smaller body's size.
    DeepPenetration,
    /// A body whose pose or velocity is not finite.
    Escape,
    /// A held (fixated) body that an awake body pushes harder across gravity than
    /// resting explains: a contact that should have moved it.
    Unresponsive,
}

impl ViolationKind {
    /// Every kind, in report order.
    pub const ALL: [ViolationKind; 5] = [
        ViolationKind::HangingSleeper,
        ViolationKind::Launch,
        ViolationKind::DeepPenetration,
        ViolationKind::Escape,
        ViolationKind::Unresponsive,
    ];

    /// A short stable name (`"hanging_sleeper"`, `"launch"`, `"deep_penetration"`,
    /// `"escape"`, `"unresponsive"`), for tables and CSV headers.
    pub const fn name(self) -> &'static str {
        match self {
            ViolationKind::HangingSleeper => "hanging_sleeper",
            ViolationKind::Launch => "launch",
            ViolationKind::DeepPenetration => "deep_penetration",
            ViolationKind::Escape => "escape",
            ViolationKind::Unresponsive => "unresponsive",
        }
    }
}

#[cfg(test)]
mod tests;
