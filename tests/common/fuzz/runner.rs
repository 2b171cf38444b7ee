//! The runner around the proptest generator (tests only): its configuration, a panic
//! hook that keeps quiet while sequences are tried, the minimiser that removes
//! operations one by one from a failing sequence, and [`property`], the whole run of
//! one configuration with its totals.

use std::cell::{Cell, RefCell};
use std::sync::{Mutex, Once};

use proptest::test_runner::TestRunner;
use proptest::test_runner::{Config as ProptestConfig, RngSeed, TestCaseError, TestError};

use super::{run_in, strategies, Config, Counters, Op};

/// 256 sequences from a fixed seed (one per configuration, so that they do not all
/// run the same sequences) unless `PROPTEST_CASES` / `PROPTEST_RNG_SEED` say
/// otherwise; no failure persistence (a failure is printed, minimised).
pub fn config(of: Config) -> ProptestConfig {
    let mut c = ProptestConfig::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        c.cases = 256;
    }
    if std::env::var_os("PROPTEST_RNG_SEED").is_none() {
        let salt = of
            .name()
            .bytes()
            .fold(0u64, |h, b| h.wrapping_mul(31) + u64::from(b));
        c.rng_seed = RngSeed::Fixed(0x5EED_C0DE ^ salt);
    }
    c.failure_persistence = None;
    c
}

/// The failure with step numbers, node ids and counts blotted out, so that a
/// shorter sequence failing the same way is recognised.
fn signature(msg: &str) -> String {
    let core = msg.rsplit("after step ").next().unwrap_or(msg);
    let core = core.split_once(": ").map_or(core, |(_, c)| c);
    core.chars()
        .filter(|c| !c.is_ascii_digit())
        .take(60)
        .collect()
}

thread_local! {
    /// Whether panics on this thread are expected (a sequence being tried).
    static QUIET: Cell<bool> = const { Cell::new(false) };
    /// Where the last quiet panic on this thread happened.
    static PANIC_AT: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Installs, once per process, a panic hook that records the location only of the
/// panics of threads trying sequences (the runner and the minimiser report those
/// themselves) and leaves every other panic to the default hook: the configurations
/// run as parallel tests, and a test's own failure must still be printed.
fn install_quiet_hook() {
    static ONCE: Once = Once::new();
    ONCE.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if QUIET.with(Cell::get) {
                if let Some(l) = info.location() {
                    PANIC_AT.with(|p| *p.borrow_mut() = l.to_string());
                }
            } else {
                default(info);
            }
        }));
    });
}

/// Runs `f` with this thread's panics quiet.
fn quietly<T>(f: impl FnOnce() -> T) -> T {
    install_quiet_hook();
    let was = QUIET.with(|q| q.replace(true));
    let out = f();
    QUIET.with(|q| q.set(was));
    out
}

/// Runs a sequence; the failure message (a panic's too), if any.
pub fn failure(config: Config, ops: &[Op]) -> Option<String> {
    let r = quietly(|| {
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| run_in(config, ops, false)))
    });
    match r {
        Ok(Ok(_)) => None,
        Ok(Err(m)) => Some(m),
        Err(p) => Some(format!(
            "panic: {} (at {})",
            p.downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default(),
            PANIC_AT.with(|p| p.borrow().clone())
        )),
    }
}

/// Removes operations one by one while the sequence still fails the same way
/// (proptest does not shrink below the 20 operations the strategy asks for).
pub fn minimise(config: Config, mut ops: Vec<Op>, reason: String) -> (Vec<Op>, String) {
    let Some(first) = failure(config, &ops) else {
        return (ops, reason);
    };
    let sig = signature(&first);
    let mut last = first;
    loop {
        let mut changed = false;
        for i in (0..ops.len()).rev() {
            let mut t = ops.clone();
            t.remove(i);
            if let Some(m) = failure(config, &t).filter(|m| signature(m) == sig) {
                ops = t;
                last = m;
                changed = true;
            }
        }
        if !changed {
            break;
        }
    }
    (ops, last)
}

/// The property under one configuration: every sequence the generator makes keeps
/// every check. Prints the run's totals; panics with the minimised sequence on a
/// failure, and when touching tracking was in effect on no step where the
/// configuration wants it (or on some step where it must not be).
pub fn property(config: Config) {
    let cfg = self::config(config);
    let cases = cfg.cases;
    let trace = std::env::var_os("FUZZ_TRACE").is_some();
    let total = Mutex::new(Counters::default());
    let start = std::time::Instant::now();
    let mut runner = TestRunner::new(cfg);
    let result = quietly(|| {
        runner.run(&strategies::ops(config), |ops| {
            if trace {
                eprintln!("sequence of {} ops", ops.len());
            }
            let c = run_in(config, &ops, trace).map_err(TestCaseError::fail)?;
            total.lock().unwrap().add(&c);
            Ok(())
        })
    });
    let result = result.map_err(|e| match e {
        TestError::Fail(reason, ops) => {
            let (ops, reason) = minimise(config, ops, reason.to_string());
            let list: Vec<String> = ops.iter().map(|op| format!("        {op:?},")).collect();
            format!(
                "{reason}\nminimised sequence ({} ops), for harness::run_in(Config::{config:?}, ..):\n{}",
                ops.len(),
                list.join("\n")
            )
        }
        e => e.to_string(),
    });
    let t = *total.lock().unwrap();
    eprintln!(
        "fuzz_operations {}: {} sequences passed ({cases} asked; shrinking's included) in {:.1?}: {} ops, {} steps, {} events, \
         max {} nodes, event kinds seen {:#015b}, body-steps asleep {}, \
         passive changes refused {}, steps with touching tracking {}, touching pairs \
         checked {}, twin steps {}, body-steps held {} (parked {}), user calls {} \
         (on held bodies {}), unseen steps {}, second-layer steps {}",
        config.name(),
        t.cases,
        start.elapsed(),
        t.ops,
        t.steps,
        t.events,
        t.max_nodes,
        t.kinds_seen,
        t.sleeping_seen,
        t.refused,
        t.touching_steps,
        t.touching_pairs,
        t.twin_steps,
        t.held_seen,
        t.parked_seen,
        t.user_calls,
        t.user_calls_held,
        t.unseen_steps,
        t.second_steps,
    );
    if let Err(e) = result {
        panic!("{e}");
    }
    match config.expects_touching() {
        Some(true) => assert!(
            t.touching_steps * 2 > t.steps,
            "touching tracking in effect on {} of {} steps: not most",
            t.touching_steps,
            t.steps
        ),
        Some(false) => assert_eq!(t.touching_steps, 0, "touching tracking in effect"),
        None => {}
    }
    if config.observe_only() {
        assert!(t.twin_steps > 0, "no step compared with the twin");
    }
    if config.speedups().is_some_and(|s| s.hold) {
        assert!(t.held_seen > 0, "no body held");
    }
}
