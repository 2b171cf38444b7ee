//! Timers (node kind `Timer`): a period in simulated seconds, a tick count.
//!
//! No drift: tick *k* is due when the simulated time since the timer was added first
//! reaches *k*·period, each due time computed as *k*·period, never by adding periods
//! up. The simulated time is kept without accumulating rounding: Rapier's `dt` is an
//! `f32` (0.01 is stored as 0.00999999977…, which would lose a step every few
//! thousand seconds), so it is read as the decimal it prints as (0.01), and the time is
//! `base + n·dt` with `n` the steps taken since `dt` last changed. A tick is taken as
//! reached when the time is within a thousandth of a step of it. A step longer than
//! the period fires every tick it covers, in order (up to [`MAX_TICKS_PER_STEP`] per
//! step; beyond that the earlier ones are skipped, the tick count stays exact). A step
//! whose `dt` is not finite and positive advances no time.

use crate::graph::NodeId;

/// The most ticks of one timer reported in one step.
pub(crate) const MAX_TICKS_PER_STEP: u64 = 10_000;

#[derive(Clone, Debug)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
struct Timer {
    node: NodeId,
    period: f64,
    /// Simulated time when the timer was added.
    start: f64,
    /// Ticks fired so far.
    ticks: u64,
}

/// The timers of a layer.
#[derive(Clone, Debug, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub(crate) struct Timers {
    list: Vec<Timer>,
    /// Simulated time: `base + steps * dt`.
    time: f64,
    base: f64,
    steps: u64,
    dt_bits: u32,
    dt: f64,
}

impl Timers {
    pub(crate) fn time(&self) -> f64 {
        self.time
    }

    pub(crate) fn add(&mut self, node: NodeId, period: f64) {
        self.list.push(Timer {
            node,
            period,
            start: self.time,
            ticks: 0,
        });
        // Slot order for deterministic event order.
        self.list.sort_by_key(|t| t.node.index());
    }

    pub(crate) fn remove(&mut self, node: NodeId) -> bool {
        let before = self.list.len();
        self.list.retain(|t| t.node != node);
        before != self.list.len()
    }

    pub(crate) fn period(&self, node: NodeId) -> Option<f64> {
        self.list.iter().find(|t| t.node == node).map(|t| t.period)
    }

    pub(crate) fn ticks(&self, node: NodeId) -> Option<u64> {
        self.list.iter().find(|t| t.node == node).map(|t| t.ticks)
    }

    /// The timers' nodes, in slot order.
    #[cfg(feature = "serde")]
    pub(crate) fn nodes(&self) -> impl Iterator<Item = NodeId> + '_ {
        self.list.iter().map(|t| t.node)
    }

    /// Checks a deserialised timer list: periods as `add_timer` accepts them, one
    /// timer per node, in slot order. O(timers).
    #[cfg(feature = "serde")]
    pub(crate) fn check(&self) -> Result<(), String> {
        for t in &self.list {
            if !t.period.is_finite() || t.period < super::MIN_TIMER_PERIOD {
                return Err(format!("timer {:?} has period {}", t.node, t.period));
            }
        }
        if self
            .list
            .windows(2)
            .any(|w| w[0].node.index() >= w[1].node.index())
        {
            return Err("timers are not in slot order, or a node has two".into());
        }
        Ok(())
    }

    pub(crate) fn is_empty(&self) -> bool {
        self.list.is_empty()
    }

    /// Advances the time by one step of `dt` and reports the ticks due,
    /// `(timer, tick)` in timer slot order, ticks ascending. O(timers + ticks).
    pub(crate) fn advance(&mut self, dt: f32, out: &mut Vec<(NodeId, u64)>) {
        // A step that is not a finite positive duration advances no time (Rapier makes
        // it a zero-length step): the clock never goes NaN or backwards.
        if !dt.is_finite() || dt <= 0.0 {
            return;
        }
        if dt.to_bits() != self.dt_bits || self.steps == 0 {
            self.base = self.time;
            self.steps = 0;
            self.dt_bits = dt.to_bits();
            // The shortest decimal that round-trips to `dt`: 0.01f32 → 0.01f64.
            self.dt = dt.to_string().parse::<f64>().unwrap_or(dt as f64);
        }
        self.steps = self.steps.saturating_add(1);
        self.time = self.base + self.steps as f64 * self.dt;
        let dt = self.dt;
        let slack = dt * 1e-3;
        for t in &mut self.list {
            let elapsed = self.time - t.start;
            // The ticks due, computed at once (never by adding periods up), and at most
            // MAX_TICKS_PER_STEP of them reported per step: a step far longer than the
            // period reports the last ones and skips the rest (the count stays exact).
            // A tick count past u64::MAX (a huge `dt`, or a restored count) stays at
            // u64::MAX: the comparison is on the clamped count, so no tick is reported
            // twice and nothing overflows.
            let due = ((elapsed + slack) / t.period).floor();
            if !due.is_finite() {
                continue;
            }
            let due = due.min(u64::MAX as f64) as u64;
            if due <= t.ticks {
                continue;
            }
            let first = t
                .ticks
                .saturating_add(1)
                .max(due.saturating_sub(MAX_TICKS_PER_STEP - 1));
            for k in first..=due {
                out.push((t.node, k));
            }
            t.ticks = due;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ticks_do_not_drift_over_a_long_run() {
        let mut timers = Timers::default();
        let n = NodeId::from_raw_parts(0, 0);
        timers.add(n, 0.25);
        let mut out = Vec::new();
        let dt = 0.01f32;
        let mut fired_at = Vec::new();
        for step in 1..=1_000_000u64 {
            out.clear();
            timers.advance(dt, &mut out);
            for &(_, k) in &out {
                fired_at.push((k, step));
            }
        }
        assert_eq!(fired_at.len(), 40_000);
        for &(k, step) in &fired_at {
            assert_eq!(step, 25 * k, "tick {k} fired at step {step}");
        }
    }

    #[test]
    fn a_long_step_fires_every_tick_it_covers() {
        let mut timers = Timers::default();
        let n = NodeId::from_raw_parts(3, 0);
        timers.add(n, 0.1);
        let mut out = Vec::new();
        timers.advance(0.35, &mut out);
        assert_eq!(out, vec![(n, 1), (n, 2), (n, 3)]);
        out.clear();
        timers.advance(0.05, &mut out);
        assert_eq!(out, vec![(n, 4)], "a change of dt keeps the time exact");
        assert_eq!(timers.ticks(n), Some(4));
        assert!(timers.remove(n));
        assert!(!timers.remove(n));
    }

    #[test]
    fn a_huge_dt_saturates_the_tick_count_and_reports_no_tick_twice() {
        for dt in [1e30f32, f32::MAX] {
            let mut timers = Timers::default();
            let n = NodeId::from_raw_parts(0, 0);
            timers.add(n, 0.5);
            let mut reported = Vec::new();
            for _ in 0..5 {
                let mut out = Vec::new();
                timers.advance(dt, &mut out);
                assert!(out.len() as u64 <= MAX_TICKS_PER_STEP, "{dt}");
                reported.extend(out.into_iter().map(|(_, k)| k));
            }
            assert_eq!(timers.ticks(n), Some(u64::MAX), "{dt}");
            let mut sorted = reported.clone();
            sorted.dedup();
            assert_eq!(sorted, reported, "{dt}: a tick was reported twice");
            assert!(reported.windows(2).all(|w| w[0] < w[1]), "{dt}");
            assert_eq!(reported.last(), Some(&u64::MAX), "{dt}");
        }
    }
}
