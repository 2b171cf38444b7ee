//! Unit tests of the snapshot's bytes and world stamp.

use serde::{Deserialize, Serialize};

use super::stamp::WorldStamp;
use crate::WorldView;
use rapier3d::prelude::{
    ColliderBuilder, ColliderHandle, PhysicsWorld, RigidBodyBuilder, RigidBodyHandle,
};
use std::collections::{HashMap, HashSet};

#[derive(Serialize, Deserialize)]
struct Maps {
    #[serde(with = "crate::util::serde_maps::sorted_map")]
    map: HashMap<ColliderHandle, u32>,
    #[serde(with = "crate::util::serde_maps::sorted_set")]
    set: HashSet<RigidBodyHandle>,
}

fn maps(order: &[u32]) -> Maps {
    let mut m = Maps {
        map: HashMap::new(),
        set: HashSet::new(),
    };
    for &i in order {
        m.map.insert(ColliderHandle::from_raw_parts(i, 1), i * 10);
        m.set.insert(RigidBodyHandle::from_raw_parts(i, 2));
    }
    m
}

#[test]
fn hash_maps_give_the_same_bytes_whatever_their_history() {
    let a = bincode::serialize(&maps(&[5, 1, 9, 3, 7])).unwrap();
    let mut grown = maps(&(0..200).collect::<Vec<_>>());
    for i in 0..200 {
        if ![1, 3, 5, 7, 9].contains(&i) {
            grown.map.remove(&ColliderHandle::from_raw_parts(i, 1));
            grown.set.remove(&RigidBodyHandle::from_raw_parts(i, 2));
        }
    }
    assert_eq!(a, bincode::serialize(&grown).unwrap());
    let back: Maps = bincode::deserialize(&a).unwrap();
    assert_eq!(back.map.len(), 5);
    assert_eq!(back.map[&ColliderHandle::from_raw_parts(9, 1)], 90);
    assert!(back.set.contains(&RigidBodyHandle::from_raw_parts(3, 2)));
}

#[test]
fn a_repeated_key_is_refused() {
    #[derive(Serialize)]
    struct Raw {
        map: Vec<(ColliderHandle, u32)>,
        set: Vec<RigidBodyHandle>,
    }
    let (c, b) = (
        ColliderHandle::from_raw_parts(1, 0),
        RigidBodyHandle::from_raw_parts(1, 0),
    );
    let twice_in_map = Raw {
        map: vec![(c, 1), (c, 2)],
        set: vec![b],
    };
    let bytes = bincode::serialize(&twice_in_map).unwrap();
    assert!(bincode::deserialize::<Maps>(&bytes).is_err());
    let twice_in_set = Raw {
        map: vec![(c, 1)],
        set: vec![b, b],
    };
    let bytes = bincode::serialize(&twice_in_set).unwrap();
    assert!(bincode::deserialize::<Maps>(&bytes).is_err());
}

#[test]
fn the_world_stamp_sees_one_bit_of_one_pose() {
    let mut world = PhysicsWorld::new();
    let (h, _) = world.insert(
        RigidBodyBuilder::dynamic().translation(rapier3d::math::Vector::new(0.0, 1.0, 0.0)),
        ColliderBuilder::ball(0.5),
    );
    let before = WorldStamp::of(&WorldView::from(&world));
    assert_eq!(before, WorldStamp::of(&WorldView::from(&world)));
    let mut t = world.bodies[h].translation();
    t.y = f32::from_bits(t.y.to_bits() + 1);
    world.bodies[h].set_translation(t, false);
    let after = WorldStamp::of(&WorldView::from(&world));
    assert_eq!(
        (after.bodies, after.colliders),
        (before.bodies, before.colliders)
    );
    assert_ne!(after.digest, before.digest);
}
