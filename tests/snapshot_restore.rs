//! Snapshot and restore: a world and its layer saved to bytes (Rapier's serde and
//! `ContactLayer::snapshot`, bincode), loaded, and stepped beside the original. The pair
//! must continue bit for bit: poses, events, the graph's text form and the full layer
//! state (its snapshot bytes) are compared after every step, and both layers are
//! validated after every step.
#![cfg(feature = "serde")]

mod common;

use std::sync::Arc;

use common::audit::xorshift;
use common::build::ball_at;
use common::pose_bits;
use crossbeam_channel::Receiver;
use rapier3d::prelude::*;
use rapier_contact_graph::export::text::describe;
use rapier_contact_graph::logic::IgnorePredicate;
use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
use rapier_contact_graph::speedups::SpeedUps;
use rapier_contact_graph::{
    ContactLayer, Error, Event, Filter, KindSet, LayerSnapshot, NodeId, Rule, SNAPSHOT_FORMAT,
};
use rcg_scenes::{self as scenes, Scene, Script};

/// World and layer to bytes, the way a game would save them.
fn save(world: &PhysicsWorld, layer: &ContactLayer) -> Vec<u8> {
    bincode::serialize(&(world, &layer.snapshot(world))).unwrap()
}

fn load(bytes: &[u8]) -> (PhysicsWorld, LayerSnapshot) {
    bincode::deserialize(bytes).unwrap()
}

fn layer_bytes(world: &PhysicsWorld, layer: &ContactLayer) -> Vec<u8> {
    bincode::serialize(&layer.snapshot(world)).unwrap()
}

fn debug_lines(layer: &ContactLayer) -> Vec<String> {
    let mut v: Vec<String> = format!("{layer:#?}").lines().map(str::to_owned).collect();
    v.sort_unstable();
    v
}

fn validated(name: &str, side: &str, step: u64, layer: &ContactLayer, world: &PhysicsWorld) {
    if let Err(e) = layer.validate(world) {
        panic!("{name}: {side} layer invalid after step {step}: {e}");
    }
}

/// One side of the comparison.
struct Side {
    world: PhysicsWorld,
    layer: ContactLayer,
    all: Receiver<Event>,
    some: Receiver<Event>,
}

impl Side {
    fn new(world: PhysicsWorld, mut layer: ContactLayer, watched: &[NodeId]) -> Self {
        let all = layer.subscribe(Filter::all());
        let some = layer.subscribe(Filter::kinds(KindSet::ALL).with_nodes(watched));
        Self {
            world,
            layer,
            all,
            some,
        }
    }

    fn step(&mut self, script: Option<Script>, step: u64) {
        if let Some(s) = script {
            s(&mut self.world, step);
        }
        self.layer.step(&mut self.world);
    }
}

/// The original and the restored pair, stepped side by side.
struct Twins {
    name: &'static str,
    script: Option<Script>,
    orig: Side,
    copy: Side,
    /// Index of the next step (0-based, as `Scene::before_step` counts).
    next: u64,
    events: usize,
}

impl Twins {
    /// Runs `scene` with `layer` for `k` steps (validated, with a subscriber), saves
    /// world and layer to bytes, loads them, and checks the loaded pair equals the
    /// original.
    fn split(
        scene: Scene,
        layer: ContactLayer,
        k: u64,
        bind: rapier_contact_graph::snapshot::PredicateResolver<'_>,
    ) -> Self {
        Self::split_after(scene, layer, k, &mut |_, _| {}, bind)
    }

    /// [`Self::split`], with `edit` applied to the world and the layer after the `k`
    /// steps, just before saving.
    fn split_after(
        mut scene: Scene,
        mut layer: ContactLayer,
        k: u64,
        edit: &mut dyn FnMut(&mut PhysicsWorld, &mut ContactLayer),
        bind: rapier_contact_graph::snapshot::PredicateResolver<'_>,
    ) -> Self {
        let (sub, _rx) = layer.subscribe_with_id(Filter::all());
        common::run_validated(&mut scene, &mut layer, 0, k);
        edit(&mut scene.world, &mut layer);
        // The restored layer has no subscriptions; leave the original none either, so
        // that both continue with the same ones.
        assert!(layer.unsubscribe(sub));
        let bytes = save(&scene.world, &layer);
        let (world, snap) = load(&bytes);
        assert_eq!(snap.step(), layer.current_step());
        let copy = ContactLayer::restore_with(&snap, &world, bind)
            .unwrap_or_else(|e| panic!("{}: restore failed: {e}", scene.name));
        assert_eq!(
            copy.event_bus().len(),
            0,
            "no subscriptions after a restore"
        );
        assert_eq!(copy.last_events(), layer.last_events());
        assert_eq!(copy.stats(), layer.stats());
        assert_eq!(
            describe(&copy, &|_| None),
            describe(&layer, &|_| None),
            "{}: the restored graph differs",
            scene.name
        );
        assert_eq!(
            layer_bytes(&world, &copy),
            layer_bytes(&scene.world, &layer),
            "{}: the restored state differs",
            scene.name
        );
        // Every field, serialised or not: the Debug forms hold the same lines (sorted,
        // because hash maps print in their own order).
        assert!(
            debug_lines(&copy) == debug_lines(&layer),
            "{}: the restored layer's fields differ",
            scene.name
        );
        // An edit since the last step may leave the layer behind the world until the
        // next step: then both layers fail validation alike.
        if layer.validate(&scene.world).is_ok() {
            validated(scene.name, "restored", k, &copy, &world);
        } else {
            assert!(copy.validate(&world).is_err());
        }
        // Watch the first few body nodes with a node filter too.
        let watched: Vec<NodeId> = layer
            .graph()
            .nodes()
            .filter(|(_, n)| n.body().is_some())
            .map(|(id, _)| id)
            .take(3)
            .collect();
        Self {
            name: scene.name,
            script: scene.script,
            orig: Side::new(scene.world, layer, &watched),
            copy: Side::new(world, copy, &watched),
            next: k,
            events: 0,
        }
    }

    /// Steps both `n` times and compares everything after every step.
    fn run(&mut self, n: u64) {
        for _ in 0..n {
            let step = self.next;
            self.next += 1;
            self.orig.step(self.script, step);
            self.copy.step(self.script, step);
            self.compare(step);
        }
    }

    /// Applies the same change to both sides (world or layer), between two steps.
    fn both(&mut self, f: impl Fn(&mut PhysicsWorld, &mut ContactLayer)) {
        f(&mut self.orig.world, &mut self.orig.layer);
        f(&mut self.copy.world, &mut self.copy.layer);
    }

    fn compare(&mut self, step: u64) {
        let (a, b) = (&self.orig, &self.copy);
        validated(self.name, "original", step, &a.layer, &a.world);
        validated(self.name, "restored", step, &b.layer, &b.world);
        assert!(
            pose_bits(&a.world) == pose_bits(&b.world),
            "{}: poses differ after step {step}",
            self.name
        );
        let ea: Vec<Event> = a.all.try_iter().collect();
        let eb: Vec<Event> = b.all.try_iter().collect();
        assert_eq!(ea, eb, "{}: events differ at step {step}", self.name);
        self.events += ea.len();
        let (fa, fb): (Vec<Event>, Vec<Event>) =
            (a.some.try_iter().collect(), b.some.try_iter().collect());
        assert_eq!(
            fa, fb,
            "{}: filtered events differ at step {step}",
            self.name
        );
        assert_eq!(
            a.layer.stats(),
            b.layer.stats(),
            "{}: stats at step {step}",
            self.name
        );
        assert_eq!(
            describe(&a.layer, &|_| None),
            describe(&b.layer, &|_| None),
            "{}: graphs differ after step {step}",
            self.name
        );
        assert!(
            layer_bytes(&a.world, &a.layer) == layer_bytes(&b.world, &b.layer),
            "{}: layer states differ after step {step}",
            self.name
        );
    }
}

fn no_predicates() -> impl FnMut(NodeId, &[NodeId]) -> Option<IgnorePredicate> {
    |_, _| None
}

// ── Rapier alone ────────────────────────────────────────────────────────────

/// A scene with impulse joints (a fixed pair and a hinged pair) on a floor.
fn jointed_boxes() -> Scene {
    let mut world = PhysicsWorld::new();
    world.integration_parameters.dt = scenes::DT;
    world.insert(
        RigidBodyBuilder::fixed(),
        ColliderBuilder::cuboid(10.0, 0.5, 10.0).translation(Vector::new(0.0, -0.5, 0.0)),
    );
    let mut bodies = Vec::new();
    let names = ["a", "b", "c", "d"];
    for (i, x) in [-3.0f32, -2.4, 2.0, 2.6].into_iter().enumerate() {
        let (h, _) = world.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(x, 1.5 + 0.3 * i as f32, 0.0))
                .angvel(Vector::new(0.0, 0.0, 1.0)),
            ColliderBuilder::cuboid(0.25, 0.25, 0.25),
        );
        bodies.push((names[i], h));
    }
    let anchors = |b: FixedJointBuilder| {
        b.local_anchor1(Vector::new(0.3, 0.0, 0.0))
            .local_anchor2(Vector::new(-0.3, 0.0, 0.0))
    };
    world.insert_impulse_joint(bodies[0].1, bodies[1].1, anchors(FixedJointBuilder::new()));
    world.insert_impulse_joint(
        bodies[2].1,
        bodies[3].1,
        RevoluteJointBuilder::new(Vector::Z)
            .local_anchor1(Vector::new(0.3, 0.0, 0.0))
            .local_anchor2(Vector::new(-0.3, 0.0, 0.0)),
    );
    Scene {
        name: "jointed_boxes",
        world,
        bodies,
        script: None,
    }
}

#[test]
fn rapier_alone_continues_bit_for_bit_after_a_round_trip() {
    // The layer's guarantee rests on Rapier's: check it first, on its own, at several
    // moments of each scene (falling, colliding, settling, asleep).
    type Builder = (fn() -> Scene, &'static [u64]);
    let builders: [Builder; 6] = [
        (|| scenes::sphere_pile(40, 7), &[1, 60, 250]),
        (scenes::toppling_stack, &[1, 40, 120]),
        (scenes::trigger_ledge, &[1, 50, 150]),
        (scenes::pendulum_wall, &[1, 45, 90]),
        (scenes::kinematic_platform, &[1, 30, 100]),
        (jointed_boxes, &[1, 30, 200]),
    ];
    for (build, points) in builders {
        for &k in points {
            let mut scene = build();
            scene.run_plain(0, k);
            let mut copy: PhysicsWorld =
                bincode::deserialize(&bincode::serialize(&scene.world).unwrap()).unwrap();
            for step in k..k + 300 {
                scene.before_step(step);
                if let Some(s) = scene.script {
                    s(&mut copy, step);
                }
                scene.world.step();
                copy.step();
                assert!(
                    pose_bits(&scene.world) == pose_bits(&copy),
                    "{}: Rapier's restored world diverges at step {step} (saved after {k})",
                    scene.name
                );
            }
        }
    }
}

// ── The layer ───────────────────────────────────────────────────────────────

#[test]
fn a_restored_sphere_pile_continues_bit_for_bit() {
    for k in [1, 45, 200] {
        let mut t = Twins::split(
            scenes::sphere_pile(40, 7),
            ContactLayer::new(),
            k,
            &mut no_predicates(),
        );
        t.run(300);
        assert!(t.events > 0 || k == 200, "the pile produced no event");
    }
}

#[test]
fn a_restored_trigger_ledge_continues_bit_for_bit_with_its_trigger_events() {
    // Saved before the ball reaches the trigger, while it is inside, and after.
    let mut inside_seen = false;
    for k in [5, 40, 70, 120] {
        let mut t = Twins::split(
            scenes::trigger_ledge(),
            ContactLayer::new(),
            k,
            &mut no_predicates(),
        );
        let start = t
            .orig
            .layer
            .graph()
            .count_of_kind(rapier_contact_graph::NodeKind::Trigger);
        assert_eq!(start, 1);
        inside_seen |= t
            .orig
            .layer
            .graph()
            .edges()
            .any(|(_, e)| e.kind() == rapier_contact_graph::EdgeKind::Geometric);
        t.run(250);
    }
    assert!(
        inside_seen,
        "no snapshot was taken with the ball inside the trigger"
    );
}

#[test]
fn a_restored_toppling_stack_continues_bit_for_bit() {
    for k in [20, 90] {
        let mut t = Twins::split(
            scenes::toppling_stack(),
            ContactLayer::new(),
            k,
            &mut no_predicates(),
        );
        t.run(300);
    }
}

#[test]
fn a_restored_kinematic_platform_continues_bit_for_bit() {
    let mut t = Twins::split(
        scenes::kinematic_platform(),
        ContactLayer::new(),
        40,
        &mut no_predicates(),
    );
    t.run(250);
}

/// The pendulum scene plus every logical feature: rules of all three kinds, timers, a
/// passive body, joint-derived and declared composites, a trigger.
fn logic_scene() -> (Scene, ContactLayer, NodeId, RigidBodyHandle) {
    let mut scene = scenes::pendulum_wall();
    let ground = scene.body("ground").unwrap();
    let w = &mut scene.world;
    let ball = |w: &mut PhysicsWorld, x: f32, y: f32| ball_at(w, [x, y, 1.5], 0.2).0;
    let ghost = ball(w, 2.0, 1.0);
    let picky = ball(w, 3.0, 1.0);
    let sleeper = ball(w, -2.0, 0.5);
    let (b1, b2) = (ball(w, 1.0, 0.5), ball(w, 1.5, 0.5));
    let (j1, j2) = (ball(w, -3.0, 0.8), ball(w, -2.5, 0.8));
    w.insert_impulse_joint(
        j1,
        j2,
        FixedJointBuilder::new()
            .local_anchor1(Vector::new(0.25, 0.0, 0.0))
            .local_anchor2(Vector::new(-0.25, 0.0, 0.0)),
    );
    let sensor = w.insert_body(RigidBodyBuilder::fixed().translation(Vector::new(2.0, 0.3, 1.5)));
    w.insert_collider(
        ColliderBuilder::cuboid(1.5, 0.3, 0.5).sensor(true),
        Some(sensor),
    );
    scene
        .bodies
        .extend([("ghost", ghost), ("picky", picky), ("sleeper", sleeper)]);

    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, 1);
    let n = |h| layer.node_of_body(h).unwrap();
    let (g, nghost, npicky, nsleeper) = (n(ground), n(ghost), n(picky), n(sleeper));
    let (nb1, nb2) = (n(b1), n(b2));
    layer.add_rule(Rule::ignore_pair(g, nghost)).unwrap();
    layer
        .add_rule(Rule::ignore_between(&[nb1], &[nb2]))
        .unwrap();
    let predicate = layer
        .add_rule(Rule::ignore_if(&[npicky], picky_predicate(g)))
        .unwrap();
    layer.add_timer(0.07).unwrap();
    layer.add_timer(0.25).unwrap();
    layer.declare_composite(&[nb1, nb2]).unwrap();
    layer.set_passive(sleeper, true).unwrap();
    let _ = nsleeper;
    let (c, r) = (MonitorConfig::default(), RepairConfig::default());
    layer.set_monitor(MonitorMode::Report, c, r).unwrap();
    (scene, layer, predicate, sleeper)
}

/// The predicate of the logic scene: the picky ball ignores the ground (and nothing
/// else). Built the same way for the original and the restored layer.
fn picky_predicate(ground: NodeId) -> impl Fn(NodeId, NodeId) -> bool + Send + Sync + 'static {
    move |a, b| a == ground || b == ground
}

#[test]
fn a_restored_layer_with_rules_timers_passive_bodies_and_containers_continues_bit_for_bit() {
    for k in [3, 60] {
        let (scene, layer, predicate, sleeper) = logic_scene();
        let ground = layer.node_of_body(scene.body("ground").unwrap()).unwrap();
        let mut asked = Vec::new();
        let mut bind = |n: NodeId, members: &[NodeId]| -> Option<IgnorePredicate> {
            asked.push((n, members.to_vec()));
            (n == predicate).then(|| Arc::new(picky_predicate(ground)) as IgnorePredicate)
        };
        let mut t = Twins::split(scene, layer, k, &mut bind);
        assert_eq!(asked.len(), 1, "one predicate rule to give back");
        assert_eq!(asked[0].0, predicate);
        t.run(80);
        // A logical change after the restore, on both sides: the passive body comes
        // back, a timer goes, a rule goes.
        t.both(|_, layer| {
            layer.set_passive(sleeper, false).unwrap();
        });
        t.run(40);
        t.both(|_, layer| {
            let timer = layer
                .graph()
                .nodes_of_kind(rapier_contact_graph::NodeKind::Timer)
                .map(|(id, _)| id)
                .next()
                .unwrap();
            layer.remove_timer(timer).unwrap();
            layer.remove_rule(predicate).unwrap();
        });
        t.run(120);
        assert!(t.events > 0);
    }
}

#[test]
fn a_restored_layer_with_every_speed_up_and_repair_continues_bit_for_bit() {
    let mut scene = scenes::sphere_pile(40, 11);
    let layer_with_everything = || {
        let mut layer = ContactLayer::new();
        layer
            .set_speedups(Some(SpeedUps::combination(127)))
            .unwrap();
        let (c, r) = (MonitorConfig::default(), RepairConfig::default());
        layer.set_monitor(MonitorMode::Repair, c, r).unwrap();
        layer
    };
    let mut layer = layer_with_everything();
    // Run until a few bodies are fixated while the others are still counting their
    // steps at rest, then save.
    let mut k = 0;
    while layer.speedups().is_none_or(|s| s.stats().fixated < 4) {
        assert!(k < 1_000, "too little was ever fixated");
        common::run_validated(&mut scene, &mut layer, k, 1);
        k += 1;
    }
    let fixated = layer.speedups().unwrap().stats().fixated;
    assert!(fixated < 40, "everything fixated already");
    // `split` runs from step 0: give it a fresh pile and the same number of steps.
    let fresh = layer_with_everything();
    let mut t = Twins::split(scenes::sphere_pile(40, 11), fresh, k, &mut no_predicates());
    assert_eq!(t.copy.layer.speedups().unwrap().stats().fixated, fixated);
    t.run(100);
    // A hammer dropped into the box releases fixated bodies, on both sides alike.
    let above = scenes::pile::wall_height(40) + 1.0;
    t.both(|world, _| {
        world.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.3, above, 0.2))
                .linvel(Vector::new(0.0, -10.0, 0.0)),
            ColliderBuilder::ball(0.4).density(20.0),
        );
    });
    let before = t.orig.layer.speedups().unwrap().stats().fixated;
    let mut released = 0;
    for _ in 0..300 {
        t.run(1);
        released += t.orig.layer.speedups().unwrap().stats().releases;
    }
    assert!(
        released > 0 || t.orig.layer.speedups().unwrap().stats().fixated < before,
        "the hammer released nothing"
    );
    // Switching the speed-ups and the monitor off restores the world on both sides
    // alike.
    t.both(|_, layer| {
        layer.set_speedups(None).unwrap();
        let (c, r) = (MonitorConfig::default(), RepairConfig::default());
        layer.set_monitor(MonitorMode::Off, c, r).unwrap();
    });
    t.run(100);
}

#[test]
fn a_snapshot_taken_between_world_edits_and_the_next_step_continues_bit_for_bit() {
    // Bodies removed and inserted, a rule, a timer and a passive body queued: the
    // layer has not seen any of it yet when the pair is saved.
    let mut edit = |world: &mut PhysicsWorld, layer: &mut ContactLayer| {
        let spheres: Vec<RigidBodyHandle> = world
            .bodies
            .iter()
            .filter(|(_, b)| b.is_dynamic())
            .map(|(h, _)| h)
            .collect();
        let [gone, passive, a, b] = spheres[..4] else {
            unreachable!()
        };
        world.remove_body(gone);
        ball_at(world, [0.2, 8.0, -0.3], 0.3);
        let (na, nb) = (
            layer.node_of_body(a).unwrap(),
            layer.node_of_body(b).unwrap(),
        );
        layer.add_rule(Rule::ignore_pair(na, nb)).unwrap();
        layer.add_timer(0.1).unwrap();
        layer.set_passive(passive, true).unwrap();
    };
    let mut t = Twins::split_after(
        scenes::sphere_pile(30, 5),
        ContactLayer::new(),
        80,
        &mut edit,
        &mut no_predicates(),
    );
    t.run(250);
}

// ── What restore refuses ────────────────────────────────────────────────────

fn saved_pile(k: u64) -> (Scene, ContactLayer) {
    let mut scene = scenes::sphere_pile(30, 3);
    let mut layer = ContactLayer::new();
    common::run_validated(&mut scene, &mut layer, 0, k);
    (scene, layer)
}

#[test]
fn restoring_against_the_wrong_world_is_an_error() {
    let (mut scene, mut layer) = saved_pile(40);
    let snap = layer.snapshot(&scene.world);
    let is_mismatch = |r: Result<ContactLayer, Error>| match r {
        Err(Error::SnapshotMismatch(msg)) => msg,
        other => panic!("expected a mismatch, got {other:?}"),
    };
    // Another scene: names a body it lacks.
    let other = scenes::ball_on_box();
    let msg = is_mismatch(ContactLayer::restore(&snap, &other.world));
    assert!(msg.contains("lacks"), "{msg}");
    // The same world, one body removed.
    let mut fewer = load(&save(&scene.world, &layer)).0;
    let (h, _) = fewer.bodies.iter().last().unwrap();
    fewer.remove_body(h);
    let msg = is_mismatch(ContactLayer::restore(&snap, &fewer));
    assert!(msg.contains(&format!("{h:?}")), "{msg}");
    // The same world, one step later.
    let saved = load(&save(&scene.world, &layer)).0;
    common::run_validated(&mut scene, &mut layer, 40, 1);
    let msg = is_mismatch(ContactLayer::restore(&snap, &scene.world));
    assert!(msg.contains("same objects"), "{msg}");
    // The snapshot is intact: the right world restores.
    ContactLayer::restore(&snap, &saved)
        .unwrap()
        .validate(&saved)
        .unwrap();
}

#[test]
fn a_predicate_rule_needs_its_predicate_given_back() {
    let (scene, layer, predicate, _) = logic_scene();
    let bytes = save(&scene.world, &layer);
    let (world, snap) = load(&bytes);
    assert_eq!(snap.predicate_rules().len(), 1);
    assert_eq!(snap.predicate_rules()[0].0, predicate);
    assert_eq!(
        ContactLayer::restore(&snap, &world).unwrap_err(),
        Error::UnboundPredicate(predicate)
    );
    // A resolver that refuses is the same error.
    let r = ContactLayer::restore_with(&snap, &world, &mut |_, _| None);
    assert_eq!(r.unwrap_err(), Error::UnboundPredicate(predicate));
}

#[test]
fn a_snapshot_of_another_format_or_not_a_snapshot_is_an_error() {
    let (scene, layer) = saved_pile(20);
    let bytes = bincode::serialize(&layer.snapshot(&scene.world)).unwrap();
    // Format: the second u32.
    let mut newer = bytes.clone();
    newer[4..8].copy_from_slice(&(SNAPSHOT_FORMAT + 1).to_le_bytes());
    let err = bincode::deserialize::<LayerSnapshot>(&newer)
        .unwrap_err()
        .to_string();
    let want = Error::SnapshotFormat {
        found: SNAPSHOT_FORMAT + 1,
        expected: SNAPSHOT_FORMAT,
    }
    .to_string();
    assert!(err.contains(&want), "{err}");
    // Magic: the first u32.
    let mut alien = bytes.clone();
    alien[0] ^= 0x20;
    let err = bincode::deserialize::<LayerSnapshot>(&alien)
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("not a rapier-contact-graph layer snapshot"),
        "{err}"
    );
    // Rapier's world bytes are not a layer snapshot.
    let world = bincode::serialize(&scene.world).unwrap();
    assert!(bincode::deserialize::<LayerSnapshot>(&world).is_err());
}

#[test]
fn truncated_snapshots_are_errors_not_panics() {
    let (scene, layer) = saved_pile(30);
    let bytes = bincode::serialize(&layer.snapshot(&scene.world)).unwrap();
    let stride = (bytes.len() / 1_500).max(1);
    for len in (0..bytes.len()).step_by(stride).chain([bytes.len() - 1]) {
        assert!(
            bincode::deserialize::<LayerSnapshot>(&bytes[..len]).is_err(),
            "a snapshot cut to {len} of {} bytes decoded",
            bytes.len()
        );
    }
}

#[test]
fn corrupted_snapshots_are_refused_or_restore_a_layer_that_steps_without_panicking() {
    // Rules, timers, a passive body, containers and a trigger, without speed-ups (their
    // iteration counts are taken as they come, as `set_speedups` takes them, so a
    // corrupted count could make Rapier's step take arbitrarily long).
    let (mut scene, mut layer, _, _) = logic_scene();
    let predicate_of = picky_predicate(layer.node_of_body(scene.body("ground").unwrap()).unwrap());
    let predicate: IgnorePredicate = Arc::new(predicate_of);
    common::run_validated(&mut scene, &mut layer, 1, 60);
    let world_bytes = bincode::serialize(&scene.world).unwrap();
    let bytes = bincode::serialize(&layer.snapshot(&scene.world)).unwrap();
    let (mut undecodable, mut refused, mut accepted) = (0, 0, 0);
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let trials = 1_500;
    for _ in 0..trials {
        let mut bad = bytes.clone();
        let pos = (xorshift(&mut seed) % bad.len() as u64) as usize;
        let bit = xorshift(&mut seed) % 8;
        bad[pos] ^= 1 << bit;
        let Ok(snap) = bincode::deserialize::<LayerSnapshot>(&bad) else {
            undecodable += 1;
            continue;
        };
        let mut world: PhysicsWorld = bincode::deserialize(&world_bytes).unwrap();
        let restored =
            ContactLayer::restore_with(&snap, &world, &mut |_, _| Some(predicate.clone()));
        match restored {
            Err(Error::Invariant(_)) | Err(Error::SnapshotMismatch(_)) => refused += 1,
            Err(e) => panic!("unexpected error {e}"),
            Ok(mut l) => {
                accepted += 1;
                for _ in 0..5 {
                    l.step(&mut world);
                    let _ = l.validate(&world);
                }
            }
        }
    }
    println!(
        "{trials} one-bit corruptions of {} bytes: {undecodable} undecodable, {refused} refused by restore, {accepted} accepted and stepped",
        bytes.len()
    );
    assert_eq!(undecodable + refused + accepted, trials);
    assert!(refused > 0, "restore's checks never fired");
}
