//! The contact graph as a debug-render overlay: [`GraphOverlay`] draws the graph, its
//! contact groups and the state of every body into any Rapier
//! [`DebugRenderBackend`](rapier3d::pipeline::DebugRenderBackend) (bevy_rapier's debug
//! render, Rapier's testbed, a recorder of one's own), on top of what Rapier's own
//! [`DebugRenderPipeline`](rapier3d::pipeline::DebugRenderPipeline) draws: call its
//! `render`, then [`GraphOverlay::render`], on the same backend. Needs the feature
//! `debug-render` (on by default; it turns on Rapier's own and adds no dependency).
//!
//! # What it draws
//! Lines only (`draw_line` is the one primitive every backend provides), in this order
//! (later ones on top), each in the graph's slot order:
//! 1. **Proximity edges** (off by default): physical edges in Rapier's narrow phase
//!    whose bodies do not touch; one faint line.
//! 2. **Structural edges**: a line from a container's hub (the mean of its members'
//!    positions) to each member, so a container is drawn as a star.
//! 3. **Trigger edges**: a dashed line from the sensor's centre to the body inside.
//! 4. **Touching edges**: one solid line per edge, however many contact points it
//!    stands for, in its contact group's colour ([`OverlayStyle::group_color`] of
//!    [`group_key`], which a group keeps through merges and rebuilds).
//! 5. **State markers**: an octahedron (or a cross) at every body's centre of mass and
//!    every collider without a body, coloured by its [`BodyState`] (the paper's Fig. 17).
//!
//! Edges run between the bodies' centres of mass (a picture of the graph; Rapier draws
//! the contact points itself), except that an end on *scenery* (an insulator not held: a
//! ground, a wall, a platform) sits at its surface point nearest the other body
//! ([`OverlayStyle::anchor_on_scenery`]). Logical edges, rules and timers have no place.
//!
//! Each line carries the `DebugRenderObject` of what it is about (a marker its body or
//! collider; an edge a body, a simulated one first and end *A* on ties, else a collider)
//! and is drawn only if the backend's `filter_object` accepts the objects of all its
//! ends. A backend that filters out every `RigidBody` therefore hides the overlay too:
//! hide Rapier's body axes with `DebugRenderMode` instead. Deterministic (the same layer
//! and sets give the same lines in the same order) and forgiving: stale handles,
//! non-finite poses and unbounded shapes never panic, and what is left out is counted in
//! [`OverlayStats`]. `docs/ARCHITECTURE.md` §5 gives the alternatives rejected.
//!
//! # Cost
//! [`GraphOverlay::render`]: O(node slots + edge slots), O(log held bodies) per body for
//! the speed-ups' state, one point projection per collider of each drawn edge's scenery
//! end (O(1) for primitives, logarithmic for meshes); no allocation once its buffers
//! have grown to the graph's size.

mod draw;
mod overlay;
mod place;
mod state;
mod style;

pub use overlay::{GraphOverlay, OverlayStats};
pub use state::BodyState;
pub use style::{group_key, MarkerShape, OverlayStyle, StateColors, DEFAULT_REST_SPEED};
