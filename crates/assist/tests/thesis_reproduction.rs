//! Reproduction of thesis §5.4 (Fig. 5-3 to 5-6) with Table 5.1's parameters on the crate's
//! own RK4 plant: J = 10, B = 25, C = 15, K = [6000, 1100, 60], human PID K_P = 2.

use assist::force::ForceAssist;
use assist::limits::Limits;
use assist::model::{PlantParams, gains_for_poles};
use assist::motion::{DesiredMotion, LinearisingMotion, SaturationHandling};
use assist::sim::Rk4Plant;
use assist::{HumanArm, HumanArmParams};

const DT: f64 = 0.001;
const NO_LIMITS: Limits = Limits {
    ceiling_nm: f64::INFINITY,
    slew_nm_per_s: f64::INFINITY,
};

/// The sine reference of Fig. 5-3, θ_d = sin t, with its derivatives (eq. 5.32–5.33).
fn sine(t: f64) -> DesiredMotion {
    DesiredMotion {
        angle_rad: t.sin(),
        vel_rad_s: t.cos(),
        acc_rad_s2: -t.sin(),
        jerk_rad_s3: -t.cos(),
    }
}

fn thesis_human() -> HumanArm {
    HumanArm::new(
        HumanArmParams {
            kp_nm_per_rad: 2.0,
            ki_nm_per_rad_s: 0.0,
            kd_nm_s_per_rad: 0.0,
            delay_s: 0.0,
            noise_nm: 0.0,
            max_torque_nm: 1e9,
            ..Default::default()
        },
        DT,
        1,
    )
}

struct Run {
    rms_after_2s: f64,
    peak_torque_nm: f64,
}

fn run(mut human: Option<HumanArm>, mut assist: Option<LinearisingMotion>) -> Run {
    let mut plant = Rk4Plant::new(PlantParams::THESIS, 0.0);
    let (mut sq, mut n, mut peak) = (0.0, 0usize, 0.0f64);
    for i in 0..20_000 {
        let t = i as f64 * DT;
        let d = sine(t);
        let hand = human.as_mut().map_or(0.0, |h| {
            h.step(d.angle_rad, plant.angle_rad(), plant.vel_rad_s(), DT)
        });
        let motor = assist.as_mut().map_or(0.0, |a| {
            a.step(plant.angle_rad(), plant.vel_rad_s(), &d, NO_LIMITS, DT)
        });
        peak = peak.max(motor.abs());
        plant.step(motor + hand, DT);
        if t >= 2.0 {
            let e = sine(t + DT).angle_rad - plant.angle_rad();
            sq += e * e;
            n += 1;
        }
    }
    Run {
        rms_after_2s: (sq / n as f64).sqrt(),
        peak_torque_nm: peak,
    }
}

fn thesis_controller() -> LinearisingMotion {
    LinearisingMotion::new(
        PlantParams::THESIS,
        gains_for_poles([-10.0, -20.0, -30.0]).unwrap(),
        SaturationHandling::Unconstrained,
    )
}

#[test]
fn fig_5_3_pid_human_alone_fails_to_track_the_sine() {
    let r = run(Some(thesis_human()), None);
    eprintln!("PID human alone: RMS error {:.4} rad", r.rms_after_2s);
    // K_P = 2 against C = 15 and B = 25: the arm reaches under a tenth of the amplitude.
    assert!(r.rms_after_2s > 0.6, "{}", r.rms_after_2s);
}

#[test]
fn fig_5_3_linearised_motion_assist_tracks_the_sine() {
    let r = run(None, Some(thesis_controller()));
    eprintln!(
        "linearised motion assist: RMS error {:.2e} rad",
        r.rms_after_2s
    );
    assert!(r.rms_after_2s < 1e-3, "{}", r.rms_after_2s);
}

#[test]
fn motion_assist_tracks_with_the_pid_human_as_an_unmodelled_disturbance() {
    let r = run(Some(thesis_human()), Some(thesis_controller()));
    eprintln!("assist + PID human: RMS error {:.2e} rad", r.rms_after_2s);
    assert!(r.rms_after_2s < 5e-3, "{}", r.rms_after_2s);
}

#[test]
fn fig_5_4_perfect_tracking_needs_far_more_torque_than_the_wheel_has() {
    // Steady state |C − Jω² + jBω| = |5 + 25j| ≈ 25.5 N·m against the wheel's 1.87 N·m.
    let r = run(None, Some(thesis_controller()));
    eprintln!(
        "peak torque of the thesis design: {:.2} N·m",
        r.peak_torque_nm
    );
    assert!(r.peak_torque_nm > 10.0 * 1.87, "{}", r.peak_torque_nm);
}

#[test]
fn fig_5_5_and_5_6_force_assist_tracks_force_while_position_drifts() {
    // Ideal (massless) wheel: the interaction torque is the actuator torque, as in eq. 5.34 —
    // the figures' setting; force_assist_tracks_the_torque_the_hand_feels_on_a_wheel_with_inertia
    // checks the torque the hand feels instead.
    let ideal = PlantParams {
        inertia_kg_m2: 0.0,
        damping_nm_s_per_rad: 0.0,
        stiffness_nm_per_rad: 0.0,
    };
    let mut force = ForceAssist::new(ideal, PlantParams::THESIS, 20.0);
    let mut plant = Rk4Plant::new(PlantParams::THESIS, 0.0);
    let (mut sq, mut n) = (0.0, 0usize);
    let (mut angle_before, mut angle_after) = (0.0, 0.0);
    for i in 0..40_000 {
        let t = i as f64 * DT;
        let (desired, rate) = (5.0 * t.sin(), 5.0 * t.cos());
        // After 20 s something the force loop does not control — the patient leaning on the
        // wheel with 3 N·m — moves the position; the force is tracked all the same.
        let hand = if t >= 20.0 { 3.0 } else { 0.0 };
        let tau = force.step(
            plant.angle_rad(),
            plant.vel_rad_s(),
            desired,
            rate,
            NO_LIMITS,
            DT,
        );
        plant.step(tau + hand, DT);
        if t >= 1.0 {
            let e = desired - tau;
            sq += e * e;
            n += 1;
        }
        // Mean angle over one full period of the desired force before and after the lean.
        let period = std::f64::consts::TAU;
        if (20.0 - period..20.0).contains(&t) {
            angle_before += plant.angle_rad() * DT / period;
        }
        if (40.0 - period..40.0).contains(&t) {
            angle_after += plant.angle_rad() * DT / period;
        }
    }
    let rms = (sq / n as f64).sqrt();
    eprintln!(
        "force assist: RMS force error {rms:.2e} N·m; mean angle {angle_before:.3} → {angle_after:.3} rad"
    );
    assert!(rms < 0.02 * 5.0, "{rms}");
    // The position moved by the lean (3 N·m / C = 0.2 rad at rest) — not held by the loop.
    assert!(
        (angle_after - angle_before).abs() > 0.1,
        "{angle_before} {angle_after}"
    );
}

#[test]
fn force_assist_tracks_the_torque_the_hand_feels_on_a_wheel_with_inertia() {
    // A consumer rim (J₁ = 0.02 kg·m²) held by a relaxed arm whose muscles move it (a PID
    // human following a sine): the controller sees only the angle and velocity and estimates
    // the torque it delivers quasi-statically (it drops J₁θ̈). The check is the torque the
    // hand actually feels, from the arm's own balance with the simulated muscle torque τ_m:
    // τ_in = J₂θ̈ + B₂θ̇ + C₂θ − τ_m, θ̈ the plant's true acceleration — nothing the controller
    // computes.
    let (rim, arm) = (PlantParams::CONSUMER_WHEEL, PlantParams::RELAXED_ARM);
    let total = rim.coupled_with(&arm);
    let mut force = ForceAssist::new(rim, total, 20.0);
    let mut plant = Rk4Plant::new(total, 0.0);
    let mut human = HumanArm::new(HumanArmParams::default(), DT, 3);
    let (mut sq_err, mut sq_desired, mut sq_acc_nm) = (0.0, 0.0, 0.0);
    for i in 0..20_000 {
        let t = i as f64 * DT;
        let (desired, rate) = (0.3 * (2.0 * t).sin(), 0.6 * (2.0 * t).cos());
        let target = 0.8 * (std::f64::consts::TAU * 0.25 * t).sin();
        let muscle = human.step(target, plant.angle_rad(), plant.vel_rad_s(), DT);
        let tau = force.step(
            plant.angle_rad(),
            plant.vel_rad_s(),
            desired,
            rate,
            NO_LIMITS,
            DT,
        );
        let (angle, vel) = (plant.angle_rad(), plant.vel_rad_s());
        let acc = plant.acceleration(tau + muscle);
        let felt = arm.inertia_kg_m2 * acc
            + arm.damping_nm_s_per_rad * vel
            + arm.stiffness_nm_per_rad * angle
            - muscle;
        plant.step(tau + muscle, DT);
        if t >= 1.0 {
            sq_err += (desired - felt).powi(2);
            sq_desired += desired * desired;
            sq_acc_nm += (rim.inertia_kg_m2 * acc).powi(2);
        }
    }
    let ratio = (sq_err / sq_desired).sqrt();
    let inertial = (sq_acc_nm / sq_desired).sqrt();
    eprintln!(
        "force tracking on a rim with inertia: RMS error {:.1} % of the desired torque (the \
         rim's J₁θ̈ is {:.1} % of it)",
        100.0 * ratio,
        100.0 * inertial
    );
    // The patient moved the wheel enough for the inertia to matter; the torque felt follows
    // the desired one within 20 % (16 % measured), and what it misses is the rim's J₁θ̈ the
    // controller drops (force.rs), within 5 points of the desired torque.
    assert!(inertial > 0.02, "J₁θ̈ only {inertial}");
    assert!(ratio < 0.20, "RMS error {ratio}");
    assert!(ratio < inertial + 0.05, "RMS error {ratio}, J₁θ̈ {inertial}");
}
