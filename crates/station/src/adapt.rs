//! Difficulty that follows the patient: a small per-patient history in the station's home
//! and, at the start of each session, the next difficulty within the therapist's bounds
//! (the regimen's `[difficulty]`, `regimen::difficulty`).
//!
//! * The history (`difficulty.jsonl` in the home, one JSON object a line, the last
//!   [`KEPT_SESSIONS`]) holds each adapted session's difficulty, success rate
//!   ([`success_rate`]) and the check-in's "too easy / about right / too hard".
//! * [`next`] replays the patient's history through `assist::DifficultyAdapter` (its
//!   per-session PI step on the success rate, aiming at the therapist's `target_success`),
//!   then honours the patient's word: "too hard" lowers the difficulty by at least
//!   [`TOO_HARD_STEP`], "too easy" raises it by at least [`TOO_EASY_STEP`]; the result is
//!   held within the therapist's `lowest`–`highest`. Each decision says why, in words.

use assist::{DifficultyAdapter, difficulty::DifficultyParams};
use regimen::DifficultySpec;
use serde::{Deserialize, Serialize};
use session::SessionReport;
use std::path::{Path, PathBuf};

/// The history's file in the station's home.
pub const HISTORY_FILE: &str = "difficulty.jsonl";
/// Sessions the history keeps (the oldest go first).
pub const KEPT_SESSIONS: usize = 50;
/// "Too hard" lowers the next difficulty by at least this much.
pub const TOO_HARD_STEP: f64 = 0.10;
/// "Too easy" raises the next difficulty by at least this much (less than "too hard": a
/// patient who says too easy while failing is not pushed far).
pub const TOO_EASY_STEP: f64 = 0.05;
/// A dial session's RMS tracking error at which its success rate is 0, deg.
pub const DIAL_FAIL_RMS_DEG: f64 = 45.0;
/// Sessions shorter than this (active time) tell no success rate, s.
pub const MIN_ACTIVE_S: f64 = 1.0;

/// One adapted session in the history.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Entry {
    /// When the session ended, ms since the Unix epoch.
    pub unix_ms: u64,
    /// The patient (a station re-paired to another patient starts afresh).
    pub patient_id: String,
    /// The difficulty it ran at, in [0, 1].
    pub difficulty: f64,
    /// Its success rate ([`success_rate`]), if it ran long enough to tell.
    pub success_rate: Option<f64>,
    /// The check-in's answer: `too_easy`, `about_right` or `too_hard`, if answered.
    pub felt: Option<String>,
}

/// The difficulty of the next session, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct Decision {
    /// The difficulty, in [0, 1].
    pub difficulty: f64,
    /// The change from the last session's.
    pub change: f64,
    /// Why, in words.
    pub reason: String,
    /// The same why for a clinician's words in any language (the console's).
    pub why: netlink::DifficultyWhy,
}

impl Decision {
    /// As the recording keeps it.
    pub fn note(&self) -> record::DifficultyNote {
        record::DifficultyNote {
            difficulty: self.difficulty,
            change: self.change,
            reason: self.reason.clone(),
        }
    }

    /// As the session's `Bye` carries it, with the session's success rate.
    pub fn change_for_hub(&self, success_rate: Option<f64>) -> netlink::DifficultyChange {
        netlink::DifficultyChange {
            difficulty: self.difficulty,
            change: self.change.clamp(-1.0, 1.0),
            // Our own words, far under the frame's limit: cut on a character boundary anyway.
            reason: self
                .reason
                .char_indices()
                .take_while(|(i, c)| i + c.len_utf8() <= netlink::frame::MAX_TEXT_LEN)
                .map(|(_, c)| c)
                .collect(),
            success_rate,
            why: Some(self.why.clone()),
        }
    }
}

/// A why of `code` without numbers.
fn why_of(code: &str) -> netlink::DifficultyWhy {
    netlink::DifficultyWhy {
        code: code.to_owned(),
        success_pct: None,
        target_pct: None,
        held_at: None,
    }
}

/// The history's file in the home at `dir`.
pub fn history_path(dir: &Path) -> PathBuf {
    dir.join(HISTORY_FILE)
}

/// The history of `patient_id` kept at `path`, oldest first (none if the file is missing;
/// a line that does not read is skipped).
pub fn load(path: &Path, patient_id: &str) -> Vec<Entry> {
    let Ok(bytes) = std::fs::read(path) else {
        return Vec::new();
    };
    netlink::ndjson::read_lines(&bytes[..])
        .filter_map(|(_, l)| netlink::ndjson::parse::<Entry>(&l).ok())
        .filter(|e| e.patient_id == patient_id && e.difficulty.is_finite())
        .collect()
}

/// Appends `entry` to the history at `path`, keeping the last [`KEPT_SESSIONS`] lines
/// (written whole, atomically, 0600).
pub fn append(path: &Path, entry: &Entry) -> anyhow::Result<()> {
    session::files::append_kept(path, entry, KEPT_SESSIONS)
}

/// A session's success rate in [0, 1], from its scores, per exercise kind:
///
/// * a road: the share of time in the lane (`pct_in_lane` / 100);
/// * the dial: `1 − RMS error / 45°` ([`DIAL_FAIL_RMS_DEG`]), 0 beyond — 1 on the needle, 0
///   when off by 45° on average;
/// * a session with both: the two weighted by the time on each.
///
/// `None` for a session of less than [`MIN_ACTIVE_S`] of exercise.
pub fn success_rate(report: &SessionReport) -> Option<f64> {
    let rec = &report.recorder;
    let score = &rec.last.score;
    success_of(
        score.active_s,
        (rec.road_ticks as f64, score.pct_in_lane),
        (rec.dial_ticks as f64, score.dial_rms_error_deg),
    )
}

/// [`success_rate`] from the active time, (road ticks, % in lane) and (dial ticks, RMS
/// dial error in degrees).
pub fn success_of(active_s: f64, road: (f64, f64), dial: (f64, f64)) -> Option<f64> {
    let (road_n, pct_in_lane) = road;
    let (dial_n, rms_deg) = dial;
    if active_s.is_nan() || active_s < MIN_ACTIVE_S || road_n + dial_n <= 0.0 {
        return None;
    }
    let lane = (pct_in_lane / 100.0).clamp(0.0, 1.0);
    let on_dial = (1.0 - rms_deg / DIAL_FAIL_RMS_DEG).clamp(0.0, 1.0);
    let rate = (road_n * lane + dial_n * on_dial) / (road_n + dial_n);
    rate.is_finite().then_some(rate)
}

/// "+0.05", "−0.10".
fn signed(x: f64) -> String {
    if x < -0.0005 {
        format!("\u{2212}{:.2}", -x)
    } else {
        format!("+{x:.2}")
    }
}

/// The first session's difficulty, and why.
fn first(spec: &DifficultySpec) -> Decision {
    let d = spec.first();
    let (code, words) = match (spec.adapt, spec.start) {
        (false, _) => ("adapt-off", "adaptation off: the therapist's"),
        (true, Some(_)) => ("first-start", "first session: the therapist's start"),
        (true, None) => (
            "first-midway",
            "first session: midway between the therapist's bounds,",
        ),
    };
    Decision {
        difficulty: d,
        change: 0.0,
        reason: format!("{words} {d:.2}"),
        why: why_of(code),
    }
}

/// The difficulty of the next session from `history` (oldest first) within `spec`.
pub fn next(spec: &DifficultySpec, history: &[Entry]) -> Decision {
    let Some(last) = history.last().filter(|_| spec.adapt) else {
        return first(spec);
    };
    let params = DifficultyParams {
        target_success: spec.target_success,
        ..DifficultyParams::default()
    };
    let base = last.difficulty.clamp(0.0, 1.0);
    // The PI step on the success rate, its integral over the patient's history.
    let proposal = match DifficultyAdapter::new(params, history[0].difficulty.clamp(0.0, 1.0)) {
        Ok(mut a) => {
            for e in history {
                a.set_difficulty(e.difficulty);
                if let Some(r) = e.success_rate {
                    a.end_session(r);
                }
            }
            a.difficulty()
        }
        // The regimen's validation keeps the target within the adapter's range.
        Err(_) => base,
    };
    let target_pct = spec.target_success * 100.0;
    let mut step = proposal - base;
    let (mut reason, mut why) = match last.success_rate {
        Some(r) => {
            let pct = r * 100.0;
            let side = if pct.round() > target_pct.round() {
                "above"
            } else if pct.round() < target_pct.round() {
                "below"
            } else {
                "at"
            };
            let words = format!(
                "success {pct:.0} % {side} the {target_pct:.0} % target: {}",
                signed(step)
            );
            let why = netlink::DifficultyWhy {
                success_pct: Some(pct.round().clamp(0.0, 100.0)),
                target_pct: Some(target_pct.round().clamp(0.0, 100.0)),
                ..why_of(&format!("success-{side}"))
            };
            (words, why)
        }
        None => {
            step = 0.0;
            let words = "no success rate from the last session: held".to_owned();
            (words, why_of("no-rate"))
        }
    };
    // The patient's word comes first: at least its step, in its direction.
    match last.felt.as_deref() {
        Some("too_hard") => {
            step = step.min(-TOO_HARD_STEP);
            reason = format!("patient said too hard: {}", signed(step));
            why = why_of("felt-too-hard");
        }
        Some("too_easy") => {
            step = step.max(TOO_EASY_STEP);
            reason = format!("patient said too easy: {}", signed(step));
            why = why_of("felt-too-easy");
        }
        _ => {}
    }
    let wanted = ((base + step) * 1000.0).round() / 1000.0;
    let d = wanted.clamp(spec.lowest, spec.highest);
    if wanted > spec.highest {
        reason = format!(
            "{reason}; held at the therapist's highest ({:.2})",
            spec.highest
        );
        why.held_at = Some("highest".to_owned());
    } else if wanted < spec.lowest {
        reason = format!(
            "{reason}; held at the therapist's lowest ({:.2})",
            spec.lowest
        );
        why.held_at = Some("lowest".to_owned());
    }
    Decision {
        difficulty: d,
        change: d - base,
        reason,
        why,
    }
}

/// A session that adapts: its decision, and where its history is kept (none without a home).
#[derive(Debug, Clone)]
pub struct Adapted {
    /// The difficulty this session runs at, and why.
    pub decision: Decision,
    history: Option<PathBuf>,
    patient_id: String,
}

impl Adapted {
    /// The difficulty for a session of `patient_id` running `regimen` (`None` unless it has a
    /// `[difficulty]` table), from the history in the home at `home_dir`; `regimen` is
    /// replaced by itself at that difficulty.
    pub fn plan(
        regimen: &mut Option<regimen::Regimen>,
        home_dir: Option<&Path>,
        patient_id: &str,
    ) -> Option<Self> {
        let r = regimen.as_mut()?;
        let spec = r.difficulty.clone()?;
        let history = home_dir.map(history_path);
        let past = history
            .as_deref()
            .map(|p| load(p, patient_id))
            .unwrap_or_default();
        let decision = next(&spec, &past);
        *r = r.at_difficulty(decision.difficulty);
        tracing::info!(
            difficulty = decision.difficulty,
            reason = %decision.reason,
            "the session's difficulty"
        );
        Some(Self {
            decision,
            history,
            patient_id: patient_id.to_owned(),
        })
    }

    /// Keeps the finished session in the history: its difficulty, `success_rate` and the
    /// check-in's `felt` answer. A history that cannot be written is a warning.
    pub fn remember(&self, success_rate: Option<f64>, felt: Option<&str>, unix_ms: u64) {
        let Some(path) = &self.history else {
            return;
        };
        let entry = Entry {
            unix_ms,
            patient_id: self.patient_id.clone(),
            difficulty: self.decision.difficulty,
            success_rate,
            felt: felt.map(str::to_owned),
        };
        if let Err(e) = append(path, &entry) {
            tracing::warn!("the session's difficulty is not kept for the next: {e:#}");
        }
    }
}

#[cfg(test)]
mod tests;
