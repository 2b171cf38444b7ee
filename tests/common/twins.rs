//! Snapshot tests' twins: a world and its layer saved, loaded, and stepped beside the
//! original, compared after every step (`tests/snapshot_*.rs`); and the logic scene
//! they share.
#![allow(dead_code)]

use crate::common::build::ball_at;
use crate::common::pose_bits;
use crossbeam_channel::Receiver;
use rapier3d::prelude::*;
use rapier_contact_graph::export::text::describe;
use rapier_contact_graph::logic::IgnorePredicate;
use rapier_contact_graph::monitor::{MonitorConfig, MonitorMode, RepairConfig};
use rapier_contact_graph::{ContactLayer, Event, Filter, KindSet, LayerSnapshot, NodeId, Rule};
use rcg_scenes::{self as scenes, Scene, Script};

/// World and layer to bytes, the way a game would save them.
pub fn save(world: &PhysicsWorld, layer: &ContactLayer) -> Vec<u8> {
    bincode::serialize(&(world, &layer.snapshot(world))).unwrap()
}

pub fn load(bytes: &[u8]) -> (PhysicsWorld, LayerSnapshot) {
    bincode::deserialize(bytes).unwrap()
}

pub fn layer_bytes(world: &PhysicsWorld, layer: &ContactLayer) -> Vec<u8> {
    bincode::serialize(&layer.snapshot(world)).unwrap()
}

pub fn debug_lines(layer: &ContactLayer) -> Vec<String> {
    let mut v: Vec<String> = format!("{layer:#?}").lines().map(str::to_owned).collect();
    v.sort_unstable();
    v
}

pub fn validated(name: &str, side: &str, step: u64, layer: &ContactLayer, world: &PhysicsWorld) {
    if let Err(e) = layer.validate(&*world) {
        panic!("{name}: {side} layer invalid after step {step}: {e}");
    }
}

/// One side of the comparison.
pub struct Side {
    pub world: PhysicsWorld,
    pub layer: ContactLayer,
    pub all: Receiver<Event>,
    pub some: Receiver<Event>,
}

impl Side {
    pub fn new(world: PhysicsWorld, mut layer: ContactLayer, watched: &[NodeId]) -> Self {
        let all = layer.subscribe(Filter::all());
        let some = layer.subscribe(Filter::kinds(KindSet::ALL).with_nodes(watched));
        Self {
            world,
            layer,
            all,
            some,
        }
    }

    pub fn step(&mut self, script: Option<Script>, step: u64) {
        if let Some(s) = script {
            s(&mut self.world, step);
        }
        self.layer.step(&mut self.world);
    }
}

/// The original and the restored pair, stepped side by side.
pub struct Twins {
    pub name: &'static str,
    pub script: Option<Script>,
    pub orig: Side,
    pub copy: Side,
    /// Index of the next step (0-based, as `Scene::before_step` counts).
    pub next: u64,
    pub events: usize,
}

impl Twins {
    /// Runs `scene` with `layer` for `k` steps (validated, with a subscriber), saves
    /// world and layer to bytes, loads them, and checks the loaded pair equals the
    /// original.
    pub fn split(
        scene: Scene,
        layer: ContactLayer,
        k: u64,
        bind: rapier_contact_graph::snapshot::PredicateResolver<'_>,
    ) -> Self {
        Self::split_after(scene, layer, k, &mut |_, _| {}, bind)
    }

    /// [`Self::split`], with `edit` applied to the world and the layer after the `k`
    /// steps, just before saving.
    pub fn split_after(
        mut scene: Scene,
        mut layer: ContactLayer,
        k: u64,
        edit: &mut dyn FnMut(&mut PhysicsWorld, &mut ContactLayer),
        bind: rapier_contact_graph::snapshot::PredicateResolver<'_>,
    ) -> Self {
        let (sub, _rx) = layer.subscribe_with_id(Filter::all());
        crate::common::run_validated(&mut scene, &mut layer, 0, k);
        edit(&mut scene.world, &mut layer);
        // The restored layer has no subscriptions; leave the original none either, so
        // that both continue with the same ones.
        assert!(layer.unsubscribe(sub));
        let bytes = save(&scene.world, &layer);
        let (world, snap) = load(&bytes);
        assert_eq!(snap.step(), layer.analysis().current_step());
        let copy = ContactLayer::restore_with(&snap, &world, bind)
            .unwrap_or_else(|e| panic!("{}: restore failed: {e}", scene.name));
        assert_eq!(
            copy.analysis().event_bus().len(),
            0,
            "no subscriptions after a restore"
        );
        assert_eq!(copy.last_events(), layer.last_events());
        assert_eq!(copy.analysis().stats(), layer.analysis().stats());
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
    pub fn run(&mut self, n: u64) {
        for _ in 0..n {
            let step = self.next;
            self.next += 1;
            self.orig.step(self.script, step);
            self.copy.step(self.script, step);
            self.compare(step);
        }
    }

    /// Applies the same change to both sides (world or layer), between two steps.
    pub fn both(&mut self, f: impl Fn(&mut PhysicsWorld, &mut ContactLayer)) {
        f(&mut self.orig.world, &mut self.orig.layer);
        f(&mut self.copy.world, &mut self.copy.layer);
    }

    pub fn compare(&mut self, step: u64) {
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
            a.layer.analysis().stats(),
            b.layer.analysis().stats(),
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

pub fn no_predicates() -> impl FnMut(NodeId, &[NodeId]) -> Option<IgnorePredicate> {
    |_, _| None
}

/// The pendulum scene plus every logical feature: rules of all three kinds, timers, a
/// passive body, joint-derived and declared composites, a trigger.
pub fn logic_scene() -> (Scene, ContactLayer, NodeId, RigidBodyHandle) {
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
    crate::common::run_validated(&mut scene, &mut layer, 0, 1);
    let n = |h| layer.graph().try_node_of_body(h).unwrap();
    let (g, nghost, npicky, nsleeper) = (n(ground), n(ghost), n(picky), n(sleeper));
    let (nb1, nb2) = (n(b1), n(b2));
    layer
        .logic_mut()
        .add_rule(Rule::ignore_pair(g, nghost))
        .unwrap();
    layer
        .logic_mut()
        .add_rule(Rule::ignore_between(&[nb1], &[nb2]))
        .unwrap();
    let predicate = layer
        .logic_mut()
        .add_rule(Rule::ignore_if(&[npicky], picky_predicate(g)))
        .unwrap();
    layer.logic_mut().add_timer(0.07).unwrap();
    layer.logic_mut().add_timer(0.25).unwrap();
    layer
        .logic_mut()
        .declare_composite_nodes(&[nb1, nb2])
        .unwrap();
    layer
        .logic_mut()
        .set_body_disabled(&scene.world.bodies, sleeper, true)
        .unwrap();
    let _ = nsleeper;
    let (c, r) = (MonitorConfig::default(), RepairConfig::default());
    layer.monitor_mut().set(MonitorMode::Report, c, r).unwrap();
    (scene, layer, predicate, sleeper)
}

/// The predicate of the logic scene: the picky ball ignores the ground (and nothing
/// else). Built the same way for the original and the restored layer.
pub fn picky_predicate(ground: NodeId) -> impl Fn(NodeId, NodeId) -> bool + Send + Sync + 'static {
    move |a, b| a == ground || b == ground
}
