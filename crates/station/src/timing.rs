//! Loop-timing statistics: percentiles of wake-up lateness and period error.

/// Collected per-tick timing on the wall clock, summarised at the end of a session.
#[derive(Clone, Debug, Default)]
pub struct TimingStats {
    lateness_ns: Vec<u64>,
    period_error_ns: Vec<u64>,
    work_ns: Vec<u64>,
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
    /// Statistics for a loop with a nominal period of `nominal_period_ns`.
    pub fn new(nominal_period_ns: u64, expected_ticks: usize) -> Self {
        Self {
            lateness_ns: Vec::with_capacity(expected_ticks),
            period_error_ns: Vec::with_capacity(expected_ticks),
            work_ns: Vec::with_capacity(expected_ticks),
            nominal_period_ns,
        }
    }

    /// Add one tick. The first tick has no period and only counts for lateness and work.
    pub fn add(&mut self, lateness_ns: u64, period_ns: u64, work_ns: u64) {
        if !self.lateness_ns.is_empty() {
            self.period_error_ns
                .push(period_ns.abs_diff(self.nominal_period_ns));
        }
        self.lateness_ns.push(lateness_ns);
        self.work_ns.push(work_ns);
    }

    /// Ticks added.
    pub fn ticks(&self) -> usize {
        self.lateness_ns.len()
    }

    /// |period − nominal period| percentiles.
    pub fn period_error(&self) -> Percentiles {
        percentiles(&self.period_error_ns)
    }

    /// Wake-up lateness after the absolute deadline.
    pub fn lateness(&self) -> Percentiles {
        percentiles(&self.lateness_ns)
    }

    /// Compute time per tick.
    pub fn work(&self) -> Percentiles {
        percentiles(&self.work_ns)
    }

    /// 99th percentile of the period error over the last `n` ticks, µs (for live summaries).
    pub fn recent_period_error_p99_us(&self, n: usize) -> f64 {
        let start = self.period_error_ns.len().saturating_sub(n);
        percentiles(&self.period_error_ns[start..]).p99_us
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn percentiles_use_nearest_rank() {
        let mut t = TimingStats::new(1_000_000, 100);
        for i in 1..=100u64 {
            t.add(i * 1000, 1_000_000 + i * 1000, 0);
        }
        let l = t.lateness();
        assert_eq!((l.p50_us, l.p99_us, l.max_us), (50.0, 99.0, 100.0));
        // 99 periods (the first tick has none): errors 2..=100 µs.
        assert_eq!(t.period_error().p50_us, 51.0);
    }
}
