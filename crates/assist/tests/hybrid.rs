//! Hybrid motion + force assist along the wheel's single axis: motion tracking in the free
//! range, regulation of the hand torque at the exercise's constraint.

use assist::sim::Rk4Plant;
use assist::{Assist, AssistMode, AssistSpec, HybridParams, Limits, Measurement, ModelSpec};

const DT: f64 = 0.001;
const LIMITS: Limits = Limits {
    ceiling_nm: 1.87,
    slew_nm_per_s: 50.0,
};

#[test]
fn tracks_motion_in_the_free_range_and_regulates_contact_torque_at_the_constraint() {
    let model = ModelSpec::default();
    let params = HybridParams {
        lower_rad: -0.6,
        upper_rad: 0.4,
        contact_nm: 0.6,
        ..Default::default()
    };
    let spec = AssistSpec {
        model: model.clone(),
        mode: AssistMode::Hybrid(params.clone()),
    };
    let mut assist = Assist::new(&spec).unwrap();
    let mut plant = Rk4Plant::new(model.total(), 0.0);
    let (mut free_sq, mut free_n) = (0.0, 0usize);
    let mut contact_torques = Vec::new();
    for i in 0..30_000 {
        let t = i as f64 * DT;
        // 0–10 s: a slow sine inside the free range. 10–30 s: the exercise asks for 0.8 rad,
        // beyond the constraint at 0.4, and a strong patient presses into it and holds
        // (isometrically) near 0.6 rad.
        let (reference, hand) = if t < 10.0 {
            (0.3 * (0.5 * t).sin(), 0.0)
        } else {
            (
                0.8,
                30.0 * (0.6 - plant.angle_rad()) - 1.0 * plant.vel_rad_s(),
            )
        };
        let out = assist.step(
            Measurement {
                angle_rad: plant.angle_rad(),
                vel_rad_s: plant.vel_rad_s(),
            },
            reference,
            LIMITS,
            DT,
        );
        plant.step(out.torque_nm + hand, DT);
        if (2.0..10.0).contains(&t) {
            free_sq += (reference - plant.angle_rad()).powi(2);
            free_n += 1;
        }
        if t >= 25.0 {
            assert!(
                plant.angle_rad() > params.upper_rad + params.blend_rad,
                "the press holds the wheel in the constrained region"
            );
            contact_torques.push(out.torque_nm);
        }
    }
    let free_rms = (free_sq / free_n as f64).sqrt();
    let mean_contact = contact_torques.iter().sum::<f64>() / contact_torques.len() as f64;
    // At rest the rim passes the actuator torque to the hand, less its spring (none here).
    let delivered = mean_contact - model.wheel.stiffness_nm_per_rad * plant.angle_rad();
    eprintln!(
        "hybrid: free-range RMS {:.2e} rad; at the constraint actuator {mean_contact:.3} N·m, \
         hand torque {delivered:.3} N·m (target −0.6), angle {:.3} rad",
        free_rms,
        plant.angle_rad()
    );
    assert!(free_rms < 0.01, "{free_rms}");
    assert!((delivered + 0.6).abs() < 0.02, "{delivered}");
}
