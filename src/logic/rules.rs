//! Logical rules (node kind `Rule`, paper §3.2): "ignore interactions between group X
//! and group Y", "ignore this pair", and a user predicate.
//!
//! A rule is applied twice, consistently:
//! - in Rapier, through `PhysicsHooks::filter_contact_pair` / `filter_intersection_pair`
//!   ([`RuleHooks`]), so an ignored pair gets no contact and no response;
//! - in the graph, as the paper's logical test of Fig. 4: an overlap a rule excludes is
//!   screened out before marking, so it makes no edge and no event.
//!
//! Hook flags go only on the colliders of the bodies a rule names: a flag anywhere else
//! would switch off Rapier's contact recycling for that collider and change results
//! (`docs/rapier-notes.md`). A scene without rules sets no flag at all.

use std::collections::HashMap;
use std::fmt;
use std::sync::Arc;

use crate::graph::{NodeId, PairBuildHasher};

/// A user predicate: returns `true` when the interaction of the two nodes must be
/// ignored. Called from inside Rapier's step (keep it cheap and pure).
pub type IgnorePredicate = Arc<dyn Fn(NodeId, NodeId) -> bool + Send + Sync>;

/// What a rule says.
#[derive(Clone)]
pub enum Rule {
    /// Ignore every interaction between a node of the first set and a node of the
    /// second (a node in both sets ignores the others of both).
    IgnoreBetween(Vec<NodeId>, Vec<NodeId>),
    /// Ignore the interaction of these two nodes.
    IgnorePair(NodeId, NodeId),
    /// Ignore the interactions of the member nodes for which the predicate says so
    /// (only pairs with at least one member are asked).
    Predicate {
        /// The nodes the predicate concerns (their colliders get the hook flags).
        members: Vec<NodeId>,
        /// The predicate.
        ignore: IgnorePredicate,
    },
}

impl fmt::Debug for Rule {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Rule::IgnoreBetween(x, y) => f.debug_tuple("IgnoreBetween").field(x).field(y).finish(),
            Rule::IgnorePair(a, b) => f.debug_tuple("IgnorePair").field(a).field(b).finish(),
            Rule::Predicate { members, .. } => f
                .debug_struct("Predicate")
                .field("members", members)
                .finish_non_exhaustive(),
        }
    }
}

impl Rule {
    /// "Ignore interactions between group X and group Y".
    pub fn ignore_between(x: &[NodeId], y: &[NodeId]) -> Self {
        Rule::IgnoreBetween(x.to_vec(), y.to_vec())
    }
    /// "Ignore this pair".
    pub fn ignore_pair(a: NodeId, b: NodeId) -> Self {
        Rule::IgnorePair(a, b)
    }
    /// A user predicate over the pairs involving `members`.
    pub fn ignore_if(
        members: &[NodeId],
        ignore: impl Fn(NodeId, NodeId) -> bool + Send + Sync + 'static,
    ) -> Self {
        Rule::Predicate {
            members: members.to_vec(),
            ignore: Arc::new(ignore),
        }
    }

    /// Every node the rule names, sorted, without repeats.
    pub fn members(&self) -> Vec<NodeId> {
        let mut v = match self {
            Rule::IgnoreBetween(x, y) => x.iter().chain(y.iter()).copied().collect(),
            Rule::IgnorePair(a, b) => vec![*a, *b],
            Rule::Predicate { members, .. } => members.clone(),
        };
        v.sort();
        v.dedup();
        v
    }

    /// Whether the rule ignores the interaction of `a` and `b`.
    pub fn ignores(&self, a: NodeId, b: NodeId) -> bool {
        match self {
            Rule::IgnoreBetween(x, y) => {
                (x.contains(&a) && y.contains(&b)) || (x.contains(&b) && y.contains(&a))
            }
            Rule::IgnorePair(p, q) => (a == *p && b == *q) || (a == *q && b == *p),
            Rule::Predicate { members, ignore } => {
                (members.contains(&a) || members.contains(&b)) && ignore(a, b)
            }
        }
    }
}

/// The rules in force, indexed for the hooks and the logical test. Rebuilt when rules
/// change (rare); read during every step.
#[derive(Clone, Default)]
pub struct RuleTable {
    rules: Vec<(NodeId, Rule)>,
    /// Node → indices into `rules` of the rules naming it.
    by_node: HashMap<NodeId, Vec<u32>, PairBuildHasher>,
}

impl fmt::Debug for RuleTable {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("RuleTable")
            .field("rules", &self.rules)
            .finish_non_exhaustive()
    }
}

impl RuleTable {
    pub(crate) fn rebuild(&mut self, rules: impl Iterator<Item = (NodeId, Rule)>) {
        self.rules = rules.collect();
        self.by_node.clear();
        for (i, (_, r)) in self.rules.iter().enumerate() {
            for n in r.members() {
                self.by_node.entry(n).or_default().push(i as u32);
            }
        }
    }

    /// The rules in force with their nodes, in table order (for a snapshot).
    #[cfg(feature = "serde")]
    pub(crate) fn entries(&self) -> &[(NodeId, Rule)] {
        &self.rules
    }

    /// The rules in force, to re-bind their predicates after a restore (the index by
    /// node does not change).
    #[cfg(feature = "serde")]
    pub(crate) fn entries_mut(&mut self) -> &mut [(NodeId, Rule)] {
        &mut self.rules
    }

    /// Whether no rule is in force.
    pub fn is_empty(&self) -> bool {
        self.rules.is_empty()
    }

    /// The number of rules in force.
    pub fn len(&self) -> usize {
        self.rules.len()
    }

    /// Whether some rule ignores the interaction of `a` and `b`. O(rules naming `a` or
    /// `b`); O(1) when neither is named.
    pub fn ignores(&self, a: NodeId, b: NodeId) -> bool {
        if self.rules.is_empty() {
            return false;
        }
        let check = |n: NodeId| {
            self.by_node
                .get(&n)
                .is_some_and(|idx| idx.iter().any(|&i| self.rules[i as usize].1.ignores(a, b)))
        };
        check(a) || check(b)
    }

    /// Whether a node is named by some rule. O(1).
    pub fn names(&self, n: NodeId) -> bool {
        self.by_node.contains_key(&n)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn n(i: u32) -> NodeId {
        NodeId::from_raw_parts(i, 0)
    }

    #[test]
    fn rule_semantics() {
        let r = Rule::ignore_between(&[n(1), n(2)], &[n(3)]);
        assert!(r.ignores(n(1), n(3)) && r.ignores(n(3), n(2)));
        assert!(!r.ignores(n(1), n(2)), "not within a set");
        let p = Rule::ignore_pair(n(4), n(5));
        assert!(p.ignores(n(5), n(4)) && !p.ignores(n(4), n(6)));
        let q = Rule::ignore_if(&[n(7)], |a, b| a.index() + b.index() == 15);
        assert!(q.ignores(n(7), n(8)) && !q.ignores(n(7), n(9)));
        assert!(!q.ignores(n(6), n(9)), "no member, not asked");
        assert_eq!(r.members(), vec![n(1), n(2), n(3)]);
    }

    #[test]
    fn table_indexes_rules_by_node() {
        let mut t = RuleTable::default();
        assert!(!t.ignores(n(1), n(3)));
        t.rebuild(vec![(n(100), Rule::ignore_between(&[n(1)], &[n(3)]))].into_iter());
        assert!(t.ignores(n(3), n(1)));
        assert!(!t.ignores(n(3), n(2)));
        assert!(t.names(n(1)) && !t.names(n(2)));
    }
}
