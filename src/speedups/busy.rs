//! Busy groups: a sleepy body is not held while a contact group it belongs to or
//! touches has a body still moving fast, as a Rapier island does not sleep while one
//! of its bodies moves (paper §7, fixation). With `insulate_sleepy` the sleepy bodies
//! split the groups, so the bodies deep in a pile are held while its top still moves
//! (`docs/ARCHITECTURE.md`, "Releasing held bodies", *Busy groups*).

use rapier3d::prelude::{RigidBody, RigidBodyHandle};

use super::SpeedUpState;
use crate::graph::{ContactGraph, EdgeKind, Node, NodeId};
use crate::{GroupId, WorldView};

impl SpeedUpState {
    /// Whether a body counts as moving for the reach and the busy groups: an awake,
    /// not sleepy, simulated body faster than `release_speed`. O(log sleepy).
    pub(super) fn moves_fast(&self, node: &Node, h: RigidBodyHandle, rb: &RigidBody) -> bool {
        node.kind().is_simulated()
            && node.is_awake()
            && !self.is_sleepy(h)
            && rb.linvel().length() > self.config.release_speed
    }

    /// The groups of the refreshed bodies that move fast ([`Self::moves_fast`]), sorted.
    /// O(refreshed bodies · log).
    pub(super) fn busy_groups(
        &self,
        graph: &ContactGraph,
        view: &WorldView,
        refreshed: &[NodeId],
    ) -> Vec<GroupId> {
        let mut busy: Vec<GroupId> = refreshed
            .iter()
            .filter_map(|&n| {
                let node = graph.node(n)?;
                let h = node.body()?;
                let rb = view.bodies.get(h)?;
                self.moves_fast(node, h, rb).then(|| node.group())?
            })
            .collect();
        busy.sort_unstable();
        busy.dedup();
        busy
    }
}

/// Whether node `n` belongs to a busy group or touches a member of one (`busy`
/// sorted). O(its edges · log busy).
pub(super) fn beside_busy(graph: &ContactGraph, n: NodeId, busy: &[GroupId]) -> bool {
    if busy.is_empty() {
        return false;
    }
    let is_busy = |m: NodeId| {
        graph
            .node(m)
            .and_then(Node::group)
            .is_some_and(|g| busy.binary_search(&g).is_ok())
    };
    is_busy(n)
        || graph
            .neighbors(n)
            .any(|(m, _, e)| e.kind() == EdgeKind::Physical && e.is_touching() && is_busy(m))
}
