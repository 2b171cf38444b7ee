//! Rules in snapshots: a predicate rule keeps its members, not its closure (the
//! closure is given back on restore). Used through `#[serde(with = "...")]` on
//! [`super::Logic`]'s fields.

use std::collections::BTreeMap;
use std::sync::Arc;

use serde::de;
use serde::{Deserialize, Deserializer, Serialize, Serializer};

use crate::graph::NodeId;
use crate::logic::Rule;

/// A rule as written in a snapshot: a predicate keeps its members, not its closure.
#[derive(Serialize, Deserialize)]
enum RuleRepr {
    IgnoreBetween(Vec<NodeId>, Vec<NodeId>),
    IgnorePair(NodeId, NodeId),
    Predicate { members: Vec<NodeId> },
}

impl RuleRepr {
    fn of(rule: &Rule) -> Self {
        match rule {
            Rule::IgnoreBetween(x, y) => RuleRepr::IgnoreBetween(x.clone(), y.clone()),
            Rule::IgnorePair(a, b) => RuleRepr::IgnorePair(*a, *b),
            Rule::Predicate { members, .. } => RuleRepr::Predicate {
                members: members.clone(),
            },
        }
    }

    /// The rule; a predicate gets a placeholder that `restore_with` always replaces
    /// before the layer is handed out.
    fn into_rule(self) -> Rule {
        match self {
            RuleRepr::IgnoreBetween(x, y) => Rule::IgnoreBetween(x, y),
            RuleRepr::IgnorePair(a, b) => Rule::IgnorePair(a, b),
            RuleRepr::Predicate { members } => Rule::Predicate {
                members,
                ignore: Arc::new(|_, _| false),
            },
        }
    }
}

fn write_rules<'a, S: Serializer>(
    rules: impl Iterator<Item = (&'a NodeId, &'a Rule)>,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    s.collect_seq(rules.map(|(n, r)| (*n, RuleRepr::of(r))))
}

fn read_rules<'de, D: Deserializer<'de>>(
    d: D,
) -> std::result::Result<impl Iterator<Item = (NodeId, Rule)>, D::Error> {
    let v = Vec::<(NodeId, RuleRepr)>::deserialize(d)?;
    Ok(v.into_iter().map(|(n, r)| (n, r.into_rule())))
}

/// `Logic::rules`: the rules with their nodes; predicates lose their closure.
pub(crate) mod rules {
    use super::*;

    pub(crate) fn serialize<S: Serializer>(
        rules: &BTreeMap<NodeId, Rule>,
        s: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        write_rules(rules.iter(), s)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<BTreeMap<NodeId, Rule>, D::Error> {
        let mut map = BTreeMap::new();
        for (n, r) in read_rules(d)? {
            if map.insert(n, r).is_some() {
                return Err(de::Error::custom(format!("rule {n:?} written twice")));
            }
        }
        Ok(map)
    }
}

/// `Logic::hooks`: the rule table (its index by node is rebuilt) and the contact
/// modifications.
pub(crate) mod layer_hooks {
    use super::*;
    use crate::logic::hooks::{ContactMods, LayerHooks};
    use crate::logic::RuleTable;

    struct Rules<'a>(&'a RuleTable);

    impl Serialize for Rules<'_> {
        fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
            write_rules(self.0.entries().iter().map(|(n, r)| (n, r)), s)
        }
    }

    struct ReadRules(Vec<(NodeId, Rule)>);

    impl<'de> Deserialize<'de> for ReadRules {
        fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
            Ok(ReadRules(read_rules(d)?.collect()))
        }
    }

    pub(crate) fn serialize<S: Serializer>(
        hooks: &LayerHooks,
        s: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        (Rules(&hooks.rules), &hooks.mods).serialize(s)
    }

    pub(crate) fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> std::result::Result<LayerHooks, D::Error> {
        let (rules, mods) = <(ReadRules, ContactMods)>::deserialize(d)?;
        let mut table = RuleTable::default();
        table.rebuild(rules.0.into_iter());
        Ok(LayerHooks { rules: table, mods })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_keep_everything_but_the_predicate() {
        let (a, b) = (NodeId::from_raw_parts(1, 0), NodeId::from_raw_parts(2, 0));
        for rule in [
            Rule::ignore_between(&[a], &[b]),
            Rule::ignore_pair(a, b),
            Rule::ignore_if(&[a], |_, _| true),
        ] {
            let back = RuleRepr::of(&rule).into_rule();
            assert_eq!(back.members(), rule.members());
            assert_eq!(format!("{back:?}"), format!("{rule:?}"));
        }
    }
}
