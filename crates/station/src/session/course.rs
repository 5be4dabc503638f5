//! The course of a session: the exercises in order, each built before the session starts
//! (road, rapier world, haptic model, assist controller) so that switching from one to the
//! next on the haptic thread allocates nothing.
//!
//! `--exercise NAME` repeats that exercise (laps) to fill `--duration`; `--regimen FILE` runs
//! the prescribed exercises once, in order.

use crate::config::StationConfig;
use anyhow::Context;
use assist::Assist;
use haptic_wheel::HapticRegimen;
use regimen::{Regimen, RegimenEntry};
use vehicle::{Exercise, ExerciseSpec, World};

/// Most laps one session prebuilds (a 45 s lap × 200 ≈ 2.5 h).
pub const MAX_LAPS: usize = 200;

/// One exercise, ready to run.
pub struct Segment {
    /// The exercise: road (or dial reference), speed profile, cones.
    pub exercise: Exercise,
    /// The rapier world of a road exercise; `None` for the dial task.
    pub world: Option<World>,
    /// Haptic rendering during this exercise (effects, model, ceiling).
    pub haptic: HapticRegimen,
    /// Assistance during this exercise.
    pub assist: Option<Assist>,
    /// The break after this exercise, before the next (none after the last one, nor between
    /// laps of one exercise).
    pub break_after: Option<Break>,
}

/// Shortest break between two prescribed exercises, s: long enough to read the card that says
/// what comes next. Not exercise time.
pub const TRANSITION_S: f64 = 6.0;

/// A break between two exercises: the exercise paused (the torque faded out, as for a pause)
/// while the screen says what comes next.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Break {
    /// How long, s.
    pub length_s: f64,
    /// The regimen prescribes a rest here (recorded as rest time); otherwise it is the short
    /// card between two exercises ([`TRANSITION_S`]).
    pub rest: bool,
}

impl Break {
    /// The break after a prescribed exercise that rests `rest_s` (none or 0: just the card; a
    /// rest shorter than the card's [`TRANSITION_S`] lasts that long).
    pub fn after(rest_s: Option<f64>) -> Self {
        let rest_s = rest_s.unwrap_or(0.0);
        Self {
            length_s: rest_s.max(TRANSITION_S),
            rest: rest_s > 0.0,
        }
    }
}

/// How long one run of `exercise` takes, s: its time limit, or the road driven at its speed
/// profile, whichever is shorter.
pub fn nominal_time_s(exercise: &Exercise) -> f64 {
    let driving = if exercise.road.is_some() {
        let metres = exercise.length_m.ceil() as usize;
        (0..metres)
            .map(|s| 1.0 / exercise.target_speed_m_s(s as f64).max(1.0))
            .sum::<f64>()
    } else {
        f64::INFINITY
    };
    exercise.duration_s.unwrap_or(f64::INFINITY).min(driving)
}

fn build_segment(cfg: &StationConfig, entry: &RegimenEntry) -> anyhow::Result<Segment> {
    let name = entry.exercise.name();
    let exercise = entry
        .exercise
        .build()
        .with_context(|| format!("exercise {name}"))?;
    let world = match exercise.road {
        Some(_) => Some(
            World::new(
                cfg.vehicle.clone(),
                exercise.start_state(),
                exercise.track_layout(),
            )
            .with_context(|| format!("exercise {name}: vehicle world"))?,
        ),
        None => None,
    };
    let assist_spec = entry.assist.as_ref().or(cfg.assist.as_ref());
    let assist = assist_spec
        .map(Assist::new)
        .transpose()
        .with_context(|| format!("exercise {name}: assist"))?;
    let mut haptic = entry.haptic.clone().unwrap_or(HapticRegimen {
        model: Some(cfg.haptic.centring),
        ..HapticRegimen::default()
    });
    // A regimen may lower the patient's ceiling for an exercise, never raise it.
    if let (Some(c), Some(patient)) = (haptic.ceiling_nm, cfg.haptic.safety.ceiling_nm) {
        haptic.ceiling_nm = Some(c.min(patient));
    }
    Ok(Segment {
        exercise,
        world,
        haptic,
        assist,
        break_after: None,
    })
}

/// Build the course: the regimen's exercises in order, or laps of `cfg.session.exercise`
/// enough to fill `cfg.session.duration_s`.
pub fn build(cfg: &StationConfig, regimen: Option<&Regimen>) -> anyhow::Result<Vec<Segment>> {
    match regimen {
        Some(r) => {
            let last = r.exercises.len().saturating_sub(1);
            r.exercises
                .iter()
                .enumerate()
                .map(|(i, e)| {
                    let mut segment = build_segment(cfg, e)?;
                    segment.break_after = (i < last).then(|| Break::after(e.rest_s));
                    Ok(segment)
                })
                .collect()
        }
        None => {
            let entry = RegimenEntry {
                exercise: ExerciseSpec::from_name(&cfg.session.exercise)?,
                haptic: None,
                assist: None,
                rest_s: None,
            };
            let first = build_segment(cfg, &entry)?;
            let lap_s = nominal_time_s(&first.exercise);
            let laps = if lap_s.is_finite() && lap_s > 0.0 {
                ((cfg.session.duration_s / lap_s).ceil() as usize).clamp(1, MAX_LAPS)
            } else {
                1
            };
            let mut course = vec![first];
            for _ in 1..laps {
                course.push(build_segment(cfg, &entry)?);
            }
            Ok(course)
        }
    }
}
