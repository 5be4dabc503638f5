//! The arm calibrated during the session against the end-of-session batch fit, on default
//! simulated sessions (sine road, 60 s, square mounting): how far the wheel turns and the
//! grip moves, when the estimate during the session converges and to what, and the batch
//! fit's lengths and warnings. The table of BENCHMARKS.md ("Arm calibration during the
//! session").
//!
//! `cargo run -p session --example arm_calibration_online [SEED …]` (seeds 7 1 2 3 4 by
//! default).

use record::{ArmSetup, TickRecord};
use session::config::StationConfig;
use session::{self, Controls, SessionObserver, SessionOptions};

/// The wheel angle of every tick and the grip point of every tracked tick.
#[derive(Default)]
struct Motion {
    wheel_rad: Vec<f64>,
    grip_m: Vec<[f64; 3]>,
}

impl SessionObserver for Motion {
    fn on_tick(&mut self, rec: &TickRecord) {
        self.wheel_rad.push(rec.wheel.angle_rad);
        if let Some(arm) = rec.arm.filter(|a| a.setup == ArmSetup::Tracking) {
            self.grip_m.push(arm.grip_m);
        }
    }
}

/// RMS about the mean of points (their 3-D spread), in their unit.
fn spread<const N: usize>(points: &[[f64; N]]) -> f64 {
    let n = points.len().max(1) as f64;
    let mean: [f64; N] = std::array::from_fn(|i| points.iter().map(|p| p[i]).sum::<f64>() / n);
    let ss: f64 = points
        .iter()
        .map(|p| (0..N).map(|i| (p[i] - mean[i]).powi(2)).sum::<f64>())
        .sum();
    (ss / n).sqrt()
}

fn main() -> anyhow::Result<()> {
    let seeds: Vec<u64> = std::env::args()
        .skip(1)
        .map(|s| s.parse())
        .collect::<Result<_, _>>()?;
    let seeds = if seeds.is_empty() {
        vec![7, 1, 2, 3, 4]
    } else {
        seeds
    };
    println!(
        "| seed | wheel RMS ° | grip RMS mm | converged at s | during: upper / elbow–grip m, residual mm \
         | end batch: upper / elbow–grip m, residual mm | batch warnings |"
    );
    println!("|---|---|---|---|---|---|---|");
    for seed in seeds {
        let mut cfg = StationConfig::default();
        cfg.session.seed = seed;
        let opts = SessionOptions::simulated(cfg);
        let mut motion = Motion::default();
        let report = session::run(&opts, &Controls::default(), &mut motion)?;
        let wheel: Vec<[f64; 1]> = motion.wheel_rad.iter().map(|w| [*w]).collect();
        let during = report.recorder.online_arm_calibration.as_ref().map_or_else(
            || ("never".to_owned(), "—".to_owned()),
            |o| {
                (
                    format!("{:.0}", o.converged_at_s),
                    format!(
                        "{:.4} / {:.4}, {:.1}",
                        o.upper_arm_m,
                        o.forearm_m,
                        o.rms_residual_m * 1e3
                    ),
                )
            },
        );
        let (batch, warnings) = match &report.recorder.arm_calibration {
            Some(Ok(b)) => (
                format!(
                    "{:.4} / {:.4}, {:.1}",
                    b.upper_arm_m,
                    b.forearm_m,
                    b.rms_residual_m * 1e3
                ),
                if b.warnings.is_empty() {
                    "none".to_owned()
                } else {
                    b.warnings.join("; ")
                },
            ),
            Some(Err(e)) => ("failed".to_owned(), e.clone()),
            None => ("—".to_owned(), "no arm sensing".to_owned()),
        };
        println!(
            "| {seed} | {:.1} | {:.1} | {} | {} | {batch} | {warnings} |",
            spread(&wheel).to_degrees(),
            spread(&motion.grip_m) * 1e3,
            during.0,
            during.1
        );
    }
    Ok(())
}
