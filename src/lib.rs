//! # rapier-contact-graph
//!
//! A persistent contact graph of a whole [`rapier3d`] 0.36 scene, kept in step by one
//! call per step: who touches what, what is inside each sensor, which bodies form a
//! contact group, and events when any of it changes, by Rapier handle. It implements
//! Kenny Erleben's report *Contact Graphs in Multibody Dynamics Simulation* (DIKU
//! TR-04/06), with the report's speed-ups and a plausibility monitor on top. Stock
//! Rapier, no fork: observing changes no bit of Rapier's results.
//!
//! # Add it in three lines
//! ```
//! use rapier3d::prelude::*;
//! use rapier_contact_graph::ContactLayer;
//!
//! let mut world = PhysicsWorld::new();
//! world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
//! let (ball, _) = world.insert(
//!     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.2, 0.0)),
//!     ColliderBuilder::ball(0.5),
//! );
//!
//! let mut layer = ContactLayer::new(); // 1. make it
//! for _ in 0..60 {
//!     layer.step(&mut world); // 2. step through it (Rapier's step + the analysis)
//! }
//! let touching = layer.touching_body(&world.bodies, ball)?; // 3. ask it
//! assert_eq!(touching.len(), 1, "the ball rests on the ground");
//! # Ok::<(), rapier_contact_graph::Error>(())
//! ```
//! Stepping Rapier yourself: call [`ContactLayer::pre_step`], pass
//! [`ContactLayer::hooks`] (or [`ContactLayer::hooks_with`] your own) and
//! [`ContactLayer::event_handler`] (or [`ContactLayer::event_handler_with`] your own)
//! to Rapier's step, then [`ContactLayer::analyze`].
//!
//! # Who touches what
//! By Rapier handle, as of the last step; a body inserted since answers empty, a
//! removed one is an error:
//! [`touching_body`](ContactLayer::touching_body) (bodies and static colliders),
//! [`supports_of_body`](ContactLayer::supports_of_body) (what holds it up),
//! [`contact_details`](ContactLayer::contact_details) (distance, normal, impulses,
//! read from Rapier on demand). The graph itself ([`ContactLayer::graph`]) holds a
//! node per body, static collider, sensor and container, and an edge per touching
//! pair (and, under proximity tracking, per pair Rapier's broad phase keeps).
//!
//! # Sensors
//! [`sensor_contents`](ContactLayer::sensor_contents) (what is inside a sensor
//! collider), [`sensors_containing`](ContactLayer::sensors_containing) (which sensors
//! a body is in), and `SensorStarted` / `SensorStopped` events naming the sensor's
//! collider. Sensors see what Rapier's own sensor collision types give;
//! [`LayerLogicMut::set_trigger_widening`](crate::LayerLogicMut::set_trigger_widening) opts in to the paper's triggers, which see
//! bodies of every type (a sensor on a fixed body sees fixed bodies too), and says
//! what that changes.
//!
//! # Contact groups and sleeping piles
//! Bodies that touch, directly or through others, form a contact group; fixed and
//! kinematic bodies do not join groups (the report's Figs. 7–8):
//! [`group_of_body`](ContactLayer::group_of_body), [`ContactLayer::groups`]. With the
//! speed-ups ([`SpeedUpsMut::set`](crate::SpeedUpsMut::set), [`speedups::SpeedUps`]) a group at rest
//! is put to sleep or held still as a whole, which settles piles that Rapier leaves
//! awake; the monitor ([`MonitorMut::set`](crate::MonitorMut::set)) finds and repairs what that
//! breaks (a body left hanging, a launch, deep penetration).
//!
//! # Events
//! ```
//! use rapier3d::prelude::*;
//! use rapier_contact_graph::{ContactLayer, EventKind, Filter, KindSet};
//!
//! let mut world = PhysicsWorld::new();
//! world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
//! let (ball, _) = world.insert(
//!     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.2, 0.0)),
//!     ColliderBuilder::ball(0.5),
//! );
//! let mut layer = ContactLayer::new();
//! // The ball's contacts and sensors starting and stopping (Rapier's collision
//! // events), and any body falling asleep (crossbeam receivers).
//! let touches =
//!     layer.subscribe(Filter::kinds(KindSet::COLLISION_EVENTS).with_bodies(&[ball]));
//! let _sleep = layer.subscribe(Filter::kinds(KindSet::SLEEP));
//! for _ in 0..60 {
//!     layer.step(&mut world);
//! }
//! let first = touches.try_iter().next().unwrap();
//! assert_eq!(first.kind, EventKind::ContactStarted);
//! assert!(first.body1 == Some(ball) || first.body2 == Some(ball));
//! ```
//! Kinds come in Started / Persisted / Stopped spans (the listener contract of
//! [`events`]); every event carries the Rapier handles of what it names. Subscribe
//! to `Started`/`Stopped` only where you can: `ContactPersisted` and the proximity kinds need
//! every pair read each step (proximity tracking), the others follow Rapier's own
//! collision events under touching tracking ([`coherence::Tracking::Touching`], the
//! default, a fraction of the cost): [`KindSet::COLLISION_EVENTS`] is that set.
//!
//! # Coming from Rapier
//! | Rapier | this crate |
//! |---|---|
//! | `narrow_phase.contact_pairs_with(c)` + `has_any_active_contact()` | [`ContactLayer::touching_body`] |
//! | a contact's normal and impulses | [`ContactLayer::contact_details`], [`ContactLayer::supports_of_body`] |
//! | `narrow_phase.intersection_pairs_with(sensor)` | [`ContactLayer::sensor_contents`], [`ContactLayer::sensors_containing`] |
//! | `CollisionEvent::Started` / `Stopped` | [`EventKind::ContactStarted`] / [`EventKind::ContactStopped`], [`EventKind::SensorStarted`] / [`EventKind::SensorStopped`]; all four: [`KindSet::COLLISION_EVENTS`] |
//! | `collider1` / `collider2` | [`Event::collider1`] / [`Event::collider2`], and [`Event::body1`] / [`Event::body2`] |
//! | `ActiveEvents` on a collider | a [`Filter`] with [`Filter::with_bodies`] / [`Filter::with_colliders`] |
//! | islands (`IslandManager`) | contact groups ([`ContactLayer::group_of_body`]): fixed and kinematic bodies insulate |
//! | dynamic / kinematic / fixed body, sensor collider | node kinds [`NodeKind::Dynamic`] / [`NodeKind::Kinematic`] / [`NodeKind::Fixed`], [`NodeKind::Sensor`] |
//! | `RigidBody::set_enabled(false)` (a disabled body) | [`LayerLogicMut::set_body_disabled`](crate::LayerLogicMut::set_body_disabled) (guarded against Rapier's panics), [`Node::is_body_disabled`] |
//! | `PhysicsHooks`, `EventHandler` | yours run beside the layer's: [`ContactLayer::hooks_with`], [`ContactLayer::event_handler_with`] |
//!
//! # Rapier's features
//! Rapier's optional features are the user's choice; the crate builds and keeps its
//! promises with each (CI runs the determinism and bit-identity tests built with
//! `parallel` and `enhanced-determinism`, and type-checks `simd8` and
//! `unsync-callbacks` with `parallel`):
//! - `parallel`, this crate's feature of the same name: turns on `rapier3d/parallel`
//!   (Rapier's step on rayon's threads). The layer's hooks and event handler are
//!   `Send + Sync` and may be called from Rapier's workers; Rapier hands the collision
//!   events over in its own sorted order, so the graph, the groups and the event
//!   stream are the same as single-threaded, event for event, and observing still
//!   changes no bit of Rapier's results. The analysis runs on the calling thread, in
//!   O(awake bodies + changes) per step as without the feature.
//! - `enhanced-determinism` (turn it on for `rapier3d` in your own `Cargo.toml`;
//!   cargo's feature unification gives it to the crate's Rapier too): Rapier's
//!   cross-platform determinism. The layer adds no arithmetic of its own that
//!   depends on the platform (no transcendental function), so its graph and events
//!   follow Rapier's poses; its golden hashes for this build are pinned apart.
//! - `simd8` (also on `rapier3d`): wider SIMD in Rapier and parry; nothing changes for
//!   the layer. Parry refuses it beside `enhanced-determinism`.
//! - `unsync-callbacks` (also on `rapier3d`, with `parallel`): Rapier calls hooks and
//!   event handlers from one thread; the layer works the same either way.
//!
//! `enhanced-determinism` changes Rapier's trajectories (another libm) and `simd8` may
//! (another SIMD width); `parallel` does not. Within one build, observing leaves
//! Rapier's trajectories as they are.
//!
//! # The paper's terms
//! The crate names what Rapier has a name for as Rapier does; the paper's terms stay in
//! the docs where they explain the paper (and as the one-letter codes of text dumps).
//!
//! | the paper | this crate | Rapier |
//! |---|---|---|
//! | rigid body (R) | [`NodeKind::Dynamic`] | a dynamic `RigidBody` |
//! | fixed body (F) | [`NodeKind::Fixed`] | a fixed `RigidBody`, or a collider without a parent |
//! | scripted body (S) | [`NodeKind::Kinematic`] | a kinematic `RigidBody` |
//! | link body (L) | [`NodeKind::Link`] | a link of a multibody |
//! | composite (C), multibody (M) | [`NodeKind::Composite`], [`NodeKind::Multibody`] | bodies joined by fixed joints; a multibody or jointed articulation |
//! | logical rule (A), timer (T) | [`NodeKind::Rule`], [`NodeKind::Timer`] | — |
//! | trigger volume (V) | [`NodeKind::Sensor`] | a sensor collider |
//! | passive body (§3.2) | [`LayerLogicMut::set_body_disabled`](crate::LayerLogicMut::set_body_disabled), [`Node::is_body_disabled`] | a disabled body (`RigidBody::set_enabled(false)`) |
//! | touch begin / persist / end (Table 3) | [`EventKind::ContactStarted`] / [`EventKind::ContactPersisted`] / [`EventKind::ContactStopped`] | `CollisionEvent::Started` / `Stopped` of a contact pair |
//! | proximity begin / persist / end | [`EventKind::ProximityStarted`] / [`EventKind::ProximityPersisted`] / [`EventKind::ProximityStopped`] | a narrow-phase pair appearing / kept / removed |
//! | trigger enter / exit | [`EventKind::SensorStarted`] / [`EventKind::SensorStopped`] | `CollisionEvent::Started` / `Stopped` with a sensor |
//! | the pair's nodes *A*, *B* | [`Event::node1`] / [`Event::node2`] (handles: [`Event::body1`] / [`Event::body2`], [`Event::collider1`] / [`Event::collider2`]) | `collider1` / `collider2` |
//! | contact group (Figs. 7–8) | [`Group`], [`ContactLayer::group_of_body`] | Rapier's islands, roughly |
//!
//! # The report's sections, for readers of the paper
//! - [`graph`]: nodes (Table 1), edges (Table 2), ids, the per-edge cache;
//! - [`coherence`]: the Spatial-Temporal Coherence analysis after each Rapier step
//!   (§3): node upkeep, edge insertion, proximity and touching marks, the §3.1
//!   obsolete test (proximity tracking); or, with [`coherence::Tracking::Touching`]
//!   (the default), touch transitions from Rapier's own collision events
//!   ([`coherence::TouchFeed`]);
//! - [`groups`]: contact groups by the traversal of Figs. 7–8, kept incrementally;
//! - [`logic`]: rules, timers, passive (disabled) bodies, containers (Table 1, §3.2),
//!   and the one `PhysicsHooks` object Rapier calls ([`logic::hooks`]);
//! - [`events`]: event kinds, filters and crossbeam subscriptions (§4, Table 3);
//! - [`speedups`]: the §7 switches and how each is realised in Rapier;
//! - [`monitor`]: plausibility violations and their repair (§8, Figs. 15 and 17);
//! - [`export`]: text, and Graphviz pictures of the graph (Figs. 2 and 9);
//! - `debug_render` (feature `debug-render`, on by default): the graph drawn into any
//!   Rapier `DebugRenderBackend` (`GraphOverlay`);
//! - [`snapshot`] (feature `serde`, on by default): the layer's state saved and
//!   restored beside Rapier's own world snapshot, continuing bit for bit;
//! - [`ContactLayer`] ties them together.
//!
//! The scenes shared by examples, tests and benchmarks (`rcg-scenes`) and the
//! laboratory that measures speed against accuracy (`rcg-lab`: the DIKU run, the
//! stability suite, charts and frames) are workspace members beside this crate, not
//! part of it. `docs/ARCHITECTURE.md` maps the modules and their dependency direction.

#![warn(missing_docs)]

pub mod coherence;
#[cfg(feature = "debug-render")]
pub mod debug_render;
mod error;
pub mod events;
pub mod export;
pub mod graph;
pub mod groups;
mod layer;
pub mod logic;
pub mod monitor;
#[cfg(feature = "serde")]
pub mod snapshot;
pub mod speedups;
mod util;
mod validate;
mod world;

#[cfg(feature = "debug-render")]
pub use debug_render::{BodyState, GraphOverlay, OverlayStats, OverlayStyle};
pub use error::{Error, Result};
pub use events::{Event, EventKind, Filter, KindSet};
pub use graph::{
    Category, ContactCache, ContactGraph, Edge, EdgeId, EdgeKind, Node, NodeId, NodeKind,
    NodeSource, PairKey, Transition,
};
pub use groups::{Group, GroupId, GroupStats, Groups};
pub use layer::{
    ContactLayer, LayerAnalysis, LayerAnalysisMut, LayerLogic, LayerLogicMut, MonitorMut,
    RuleMember, SpeedUpsMut, StepStats, Touching,
};
pub use logic::hooks::{HooksView, HooksWith};
pub use logic::{Rule, WorldMut};
#[cfg(feature = "serde")]
pub use snapshot::{LayerSnapshot, SNAPSHOT_FORMAT};
pub use world::WorldView;

/// Re-export of the Rapier version this crate is built against.
pub use rapier3d;

/// The receiving end of a subscription ([`ContactLayer::subscribe`]), re-exported so
/// that naming it needs no `crossbeam-channel` dependency of your own.
pub use crossbeam_channel::{Receiver, RecvError, TryRecvError};

/// The code blocks of `docs/audit.md` (what the borrow checker refuses at the wrong
/// time, and the one order that compiles) run as doc tests.
#[cfg(doctest)]
#[doc = include_str!("../docs/audit.md")]
struct AuditDocTests;
