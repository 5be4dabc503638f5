//! Movement measures as robot assessments of stroke report them (InMotion, Kinarm), defined
//! for the wheel's one angle.
//!
//! - **Speed metric** ([`crate::speed_metric`], beside the other measures of one movement): a movement's mean speed over its peak speed, 1 for a
//!   constant speed, 0.533 for a whole minimum-jerk movement (1/1.875); it rises as the
//!   speed profile fills out with recovery. Rohrer B, Fasoli S, Krebs HI, Hughes R, Volpe B,
//!   Frontera WR, Stein J, Hogan N (2002) "Movement smoothness changes during stroke
//!   recovery", J Neurosci 22(18):8297–8304.
//! - **Number of speed peaks** and **movement time**: per movement, [`crate::Movement`]'s
//!   `n_peaks` and `duration_s` (Rohrer et al. 2002; Coderre AM, Zeid AA, Dukelow SP, Demmer
//!   MJ, Moore KD, Demers MJ, Bretzke H, Herter TM, Glasgow JI, Norman KE, Bagg SD, Scott SH
//!   (2010) "Assessment of upper-limb sensorimotor function of subacute stroke patients using
//!   visually guided reaching", Neurorehabil Neural Repair 24(6):528–541).
//! - **Reaction time**, **initial direction error**, **path length ratio**: per step change
//!   of the target ([`step_responses`]), as Coderre et al. 2010 define them for a reach to a
//!   target that appears, restated for a 1-D wheel angle (see [`StepResponse`]), with each
//!   response measured as one discrete movement from its onset to its rest
//!   ([`StepResponse::movement`]: its time, SPARC and LDLJ). A lane
//!   change asks for a turn of known way but no fixed size when its lane shifts: reaction
//!   time and initial direction error only ([`directed_step_responses`]), the onset signed,
//!   since the patient sees the shift coming and may steer before reaching it.
//! - **Anticipation** ([`DirectedResponse::anticipated`]): a response to a predictable cue (a
//!   lane shift visible ahead) starting earlier than [`MIN_REACTION_TIME_S`] after it is no
//!   reaction but an anticipation; reaction time is a measure of unpredictable steps only (a
//!   dial target's random jumps).
//! - **Dose** ([`steering_reversals`]; per minute in [`crate::SessionMeasures`]): movements
//!   and steering reversals per active minute. Reversals as Markkula G, Engström J (2006) "A
//!   steering wheel reversal rate metric for assessing effects of visual and cognitive
//!   secondary task load", ITS World Congress, London, count them: a change of the wheel's
//!   direction once it has gone back by at least a gap from its last extremum. Krebs HI,
//!   Hogan N et al. (InMotion; e.g. Krebs et al. 2004 "Rehabilitation robotics: pilot trial of
//!   a spatial extension for MIT-Manus", J NeuroEng Rehabil 1:5) and Lang CE et al. (2009) "Observation
//!   of amounts of movement practice provided during stroke rehabilitation", Arch Phys Med
//!   Rehabil 90(10):1692–1698, count the dose in movements.
//!
//! SPARC, the smoothness measure of these robots' later studies, is in [`crate::sparc`]
//! (Balasubramanian S, Melendez-Calderon A, Burdet E (2012) "A robust and sensitive metric for
//! quantifying movement smoothness", IEEE Trans Biomed Eng 59(8):2126–2136; Balasubramanian
//! et al. 2015, J NeuroEng Rehabil 12:112).

use serde::{Deserialize, Serialize};

use crate::error::{MetricError, check_fs, check_signal};
use crate::filter::speed_profile;

/// The shortest physiological reaction time, s: a movement starting sooner after a cue did
/// not answer it (it was started before, on a prediction). 0.1 s, the false-start bound of
/// sprint starts (World Athletics Technical Rules, TR 16.6; Pain MTG, Hibbs A (2007) "Sprint
/// starts and the minimum auditory reaction time", J Sports Sci 25(1):79–86, found none
/// faster than about 0.085 s); visual reactions, the wheel's, are slower still (Luce RD 1986,
/// "Response Times", ch. 2: ~0.18 s), so the bound never takes a true reaction for an
/// anticipation.
pub const MIN_REACTION_TIME_S: f64 = 0.1;

/// Steering reversals of an angle signal (rad) with a gap of `gap_rad` (Markkula & Engström
/// 2006): once the angle has moved `gap_rad` one way from where it started, each time it goes
/// back by at least `gap_rad` from its furthest point is one reversal. The first direction
/// taken is no reversal; movements smaller than the gap (tremor, noise) are none. A sine of
/// amplitude `A ≥ gap_rad` over `k` whole cycles from 0 has `2k` reversals.
///
/// # Errors
/// A non-finite sample (its index is named), or `gap_rad` not finite and > 0.
pub fn steering_reversals(angle_rad: &[f64], gap_rad: f64) -> Result<usize, MetricError> {
    if !(gap_rad.is_finite() && gap_rad > 0.0) {
        return Err(MetricError::BadParameter {
            context: "steering_reversals",
            field: "gap_rad",
            value: gap_rad,
            allowed: "finite and > 0 rad",
        });
    }
    if angle_rad.is_empty() {
        return Ok(0);
    }
    check_signal("wheel angle", angle_rad, 1)?;
    let (mut lo, mut hi) = (angle_rad[0], angle_rad[0]);
    // +1 going up (`hi` its furthest point), −1 going down (`lo`), 0 not yet a gap either way.
    let mut dir = 0_i8;
    let mut reversals = 0;
    for &x in angle_rad {
        lo = lo.min(x);
        hi = hi.max(x);
        match dir {
            1 if hi - x >= gap_rad => {
                (dir, lo, reversals) = (-1, x, reversals + 1);
            }
            -1 if x - lo >= gap_rad => {
                (dir, hi, reversals) = (1, x, reversals + 1);
            }
            0 if x - lo >= gap_rad => (dir, hi) = (1, x),
            0 if hi - x >= gap_rad => (dir, lo) = (-1, x),
            _ => {}
        }
    }
    Ok(reversals)
}

/// A step change of the target: at sample `index` the target jumps to `target_rad`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TargetStep {
    /// The first sample with the new target.
    pub index: usize,
    /// The new target, rad.
    pub target_rad: f64,
}

/// Parameters of [`step_responses`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ResponseParams {
    /// Low-pass cut-off of the speed profile ([`speed_profile`]), Hz. Default 10 Hz.
    pub lowpass_hz: f64,
    /// Movement onset: the speed first above this fraction of the response's peak speed (or
    /// [`floor_rad_s`](Self::floor_rad_s), whichever is larger). Default 0.1 (Coderre et al.
    /// 2010 use 10 % of peak hand speed).
    pub onset_fraction: f64,
    /// Below this speed nothing counts as a response, rad/s. Default 0.05 rad/s.
    pub floor_rad_s: f64,
    /// A response is looked for until the next step or this long after the step, s.
    /// Default 4 s.
    pub max_window_s: f64,
    /// Steps asking for less movement than this (the wheel already near the new target) get
    /// no direction error nor path length ratio, rad. Default 0.05 rad (≈ 2.9°).
    pub min_distance_rad: f64,
    /// A step's response starts with a run of the speed above the onset threshold at least
    /// this long, s: a shorter burst (a tremor's, motor noise's) is no movement. Default
    /// 0.1 s, the gap [`segment`](fn@crate::segment) merges into one movement (its `merge_gap_s`).
    #[serde(default = "default_min_run_s")]
    pub min_run_s: f64,
}

fn default_min_run_s() -> f64 {
    0.1
}

impl Default for ResponseParams {
    fn default() -> Self {
        Self {
            lowpass_hz: 10.0,
            onset_fraction: 0.1,
            floor_rad_s: 0.05,
            max_window_s: 4.0,
            min_distance_rad: 0.05,
            min_run_s: default_min_run_s(),
        }
    }
}

impl ResponseParams {
    /// Check every field against its allowed range.
    ///
    /// # Errors
    /// [`MetricError::BadParameter`] naming the first field out of range.
    pub fn validate(&self) -> Result<(), MetricError> {
        let fields = [
            ("lowpass_hz", self.lowpass_hz, self.lowpass_hz > 0.0),
            (
                "onset_fraction",
                self.onset_fraction,
                (0.0..1.0).contains(&self.onset_fraction),
            ),
            ("floor_rad_s", self.floor_rad_s, self.floor_rad_s >= 0.0),
            ("max_window_s", self.max_window_s, self.max_window_s > 0.0),
            (
                "min_distance_rad",
                self.min_distance_rad,
                self.min_distance_rad >= 0.0,
            ),
            ("min_run_s", self.min_run_s, self.min_run_s >= 0.0),
        ];
        for (field, value, ok) in fields {
            if !(ok && value.is_finite()) {
                return Err(MetricError::BadParameter {
                    context: "ResponseParams",
                    field,
                    value,
                    allowed: "finite; fractions in [0, 1), times and rates > 0, floors >= 0",
                });
            }
        }
        Ok(())
    }
}

/// The wheel's response to one step of the target, as Coderre et al. 2010 measure a reach to
/// a target that appears, for one angle.
///
/// The response starts with the first run of the speed above the onset threshold
/// `max(onset_fraction · peak, floor)` that begins after the step and lasts at least
/// `min_run_s` (Coderre et al. 2010: 10 % of the peak speed). Two things the wheel does are
/// no onset: a movement still going when the target stepped (the speed above the threshold
/// at the step: the response can only start once it has fallen below), and a burst shorter
/// than `min_run_s` (tremor, motor noise). `peak` is the response's own peak speed: the
/// window's, after a movement in progress at the step has fallen below the threshold.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct StepResponse {
    /// The step responded to.
    pub step: TargetStep,
    /// From the step to the response's onset, s; `None` when the wheel made no movement in
    /// the window that started after the step (still, or moving throughout).
    pub reaction_time_s: Option<f64>,
    /// The initial direction error of a 1-D wheel angle: the direction of the wheel's
    /// displacement from the movement's onset to its first speed peak against the direction
    /// from the wheel's angle at the step to the new target: 0° the right way, 180° the
    /// wrong way (a single angle has no angles in between). `None` without a movement or
    /// when less than `min_distance_rad` was asked.
    pub initial_direction_error_deg: Option<f64>,
    /// Path travelled by the wheel angle (`Σ|Δθ|`) from the movement's onset to its end (the
    /// last sample above the onset threshold in the window) over the straight distance
    /// needed, `|target − θ(step)|`; 1 for a direct movement that stops on the target, more
    /// with overshoots and corrections. `None` without a movement or when less than
    /// `min_distance_rad` was asked.
    pub path_length_ratio: Option<f64>,
    /// The response as one discrete movement, from its onset to its end (the first sample
    /// back at or below the threshold after the last above it in the window): its time,
    /// peak speed, speed peaks, speed metric, SPARC and LDLJ, as [`segment`](fn@crate::segment) measures
    /// a movement from rest to rest. `None` unless the response came to rest before the
    /// window closed (the next step, `max_window_s` or the signal's end): a movement cut by
    /// the next step is not a whole movement, and its smoothness is not the published one.
    #[serde(default)]
    pub movement: Option<crate::Movement>,
}

/// The wheel's response to each step of the target in one continuous angle signal (rad,
/// sampled at `fs_hz`); `steps` in time order, indices into `angle_rad`. The window of a step
/// runs to the next step, `max_window_s`, or the signal's end, whichever is first.
///
/// # Errors
/// `fs_hz` not finite and > 0, a non-finite angle sample (its index named), parameters out of
/// range, or steps out of order or past the signal's end.
pub fn step_responses(
    angle_rad: &[f64],
    fs_hz: f64,
    steps: &[TargetStep],
    params: &ResponseParams,
) -> Result<Vec<StepResponse>, MetricError> {
    check_fs(fs_hz)?;
    params.validate()?;
    if steps.is_empty() {
        return Ok(Vec::new());
    }
    check_signal("wheel angle", angle_rad, 2)?;
    let n = angle_rad.len();
    check_steps(
        steps.iter().map(|s| (s.index, s.target_rad.is_finite())),
        n,
        "step_responses",
        "indices in time order within the signal, finite targets",
    )?;
    let speed = speed_profile(angle_rad, fs_hz, params.lowpass_hz);
    let max_window = ((params.max_window_s * fs_hz).round() as usize).max(1);
    Ok(steps
        .iter()
        .enumerate()
        .map(|(k, &step)| {
            let next = steps.get(k + 1).map_or(n, |s| s.index);
            let end = next.min(step.index + max_window).min(n);
            respond(angle_rad, &speed, fs_hz, step, end, params)
        })
        .collect())
}

/// The response to `step` within `angle[step.index..end]`.
fn respond(
    angle: &[f64],
    speed: &[f64],
    fs_hz: f64,
    step: TargetStep,
    end: usize,
    params: &ResponseParams,
) -> StepResponse {
    let none = StepResponse {
        step,
        reaction_time_s: None,
        initial_direction_error_deg: None,
        path_length_ratio: None,
        movement: None,
    };
    let i0 = step.index;
    let Some(r) = response_in(speed, i0, end, fs_hz, params) else {
        return none;
    };
    let needed = step.target_rad - angle[i0];
    let asked = needed.abs() >= params.min_distance_rad;
    let before_onset = r.onset.saturating_sub(1).max(i0);
    let initial = angle[r.first_peak] - angle[before_onset];
    let initial_direction_error_deg = asked
        .then(|| direction_error_deg(initial, needed.signum()))
        .flatten();
    let path: f64 = angle[before_onset..=r.last]
        .windows(2)
        .map(|w| (w[1] - w[0]).abs())
        .sum();
    StepResponse {
        step,
        reaction_time_s: Some((r.onset - i0) as f64 / fs_hz),
        initial_direction_error_deg,
        path_length_ratio: asked.then(|| path / needed.abs()),
        movement: (r.last + 1 < end).then(|| {
            crate::segment::movement(
                speed,
                r.onset,
                r.last + 1,
                fs_hz,
                true,
                &crate::SegmentParams::default(),
            )
        }),
    }
}

/// Where a step's response lies in the speed profile (indices into it).
struct Response {
    /// The first sample of the response's first run above the threshold.
    onset: usize,
    /// The first speed peak after the onset.
    first_peak: usize,
    /// The last sample above the threshold in the window.
    last: usize,
}

/// The response to a step at `start` in `speed[start..end]`, as [`StepResponse`] defines its
/// onset; `None` when the wheel makes no such movement in the window.
fn response_in(
    speed: &[f64],
    start: usize,
    end: usize,
    fs_hz: f64,
    params: &ResponseParams,
) -> Option<Response> {
    let threshold = |w: &[f64]| {
        let peak = w.iter().copied().fold(0.0, f64::max);
        (params.onset_fraction * peak).max(params.floor_rad_s)
    };
    let window = &speed[start..end];
    // A movement in progress at the step, by the whole window's threshold, then the
    // response's own threshold from where that movement has fallen below it.
    let settled = window.iter().position(|&v| v <= threshold(window))?;
    let v_th = threshold(&window[settled..]);
    let quiet = settled + window[settled..].iter().position(|&v| v <= v_th)?;
    let min_run = ((params.min_run_s * fs_hz).round() as usize).max(1);
    let mut k = quiet;
    let onset = loop {
        let from = k + window[k..].iter().position(|&v| v > v_th)?;
        let run = window[from..].iter().take_while(|&&v| v > v_th).count();
        if run >= min_run {
            break from;
        }
        k = from + run;
    };
    let last = onset + window[onset..].iter().rposition(|&v| v > v_th)?;
    let (onset, last) = (start + onset, start + last);
    let first_peak = (onset..last)
        .find(|&j| speed[j + 1] < speed[j])
        .unwrap_or(last);
    Some(Response {
        onset,
        first_peak,
        last,
    })
}

/// Steps given as `(index, valid)` are in time order within a signal of `n` samples and
/// valid; the error names the first that is not, for `context`.
fn check_steps(
    steps: impl Iterator<Item = (usize, bool)>,
    n: usize,
    context: &'static str,
    allowed: &'static str,
) -> Result<(), MetricError> {
    let mut previous: Option<usize> = None;
    for (index, valid) in steps {
        if index >= n || previous.is_some_and(|p| p >= index) || !valid {
            return Err(MetricError::BadParameter {
                context,
                field: "steps",
                value: index as f64,
                allowed,
            });
        }
        previous = Some(index);
    }
    Ok(())
}

/// The initial direction error of a one-angle movement `initial_rad` against the way
/// `wanted_sign` (±1): 0° the right way, 180° the wrong way; `None` when it did not move.
fn direction_error_deg(initial_rad: f64, wanted_sign: f64) -> Option<f64> {
    (initial_rad != 0.0).then(|| {
        if initial_rad.signum() == wanted_sign {
            0.0
        } else {
            180.0
        }
    })
}

/// The movement in `speed[start..end]`: its onset (the first sample above
/// `max(onset_fraction · peak, floor)`), its first speed peak (the first sample after the onset
/// not exceeded by the next one) and its end (the last sample above the threshold); `None`
/// when nothing in the window exceeds the threshold.
fn movement_in(
    speed: &[f64],
    start: usize,
    end: usize,
    params: &ResponseParams,
) -> Option<(usize, usize, usize)> {
    let window = &speed[start..end];
    let peak = window.iter().copied().fold(0.0, f64::max);
    let v_th = (params.onset_fraction * peak).max(params.floor_rad_s);
    let onset = start + window.iter().position(|&v| v > v_th)?;
    let last = start + window.iter().rposition(|&v| v > v_th).unwrap_or(0);
    let first_peak = (onset..last)
        .find(|&j| speed[j + 1] < speed[j])
        .unwrap_or(last);
    Some((onset, first_peak, last))
}

/// A change of what is asked whose way is known but not its size: a lane change's lane
/// starting to move over, which asks the wheel to turn one way first (then back to follow the
/// new lane) by an amount that depends on the car's speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DirectedStep {
    /// The sample at which the change happens (the car reaches the shift).
    pub index: usize,
    /// The way the wheel must turn first: +1 towards positive angles, −1 towards negative.
    pub direction: f64,
}

impl DirectedResponse {
    /// The movement started earlier than [`MIN_REACTION_TIME_S`] after the change (before it,
    /// too): an anticipation of a predictable cue, not a reaction to it. `None` when the
    /// wheel did not move.
    #[must_use]
    pub fn anticipated(&self) -> Option<bool> {
        self.reaction_time_s.map(|t| t < MIN_REACTION_TIME_S)
    }
}

/// The wheel's response to a [`DirectedStep`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DirectedResponse {
    /// The change responded to.
    pub step: DirectedStep,
    /// From the change to the movement's onset, s (as [`StepResponse`]'s, the onset at
    /// `max(onset_fraction · peak, floor)` of the window's speed); negative when the wheel
    /// started before the change, as a patient who sees the lane shift coming ahead may (the
    /// window opens `lead_s` before the change). `None` when the wheel did not move. Below
    /// [`MIN_REACTION_TIME_S`] it is an anticipation ([`Self::anticipated`]), not a reaction
    /// time.
    pub reaction_time_s: Option<f64>,
    /// The way of the wheel's displacement from the onset to its first speed peak against
    /// the way asked: 0° the right way, 180° the wrong way. `None` without a movement.
    pub initial_direction_error_deg: Option<f64>,
}

/// The wheel's response to each [`DirectedStep`] in one continuous angle signal (rad, sampled
/// at `fs_hz`), `steps` in time order. A change's window opens `lead_s` before it (not before
/// the previous change) and runs to `lead_s` before the next change, `max_window_s` after it,
/// or the signal's end, whichever is first. No path length ratio: the turn a lane change asks
/// has no fixed size.
///
/// # Errors
/// `fs_hz` not finite and > 0, `lead_s` not finite and ≥ 0, a non-finite angle sample,
/// parameters out of range, steps out of order or past the signal's end, or a direction not
/// ±1.
pub fn directed_step_responses(
    angle_rad: &[f64],
    fs_hz: f64,
    steps: &[DirectedStep],
    lead_s: f64,
    params: &ResponseParams,
) -> Result<Vec<DirectedResponse>, MetricError> {
    check_fs(fs_hz)?;
    params.validate()?;
    if !(lead_s.is_finite() && lead_s >= 0.0) {
        return Err(MetricError::BadParameter {
            context: "directed_step_responses",
            field: "lead_s",
            value: lead_s,
            allowed: "finite and >= 0 s",
        });
    }
    if steps.is_empty() {
        return Ok(Vec::new());
    }
    check_signal("wheel angle", angle_rad, 2)?;
    let n = angle_rad.len();
    check_steps(
        steps.iter().map(|s| (s.index, s.direction.abs() == 1.0)),
        n,
        "directed_step_responses",
        "indices in time order within the signal, directions ±1",
    )?;
    let speed = speed_profile(angle_rad, fs_hz, params.lowpass_hz);
    let max_window = ((params.max_window_s * fs_hz).round() as usize).max(1);
    let lead = (lead_s * fs_hz).round() as usize;
    Ok(steps
        .iter()
        .enumerate()
        .map(|(k, &step)| {
            let previous = if k == 0 { 0 } else { steps[k - 1].index };
            let start = step.index.saturating_sub(lead).max(previous);
            let next = steps.get(k + 1).map_or(n, |s| s.index.saturating_sub(lead));
            let end = next.min(step.index + max_window).min(n).max(step.index + 1);
            let Some((onset, first_peak, _)) = movement_in(&speed, start, end, params) else {
                return DirectedResponse {
                    step,
                    reaction_time_s: None,
                    initial_direction_error_deg: None,
                };
            };
            let before_onset = onset.saturating_sub(1).max(start);
            let initial = angle_rad[first_peak] - angle_rad[before_onset];
            DirectedResponse {
                step,
                reaction_time_s: Some((onset as f64 - step.index as f64) / fs_hz),
                initial_direction_error_deg: direction_error_deg(initial, step.direction),
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Minimum-jerk position from 0 to 1 over `tau` in [0, 1].
    fn min_jerk(tau: f64) -> f64 {
        let t = tau.clamp(0.0, 1.0);
        10.0 * t.powi(3) - 15.0 * t.powi(4) + 6.0 * t.powi(5)
    }

    #[test]
    fn a_sine_of_three_cycles_has_six_reversals_and_noise_below_the_gap_none() {
        let fs = 100.0;
        let gap = 2.0_f64.to_radians();
        let sine: Vec<f64> = (0..=600)
            .map(|i| 0.5 * (std::f64::consts::TAU * 0.5 * f64::from(i) / fs).sin())
            .collect();
        assert_eq!(steering_reversals(&sine, gap).unwrap(), 6);
        // Uniform noise of ±0.9° (a fixed-seed LCG) around a hold: never a 2° swing.
        let mut state = 0x2545_f491_4f6c_dd1d_u64;
        let noise: Vec<f64> = (0..5000)
            .map(|_| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                let u = (state >> 11) as f64 / (1_u64 << 53) as f64;
                0.3 + (2.0 * u - 1.0) * 0.9_f64.to_radians()
            })
            .collect();
        assert_eq!(steering_reversals(&noise, gap).unwrap(), 0);
        assert_eq!(steering_reversals(&[], gap).unwrap(), 0);
        assert!(steering_reversals(&sine, 0.0).is_err());
    }

    /// A step at 1 s to 0.5 rad; the wheel waits `delay_s`, then makes a minimum-jerk turn of
    /// 0.5 rad · `direction` over 0.8 s, then (when `direction` < 0) turns back over 1.6 s.
    fn response_to_a_step(delay_s: f64, direction: f64) -> (Vec<f64>, TargetStep) {
        let fs = 100.0;
        let angle = (0..500)
            .map(|i| {
                let t = f64::from(i) / fs - 1.0 - delay_s;
                let out = 0.5 * direction * min_jerk(t / 0.8);
                let back = if direction < 0.0 {
                    min_jerk((t - 0.8) / 1.6)
                } else {
                    0.0
                };
                out + (0.5 - out) * back
            })
            .collect();
        let step = TargetStep {
            index: 100,
            target_rad: 0.5,
        };
        (angle, step)
    }

    #[test]
    fn a_direct_response_has_its_delay_as_reaction_time_no_direction_error_and_path_ratio_one() {
        let (angle, step) = response_to_a_step(0.3, 1.0);
        let r = step_responses(&angle, 100.0, &[step], &ResponseParams::default()).unwrap();
        let r = r[0];
        // The onset at 10 % of the peak speed comes 0.8 · 0.086 ≈ 0.069 s into the turn
        // (30 τ²(1−τ)² = 0.1875 at τ ≈ 0.086).
        let rt = r.reaction_time_s.unwrap();
        assert!((rt - (0.3 + 0.069)).abs() < 0.02, "{rt}");
        assert_eq!(r.initial_direction_error_deg, Some(0.0));
        let p = r.path_length_ratio.unwrap();
        assert!((0.95..1.01).contains(&p), "{p}");
    }

    #[test]
    fn a_response_that_starts_the_wrong_way_has_180_degrees_and_path_ratio_three() {
        let (angle, step) = response_to_a_step(0.2, -1.0);
        let r = step_responses(&angle, 100.0, &[step], &ResponseParams::default()).unwrap()[0];
        assert_eq!(r.initial_direction_error_deg, Some(180.0));
        // Out 0.5 rad the wrong way, then back 1 rad: 1.5 rad for 0.5 rad needed.
        let p = r.path_length_ratio.unwrap();
        assert!((2.85..3.01).contains(&p), "{p}");
        assert!(r.reaction_time_s.unwrap() > 0.2);
    }

    #[test]
    fn a_wheel_that_never_moves_has_no_response_and_bad_steps_are_refused() {
        let still = vec![0.1; 300];
        let step = TargetStep {
            index: 50,
            target_rad: 0.6,
        };
        let r = step_responses(&still, 100.0, &[step], &ResponseParams::default()).unwrap();
        assert_eq!(r[0].reaction_time_s, None);
        assert_eq!(r[0].path_length_ratio, None);
        let late = TargetStep { index: 300, ..step };
        assert!(step_responses(&still, 100.0, &[late], &ResponseParams::default()).is_err());
        let unordered = [step, step];
        assert!(step_responses(&still, 100.0, &unordered, &ResponseParams::default()).is_err());
    }

    /// Issue 42: the steps part's reaction times were 0–0.05 s for patients whose wheel was
    /// still moving (or trembling) when the target stepped. A movement under way at the step
    /// and a burst shorter than `min_run_s` are no onset: the reaction time is the delay to
    /// the response's own movement.
    #[test]
    fn a_movement_under_way_at_the_step_or_a_short_burst_is_no_onset() {
        let fs = 100.0;
        // The last turn (0 → 0.5 rad over 1 s) ends 0.3 s after the step at 1 s; the response
        // (0.5 → 0 over 0.8 s) starts 0.6 s after the step.
        let angle: Vec<f64> = (0..400)
            .map(|i| {
                let t = f64::from(i) / fs;
                0.5 * min_jerk(t - 0.3) - 0.5 * min_jerk((t - 1.6) / 0.8)
            })
            .collect();
        let step = TargetStep {
            index: 100,
            target_rad: 0.0,
        };
        let params = ResponseParams::default();
        let r = step_responses(&angle, fs, &[step], &params).unwrap()[0];
        let rt = r.reaction_time_s.unwrap();
        // The onset at 10 % of the peak speed: 0.8 · 0.086 s into the turn.
        assert!((rt - (0.6 + 0.069)).abs() < 0.03, "{rt}");
        assert_eq!(r.initial_direction_error_deg, Some(0.0));
        // A 50 ms burst of 0.3 rad/s at 1.4 s (the last turn over, the response not begun):
        // no onset either.
        let mut bumped = angle.clone();
        for (i, a) in bumped.iter_mut().enumerate().skip(140) {
            *a += 0.3 * (f64::from(i.min(145) as u32) - 140.0) / fs;
        }
        let b = step_responses(&bumped, fs, &[step], &params).unwrap()[0];
        let brt = b.reaction_time_s.unwrap();
        assert!((brt - rt).abs() < 0.03, "{brt} vs {rt}");
        // The same burst made 0.15 s long is a movement: the onset is its start.
        let mut pushed = angle;
        for (i, a) in pushed.iter_mut().enumerate().skip(140) {
            *a += 0.3 * (f64::from(i.min(155) as u32) - 140.0) / fs;
        }
        let p = step_responses(&pushed, fs, &[step], &params).unwrap()[0];
        let prt = p.reaction_time_s.unwrap();
        assert!((0.35..0.45).contains(&prt), "{prt}");
        // A wheel moving through the whole window never responded after the step.
        let turning: Vec<f64> = (0..400).map(|i| 0.01 * f64::from(i)).collect();
        let t = step_responses(&turning, fs, &[step], &params).unwrap()[0];
        assert_eq!((t.reaction_time_s, t.movement), (None, None));
    }

    /// Issue 42: each step's response is one discrete movement, measured from rest to rest,
    /// unless the next step cut it.
    #[test]
    fn a_response_that_comes_to_rest_is_one_movement_and_one_cut_by_the_next_step_is_none() {
        let (angle, step) = response_to_a_step(0.3, 1.0);
        let params = ResponseParams::default();
        let r = step_responses(&angle, 100.0, &[step], &params).unwrap()[0];
        let m = r.movement.expect("a whole movement");
        // A minimum-jerk turn of 0.8 s above 10 % of its peak for 0.8 · (1 − 2 · 0.086) s.
        assert!((m.duration_s - 0.66).abs() < 0.03, "{}", m.duration_s);
        assert_eq!(m.n_peaks, 1);
        let sparc = m.sparc.unwrap();
        assert!((-1.6..-1.3).contains(&sparc), "{sparc}");
        assert!(m.ldlj.unwrap() < 0.0);
        assert!(m.discrete);
        // The next step 0.6 s after the turn began: the response cut before it came to rest.
        let next = TargetStep {
            index: 190,
            target_rad: 0.0,
        };
        let cut = step_responses(&angle, 100.0, &[step, next], &params).unwrap()[0];
        assert!(cut.reaction_time_s.is_some());
        assert_eq!(cut.movement, None);
    }

    /// A wheel that makes a lane change's out-and-back turn (a minimum-jerk turn of 0.3 rad
    /// `direction` over 1 s, then back over 1 s) starting `start_s` after the shift at 2 s,
    /// at 100 Hz for 8 s.
    fn lane_change_turn(start_s: f64, direction: f64) -> Vec<f64> {
        (0..800)
            .map(|i| {
                let t = f64::from(i) / 100.0 - 2.0 - start_s;
                0.3 * direction * (min_jerk(t) - min_jerk(t - 1.0))
            })
            .collect()
    }

    #[test]
    fn a_lane_shift_met_late_or_early_has_its_signed_reaction_time_and_direction() {
        let params = ResponseParams::default();
        let shift = DirectedStep {
            index: 200,
            direction: 1.0,
        };
        // The onset at 10 % of the peak speed comes 1 · 0.086 s into the turn.
        for start_s in [0.4, -0.5] {
            let angle = lane_change_turn(start_s, 1.0);
            let r = directed_step_responses(&angle, 100.0, &[shift], 1.5, &params).unwrap()[0];
            let rt = r.reaction_time_s.unwrap();
            assert!((rt - (start_s + 0.086)).abs() < 0.03, "{start_s}: {rt}");
            assert_eq!(r.initial_direction_error_deg, Some(0.0));
        }
        // The wrong way first.
        let angle = lane_change_turn(0.3, -1.0);
        let r = directed_step_responses(&angle, 100.0, &[shift], 1.5, &params).unwrap()[0];
        assert_eq!(r.initial_direction_error_deg, Some(180.0));
        // Earlier than the window opens: the onset is where it opens, no earlier.
        let angle = lane_change_turn(-1.9, 1.0);
        let r = directed_step_responses(&angle, 100.0, &[shift], 1.0, &params).unwrap()[0];
        assert!(r.reaction_time_s.unwrap() >= -1.0);
        // A wheel held still: no response; bad directions and lead times are refused.
        let still = vec![0.2; 800];
        let r = directed_step_responses(&still, 100.0, &[shift], 1.5, &params).unwrap()[0];
        assert_eq!(
            (r.reaction_time_s, r.initial_direction_error_deg),
            (None, None)
        );
        let half = DirectedStep {
            direction: 0.5,
            ..shift
        };
        assert!(directed_step_responses(&still, 100.0, &[half], 1.5, &params).is_err());
        assert!(directed_step_responses(&still, 100.0, &[shift], -1.0, &params).is_err());
    }

    /// Issue 42: a turn started before the physiological minimum after a visible shift is an
    /// anticipation, one started later a reaction.
    #[test]
    fn a_lane_shift_met_sooner_than_the_shortest_reaction_is_an_anticipation() {
        let params = ResponseParams::default();
        let shift = DirectedStep {
            index: 200,
            direction: 1.0,
        };
        let of = |start_s: f64| {
            let angle = lane_change_turn(start_s, 1.0);
            directed_step_responses(&angle, 100.0, &[shift], 1.5, &params).unwrap()[0]
        };
        // Onsets at about −0.41 s and 0.0 s (before and just at the shift): anticipations.
        assert_eq!(of(-0.5).anticipated(), Some(true));
        assert_eq!(of(-0.086).anticipated(), Some(true));
        // Onset at about 0.49 s: a reaction.
        assert_eq!(of(0.4).anticipated(), Some(false));
        let still = vec![0.2; 800];
        let r = directed_step_responses(&still, 100.0, &[shift], 1.5, &params).unwrap()[0];
        assert_eq!(r.anticipated(), None);
    }
}
