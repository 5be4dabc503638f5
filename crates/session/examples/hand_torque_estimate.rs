//! The patient's torque estimate against the simulated patient's true hand torque, for every
//! exercise and assist mode: the table of BENCHMARKS.md ("Hand torque estimate").
//!
//! `cargo run --release -p session --example hand_torque_estimate [SECONDS]` (20 s each by
//! default, seed 7).

use session::effort_check::{ASSIST_MODES, run};

fn main() -> anyhow::Result<()> {
    let seconds: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(20.0);
    println!(
        "| exercise | assist | RMS hand N·m | RMS error N·m | error % | absent % | \
         patient work % (est / true) | bound |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let (mut worst, mut misses): (f64, u32) = (0.0, 0);
    for exercise in exercises::EXERCISE_NAMES {
        for mode in ASSIST_MODES {
            let f = run(exercise, mode, seconds, 7)?;
            let holds = f.holds(20.0);
            misses += u32::from(!holds);
            if f.rms_hand_nm > f.floor_nm / 0.2 {
                worst = worst.max(f.error_pct());
            }
            println!(
                "| {exercise} | {mode} | {:.3} | {:.4} | {:.1} | {:.1} | {:.1} / {:.1} | {} |",
                f.rms_hand_nm,
                f.rms_error_nm,
                f.error_pct(),
                f.absent_pct,
                f.patient_work_pct,
                f.patient_work_true_pct,
                if holds { "met" } else { "NOT met" }
            );
        }
    }
    println!(
        "\nworst where the hand is stronger than the floor: {worst:.1} % of the RMS hand \
         torque; bound not met: {misses} ({seconds} s each, seed 7)"
    );
    Ok(())
}
