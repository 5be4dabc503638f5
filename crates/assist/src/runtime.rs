//! The one runtime type the station's 1 kHz haptic loop calls: [`Assist`], built from an
//! [`AssistSpec`]. Allocation-free per tick; every output is finite and inside the limits.

use crate::aan::AssistAsNeeded;
use crate::error::AssistError;
use crate::force::ForceAssist;
use crate::governor::{Infeasibility, ReferenceGovernor};
use crate::limits::Limits;
use crate::model::{PlantParams, gains_for_poles};
use crate::motion::{LinearisingMotion, SaturationHandling};
use crate::resist::Resist;
use crate::spec::{AssistMode, AssistSpec};
use serde::Serialize;

/// What the wheel measured this tick.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Measurement {
    /// Wheel angle, rad.
    pub angle_rad: f64,
    /// Wheel angular velocity, rad/s.
    pub vel_rad_s: f64,
}

/// One tick's result: what to command and what to record.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct AssistOutput {
    /// Torque to command, N·m: finite, `|τ| ≤ ceiling`, `|Δτ| ≤ slew·dt`.
    pub torque_nm: f64,
    /// Reference the assist is tracking this tick (the governed reference; equal to the
    /// requested one when it is feasible), rad.
    pub reference_rad: f64,
    /// `reference_rad − angle`, rad.
    pub error_rad: f64,
    /// How much the robot is helping, 0 (none) … 1 (full authority).
    pub assistance_level: f64,
    /// `true` when the ceiling or slew limit cut the torque this tick.
    pub saturated: bool,
}

/// Running account of how the limits and the request fared.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct AssistStatus {
    /// Ticks stepped since construction or [`Assist::reset`].
    pub ticks: u64,
    /// Fraction of those ticks on which a limit cut the torque.
    pub saturated_fraction: f64,
    /// Fraction of those ticks on which the raw request was not deliverable.
    pub infeasible_fraction: f64,
    /// `true` if the request was not deliverable at some tick within the last second.
    pub infeasible: bool,
    /// The most recent reason the request was not deliverable.
    pub reason: Option<Infeasibility>,
    /// RMS of `requested reference − measured angle` over the ticks with valid input, rad
    /// (the task error the therapist summary reports).
    pub rms_task_error_rad: f64,
    /// Mean [`AssistOutput::assistance_level`] over the ticks with valid input.
    pub mean_assistance_level: f64,
}

/// Largest `dt` accepted, s; anything longer is a stalled loop and gets the safe state.
pub const MAX_DT_S: f64 = 0.1;
/// How long an infeasible tick keeps [`AssistStatus::infeasible`] set, s.
const INFEASIBLE_HOLD_S: f64 = 1.0;

#[derive(Clone, Debug)]
enum Controller {
    None,
    Resist(Resist),
    Motion {
        ctrl: LinearisingMotion,
        governor: ReferenceGovernor,
        authority: f64,
    },
    Force {
        ctrl: ForceAssist,
        governor: ReferenceGovernor,
        arm: PlantParams,
        fraction: f64,
        bias_nm: f64,
        prev_desired_nm: Option<f64>,
    },
    Hybrid {
        motion: LinearisingMotion,
        force: ForceAssist,
        governor: ReferenceGovernor,
        authority: f64,
        lower_rad: f64,
        upper_rad: f64,
        contact_nm: f64,
        blend_rad: f64,
    },
    Aan(AssistAsNeeded),
}

/// The runtime assist for one exercise.
#[derive(Clone, Debug)]
pub struct Assist {
    spec: AssistSpec,
    ctrl: Controller,
    last_torque_nm: f64,
    last_reference_rad: f64,
    needs_resync: bool,
    ticks: u64,
    saturated_ticks: u64,
    infeasible_ticks: u64,
    since_infeasible_s: f64,
    reason: Option<Infeasibility>,
    valid_ticks: u64,
    sum_sq_task_error: f64,
    sum_assistance: f64,
}

impl Assist {
    /// Validate `spec` and build the controller (the only allocation happens here).
    pub fn new(spec: &AssistSpec) -> Result<Self, AssistError> {
        spec.validate()?;
        let total = spec.model.total();
        let ctrl = match &spec.mode {
            AssistMode::None {} => Controller::None,
            AssistMode::Resist(p) => Controller::Resist(Resist::new(
                p.spring_nm_per_rad,
                p.damper_nm_s_per_rad,
                p.inertia_kg_m2,
                p.center_rad,
            )),
            AssistMode::Motion(p) => Controller::Motion {
                ctrl: LinearisingMotion::new(
                    total,
                    gains_for_poles(p.poles_rad_s)?,
                    SaturationHandling::AntiWindup,
                ),
                governor: ReferenceGovernor::new(
                    total,
                    p.governor_budget,
                    p.governor_bandwidth_rad_s,
                ),
                authority: p.authority,
            },
            AssistMode::Force(p) => Controller::Force {
                ctrl: ForceAssist::new(spec.model.wheel, total, p.gain_per_s),
                governor: ReferenceGovernor::new(total, 1.0, p.governor_bandwidth_rad_s),
                arm: spec.model.arm,
                fraction: p.fraction,
                bias_nm: p.bias_nm,
                prev_desired_nm: None,
            },
            AssistMode::Hybrid(p) => Controller::Hybrid {
                motion: LinearisingMotion::new(
                    total,
                    gains_for_poles(p.motion.poles_rad_s)?,
                    SaturationHandling::AntiWindup,
                ),
                force: ForceAssist::new(spec.model.wheel, total, p.force_gain_per_s),
                governor: ReferenceGovernor::new(
                    total,
                    p.motion.governor_budget,
                    p.motion.governor_bandwidth_rad_s,
                ),
                authority: p.motion.authority,
                lower_rad: p.lower_rad,
                upper_rad: p.upper_rad,
                contact_nm: p.contact_nm,
                blend_rad: p.blend_rad,
            },
            AssistMode::AssistAsNeeded(p) => Controller::Aan(AssistAsNeeded::new(
                p.period_s,
                p.bins,
                p.forgetting,
                p.gain_nm_per_rad,
                p.lead_bins,
                p.feedback_nm_per_rad,
            )),
        };
        Ok(Self {
            spec: spec.clone(),
            ctrl,
            last_torque_nm: 0.0,
            last_reference_rad: 0.0,
            needs_resync: true,
            ticks: 0,
            saturated_ticks: 0,
            infeasible_ticks: 0,
            since_infeasible_s: f64::INFINITY,
            reason: None,
            valid_ticks: 0,
            sum_sq_task_error: 0.0,
            sum_assistance: 0.0,
        })
    }

    /// The spec this assist was built from.
    pub fn spec(&self) -> &AssistSpec {
        &self.spec
    }

    /// Start over (new exercise): zero torque, fresh controller state and status.
    pub fn reset(&mut self) {
        // The spec was validated at construction, so rebuilding cannot fail.
        if let Ok(fresh) = Self::new(&self.spec) {
            *self = fresh;
        }
    }

    /// Running account of saturation and feasibility.
    pub fn status(&self) -> AssistStatus {
        let n = self.ticks.max(1) as f64;
        let valid = self.valid_ticks.max(1) as f64;
        AssistStatus {
            ticks: self.ticks,
            saturated_fraction: self.saturated_ticks as f64 / n,
            infeasible_fraction: self.infeasible_ticks as f64 / n,
            infeasible: self.since_infeasible_s <= INFEASIBLE_HOLD_S,
            reason: self.reason,
            rms_task_error_rad: (self.sum_sq_task_error / valid).sqrt(),
            mean_assistance_level: self.sum_assistance / valid,
        }
    }

    /// The learned assist-as-needed help per phase bin, N·m (empty for other modes).
    pub fn learned_help_nm(&self) -> &[f64] {
        match &self.ctrl {
            Controller::Aan(a) => a.bins_nm(),
            _ => &[],
        }
    }

    fn mark_infeasible(&mut self, why: Infeasibility) {
        self.infeasible_ticks += 1;
        self.since_infeasible_s = 0.0;
        self.reason = Some(why);
    }

    /// One tick of the haptic loop.
    ///
    /// * `m` — measured wheel angle and velocity;
    /// * `reference_rad` — the angle the exercise wants now;
    /// * `limits` — the haptic layer's ceiling and slew limit (per patient);
    /// * `dt_s` — tick length (0.001 at 1 kHz), in (0, [`MAX_DT_S`]].
    ///
    /// Any non-finite input (or `dt` out of range) sends the torque to zero along the slew
    /// limit (at once if the limits themselves are bad), resets the controllers so no
    /// garbage survives, and reports [`Infeasibility::NonFiniteInput`].
    pub fn step(
        &mut self,
        m: Measurement,
        reference_rad: f64,
        limits: Limits,
        dt_s: f64,
    ) -> AssistOutput {
        self.ticks += 1;
        if dt_s.is_finite() && dt_s > 0.0 {
            self.since_infeasible_s += dt_s;
        }
        let inputs_ok = m.angle_rad.is_finite()
            && m.vel_rad_s.is_finite()
            && reference_rad.is_finite()
            && dt_s.is_finite()
            && dt_s > 0.0
            && dt_s <= MAX_DT_S;
        if !inputs_ok || !limits.is_sane() {
            return self.safe_state(limits, dt_s);
        }
        if self.needs_resync {
            self.resync(m);
        }
        let (request, reference, level) = self.request(m, reference_rad, limits, dt_s);
        let (torque, saturated) = if request.is_finite() {
            limits.apply(self.last_torque_nm, request, dt_s)
        } else {
            // Cannot happen with validated specs and finite inputs; handled all the same.
            self.needs_resync = true;
            limits.apply(self.last_torque_nm, 0.0, dt_s)
        };
        self.last_torque_nm = torque;
        self.track_applied(torque);
        if saturated {
            self.saturated_ticks += 1;
        }
        let reference = if reference.is_finite() {
            reference
        } else {
            reference_rad
        };
        self.last_reference_rad = reference;
        let level = level.clamp(0.0, 1.0);
        self.valid_ticks += 1;
        self.sum_sq_task_error += (reference_rad - m.angle_rad).powi(2);
        self.sum_assistance += level;
        AssistOutput {
            torque_nm: torque,
            reference_rad: reference,
            error_rad: reference - m.angle_rad,
            assistance_level: level,
            saturated,
        }
    }

    fn safe_state(&mut self, limits: Limits, dt_s: f64) -> AssistOutput {
        self.mark_infeasible(Infeasibility::NonFiniteInput);
        self.needs_resync = true;
        if let Controller::Aan(a) = &mut self.ctrl
            && dt_s.is_finite()
            && dt_s > 0.0
        {
            a.skip(dt_s.min(MAX_DT_S));
        }
        let clean = limits.sanitised();
        let torque = if limits.is_sane() && dt_s.is_finite() && dt_s > 0.0 {
            // Towards zero by at most one slew step (the ceiling still wins if it dropped).
            let step = clean.slew_nm_per_s * dt_s.min(MAX_DT_S);
            (self.last_torque_nm - self.last_torque_nm.clamp(-step, step))
                .clamp(-clean.ceiling_nm, clean.ceiling_nm)
        } else {
            0.0
        };
        self.last_torque_nm = torque;
        AssistOutput {
            torque_nm: torque,
            reference_rad: self.last_reference_rad,
            error_rad: 0.0,
            assistance_level: 0.0,
            saturated: true,
        }
    }

    /// After a fault or at start: restart the governor from where the wheel is and make
    /// every torque state equal the torque actually applied (bumpless).
    fn resync(&mut self, m: Measurement) {
        let tau = self.last_torque_nm;
        match &mut self.ctrl {
            Controller::None => {}
            Controller::Resist(r) => r.reset(),
            Controller::Motion { ctrl, governor, .. } => {
                governor.reset_to(m.angle_rad, m.vel_rad_s);
                ctrl.track_applied(tau);
            }
            Controller::Force {
                ctrl,
                governor,
                prev_desired_nm,
                ..
            } => {
                governor.reset_to(m.angle_rad, m.vel_rad_s);
                ctrl.track_applied(tau);
                *prev_desired_nm = None;
            }
            Controller::Hybrid {
                motion,
                force,
                governor,
                ..
            } => {
                governor.reset_to(m.angle_rad, m.vel_rad_s);
                motion.track_applied(tau);
                force.track_applied(tau);
            }
            Controller::Aan(_) => {}
        }
        self.needs_resync = false;
    }

    fn track_applied(&mut self, tau: f64) {
        match &mut self.ctrl {
            Controller::Motion { ctrl, .. } => ctrl.track_applied(tau),
            Controller::Force { ctrl, .. } => ctrl.track_applied(tau),
            Controller::Hybrid { motion, force, .. } => {
                motion.track_applied(tau);
                force.track_applied(tau);
            }
            Controller::None | Controller::Resist(_) | Controller::Aan(_) => {}
        }
    }

    /// The mode's torque request (already saturation-aware), the reference it tracks and
    /// its assistance level.
    fn request(
        &mut self,
        m: Measurement,
        reference_rad: f64,
        limits: Limits,
        dt_s: f64,
    ) -> (f64, f64, f64) {
        let (x, v) = (m.angle_rad, m.vel_rad_s);
        let mut infeasible = None;
        let out = match &mut self.ctrl {
            Controller::None => (0.0, reference_rad, 0.0),
            Controller::Resist(r) => (r.torque_nm(x, v, dt_s), reference_rad, 0.0),
            Controller::Motion {
                ctrl,
                governor,
                authority,
            } => {
                let lim = Limits {
                    ceiling_nm: limits.ceiling_nm * *authority,
                    ..limits
                };
                let shaped = governor.step(reference_rad, lim, dt_s);
                infeasible = shaped.infeasible;
                let tau = ctrl.step(x, v, &shaped.motion, lim, dt_s);
                (tau, shaped.motion.angle_rad, *authority)
            }
            Controller::Force {
                ctrl,
                governor,
                arm,
                fraction,
                bias_nm,
                prev_desired_nm,
            } => {
                let shaped = governor.step(reference_rad, limits, dt_s);
                infeasible = shaped.infeasible;
                let d = shaped.motion;
                let desired = *fraction
                    * arm.inverse_dynamics(d.angle_rad, d.vel_rad_s, d.acc_rad_s2)
                    + *bias_nm;
                let rate = prev_desired_nm.map_or(0.0, |p| (desired - p) / dt_s);
                *prev_desired_nm = Some(desired);
                let tau = ctrl.step(x, v, desired, rate, limits, dt_s);
                (tau, d.angle_rad, *fraction)
            }
            Controller::Hybrid {
                motion,
                force,
                governor,
                authority,
                lower_rad,
                upper_rad,
                contact_nm,
                blend_rad,
            } => {
                let lim = Limits {
                    ceiling_nm: limits.ceiling_nm * *authority,
                    ..limits
                };
                // Motion only ever asks for the free range.
                let shaped = governor.step(reference_rad.clamp(*lower_rad, *upper_rad), lim, dt_s);
                infeasible = shaped.infeasible;
                // Selection (Raibert & Craig 1981 hybrid control, here along the single
                // axis): 1 in the free range, falling to 0 over `blend_rad` beyond it.
                let beyond = (x - *upper_rad).max(*lower_rad - x);
                let s = 1.0 - (beyond / *blend_rad).clamp(0.0, 1.0);
                let push = if x > *upper_rad {
                    -*contact_nm
                } else {
                    *contact_nm
                };
                let u_m = motion.rate_nm_per_s(x, v, &shaped.motion);
                let u_f = force.rate_nm_per_s(x, v, push, 0.0);
                let u = (s * u_m + (1.0 - s) * u_f).clamp(-lim.slew_nm_per_s, lim.slew_nm_per_s);
                let tau =
                    (motion.torque_state_nm() + u * dt_s).clamp(-lim.ceiling_nm, lim.ceiling_nm);
                (tau, shaped.motion.angle_rad, *authority * s)
            }
            Controller::Aan(a) => {
                let tau = a.torque_nm(x, reference_rad, limits.ceiling_nm, dt_s);
                let level = if limits.ceiling_nm > 0.0 {
                    a.mean_help_nm() / limits.ceiling_nm
                } else {
                    0.0
                };
                (tau, reference_rad, level)
            }
        };
        if let Some(why) = infeasible {
            self.mark_infeasible(why);
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spec::{ModelSpec, MotionParams};

    const LIMITS: Limits = Limits {
        ceiling_nm: 1.87,
        slew_nm_per_s: 50.0,
    };

    #[test]
    fn status_reports_task_error_and_mean_assistance_over_valid_ticks() {
        let spec = AssistSpec {
            model: ModelSpec::default(),
            mode: AssistMode::None {},
        };
        let mut a = Assist::new(&spec).unwrap();
        for (angle, reference) in [(0.0, 0.3), (0.1, -0.3), (f64::NAN, 0.0)] {
            a.step(
                Measurement {
                    angle_rad: angle,
                    vel_rad_s: 0.0,
                },
                reference,
                LIMITS,
                0.001,
            );
        }
        let st = a.status();
        assert_eq!(st.ticks, 3);
        let expect = ((0.09 + 0.16) / 2.0f64).sqrt();
        assert!((st.rms_task_error_rad - expect).abs() < 1e-12);
        assert_eq!(st.mean_assistance_level, 0.0);
        assert_eq!(st.reason, Some(Infeasibility::NonFiniteInput));
    }

    #[test]
    fn motion_assist_starts_from_where_the_wheel_is_without_a_jolt() {
        let spec = AssistSpec {
            model: ModelSpec::default(),
            mode: AssistMode::Motion(MotionParams::default()),
        };
        let mut a = Assist::new(&spec).unwrap();
        // Wheel at 0.5 rad, exercise reference at 0: the governed reference starts at 0.5.
        let out = a.step(
            Measurement {
                angle_rad: 0.5,
                vel_rad_s: 0.0,
            },
            0.0,
            LIMITS,
            0.001,
        );
        assert!((out.reference_rad - 0.5).abs() < 1e-3, "{out:?}");
        assert!(out.torque_nm.abs() <= 0.05 + 1e-12);
    }

    #[test]
    fn reset_clears_state_and_status() {
        let spec = AssistSpec {
            model: ModelSpec::default(),
            mode: AssistMode::Motion(MotionParams::default()),
        };
        let mut a = Assist::new(&spec).unwrap();
        for _ in 0..100 {
            a.step(Measurement::default(), 1.0, LIMITS, 0.001);
        }
        a.reset();
        assert_eq!(a.status().ticks, 0);
        let out = a.step(Measurement::default(), 0.0, LIMITS, 0.001);
        assert_eq!(out.torque_nm, 0.0);
    }
}
