//! The runner around the proptest generator (tests only): its configuration, a panic
//! hook that keeps quiet while sequences are tried, and the minimiser that removes
//! operations one by one from a failing sequence.

use std::sync::Mutex;

use proptest::test_runner::{Config, RngSeed};

use super::Op;

/// 256 sequences from a fixed seed unless `PROPTEST_CASES` / `PROPTEST_RNG_SEED`
/// say otherwise; no failure persistence (a failure is printed, minimised).
pub fn config() -> Config {
    let mut c = Config::default();
    if std::env::var_os("PROPTEST_CASES").is_none() {
        c.cases = 256;
    }
    if std::env::var_os("PROPTEST_RNG_SEED").is_none() {
        c.rng_seed = RngSeed::Fixed(0x5EED_C0DE);
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

/// Where the last panic happened (the hook below records it silently).
static PANIC_AT: Mutex<String> = Mutex::new(String::new());

/// Replaces the panic hook by one that records the location only (the runner and
/// the minimiser report panics themselves); returns the previous hook.
pub fn silence_panics() -> Box<dyn Fn(&std::panic::PanicHookInfo<'_>) + Sync + Send> {
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|info| {
        if let Some(l) = info.location() {
            *PANIC_AT.lock().unwrap_or_else(|e| e.into_inner()) = l.to_string();
        }
    }));
    hook
}

/// Runs a sequence; the failure message (a panic's too), if any.
pub fn failure(ops: &[Op]) -> Option<String> {
    match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| super::run(ops, false))) {
        Ok(Ok(_)) => None,
        Ok(Err(m)) => Some(m),
        Err(p) => Some(format!(
            "panic: {} (at {})",
            p.downcast_ref::<String>()
                .cloned()
                .or_else(|| p.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default(),
            PANIC_AT.lock().unwrap_or_else(|e| e.into_inner())
        )),
    }
}

/// Removes operations one by one while the sequence still fails the same way
/// (proptest does not shrink below the 20 operations the strategy asks for).
pub fn minimise(mut ops: Vec<Op>, reason: String) -> (Vec<Op>, String) {
    let Some(first) = failure(&ops) else {
        return (ops, reason);
    };
    let sig = signature(&first);
    let mut last = first;
    loop {
        let mut changed = false;
        for i in (0..ops.len()).rev() {
            let mut t = ops.clone();
            t.remove(i);
            if let Some(m) = failure(&t).filter(|m| signature(m) == sig) {
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
