//! Subscriptions and dispatch.
//!
//! Chosen: one crossbeam channel per subscription, filtered on the sending side, so a
//! subscriber only wakes for what it asked for and a slow subscriber cannot hold up
//! another. Sending never blocks (`try_send`): the simulation is never at the mercy of
//! a consumer.
//!
//! Rejected: a single broadcast channel with receiver-side filtering (every receiver
//! pays for every event), and callbacks (they would run inside the step, where the
//! graph is being changed — exactly what the paper's safe point avoids).

use crossbeam_channel::{bounded, unbounded, Receiver, Sender, TrySendError};

use super::{Event, Filter, KindSet};
use crate::graph::{ContactGraph, EdgeKind, NodeId};

/// A subscription's id (for [`EventBus::unsubscribe`] and per-subscription counts).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SubscriptionId(u64);

#[derive(Debug)]
struct Subscription {
    id: SubscriptionId,
    filter: Filter,
    tx: Sender<Event>,
    dropped: u64,
}

/// The set of subscriptions of a layer.
#[derive(Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EventBus {
    /// Channels cannot be serialised: a deserialised bus has no subscriptions.
    #[cfg_attr(feature = "serde", serde(skip))]
    subs: Vec<Subscription>,
    next_id: u64,
    dropped: u64,
    pruned: u64,
    sent: u64,
}

impl Clone for EventBus {
    /// A clone has no subscriptions: receivers belong to the original.
    fn clone(&self) -> Self {
        Self::default()
    }
}

impl EventBus {
    /// The bus's counters without its subscriptions (for a snapshot: channels cannot
    /// be serialised). O(1).
    #[cfg(feature = "serde")]
    pub(crate) fn without_subscriptions(&self) -> Self {
        Self {
            subs: Vec::new(),
            next_id: self.next_id,
            dropped: self.dropped,
            pruned: self.pruned,
            sent: self.sent,
        }
    }

    fn add(&mut self, filter: Filter, tx: Sender<Event>) -> SubscriptionId {
        let id = SubscriptionId(self.next_id);
        self.next_id = self.next_id.saturating_add(1);
        self.subs.push(Subscription {
            id,
            filter,
            tx,
            dropped: 0,
        });
        id
    }

    /// Subscribes with an unbounded channel. O(1).
    pub fn subscribe(&mut self, filter: Filter) -> (SubscriptionId, Receiver<Event>) {
        let (tx, rx) = unbounded();
        (self.add(filter, tx), rx)
    }

    /// Subscribes with a channel holding at most `capacity` events; when it is full the
    /// newest events are dropped and counted. `capacity` 0 is refused (a rendezvous
    /// channel would drop everything). O(1).
    pub fn subscribe_bounded(
        &mut self,
        filter: Filter,
        capacity: usize,
    ) -> crate::Result<(SubscriptionId, Receiver<Event>)> {
        if capacity == 0 || capacity > super::MAX_CAPACITY {
            return Err(crate::Error::InvalidParameter {
                name: "capacity",
                reason: format!("must be in 1..={}, got {capacity}", super::MAX_CAPACITY),
            });
        }
        let (tx, rx) = bounded(capacity);
        Ok((self.add(filter, tx), rx))
    }

    /// Removes a subscription; `false` if it was not there. O(subscriptions).
    pub fn unsubscribe(&mut self, id: SubscriptionId) -> bool {
        let before = self.subs.len();
        self.subs.retain(|s| s.id != id);
        self.subs.len() != before
    }

    /// The number of live subscriptions.
    pub fn len(&self) -> usize {
        self.subs.len()
    }

    /// Whether nobody listens.
    pub fn is_empty(&self) -> bool {
        self.subs.is_empty()
    }

    /// The kinds some subscription wants (generation skips the others).
    pub fn wanted(&self) -> KindSet {
        self.subs
            .iter()
            .fold(KindSet::NONE, |acc, s| acc.union(s.filter.kinds_set()))
    }

    /// Events dropped so far because a bounded channel was full, over all
    /// subscriptions.
    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    /// Events dropped so far for one subscription (`None` if it is gone).
    pub fn dropped_for(&self, id: SubscriptionId) -> Option<u64> {
        self.subs.iter().find(|s| s.id == id).map(|s| s.dropped)
    }

    /// Subscriptions removed because their receiver was dropped.
    pub fn pruned(&self) -> u64 {
        self.pruned
    }

    /// Events delivered so far.
    pub fn sent(&self) -> u64 {
        self.sent
    }

    /// Sends `events` to every matching subscription, never blocking. A subscription
    /// whose receiver is gone is removed the first time an event for it fails to send
    /// (crossbeam offers no other way to see a dropped receiver). O(subscriptions ×
    /// events), plus O(degree) per event for node filters (container membership).
    pub(crate) fn dispatch(&mut self, events: &[Event], graph: &ContactGraph) {
        let mut gone = Vec::new();
        for sub in &mut self.subs {
            for ev in events {
                if !matches(&sub.filter, ev, graph) {
                    continue;
                }
                match sub.tx.try_send(*ev) {
                    Ok(()) => self.sent = self.sent.saturating_add(1),
                    Err(TrySendError::Full(_)) => {
                        sub.dropped = sub.dropped.saturating_add(1);
                        self.dropped = self.dropped.saturating_add(1);
                    }
                    Err(TrySendError::Disconnected(_)) => {
                        gone.push(sub.id);
                        break;
                    }
                }
            }
        }
        if !gone.is_empty() {
            self.subs.retain(|s| !gone.contains(&s.id));
            self.pruned += gone.len() as u64;
        }
    }
}

fn member_of_any(n: NodeId, set: &[NodeId], graph: &ContactGraph) -> bool {
    if set.binary_search(&n).is_ok() {
        return true;
    }
    graph
        .neighbors(n)
        .any(|(m, _, e)| e.kind() == EdgeKind::Structural && set.binary_search(&m).is_ok())
}

fn matches(filter: &Filter, ev: &Event, graph: &ContactGraph) -> bool {
    if !filter.kinds_set().contains(ev.kind) {
        return false;
    }
    let by_handle = filter.names_handle(ev);
    if by_handle == Some(true) {
        return true;
    }
    match filter.nodes() {
        None => by_handle.is_none(),
        Some(set) => {
            member_of_any(ev.node1, set, graph)
                || ev.node2.is_some_and(|b| member_of_any(b, set, graph))
        }
    }
}
