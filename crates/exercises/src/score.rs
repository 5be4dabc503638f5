//! Scores, online and final: lane keeping (thesis §3.3.4: deviation from the road centre),
//! heading error, completion time and cone hits for the driving exercises, and the squared
//! angle error of the rotary dial task (thesis §3.3.3; Appendix E reports ≈ 3° of tracking
//! error for a healthy subject).

use common::wrap_angle;
use serde::{Deserialize, Serialize};

use crate::road::Projection;
use crate::world::WorldEvent;

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

/// Everything scored on a driving exercise, updated every tick.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DrivingScore {
    lane: LaneScore,
    heading_sq_rad2_s: f64,
    max_heading_rad: f64,
    cone_hits: u32,
    barrier_hits: u32,
    road_exits: u32,
    completion_time_s: Option<f64>,
}

impl DrivingScore {
    /// Add `dt_s` seconds with the car at `yaw_rad`, projected onto the road as `here`.
    pub fn update(&mut self, here: &Projection, yaw_rad: f64, lane_width_m: f64, dt_s: f64) {
        let e = wrap_angle(yaw_rad - here.heading_rad);
        if !e.is_finite() || !dt_s.is_finite() || dt_s <= 0.0 || !here.lateral_m.is_finite() {
            return;
        }
        self.lane.update(here.lateral_m, lane_width_m, dt_s);
        self.heading_sq_rad2_s += e * e * dt_s;
        self.max_heading_rad = self.max_heading_rad.max(e.abs());
    }

    /// Count a world event (cone hit, leaving the road, barrier contact).
    pub fn record(&mut self, event: &WorldEvent) {
        match event {
            WorldEvent::ConeHit { .. } => self.cone_hits += 1,
            WorldEvent::BarrierHit => self.barrier_hits += 1,
            WorldEvent::EdgeCleared { off_road: true, .. } => self.road_exits += 1,
            _ => {}
        }
    }

    /// Mark the exercise completed at `t_s` (the first call wins).
    pub fn complete(&mut self, t_s: f64) {
        self.completion_time_s.get_or_insert(t_s);
    }

    /// The lane-keeping part.
    pub fn lane(&self) -> &LaneScore {
        &self.lane
    }

    /// The scores so far.
    pub fn summary(&self) -> DrivingSummary {
        let t = self.lane.time_s();
        DrivingSummary {
            time_s: t,
            rms_lateral_m: self.lane.rms_m(),
            max_lateral_m: self.lane.max_abs_m(),
            pct_in_lane: self.lane.pct_in_lane(),
            rms_heading_error_deg: if t > 0.0 {
                (self.heading_sq_rad2_s / t).sqrt().to_degrees()
            } else {
                0.0
            },
            max_heading_error_deg: self.max_heading_rad.to_degrees(),
            cone_hits: self.cone_hits,
            barrier_hits: self.barrier_hits,
            road_exits: self.road_exits,
            completion_time_s: self.completion_time_s,
        }
    }
}

/// Scores of a driving exercise (final or so far).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DrivingSummary {
    /// Time scored, s.
    pub time_s: f64,
    /// RMS lateral deviation from the centre line, m.
    pub rms_lateral_m: f64,
    /// Largest |lateral deviation|, m.
    pub max_lateral_m: f64,
    /// Share of time with the car's centre inside the lane, %.
    pub pct_in_lane: f64,
    /// RMS heading error relative to the centre line, deg.
    pub rms_heading_error_deg: f64,
    /// Largest |heading error|, deg.
    pub max_heading_error_deg: f64,
    /// Cones hit.
    pub cone_hits: u32,
    /// Barrier contacts.
    pub barrier_hits: u32,
    /// Times the car left the road.
    pub road_exits: u32,
    /// Time to reach the end of the road, s (`None` while not reached).
    pub completion_time_s: Option<f64>,
}

/// Dial tracking score: the squared angle error of thesis §3.3.3 integrated over time.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct DialScore {
    sum_sq_rad2_s: f64,
    sum_abs_rad_s: f64,
    max_abs_rad: f64,
    time_s: f64,
}

impl DialScore {
    /// Add `dt_s` seconds with the wheel at `actual_rad` and the needle at `desired_rad`.
    pub fn update(&mut self, desired_rad: f64, actual_rad: f64, dt_s: f64) {
        let e = desired_rad - actual_rad;
        if !e.is_finite() || !dt_s.is_finite() || dt_s <= 0.0 {
            return;
        }
        self.sum_sq_rad2_s += e * e * dt_s;
        self.sum_abs_rad_s += e.abs() * dt_s;
        self.max_abs_rad = self.max_abs_rad.max(e.abs());
        self.time_s += dt_s;
    }

    /// Integral of the squared angle error ∫ (θd − θ)² dt, rad²·s (§3.3.3's measure).
    pub fn integrated_sq_error_rad2_s(&self) -> f64 {
        self.sum_sq_rad2_s
    }

    /// The scores so far.
    pub fn summary(&self) -> DialSummary {
        let t = self.time_s;
        let per = |v: f64| if t > 0.0 { v / t } else { 0.0 };
        DialSummary {
            time_s: t,
            mean_sq_error_rad2: per(self.sum_sq_rad2_s),
            rms_error_deg: per(self.sum_sq_rad2_s).sqrt().to_degrees(),
            mean_abs_error_deg: per(self.sum_abs_rad_s).to_degrees(),
            max_abs_error_deg: self.max_abs_rad.to_degrees(),
        }
    }
}

/// Scores of a dial tracking exercise.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct DialSummary {
    /// Time scored, s.
    pub time_s: f64,
    /// Time-averaged squared angle error, rad².
    pub mean_sq_error_rad2: f64,
    /// RMS angle error, deg.
    pub rms_error_deg: f64,
    /// Mean absolute angle error, deg (Appendix E's "absolute tracking error", ≈ 3°).
    pub mean_abs_error_deg: f64,
    /// Largest absolute angle error, deg.
    pub max_abs_error_deg: f64,
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

    #[test]
    fn dial_score_of_a_lagging_sine_matches_closed_form() {
        // Tracking A sin(t) with a lag φ: error 2A sin(φ/2) cos(t − φ/2), RMS = √2 A sin(φ/2).
        let (a, phi, dt) = (1.0f64, 0.1f64, 1e-3);
        let mut d = DialScore::default();
        let n = (2.0 * std::f64::consts::PI * 10.0 / dt).round() as usize;
        for i in 0..n {
            let t = i as f64 * dt;
            d.update(a * t.sin(), a * (t - phi).sin(), dt);
        }
        let s = d.summary();
        let expect = (2.0f64).sqrt() * a * (phi / 2.0).sin();
        assert!(
            (s.rms_error_deg - expect.to_degrees()).abs() < 1e-3,
            "{s:?}"
        );
        assert!((d.integrated_sq_error_rad2_s() - expect * expect * s.time_s).abs() < 1e-6);
        // Mean |cos| = 2/π.
        let mean_abs = 2.0 * a * (phi / 2.0).sin() * 2.0 / std::f64::consts::PI;
        assert!((s.mean_abs_error_deg - mean_abs.to_degrees()).abs() < 1e-3);
    }

    #[test]
    fn driving_score_counts_events_and_heading_error() {
        let mut d = DrivingScore::default();
        let here = Projection {
            s_m: 0.0,
            lateral_m: 0.5,
            heading_rad: 0.1,
            curvature_1_m: 0.0,
        };
        for _ in 0..100 {
            d.update(&here, 0.1 + 2f64.to_radians(), 3.5, 0.01);
        }
        d.record(&WorldEvent::ConeHit { cone: 3 });
        d.record(&WorldEvent::EdgeCleared {
            side: crate::world::Side::Left,
            off_road: true,
        });
        d.record(&WorldEvent::EdgeCleared {
            side: crate::world::Side::Left,
            off_road: false,
        });
        d.complete(12.0);
        d.complete(13.0);
        let s = d.summary();
        assert!((s.rms_heading_error_deg - 2.0).abs() < 1e-9);
        assert!((s.rms_lateral_m - 0.5).abs() < 1e-12 && s.pct_in_lane == 100.0);
        assert_eq!((s.cone_hits, s.road_exits), (1, 1));
        assert_eq!(s.completion_time_s, Some(12.0));
    }
}
