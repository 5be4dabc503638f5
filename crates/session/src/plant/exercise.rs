//! The exercise the patient does with the wheel: the course of exercises in order, the car on
//! the road (or the dial's desired angle), the scores, and the assist controller that helps.
//! Allocation-free once built.

use super::LoopTime;
use crate::config::StationConfig;
use crate::course::Segment;
use assist::{AssistOutput, Limits, Measurement};
use exercises::{
    AligningTorque, DialScore, DrivingScore, PedalDrive, Pedals, PreviewDriver, Projection,
    SpeedController,
};
use haptic_wheel::HapticRegimen;
use measures::ExerciseScores;
use record::{AssistSample, ScoreSample, VehicleSample};

/// The course and where the patient is in it.
pub(super) struct Exercise {
    course: Vec<Segment>,
    segment: usize,
    segment_start_s: f64,
    pub(super) course_done: bool,
    driver: PreviewDriver,
    cruise: SpeedController,
    feel: AligningTorque,
    projection: Projection,
    driving: DrivingScore,
    dial: DialScore,
    params: exercises::VehicleParams,
    /// The safety supervisor's slew limit, N·m/s (the assist plans within it).
    slew_nm_per_s: f64,
    /// Where the patient aimed last, rad (held while paused).
    last_target_rad: f64,
    /// Each exercise's own scores, in course order (allocated before the session).
    own: Vec<OwnScore>,
    /// What [`Self::exercise_scores`] hands over, built before the session (names included)
    /// so that the haptic thread allocates nothing at its end either.
    handed: Vec<ExerciseScores>,
    /// The session is stopping: its fade-out is no exercise's own time.
    stopping: bool,
    /// The torque ceiling in force, N·m (the strength test's spring ramps up to it).
    pub(super) ceiling_nm: f64,
}

/// One exercise's own scores, kept beside the session's cumulative ones.
#[derive(Clone, Default)]
struct OwnScore {
    driving: DrivingScore,
    dial: DialScore,
    /// The strength test in progress (the strength exercise only).
    strength: Option<exercises::StrengthTest>,
    /// The side it asked for and the push it measured at the last tick it took (1 left,
    /// −1 right, 0 neither; N·m).
    strength_now: (f64, f64),
    /// Exercise time it took, s, when it ran to its end.
    completed_s: Option<f64>,
}

/// What the exercise asks of the wheel this tick.
pub(super) struct ExerciseStep {
    /// Where an ideal patient would hold the wheel, rad: the reference for assistance and
    /// the simulated patient's intention.
    pub(super) target_rad: f64,
    /// The exercise's own torque on the wheel, N·m: the self-aligning road feel, or the
    /// strength test's spring (recorded as the road feel: the chain adds it alike).
    pub(super) road_feel_nm: f64,
    /// The car on the road (`None` in the dial task).
    pub(super) vehicle: Option<VehicleSample>,
    /// The exercise this tick belongs to (0-based).
    pub(super) segment_index: u32,
    /// The exercise is over: the next one starts on the next tick.
    pub(super) finished: bool,
}

/// What the assist controller did this tick.
pub(super) struct AssistStep {
    /// This exercise has an assist controller.
    active: bool,
    pub(super) out: AssistOutput,
}

impl AssistStep {
    /// As recorded on `/assist`.
    pub(super) fn sample(&self) -> AssistSample {
        AssistSample {
            active: self.active,
            torque_nm: self.out.torque_nm,
            reference_rad: self.out.reference_rad,
            error_rad: self.out.error_rad,
            assistance_level: self.out.assistance_level,
            saturated: self.out.saturated,
        }
    }
}

impl Exercise {
    /// The start of `course` (at least one exercise) under a validated `cfg`; the road feel
    /// never asks more than `ceiling_nm` (the chain's at the start).
    pub(super) fn new(cfg: &StationConfig, course: Vec<Segment>, ceiling_nm: f64) -> Self {
        let mut exercise = Self {
            course,
            segment: 0,
            segment_start_s: 0.0,
            course_done: false,
            driver: PreviewDriver::default(),
            cruise: SpeedController {
                target_m_s: 0.0,
                gain_n_per_m_s: 2000.0,
                max_force_n: 8000.0,
            },
            feel: AligningTorque {
                nm_per_kn: cfg.haptic.road_feel_nm_per_kn,
                max_torque_nm: ceiling_nm,
            },
            projection: Projection::default(),
            driving: DrivingScore::default(),
            dial: DialScore::default(),
            params: cfg.vehicle.clone(),
            slew_nm_per_s: cfg.haptic.safety.slew_nm_per_s,
            last_target_rad: 0.0,
            own: Vec::new(),
            handed: Vec::new(),
            stopping: false,
            ceiling_nm,
        };
        let dt_s = 1.0 / cfg.session.loop_rate_hz;
        exercise.own = exercise
            .course
            .iter()
            .map(|seg| OwnScore {
                strength: seg.exercise.strength().map(|s| {
                    exercises::StrengthTest::new(
                        s.stiffness_nm_per_rad,
                        s.ramp_nm_per_s,
                        s.side_s,
                        dt_s,
                    )
                }),
                ..OwnScore::default()
            })
            .collect();
        exercise.handed = exercise
            .course
            .iter()
            .enumerate()
            .map(|(i, seg)| ExerciseScores {
                index: i as u32,
                kind: seg.exercise.name.clone(),
                prescribed_s: seg.exercise.planned_duration_s(),
                driving: None,
                dial: None,
                strength: None,
                sweep: seg.exercise.sweep(),
                completion_time_s: None,
            })
            .collect();
        exercise.projection = exercise.start_projection();
        exercise
    }

    fn start_projection(&self) -> Projection {
        let seg = &self.course[self.segment];
        match &seg.exercise.road {
            Some(road) => {
                let s = seg.exercise.start_state();
                road.project(s.x_m, s.y_m, 0.0)
            }
            None => Projection::default(),
        }
    }

    /// One tick of the exercise with the wheel at `angle` rad: drive the car with it, or
    /// score it against the dial's desired angle. Frozen while `paused`.
    pub(super) fn step(
        &mut self,
        angle: f64,
        paused: bool,
        now: LoopTime,
        pedals: Pedals,
    ) -> ExerciseStep {
        let dt = now.dt_s;
        let segment_index = self.segment as u32;
        let seg = &mut self.course[self.segment];
        let own = &mut self.own[self.segment];
        // An exercise's own scores end with it (the last one goes on through the fade-out).
        let own_counts = !self.stopping && own.completed_s.is_none();
        let t_in = now.t_s - self.segment_start_s;
        let (target, road_feel, vehicle, finished) = match (&mut seg.world, &seg.exercise.road) {
            (Some(world), Some(_)) if paused => {
                let steer = self.params.road_wheel_angle_rad(angle);
                let vehicle = vehicle_sample(world, steer, &self.projection);
                (self.last_target_rad, 0.0, Some(vehicle), false)
            }
            _ if paused => (self.last_target_rad, 0.0, None, false),
            (Some(world), Some(road)) => {
                let steer = self.params.road_wheel_angle_rad(angle);
                let st = world.state();
                self.cruise.target_m_s = seg.exercise.target_speed_m_s(self.projection.s_m);
                let input = if seg.pedals {
                    // The patient's feet, governed at the exercise's speed.
                    PedalDrive {
                        governor: self.cruise.clone(),
                    }
                    .input(pedals, st.ux_m_s, steer)
                } else {
                    self.cruise.input(st.ux_m_s, steer)
                };
                world.step(input, dt);
                let st = world.state();
                self.projection = road.project(st.x_m, st.y_m, self.projection.s_m);
                // Drained in place: no allocation on a contact tick.
                for event in world.drain_events() {
                    self.driving.record(&event);
                    if own_counts {
                        own.driving.record(&event);
                    }
                }
                let lane_m = seg.exercise.lane_width_m;
                self.driving
                    .update(&self.projection, st.yaw_rad, lane_m, dt);
                if own_counts {
                    own.driving.update(&self.projection, st.yaw_rad, lane_m, dt);
                }
                let fyf = world.tyre_forces().front_lateral_n;
                let desired = self.driver.desired_steer_rad(
                    &self.params,
                    &st,
                    &self.projection,
                    road.as_ref(),
                );
                let vehicle = vehicle_sample(world, steer, &self.projection);
                (
                    self.params.hand_wheel_angle_rad(desired),
                    // Self-aligning road feel from the front lateral tyre force (§3.3.4).
                    self.feel.torque_nm(fyf),
                    Some(vehicle),
                    seg.exercise.is_finished(t_in, self.projection.s_m),
                )
            }
            _ if own.strength.is_some() => {
                // The spring holds the wheel; the patient pushes where the test asks.
                let test = own.strength.as_mut().expect("checked just above");
                if own_counts {
                    let st = test.step(angle, self.ceiling_nm, dt);
                    own.strength_now = (
                        st.side.map_or(0.0, exercises::StrengthSide::sign),
                        st.push_nm,
                    );
                    let timed_out = seg.exercise.is_finished(t_in, 0.0);
                    if timed_out && !st.done {
                        // The side in progress ends with the exercise's time.
                        test.time_up();
                    }
                    (test.aim_rad(), st.torque_nm, None, st.done || timed_out)
                } else {
                    // Stopping (the fade-out of a stop or a fault): the torque the wheel
                    // delivers is no longer the spring's, so the test asks for none and
                    // measures nothing; its results stand as they were.
                    (
                        test.aim_rad(),
                        0.0,
                        None,
                        seg.exercise.is_finished(t_in, 0.0),
                    )
                }
            }
            _ => {
                let desired = seg.exercise.desired_angle_rad(t_in).unwrap_or(0.0);
                self.dial.update(desired, angle, dt);
                if own_counts {
                    own.dial.update(desired, angle, dt);
                }
                (desired, 0.0, None, seg.exercise.is_finished(t_in, 0.0))
            }
        };
        self.last_target_rad = target;
        ExerciseStep {
            target_rad: target,
            road_feel_nm: road_feel,
            vehicle,
            segment_index,
            finished,
        }
    }

    /// The assist controller's torque towards `step`'s target with the wheel as `measured`,
    /// within the budget the road feel leaves under the chain's `ceiling_nm` now (a regimen
    /// may have lowered it: the chain's limiter would otherwise clip torque the assist
    /// believes it delivered). None while `paused` or without an assist controller.
    pub(super) fn assist(
        &mut self,
        step: &ExerciseStep,
        measured: Measurement,
        ceiling_nm: f64,
        paused: bool,
        dt_s: f64,
    ) -> AssistStep {
        let seg = &mut self.course[self.segment];
        // The strength test measures the patient alone: no assist pushes with them.
        let strength = seg.exercise.strength().is_some();
        let active = seg.assist.is_some() && !strength;
        let out = match &mut seg.assist {
            Some(a) if !paused && !strength => {
                let limits = Limits {
                    ceiling_nm: (ceiling_nm - step.road_feel_nm.abs()).max(0.0),
                    slew_nm_per_s: self.slew_nm_per_s,
                };
                a.step(measured, step.target_rad, limits, dt_s)
            }
            _ => Default::default(),
        };
        AssistStep { active, out }
    }

    /// The car's forward speed and the exercise's speed there, m/s, while the exercise in
    /// progress is driven with the pedals (what a foot on them aims at); `None` otherwise.
    pub(super) fn pedal_speeds_m_s(&self) -> Option<(f64, f64)> {
        let seg = &self.course[self.segment];
        match (&seg.world, seg.pedals) {
            (Some(world), true) => Some((
                world.state().ux_m_s,
                seg.exercise.target_speed_m_s(self.projection.s_m),
            )),
            _ => None,
        }
    }

    /// The session's time is up: a strength test's side in progress stops at its time limit
    /// with what it measured (the session's last tick can come a tick before the side's own
    /// limit), unless the test already ended.
    pub(super) fn time_up(&mut self) {
        let own = &mut self.own[self.segment];
        if let (Some(test), None) = (own.strength.as_mut(), own.completed_s) {
            test.time_up();
        }
    }

    /// The session is stopping: what follows is its fade-out, no exercise's own time.
    pub(super) fn stop(&mut self) {
        self.stopping = true;
    }

    /// The break after exercise `segment` of the course, if any.
    pub(super) fn break_after(&self, segment: usize) -> Option<crate::course::Break> {
        self.course.get(segment).and_then(|s| s.break_after)
    }

    /// The trunk cue's threshold of the exercise in progress, deg (`None`: no cue).
    pub(super) fn trunk_cue_deg(&self) -> Option<f64> {
        self.course[self.segment].trunk_cue_deg
    }

    /// Move on to the next exercise at exercise time `t_s`, and the haptic settings it
    /// brings; or mark the course done after the last one.
    pub(super) fn next_segment(&mut self, t_s: f64) -> Option<&HapticRegimen> {
        // The first end counts: the last exercise goes on through the session's fade-out.
        let took_s = t_s - self.segment_start_s;
        self.own[self.segment].completed_s.get_or_insert(took_s);
        if self.segment + 1 >= self.course.len() {
            self.course_done = true;
            return None;
        }
        self.segment += 1;
        self.segment_start_s = t_s;
        self.projection = self.start_projection();
        Some(&self.course[self.segment].haptic)
    }

    /// Each exercise's own scores so far, of the exercises started (in course order), handed
    /// over once (a second call gives none): without allocating, at the session's end.
    pub(super) fn exercise_scores(&mut self) -> Vec<ExerciseScores> {
        let mut handed = std::mem::take(&mut self.handed);
        handed.truncate(self.segment + 1);
        for ((out, seg), own) in handed.iter_mut().zip(&self.course).zip(&self.own) {
            let road = seg.exercise.road.is_some();
            out.strength = own.strength.as_ref().map(|t| t.summary());
            out.driving = road.then(|| own.driving.summary());
            out.dial = (!road && out.strength.is_none()).then(|| own.dial.summary());
            out.completion_time_s = own.completed_s;
        }
        handed
    }

    /// The scores so far, as recorded on `/score`.
    pub(super) fn score(&self, segment_index: u32, active_s: f64, paused: bool) -> ScoreSample {
        let lane = self.driving.lane();
        let dial = self.dial.summary();
        ScoreSample {
            exercise_index: segment_index,
            rms_lateral_m: lane.rms_m(),
            max_lateral_m: lane.max_abs_m(),
            pct_in_lane: lane.pct_in_lane(),
            cone_hits: self.driving.summary().cone_hits,
            dial_rms_error_deg: dial.rms_error_deg,
            active_s,
            paused,
            strength: self.own.get(segment_index as usize).and_then(|own| {
                let test = own.strength.as_ref()?;
                let [peak_left_nm, peak_right_nm] = test.peaks_nm();
                Some(record::StrengthNow {
                    side: own.strength_now.0,
                    push_nm: own.strength_now.1,
                    peak_left_nm,
                    peak_right_nm,
                })
            }),
        }
    }
}

/// The car's state on the road as recorded, with the road-wheel angle `steer_rad` the wheel
/// asks for now.
fn vehicle_sample(
    world: &exercises::World,
    steer_rad: f64,
    projection: &Projection,
) -> VehicleSample {
    let st = world.state();
    VehicleSample {
        x_m: st.x_m,
        y_m: st.y_m,
        yaw_rad: st.yaw_rad,
        ux_m_s: st.ux_m_s,
        uy_m_s: st.uy_m_s,
        r_rad_s: st.r_rad_s,
        steer_rad,
        front_lateral_n: world.tyre_forces().front_lateral_n,
        s_m: projection.s_m,
        lateral_m: projection.lateral_m,
    }
}
