//! Online scoring of lane keeping (thesis §3.3.4: deviation from the road centre).

/// Running lateral-deviation score: RMS, maximum and share of time inside the lane.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LaneScore {
    sum_sq_m2_s: f64,
    max_abs_m: f64,
    time_in_lane_s: f64,
    time_s: f64,
}

impl LaneScore {
    /// Add `dt_s` seconds at lateral deviation `lateral_m` in a lane of `lane_width_m`.
    /// The car is in the lane while its centre is within half the lane width of the centre line.
    pub fn update(&mut self, lateral_m: f64, lane_width_m: f64, dt_s: f64) {
        if !lateral_m.is_finite() || !dt_s.is_finite() || dt_s <= 0.0 {
            return;
        }
        self.sum_sq_m2_s += lateral_m * lateral_m * dt_s;
        self.max_abs_m = self.max_abs_m.max(lateral_m.abs());
        if lateral_m.abs() <= lane_width_m / 2.0 {
            self.time_in_lane_s += dt_s;
        }
        self.time_s += dt_s;
    }

    /// Root-mean-square lateral deviation, m.
    pub fn rms_m(&self) -> f64 {
        if self.time_s > 0.0 {
            (self.sum_sq_m2_s / self.time_s).sqrt()
        } else {
            0.0
        }
    }

    /// Largest |lateral deviation| seen, m.
    pub fn max_abs_m(&self) -> f64 {
        self.max_abs_m
    }

    /// Percentage of time inside the lane, 0–100.
    pub fn pct_in_lane(&self) -> f64 {
        if self.time_s > 0.0 {
            100.0 * (self.time_in_lane_s / self.time_s).min(1.0)
        } else {
            100.0
        }
    }

    /// Time scored so far, s.
    pub fn time_s(&self) -> f64 {
        self.time_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn constant_offset_gives_that_rms_and_time_share() {
        let mut s = LaneScore::default();
        for _ in 0..100 {
            s.update(1.0, 3.0, 0.01);
        }
        for _ in 0..100 {
            s.update(-2.0, 3.0, 0.01);
        }
        assert!((s.rms_m() - (2.5f64).sqrt()).abs() < 1e-12);
        assert_eq!(s.max_abs_m(), 2.0);
        assert!((s.pct_in_lane() - 50.0).abs() < 1e-9);
    }

    #[test]
    fn always_in_lane_is_exactly_one_hundred_percent() {
        let mut s = LaneScore::default();
        for _ in 0..2600 {
            s.update(0.1, 3.5, 0.001);
        }
        assert_eq!(s.pct_in_lane(), 100.0);
    }
}
