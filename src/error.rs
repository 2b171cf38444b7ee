//! Errors returned by the `try_` queries and by validation.
//!
//! The library never panics on a user mistake: a stale id, a removed body or a body
//! the layer has not seen yet give an [`Error`]; the panicking conveniences say so in
//! their docs and each has a `try_` twin.

use std::fmt;

use rapier3d::prelude::{ColliderHandle, RigidBodyHandle};

use crate::{EdgeId, NodeId};

/// What went wrong.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// The node id names a slot that was freed (the node was removed) or reused since.
    StaleNode(NodeId),
    /// The edge id names a slot that was freed or reused since.
    StaleEdge(EdgeId),
    /// The world has no such body (it was removed, or never inserted), or, where no
    /// world is passed (the graph's `try_node_of_body`), the last analysed step had
    /// none.
    UnknownBody(RigidBodyHandle),
    /// The world has no such collider (removed, or never inserted), or, where no
    /// world is passed, the collider has no node (only sensors and parentless
    /// colliders have their own node).
    UnknownCollider(ColliderHandle),
    /// The body is in the world but the layer has not seen it yet: it was inserted
    /// since the last step, and has a node from the next one. Queries that can answer
    /// for it answer empty instead; this is the error of calls that need its node.
    UnseenBody(RigidBodyHandle),
    /// The collider is in the world but the layer has not seen it yet: a sensor or
    /// parentless collider inserted since the last step, or a collider of a body
    /// inserted since; it has a node (or its body has) from the next step.
    UnseenCollider(ColliderHandle),
    /// The collider exists but is not a sensor (a sensor query was asked of it).
    NotASensor(ColliderHandle),
    /// The body set, collider set or world passed to a query is not the one the layer
    /// last analysed (another world, or a copy of it): a handle valid in both would be
    /// answered with the other world's contacts. Pass the world the layer steps, or
    /// step the layer on this one first (a layer stepped on another world reads it in
    /// full and follows it from then on; keep one layer per world).
    ///
    /// How it is told, in O(1), by addresses that a move of the world value does not
    /// change (so `let w2 = w;` still answers):
    /// - where the set stores its first element, with its count (both noted at each
    ///   analysis): the analysed world has them unless it was edited since;
    /// - where the first few bodies of the set that the layer has read keep their
    ///   collider lists (for a collider set: their first colliders' shapes): Rapier
    ///   allocates these apart from its storage, so they stay put when the storage
    ///   grows, and another world, or a copy, has its own.
    ///
    /// A set is another world's when both say so: its storage is elsewhere, or its
    /// count differs, and none of those bodies (colliders) has its list (shape) where
    /// the layer read it while one at the length read has it elsewhere. When the set
    /// holds none that the layer has read, nothing tells and the set answers as the
    /// analysed world's. So:
    /// - the same world moved, or edited since the last step (bodies and colliders
    ///   inserted or removed, its storage grown), answers: a body inserted since
    ///   answers empty, a removed one `UnknownBody`;
    /// - another world, or a copy of its body set, is found when one of its first eight
    ///   bodies with colliders has the handle of a body the layer read (so a world
    ///   built as the analysed one was is found; one sharing none of its handles
    ///   answers, for bodies the layer has not seen, as a world edited since);
    /// - a collider set alone (`sensor_contents`) is told by its shapes: a copy made
    ///   with `clone`, or another world whose colliders were built from the same
    ///   `SharedShape`, is not told from the analysed world's (with its body set, as in
    ///   the queries taking a world, the bodies tell);
    /// - the same world may be taken for another until the next step when, since the
    ///   last step, both its storage moved (grown past its capacity, or its first
    ///   element removed) and every body the layer read among the first eight with
    ///   colliders has its collider list elsewhere (colliders attached past its
    ///   capacity, then as many removed), or, for a collider set, every such collider
    ///   had its shape replaced;
    /// - before the first step, and after a restore until the next step, nothing is
    ///   compared (nothing analysed, or addresses of another process).
    ForeignWorld,
    /// The node exists but is not of a kind the call accepts.
    WrongKind {
        /// The node.
        node: NodeId,
        /// What the call expected, in words.
        expected: &'static str,
    },
    /// A value that must be finite was not.
    NonFinite(&'static str),
    /// A parameter is out of its range.
    InvalidParameter {
        /// The parameter's name.
        name: &'static str,
        /// Why it is refused.
        reason: String,
    },
    /// An invariant of the graph does not hold (reported by `validate()`, and by
    /// `ContactLayer::restore` for a snapshot whose state is inconsistent).
    Invariant(String),
    /// A layer snapshot was written in another snapshot format than this build reads
    /// (returned, as its message, by the deserialiser).
    SnapshotFormat {
        /// The format of the snapshot.
        found: u32,
        /// The format this build reads.
        expected: u32,
    },
    /// A layer snapshot does not belong to the world it is restored against.
    SnapshotMismatch(String),
    /// A layer snapshot holds a predicate rule (`Rule::ignore_if`): closures are not
    /// part of a snapshot, so restoring it needs the predicate given back
    /// (`ContactLayer::restore_with`).
    UnboundPredicate(NodeId),
    /// The call is refused because Rapier 0.36 cannot carry it out: it would panic in
    /// Rapier's next step (see the "Rapier's own panics" part of `docs/audit.md`).
    /// Nothing was changed.
    Unsupported {
        /// The call or change refused, in words.
        what: &'static str,
        /// Why Rapier cannot carry it out.
        reason: &'static str,
    },
    /// The query reads the per-edge contact details, which the layer keeps only under
    /// proximity tracking with the details on (touching tracking, the default, copies
    /// none): ask the by-handle query that reads them from Rapier
    /// (`ContactLayer::supports_of_body`, `ContactLayer::contact_details`), or set
    /// `Tracking::Proximity`.
    DetailsNotKept,
}

impl fmt::Display for Error {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Error::StaleNode(n) => write!(f, "node {n:?} was removed (stale id)"),
            Error::StaleEdge(e) => write!(f, "edge {e:?} was removed (stale id)"),
            Error::UnknownBody(h) => write!(
                f,
                "rigid body {h:?} is not in the world (removed, or never inserted); asked \
                 without the world, it had no node at the layer's last step"
            ),
            Error::UnknownCollider(h) => write!(
                f,
                "collider {h:?} is not in the world (removed, or never inserted); asked \
                 without the world, it had no node of its own at the layer's last step"
            ),
            Error::UnseenBody(h) => write!(
                f,
                "rigid body {h:?} was inserted since the layer's last step: it has a node from the next step"
            ),
            Error::UnseenCollider(h) => write!(
                f,
                "collider {h:?} was inserted since the layer's last step: it has a node from the next step"
            ),
            Error::NotASensor(h) => write!(f, "collider {h:?} is not a sensor"),
            Error::ForeignWorld => f.write_str(
                "the set or world passed is not the one the layer last analysed (another \
                 world, or a copy): pass the world the layer steps, or step the layer on \
                 this world first (one layer per world)",
            ),
            Error::WrongKind { node, expected } => {
                write!(f, "node {node:?} is not {expected}")
            }
            Error::NonFinite(what) => write!(f, "{what} is not finite"),
            Error::InvalidParameter { name, reason } => {
                write!(f, "invalid parameter `{name}`: {reason}")
            }
            Error::Invariant(msg) => write!(f, "graph invariant violated: {msg}"),
            Error::SnapshotFormat { found, expected } => write!(
                f,
                "layer snapshot format {found}, this build of rapier-contact-graph reads format {expected}"
            ),
            Error::SnapshotMismatch(msg) => {
                write!(f, "layer snapshot does not match the world: {msg}")
            }
            Error::UnboundPredicate(rule) => write!(
                f,
                "rule {rule:?} is a predicate, which a snapshot cannot hold: restore with \
                 `restore_with` and give its predicate back"
            ),
            Error::Unsupported { what, reason } => write!(f, "{what} is not supported: {reason}"),
            Error::DetailsNotKept => write!(
                f,
                "the layer keeps no per-edge contact details (touching tracking or details \
                 off): use `supports_of_body` / `contact_details`, which read Rapier, or \
                 `set_tracking(Tracking::Proximity)`"
            ),
        }
    }
}

impl std::error::Error for Error {}

/// Shorthand for results of this crate.
pub type Result<T, E = Error> = std::result::Result<T, E>;
