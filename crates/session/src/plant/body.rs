//! Who holds the wheel: a simulated patient on a simulated wheel, a real patient on a real
//! force-feedback wheel, or a recording's raw inputs played back.

use crate::config::StationConfig;
use crate::faults::FaultyWheel;
use anyhow::Context;
use arm::sim::SimArmSensing;
use arm::{ArmSeam, SetupStep, WheelNow};
use assist::HumanArm;
use haptic_wheel::{SimWheel, Wheel, ZeroTorqueOnDrop};
use record::ArmSample;
use record::raw::{ANGLE_QUANTUM_RAD, TORQUE_QUANTUM_NM, on_grid};

/// Who holds the wheel.
// One body per session, built once and never moved on the hot path: its size does not matter.
#[allow(clippy::large_enum_variant)]
pub enum Body {
    /// A simulated wheel held by a simulated patient who wears simulated IMUs.
    Sim {
        /// The simulated wheel (zero torque when dropped), failing as the session's injected
        /// faults say.
        wheel: ZeroTorqueOnDrop<FaultyWheel<SimWheel>>,
        /// The simulated patient's arm control.
        arm: HumanArm,
        /// The simulated arm kinematics, IMUs and pose estimator.
        sensing: Box<SimArmSensing>,
        /// The simulated patient's foot on the pedals.
        foot: exercises::SimFoot,
    },
    /// A real force-feedback wheel (the Linux kernel FF API; DirectInput 8 on Windows) held by
    /// the patient, who may wear two controller IMUs.
    #[cfg(any(target_os = "linux", windows))]
    Evdev {
        /// The device (zero torque, effects erased and gain restored when dropped). Boxed so
        /// that the kernel backend can run over any device seam (tests use an in-memory one).
        wheel: ZeroTorqueOnDrop<Box<dyn Wheel + Send>>,
        /// The arm's IMUs, when two are present.
        arm: Option<Box<arm::hid::HidArmSensing>>,
        /// The clock of the wheel's readings.
        clock: clock::Clock,
    },
    /// A recording's raw inputs played back (`telerehab replay`).
    Recorded(Box<crate::recorded::RecordedBody>),
}

impl Body {
    /// The simulated body of `cfg`, seeded from `cfg.session.seed`; `real_time` when the
    /// session runs on the wall clock; `clock` is the session's.
    pub fn simulated(
        cfg: &StationConfig,
        real_time: bool,
        clock: clock::Clock,
    ) -> anyhow::Result<Self> {
        let dt_s = 1.0 / cfg.session.loop_rate_hz;
        let mut wheel_params = cfg.sim_wheel.clone();
        wheel_params.seed = cfg.session.seed;
        Ok(Body::Sim {
            wheel: ZeroTorqueOnDrop::new(FaultyWheel::new(
                SimWheel::new(wheel_params),
                &cfg.faults,
            )),
            arm: HumanArm::new(cfg.sim_patient.clone(), dt_s, cfg.session.seed),
            sensing: Box::new(
                SimArmSensing::new(
                    cfg.sim_arm,
                    cfg.arm.sim_mounting,
                    cfg.session.seed,
                    real_time,
                    clock,
                    crate::config::faults::imu_faults(&cfg.faults),
                )
                .and_then(|s| {
                    if cfg.arm.sternum {
                        s.with_sternum(cfg.sim_patient.weakness, cfg.session.seed)
                    } else {
                        Ok(s)
                    }
                })
                .context("simulated arm")?,
            ),
            foot: exercises::SimFoot::default(),
        })
    }

    /// The first force-feedback wheel found, and the first two controller IMUs if there are
    /// two (see `telerehab devices`). `clock` is the session's (a real one: real devices stamp
    /// their readings on it).
    #[cfg(any(target_os = "linux", windows))]
    pub fn first_real_wheel(cfg: &StationConfig, clock: clock::Clock) -> anyhow::Result<Self> {
        // evdev on Linux, DirectInput 8 on Windows; unplugged and plugged back in, it is found
        // again (within the replug grace).
        let wheel = wheel_devices::real_wheel::open_first(cfg.wheel.clone(), clock.clone())
            .context("no usable force-feedback wheel (run `telerehab devices`)")?;
        // Arm sensing is optional: an IMU that cannot be opened (permissions, a flat battery)
        // costs the joint angles, not the exercise.
        let arm = arm::hid::HidArmSensing::open_first_two(
            cfg.arm.geometry,
            cfg.arm.swivel_rad,
            clock::monotonic_ns,
            clock.clone(),
        )
        .unwrap_or_else(|e| {
            tracing::warn!("no arm sensing this session: {e:#}");
            None
        })
        .map(Box::new);
        Ok(Self::real_wheel(wheel, arm, clock))
    }

    /// A real wheel backend (already opened) held by a patient, with optional arm sensing;
    /// `clock` is the clock of the wheel's readings.
    #[cfg(any(target_os = "linux", windows))]
    pub fn real_wheel(
        wheel: Box<dyn Wheel + Send>,
        arm: Option<Box<arm::hid::HidArmSensing>>,
        clock: clock::Clock,
    ) -> Self {
        Body::Evdev {
            wheel: ZeroTorqueOnDrop::new(wheel),
            arm,
            clock,
        }
    }

    /// An exercise starts: the trunk's start posture is taken again.
    pub(super) fn restart_trunk(&mut self) {
        if let Body::Sim { sensing, .. } = self {
            sensing.restart_trunk();
        }
    }

    /// Where the arm sensing is; `None` without IMUs.
    pub(super) fn arm_setup(&self) -> Option<SetupStep> {
        match self {
            Body::Sim { sensing, .. } => Some(sensing.setup_step()),
            #[cfg(any(target_os = "linux", windows))]
            Body::Evdev { arm, .. } => arm.as_ref().map(|a| a.setup_step()),
            Body::Recorded(r) => r.arm_setup(),
        }
    }

    pub(super) fn wheel(&mut self) -> &mut dyn Wheel {
        match self {
            Body::Sim { wheel, .. } => &mut **wheel,
            #[cfg(any(target_os = "linux", windows))]
            Body::Evdev { wheel, .. } => &mut **wheel,
            Body::Recorded(r) => &mut **r,
        }
    }

    /// Now, ns, on the clock of the wheel's readings.
    pub(super) fn now_ns(&self) -> u64 {
        match self {
            Body::Sim { wheel, .. } => wheel.time_ns(),
            #[cfg(any(target_os = "linux", windows))]
            Body::Evdev { clock, .. } => clock.now_ns(),
            Body::Recorded(r) => r.now_ns(),
        }
    }

    /// The encoder step of the wheel, rad (tunes the velocity estimator).
    pub(super) fn encoder_step_rad(&self, cfg: &StationConfig) -> f64 {
        match self {
            Body::Sim { .. } => cfg.sim_wheel.encoder_step_rad,
            #[cfg(any(target_os = "linux", windows))]
            Body::Evdev { wheel, .. } => wheel.profile().ka_rad_per_unit,
            Body::Recorded(r) => r.encoder_step_rad(),
        }
    }

    /// The wheel's dynamics the patient's torque is estimated with: the simulated wheel's
    /// own (also when a simulated session is replayed); for a real wheel the nominal consumer
    /// wheel's ([`assist::WheelDynamics::NOMINAL`]: `telerehab wheel calibrate` does not
    /// measure inertia and friction yet) with its `half_range_rad`.
    /// `dt_s` is the loop period (for the USB delay).
    pub(super) fn wheel_dynamics(
        &self,
        cfg: &StationConfig,
        dt_s: f64,
        half_range_rad: f64,
    ) -> assist::WheelDynamics {
        let sim = match self {
            Body::Sim { .. } => true,
            #[cfg(any(target_os = "linux", windows))]
            Body::Evdev { .. } => false,
            Body::Recorded(r) => !r.real(),
        };
        if !sim {
            // Its range is known (the estimate is absent at its stop), its stop's feel not.
            return assist::WheelDynamics {
                half_range_rad,
                ..assist::WheelDynamics::NOMINAL
            };
        }
        let w = &cfg.sim_wheel;
        // A command is due `delay + jitter` after it is sent (half the jitter on average) and
        // acts from the first step at or after it.
        let delay_ticks = ((w.usb_delay_s + 0.5 * w.usb_jitter_s) / dt_s - 1e-9).ceil();
        assist::WheelDynamics {
            inertia_kg_m2: w.inertia_kg_m2,
            viscous_nm_s_per_rad: w.viscous_nm_s_per_rad,
            coulomb_nm: w.coulomb_nm,
            delay_ticks: delay_ticks.clamp(0.0, 62.0) as usize,
            half_range_rad: w.range_rad,
            end_stop_nm_per_rad: w.end_stop_k_nm_per_rad,
            end_stop_nm_s_per_rad: w.end_stop_b_nm_s_per_rad,
        }
    }

    /// The simulated patient looks at the road and moves the simulated wheel, and the arm
    /// pose is estimated from the simulated IMUs; a real patient moves a real wheel alone.
    pub(super) fn move_to(&mut self, target_rad: f64, read: WheelNow) -> BodyMotion {
        let dt = read.dt_s;
        match self {
            Body::Sim {
                wheel,
                arm,
                sensing,
                ..
            } => {
                let muscle_nm = arm.step(
                    target_rad,
                    wheel.true_angle_rad(),
                    wheel.true_velocity_rad_s(),
                    dt,
                );
                // The arm moves with the rim: what reaches the rim is the muscles' torque
                // less the arm's own inertial torque.
                let hand = wheel.advance_held(dt, muscle_nm, arm.params().inertia_kg_m2);
                let sample =
                    sensing.step(wheel.true_angle_rad(), wheel.true_velocity_rad_s(), read);
                // What the simulation alone observes, on the recording's grid: a replay of
                // the raw inputs takes it from the recording, and the measures must agree.
                BodyMotion {
                    hand_nm: Some(on_grid(hand, TORQUE_QUANTUM_NM)),
                    true_angle_rad: Some(on_grid(wheel.true_angle_rad(), ANGLE_QUANTUM_RAD)),
                    arm: Some(sample),
                    seam: Some(sensing.take_seam()),
                }
            }
            #[cfg(any(target_os = "linux", windows))]
            Body::Evdev { arm, .. } => BodyMotion {
                hand_nm: None,
                true_angle_rad: None,
                arm: arm.as_mut().map(|a| a.step(read)),
                seam: arm.as_mut().map(|a| a.take_seam()),
            },
            Body::Recorded(r) => {
                let m = r.step(read);
                BodyMotion {
                    hand_nm: m.hand_nm,
                    true_angle_rad: m.true_angle_rad,
                    arm: m.arm,
                    seam: m.seam,
                }
            }
        }
    }

    /// The pedals this tick, `dt_s` after the last: the simulated foot aims at the speed in
    /// `speeds` (the car's and the exercise's, m/s; `None`: the exercise in progress is not
    /// driven with the pedals, and the foot rests), a replay gives the recorded ones, and a
    /// real patient's are `live` (as last read).
    pub(super) fn pedals(
        &mut self,
        speeds: Option<(f64, f64)>,
        live: exercises::Pedals,
        dt_s: f64,
    ) -> exercises::Pedals {
        // Only a real wheel's pedals are read live.
        #[cfg(not(any(target_os = "linux", windows)))]
        let _ = live;
        match self {
            Body::Sim { foot, .. } => speeds
                .map_or_else(exercises::Pedals::default, |(ux, aim)| {
                    foot.step(ux, aim, dt_s)
                }),
            #[cfg(any(target_os = "linux", windows))]
            Body::Evdev { .. } => live,
            Body::Recorded(r) => r.pedals(),
        }
    }

    /// Range of motion of each estimated joint angle so far, rad; `None` without arm sensing.
    pub(super) fn range_of_motion_rad(&self) -> Option<[f64; 5]> {
        match self {
            Body::Sim { sensing, .. } => Some(sensing.range_of_motion_rad()),
            #[cfg(any(target_os = "linux", windows))]
            Body::Evdev { arm, .. } => arm.as_ref().map(|a| a.range_of_motion_rad()),
            Body::Recorded(r) => r.range_of_motion_rad(),
        }
    }

    /// Why arm sensing stopped or never started, if it did.
    pub(super) fn arm_failure(&self) -> Option<&arm::ArmFailure> {
        match self {
            Body::Sim { sensing, .. } => sensing.failure(),
            #[cfg(any(target_os = "linux", windows))]
            Body::Evdev { arm, .. } => arm.as_ref().and_then(|a| a.failure()),
            Body::Recorded(r) => r.arm_failure(),
        }
    }
}

/// What the body did this tick (simulation only: a real patient is not observed this way),
/// and what the arm tracker was handed.
pub(super) struct BodyMotion {
    pub(super) hand_nm: Option<f64>,
    pub(super) true_angle_rad: Option<f64>,
    pub(super) arm: Option<ArmSample>,
    pub(super) seam: Option<ArmSeam>,
}
