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

/// The deprecated names of 0.1 are the renamed kinds and sets, with the same
/// discriminants, in expressions and in patterns.
#[test]
#[allow(deprecated)]
fn deprecated_kind_names_are_the_new_kinds() {
    let pairs = [
        (EventKind::ProximityBegin, EventKind::ProximityStarted),
        (EventKind::ProximityPersist, EventKind::ProximityPersisted),
        (EventKind::ProximityEnd, EventKind::ProximityStopped),
        (EventKind::TouchBegin, EventKind::ContactStarted),
        (EventKind::TouchPersist, EventKind::ContactPersisted),
        (EventKind::TouchEnd, EventKind::ContactStopped),
        (EventKind::TriggerEnter, EventKind::SensorStarted),
        (EventKind::TriggerExit, EventKind::SensorStopped),
    ];
    for (i, (old, new)) in pairs.into_iter().enumerate() {
        assert_eq!(old, new);
        assert_eq!(new as u8, i as u8, "discriminants kept");
    }
    assert!(matches!(EventKind::ContactStarted, EventKind::TouchBegin));
    assert!(!matches!(EventKind::ContactStopped, EventKind::TouchBegin));
    assert_eq!(KindSet::TOUCH, KindSet::CONTACT);
    assert_eq!(KindSet::TRIGGER, KindSet::SENSOR);
    assert_eq!(
        KindSet::CONTACT,
        EventKind::ContactStarted | EventKind::ContactPersisted | EventKind::ContactStopped
    );
    assert_eq!(
        KindSet::SENSOR,
        EventKind::SensorStarted | EventKind::SensorStopped
    );
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
