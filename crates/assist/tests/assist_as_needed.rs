//! Assist-as-needed on the dial task: the help falls as the simulated patient recovers
//! strength over repetitions, and stays up when the patient does not recover.

use assist::sim::{DialTask, run_dial_task};
use assist::{AanParams, AssistMode, AssistSpec, HumanArmParams, ModelSpec};

fn mean(x: &[f64]) -> f64 {
    x.iter().sum::<f64>() / x.len() as f64
}

#[test]
fn assistance_falls_as_the_simulated_patient_improves() {
    let task = DialTask {
        duration_s: 300.0,
        ..Default::default()
    };
    let spec = AssistSpec {
        model: ModelSpec::default(),
        mode: AssistMode::AssistAsNeeded(AanParams::default()),
    };
    // Improves over repetitions: strength comes back and the arm learns to anticipate the
    // dial (Emken et al. 2007 model, retention 0.95 — above the robot's forgetting 0.8).
    let recovering = HumanArmParams {
        weakness: 0.95,
        recovery_per_repetition: 0.08,
        learning_gain_nm_per_rad: 1.0,
        retention: 0.95,
        ..HumanArmParams::weak_patient()
    };
    let stuck = HumanArmParams {
        weakness: 0.95,
        ..HumanArmParams::weak_patient()
    };
    let r = run_dial_task(&task, &spec, &recovering, 9).unwrap();
    let s = run_dial_task(&task, &spec, &stuck, 9).unwrap();
    let level = &r.assistance_per_repetition;
    let n = level.len();
    let peak_r = level.iter().cloned().fold(0.0, f64::max);
    let early_r = mean(&level[3..8]);
    let late_r = mean(&level[n - 5..]);
    let late_s = mean(&s.assistance_per_repetition[n - 5..]);
    eprintln!(
        "assistance level: recovering patient peak {peak_r:.3}, reps 3–7 {early_r:.3}, last 5 {late_r:.3}; \
         non-recovering last 5 {late_s:.3}"
    );
    eprintln!(
        "RMS error last 5 reps: recovering {:.2}°, non-recovering {:.2}°",
        mean(&r.rms_error_per_repetition_rad[n - 5..]).to_degrees(),
        mean(&s.rms_error_per_repetition_rad[n - 5..]).to_degrees()
    );
    assert!(
        late_r < 0.75 * peak_r,
        "help must fall as the patient improves"
    );
    assert!(
        late_s > 1.5 * late_r,
        "a patient who does not improve keeps the help"
    );
    // The improving patient ends up doing most of the work and tracking well.
    assert!(mean(&r.rms_error_per_repetition_rad[n - 5..]) < 3f64.to_radians());
}
