//! The per-tick record the haptic thread hands to the recorder (plain `Copy` data: no
//! allocation on the 1 kHz path).

/// Everything one haptic tick measured, commanded and computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct TickRecord {
    /// Tick number since the session started.
    pub tick: u64,
    /// Session (simulation) time, ns since the start.
    pub t_ns: u64,
    /// Wheel side.
    pub wheel: WheelSample,
    /// Car and road side.
    pub vehicle: VehicleSample,
    /// Running score.
    pub score: ScoreSample,
    /// Loop timing on the wall clock.
    pub timing: TimingSample,
}

/// Wheel state and torques in one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct WheelSample {
    /// Angle as read from the device (quantised), rad.
    pub angle_rad: f64,
    /// Estimated angular velocity, rad/s.
    pub velocity_rad_s: f64,
    /// Torque requested by the haptic model before the safety chain, N·m.
    pub requested_nm: f64,
    /// Torque commanded to the motor after the safety chain, N·m.
    pub commanded_nm: f64,
    /// The safety chain limited the request this tick.
    pub clipped: bool,
    /// True wheel angle (simulation only; NaN with a real wheel), rad.
    pub true_angle_rad: f64,
    /// Simulated patient's hand torque (simulation only; NaN with a real wheel), N·m.
    pub hand_nm: f64,
    /// Wheel angle the (simulated) patient is aiming for, rad.
    pub target_rad: f64,
}

/// Car and road state in one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct VehicleSample {
    /// Global x, m.
    pub x_m: f64,
    /// Global y, m.
    pub y_m: f64,
    /// Heading, rad.
    pub yaw_rad: f64,
    /// Forward velocity, m/s.
    pub ux_m_s: f64,
    /// Lateral velocity, m/s.
    pub uy_m_s: f64,
    /// Yaw rate, rad/s.
    pub r_rad_s: f64,
    /// Road-wheel angle δ, rad.
    pub steer_rad: f64,
    /// Front lateral tyre force, N.
    pub front_lateral_n: f64,
    /// Distance along the road, m.
    pub s_m: f64,
    /// Lateral deviation from the road centre, m (positive left).
    pub lateral_m: f64,
}

/// The running lane score.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct ScoreSample {
    /// RMS lateral deviation so far, m.
    pub rms_lateral_m: f64,
    /// Largest |lateral deviation| so far, m.
    pub max_lateral_m: f64,
    /// Share of time in the lane so far, %.
    pub pct_in_lane: f64,
}

/// Wall-clock timing of one tick.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct TimingSample {
    /// How late the tick started after its absolute deadline, ns (0 at `--speed max`).
    pub lateness_ns: u64,
    /// Wall time since the previous tick started, ns.
    pub period_ns: u64,
    /// Time spent computing this tick, ns.
    pub work_ns: u64,
    /// Records the recorder could not take so far (ring full), count.
    pub dropped_records: u64,
}
