//! Unit tests of events, filters and subscriptions.

use super::*;

/// Rapier's collision events: contact and sensor starts and stops, nothing that
/// needs every pair read.
#[test]
fn collision_events_are_rapiers_started_and_stopped() {
    let want = KindSet::of(&[
        EventKind::ContactStarted,
        EventKind::ContactStopped,
        EventKind::SensorStarted,
        EventKind::SensorStopped,
    ]);
    assert_eq!(KindSet::COLLISION_EVENTS, want);
    assert!(!KindSet::COLLISION_EVENTS.intersects(KindSet::NEEDS_EVERY_PAIR));
    assert_eq!(
        KindSet::COLLISION_EVENTS,
        (KindSet::CONTACT | KindSet::SENSOR).without(KindSet::NEEDS_EVERY_PAIR)
    );
}

/// The kinds keep their discriminants: bincode encodes a kind by index, so
/// saved snapshots and events read back the same kinds.
#[test]
fn kinds_keep_their_discriminants() {
    let kinds = [
        EventKind::ProximityStarted,
        EventKind::ProximityPersisted,
        EventKind::ProximityStopped,
        EventKind::ContactStarted,
        EventKind::ContactPersisted,
        EventKind::ContactStopped,
        EventKind::SensorStarted,
        EventKind::SensorStopped,
    ];
    for (i, k) in kinds.into_iter().enumerate() {
        assert_eq!(k as u8, i as u8);
    }
}

#[test]
fn kind_sets_combine_with_bitor() {
    assert_eq!(
        KindSet::CONTACT | KindSet::SENSOR,
        KindSet::CONTACT.union(KindSet::SENSOR)
    );
    let mut k = KindSet::NONE;
    k |= KindSet::SLEEP;
    assert_eq!(k, KindSet::SLEEP);
    assert_eq!(
        EventKind::ContactStarted | EventKind::ContactStopped,
        KindSet::of(&[EventKind::ContactStarted, EventKind::ContactStopped])
    );
    let with = KindSet::CONTACT | EventKind::FellAsleep;
    assert!(with.contains(EventKind::FellAsleep) && with.contains(EventKind::ContactStarted));
    assert!(!with.contains(EventKind::WokeUp));
    assert_eq!(
        KindSet::from(EventKind::WokeUp),
        KindSet::of(&[EventKind::WokeUp])
    );
}

/// An event stays as small as its docs say.
#[test]
fn an_event_is_small() {
    let size = std::mem::size_of::<super::Event>();
    assert!(size <= 112, "Event is {size} bytes");
}
