//! Data serialised with the names of 0.1 still loads (serde aliases), in a
//! self-describing format (CBOR here, as `ciborium` writes it). Formats that encode
//! variants and fields by index (bincode) never wrote the names, so nothing changed
//! for them.
//!
//! The old encodings are made from new ones by renaming, in the CBOR value tree, what
//! 0.1 named otherwise: node kinds `Rigid` / `Scripted` / `Trigger`, event kinds
//! `TouchBegin` …, the event's fields `a` / `b` / `body_a` …, and `GroupStats::groups`.
#![cfg(feature = "serde")]

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::{ContactLayer, Event, Filter, LayerSnapshot};

use ciborium::Value;

use common::build::*;

/// New name → the name of 0.1, for values of a `kind` field.
const OLD_KINDS: [(&str, &str); 11] = [
    ("Dynamic", "Rigid"),
    ("Kinematic", "Scripted"),
    ("Sensor", "Trigger"),
    ("ProximityStarted", "ProximityBegin"),
    ("ProximityPersisted", "ProximityPersist"),
    ("ProximityStopped", "ProximityEnd"),
    ("ContactStarted", "TouchBegin"),
    ("ContactPersisted", "TouchPersist"),
    ("ContactStopped", "TouchEnd"),
    ("SensorStarted", "TriggerEnter"),
    ("SensorStopped", "TriggerExit"),
];

/// New field name → the name of 0.1, in an event.
const OLD_EVENT_FIELDS: [(&str, &str); 6] = [
    ("node1", "a"),
    ("node2", "b"),
    ("body1", "body_a"),
    ("body2", "body_b"),
    ("collider1", "collider_a"),
    ("collider2", "collider_b"),
];

fn text(v: &Value) -> Option<&str> {
    match v {
        Value::Text(s) => Some(s),
        _ => None,
    }
}

fn has_key(map: &[(Value, Value)], key: &str) -> bool {
    map.iter().any(|(k, _)| text(k) == Some(key))
}

/// Renames, in place, what 0.1 named otherwise; counts the renames.
fn to_old_names(v: &mut Value, count: &mut usize) {
    match v {
        Value::Map(map) => {
            let event = has_key(map, "node1") && has_key(map, "body1");
            let group_stats = has_key(map, "awake_groups") && has_key(map, "count");
            for (k, val) in map.iter_mut() {
                let key = text(k).unwrap_or_default().to_owned();
                if key == "kind" {
                    if let Some(&(_, old)) = OLD_KINDS.iter().find(|(n, _)| Some(*n) == text(val)) {
                        *val = Value::Text(old.into());
                        *count += 1;
                    }
                }
                let old = if event {
                    OLD_EVENT_FIELDS
                        .iter()
                        .find(|(n, _)| *n == key)
                        .map(|p| p.1)
                } else if group_stats && key == "count" {
                    Some("groups")
                } else {
                    None
                };
                if let Some(old) = old {
                    *k = Value::Text(old.into());
                    *count += 1;
                }
                to_old_names(val, count);
            }
        }
        Value::Array(a) => a.iter_mut().for_each(|x| to_old_names(x, count)),
        Value::Tag(_, x) => to_old_names(x, count),
        _ => {}
    }
}

/// A ground, balls falling on it, a kinematic platform and a sensor, stepped 60 times.
fn scene() -> (PhysicsWorld, ContactLayer, Vec<Event>) {
    let (mut world, _) = world_with_ground();
    for i in 0..4 {
        ball_at(&mut world, [i as f32 * 1.1 - 1.6, 1.0, 0.0], 0.4);
    }
    world.insert(
        RigidBodyBuilder::kinematic_velocity_based()
            .translation(Vector::new(0.0, 0.6, 3.0))
            .linvel(Vector::new(0.2, 0.0, 0.0)),
        ColliderBuilder::cuboid(1.0, 0.1, 1.0),
    );
    let sensor = world.insert_body(RigidBodyBuilder::fixed());
    world.insert_collider(
        ColliderBuilder::cuboid(3.0, 1.0, 1.0).sensor(true),
        Some(sensor),
    );
    let mut layer = ContactLayer::new();
    let rx = layer.subscribe(Filter::all());
    for _ in 0..60 {
        layer.step(&mut world);
    }
    (world, layer, rx.try_iter().collect())
}

#[test]
fn a_snapshot_with_the_old_names_restores_to_the_same_state() {
    let (world, layer, _) = scene();
    let new = Value::serialized(&layer.snapshot(&world)).unwrap();
    let mut old = new.clone();
    let mut renamed = 0;
    to_old_names(&mut old, &mut renamed);
    // One node kind per body or sensor (6 dynamic or fixed, 1 kinematic, 1 sensor)
    // and the group statistics at least.
    assert!(
        renamed >= 7,
        "{renamed} renames: the tree has no old names to test"
    );
    assert_ne!(old, new);

    let snap: LayerSnapshot = old.deserialized().unwrap();
    let restored = ContactLayer::restore(&snap, &world).unwrap();
    restored.validate(&world).unwrap();
    let again = Value::serialized(&restored.snapshot(&world)).unwrap();
    assert_eq!(again, new, "the old names load as the new ones");
}

#[test]
fn events_with_the_old_names_load_as_the_new_ones() {
    let (_, _, events) = scene();
    let kinds: std::collections::BTreeSet<_> = events.iter().map(|e| e.kind).collect();
    assert!(kinds.len() >= 4, "a varied stream: {kinds:?}");
    let new = Value::serialized(&events).unwrap();
    let mut old = new.clone();
    let mut renamed = 0;
    to_old_names(&mut old, &mut renamed);
    assert!(renamed >= 6 * events.len(), "every event's fields renamed");
    let back: Vec<Event> = old.deserialized().unwrap();
    assert_eq!(back, events);
}
