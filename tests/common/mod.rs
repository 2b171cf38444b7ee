//! Helpers shared by the integration tests; a test binary pulls them in with
//! `mod common;`.
//!
//! - [`build`]: world-building shorthands (`ground`, `ball_at`, `box_at`, ...);
//! - [`audit`]: the bad-input audit's helpers (`no_panic`, stale and foreign ids, the
//!   ball-on-ground world the `bad_input_*` tests start from);
//! - [`contract`]: a subscriber that checks the listener contract of `events`;
//! - [`groups`]: contact groups computed independently (petgraph's union-find);
//! - [`scene`]: running a scene validated after every step, and naming its nodes for
//!   snapshots (re-exported here).
//!
//! `fuzz/` is the fuzz harness. It is no module of `common`: `tests/fuzz_operations.rs`
//! includes it as its module `harness` (with `#[path]`), so that the cargo-fuzz target,
//! which includes that file, gets it too; the regression binaries that replay
//! sequences include it the same way.
#![allow(dead_code)]

pub mod audit;
pub mod build;
pub mod contract;
pub mod groups;
pub mod scene;

// The scene helpers predate this index; their callers name them `common::...`.
#[allow(unused_imports)]
pub use scene::*;
