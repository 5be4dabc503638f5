//! The patient's torque estimate against the simulated patient's true hand torque, for every
//! exercise and assist mode: the table of BENCHMARKS.md ("Hand torque estimate").
//!
//! `cargo run --release -p station --example hand_torque_estimate [SECONDS]` (20 s each by
//! default, seed 7).

use station::session::effort_check::{ASSIST_MODES, run};

fn main() -> anyhow::Result<()> {
    let seconds: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(20.0);
    println!(
        "| exercise | assist | RMS hand N·m | RMS error N·m | error % | patient work % (est / true) |"
    );
    println!("|---|---|---|---|---|---|");
    let mut worst: f64 = 0.0;
    for exercise in vehicle::EXERCISE_NAMES {
        for mode in ASSIST_MODES {
            let f = run(exercise, mode, seconds, 7)?;
            worst = worst.max(f.error_pct());
            println!(
                "| {exercise} | {mode} | {:.3} | {:.4} | {:.1} | {:.1} / {:.1} |",
                f.rms_hand_nm,
                f.rms_error_nm,
                f.error_pct(),
                f.patient_work_pct,
                f.patient_work_true_pct
            );
        }
    }
    println!("\nworst: {worst:.1} % of the RMS hand torque ({seconds} s each, seed 7)");
    Ok(())
}
