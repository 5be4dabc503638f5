//! The per-tick record the haptic thread hands to the recorder (plain `Copy` data: no
//! allocation on the 1 kHz path). Each part is one MCAP channel; its JSON schema is derived
//! from the struct, so the schema and the messages cannot drift apart.

use haptic_wheel::{Fault, WatchdogState};
use schemars::JsonSchema;
use serde::Serialize;

/// Everything one haptic tick measured, commanded and computed.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TickRecord {
    /// Tick number since the session started.
    pub tick: u64,
    /// Session (simulation) time, ns since the start.
    pub t_ns: u64,
    /// Wheel side.
    pub wheel: WheelSample,
    /// Car and road side (absent during the dial task).
    pub vehicle: Option<VehicleSample>,
    /// Running score.
    pub score: ScoreSample,
    /// Active assistance.
    pub assist: AssistSample,
    /// Arm pose from the gyros (absent without arm sensing).
    pub arm: Option<ArmSample>,
    /// Loop timing on the wall clock.
    pub timing: TimingSample,
}

/// Wheel state and torques in one tick (channel `/wheel`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, JsonSchema)]
pub struct WheelSample {
    /// Angle as read from the device (quantised), rad.
    pub angle_rad: f64,
    /// Estimated angular velocity (Kalman), rad/s.
    pub velocity_rad_s: f64,
    /// Torque of the haptic model (centring spring–damper, eq. 3.5), N·m.
    pub model_nm: f64,
    /// Road feel from the front lateral tyre force (§3.3.4), N·m.
    pub road_feel_nm: f64,
    /// Torque requested before the safety chain, N·m.
    pub requested_nm: f64,
    /// Torque commanded to the motor after the safety chain, N·m.
    pub commanded_nm: f64,
    /// The safety chain limited the request this tick.
    pub clipped: bool,
    /// Soft-start / fade-out scale of the safety supervisor, 0–1.
    pub safety_scale: f64,
    /// Safety supervisor state: soft-start, running, paused, fault-missed-deadline,
    /// fault-stale-reading, stopping, stopped.
    pub watchdog: &'static str,
    /// Passivity observer energy, J (negative: the rendered environment generated energy).
    pub passivity_energy_j: f64,
    /// Damping the passivity controller added, N·m·s/rad.
    pub passivity_damping_nm_s_per_rad: f64,
    /// True wheel angle, rad (simulation only; null with a real wheel).
    pub true_angle_rad: Option<f64>,
    /// Simulated patient's hand torque, N·m (simulation only; null with a real wheel).
    pub hand_nm: Option<f64>,
    /// Wheel angle the patient aims for, rad.
    pub target_rad: f64,
}

/// Where the arm sensing is, as recorded (a kebab-case string in the JSON).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum ArmSetup {
    /// Joint angles are being estimated.
    #[default]
    Tracking,
    /// Guided procedure: hold the wheel still, centred.
    HoldStill,
    /// Guided procedure: turn the wheel left and right.
    TurnWheel,
    /// The mounting is being computed.
    Solving,
    /// The procedure failed: no joint angles this session.
    Failed,
    /// An IMU stopped answering: the pose is frozen.
    SensorLost,
}

impl ArmSetup {
    /// The label as recorded (and shown on the screen's device line).
    pub fn as_str(self) -> &'static str {
        match self {
            ArmSetup::Tracking => "tracking",
            ArmSetup::HoldStill => "hold-still",
            ArmSetup::TurnWheel => "turn-wheel",
            ArmSetup::Solving => "solving",
            ArmSetup::Failed => "failed",
            ArmSetup::SensorLost => "sensor-lost",
        }
    }
}

/// The supervisor state as a stable label for recordings.
pub fn watchdog_label(state: WatchdogState) -> &'static str {
    match state {
        WatchdogState::SoftStart => "soft-start",
        WatchdogState::Running => "running",
        WatchdogState::Fault(Fault::MissedDeadline) => "fault-missed-deadline",
        WatchdogState::Fault(Fault::StaleReading) => "fault-stale-reading",
        WatchdogState::Fault(_) => "fault",
        WatchdogState::Paused => "paused",
        WatchdogState::Stopping => "stopping",
        WatchdogState::Stopped => "stopped",
    }
}

/// Car and road state in one tick (channel `/vehicle`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, JsonSchema)]
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

/// The running session score (channel `/score`, every 100 ms).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, JsonSchema)]
pub struct ScoreSample {
    /// Which exercise of the course is running (0-based).
    pub exercise_index: u32,
    /// RMS lateral deviation so far, m.
    pub rms_lateral_m: f64,
    /// Largest |lateral deviation| so far, m.
    pub max_lateral_m: f64,
    /// Share of time in the lane so far, %.
    pub pct_in_lane: f64,
    /// Cones hit so far.
    pub cone_hits: u32,
    /// RMS dial tracking error so far (thesis §3.3.3), degrees.
    pub dial_rms_error_deg: f64,
    /// Exercise time so far, s: the session clock without the pauses.
    pub active_s: f64,
    /// The patient paused the exercise (car, exercise clock and scores frozen; torque faded
    /// to zero).
    pub paused: bool,
}

/// Active assistance in one tick (channel `/assist`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, JsonSchema)]
pub struct AssistSample {
    /// An assist controller runs during this exercise.
    pub active: bool,
    /// Assist torque, N·m.
    pub torque_nm: f64,
    /// Reference the assist tracks (after the reference governor), rad.
    pub reference_rad: f64,
    /// Reference minus measured angle, rad.
    pub error_rad: f64,
    /// How much the robot helps, 0 (none) to 1 (full authority).
    pub assistance_level: f64,
    /// A torque limit cut the assist this tick.
    pub saturated: bool,
}

/// The arm pose estimated from the two IMUs, beside the simulated truth (channel `/arm`).
/// Angles follow `gyro_imu::arm::JointAngles`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, JsonSchema)]
pub struct ArmSample {
    /// Estimated humerus elevation from hanging, rad.
    pub shoulder_elevation_rad: f64,
    /// Estimated plane of elevation (0 lateral, π/2 forward), rad.
    pub shoulder_plane_rad: f64,
    /// Estimated humeral axial rotation (internal positive), rad.
    pub shoulder_rotation_rad: f64,
    /// Estimated elbow flexion (0 straight), rad.
    pub elbow_flexion_rad: f64,
    /// Estimated forearm pronation, rad.
    pub forearm_pronation_rad: f64,
    /// True humerus elevation (simulation only), rad.
    pub true_shoulder_elevation_rad: f64,
    /// True elbow flexion (simulation only), rad.
    pub true_elbow_flexion_rad: f64,
    /// RMS mismatch of the measured and fitted segment "up" directions, rad.
    pub fit_residual_rad: f64,
    /// Arm sensing step (angles are zero until tracking starts).
    pub setup: ArmSetup,
    /// Time left in the set-up step, s.
    pub setup_remaining_s: f64,
    /// Upper-arm sensor-to-earth orientation (w, x, y, z; earth z up, heading that of the
    /// wheel frame when tracking began).
    pub upper_orientation_wxyz: [f64; 4],
    /// Forearm sensor-to-earth orientation (w, x, y, z).
    pub fore_orientation_wxyz: [f64; 4],
    /// Range of motion so far of shoulder elevation, plane, rotation, elbow flexion and
    /// forearm pronation, rad.
    pub range_of_motion_rad: [f64; 5],
    /// Upper arm's long axis (shoulder → elbow) in the wheel frame, from the upper-arm IMU's
    /// orientation and mounting alone (not from the chain fit): the arm calibration's input.
    pub upper_axis: [f64; 3],
    /// Forearm's long axis (elbow → grip) in the wheel frame, from the forearm IMU alone.
    pub fore_axis: [f64; 3],
    /// Grip point on the wheel rim at the wheel angle read, m (wheel frame).
    pub grip_m: [f64; 3],
    /// Upper-arm gyro, sensor x, rad/s.
    pub upper_gyro_x_rad_s: f64,
    /// Upper-arm gyro, sensor y, rad/s.
    pub upper_gyro_y_rad_s: f64,
    /// Upper-arm gyro, sensor z, rad/s.
    pub upper_gyro_z_rad_s: f64,
    /// Forearm gyro, sensor x, rad/s.
    pub fore_gyro_x_rad_s: f64,
    /// Forearm gyro, sensor y, rad/s.
    pub fore_gyro_y_rad_s: f64,
    /// Forearm gyro, sensor z, rad/s.
    pub fore_gyro_z_rad_s: f64,
}

/// Wall-clock timing of one tick (channel `/timing`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, JsonSchema)]
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

#[cfg(test)]
mod tests {
    use super::ArmSetup;

    #[test]
    fn arm_setup_labels_are_the_recorded_strings() {
        for s in [
            ArmSetup::Tracking,
            ArmSetup::HoldStill,
            ArmSetup::TurnWheel,
            ArmSetup::Solving,
            ArmSetup::Failed,
            ArmSetup::SensorLost,
        ] {
            assert_eq!(
                serde_json::to_string(&s).unwrap(),
                format!("\"{}\"", s.as_str())
            );
        }
    }
}
