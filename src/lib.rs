//! # rapier-contact-graph
//!
//! Kenny Erleben's *Contact Graphs in Multibody Dynamics Simulation* (DIKU TR-04/06)
//! as a drop-in layer for stock [`rapier3d`] 0.36: a persistent, typed contact graph
//! of the whole scene, the Spatial-Temporal Coherence (STC) marks, and contact groups,
//! kept in step with a Rapier world by one call per step.
//!
//! ```
//! use rapier3d::prelude::*;
//! use rapier_contact_graph::ContactLayer;
//!
//! let mut world = PhysicsWorld::new();
//! world.insert(RigidBodyBuilder::fixed(), ColliderBuilder::cuboid(5.0, 0.5, 5.0));
//! world.insert(
//!     RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 1.0, 0.0)),
//!     ColliderBuilder::ball(0.5),
//! );
//! let mut layer = ContactLayer::new();
//! let stats = layer.step(&mut world); // Rapier's step + the analysis
//! assert_eq!(stats.nodes, 2);
//! ```
//!
//! # Architecture (the paper's phases as modules)
//! - [`graph`]: nodes (Table 1), edges (Table 2), ids, the per-edge cache;
//! - [`coherence`]: the STC analysis after each Rapier step (§3): node upkeep,
//!   edge insertion, proximity and touching marks, obsolete removal; or, with
//!   [`coherence::Tracking::Touching`], touch transitions from Rapier's own collision
//!   events ([`coherence::TouchFeed`], the layer's `EventHandler`);
//! - [`groups`]: contact groups by the traversal of Figs. 7–8;
//! - [`logic`]: rules, timers, passive bodies, containers (Table 1, §3.2), and the
//!   one `PhysicsHooks` object Rapier calls ([`logic::hooks`]);
//! - [`events`]: event kinds, filters and crossbeam subscriptions (§4, Table 3);
//! - [`speedups`]: the §7 switches and how each is realised in Rapier;
//! - [`monitor`]: plausibility violations and their repair (§8, Figs. 15 and 17);
//! - [`export`]: text, and Graphviz pictures of the graph (Figs. 2 and 9);
//! - `debug_render` (feature `debug-render`, on by default): the graph drawn into any
//!   Rapier `DebugRenderBackend` ([`GraphOverlay`]);
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
pub use layer::{ContactLayer, StepStats, Touching};
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
