//! # Bad-input audit
//!
//! The project rule: *bad input gets a clear error and loses nothing — stale
//! handles, removed bodies, non-finite poses, rules naming unknown nodes, dropped
//! event receivers — and library code does not panic on user mistakes.* This page
//! lists every public entry point and what it does with each kind of bad input. Every
//! row names its tests in `tests/bad_input_audit.rs`. The audit found 14 bugs
//! (B1–B14, under [Findings](#findings)); all are fixed, and their `bug_*` tests run
//! as regression tests. The states on which Rapier 0.36.1 itself panics, and what the
//! layer does about each, are under [Rapier's own panics](#rapiers-own-panics).
//!
//! This module holds no code.
//!
//! ## Reading the table
//!
//! - **stale**: an id that was valid and is not any more (its node, edge or group was
//!   removed), or the handle of a body or collider removed from the world.
//! - **foreign**: an id or handle this layer or world never issued: the next generation
//!   of a live slot, a slot far past the end, Rapier's `invalid()` handle, a handle of
//!   another `PhysicsWorld`, an id of another layer. Rapier handles, [`NodeId`],
//!   [`EdgeId`](crate::EdgeId), [`GroupId`](crate::GroupId) and
//!   [`SubscriptionId`](crate::events::SubscriptionId) carry no world or layer
//!   identity, so a foreign one *with the same slot and generation* as a local one
//!   names the local object: **alias** below. That cannot be detected; every other
//!   foreign id behaves as a stale one.
//! - **non-finite**: NaN or ±∞ in an argument, in a [`WorldView`](crate::WorldView)
//!   (its fields are public), or injected into the world between steps (body pose,
//!   rotation, velocities, mass, gravity, `dt`, a static collider's pose).
//! - **out of range**: a finite value outside what the entry point accepts (zero,
//!   negative, huge, empty).
//! - **wrong time**: before the first step, between `pre_step` and Rapier's step, twice
//!   per step, or during a step (see [Wrong time](#wrong-time)).
//! - `Err(X)` stands for `Err(Error::X)` (see [`Error`](crate::Error)); such a call
//!   changes nothing. "—" means the entry point takes no such input.
//!
//! ## The table
//!
//! | entry point | stale id / handle | foreign handle | non-finite value | out-of-range parameter | wrong time | test |
//! |---|---|---|---|---|---|---|
//! | [`ContactLayer::step`] | removed body: its node and spans end, `UnknownBody` afterwards. a fixed or sleeping body (or a static collider) removed *and another inserted* before the same step: the node whose Rapier slot was reused goes at once, any other within `nodes / coherence::VERIFY_PER_STEP` steps (round-robin check), at once after `request_full_sync()` (B1: fixed) | another world: resynchronised by handle (alias), valid after the step | NaN/∞ pose, rotation, velocity, mass, gravity, static-collider pose: Rapier quarantines, the node is kept, `validate()` holds. `dt` NaN or ∞: no time passes for the timers (B2, B4: fixed) | `dt` = 0: zero-length step. `dt` < 0: no time passes for the timers (B3: fixed). `dt` = 100 or ∞: pairs of a body Rapier puts to sleep in its first step are read (B5: fixed) | `&mut self`: nothing can overlap it | `step_with_non_finite_state_and_foreign_worlds`, `bug_step_remove_and_insert_leaves_ghost_node`, `bug_nan_dt_stops_timers_forever`, `bug_negative_dt_runs_timers_backwards`, `bug_step_infinite_dt_with_timer_hangs`, `bug_step_huge_dt_misses_pairs` |
//! | [`ContactLayer::pre_step`] | queued changes of removed bodies skipped | a world without the bodies: skipped; the passive bodies and the joints it holds disabled are kept (nothing lost) | — | — | twice: idempotent. Changes decided at the last analysis are checked again against the world as it is now (see [Rapier's own panics](#rapiers-own-panics)) | `pre_step_with_a_foreign_world_and_twice`, `rapier_panics_joints_of_passive_bodies_are_held_disabled`, `rapier_panics_a_deferred_fixation_is_checked_again_when_applied` |
//! | [`ContactLayer::analyze`] | as `step` | a view mixing two worlds' parts: no panic, `validate_view` answers | view gravity NaN/∞: accepted (supports nothing); `dt` NaN, ∞, < 0: as `step` (B2–B4) | `dt` = 0: accepted | twice per Rapier step: counted as two steps (timers advance 2·`dt`); one call per step is the contract, a view cannot tell | `analyze_with_odd_views` |
//! | [`ContactLayer::hooks`] | — | — | — | — | while a Rapier step borrows them, `&mut` calls do not compile; `&self` queries from a Rapier `EventHandler` see the last analysis, consistent | `wrong_time_queries_during_a_rapier_step_see_the_last_analysis`, compile-fail example below |
//! | [`ContactLayer::set_speedups`], [`ContactLayer::speedups`] | — | — | NaN/∞ parameter: `Err(InvalidParameter)` naming it; the configuration in force is kept | negative; `sleepy_steps`, `iterations`, `tweak_iterations` = 0: `Err(InvalidParameter)`. 0 thresholds and `f32::MAX` accepted; no upper bound on iteration counts (Rapier has none) | any time between steps; `None` twice: no-op | `set_speedups_refuses_bad_parameters` |
//! | [`ContactLayer::set_monitor`], [`ContactLayer::monitor`], [`ContactLayer::mark_pushed`], [`ContactLayer::prime_monitor`], [`ContactLayer::holds`] | `mark_pushed` / `holds` with a removed body: ignored / `false` | alias | NaN/∞ threshold or repair parameter: `Err(InvalidParameter)` naming it; the monitor in force is kept | `corrective_cap` ≤ 0, `penetration_warning` outside (0, 1], `fast_travel` < 0, `min_support_cos` ≥ 1: `Err(InvalidParameter)` | any time between steps; `prime_monitor` / `mark_pushed` with the monitor off: no-op; `Off` twice: no-op | `monitor_entry_points_take_bad_input` |
//! | [`ContactLayer::subscribe`], [`ContactLayer::subscribe_with_id`] | filter naming stale nodes: accepted, never matches (no error channel) | alias | — | `KindSet::NONE`, empty node list: accepted, never matches | events arrive after the step | `subscribe_with_stale_or_foreign_nodes_matches_nothing` |
//! | [`ContactLayer::subscribe_bounded`] | a stale-node filter: `Err(StaleNode)` (B6: fixed) | alias | — | 0: `Err(InvalidParameter)`. above `events::MAX_CAPACITY` (2²⁴): `Err(InvalidParameter)` (B7: fixed) | events arrive after the step | `subscribe_bounded_zero_capacity_is_an_error`, `bug_subscribe_bounded_accepts_stale_node_filter`, `bug_subscribe_bounded_huge_capacity_panics` |
//! | [`ContactLayer::unsubscribe`], [`ContactLayer::event_bus`] | twice, or after pruning: `false`, `dropped_for` → `None` | another layer's id: alias (may remove a local subscription) | — | — | dropped receiver: pruned at the next delivery, the step never blocks | `unsubscribe_and_dropped_receivers` |
//! | [`ContactLayer::add_rule`] | `Err(StaleNode)`; a member removed later: the rule stays valid and removable | other generation, past the end: `Err(StaleNode)`; alias | — | no member: `Err(InvalidParameter)`; a timer or rule as member: `Err(WrongKind)`; repeats deduplicated | added between `pre_step` and Rapier's step: applied at the next `pre_step`; a predicate runs inside Rapier's step, is `'static`, gets node ids only and sees earlier steps' events only | `add_rule_refuses_unknown_nodes`, `wrong_time_changes_between_pre_step_and_rapier_step_wait_for_the_next_pre_step`, `wrong_time_a_rule_predicate_runs_inside_the_step_and_sees_only_earlier_events` |
//! | [`ContactLayer::remove_rule`], [`ContactLayer::rule`] | `Err(StaleNode)` (twice too) / `None` | `Err(StaleNode)` / `None` | — | not a rule: `Err(WrongKind)` / `None` | between steps | `remove_rule_and_rule_with_stale_ids` |
//! | [`ContactLayer::add_timer`] | — | — | NaN, ±∞: `Err(InvalidParameter)` | 0, negative: `Err(InvalidParameter)`; `f64::MAX`: never ticks. below `logic::MIN_TIMER_PERIOD` (1e-6 s): `Err(InvalidParameter)`; at most 10,000 ticks reported per step (B4: fixed) | any time | `add_timer_refuses_bad_periods`, `bug_tiny_timer_period_hangs_next_step` |
//! | [`ContactLayer::remove_timer`], [`ContactLayer::timer_ticks`], [`ContactLayer::timer_period`] | `Err(StaleNode)` (twice too) | `Err(StaleNode)` | — | not a timer: `Err(WrongKind)` | any time | `timer_queries_with_stale_and_wrong_ids` |
//! | [`ContactLayer::simulated_time`] | — | — | unchanged by a NaN `dt` (B2: fixed) | unchanged by `dt` ≤ 0 (B3: fixed) | — | `bug_nan_dt_stops_timers_forever`, `bug_negative_dt_runs_timers_backwards` |
//! | [`ContactLayer::set_passive`] | removed and analysed: `Err(UnknownBody)`; removed from the world but not analysed yet: `Ok`, no effect | `Err(UnknownBody)`; alias | — | `true` on a multibody link (`Link` node): `Err(Unsupported)`, nothing changes (Rapier panics on a disabled multibody member); `false`: always accepted | before the first step: `Err(UnknownBody)` ("not seen by the layer yet"). joined to a multibody between the call and the pre-step: refused there, reported by `refusals()`; joined after being made passive: made active again, reported | `set_passive_with_stale_foreign_and_removed_bodies`, `wrong_time_calls_before_the_first_step`, `rapier_panics_set_passive_on_a_multibody_member_is_refused`, `rapier_panics_a_passive_body_joined_to_a_multibody_is_made_active_again` |
//! | [`ContactLayer::refusals`] | — | — | — | — | empty on a fresh layer; lists what the last pre-step refused or undid, cleared by the next | `accessors_on_a_fresh_layer_and_error_messages`, `rapier_panics_set_passive_on_a_multibody_member_is_refused` |
//! | [`ContactLayer::declare_composite`], [`ContactLayer::remove_composite`] | `Err(StaleNode)` (removing twice too); a member removed later: the composite stays valid and removable | `Err(StaleNode)`; alias | — | empty: `Err(InvalidParameter)`; fixed body or timer member, or removing what is not a declared composite: `Err(WrongKind)`; repeats: one edge | between steps | `composites_with_stale_wrong_and_removed_members` |
//! | [`ContactLayer::node_of_body`], [`ContactLayer::kind_of`], [`ContactLayer::is_supported`], [`ContactLayer::insulates`] | `Err(UnknownBody)` / `Err(StaleNode)` / `Err(StaleNode)` / `false` | the same; alias | NaN gravity of the last analysed world: `is_supported` → `Ok(false)` | — | before the first step: `Err(UnknownBody)`; contact details off: `is_supported` → `Ok(false)` (documented: no normals) | `layer_node_queries_with_bad_ids`, `settings_at_any_time`, `wrong_time_calls_before_the_first_step` |
//! | [`ContactLayer::node_of_collider`] | removed: `Err(UnknownCollider)` | other generation, past the end, `invalid()`: `Err(UnknownCollider)`; a world the layer never saw: its collider's parent is looked up (`Err(UnknownBody)` or alias) | — | parentless sensor: its trigger node (B8: fixed) | answers from the last analysis | `node_of_collider_with_bad_handles`, `bug_node_of_collider_parentless_sensor` |
//! | [`ContactLayer::validate`], [`ContactLayer::validate_view`] | — | a world the layer never saw: `Err(Invariant)` | view gravity, `dt` NaN: not used | — | before the first step: `Err(Invariant)` | `validate_against_a_foreign_world_is_an_error`, `wrong_time_calls_before_the_first_step` |
//! | `ContactLayer::snapshot`, `ContactLayer::restore`, `ContactLayer::restore_with` (feature `serde`) | a world lacking a body or collider the snapshot's graph stands for: `Err(SnapshotMismatch)` naming it (unless the saved world lacked it too: the next step drops the node, as the original's would) | another world, or the same world at another step: `Err(SnapshotMismatch)`; bytes of another snapshot format, or not a snapshot: the deserialiser's error, with `SnapshotFormat`'s message | NaN/∞ in the world: stamped by bits, so only the same world matches | truncated or corrupted bytes: the deserialiser's error, or `Err(Invariant)` for a state that decodes but is inconsistent, never a panic; a predicate rule not given back: `Err(UnboundPredicate)` naming it | between any two of the layer's calls; the restored layer has no subscriptions; the snapshot is borrowed and kept on error | in `tests/snapshot_restore.rs`: `restoring_against_the_wrong_world_is_an_error`, `a_snapshot_of_another_format_or_not_a_snapshot_is_an_error`, `truncated_snapshots_are_errors_not_panics`, `corrupted_snapshots_are_refused_or_restore_a_layer_that_steps_without_panicking`, `a_predicate_rule_needs_its_predicate_given_back` |
//! | [`ContactLayer::set_contact_details`], [`ContactLayer::request_full_sync`], [`ContactLayer::set_trigger_widening`], [`Coherence::set_scan_policy`](crate::coherence::Coherence::set_scan_policy) via [`ContactLayer::coherence_mut`] | — | — | — | — | any time, repeated: `validate()` holds after each step | `settings_at_any_time` |
//! | accessors: [`ContactLayer::new`], `default`, `graph`, `groups`, `stats`, `current_step`, `touched_edges`, `removed_edges`, `removed_nodes`, `coherence`, `grouping`, `last_events`, `flagged_colliders`; [`Error`](crate::Error)'s messages | — | — | — | — | valid on a fresh layer | `accessors_on_a_fresh_layer_and_error_messages` |
//! | [`ContactGraph::node`], [`ContactGraph::try_node`], [`ContactGraph::contains_node`], [`ContactGraph::node_id_at`] | `None` / `Err(StaleNode)` / `false`, also once the slot is reused | the same | — | `node_id_at(u32::MAX)`: `None` | — | `graph_node_lookups_with_bad_ids` |
//! | [`ContactGraph::node_of_body`], [`ContactGraph::try_node_of_body`] | removed: `None` / `Err(UnknownBody)` | other generation, past the end, `invalid()`: the same; alias | — | — | — | `graph_body_lookups_with_bad_handles` |
//! | [`ContactGraph::node_of_static_collider`], [`ContactGraph::node_of_sensor`] | removed: `None` | `None`; a collider of the other kind, or attached to a body: `None` | — | — | — | `graph_collider_lookups_with_bad_handles` |
//! | [`ContactGraph::body_of`], [`ContactGraph::try_body_of`] | `None` / `Err(StaleNode)` | the same | — | a node that is no body: `None` / `Err(WrongKind)` | — | `graph_body_of_with_bad_ids` |
//! | [`ContactGraph::edge`], [`ContactGraph::try_edge`], [`ContactGraph::edge_by_key`], [`Edge::other`](crate::Edge::other), [`Edge::proximity_mark`](crate::Edge::proximity_mark) | removed edge: `None` / `Err(StaleEdge)` | the same; any `PairKey`: `None`; `other` of a foreign node: `None` | — | any step index: `None` | — | `graph_edge_lookups_with_bad_ids` |
//! | [`ContactGraph::edge_between`], [`ContactGraph::try_edge_between`], [`ContactGraph::edge_of_bodies`] | `None` / `Err(StaleNode)`, also once the slot is reused | the same; alias | — | a node with itself: `None` / `Ok(None)` | — | `graph_edge_between_with_bad_ids` |
//! | [`ContactGraph::neighbors`], [`ContactGraph::touching`] | empty | empty | — | — | — | `graph_neighbors_and_touching_with_bad_ids` |
//! | [`ContactGraph::try_is_supported`] | `Err(StaleNode)` | `Err(StaleNode)` | NaN/∞ gravity, NaN `min_cos`: `Err(NonFinite)` (B9: fixed) | zero gravity: `Ok(false)` (documented). any finite non-zero \|g\|: answered, scaled before normalising (B10: fixed). `min_cos` outside \[-1, 1\] not checked | — | `graph_try_is_supported_with_bad_input`, `bug_try_is_supported_non_finite_input_is_not_an_error`, `bug_try_is_supported_huge_or_tiny_gravity` |
//! | [`ContactGraph::supports_of`] | empty | empty | NaN `up` or `min_cos`: empty (an iterator: no error channel) | a zero or non-unit `up`: not checked (documented: must be a unit vector) | — | `graph_supports_of_with_bad_input` |
//! | [`ContactGraph::new`], [`ContactGraph::to_petgraph`], [`ContactGraph::validate`], `nodes`, `nodes_of_kind`, `edges`, counts; [`aabbs_obsolete`](crate::coherence::aabbs_obsolete) | — | — | NaN boxes: never obsolete | empty graph | — | `graph_whole_graph_calls_on_empty_and_used_graphs` |
//! | [`Groups::get`](crate::Groups::get), `iter`, `stats`, [`GroupStats::mean_variables`](crate::GroupStats::mean_variables), [`Node::group`](crate::Node::group) | dissolved group: `None` | another layer's id: alias | — | no groups: mean 0 | — | `groups_get_with_stale_group_id` |
//! | [`Filter::with_nodes`](crate::Filter::with_nodes), `Filter::all`, `kinds`, `or_kind`, [`KindSet::of`](crate::KindSet::of) | kept; never match (see `subscribe`) | alias | — | empty list: matches nothing; repeats deduplicated | — | `filter_builders_accept_anything` |
//! | [`Rule`](crate::Rule) constructors, `members`, `ignores`; [`RuleTable::ignores`](crate::logic::RuleTable::ignores), `names`; [`ContactMods::is_sleepy`](crate::hooks::ContactMods::is_sleepy) | not matched: `false` | `false` | — | repeats deduplicated | — | `rule_values_with_stale_nodes` |
//! | [`SpeedUps::validate`](crate::speedups::SpeedUps::validate), `combination` | — | — | NaN/±∞: `Err(InvalidParameter)` | negative; 0 steps or iterations: `Err(InvalidParameter)`; bits above the seven switches ignored | — | `speedups_validate` |
//! | [`SpeedUpState::is_sleepy`](crate::speedups::SpeedUpState::is_sleepy), `is_fixated`, `fixated`, `stats` | `false` | `false` | — | — | — | `speedup_state_queries_with_foreign_handles` |
//! | [`MonitorConfig::validate`](crate::monitor::MonitorConfig::validate), [`Monitor::new`](crate::monitor::Monitor::new) | — | — | NaN/∞: `Err(InvalidParameter)` naming the field | negative; `min_support_cos` ≥ 1: `Err(InvalidParameter)` | — | `monitor_config_validate` |
//! | [`Monitor::check`](crate::monitor::Monitor::check), `check_with_quarantine`, `prime`, `prime_body` | handles the world lacks: skipped (`prime`: no effect) | a world the layer never saw (empty; NaN poses, ∞ velocities, NaN gravity): no panic; quarantine reports of handles the world lacks: taken as given, an escape with `node: None` | NaN gravity: nothing hangs; non-finite energies: skipped | — | before the first step: nothing found; twice per step: documented (no time passes) | `monitor_check_with_a_world_the_layer_never_saw`, `wrong_time_calls_before_the_first_step` |
//! | [`measure::deviation`](crate::measure::deviation) | — | — | non-finite positions skipped; NaN `radius`: NaN | empty or mismatched: compared where they overlap, NaN if nothing is; `radius` 0: ∞; negative: its absolute value (no error channel) | — | `deviation_with_empty_mismatched_and_bad_radius` |
//! | [`measure::run`](crate::measure::run), `RunSpec` constructors | — | body handles the scene lacks: sampled as NaN, counted as having left the region | NaN monitor or speed-up parameter: `Err(InvalidParameter)` | `sample_every` = 0, `Mode::Plain { iterations: 0 }`, a radius not finite and positive: `Err(InvalidParameter)`; `steps` = `u64::MAX`: no up-front allocation (B11: fixed); `steps` = 0: accepted | — | `measure_run_refuses_bad_configs`, `bug_measure_run_sample_every_zero_panics`, `bug_measure_run_huge_step_count_panics`, `bug_measure_run_plain_zero_iterations_accepted` |
//! | [`report::pareto_front`](crate::report::pareto_front) | — | — | NaN/∞ points: not candidates | empty: empty; `u64::MAX` violations; ties all kept | — | `pareto_front_with_nan_and_empty` |
//! | [`report::svg`](crate::report::svg), [`report::png`](crate::report::png) | — | — | NaN/±∞, `f64::MAX`, subnormal coordinates: left out or clamped | empty: "no data"; sizes clamped; odd text escaped. subnormal ranges: widened to a unit (B12: fixed) | — | `charts_with_nan_empty_and_extreme_input`, `bug_chart_negative_subnormal_panics` |
//! | [`report::frames`](crate::report::frames): `Camera::with_bounds`, `View::tilted`, `Classifier::with_rest_speed`, `Classifier::shade`, `Renderer::render`, `Frame::write_png` | removed body: `shade` → `Fixed` | any handle: `Fixed`; as scenery: ignored | NaN/∞ bounds or angles: `Err(NonFinite)`; NaN rest speed: `Err(InvalidParameter)`; colliders with NaN poses: left out, counted in `skipped()`; huge poses: drawn off the frame | sizes clamped to 160..=8192; bounds `mins > maxs`, negative rest speed: `Err(InvalidParameter)`; flat, tiny or huge bounds accepted; half-spaces not drawn (counted); long or non-ASCII captions shrunk, cut, `?` for unknown glyphs; a missing directory: `io::Error` | — | `frames_with_bad_bounds_views_handles_and_geometry` |
//! | [`export::dot::to_dot`](crate::export::dot::to_dot), `graph_to_dot`, `escape` | — | — | — | empty layer or graph; labels with quotes, backslashes, line breaks: escaped | — | `dot_export_on_empty_and_odd_labels` |
//! | [`export::text::describe`](crate::export::text::describe) | — | — | — | empty layer; odd labels | — | `text_export_on_empty_layer` |
//! | [`scenes`](crate::scenes) constructors and helpers | — | — | NaN radius or incline: built | 0 spheres: built; `usize::MAX` in the size helpers: answered. step index `u64::MAX`: saturates (B13: fixed) | — | `scenes_with_degenerate_parameters`, `bug_scenes_step_index_overflow_panics` |
//!
//! ## Wrong time
//!
//! Calling into the layer *during* a step is impossible by construction, so no row has
//! a "during the step" case to handle:
//!
//! 1. [`ContactLayer::step`] takes the layer as `&mut self` for the whole step: nothing
//!    else can call it meanwhile.
//! 2. A user who steps Rapier alone passes [`ContactLayer::hooks`], a shared borrow of
//!    the layer, for Rapier's whole step. While it is borrowed, every `&mut self`
//!    method is a compile error:
//!
//!    ```compile_fail,E0502
//!    use rapier3d::prelude::*;
//!    use rapier_contact_graph::{ContactLayer, WorldMut, WorldView};
//!
//!    let mut world = PhysicsWorld::new();
//!    let mut layer = ContactLayer::new();
//!    layer.pre_step(WorldMut::from(&mut world));
//!    let hooks = layer.hooks();
//!    layer.add_timer(1.0).unwrap(); // error: `layer` is borrowed by `hooks`
//!    world.step_with_events(&hooks, &());
//!    layer.analyze(WorldView::from(&world));
//!    ```
//!
//!    `&self` queries remain possible from user code Rapier runs during its step (an
//!    `EventHandler` holding `&ContactLayer`); they read the last analysis, which is
//!    complete and consistent.
//! 3. Rapier calls the hooks through `&LayerHooks` only, which exposes nothing but
//!    read access to the rules and contact modifications. The only user code they run
//!    is a [`Rule::ignore_if`](crate::Rule::ignore_if) predicate, which is
//!    `'static + Send + Sync` and receives [`NodeId`]s: it cannot borrow the layer.
//!
//!    ```compile_fail,E0373
//!    use rapier_contact_graph::{ContactLayer, NodeId, Rule};
//!
//!    let layer = ContactLayer::new();
//!    let n = NodeId::from_raw_parts(0, 0);
//!    // error: the predicate must be 'static, so it cannot borrow the layer
//!    let rule = Rule::ignore_if(&[n], |a, _| layer.graph().node(a).is_none());
//!    ```
//!
//! 4. Events are sent at the end of the analysis (the paper's safe point), never from
//!    inside Rapier's step: a receiver read anywhere, even from a predicate, sees the
//!    events of finished steps only.
//!
//! What remains possible is calling at an *unexpected* time between steps, and each
//! case is well defined (tested in the `wrong_time_*` tests and the rows above):
//! before the first step the world's bodies are unknown (`UnknownBody`, "not seen by
//! the layer yet"); changes made between `pre_step` and Rapier's step take effect at
//! the next `pre_step`; a body removed from the world is known to the layer until its
//! next analysis; `analyze` called twice for one Rapier step counts two steps (the
//! contract is one call per step, and a `WorldView` carries nothing to tell).
//!
//! For a user who drives Rapier alone the correct order compiles:
//!
//! ```
//! use rapier3d::prelude::*;
//! use rapier_contact_graph::{ContactLayer, WorldMut, WorldView};
//!
//! let mut world = PhysicsWorld::new();
//! let mut layer = ContactLayer::new();
//! layer.pre_step(WorldMut::from(&mut world));
//! let hooks = layer.hooks();
//! world.step_with_events(&hooks, &());
//! layer.analyze(WorldView::from(&world));
//! layer.add_timer(1.0).unwrap(); // between steps: fine
//! ```
//!
//! ## Findings
//!
//! Status: all fixed in the session that found them. B1 is fixed in two parts: a node
//! whose Rapier slot is taken by a newer object is removed at once, and a round-robin
//! check of a few nodes and slots per step finds the rest within
//! `nodes / VERIFY_PER_STEP` steps; [`ContactLayer::request_full_sync`] makes it
//! immediate. The descriptions below are of the bugs as found.
//!
//! Bugs found by this audit (each has a `bug_*` regression test):
//!
//! - **B1, removed bodies stay in the graph.** Removing a body that is not awake
//!   (fixed, sleeping, disabled) or a static collider, and inserting another one before
//!   the same step, keeps the counts unchanged, so no full scan runs
//!   (`coherence::Coherence::update`, the `counts_changed` test), and nothing refreshes
//!   the removed body. Its node stays for good: it is never reported in
//!   `removed_nodes()`, a sleeping body's spans never end (no `TouchEnd`, against the
//!   events contract), `ContactGraph::validate()` fails, and a static collider inserted
//!   into the freed slot never gets a node. Despawn-and-spawn in one frame is common.
//!   Workaround: `request_full_sync()` after removing bodies.
//!   Test: `bug_step_remove_and_insert_leaves_ghost_node`.
//! - **B2, one NaN `dt` stops every timer for good.** The timers' clock is
//!   `base + n·dt`; a NaN `dt` makes it NaN, and the next `dt` change copies the NaN
//!   into `base` (`logic/timers.rs`, `Timers::advance`). No timer ticks again and
//!   `simulated_time()` stays NaN. Rapier itself moves nothing in a NaN step.
//!   Test: `bug_nan_dt_stops_timers_forever`.
//! - **B3, a negative `dt` runs the timers' clock backwards.** Rapier treats `dt ≤ 0` as
//!   a zero-length step; the timers subtract it, so every timer is late from then on.
//!   Test: `bug_negative_dt_runs_timers_backwards`.
//! - **B4, a step can hang.** `Timers::advance` fires every tick a step covers in one
//!   loop (`while elapsed + slack >= (ticks + 1) · period`), pushing each into a vector.
//!   With `dt` = ∞ the loop never ends; with a tiny period accepted by `add_timer`
//!   (1e-300) it effectively never ends. Memory grows until the allocator gives up
//!   (4 GiB in the test's child process). Tests: `bug_step_infinite_dt_with_timer_hangs`,
//!   `bug_tiny_timer_period_hangs_next_step`.
//! - **B5, a huge `dt` loses pairs.** With `dt` = 100 or ∞ Rapier puts a new body to
//!   sleep in its first step. The analysis refreshes only bodies awake now or at its last
//!   update, and nodes created in a step are not walked, so the pair of that body with
//!   a fixed one never gets an edge; `validate()` fails until the body wakes.
//!   Test: `bug_step_huge_dt_misses_pairs`.
//! - **B6, `subscribe_bounded` accepts a filter naming stale nodes.** It returns a
//!   `Result` but never checks the filter's nodes, which can never match again
//!   (`subscribe` has no error channel). Test: `bug_subscribe_bounded_accepts_stale_node_filter`.
//! - **B7, `subscribe_bounded(f, usize::MAX)` panics** in crossbeam ("bounded channel
//!   capacity is too large"); a capacity of 2⁴⁰ would abort allocating the buffer,
//!   since crossbeam allocates a bounded channel's slots up front (`events/bus.rs`).
//!   Test: `bug_subscribe_bounded_huge_capacity_panics`.
//! - **B8, `node_of_collider` on a parentless sensor** returns `UnknownCollider`,
//!   though its docs promise "its parent body's node, or its own for a parentless
//!   collider" and `ContactGraph::node_of_sensor` finds the trigger node. Test:
//!   `bug_node_of_collider_parentless_sensor`.
//! - **B9, `try_is_supported` answers `Ok(false)` for NaN or infinite gravity and a
//!   NaN `min_cos`** instead of `Err(NonFinite)`, though it returns a `Result`.
//!   Test: `bug_try_is_supported_non_finite_input_is_not_an_error`.
//! - **B10, `try_is_supported` with a huge or tiny finite gravity** says "not
//!   supported": `gravity.length()` squares in `f32`, which overflows above ~1.8e19
//!   and underflows below ~1e-23 (`graph/mod.rs`). Test:
//!   `bug_try_is_supported_huge_or_tiny_gravity`.
//! - **B11, `measure::run` panics on its options.** `sample_every` = 0 divides by
//!   zero (`(step + 1) % opts.sample_every`); `steps` = `u64::MAX` overflows the
//!   per-step vectors' preallocation ("capacity overflow"). Both should be
//!   `Err(InvalidParameter)`, as `Mode::Plain { iterations: 0 }` should be (the
//!   speed-ups refuse 0 iterations). Tests: `bug_measure_run_sample_every_zero_panics`,
//!   `bug_measure_run_huge_step_count_panics`, `bug_measure_run_plain_zero_iterations_accepted`.
//! - **B12, the charts panic on a negative subnormal.** For a range `[-5e-324, 0]`,
//!   `widen` (`report/chart.rs`) computes `|lo| · 0.5`, which underflows to 0, so the
//!   span stays 5e-324; `nice_ticks` then gets a zero step and collects the ticks of
//!   `i64::MIN..=0` ("capacity overflow"). The module promises "nothing here panics on
//!   data". Test: `bug_chart_negative_subnormal_panics`.
//! - **B13, step indices near `u64::MAX` overflow** in the scenes (debug builds panic):
//!   `kinematic_platform::platform_x_after` (`step + 1`), `Scene::run_plain`
//!   (`first + n`) and the kinematic platform's script. Test:
//!   `bug_scenes_step_index_overflow_panics`.
//! - **B14 (incidental, not bad input): a predicate rule is not applied by Rapier to
//!   pairs with a non-member.** `RuleTable::ignores_pair` (`logic/rules.rs`) returns
//!   `false` when one side of a pair is not named by any rule, without asking the
//!   predicate, while the graph's logical test asks it. A predicate "ignore everything
//!   the ball touches" with the ball as its only member lets the ball rest on the
//!   ground in Rapier while the graph screens the pair out. Test:
//!   `bug_incidental_predicate_rule_with_a_non_member`.
//!
//! Not bugs of this crate:
//! - Rapier 0.36.1 with `dt` NaN moves nothing; with `dt` ≤ 0 it runs a zero-length
//!   step; with `dt` = ∞ or 100 it puts new bodies to sleep at once; non-finite body
//!   or collider state is quarantined (reset and disabled). None of it panics.
//! - Random sequences of impulse joints, body-type changes and removals make Rapier
//!   0.36.1 panic (`dynamics/solver/interaction_groups.rs:153`) without the layer:
//!   see the next section for the states behind it.
//!
//! ## Rapier's own panics
//!
//! Rapier 0.36.1 panics in its step on a few world states that ordinary calls reach,
//! with or without the layer (each was reproduced with plain Rapier and
//! `RigidBody::set_enabled`). The layer must not be the one to reach them: where its
//! own calls would (it disables passive bodies and fixates bodies by making them
//! fixed), it refuses or guards, with a clear [`Error::Unsupported`] where a call is
//! refused. Where only the user's own calls into Rapier reach them, the layer cannot
//! step in, and plain Rapier panics the same way. Found by the operation fuzzing
//! (`tests/fuzz_operations.rs`, whose `fixed_*` regression tests replay each case).
//!
//! | state Rapier panics on (where) | reached through the layer by | what the layer does | test |
//! |---|---|---|---|
//! | a disabled multibody member the solver needs (the root, or the first link under a fixed root) while other links are enabled: "Matrix slicing out of bounds" or "LU solve matrix dimension mismatch" (contact solver, `GenericRhs::apply_impulse`; Rapier does not propagate `set_enabled` to multibodies, a `FIXME` in its `user_changes.rs`) | `set_passive(true)` on a multibody member; a passive body the user joins to a multibody | `set_passive(true)` on a `Link` node: `Err(Unsupported)`. The pre-step refuses a queued change for a body that became a dynamic multibody member meanwhile, and makes a passive body the user joined to a multibody active again; both are listed by [`ContactLayer::refusals`] | `rapier_panics_set_passive_on_a_multibody_member_is_refused`, `rapier_panics_a_passive_body_joined_to_a_multibody_is_made_active_again` |
//! | an enabled impulse joint between a disabled body and a fixed or disabled one: "entered unreachable code" (`interaction_groups.rs:153`). Rapier marks a body's joints `DisabledByAttachedBody` when it disables the body, but not a joint added later, and it enables every such joint of a body it inserts or enables, whatever the other end | a joint the user adds to a passive body (or a body inserted or enabled while jointed to one) | the pre-step holds every joint of a passive body disabled (`JointEnabled::Disabled`, which Rapier never changes) and enables it again once both its bodies are active; a joint the user disabled stays disabled | `rapier_panics_joints_of_passive_bodies_are_held_disabled` |
//! | a multibody link other than the root that is not dynamic: "A rigid-body that is not at the root of a multibody must be dynamic" (`multibody.rs`) | fixation (speed-ups), decided at the analysis and applied at the next pre-step, of a body the user joined to a multibody meanwhile; a held (fixed) body the user joins as a link | the pre-step checks a fixation again when it applies it (dynamic, enabled, no multibody member), and releases a held body joined as a link before Rapier's step | `rapier_panics_a_deferred_fixation_is_checked_again_when_applied` |
//! | the same states reached by the user's own calls: a body disabled with `RigidBody::set_enabled(false)` or quarantined by Rapier (non-finite state), then jointed or joined to a multibody; a multibody link made fixed or kinematic | — (not the layer's calls) | nothing: plain Rapier panics the same way. Disable bodies with `set_passive` instead, which guards them | documented; the fuzz harness avoids them |
//!
//! [`ContactLayer::step`]: crate::ContactLayer::step
//! [`ContactLayer::pre_step`]: crate::ContactLayer::pre_step
//! [`ContactLayer::analyze`]: crate::ContactLayer::analyze
//! [`ContactLayer::hooks`]: crate::ContactLayer::hooks
//! [`ContactLayer::set_speedups`]: crate::ContactLayer::set_speedups
//! [`ContactLayer::speedups`]: crate::ContactLayer::speedups
//! [`ContactLayer::set_monitor`]: crate::ContactLayer::set_monitor
//! [`ContactLayer::monitor`]: crate::ContactLayer::monitor
//! [`ContactLayer::mark_pushed`]: crate::ContactLayer::mark_pushed
//! [`ContactLayer::prime_monitor`]: crate::ContactLayer::prime_monitor
//! [`ContactLayer::holds`]: crate::ContactLayer::holds
//! [`ContactLayer::subscribe`]: crate::ContactLayer::subscribe
//! [`ContactLayer::subscribe_with_id`]: crate::ContactLayer::subscribe_with_id
//! [`ContactLayer::subscribe_bounded`]: crate::ContactLayer::subscribe_bounded
//! [`ContactLayer::unsubscribe`]: crate::ContactLayer::unsubscribe
//! [`ContactLayer::event_bus`]: crate::ContactLayer::event_bus
//! [`ContactLayer::add_rule`]: crate::ContactLayer::add_rule
//! [`ContactLayer::remove_rule`]: crate::ContactLayer::remove_rule
//! [`ContactLayer::rule`]: crate::ContactLayer::rule
//! [`ContactLayer::add_timer`]: crate::ContactLayer::add_timer
//! [`ContactLayer::remove_timer`]: crate::ContactLayer::remove_timer
//! [`ContactLayer::timer_ticks`]: crate::ContactLayer::timer_ticks
//! [`ContactLayer::timer_period`]: crate::ContactLayer::timer_period
//! [`ContactLayer::simulated_time`]: crate::ContactLayer::simulated_time
//! [`ContactLayer::set_passive`]: crate::ContactLayer::set_passive
//! [`ContactLayer::refusals`]: crate::ContactLayer::refusals
//! [`Error::Unsupported`]: crate::Error::Unsupported
//! [`ContactLayer::declare_composite`]: crate::ContactLayer::declare_composite
//! [`ContactLayer::remove_composite`]: crate::ContactLayer::remove_composite
//! [`ContactLayer::node_of_body`]: crate::ContactLayer::node_of_body
//! [`ContactLayer::kind_of`]: crate::ContactLayer::kind_of
//! [`ContactLayer::is_supported`]: crate::ContactLayer::is_supported
//! [`ContactLayer::insulates`]: crate::ContactLayer::insulates
//! [`ContactLayer::node_of_collider`]: crate::ContactLayer::node_of_collider
//! [`ContactLayer::validate`]: crate::ContactLayer::validate
//! [`ContactLayer::validate_view`]: crate::ContactLayer::validate_view
//! [`ContactLayer::set_contact_details`]: crate::ContactLayer::set_contact_details
//! [`ContactLayer::request_full_sync`]: crate::ContactLayer::request_full_sync
//! [`ContactLayer::set_trigger_widening`]: crate::ContactLayer::set_trigger_widening
//! [`ContactLayer::coherence_mut`]: crate::ContactLayer::coherence_mut
//! [`ContactLayer::new`]: crate::ContactLayer::new
//! [`ContactGraph::node`]: crate::ContactGraph::node
//! [`ContactGraph::try_node`]: crate::ContactGraph::try_node
//! [`ContactGraph::contains_node`]: crate::ContactGraph::contains_node
//! [`ContactGraph::node_id_at`]: crate::ContactGraph::node_id_at
//! [`ContactGraph::node_of_body`]: crate::ContactGraph::node_of_body
//! [`ContactGraph::try_node_of_body`]: crate::ContactGraph::try_node_of_body
//! [`ContactGraph::node_of_static_collider`]: crate::ContactGraph::node_of_static_collider
//! [`ContactGraph::node_of_sensor`]: crate::ContactGraph::node_of_sensor
//! [`ContactGraph::body_of`]: crate::ContactGraph::body_of
//! [`ContactGraph::try_body_of`]: crate::ContactGraph::try_body_of
//! [`ContactGraph::edge`]: crate::ContactGraph::edge
//! [`ContactGraph::try_edge`]: crate::ContactGraph::try_edge
//! [`ContactGraph::edge_by_key`]: crate::ContactGraph::edge_by_key
//! [`ContactGraph::edge_between`]: crate::ContactGraph::edge_between
//! [`ContactGraph::try_edge_between`]: crate::ContactGraph::try_edge_between
//! [`ContactGraph::edge_of_bodies`]: crate::ContactGraph::edge_of_bodies
//! [`ContactGraph::neighbors`]: crate::ContactGraph::neighbors
//! [`ContactGraph::touching`]: crate::ContactGraph::touching
//! [`ContactGraph::try_is_supported`]: crate::ContactGraph::try_is_supported
//! [`ContactGraph::supports_of`]: crate::ContactGraph::supports_of
//! [`ContactGraph::new`]: crate::ContactGraph::new
//! [`ContactGraph::to_petgraph`]: crate::ContactGraph::to_petgraph
//! [`ContactGraph::validate`]: crate::ContactGraph::validate
//! [`NodeId`]: crate::NodeId
