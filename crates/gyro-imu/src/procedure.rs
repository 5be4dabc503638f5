//! The guided mounting procedure, tick by tick: what the patient is asked to do, whether they
//! did it, and the mounting that comes out (thesis §4.2.2: the gyros sit anywhere on the links,
//! turned any way).
//!
//! 1. **Hold still**, wheel centred, for `still_s`: any rate above `still_rate_rad_s` on either
//!    IMU restarts this step (a patient settling in is not "still").
//! 2. **Turn the wheel** slowly left and right through at least `min_sweep_rad` of range for
//!    `sweep_s`.
//!
//! The two IMUs may be strapped on either way round (which controller is on the upper arm is
//! not something to ask a patient): both assignments are calibrated side by side and the one
//! whose gravity directions fit the arm model better wins. The procedure gives up after
//! `max_s` with a message that says what to do next time. Pure: time comes in as timestamps;
//! no allocation per step after [`GuidedMounting::new`].

use crate::arm::ArmGeometry;
use crate::device::ImuSample;
use crate::error::{ImuError, check_range};
use crate::mounting::{MountingCalibrator, MountingReport};
use crate::pose::Mounting;

/// Durations and thresholds of the procedure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProcedureConfig {
    /// Length of the hold-still step, s.
    pub still_s: f64,
    /// Length of the wheel-turning step, s.
    pub sweep_s: f64,
    /// Wheel range (max − min) the turning step must cover, rad.
    pub min_sweep_rad: f64,
    /// Largest gyro rate that still counts as holding still, rad/s.
    pub still_rate_rad_s: f64,
    /// The procedure fails after this long, s.
    pub max_s: f64,
    /// Largest acceptable gravity misfit of the chosen assignment, rad.
    pub max_gravity_misfit_rad: f64,
    /// IMU samples the turning step may store (preallocated), count.
    pub max_sweep_samples: usize,
}

impl Default for ProcedureConfig {
    fn default() -> Self {
        Self {
            still_s: 3.0,
            sweep_s: 15.0,
            min_sweep_rad: 1.0,
            still_rate_rad_s: 0.15,
            max_s: 90.0,
            max_gravity_misfit_rad: 10f64.to_radians(),
            max_sweep_samples: 90_000,
        }
    }
}

impl ProcedureConfig {
    /// Check every field; the error names the field and its allowed range.
    pub fn validate(&self) -> Result<(), ImuError> {
        check_range("still_s", self.still_s, 0.5, 30.0, "[0.5, 30] s")?;
        check_range("sweep_s", self.sweep_s, 2.0, 120.0, "[2, 120] s")?;
        check_range(
            "min_sweep_rad",
            self.min_sweep_rad,
            0.1,
            3.0,
            "[0.1, 3] rad",
        )?;
        check_range(
            "still_rate_rad_s",
            self.still_rate_rad_s,
            0.01,
            1.0,
            "[0.01, 1] rad/s",
        )?;
        check_range(
            "max_s",
            self.max_s,
            self.still_s + self.sweep_s,
            600.0,
            "[still_s + sweep_s, 600] s",
        )?;
        check_range(
            "max_gravity_misfit_rad",
            self.max_gravity_misfit_rad,
            0.001,
            1.0,
            "[0.001, 1] rad",
        )
    }
}

/// What the patient should be doing now.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Prompt {
    /// Hold the wheel still, centred; `remaining_s` to go.
    HoldStill {
        /// Time left in this step, s.
        remaining_s: f64,
    },
    /// Turn the wheel slowly left and right.
    TurnWheel {
        /// Time left in this step, s.
        remaining_s: f64,
        /// Range covered so far over the range required, 0–1.
        coverage: f64,
    },
    /// The data are in: call [`GuidedMounting::solve_now`] here, or (on a real-time thread)
    /// move the procedure elsewhere, [`GuidedMounting::solve`] it there (tens of ms) and hand
    /// the result to [`GuidedMounting::set_outcome`]. Until then every step returns this.
    ReadyToSolve,
    /// Finished: see [`GuidedMounting::outcome`].
    Done,
}

/// The result of a finished procedure.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuidedOutcome {
    /// Sensor-to-segment rotations, with `upper` the upper-arm IMU's.
    pub mounting: Mounting,
    /// The second IMU given to [`GuidedMounting::step`] is on the upper arm.
    pub swapped: bool,
    /// Diagnostics of the chosen assignment.
    pub report: MountingReport,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Step {
    Still,
    Sweep,
    Solve,
    Finished,
}

/// The procedure's state (see the module docs).
#[derive(Debug)]
pub struct GuidedMounting {
    cfg: ProcedureConfig,
    /// First IMU on the upper arm.
    direct: MountingCalibrator,
    /// Second IMU on the upper arm.
    swapped: MountingCalibrator,
    step: Step,
    start_ns: Option<u64>,
    step_start_ns: u64,
    wheel_min_rad: f64,
    wheel_max_rad: f64,
    sweep_samples: usize,
    outcome: Option<Result<GuidedOutcome, ImuError>>,
}

impl GuidedMounting {
    /// A procedure for an arm of `geometry` holding the wheel with elbow swivel `swivel_rad`.
    pub fn new(
        geometry: ArmGeometry,
        swivel_rad: f64,
        cfg: ProcedureConfig,
    ) -> Result<Self, ImuError> {
        cfg.validate()?;
        let calibrator = || -> Result<MountingCalibrator, ImuError> {
            let mut c = MountingCalibrator::new(geometry, swivel_rad)?;
            c.reserve_motion(cfg.max_sweep_samples);
            Ok(c)
        };
        Ok(Self {
            cfg,
            direct: calibrator()?,
            swapped: calibrator()?,
            step: Step::Still,
            start_ns: None,
            step_start_ns: 0,
            wheel_min_rad: f64::INFINITY,
            wheel_max_rad: f64::NEG_INFINITY,
            sweep_samples: 0,
            outcome: None,
        })
    }

    /// The result once [`Prompt::Done`]: the mounting, or why there is none (with what to do).
    pub fn outcome(&self) -> Option<&Result<GuidedOutcome, ImuError>> {
        self.outcome.as_ref()
    }

    /// Move the result out once [`Prompt::Done`] (no copy, no allocation); `None` before, or
    /// if already taken.
    pub fn take_outcome(&mut self) -> Option<Result<GuidedOutcome, ImuError>> {
        self.outcome.take()
    }

    /// Feed one tick at `t_ns`: the wheel angle and rate (rad, rad/s) and the latest sample of
    /// each IMU. Returns the prompt to show now.
    pub fn step(
        &mut self,
        t_ns: u64,
        wheel_rad: f64,
        wheel_rate_rad_s: f64,
        a: &ImuSample,
        b: &ImuSample,
    ) -> Prompt {
        match self.step {
            Step::Finished => return Prompt::Done,
            Step::Solve => return Prompt::ReadyToSolve,
            Step::Still | Step::Sweep => {}
        }
        let start = *self.start_ns.get_or_insert(t_ns);
        let elapsed_s = |since: u64| t_ns.saturating_sub(since) as f64 * 1e-9;
        if elapsed_s(start) > self.cfg.max_s {
            let why = match self.step {
                Step::Still => {
                    "the sensors never stayed still: rest the hands on the wheel and hold it centred for a few seconds"
                }
                _ => {
                    "the wheel did not turn far enough: turn it slowly left and right, as far as is comfortable"
                }
            };
            return self.finish(Err(ImuError::Procedure(why)));
        }
        match self.step {
            Step::Still => {
                let moving = a.rate_rad_s.norm() > self.cfg.still_rate_rad_s
                    || b.rate_rad_s.norm() > self.cfg.still_rate_rad_s;
                if moving {
                    // Start the still step again, forgetting the samples so far.
                    self.step_start_ns = t_ns;
                    self.direct.restart();
                    self.swapped.restart();
                } else {
                    let added = self
                        .direct
                        .add_still(wheel_rad, a, b)
                        .and_then(|()| self.swapped.add_still(wheel_rad, b, a));
                    if let Err(e) = added {
                        return self.finish(Err(e));
                    }
                }
                let left = self.cfg.still_s - elapsed_s(self.step_start_ns);
                if left <= 0.0 {
                    self.step = Step::Sweep;
                    self.step_start_ns = t_ns;
                }
                Prompt::HoldStill {
                    remaining_s: left.max(0.0),
                }
            }
            Step::Sweep => {
                if self.sweep_samples < self.cfg.max_sweep_samples {
                    let added = self
                        .direct
                        .add_motion(wheel_rad, wheel_rate_rad_s, a, b)
                        .and_then(|()| self.swapped.add_motion(wheel_rad, wheel_rate_rad_s, b, a));
                    if let Err(e) = added {
                        return self.finish(Err(e));
                    }
                    self.sweep_samples += 1;
                }
                if wheel_rad.is_finite() {
                    self.wheel_min_rad = self.wheel_min_rad.min(wheel_rad);
                    self.wheel_max_rad = self.wheel_max_rad.max(wheel_rad);
                }
                let coverage = ((self.wheel_max_rad - self.wheel_min_rad) / self.cfg.min_sweep_rad)
                    .clamp(0.0, 1.0);
                let left = self.cfg.sweep_s - elapsed_s(self.step_start_ns);
                if left <= 0.0 && coverage >= 1.0 {
                    self.step = Step::Solve;
                    return Prompt::ReadyToSolve;
                }
                Prompt::TurnWheel {
                    remaining_s: left.max(0.0),
                    coverage,
                }
            }
            Step::Solve => Prompt::ReadyToSolve,
            Step::Finished => Prompt::Done,
        }
    }

    /// Solve and finish in place (after [`Prompt::ReadyToSolve`]; offline use).
    pub fn solve_now(&mut self) -> Prompt {
        let outcome = self.solve();
        self.set_outcome(outcome)
    }

    /// Finish with `outcome` (from [`GuidedMounting::solve`]); returns [`Prompt::Done`].
    pub fn set_outcome(&mut self, outcome: Result<GuidedOutcome, ImuError>) -> Prompt {
        self.finish(outcome)
    }

    fn finish(&mut self, outcome: Result<GuidedOutcome, ImuError>) -> Prompt {
        self.step = Step::Finished;
        self.outcome = Some(outcome);
        Prompt::Done
    }

    /// The mounting from the data so far: both assignments are solved and the one with the
    /// smaller gravity misfit wins. Takes tens of milliseconds (see `BENCHMARKS.md`): keep it
    /// off a real-time thread.
    pub fn solve(&self) -> Result<GuidedOutcome, ImuError> {
        let misfit = |r: &MountingReport| r.gravity_misfit_rad.0 + r.gravity_misfit_rad.1;
        let best = match (self.direct.finish(), self.swapped.finish()) {
            (Ok(d), Ok(s)) if misfit(&s) < misfit(&d) => (s, true),
            (Ok(d), _) => (d, false),
            (Err(_), Ok(s)) => (s, true),
            (Err(e), Err(_)) => return Err(e),
        };
        let (report, swapped) = best;
        let worst = report.gravity_misfit_rad.0.max(report.gravity_misfit_rad.1);
        if worst > self.cfg.max_gravity_misfit_rad {
            return Err(ImuError::Calibration(format!(
                "the sensors do not fit the arm model (gravity off by {:.1}°): check that one sensor is on the upper arm and one on the forearm, strapped firmly",
                worst.to_degrees()
            )));
        }
        Ok(GuidedOutcome {
            mounting: report.mounting,
            swapped,
            report,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sim::arm::{PatientArmConfig, SimArm, sine_road};
    use crate::so3;
    use nalgebra::Vector3;

    /// A patient who holds the elbow swivel constant.
    fn steady_swivel() -> PatientArmConfig {
        PatientArmConfig {
            swivel_amp_rad: 0.0,
            swivel_per_wheel: 0.0,
            ..PatientArmConfig::default()
        }
    }

    /// Runs the procedure on a simulated arm of `cfg` whose patient follows the prompts; the
    /// IMUs reach the procedure as (first, second) = (upper, fore), or swapped.
    fn run(
        cfg: PatientArmConfig,
        mu: nalgebra::UnitQuaternion<f64>,
        mf: nalgebra::UnitQuaternion<f64>,
        swap: bool,
        fidget_s: f64,
        sweep_amp_rad: f64,
    ) -> (GuidedMounting, f64) {
        let mut arm = SimArm::consumer_mems(cfg, mu, mf, 5).unwrap();
        let mut proc = GuidedMounting::new(
            cfg.geometry,
            cfg.swivel_mean_rad,
            ProcedureConfig::default(),
        )
        .unwrap();
        let dt = 0.002;
        let mut sweep_t = 0.0;
        let mut t = 0.0;
        let mut prompt = Prompt::HoldStill { remaining_s: 3.0 };
        while prompt != Prompt::Done {
            let (w, wd) = match prompt {
                // The patient settles in for `fidget_s` before holding still.
                Prompt::HoldStill { .. } if t < fidget_s => sine_road(t, 0.3, 0.5, 0.0, 0.1),
                Prompt::HoldStill { .. } => (0.0, 0.0),
                _ => {
                    sweep_t += dt;
                    sine_road(sweep_t, sweep_amp_rad, 0.25, 0.0, 0.1)
                }
            };
            arm.step((t * 1e9) as u64, w, wd, dt).unwrap();
            let (u, f) = arm.latest().unwrap();
            let (a, b) = if swap { (f, u) } else { (u, f) };
            prompt = proc.step((t * 1e9) as u64, w, wd, &a, &b);
            if prompt == Prompt::ReadyToSolve {
                prompt = proc.solve_now();
            }
            t += dt;
        }
        (proc, t)
    }

    fn random_mounting(seed: u64) -> nalgebra::UnitQuaternion<f64> {
        let s = seed as f64;
        so3::exp_quat(&Vector3::new(
            (1.3 * s).sin() * 2.5,
            (2.1 * s).cos() * 2.5,
            (0.7 * s).sin() * 2.5,
        ))
    }

    /// Runs the procedure for four seeded mountings, two of them with the IMUs swapped, and
    /// asserts the assignment, the mountings within 2° and the nominal duration.
    fn four_patients_get_the_assignment_and_mounting_within_2_deg(cfg: PatientArmConfig) {
        for (seed, swap) in [(1, false), (2, true), (3, false), (4, true)] {
            let (mu, mf) = (random_mounting(seed), random_mounting(seed + 10));
            let (proc, t) = run(cfg, mu, mf, swap, 0.0, 1.0);
            let out = proc.outcome().unwrap().as_ref().unwrap();
            assert_eq!(
                out.swapped, swap,
                "seed {seed}: which IMU is on the upper arm"
            );
            let eu = so3::angle_between(&out.mounting.upper, &mu).to_degrees();
            let ef = so3::angle_between(&out.mounting.fore, &mf).to_degrees();
            println!(
                "seed {seed}: upper {eu:.2}°, fore {ef:.2}°, swivel gain {:.3}, gravity misfit \
                 {:.2}°/{:.2}°",
                out.report.swivel_per_wheel,
                out.report.gravity_misfit_rad.0.to_degrees(),
                out.report.gravity_misfit_rad.1.to_degrees()
            );
            assert!(eu < 2.0 && ef < 2.0, "seed {seed}: upper {eu}°, fore {ef}°");
            assert!(t < 20.0, "finished in the nominal 18 s, took {t}");
        }
    }

    #[test]
    fn a_patient_who_follows_the_prompts_gets_the_mounting_within_2_deg() {
        four_patients_get_the_assignment_and_mounting_within_2_deg(steady_swivel());
    }

    #[test]
    fn swivel_following_the_wheel_and_wandering_keeps_the_assignment_and_mounting_within_2_deg() {
        // The default patient: swivel 0.2 rad per rad of wheel, wandering ±8.6° at 0.07 Hz.
        four_patients_get_the_assignment_and_mounting_within_2_deg(PatientArmConfig::default());
    }

    #[test]
    fn moving_during_the_still_step_restarts_it() {
        let (proc, t) = run(
            steady_swivel(),
            random_mounting(5),
            random_mounting(6),
            false,
            2.0,
            1.0,
        );
        assert!(proc.outcome().unwrap().is_ok());
        assert!(
            t > 2.0 + 3.0 + 15.0 - 0.1,
            "the 3 s still step began after the fidgeting: {t}"
        );
    }

    #[test]
    fn too_little_wheel_motion_fails_with_advice() {
        let (proc, t) = run(
            steady_swivel(),
            random_mounting(7),
            random_mounting(8),
            false,
            0.0,
            0.2,
        );
        let err = proc.outcome().unwrap().as_ref().unwrap_err().to_string();
        assert!(err.contains("did not turn far enough"), "{err}");
        assert!((t - 90.0).abs() < 0.1, "gave up at max_s: {t}");
    }

    #[test]
    fn bad_settings_name_the_field() {
        let cfg = ProcedureConfig {
            sweep_s: 0.0,
            ..ProcedureConfig::default()
        };
        let err = GuidedMounting::new(ArmGeometry::default(), 0.0, cfg).unwrap_err();
        assert!(err.to_string().contains("sweep_s"), "{err}");
    }
}
