//! The course of a session: the exercises in order, each built before the session starts
//! (road, rapier world, haptic model, assist controller) so that switching from one to the
//! next on the haptic thread allocates nothing.
//!
//! `--exercise NAME` prescribes that exercise for `--duration`; `--regimen FILE` runs the
//! prescribed exercises once, in order. Either way an exercise with a duration lasts exactly
//! that long: its road continues its shape as far as needed (`vehicle::ExerciseSpec::build`).

use crate::config::StationConfig;
use anyhow::Context;
use assist::Assist;
use haptic_wheel::HapticRegimen;
use regimen::{Regimen, RegimenEntry};
use vehicle::{Exercise, ExerciseSpec, World};

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
    })
}

/// The exercises a session of `cfg` runs, in order: the regimen's, or `cfg.session.exercise`
/// prescribed for `cfg.session.duration_s`.
pub fn entries(
    cfg: &StationConfig,
    regimen: Option<&Regimen>,
) -> anyhow::Result<Vec<RegimenEntry>> {
    Ok(match regimen {
        Some(r) => r.exercises.clone(),
        None => vec![RegimenEntry {
            // Within the exercise's own bounds (1 s to 1 h): a shorter session ends at its
            // duration all the same; a longer one runs this exercise for its first hour.
            exercise: ExerciseSpec::from_name(&cfg.session.exercise)?.with_duration_s(
                cfg.session.duration_s.clamp(
                    vehicle::exercise::bounds::DURATION_S.min,
                    vehicle::exercise::bounds::DURATION_S.max,
                ),
            ),
            haptic: None,
            assist: None,
        }],
    })
}

/// Build the course: [`entries`], each ready to run.
pub fn build(cfg: &StationConfig, regimen: Option<&Regimen>) -> anyhow::Result<Vec<Segment>> {
    entries(cfg, regimen)?
        .iter()
        .map(|e| build_segment(cfg, e))
        .collect()
}
