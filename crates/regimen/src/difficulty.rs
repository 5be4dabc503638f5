//! Difficulty that follows the patient: the therapist's bounds (`[difficulty]` in the
//! regimen) and the mapping from one difficulty in `[0, 1]` to the exercises.
//!
//! ```toml
//! [difficulty]
//! adapt = true                 # the station sets each session's difficulty (default true)
//! target_success = 0.7         # the success rate aimed at, 0.5–0.95 (default 0.70)
//! lowest = 0.2                 # the easiest the station may go, 0–1 (default 0)
//! highest = 0.9                # the hardest, 0–1, not below `lowest` (default 1)
//! start = 0.5                  # the first session's (default midway between the bounds)
//! changes = ["speed", "shape", "assist"]   # what the difficulty changes (default all three)
//! ```
//!
//! The mapping ([`Regimen::at_difficulty`]) never goes beyond what the regimen prescribes:
//! difficulty 1 runs every exercise as written; lower difficulties scale it down linearly.
//! With `k = 0.5 + 0.5·d` ([`challenge_scale`]):
//!
//! * `speed`: a road's `speed_m_s` × k (at least 1 m/s); a dial's sine, multi-sine and
//!   chirp frequencies and a ramp's `rate_deg_s` × k. A road driven once (no `duration_s`)
//!   keeps its prescribed time: it gets the `duration_s` it would have taken as written.
//! * `shape`: a sine road's `amplitude_m`, a triangle road's `amplitude_m`, a clothoid's
//!   `end_curvature_1_m`, sharp turns' and S-bends' `angle_deg`, a lane change's `offset_m`,
//!   a slalom's `weave_m` and a dial's `amplitude_deg` × k (each at least its lower bound).
//! * `assist`: the prescribed help × `1 − 0.5·d` ([`assist_scale`]): a motion or hybrid
//!   assist's `authority`, a force assist's `fraction`. The most help is the prescription's
//!   (at difficulty 0), half of it at difficulty 1.
//!
//! The haptic settings (model, effects, torque ceiling) are never touched. An exercise that
//! scaling would make invalid (a triangle's corners no longer fitting) runs as prescribed.

use crate::{Regimen, RegimenEntry};
use assist::AssistMode;
use exercises::dial::{AMPLITUDE_DEG, FREQUENCY_RAD_S, RATE_DEG_S};
use exercises::exercise::bounds;
use exercises::{DialSignal, ExerciseSpec};
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Lowest target success rate a therapist may ask for (as `assist::DifficultyParams`).
pub const MIN_TARGET_SUCCESS: f64 = 0.5;
/// Highest target success rate.
pub const MAX_TARGET_SUCCESS: f64 = 0.95;
/// The share of the prescribed speed and shape at difficulty 0.
pub const EASIEST_SCALE: f64 = 0.5;
/// The share of the prescribed assistance at difficulty 1.
pub const LEAST_ASSIST_SCALE: f64 = 0.5;

/// What a difficulty changes.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Aspect {
    /// The car's speed, the dial's speed.
    Speed,
    /// The road's curvature or amplitude, the dial's amplitude.
    Shape,
    /// The assistance (less help when harder).
    Assist,
}

fn default_true() -> bool {
    true
}
fn default_target() -> f64 {
    0.7
}
fn default_highest() -> f64 {
    1.0
}
fn default_changes() -> Vec<Aspect> {
    vec![Aspect::Speed, Aspect::Shape, Aspect::Assist]
}

/// The therapist's bounds on the adapted difficulty (`[difficulty]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DifficultySpec {
    /// The station adapts each session's difficulty (false: every session at `start`).
    #[serde(default = "default_true")]
    pub adapt: bool,
    /// The success rate the adaptation aims at, 0.5–0.95 (default 0.70).
    #[serde(default = "default_target")]
    #[schemars(range(min = MIN_TARGET_SUCCESS, max = MAX_TARGET_SUCCESS))]
    pub target_success: f64,
    /// The easiest difficulty allowed, 0–1. At 0: half the prescribed speed and shape, all
    /// its assistance.
    #[serde(default)]
    #[schemars(range(min = 0.0, max = 1.0))]
    pub lowest: f64,
    /// The hardest difficulty allowed, 0–1, not below the easiest. At 1: as prescribed, half
    /// its assistance.
    #[serde(default = "default_highest")]
    #[schemars(range(min = 0.0, max = 1.0))]
    pub highest: f64,
    /// The first session's difficulty, within `lowest`–`highest` (default midway).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 0.0, max = 1.0))]
    pub start: Option<f64>,
    /// What the difficulty changes: any of `speed`, `shape`, `assist` (default all three).
    #[serde(default = "default_changes")]
    pub changes: Vec<Aspect>,
}

impl Default for DifficultySpec {
    fn default() -> Self {
        Self {
            adapt: true,
            target_success: default_target(),
            lowest: 0.0,
            highest: 1.0,
            start: None,
            changes: default_changes(),
        }
    }
}

impl DifficultySpec {
    /// Checks every field; the message names it and its allowed range.
    pub fn validate(&self) -> Result<(), String> {
        let t = self.target_success;
        if !(MIN_TARGET_SUCCESS..=MAX_TARGET_SUCCESS).contains(&t) {
            return Err(format!(
                "difficulty.target_success = {t}, allowed {MIN_TARGET_SUCCESS} to \
                 {MAX_TARGET_SUCCESS}"
            ));
        }
        for (name, v) in [("lowest", self.lowest), ("highest", self.highest)] {
            if !(0.0..=1.0).contains(&v) {
                return Err(format!("difficulty.{name} = {v}, allowed 0 to 1"));
            }
        }
        if self.lowest > self.highest {
            return Err(format!(
                "difficulty.lowest = {} is above difficulty.highest = {}",
                self.lowest, self.highest
            ));
        }
        if let Some(s) = self.start
            && !(self.lowest..=self.highest).contains(&s)
        {
            return Err(format!(
                "difficulty.start = {s}, allowed difficulty.lowest to difficulty.highest \
                 ({} to {})",
                self.lowest, self.highest
            ));
        }
        Ok(())
    }

    /// The first session's difficulty: `start`, else midway between the bounds.
    pub fn first(&self) -> f64 {
        self.start
            .unwrap_or((self.lowest + self.highest) / 2.0)
            .clamp(self.lowest, self.highest)
    }

    fn changes(&self, a: Aspect) -> bool {
        self.changes.contains(&a)
    }
}

/// The share of the prescribed speed and shape at difficulty `d`: 0.5 at 0, 1 at 1.
pub fn challenge_scale(d: f64) -> f64 {
    EASIEST_SCALE + (1.0 - EASIEST_SCALE) * d.clamp(0.0, 1.0)
}

/// The share of the prescribed assistance at difficulty `d`: 1 at 0, 0.5 at 1.
pub fn assist_scale(d: f64) -> f64 {
    1.0 - (1.0 - LEAST_ASSIST_SCALE) * d.clamp(0.0, 1.0)
}

/// `v × k`, not below `min` and never above `v` itself (nor below it when `v < min`).
fn down(v: f64, k: f64, min: f64) -> f64 {
    (v * k).max(min).min(v)
}

/// The exercise's speed scaled by `k`.
fn scale_speed(spec: &mut ExerciseSpec, k: f64) {
    let min = bounds::SPEED_M_S.min;
    match spec {
        ExerciseSpec::Straight(s) => s.speed_m_s = down(s.speed_m_s, k, min),
        ExerciseSpec::Sine(s) => s.speed_m_s = down(s.speed_m_s, k, min),
        ExerciseSpec::Triangle(s) => s.speed_m_s = down(s.speed_m_s, k, min),
        ExerciseSpec::Clothoid(s) => s.speed_m_s = down(s.speed_m_s, k, min),
        ExerciseSpec::SharpTurns(s) => s.speed_m_s = down(s.speed_m_s, k, min),
        ExerciseSpec::SBend(s) => s.speed_m_s = down(s.speed_m_s, k, min),
        ExerciseSpec::LaneChange(s) => s.speed_m_s = down(s.speed_m_s, k, min),
        ExerciseSpec::Slalom(s) => s.speed_m_s = down(s.speed_m_s, k, min),
        ExerciseSpec::Dial(d) => {
            let f = FREQUENCY_RAD_S.min;
            match &mut d.reference {
                DialSignal::Sine {
                    frequency_rad_s, ..
                } => *frequency_rad_s = down(*frequency_rad_s, k, f),
                DialSignal::MultiSine { components } => {
                    for c in components {
                        c.frequency_rad_s = down(c.frequency_rad_s, k, f);
                    }
                }
                DialSignal::Ramp { rate_deg_s, .. } => {
                    *rate_deg_s = down(*rate_deg_s, k, RATE_DEG_S.min);
                }
                DialSignal::Chirp {
                    start_rad_s,
                    end_rad_s,
                    ..
                } => {
                    *start_rad_s = down(*start_rad_s, k, f);
                    *end_rad_s = down(*end_rad_s, k, f);
                }
                DialSignal::Step { .. } | DialSignal::RandomSteps { .. } => {}
            }
        }
        // A strength test has no speed: the patient sets its pace. A haptic sweep is a
        // measurement: its sine stays as prescribed, session after session.
        ExerciseSpec::Strength(_) | ExerciseSpec::HapticSweep(_) | ExerciseSpec::Assessment(_) => {}
    }
}

/// The exercise's curvature or amplitude scaled by `k`.
fn scale_shape(spec: &mut ExerciseSpec, k: f64) {
    match spec {
        ExerciseSpec::Straight(_) => {}
        ExerciseSpec::Sine(s) => {
            s.amplitude_m = down(s.amplitude_m, k, bounds::SINE_AMPLITUDE_M.min);
        }
        ExerciseSpec::Triangle(s) => {
            s.amplitude_m = down(s.amplitude_m, k, bounds::TRIANGLE_AMPLITUDE_M.min);
        }
        ExerciseSpec::Clothoid(s) => s.end_curvature_1_m *= k,
        ExerciseSpec::SharpTurns(s) => {
            s.angle_deg = down(s.angle_deg, k, bounds::TURN_ANGLE_DEG.min);
        }
        ExerciseSpec::SBend(s) => s.angle_deg = down(s.angle_deg, k, bounds::TURN_ANGLE_DEG.min),
        ExerciseSpec::LaneChange(s) => s.offset_m = down(s.offset_m, k, bounds::OFFSET_M.min),
        ExerciseSpec::Slalom(s) => s.weave_m = down(s.weave_m, k, bounds::WEAVE_M.min),
        ExerciseSpec::Dial(d) => {
            let a = AMPLITUDE_DEG.min;
            match &mut d.reference {
                DialSignal::Sine { amplitude_deg, .. }
                | DialSignal::Step { amplitude_deg, .. }
                | DialSignal::RandomSteps { amplitude_deg, .. }
                | DialSignal::Ramp { amplitude_deg, .. }
                | DialSignal::Chirp { amplitude_deg, .. } => {
                    *amplitude_deg = down(*amplitude_deg, k, a);
                }
                DialSignal::MultiSine { components } => {
                    for c in components {
                        c.amplitude_deg = down(c.amplitude_deg, k, a);
                    }
                }
            }
        }
        // Nor a shape: the patient pushes as hard as they comfortably can (nor does a sweep,
        // a measurement).
        ExerciseSpec::Strength(_) | ExerciseSpec::HapticSweep(_) | ExerciseSpec::Assessment(_) => {}
    }
}

/// The assistance scaled by `k` (≤ 1: never more help than prescribed).
fn scale_assist(mode: &mut AssistMode, k: f64) {
    match mode {
        AssistMode::Motion(m) => m.authority = down(m.authority, k, 0.0),
        AssistMode::Hybrid(h) => h.motion.authority = down(h.motion.authority, k, 0.0),
        AssistMode::Force(f) => f.fraction = down(f.fraction, k, 0.0),
        AssistMode::None {} | AssistMode::Resist(_) | AssistMode::AssistAsNeeded(_) => {}
    }
}

/// A road driven once keeps its prescribed time when its speed changes.
fn keep_duration(spec: &mut ExerciseSpec, prescribed: &ExerciseSpec) {
    if matches!(
        spec,
        ExerciseSpec::Dial(_) | ExerciseSpec::Strength(_) | ExerciseSpec::HapticSweep(_)
    ) {
        return;
    }
    let Ok(built) = prescribed.build() else {
        return;
    };
    let fixed = built
        .planned_duration_s()
        .clamp(bounds::DURATION_S.min, bounds::DURATION_S.max);
    let d = match spec {
        ExerciseSpec::Straight(s) => &mut s.duration_s,
        ExerciseSpec::Sine(s) => &mut s.duration_s,
        ExerciseSpec::Triangle(s) => &mut s.duration_s,
        ExerciseSpec::Clothoid(s) => &mut s.duration_s,
        ExerciseSpec::SharpTurns(s) => &mut s.duration_s,
        ExerciseSpec::SBend(s) => &mut s.duration_s,
        ExerciseSpec::LaneChange(s) => &mut s.duration_s,
        ExerciseSpec::Slalom(s) => &mut s.duration_s,
        ExerciseSpec::Dial(_)
        | ExerciseSpec::Strength(_)
        | ExerciseSpec::HapticSweep(_)
        | ExerciseSpec::Assessment(_) => {
            return;
        }
    };
    d.get_or_insert(fixed);
}

/// One exercise at difficulty `d` (see the module's mapping).
pub fn entry_at(entry: &RegimenEntry, spec: &DifficultySpec, d: f64) -> RegimenEntry {
    let mut out = entry.clone();
    // The standard assessment is the same task at every difficulty (`exercises::assessment`).
    if matches!(entry.exercise, ExerciseSpec::Assessment(_)) {
        return out;
    }
    let k = challenge_scale(d);
    let mut ex = entry.exercise.clone();
    if spec.changes(Aspect::Speed) {
        keep_duration(&mut ex, &entry.exercise);
        scale_speed(&mut ex, k);
    }
    if spec.changes(Aspect::Shape) {
        scale_shape(&mut ex, k);
    }
    // Scaled down within the bounds it can only stay valid, but a triangle's corners must
    // still fit its legs: what would not validate or build runs as prescribed.
    if ex.validate().is_ok() && ex.build().is_ok() {
        out.exercise = ex;
    }
    if spec.changes(Aspect::Assist)
        && let Some(a) = &mut out.assist
    {
        scale_assist(&mut a.mode, assist_scale(d));
    }
    out
}

impl Regimen {
    /// The regimen as the station runs it at difficulty `d` (clamped to `[0, 1]`): every
    /// exercise mapped by [`entry_at`]; unchanged without a `[difficulty]` table.
    pub fn at_difficulty(&self, d: f64) -> Regimen {
        let Some(spec) = &self.difficulty else {
            return self.clone();
        };
        let d = d.clamp(0.0, 1.0);
        Regimen {
            exercises: self
                .exercises
                .iter()
                .map(|e| entry_at(e, spec, d))
                .collect(),
            ..self.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const TWO: &str = "[difficulty]\nlowest = 0.2\nhighest = 0.8\n\n\
        [[exercise]]\nkind = \"sine\"\namplitude_m = 4.0\nspeed_m_s = 12.0\n\
        [exercise.assist.mode]\nkind = \"motion\"\nauthority = 0.8\n\n\
        [[exercise]]\nkind = \"dial\"\nduration_s = 30.0\n";

    fn sine(r: &Regimen) -> (f64, f64, Option<f64>) {
        match &r.exercises[0].exercise {
            ExerciseSpec::Sine(s) => (s.speed_m_s, s.amplitude_m, s.duration_s),
            other => panic!("{other:?}"),
        }
    }

    fn authority(r: &Regimen) -> f64 {
        match &r.exercises[0].assist.as_ref().unwrap().mode {
            AssistMode::Motion(m) => m.authority,
            other => panic!("{other:?}"),
        }
    }

    fn dial_amplitude_deg(r: &Regimen) -> f64 {
        match &r.exercises[1].exercise {
            ExerciseSpec::Dial(d) => match d.reference {
                DialSignal::Sine { amplitude_deg, .. } => amplitude_deg,
                ref other => panic!("{other:?}"),
            },
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn difficulty_one_is_the_prescription_and_zero_halves_speed_and_shape_with_full_help() {
        let r = Regimen::from_toml(TWO, "r.toml").unwrap();
        let hard = r.at_difficulty(1.0);
        let (speed, amp, _) = sine(&hard);
        assert_eq!((speed, amp), (12.0, 4.0));
        assert!((authority(&hard) - 0.4).abs() < 1e-12);
        assert_eq!(dial_amplitude_deg(&hard), 120.0);
        let easy = r.at_difficulty(0.0);
        let (speed, amp, duration) = sine(&easy);
        assert_eq!((speed, amp), (6.0, 2.0));
        assert!((authority(&easy) - 0.8).abs() < 1e-12);
        assert_eq!(dial_amplitude_deg(&easy), 60.0);
        // A road driven once keeps its prescribed time at any speed.
        let planned = r.exercises[0]
            .exercise
            .build()
            .unwrap()
            .planned_duration_s();
        assert_eq!(duration, Some(planned));
        // Every difficulty validates, and the haptic settings and rests are untouched.
        for d in [0.0, 0.3, 0.55, 1.0] {
            let at = r.at_difficulty(d);
            let again = Regimen::from_toml(&toml::to_string(&at).unwrap(), "at").unwrap();
            assert_eq!(again.exercises.len(), 2);
            for (a, b) in at.exercises.iter().zip(&r.exercises) {
                assert_eq!((&a.haptic, a.rest_s), (&b.haptic, b.rest_s));
            }
        }
    }

    #[test]
    fn only_the_aspects_the_therapist_names_change() {
        let text = TWO.replace("highest = 0.8\n", "highest = 0.8\nchanges = [\"speed\"]\n");
        let r = Regimen::from_toml(&text, "r.toml").unwrap();
        let easy = r.at_difficulty(0.0);
        assert_eq!(sine(&easy).0, 6.0);
        assert_eq!(sine(&easy).1, 4.0, "shape as prescribed");
        assert!(
            (authority(&easy) - 0.8).abs() < 1e-12,
            "assist as prescribed"
        );
        assert_eq!(dial_amplitude_deg(&easy), 120.0);
    }

    #[test]
    fn a_regimen_without_a_difficulty_table_runs_as_written() {
        let r = Regimen::from_toml("[[exercise]]\nkind = \"sine\"\n", "r.toml").unwrap();
        assert_eq!(r.at_difficulty(0.0), r);
    }

    #[test]
    fn bad_difficulty_bounds_name_the_field() {
        for (table, field) in [
            ("target_success = 0.99", "difficulty.target_success = 0.99"),
            ("lowest = -0.1", "difficulty.lowest"),
            ("highest = 1.5", "difficulty.highest"),
            (
                "lowest = 0.8\nhighest = 0.3",
                "difficulty.lowest = 0.8 is above",
            ),
            ("lowest = 0.4\nstart = 0.1", "difficulty.start = 0.1"),
            ("changes = [\"colour\"]", "changes"),
        ] {
            let text = format!("[difficulty]\n{table}\n\n[[exercise]]\nkind = \"sine\"\n");
            let msg = Regimen::from_toml(&text, "r.toml").unwrap_err().to_string();
            assert!(msg.contains(field), "{table}: {msg}");
        }
        let schema = Regimen::json_schema().to_string();
        assert!(schema.contains("target_success"), "{schema}");
    }

    #[test]
    fn every_shipped_regimen_at_any_difficulty_validates_lasts_as_long_and_keeps_its_haptics() {
        for name in ["easy", "medium", "hard"] {
            let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("../../regimens")
                .join(format!("{name}.toml"));
            let mut r = Regimen::load(&path).unwrap();
            r.difficulty = Some(DifficultySpec::default());
            let planned_s = r.planned_duration_s().unwrap();
            for tenth in 0..=10 {
                let at = r.at_difficulty(f64::from(tenth) / 10.0);
                let text = toml::to_string(&at).unwrap();
                let again = Regimen::from_toml(&text, name).unwrap_or_else(|e| panic!("{e}"));
                let at_s = again.planned_duration_s().unwrap();
                assert!((at_s - planned_s).abs() < 1.0, "{name} {tenth}: {at_s} s");
                for (a, b) in again.exercises.iter().zip(&r.exercises) {
                    assert_eq!((&a.haptic, a.rest_s), (&b.haptic, b.rest_s), "{name}");
                }
            }
        }
    }

    #[test]
    fn the_first_session_starts_midway_unless_told() {
        let mut s = DifficultySpec {
            lowest: 0.2,
            highest: 0.8,
            ..Default::default()
        };
        assert!((s.first() - 0.5).abs() < 1e-12);
        s.start = Some(0.3);
        assert_eq!(s.first(), 0.3);
    }
}
