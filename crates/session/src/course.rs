//! The course of a session: the exercises in order, each built before the session starts
//! (road, rapier world, haptic model, assist controller) so that switching from one to the
//! next on the haptic thread allocates nothing.
//!
//! `--exercise NAME` prescribes that exercise for `--duration`; `--regimen FILE` runs the
//! prescribed exercises once, in order. Either way an exercise with a duration lasts exactly
//! that long: its road continues its shape as far as needed (`exercises::ExerciseSpec::build`).
//!
//! The breaks between exercises ([`Break`]) and how long the breaks the patient takes may last
//! ([`BreakSettings`]) are part of the course; `breaks` keeps them on the haptic thread.

use crate::config::StationConfig;
use anyhow::Context;
use assist::Assist;
use exercises::{Exercise, ExerciseSpec, World};
use haptic_wheel::HapticRegimen;
use regimen::{Regimen, RegimenEntry};

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
    /// The patient drives the speed with the pedals (the car starts at rest); otherwise the
    /// speed is automatic.
    pub pedals: bool,
    /// The trunk's excursion that brings the gentle cue to sit up, deg (the regimen's
    /// `[trunk] cue_deg`); `None`: no cue — without the table, and always in the standard
    /// assessment, whose protocol is the same for every patient.
    pub trunk_cue_deg: Option<f64>,
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
    /// After a rest, the next exercise starts after this countdown, s; `None`: it waits for
    /// the patient ("Ready?", a wheel button). The regimen's `[patient] start_after_rest_s`.
    pub start_after_s: Option<f64>,
}

impl Break {
    /// The break after a prescribed exercise that rests `rest_s` (none or 0: just the card; a
    /// rest shorter than the card's [`TRANSITION_S`] lasts that long).
    pub fn after(rest_s: Option<f64>) -> Self {
        let rest_s = rest_s.unwrap_or(0.0);
        Self {
            length_s: rest_s.max(TRANSITION_S),
            rest: rest_s > 0.0,
            start_after_s: None,
        }
    }
}

/// How long a rest the patient asks for lasts, and how long a pause may last, s.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BreakSettings {
    /// A rest the patient asks for (R, or a wheel button), s.
    pub asked_rest_s: f64,
    /// A pause longer than this ends the session ("paused too long"), s.
    pub pause_limit_s: f64,
}

fn build_segment(cfg: &StationConfig, entry: &RegimenEntry) -> anyhow::Result<Segment> {
    let name = entry.exercise.name();
    let exercise = entry
        .exercise
        .build()
        .with_context(|| format!("exercise {name}"))?;
    let mut start = exercise.start_state();
    if entry.pedals {
        // The patient's foot starts the car.
        start.ux_m_s = 0.0;
    }
    let world = match exercise.road {
        Some(_) => Some(
            World::new(cfg.vehicle.clone(), start, exercise.track_layout())
                .with_context(|| format!("exercise {name}: vehicle world"))?,
        ),
        None => None,
    };
    // The standard assessment is measured without help, whatever the station's settings.
    let assist_spec = if matches!(entry.exercise, ExerciseSpec::Assessment(_)) {
        None
    } else {
        entry.assist.as_ref().or(cfg.assist.as_ref())
    };
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
        pedals: entry.pedals,
        // No cue in the standard assessment: every patient meets the same protocol.
        trunk_cue_deg: None,
    })
}

/// The exercises a session of `cfg` runs, in order: the regimen's, or `cfg.session.exercise`
/// prescribed for `cfg.session.duration_s`; a haptic sweep as one exercise per level, each
/// with its own haptic model ([`RegimenEntry::expand`]).
pub fn entries(
    cfg: &StationConfig,
    regimen: Option<&Regimen>,
) -> anyhow::Result<Vec<RegimenEntry>> {
    let prescribed = match regimen {
        Some(r) => r.exercises.clone(),
        None => vec![RegimenEntry {
            // Within the exercise's own bounds (1 s to 1 h): a shorter session ends at its
            // duration all the same; a longer one runs this exercise for its first hour.
            exercise: ExerciseSpec::from_name(&cfg.session.exercise)?.with_duration_s(
                cfg.session.duration_s.clamp(
                    exercises::exercise::bounds::DURATION_S.min,
                    exercises::exercise::bounds::DURATION_S.max,
                ),
            ),
            haptic: None,
            assist: None,
            rest_s: None,
            pedals: false,
        }],
    };
    // A dial's drift goes into the side the patient neglects.
    let side = regimen
        .and_then(|r| r.patient.as_ref())
        .map(|p| p.neglected_side)
        .unwrap_or_default();
    Ok(prescribed
        .iter()
        .flat_map(RegimenEntry::expand)
        .map(|e| e.drift_toward(side))
        .collect())
}

/// The road of each exercise [`build`] makes of the same `cfg` and `regimen` (`None`: the
/// dial task), for the road around the car in the live summaries (the plant owns the
/// course's own roads).
pub fn roads(
    cfg: &StationConfig,
    regimen: Option<&Regimen>,
) -> anyhow::Result<Vec<Option<Box<dyn exercises::Road + Send>>>> {
    entries(cfg, regimen)?
        .iter()
        .map(|e| {
            let name = e.exercise.name();
            Ok(e.exercise
                .build()
                .with_context(|| format!("exercise {name}"))?
                .road)
        })
        .collect()
}

/// Build the course: [`entries`], each ready to run, with the break after each but the last
/// (its card, and the regimen's rest).
pub fn build(cfg: &StationConfig, regimen: Option<&Regimen>) -> anyhow::Result<Vec<Segment>> {
    let entries = entries(cfg, regimen)?;
    let last = entries.len().saturating_sub(1);
    let start_after_s = regimen
        .and_then(|r| r.patient.as_ref())
        .and_then(|p| p.start_after_rest_s);
    let cue_deg = regimen.and_then(|r| r.trunk.as_ref()).map(|t| t.cue_deg);
    entries
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let mut segment = build_segment(cfg, e)?;
            if !matches!(e.exercise, ExerciseSpec::Assessment(_)) {
                segment.trunk_cue_deg = cue_deg;
            }
            segment.break_after = (i < last).then(|| Break {
                start_after_s,
                ..Break::after(e.rest_s)
            });
            Ok(segment)
        })
        .collect()
}
