//! Check 4 of `tests/fuzz_operations.rs`: the part of a layer's graph derived from
//! Rapier's state alone, keyed by what each node stands for in Rapier, so that the
//! layer's graph can be compared with the graph of a layer built from scratch.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;

use rapier_contact_graph::logic::ContainerSource;
use rapier_contact_graph::{ContactLayer, EdgeKind, NodeKind, NodeSource};

use super::ops::raw;

/// What a node stands for in Rapier, comparable across layers.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub(super) enum Key {
    Body(u32, u32),
    Static(u32, u32),
    Sensor(u32, u32),
    Container(u8, u32, u32),
}

pub(super) fn key_of(src: NodeSource) -> Option<Key> {
    Some(match src {
        NodeSource::Body(h) => {
            let (i, g) = h.into_raw_parts();
            Key::Body(i, g)
        }
        NodeSource::StaticCollider(c) => {
            let (i, g) = c.into_raw_parts();
            Key::Static(i, g)
        }
        NodeSource::Sensor(c) => {
            let (i, g) = c.into_raw_parts();
            Key::Sensor(i, g)
        }
        NodeSource::Container(s) => {
            let (t, h) = match s {
                ContainerSource::Multibody(h) => (0, h),
                ContainerSource::Articulation(h) => (1, h),
                ContainerSource::Composite(h) => (2, h),
            };
            let (i, g) = h.into_raw_parts();
            Key::Container(t, i, g)
        }
        NodeSource::Layer(_) => return None,
    })
}

/// The keys of the bodies the speed-ups gave back after the layer's last analysis
/// (`LayerAnalysis::given_back`): dynamic in the world, held in the graph as the step
/// saw them, until the next analysis.
pub(super) fn given_back_keys(layer: &ContactLayer) -> std::collections::HashSet<Key> {
    layer
        .analysis()
        .given_back()
        .into_iter()
        .filter_map(|h| key_of(NodeSource::Body(h)))
        .collect()
}

fn sorted(a: Key, b: Key) -> (Key, Key) {
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

/// The part of a layer's graph derived from Rapier's state alone.
#[derive(Debug, Default, PartialEq)]
pub(super) struct Derived {
    pub(super) nodes: BTreeMap<Key, (NodeKind, Option<(u32, u32)>)>,
    pub(super) physical: BTreeMap<(Key, Key), (bool, u32, u32)>,
    pub(super) geometric: BTreeSet<(Key, Key)>,
    pub(super) structural: BTreeSet<(Key, Key)>,
}

pub(super) fn derived(layer: &ContactLayer, skip: &dyn Fn(Key, Key) -> bool) -> Derived {
    let g = layer.graph();
    let mut d = Derived::default();
    for (_, n) in g.nodes() {
        if let Some(k) = key_of(n.source()) {
            d.nodes.insert(k, (n.kind(), n.carrier().map(raw)));
        }
    }
    for (_, e) in g.edges() {
        let (Some(na), Some(nb)) = (g.node(e.a()), g.node(e.b())) else {
            continue;
        };
        let (Some(ka), Some(kb)) = (key_of(na.source()), key_of(nb.source())) else {
            continue;
        };
        match e.kind() {
            // A held body's frozen contacts (`ContactGraph::is_frozen`) are the
            // layer's own record: Rapier computes none for them, so a fresh layer
            // cannot know them.
            EdgeKind::Physical if e.is_proximate() && !skip(ka, kb) && !g.is_frozen(e) => {
                let c = e.cache();
                d.physical.insert(
                    sorted(ka, kb),
                    (e.is_touching(), c.contact_count, c.collider_pairs),
                );
            }
            EdgeKind::Geometric if !skip(ka, kb) => {
                d.geometric.insert(sorted(ka, kb));
            }
            EdgeKind::Structural => {
                d.structural.insert(sorted(ka, kb));
            }
            _ => {}
        }
    }
    d
}

pub(super) fn diff<K: Ord + std::fmt::Debug, V: PartialEq + std::fmt::Debug>(
    what: &str,
    main: &BTreeMap<K, V>,
    fresh: &BTreeMap<K, V>,
    out: &mut String,
) {
    for (k, v) in main {
        match fresh.get(k) {
            None => {
                let _ = writeln!(out, "  {what} {k:?} = {v:?} in the layer only");
            }
            Some(w) if w != v => {
                let _ = writeln!(out, "  {what} {k:?}: layer {v:?}, fresh {w:?}");
            }
            _ => {}
        }
    }
    for (k, w) in fresh {
        if !main.contains_key(k) {
            let _ = writeln!(out, "  {what} {k:?} = {w:?} in the fresh layer only");
        }
    }
}

pub(super) fn set_diff<K: Ord + std::fmt::Debug + Copy>(
    what: &str,
    main: &BTreeSet<K>,
    fresh: &BTreeSet<K>,
    out: &mut String,
) {
    let m: BTreeMap<K, ()> = main.iter().map(|k| (*k, ())).collect();
    let f: BTreeMap<K, ()> = fresh.iter().map(|k| (*k, ())).collect();
    diff(what, &m, &f, out);
}
