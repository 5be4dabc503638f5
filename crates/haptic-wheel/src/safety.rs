//! The last stage of every torque path: magnitude ceiling, slew limit, non-finite rejection
//! ([`TorqueLimiter`]), and the [`Supervisor`] around it: per-patient ceiling, soft start,
//! fade-out, and a deadline watchdog that ramps torque to zero on a missed tick or a stale
//! reading (DESIGN.md safety invariants 1–3).

use crate::wheel::{ConfigError, WheelError};
use serde::{Deserialize, Serialize};

/// A torque after the safety chain.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LimitedTorque {
    /// The torque that may go to the motor, N·m.
    pub torque_nm: f64,
    /// The request was larger than the ceiling or changed faster than the slew limit.
    pub clipped: bool,
    /// The request was NaN or infinite and was replaced by a ramp towards zero.
    pub rejected_non_finite: bool,
}

/// Magnitude ceiling plus slew-rate limit (DESIGN.md safety invariant 1 and 2).
///
/// Non-finite requests are treated as a request for zero torque, so a NaN from any sensor or
/// model can never reach the motor.
#[derive(Clone, Debug)]
pub struct TorqueLimiter {
    ceiling_nm: f64,
    slew_nm_per_s: f64,
    last_nm: f64,
}

impl TorqueLimiter {
    /// A limiter with a ceiling `|τ| ≤ ceiling_nm` and slew `|dτ/dt| ≤ slew_nm_per_s`.
    /// Non-finite or negative limits are replaced by zero (the safe state: no torque).
    pub fn new(ceiling_nm: f64, slew_nm_per_s: f64) -> Self {
        let sane = |v: f64| if v.is_finite() && v > 0.0 { v } else { 0.0 };
        Self {
            ceiling_nm: sane(ceiling_nm),
            slew_nm_per_s: sane(slew_nm_per_s),
            last_nm: 0.0,
        }
    }

    /// The magnitude ceiling, N·m.
    pub fn ceiling_nm(&self) -> f64 {
        self.ceiling_nm
    }

    /// The last torque let through, N·m.
    pub fn last_nm(&self) -> f64 {
        self.last_nm
    }

    /// Limit `requested_nm` for a tick of `dt_s` seconds.
    pub fn apply(&mut self, requested_nm: f64, dt_s: f64) -> LimitedTorque {
        let rejected = !requested_nm.is_finite();
        let want = if rejected { 0.0 } else { requested_nm };
        let capped = want.clamp(-self.ceiling_nm, self.ceiling_nm);
        let dt = if dt_s.is_finite() && dt_s > 0.0 {
            dt_s
        } else {
            0.0
        };
        let max_step = self.slew_nm_per_s * dt;
        let out = capped.clamp(self.last_nm - max_step, self.last_nm + max_step);
        // Re-clamp: a ceiling lowered at run time must hold immediately.
        let out = out.clamp(-self.ceiling_nm, self.ceiling_nm);
        self.last_nm = out;
        LimitedTorque {
            torque_nm: out,
            clipped: out != want,
            rejected_non_finite: rejected,
        }
    }
}

/// Safety settings for one patient and device. Serde (`deny_unknown_fields`) so they can
/// come from the station's config or a therapist's regimen; [`SafetyConfig::validate`]
/// checks them against the device before use.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SafetyConfig {
    /// Per-patient torque ceiling, N·m; `None` uses the device maximum (the thesis wheel:
    /// ±1.87 N·m). Never above the device maximum.
    pub ceiling_nm: Option<f64>,
    /// Largest rate of change of the commanded torque, N·m/s.
    pub slew_nm_per_s: f64,
    /// Time for the torque scale to rise from 0 to 1 at start and after a fault, s.
    pub soft_start_s: f64,
    /// Time for the torque scale to fall from 1 to 0 on a fault or stop, s.
    pub fade_out_s: f64,
    /// Longest gap between ticks before the watchdog calls it a missed deadline, s.
    pub max_tick_gap_s: f64,
    /// Oldest acceptable wheel reading, s (same clock as the tick's `now_ns`).
    pub max_reading_age_s: f64,
}

impl Default for SafetyConfig {
    fn default() -> Self {
        Self {
            ceiling_nm: None,
            slew_nm_per_s: 100.0,
            soft_start_s: 1.0,
            fade_out_s: 0.25,
            max_tick_gap_s: 0.01,
            max_reading_age_s: 0.02,
        }
    }
}

impl SafetyConfig {
    /// Check every field against the device's maximum torque `device_max_nm`; the error
    /// names the field and its allowed range.
    pub fn validate(&self, device_max_nm: f64) -> Result<(), ConfigError> {
        let check = |name: &str, v: f64, lo: f64, hi: f64| {
            if v.is_finite() && v > lo && v <= hi {
                Ok(())
            } else {
                Err(ConfigError(format!(
                    "safety.{name} = {v}, allowed ({lo}, {hi}]"
                )))
            }
        };
        if !(device_max_nm.is_finite() && device_max_nm > 0.0) {
            return Err(ConfigError(format!(
                "device max torque {device_max_nm} N·m is not a positive number"
            )));
        }
        if let Some(c) = self.ceiling_nm
            && !(c.is_finite() && (0.0..=device_max_nm).contains(&c))
        {
            return Err(ConfigError(format!(
                "safety.ceiling_nm = {c}, allowed [0, {device_max_nm}] (the device maximum)"
            )));
        }
        check("slew_nm_per_s", self.slew_nm_per_s, 0.0, 10_000.0)?;
        check("soft_start_s", self.soft_start_s, 0.0, 60.0)?;
        check("fade_out_s", self.fade_out_s, 0.0, 5.0)?;
        check("max_tick_gap_s", self.max_tick_gap_s, 0.0, 1.0)?;
        check("max_reading_age_s", self.max_reading_age_s, 0.0, 1.0)?;
        Ok(())
    }

    /// The effective ceiling on a device with maximum `device_max_nm`, N·m.
    pub fn effective_ceiling_nm(&self, device_max_nm: f64) -> f64 {
        self.ceiling_nm
            .unwrap_or(device_max_nm)
            .min(device_max_nm)
            .max(0.0)
    }
}

/// Why the watchdog is fading the torque out.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum Fault {
    /// The gap since the previous tick exceeded `max_tick_gap_s`.
    MissedDeadline,
    /// The wheel reading is older than `max_reading_age_s`, from the future, or missing.
    StaleReading,
}

/// The supervisor's state, for telemetry.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum WatchdogState {
    /// Ramping the torque scale up (start of session or recovery after a fault).
    SoftStart,
    /// Full torque allowed.
    Running,
    /// A fault is present or was recent: ramping the torque scale down.
    Fault(Fault),
    /// The patient paused the exercise: ramping down, then zero torque until resumed (a
    /// resume soft-starts).
    Paused,
    /// A stop was requested: ramping down, then [`WatchdogState::Stopped`].
    Stopping,
    /// Stopped for good: zero torque until a new supervisor is made.
    Stopped,
}

/// Output of one supervised tick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Supervised {
    /// The torque that may go to the motor, N·m.
    pub torque_nm: f64,
    /// The ceiling or slew limit changed the (scaled) request.
    pub clipped: bool,
    /// The request was NaN or infinite.
    pub rejected_non_finite: bool,
    /// Soft-start / fade scale applied to the request, 0..=1.
    pub scale: f64,
    /// The watchdog's state after this tick.
    pub state: WatchdogState,
}

/// Soft start, fade-out, watchdog and limiter: the safety chain as one state machine.
///
/// Each tick the request is multiplied by a scale in [0, 1] and passed through the
/// [`TorqueLimiter`]. The scale rises over `soft_start_s` while healthy and falls over
/// `fade_out_s` while faulted or stopping. A fault keeps the scale falling for at least
/// `fade_out_s` (so a single missed tick still ramps the torque to zero), after which a
/// healthy loop soft-starts again. A pause fades like a stop but is not final: on resume the
/// scale soft-starts from wherever it is. A stop is final.
#[derive(Clone, Debug)]
pub struct Supervisor {
    cfg: SafetyConfig,
    limiter: TorqueLimiter,
    scale: f64,
    last_tick_ns: Option<u64>,
    fault_until_ns: u64,
    fault: Option<Fault>,
    paused: bool,
    stopping: bool,
}

impl Supervisor {
    /// A supervisor for a device producing at most `device_max_nm`, starting at zero torque.
    pub fn new(cfg: SafetyConfig, device_max_nm: f64) -> Result<Self, WheelError> {
        cfg.validate(device_max_nm)?;
        Ok(Self {
            limiter: TorqueLimiter::new(cfg.effective_ceiling_nm(device_max_nm), cfg.slew_nm_per_s),
            cfg,
            scale: 0.0,
            last_tick_ns: None,
            fault_until_ns: 0,
            fault: None,
            paused: false,
            stopping: false,
        })
    }

    /// The ceiling in force, N·m.
    pub fn ceiling_nm(&self) -> f64 {
        self.limiter.ceiling_nm()
    }

    /// Lower or raise the per-patient ceiling at run time, never above `device_max_nm`.
    /// Takes effect on the next tick (a lower ceiling at once, not slewed).
    pub fn set_ceiling_nm(
        &mut self,
        ceiling_nm: f64,
        device_max_nm: f64,
    ) -> Result<(), WheelError> {
        let cfg = SafetyConfig {
            ceiling_nm: Some(ceiling_nm),
            ..self.cfg
        };
        cfg.validate(device_max_nm)?;
        let last = self.limiter.last_nm();
        self.limiter = TorqueLimiter::new(ceiling_nm, cfg.slew_nm_per_s);
        self.limiter.last_nm = last.clamp(-ceiling_nm, ceiling_nm);
        self.cfg = cfg;
        Ok(())
    }

    /// Ask for a fade-out to zero and a final stop.
    pub fn request_stop(&mut self) {
        self.stopping = true;
    }

    /// Pause (fade to zero and hold there) or resume (soft start) the torque; a stop
    /// overrides both.
    pub fn set_paused(&mut self, paused: bool) {
        self.paused = paused;
    }

    /// The last torque let through, N·m.
    pub fn last_nm(&self) -> f64 {
        self.limiter.last_nm()
    }

    /// Supervise `requested_nm` at `now_ns` given the timestamp of the wheel reading used
    /// this tick (`None` if the read failed). Returns the torque to send.
    pub fn apply(
        &mut self,
        requested_nm: f64,
        now_ns: u64,
        reading_t_ns: Option<u64>,
    ) -> Supervised {
        let gap_s = self
            .last_tick_ns
            .map_or(0.0, |t| now_ns.saturating_sub(t) as f64 * 1e-9);
        // A clock going backwards counts as a missed deadline too.
        let backwards = self.last_tick_ns.is_some_and(|t| now_ns < t);
        self.last_tick_ns = Some(now_ns);
        let stale = match reading_t_ns {
            None => true,
            Some(t) => t > now_ns || (now_ns - t) as f64 * 1e-9 > self.cfg.max_reading_age_s,
        };
        let fault_now = if backwards || gap_s > self.cfg.max_tick_gap_s {
            Some(Fault::MissedDeadline)
        } else if stale {
            Some(Fault::StaleReading)
        } else {
            None
        };
        if let Some(f) = fault_now {
            self.fault = Some(f);
            self.fault_until_ns = now_ns.saturating_add((self.cfg.fade_out_s * 1e9) as u64);
        } else if now_ns >= self.fault_until_ns {
            self.fault = None;
        }
        // Ramps use the real elapsed time, capped so one long stall cannot jump the scale
        // up; the first tick ramps by nothing.
        let dt = gap_s.min(self.cfg.max_tick_gap_s);
        let state = if self.stopping {
            self.scale = (self.scale - gap_s / self.cfg.fade_out_s).max(0.0);
            if self.scale == 0.0 && self.limiter.last_nm() == 0.0 {
                WatchdogState::Stopped
            } else {
                WatchdogState::Stopping
            }
        } else if let Some(f) = self.fault {
            // Fade by the real gap: after a stall the torque has been stale for that long.
            self.scale = (self.scale - gap_s / self.cfg.fade_out_s).max(0.0);
            WatchdogState::Fault(f)
        } else if self.paused {
            self.scale = (self.scale - gap_s / self.cfg.fade_out_s).max(0.0);
            WatchdogState::Paused
        } else {
            self.scale = (self.scale + dt / self.cfg.soft_start_s).min(1.0);
            if self.scale < 1.0 {
                WatchdogState::SoftStart
            } else {
                WatchdogState::Running
            }
        };
        let rejected = !requested_nm.is_finite();
        let want = if rejected {
            0.0
        } else {
            requested_nm * self.scale
        };
        // The slew limit uses the nominal-capped dt, so a stall never allows a big step.
        let out = if state == WatchdogState::Stopped {
            self.limiter.last_nm = 0.0;
            LimitedTorque {
                torque_nm: 0.0,
                clipped: want != 0.0,
                rejected_non_finite: rejected,
            }
        } else {
            self.limiter.apply(want, dt.max(1e-4))
        };
        Supervised {
            torque_nm: out.torque_nm,
            clipped: out.clipped && !rejected,
            rejected_non_finite: rejected,
            scale: self.scale,
            state,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #[test]
        fn output_never_exceeds_ceiling_or_slew(reqs in proptest::collection::vec(prop_oneof![
            any::<f64>(), -10.0f64..10.0, Just(f64::NAN), Just(f64::INFINITY)], 1..200)) {
            let mut lim = TorqueLimiter::new(1.87, 50.0);
            let mut last = 0.0;
            for r in reqs {
                let out = lim.apply(r, 0.001);
                prop_assert!(out.torque_nm.is_finite());
                prop_assert!(out.torque_nm.abs() <= 1.87);
                prop_assert!((out.torque_nm - last).abs() <= 50.0 * 0.001 + 1e-12);
                last = out.torque_nm;
            }
        }
    }

    #[test]
    fn nan_request_ramps_to_zero() {
        let mut lim = TorqueLimiter::new(1.87, 10.0);
        for _ in 0..500 {
            lim.apply(1.5, 0.001);
        }
        let out = lim.apply(f64::NAN, 0.001);
        assert!(out.rejected_non_finite);
        assert!((out.torque_nm - 1.49).abs() < 1e-9);
    }

    fn sup() -> Supervisor {
        Supervisor::new(
            SafetyConfig {
                soft_start_s: 0.1,
                fade_out_s: 0.05,
                ..Default::default()
            },
            1.87,
        )
        .unwrap()
    }

    /// Run healthy 1 kHz ticks requesting `req` from `t0_ms` for `n` ticks.
    fn run(s: &mut Supervisor, t0_ms: u64, n: u64, req: f64) -> Supervised {
        let mut out = None;
        for k in 0..n {
            let now = (t0_ms + k) * 1_000_000;
            out = Some(s.apply(req, now, Some(now)));
        }
        out.unwrap()
    }

    #[test]
    fn soft_start_ramps_the_torque_up_over_the_configured_time() {
        let mut s = sup();
        let half = run(&mut s, 0, 51, 1.0);
        assert_eq!(half.state, WatchdogState::SoftStart);
        assert!((half.torque_nm - 0.5).abs() < 0.011, "{half:?}");
        let full = run(&mut s, 51, 60, 1.0);
        assert_eq!(full.state, WatchdogState::Running);
        assert!((full.torque_nm - 1.0).abs() < 1e-9);
    }

    #[test]
    fn missed_tick_ramps_to_zero_then_soft_starts_again() {
        let mut s = sup();
        run(&mut s, 0, 200, 1.0);
        // The loop stalls for 30 ms: a missed deadline.
        let now = 230 * 1_000_000;
        let out = s.apply(1.0, now, Some(now));
        assert_eq!(out.state, WatchdogState::Fault(Fault::MissedDeadline));
        assert!(out.scale <= 0.4 + 1e-9, "{out:?}");
        // Keeps fading for fade_out_s even though ticks are healthy again.
        let out = run(&mut s, 231, 40, 1.0);
        assert_eq!(out.state, WatchdogState::Fault(Fault::MissedDeadline));
        assert_eq!(out.torque_nm, 0.0);
        // Then recovers through a soft start.
        let out = run(&mut s, 271, 20, 1.0);
        assert_eq!(out.state, WatchdogState::SoftStart);
        let out = run(&mut s, 291, 200, 1.0);
        assert_eq!(out.state, WatchdogState::Running);
    }

    #[test]
    fn stale_or_missing_reading_fades_the_torque_out() {
        let mut s = sup();
        run(&mut s, 0, 200, 1.0);
        let mut out = None;
        for k in 200..300u64 {
            let now = k * 1_000_000;
            // The reading stopped updating at t = 199 ms.
            out = Some(s.apply(1.0, now, Some(199_000_000)));
        }
        let out = out.unwrap();
        assert_eq!(out.state, WatchdogState::Fault(Fault::StaleReading));
        assert_eq!(out.torque_nm, 0.0);
        let now = 301_000_000;
        assert_eq!(
            s.apply(1.0, now, None).state,
            WatchdogState::Fault(Fault::StaleReading)
        );
    }

    #[test]
    fn stop_fades_out_and_latches() {
        let mut s = sup();
        run(&mut s, 0, 200, 1.5);
        s.request_stop();
        let out = run(&mut s, 200, 100, 1.5);
        assert_eq!(out.state, WatchdogState::Stopped);
        assert_eq!(out.torque_nm, 0.0);
        let out = run(&mut s, 300, 1000, 1.5);
        assert_eq!(out.torque_nm, 0.0, "a stop is final");
    }

    #[test]
    fn pause_fades_to_zero_holds_and_resume_soft_starts() {
        let mut s = sup();
        run(&mut s, 0, 200, 1.5);
        s.set_paused(true);
        let out = run(&mut s, 200, 100, 1.5);
        assert_eq!(out.state, WatchdogState::Paused);
        assert_eq!(out.torque_nm, 0.0);
        let out = run(&mut s, 300, 1000, 1.5);
        assert_eq!(out.torque_nm, 0.0, "held at zero while paused");
        s.set_paused(false);
        let out = run(&mut s, 1300, 50, 1.5);
        assert_eq!(out.state, WatchdogState::SoftStart);
        assert!(out.torque_nm > 0.0 && out.torque_nm < 1.5, "{out:?}");
        let out = run(&mut s, 1350, 200, 1.5);
        assert_eq!(out.state, WatchdogState::Running);
        assert!((out.torque_nm - 1.5).abs() < 1e-9);
    }

    #[test]
    fn stop_while_paused_is_final() {
        let mut s = sup();
        run(&mut s, 0, 200, 1.5);
        s.set_paused(true);
        run(&mut s, 200, 100, 1.5);
        s.request_stop();
        s.set_paused(false);
        let out = run(&mut s, 300, 500, 1.5);
        assert_eq!(out.state, WatchdogState::Stopped);
        assert_eq!(out.torque_nm, 0.0);
    }

    #[test]
    fn ceiling_above_the_device_maximum_is_refused_with_the_field_name() {
        let cfg = SafetyConfig {
            ceiling_nm: Some(2.5),
            ..Default::default()
        };
        let msg = Supervisor::new(cfg, 1.87).unwrap_err().to_string();
        assert!(msg.contains("ceiling_nm") && msg.contains("1.87"), "{msg}");
        let mut s = sup();
        assert!(s.set_ceiling_nm(f64::NAN, 1.87).is_err());
        s.set_ceiling_nm(0.5, 1.87).unwrap();
        let out = run(&mut s, 0, 2000, 1.8);
        assert_eq!(out.torque_nm, 0.5);
        assert!(out.clipped);
    }

    #[test]
    fn lowering_the_ceiling_at_run_time_holds_immediately() {
        let mut s = sup();
        run(&mut s, 0, 500, 1.8);
        s.set_ceiling_nm(0.3, 1.87).unwrap();
        let now = 500_000_000;
        assert!(s.apply(1.8, now, Some(now)).torque_nm <= 0.3);
    }
}
