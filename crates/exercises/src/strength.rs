//! The strength test: the wheel held at the centre by a stiff spring whose torque limit ramps
//! slowly up to the torque ceiling, the patient pushing left, then (after a rest) right. Each
//! side stops at the first of: the spring's torque reaching the ceiling (the patient is at
//! least that strong), the side's time limit, or the patient letting go.
//!
//! What is measured is the torque the spring commands, `min(k·θ, L(t))` for the wheel angle
//! θ (positive to the left, the vehicle's convention) and the ramped limit L: held nearly
//! still, the wheel's torque balances the patient's, so the spring's torque is the patient's
//! isometric torque (no estimator of the hand's torque is needed). Per side: the peak, and the
//! sustained torque, the highest torque held for at least [`SUSTAIN_S`] (the largest minimum
//! over any window of that length).

use std::collections::VecDeque;

/// Window of the sustained torque, s: the highest torque held this long.
pub const SUSTAIN_S: f64 = 1.0;
/// Rest between the two sides, s (no torque: the patient lets go).
pub const REST_S: f64 = 3.0;
/// Fraction of the ceiling at which the ceiling counts as reached.
pub const CEILING_FRACTION: f64 = 0.98;
/// Torque the patient must have held before letting go can end a side, N·m.
pub const LOADED_NM: f64 = 0.2;
/// Below this fraction of the side's peak for [`LET_GO_S`], the patient has let go.
pub const LET_GO_FRACTION: f64 = 0.2;
/// How long the torque must stay low to count as letting go, s.
pub const LET_GO_S: f64 = 0.5;
/// Damping of the spring, N·m·s/rad: a stiff spring alone rings on the wheel's inertia (some
/// 6 Hz with the simulated wheel), its torque swinging well above and below the patient's
/// push, so that its peak would be the ringing's, not the patient's. The damper's torque is
/// not measured: held still, it is zero.
pub const DAMPING_NM_S_PER_RAD: f64 = 1.0;
/// Low-pass cut-off of the wheel's speed the damper uses (from the angle's differences), Hz.
const SPEED_LOWPASS_HZ: f64 = 30.0;
/// The wheel moving slower than this for [`HELD_S`] counts as held: the push is measured,
/// rad/s (29°/s).
pub const HELD_RAD_S: f64 = 0.5;
/// How long the wheel must be slower than [`HELD_RAD_S`] to count as held, s.
pub const HELD_S: f64 = 0.1;
/// Where the patient is asked to push, rad (the simulated patient aims there): 30°.
pub const PUSH_AIM_RAD: f64 = std::f64::consts::FRAC_PI_6;

/// A side of the test.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StrengthSide {
    /// Pushing to the left (positive wheel angle).
    Left,
    /// Pushing to the right (negative wheel angle).
    Right,
}

impl StrengthSide {
    /// +1 to the left, −1 to the right.
    pub fn sign(self) -> f64 {
        match self {
            Self::Left => 1.0,
            Self::Right => -1.0,
        }
    }
}

/// Why a side stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StrengthStop {
    /// The spring's torque reached the torque ceiling.
    Ceiling,
    /// The side's time limit passed.
    TimeLimit,
    /// The patient let go.
    LetGo,
}

/// One side's result.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SideResult {
    /// Highest torque, N·m.
    pub peak_nm: f64,
    /// Highest torque held for [`SUSTAIN_S`], N·m (0 when the side lasted less).
    pub sustained_nm: f64,
    /// Why it stopped.
    pub stop: StrengthStop,
    /// How long it lasted, s.
    pub duration_s: f64,
}

/// Both sides' results (a side not done is `None`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct StrengthSummary {
    /// Pushing left.
    pub left: Option<SideResult>,
    /// Pushing right.
    pub right: Option<SideResult>,
}

/// What the test asks of the wheel this tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StrengthStep {
    /// The spring's torque on the wheel, N·m (within the ceiling).
    pub torque_nm: f64,
    /// The side in progress (`None` while resting or done).
    pub side: Option<StrengthSide>,
    /// The patient's torque the spring balances, in the side's direction, N·m (≥ 0).
    pub push_nm: f64,
    /// The spring's torque limit now, N·m.
    pub limit_nm: f64,
    /// Both sides are over.
    pub done: bool,
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum Phase {
    Side(StrengthSide),
    Rest,
    Done,
}

/// The strength test in progress (allocation-free once built).
#[derive(Clone, Debug)]
pub struct StrengthTest {
    stiffness_nm_per_rad: f64,
    ramp_nm_per_s: f64,
    side_s: f64,
    phase: Phase,
    /// Time in the phase, s.
    t_s: f64,
    peak_nm: f64,
    sustained_nm: f64,
    /// Time the torque has been low after the patient loaded the spring, s.
    low_s: f64,
    loaded: bool,
    /// The sliding window's minimum candidates: (time, torque), torque increasing.
    window: VecDeque<(f64, f64)>,
    summary: StrengthSummary,
    /// The last tick's wheel angle, rad, and the wheel's low-passed speed, rad/s.
    last_angle_rad: Option<f64>,
    speed_rad_s: f64,
    /// How long the wheel has been slower than [`HELD_RAD_S`], s.
    still_s: f64,
}

impl StrengthTest {
    /// A test with a spring of `stiffness_nm_per_rad` whose limit rises at `ramp_nm_per_s`,
    /// each side lasting at most `side_s`, ticking about every `dt_s`.
    pub fn new(stiffness_nm_per_rad: f64, ramp_nm_per_s: f64, side_s: f64, dt_s: f64) -> Self {
        let per_window = (SUSTAIN_S / dt_s.max(1e-5)).ceil() as usize + 4;
        Self {
            stiffness_nm_per_rad,
            ramp_nm_per_s,
            side_s,
            phase: Phase::Side(StrengthSide::Left),
            t_s: 0.0,
            peak_nm: 0.0,
            sustained_nm: 0.0,
            low_s: 0.0,
            loaded: false,
            window: VecDeque::with_capacity(per_window.min(1 << 20)),
            summary: StrengthSummary::default(),
            last_angle_rad: None,
            speed_rad_s: 0.0,
            still_s: 0.0,
        }
    }

    /// The results so far.
    pub fn summary(&self) -> StrengthSummary {
        self.summary
    }

    /// The side in progress and its peak so far, N·m (`None` while resting or done).
    pub fn side_peak_nm(&self) -> Option<(StrengthSide, f64)> {
        match self.phase {
            Phase::Side(side) => Some((side, self.peak_nm)),
            _ => None,
        }
    }

    /// Each side's highest push, left then right, N·m: a finished side's result, the side in
    /// progress's so far, `None` for a side not started.
    pub fn peaks_nm(&self) -> [Option<f64>; 2] {
        let now = self.side_peak_nm();
        [
            (StrengthSide::Left, self.summary.left),
            (StrengthSide::Right, self.summary.right),
        ]
        .map(|(side, done)| {
            done.map(|r| r.peak_nm)
                .or_else(|| now.filter(|(s, _)| *s == side).map(|(_, p)| p))
        })
    }

    /// Where the patient is asked to aim the wheel now, rad.
    pub fn aim_rad(&self) -> f64 {
        match self.phase {
            Phase::Side(s) => s.sign() * PUSH_AIM_RAD,
            _ => 0.0,
        }
    }

    /// One tick `dt_s` long with the wheel at `angle_rad` under a torque ceiling of
    /// `ceiling_nm`.
    pub fn step(&mut self, angle_rad: f64, ceiling_nm: f64, dt_s: f64) -> StrengthStep {
        let ceiling_nm = if ceiling_nm.is_finite() {
            ceiling_nm.max(0.0)
        } else {
            0.0
        };
        let angle = if angle_rad.is_finite() {
            angle_rad
        } else {
            0.0
        };
        let idle = |done| StrengthStep {
            torque_nm: 0.0,
            side: None,
            push_nm: 0.0,
            limit_nm: 0.0,
            done,
        };
        let side = match self.phase {
            Phase::Done => return idle(true),
            Phase::Rest => {
                self.t_s += dt_s;
                if self.t_s >= REST_S {
                    self.start(Phase::Side(StrengthSide::Right));
                }
                return idle(false);
            }
            Phase::Side(s) => s,
        };
        let limit = (self.ramp_nm_per_s * self.t_s).min(ceiling_nm);
        let spring = (self.stiffness_nm_per_rad * angle).clamp(-limit, limit);
        // What is measured is the spring's torque; the damper only stops the ringing.
        let push = (side.sign() * spring).max(0.0);
        let speed = self.speed(angle, dt_s);
        let held =
            (self.stiffness_nm_per_rad * angle + DAMPING_NM_S_PER_RAD * speed).clamp(-limit, limit);
        // Only a wheel held (nearly) still balances the patient's push: a moving one has the
        // wheel's inertia in it (the spring carrying the wheel back once its limit passed the
        // push, or the wheel swinging about the balance, still only at its turning points).
        self.still_s = if speed.abs() <= HELD_RAD_S {
            self.still_s + dt_s
        } else {
            0.0
        };
        let held_still = self.still_s >= HELD_S;
        self.take(push, dt_s, held_still);
        let stop = if held_still && ceiling_nm > 0.0 && push >= CEILING_FRACTION * ceiling_nm {
            Some(StrengthStop::Ceiling)
        } else if self.loaded && self.low_s >= LET_GO_S {
            Some(StrengthStop::LetGo)
        } else if self.t_s >= self.side_s {
            Some(StrengthStop::TimeLimit)
        } else {
            None
        };
        self.t_s += dt_s;
        if let Some(stop) = stop {
            let result = SideResult {
                peak_nm: self.peak_nm,
                sustained_nm: self.sustained_nm,
                stop,
                duration_s: self.t_s,
            };
            match side {
                StrengthSide::Left => {
                    self.summary.left = Some(result);
                    self.start(Phase::Rest);
                }
                StrengthSide::Right => {
                    self.summary.right = Some(result);
                    self.start(Phase::Done);
                }
            }
        }
        StrengthStep {
            torque_nm: -held,
            side: Some(side),
            push_nm: push,
            limit_nm: limit,
            done: self.phase == Phase::Done,
        }
    }

    /// The wheel's speed from the angle's differences, low-passed, rad/s.
    fn speed(&mut self, angle: f64, dt_s: f64) -> f64 {
        if let Some(last) = self.last_angle_rad
            && dt_s > 0.0
        {
            let a = 1.0 - (-std::f64::consts::TAU * SPEED_LOWPASS_HZ * dt_s).exp();
            self.speed_rad_s += a * ((angle - last) / dt_s - self.speed_rad_s);
        }
        self.last_angle_rad = Some(angle);
        self.speed_rad_s
    }

    /// The exercise's time is up: a side still in progress stops at its time limit with what
    /// it measured (the exercise's duration is both sides' limits and the rest, so the last
    /// side can reach it a tick or two before its own limit), and the test is done.
    pub fn time_up(&mut self) {
        if let Phase::Side(side) = self.phase {
            let result = Some(SideResult {
                peak_nm: self.peak_nm,
                sustained_nm: self.sustained_nm,
                stop: StrengthStop::TimeLimit,
                duration_s: self.t_s,
            });
            match side {
                StrengthSide::Left => self.summary.left = result,
                StrengthSide::Right => self.summary.right = result,
            }
        }
        self.start(Phase::Done);
    }

    /// Take the patient's torque `push` at the phase's time, for a tick `dt_s` long: peak,
    /// sustained, letting go.
    fn take(&mut self, push: f64, dt_s: f64, measured: bool) {
        if measured {
            self.hold(push);
        }
        if push >= LOADED_NM {
            self.loaded = true;
        }
        if self.loaded && push < LET_GO_FRACTION * self.peak_nm {
            self.low_s += dt_s;
        } else {
            self.low_s = 0.0;
        }
    }

    /// Take the patient's torque `push` into the peak and the sustained torque.
    fn hold(&mut self, push: f64) {
        self.peak_nm = self.peak_nm.max(push);
        let t = self.t_s;
        while self.window.back().is_some_and(|b| b.1 >= push) {
            self.window.pop_back();
        }
        if self.window.len() < self.window.capacity() {
            self.window.push_back((t, push));
        }
        while self
            .window
            .front()
            .is_some_and(|f| f.0 < t - SUSTAIN_S - 1e-9)
        {
            self.window.pop_front();
        }
        if t >= SUSTAIN_S - 1e-9
            && let Some(f) = self.window.front()
        {
            self.sustained_nm = self.sustained_nm.max(f.1);
        }
    }

    fn start(&mut self, phase: Phase) {
        self.phase = phase;
        self.t_s = 0.0;
        self.peak_nm = 0.0;
        self.sustained_nm = 0.0;
        self.low_s = 0.0;
        self.loaded = false;
        self.window.clear();
        (self.last_angle_rad, self.speed_rad_s, self.still_s) = (None, 0.0, 0.0);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DT_S: f64 = 1e-3;
    const K: f64 = 40.0;

    /// Run a test whose patient pushes `push_nm(side, t)` against a wheel held nearly still (the
    /// wheel's angle is the one at which the spring balances the push, or where the push
    /// carries it past the limit), until done; the ticks of each side.
    fn run(
        ceiling_nm: f64,
        side_s: f64,
        push_nm: impl Fn(StrengthSide, f64) -> f64,
    ) -> (StrengthSummary, Vec<StrengthStep>) {
        let mut test = StrengthTest::new(K, 0.5, side_s, DT_S);
        let mut angle = 0.0;
        let mut t_in = 0.0;
        let mut last_side = None;
        let mut steps = Vec::new();
        for _ in 0..200_000 {
            let step = test.step(angle, ceiling_nm, DT_S);
            steps.push(step);
            if step.done {
                break;
            }
            if step.side != last_side {
                t_in = 0.0;
                last_side = step.side;
            }
            t_in += DT_S;
            // Quasi-static: the wheel settles where the spring balances the hand, or goes
            // 0.2 rad further when the hand beats the limit.
            angle = match step.side {
                Some(s) => {
                    let p = push_nm(s, t_in);
                    let held = p / K;
                    let beaten = p > step.limit_nm + 1e-12;
                    s.sign()
                        * if beaten {
                            held.max(step.limit_nm / K) + 0.2
                        } else {
                            held
                        }
                }
                None => 0.0,
            };
        }
        (test.summary(), steps)
    }

    #[test]
    fn the_peaks_are_each_sides_so_far_then_its_result_and_none_before_it_starts() {
        // The patient holds 1 N·m the way asked: the wheel where the spring balances it.
        let mut test = StrengthTest::new(K, 0.5, 3.0, DT_S);
        let mut angle = 0.0;
        let mut seen_right = false;
        for n in 0..9000 {
            let step = test.step(angle, 5.0, DT_S);
            angle = step.side.map_or(0.0, |s| s.sign() * 1.0 / K);
            if n == 2800 {
                assert_eq!(step.side, Some(StrengthSide::Left));
                assert!((step.push_nm - 1.0).abs() < 1e-9);
                let [left, right] = test.peaks_nm();
                assert!((left.unwrap() - 1.0).abs() < 1e-9);
                assert_eq!(right, None, "the right side has not started");
            }
            seen_right |= step.side == Some(StrengthSide::Right);
        }
        assert!(seen_right);
        let [left, right] = test.peaks_nm();
        assert!((left.unwrap() - 1.0).abs() < 1e-9 && (right.unwrap() - 1.0).abs() < 1e-9);
    }

    #[test]
    fn a_patient_stronger_than_the_ceiling_stops_each_side_at_the_ceiling() {
        let (s, steps) = run(2.0, 30.0, |_, _| 5.0);
        for side in [s.left.unwrap(), s.right.unwrap()] {
            assert_eq!(side.stop, StrengthStop::Ceiling);
            assert!(
                side.peak_nm <= 2.0 && side.peak_nm >= 0.98 * 2.0,
                "{side:?}"
            );
            // The limit rises at 0.5 N·m/s: about 4 s to the ceiling.
            assert!((3.8..4.3).contains(&side.duration_s), "{side:?}");
        }
        assert!(steps.iter().all(|st| st.torque_nm.abs() <= 2.0));
    }

    #[test]
    fn a_patient_weaker_than_the_ceiling_stops_each_side_at_the_time_limit() {
        let (s, _) = run(3.0, 10.0, |side, _| match side {
            StrengthSide::Left => 1.5,
            StrengthSide::Right => 1.0,
        });
        let (l, r) = (s.left.unwrap(), s.right.unwrap());
        assert_eq!(
            (l.stop, r.stop),
            (StrengthStop::TimeLimit, StrengthStop::TimeLimit)
        );
        assert!((l.duration_s - 10.0).abs() < 0.01, "{l:?}");
        assert!((l.peak_nm - 1.5).abs() < 1e-9 && (r.peak_nm - 1.0).abs() < 1e-9);
        assert!((l.sustained_nm - 1.5).abs() < 1e-9 && (r.sustained_nm - 1.0).abs() < 1e-9);
    }

    #[test]
    fn the_exercise_ending_mid_side_keeps_that_side_stopped_at_its_time_limit() {
        let mut test = StrengthTest::new(K, 0.5, 3.0, DT_S);
        // Left at 1 N·m to its limit, the rest, then right until 0.5 s before its limit.
        let ticks = ((3.0 + REST_S + 2.5) / DT_S) as usize;
        for _ in 0..ticks {
            let aim = test.aim_rad().signum();
            test.step(aim * 1.0 / K, 5.0, DT_S);
        }
        assert!(test.summary().right.is_none());
        test.time_up();
        let right = test.summary().right.unwrap();
        assert_eq!(right.stop, StrengthStop::TimeLimit);
        assert!((right.peak_nm - 1.0).abs() < 1e-9, "{right:?}");
        assert!((right.duration_s - 2.5).abs() < 0.01, "{right:?}");
        assert!(test.step(0.0, 5.0, DT_S).done);
        assert_eq!(test.aim_rad(), 0.0);
    }

    #[test]
    fn a_patient_letting_go_stops_the_side_half_a_second_later() {
        // Pushes 1.2 N·m from 1 s to 4 s, then lets go.
        let (s, _) = run(
            3.0,
            20.0,
            |_, t| if (1.0..4.0).contains(&t) { 1.2 } else { 0.0 },
        );
        for side in [s.left.unwrap(), s.right.unwrap()] {
            assert_eq!(side.stop, StrengthStop::LetGo);
            assert!((4.4..4.7).contains(&side.duration_s), "{side:?}");
            assert!((side.peak_nm - 1.2).abs() < 1e-9, "{side:?}");
        }
    }

    #[test]
    fn peak_and_sustained_torque_of_a_known_trace() {
        // A brief 2.5 N·m spike of 0.3 s on a 1.6 N·m hold of 2 s, on a 1 N·m base: the peak
        // is the spike, the sustained torque the hold (the spike lasts less than 1 s).
        let trace = |t: f64| {
            if (5.0..5.3).contains(&t) {
                2.5
            } else if (5.0..7.0).contains(&t) {
                1.6
            } else {
                1.0
            }
        };
        let (s, _) = run(3.0, 10.0, |side, t| match side {
            StrengthSide::Left => trace(t),
            // A hold of 0.9 s is too short: the sustained torque is the base.
            StrengthSide::Right => {
                if (6.0..6.9).contains(&t) {
                    2.0
                } else {
                    0.8
                }
            }
        });
        let (l, r) = (s.left.unwrap(), s.right.unwrap());
        assert!((l.peak_nm - 2.5).abs() < 1e-9, "{l:?}");
        assert!((l.sustained_nm - 1.6).abs() < 1e-9, "{l:?}");
        assert!((r.peak_nm - 2.0).abs() < 1e-9, "{r:?}");
        assert!((r.sustained_nm - 0.8).abs() < 1e-9, "{r:?}");
    }

    #[test]
    fn the_spring_never_asks_more_than_the_ceiling_whatever_the_angle() {
        let mut test = StrengthTest::new(200.0, 5.0, 60.0, DT_S);
        for i in 0..20_000 {
            let angle = [f64::NAN, f64::INFINITY, -3.0, 3.0, 0.01][i % 5];
            let ceiling = [1.0, 0.5, f64::NAN, 2.0][i % 4];
            let st = test.step(angle, ceiling, DT_S);
            let bound = if ceiling.is_finite() { ceiling } else { 0.0 };
            assert!(
                st.torque_nm.is_finite() && st.torque_nm.abs() <= bound,
                "{st:?}"
            );
        }
    }
}
