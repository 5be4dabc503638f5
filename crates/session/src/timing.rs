//! Loop-timing statistics: percentiles of wake-up lateness and period error.
//!
//! Memory is bounded whatever the session's length (an hour at 1 kHz is 3.6 million ticks):
//! each quantity is a count per nanosecond below [`EXACT_BELOW_NS`] and a list of the rare
//! larger values, so the percentiles are the exact nearest-rank ones of every tick.

use std::collections::VecDeque;

/// Values below this are counted per nanosecond (1.05 ms: every tick of a healthy loop); the
/// rare larger ones are kept as they are.
pub const EXACT_BELOW_NS: u64 = 1 << 20;

/// The period errors of the most recent ticks kept for the live summaries' p99.
pub const RECENT_TICKS: usize = 1000;

/// Every value added, as counts: exact nearest-rank quantiles in bounded memory.
#[derive(Clone, Debug, Default)]
struct Counts {
    /// `per_ns[v]`: how many values equal `v` ns (allocated, resident, on first use).
    per_ns: Vec<u32>,
    /// Values of [`EXACT_BELOW_NS`] and more, in the order added.
    large: Vec<u64>,
    n: u64,
}

impl Counts {
    fn add(&mut self, v: u64) {
        self.n += 1;
        if v >= EXACT_BELOW_NS {
            self.large.push(v);
            return;
        }
        if self.per_ns.is_empty() {
            // 4 MiB, resident at once: taken page by page as the loop's jitter reaches new
            // values, it would look like growth for the whole session.
            self.per_ns = common::resident::resident_vec(EXACT_BELOW_NS as usize, 1, 0);
        }
        let c = &mut self.per_ns[v as usize];
        *c = c.saturating_add(1);
    }

    /// The nearest-rank quantile (as [`common::quantile`] on the sorted values).
    fn quantile(&self, q: f64) -> Option<u64> {
        if self.n == 0 {
            return None;
        }
        // `as u64` saturates: NaN and negative q give 0, clamped to the first value.
        let rank = ((q * self.n as f64).ceil() as u64).clamp(1, self.n);
        let mut seen = 0u64;
        for (v, &c) in self.per_ns.iter().enumerate() {
            seen += u64::from(c);
            if seen >= rank {
                return Some(v as u64);
            }
        }
        let mut large = self.large.clone();
        large.sort_unstable();
        large.get((rank - seen - 1) as usize).copied()
    }

    fn max(&self) -> Option<u64> {
        self.large
            .iter()
            .copied()
            .max()
            .or_else(|| self.per_ns.iter().rposition(|&c| c > 0).map(|v| v as u64))
    }

    fn percentiles(&self) -> Percentiles {
        let us = |v: Option<u64>| v.unwrap_or(0) as f64 / 1e3;
        Percentiles {
            p50_us: us(self.quantile(0.50)),
            p99_us: us(self.quantile(0.99)),
            max_us: us(self.max()),
        }
    }
}

/// Collected per-tick timing on the wall clock, summarised at the end of a session.
#[derive(Clone, Debug, Default)]
pub struct TimingStats {
    lateness_ns: Counts,
    period_error_ns: Counts,
    work_ns: Counts,
    /// The last [`RECENT_TICKS`] period errors.
    recent_period_error_ns: VecDeque<u64>,
    nominal_period_ns: u64,
}

/// Percentiles of one timing quantity, µs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Percentiles {
    /// Median, µs.
    pub p50_us: f64,
    /// 99th percentile, µs.
    pub p99_us: f64,
    /// Maximum, µs.
    pub max_us: f64,
}

fn percentiles(values: &[u64]) -> Percentiles {
    let mut v = values.to_vec();
    v.sort_unstable();
    Percentiles {
        p50_us: common::quantile(&v, 0.50).unwrap_or(0) as f64 / 1e3,
        p99_us: common::quantile(&v, 0.99).unwrap_or(0) as f64 / 1e3,
        max_us: v.last().copied().unwrap_or(0) as f64 / 1e3,
    }
}

impl TimingStats {
    /// Statistics for a loop with a nominal period of `nominal_period_ns` (bounded memory,
    /// whatever the number of ticks).
    pub fn new(nominal_period_ns: u64) -> Self {
        Self {
            nominal_period_ns,
            recent_period_error_ns: VecDeque::with_capacity(RECENT_TICKS),
            ..Self::default()
        }
    }

    /// Add one tick. The first tick has no period and only counts for lateness and work.
    pub fn add(&mut self, lateness_ns: u64, period_ns: u64, work_ns: u64) {
        if self.lateness_ns.n > 0 {
            let e = period_ns.abs_diff(self.nominal_period_ns);
            self.period_error_ns.add(e);
            if self.recent_period_error_ns.len() == RECENT_TICKS {
                self.recent_period_error_ns.pop_front();
            }
            self.recent_period_error_ns.push_back(e);
        }
        self.lateness_ns.add(lateness_ns);
        self.work_ns.add(work_ns);
    }

    /// Ticks added.
    pub fn ticks(&self) -> usize {
        self.lateness_ns.n as usize
    }

    /// |period − nominal period| percentiles.
    pub fn period_error(&self) -> Percentiles {
        self.period_error_ns.percentiles()
    }

    /// Wake-up lateness after the absolute deadline.
    pub fn lateness(&self) -> Percentiles {
        self.lateness_ns.percentiles()
    }

    /// Compute time per tick.
    pub fn work(&self) -> Percentiles {
        self.work_ns.percentiles()
    }

    /// 99th percentile of the period error over the last `n` ticks (at most
    /// [`RECENT_TICKS`]), µs (for live summaries).
    pub fn recent_period_error_p99_us(&self, n: usize) -> f64 {
        let start = self.recent_period_error_ns.len().saturating_sub(n);
        let recent: Vec<u64> = self
            .recent_period_error_ns
            .range(start..)
            .copied()
            .collect();
        percentiles(&recent).p99_us
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_use_nearest_rank() {
        let mut t = TimingStats::new(1_000_000);
        for i in 1..=100u64 {
            t.add(i * 1000, 1_000_000 + i * 1000, 0);
        }
        let l = t.lateness();
        assert_eq!((l.p50_us, l.p99_us, l.max_us), (50.0, 99.0, 100.0));
        // 99 periods (the first tick has none): errors 2..=100 µs.
        assert_eq!(t.period_error().p50_us, 51.0);
    }

    #[test]
    fn percentiles_are_those_of_every_value_kept_in_bounded_memory() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(17);
        let mut t = TimingStats::new(1_000_000);
        let (mut late, mut err, mut work) = (Vec::new(), Vec::new(), Vec::new());
        for i in 0..20_000 {
            // Mostly microseconds, some past the exact range (late ticks of several ms).
            let big = rng.random_bool(0.02);
            let l = if big {
                rng.random_range(EXACT_BELOW_NS..20_000_000)
            } else {
                rng.random_range(0..50_000)
            };
            let p = 1_000_000 + rng.random_range(0..60_000) - 30_000 + if big { l } else { 0 };
            let w = rng.random_range(10_000..90_000);
            t.add(l, p, w);
            late.push(l);
            work.push(w);
            if i > 0 {
                err.push(p.abs_diff(1_000_000));
            }
        }
        assert_eq!(t.ticks(), 20_000);
        assert_eq!(t.lateness(), percentiles(&late));
        assert_eq!(t.period_error(), percentiles(&err));
        assert_eq!(t.work(), percentiles(&work));
        assert_eq!(
            t.recent_period_error_p99_us(1000),
            percentiles(&err[err.len() - 1000..]).p99_us
        );
        // Memory: one count per ns below the exact bound per quantity, and the large values.
        let bytes = 3 * EXACT_BELOW_NS as usize * 4;
        assert!(t.lateness_ns.per_ns.len() * 4 * 3 <= bytes);
        assert!(
            t.lateness_ns.large.len() < 1000,
            "{}",
            t.lateness_ns.large.len()
        );
    }

    #[test]
    fn no_tick_means_zero_percentiles() {
        let t = TimingStats::new(1_000_000);
        assert_eq!(t.lateness(), Percentiles::default());
        assert_eq!(t.recent_period_error_p99_us(10), 0.0);
    }
}
