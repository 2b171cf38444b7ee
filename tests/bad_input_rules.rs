//! Bad-input audit (see `tests/common/audit.rs`): the logical nodes a user adds —
//! `add_rule`, `remove_rule`, `rule`, the `Rule` values and the hooks' rule table, and
//! `declare_composite` / `remove_composite`. (Rules added at the wrong time are in
//! `bad_input_stepping.rs`.)

mod common;

use rapier3d::prelude::*;
use rapier_contact_graph::{Error, NodeId, Rule};

use common::audit::*;
use common::build::*;

#[test]
fn add_rule_refuses_unknown_nodes() {
    let (mut world, ground, ball, mut layer) = stepped(0);
    let (stale, _) = stale_node(&mut layer, &mut world);
    let (g, b) = (
        layer.graph().try_node_of_body(ground).unwrap(),
        layer.graph().try_node_of_body(ball).unwrap(),
    );
    let timer = layer.logic_mut().add_timer(1.0).unwrap();
    let before = fingerprint(&layer);
    type Want = fn(&Error) -> bool;
    let cases: Vec<(Rule, Want)> = vec![
        (Rule::ignore_pair(b, stale), |e| {
            matches!(e, Error::StaleNode(_))
        }),
        (Rule::ignore_between(&[g], &[foreign_nodes(b)[0]]), |e| {
            matches!(e, Error::StaleNode(_))
        }),
        (Rule::ignore_if(&[foreign_nodes(b)[2]], |_, _| true), |e| {
            matches!(e, Error::StaleNode(_))
        }),
        (Rule::ignore_pair(b, timer), |e| {
            matches!(e, Error::WrongKind { .. })
        }),
        (Rule::ignore_between(&[], &[]), |e| {
            matches!(e, Error::InvalidParameter { .. })
        }),
        (Rule::ignore_if(&[], |_, _| true), |e| {
            matches!(e, Error::InvalidParameter { .. })
        }),
    ];
    for (rule, want) in cases {
        let r = layer.logic_mut().add_rule(rule.clone());
        assert!(r.as_ref().is_err_and(want), "{rule:?}: {r:?}");
        assert_eq!(fingerprint(&layer), before, "{rule:?} changed nothing");
    }
    // A pair of one node, and repeats: accepted (members are deduplicated).
    let r = layer
        .logic_mut()
        .add_rule(Rule::ignore_between(&[b, b], &[b]))
        .unwrap();
    assert_eq!(layer.logic().rule(r).unwrap().members(), vec![b]);
    // A member removed from the world later: the rule stays and can be removed.
    let r2 = layer.logic_mut().add_rule(Rule::ignore_pair(g, b)).unwrap();
    world.remove_body(ball);
    layer.step(&mut world);
    layer.validate(&world).unwrap();
    layer.logic_mut().remove_rule(r2).unwrap();
    layer.logic_mut().remove_rule(r).unwrap();
    layer.step(&mut world);
    layer.validate(&world).unwrap();
}

#[test]
fn remove_rule_and_rule_with_stale_ids() {
    let (mut world, ground, ball, mut layer) = stepped(2);
    let (g, b) = (
        layer.graph().try_node_of_body(ground).unwrap(),
        layer.graph().try_node_of_body(ball).unwrap(),
    );
    let r = layer.logic_mut().add_rule(Rule::ignore_pair(g, b)).unwrap();
    layer.step(&mut world);
    layer.logic_mut().remove_rule(r).unwrap();
    assert_eq!(
        layer.logic_mut().remove_rule(r).map(|_| ()),
        Err(Error::StaleNode(r)),
        "twice"
    );
    assert!(layer.logic().rule(r).is_none());
    for f in foreign_nodes(b) {
        assert_eq!(
            layer.logic_mut().remove_rule(f).map(|_| ()),
            Err(Error::StaleNode(f))
        );
        assert!(layer.logic().rule(f).is_none());
    }
    assert!(matches!(
        layer.logic_mut().remove_rule(b),
        Err(Error::WrongKind { .. })
    ));
    assert!(layer.logic().rule(b).is_none(), "not a rule");
    layer.step(&mut world);
    layer.validate(&world).unwrap();
}

#[test]
fn rule_values_with_stale_nodes() {
    let (a, b) = (NodeId::from_raw_parts(1, 0), NodeId::from_raw_parts(2, 0));
    let stale = NodeId::from_raw_parts(1, 5);
    let r = Rule::ignore_between(&[a, a], &[b]);
    assert_eq!(r.members(), vec![a, b]);
    assert!(!r.ignores(stale, b) && r.ignores(b, a));
    assert!(!Rule::ignore_pair(a, b).ignores(a, a));
    let (_, _, _, layer) = stepped(2);
    let table = layer.hooks().table();
    assert!(!table.ignores(stale, b) && !table.names(stale));
    assert!(!layer.hooks().mods().is_sleepy(RigidBodyHandle::invalid()));
}

#[test]
// Fixed: the hooks resolve any body through the graph and ask the predicate.
fn bug_incidental_predicate_rule_with_a_non_member() {
    let (mut world, _, ball, mut layer) = stepped(5);
    let b = layer.graph().try_node_of_body(ball).unwrap();
    // "Ignore every interaction of the ball": only the ball is a member.
    layer
        .logic_mut()
        .add_rule(Rule::ignore_if(&[b], move |x, y| x == b || y == b))
        .unwrap();
    for _ in 0..60 {
        layer.step(&mut world);
    }
    assert!(
        world.bodies[ball].translation().y < 0.0,
        "the ball fell through the ground"
    );
}

#[test]
fn composites_with_stale_wrong_and_removed_members() {
    let (mut world, ground, ball, mut layer) = stepped(0);
    let (extra, _) = ball_at(&mut world, [3.0, 1.0, 0.0], 0.5);
    layer.step(&mut world);
    let (stale, _) = stale_node(&mut layer, &mut world);
    let (g, b, x) = (
        layer.graph().try_node_of_body(ground).unwrap(),
        layer.graph().try_node_of_body(ball).unwrap(),
        layer.graph().try_node_of_body(extra).unwrap(),
    );
    let t = layer.logic_mut().add_timer(1.0).unwrap();
    let before = fingerprint(&layer);
    assert!(matches!(
        layer.logic_mut().declare_composite_nodes(&[]),
        Err(Error::InvalidParameter { .. })
    ));
    assert_eq!(
        layer.logic_mut().declare_composite_nodes(&[b, stale]),
        Err(Error::StaleNode(stale))
    );
    let f = foreign_nodes(b)[0];
    assert_eq!(
        layer.logic_mut().declare_composite_nodes(&[f]),
        Err(Error::StaleNode(f))
    );
    assert!(matches!(
        layer.logic_mut().declare_composite_nodes(&[b, g]),
        Err(Error::WrongKind { .. })
    ));
    assert!(matches!(
        layer.logic_mut().declare_composite_nodes(&[t]),
        Err(Error::WrongKind { .. })
    ));
    assert_eq!(fingerprint(&layer), before, "nothing added");
    // Repeats: one structural edge per member.
    let c = layer
        .logic_mut()
        .declare_composite_nodes(&[b, b, x])
        .unwrap();
    assert_eq!(layer.graph().node(c).unwrap().degree(), 2);
    // remove_composite with wrong ids.
    assert_eq!(
        layer.logic_mut().remove_composite(stale),
        Err(Error::StaleNode(stale))
    );
    assert!(matches!(
        layer.logic_mut().remove_composite(b),
        Err(Error::WrongKind { .. })
    ));
    assert!(matches!(
        layer.logic_mut().remove_composite(t),
        Err(Error::WrongKind { .. })
    ));
    // A member removed from the world: the composite stays, removable, valid.
    world.remove_body(extra);
    for _ in 0..3 {
        layer.step(&mut world);
        layer.validate(&world).unwrap();
    }
    layer.logic_mut().remove_composite(c).unwrap();
    assert_eq!(
        layer.logic_mut().remove_composite(c),
        Err(Error::StaleNode(c)),
        "twice"
    );
    layer.step(&mut world);
    layer.validate(&world).unwrap();
}
