//! Bad-input audit (see `tests/common/audit.rs`): events — `subscribe`,
//! `subscribe_with_id`, `subscribe_bounded`, `unsubscribe`, dropped receivers, and the
//! `Filter` / `KindSet` builders.

mod common;

use rapier_contact_graph::events::{EventKind, Filter, KindSet};
use rapier_contact_graph::{ContactLayer, Error, NodeId};

use common::audit::*;
use common::build::*;

#[test]
fn subscribe_with_stale_or_foreign_nodes_matches_nothing() {
    let (mut world, ground, ball, mut layer) = stepped(0);
    let (stale, _) = stale_node(&mut layer, &mut world);
    let [next_gen, far, _] = foreign_nodes(layer.graph().try_node_of_body(ball).unwrap());
    // Accepted (subscribe cannot fail); such a filter never matches, as the node can
    // never come back (ids are generational).
    let rx = layer.subscribe(Filter::all().with_nodes(&[stale, next_gen, far]));
    let (_, rx2) = layer.subscribe_with_id(Filter::kinds(KindSet::NONE));
    let rx3 = layer.subscribe(Filter::all().with_nodes(&[]));
    let all = layer.subscribe(Filter::all());
    ball_at(&mut world, [0.0, 3.0, 0.0], 0.5);
    for _ in 0..100 {
        layer.step(&mut world);
    }
    assert!(all.try_iter().count() > 0, "events happened");
    assert_eq!(rx.try_iter().count(), 0);
    assert_eq!(rx2.try_iter().count(), 0);
    assert_eq!(rx3.try_iter().count(), 0);
    let _ = ground;
}

#[test]
fn subscribe_bounded_zero_capacity_is_an_error() {
    let mut layer = ContactLayer::new();
    assert!(matches!(
        layer.subscribe_bounded(Filter::all(), 0),
        Err(Error::InvalidParameter {
            name: "capacity",
            ..
        })
    ));
    assert_eq!(layer.analysis().event_bus().len(), 0, "nothing subscribed");
    let rx = layer.subscribe_bounded(Filter::all(), 1).unwrap();
    let (mut world, _, _) = ball_on_ground();
    for _ in 0..50 {
        layer.step(&mut world);
    }
    assert_eq!(rx.try_iter().count(), 1, "the newest are dropped");
    assert!(layer.analysis().event_bus().dropped() > 0);
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_subscribe_bounded_huge_capacity_panics() {
    let mut layer = ContactLayer::new();
    let r = no_panic("subscribe_bounded(usize::MAX)", || {
        layer
            .subscribe_bounded(Filter::all(), usize::MAX)
            .map(|_| ())
    });
    assert!(matches!(r, Err(Error::InvalidParameter { .. })), "{r:?}");
}

#[test]
// Fixed: the bug this test was written for (see the audit table).
fn bug_subscribe_bounded_accepts_stale_node_filter() {
    let (mut world, _, _, mut layer) = stepped(0);
    let (stale, _) = stale_node(&mut layer, &mut world);
    assert_eq!(
        layer
            .subscribe_bounded(Filter::all().with_nodes(&[stale]), 8)
            .map(|_| ()),
        Err(Error::StaleNode(stale))
    );
}

#[test]
fn unsubscribe_and_dropped_receivers() {
    let (mut world, _, _) = ball_on_ground();
    let mut layer = ContactLayer::new();
    let (id, rx) = layer.subscribe_with_id(Filter::all());
    let (id2, _keep) = layer.subscribe_with_id(Filter::all());
    // Dropped receiver: pruned at the next delivery, never an error or a block.
    drop(rx);
    no_panic("dispatch to a dropped receiver", || {
        for _ in 0..5 {
            layer.step(&mut world);
        }
    });
    assert_eq!(layer.analysis().event_bus().pruned(), 1);
    assert_eq!(layer.analysis().event_bus().dropped_for(id), None, "gone");
    assert!(!layer.unsubscribe(id), "already pruned");
    assert!(layer.unsubscribe(id2));
    assert!(!layer.unsubscribe(id2), "twice");
    assert_eq!(layer.analysis().event_bus().dropped_for(id2), None);
    // A foreign id (another layer's) names this layer's subscription with the same
    // number: ids carry no layer identity (aliasing, undetectable).
    let mut other = ContactLayer::new();
    let (foreign, _) = other.subscribe_with_id(Filter::all());
    let (_, _rx3) = layer.subscribe_with_id(Filter::all());
    let _ = layer.unsubscribe(foreign);
}

#[test]
fn filter_builders_accept_anything() {
    let stale = NodeId::from_raw_parts(9, 9);
    let f = Filter::all().with_nodes(&[stale, stale, NodeId::from_raw_parts(0, 0)]);
    assert_eq!(f.nodes().unwrap().len(), 2, "sorted, deduplicated");
    assert_eq!(Filter::all().with_nodes(&[]).nodes(), Some(&[][..]));
    assert!(KindSet::of(&[]).is_empty());
    let k = Filter::kinds(KindSet::NONE)
        .or_kind(EventKind::WokeUp)
        .or_kind(EventKind::WokeUp);
    assert_eq!(k.kinds_set(), KindSet::of(&[EventKind::WokeUp]));
}
