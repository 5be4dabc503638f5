//! The patient's own torque bounds: a prescription may not ask more of a torque than the
//! patient's wheel can give (the ceiling their station told the hub, `GET /api/patients/{id}`'s
//! `wheel`).

use super::Says as _;
use super::{ApiError, AppState};
use hub_store::db::{Patient, PatientWheel, Therapist, plain_name};
use hub_store::refusal::{Code, Why};

/// `value` N·m in words: at most two decimals, without trailing zeros (`5`, `1.87`).
pub(crate) fn nm_words(value: f64) -> String {
    let s = format!("{value:.2}");
    s.trim_end_matches('0').trim_end_matches('.').to_owned()
}

/// The patient's ceiling as the console states it: cut (never rounded up) to 0.01 N·m, so
/// that the value stated is always one the hub accepts.
pub(crate) fn stated_ceiling_nm(wheel: &PatientWheel) -> f64 {
    (wheel.ceiling_nm * 100.0 + 1e-9).floor() / 100.0
}

/// Why `regimen` asks more than `wheel` can give, naming the exercise, the field, the value
/// and the wheel, and the same for the console's words; `None` when every torque bound is
/// within the patient's ceiling.
pub(crate) fn above_wheel(
    regimen: &regimen::Regimen,
    pseudonym: &str,
    wheel: &PatientWheel,
) -> Option<(String, Why)> {
    regimen.exercises.iter().enumerate().find_map(|(i, e)| {
        let ceiling_nm = e.haptic.as_ref()?.ceiling_nm?;
        (ceiling_nm > wheel.ceiling_nm + 1e-9).then(|| {
            let why = Why::new(Code::AboveWheel)
                .with("exercise", i + 1)
                .with("max_nm", stated_ceiling_nm(wheel));
            let words = format!(
                "ceiling_nm {} N·m for exercise {} ({}) is above what {pseudonym}'s wheel ({}) \
                 can give: at most {} N·m",
                nm_words(ceiling_nm),
                i + 1,
                plain_name(&e.exercise.name()),
                wheel.model,
                nm_words(stated_ceiling_nm(wheel)),
            );
            (words, why)
        })
    })
}

/// Refuses (422, audited as `regimen_rejected`) a regimen above the patient's wheel; a
/// patient whose station has not told its wheel yet is bounded by the schema alone.
pub(crate) async fn check(
    state: &AppState,
    therapist: &Therapist,
    patient: &Patient,
    regimen: &regimen::Regimen,
) -> Result<(), ApiError> {
    let Some(wheel) = state.db.wheel_of(&patient.id).await? else {
        return Ok(());
    };
    let Some((reason, why)) = above_wheel(regimen, &patient.pseudonym, &wheel) else {
        return Ok(());
    };
    state
        .audit(&therapist.actor(), "regimen_rejected", &patient.id, &reason)
        .await?;
    Err(ApiError::Unprocessable(
        why.says(format!("regimen refused: {reason}")),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn g29() -> PatientWheel {
        PatientWheel {
            station_id: "st-1".into(),
            model: "Logitech G29".into(),
            rated_torque_nm: 2.2,
            ceiling_nm: 1.873,
            unknown: false,
            seen_at_ms: 0,
        }
    }

    #[test]
    fn a_ceiling_above_the_wheel_is_refused_naming_exercise_field_value_and_wheel() {
        let r = regimen::Regimen::from_toml(
            "[[exercise]]\nkind = \"straight\"\n\n[[exercise]]\nkind = \"sine\"\n\
             [exercise.haptic]\nceiling_nm = 5.0\n",
            "test",
        )
        .unwrap();
        let (words, why) = above_wheel(&r, "P-0042", &g29()).unwrap();
        assert_eq!(why.args()["exercise"], 2);
        assert_eq!(why.args()["max_nm"], 1.87);
        assert_eq!(
            words,
            "ceiling_nm 5 N·m for exercise 2 (Sine road) is above what P-0042's wheel \
             (Logitech G29) can give: at most 1.87 N·m"
        );
    }

    #[test]
    fn a_ceiling_at_the_stated_maximum_is_accepted() {
        let r = regimen::Regimen::from_toml(
            "[[exercise]]\nkind = \"sine\"\n[exercise.haptic]\nceiling_nm = 1.87\n",
            "test",
        )
        .unwrap();
        assert_eq!(above_wheel(&r, "P-0042", &g29()), None);
    }
}
