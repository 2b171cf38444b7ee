//! Frozen edges: the contacts of held bodies. The speed-ups hold a sleepy body by
//! making it a fixed body in Rapier (paper §7, fixation), and Rapier pairs no two
//! bodies that do not move: the held body's contacts with fixed geometry and with
//! other held bodies leave Rapier's narrow phase, as a sleeping body's would not. The
//! graph keeps them, touching and with the details they had, while the body is held,
//! as Rapier keeps a sleeping body's contacts: no contact ends because a pile was
//! held, and the queries answer as before. When the body is released, Rapier pairs
//! it again and the edge follows Rapier from that step on.

use super::{ContactGraph, Edge, EdgeKind, NodeId};

impl ContactGraph {
    /// Whether an edge is frozen: a touching physical edge of a held body whose other
    /// end stands still too (fixed, kinematic or held), so that Rapier computes no
    /// contact for it. A held body the user gave another type no longer stands still
    /// (its kind follows Rapier's): its edges follow Rapier again; a passive end (a
    /// body disabled in Rapier) has no edges at all. O(1).
    pub fn is_frozen(&self, e: &Edge) -> bool {
        let (Some(a), Some(b)) = (self.node(e.a), self.node(e.b)) else {
            return false;
        };
        e.kind == EdgeKind::Physical
            && e.cache.touching
            && (a.held || b.held)
            && a.kind.is_insulator()
            && b.kind.is_insulator()
            && !a.passive
            && !b.passive
    }

    /// Marks a body's node held (`true`) or given back (`false`) by the speed-ups.
    /// O(1).
    pub(crate) fn set_held(&mut self, n: NodeId, held: bool) {
        if let Some(node) = self.node_mut(n) {
            node.held = held;
            // Given back: its edges that were frozen must be allowed by Table 2 again
            // (a held body the user turned kinematic has none with the floor).
            if !held {
                self.kind_changed.push(n);
            }
        }
    }
}
