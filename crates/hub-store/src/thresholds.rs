//! The clinic's thresholds for the caseload's alerts: each with its default and why
//! (docs/DESIGN.md, "Needs attention today"), its bounds, and its unit in its name. Stored in
//! `clinic_settings` (migration 0020) only when the clinic changed it.

use crate::refusal::{Code, Why};
use serde::Serialize;

use crate::HubError;

/// One threshold a clinic can set.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct SettingDef {
    /// Its key (`pain_threshold_0_10`, …).
    pub key: &'static str,
    /// The value when the clinic has not set it.
    pub default: i64,
    /// Smallest value accepted.
    pub min: i64,
    /// Largest value accepted.
    pub max: i64,
}

/// Pain (0–10) at or over which the latest check-in raises an urgent alert.
pub const PAIN_THRESHOLD: &str = "pain_threshold_0_10";
/// Points pain must have risen by over three check-ins, each higher than the one before.
pub const PAIN_RISE_POINTS: &str = "pain_rise_points";
/// Days without a session after which an alert is raised (at least the gap the prescription
/// itself leaves between sessions).
pub const NO_SESSION_DAYS: &str = "no_session_days";
/// Active minutes a week under which a patient with nothing prescribed raises an alert.
pub const MIN_ACTIVE_MINUTES_WEEK: &str = "min_active_minutes_week";
/// How much worse than the mean of the earlier sessions of the same exercise kind, percent
/// of that mean, a measure must be to raise an alert (beyond measurement noise).
pub const DECLINE_PERCENT: &str = "decline_percent";
/// Sessions ended early among the last [`ENDED_EARLY_WINDOW`] that raise an alert.
pub const ENDED_EARLY_SESSIONS: &str = "ended_early_sessions";
/// Tiredness (0–10) at or over which the latest check-in raises an alert.
pub const EFFORT_THRESHOLD: &str = "effort_threshold_0_10";
/// Days the station has been on without the wheel, or arm sensors lost, before an alert.
pub const DEVICES_UNSEEN_DAYS: &str = "devices_unseen_days";
/// Days a paired station may stay silent (no connection) before an alert.
pub const STATION_SILENT_DAYS: &str = "station_silent_days";

/// The sessions [`ENDED_EARLY_SESSIONS`] counts among, newest first.
pub const ENDED_EARLY_WINDOW: usize = 5;

/// Every threshold, in the order the settings page shows them.
pub const SETTINGS: [SettingDef; 9] = [
    SettingDef {
        key: PAIN_THRESHOLD,
        default: 7,
        min: 1,
        max: 10,
    },
    SettingDef {
        key: PAIN_RISE_POINTS,
        default: 2,
        min: 1,
        max: 10,
    },
    SettingDef {
        key: NO_SESSION_DAYS,
        default: 3,
        min: 1,
        max: 60,
    },
    SettingDef {
        key: MIN_ACTIVE_MINUTES_WEEK,
        default: 30,
        min: 0,
        max: 1000,
    },
    SettingDef {
        key: DECLINE_PERCENT,
        default: 15,
        min: 1,
        max: 100,
    },
    SettingDef {
        key: ENDED_EARLY_SESSIONS,
        default: 2,
        min: 1,
        max: 5,
    },
    SettingDef {
        key: EFFORT_THRESHOLD,
        default: 7,
        min: 1,
        max: 10,
    },
    SettingDef {
        key: DEVICES_UNSEEN_DAYS,
        default: 3,
        min: 1,
        max: 60,
    },
    SettingDef {
        key: STATION_SILENT_DAYS,
        default: 3,
        min: 1,
        max: 60,
    },
];

/// The definition of setting `key`, if there is one.
pub fn setting_def(key: &str) -> Option<&'static SettingDef> {
    SETTINGS.iter().find(|s| s.key == key)
}

/// The thresholds in force: the clinic's values over the defaults.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Thresholds {
    /// See [`PAIN_THRESHOLD`].
    pub pain_threshold_0_10: i64,
    /// See [`PAIN_RISE_POINTS`].
    pub pain_rise_points: i64,
    /// See [`NO_SESSION_DAYS`].
    pub no_session_days: i64,
    /// See [`MIN_ACTIVE_MINUTES_WEEK`].
    pub min_active_minutes_week: i64,
    /// See [`DECLINE_PERCENT`].
    pub decline_percent: i64,
    /// See [`ENDED_EARLY_SESSIONS`].
    pub ended_early_sessions: i64,
    /// See [`EFFORT_THRESHOLD`].
    pub effort_threshold_0_10: i64,
    /// See [`DEVICES_UNSEEN_DAYS`].
    pub devices_unseen_days: i64,
    /// See [`STATION_SILENT_DAYS`].
    pub station_silent_days: i64,
}

impl Default for Thresholds {
    fn default() -> Self {
        Self::from_values(|_| None)
    }
}

impl Thresholds {
    /// The thresholds with `value(key)` where it gives one, the default elsewhere.
    pub fn from_values(value: impl Fn(&str) -> Option<i64>) -> Self {
        let get =
            |key: &str| value(key).unwrap_or_else(|| setting_def(key).map_or(0, |d| d.default));
        Self {
            pain_threshold_0_10: get(PAIN_THRESHOLD),
            pain_rise_points: get(PAIN_RISE_POINTS),
            no_session_days: get(NO_SESSION_DAYS),
            min_active_minutes_week: get(MIN_ACTIVE_MINUTES_WEEK),
            decline_percent: get(DECLINE_PERCENT),
            ended_early_sessions: get(ENDED_EARLY_SESSIONS),
            effort_threshold_0_10: get(EFFORT_THRESHOLD),
            devices_unseen_days: get(DEVICES_UNSEEN_DAYS),
            station_silent_days: get(STATION_SILENT_DAYS),
        }
    }
}

/// Checks `value` for setting `key`: a known key, within its bounds; the error names both
/// (nothing is changed).
pub fn check_setting(key: &str, value: i64) -> Result<&'static SettingDef, HubError> {
    let def = setting_def(key).ok_or_else(|| {
        let known: Vec<&str> = SETTINGS.iter().map(|s| s.key).collect();
        HubError::refused(
            "setting",
            format!(
                "no setting {key:?}; the settings are {} (nothing was changed)",
                known.join(", ")
            ),
            Why::field(Code::NotOneOf, "setting"),
        )
    })?;
    if (def.min..=def.max).contains(&value) {
        Ok(def)
    } else {
        Err(HubError::refused(
            def.key,
            format!(
                "{key} = {value} refused: it must be from {} to {} (default {}; nothing was \
                 changed)",
                def.min, def.max, def.default
            ),
            Why::field(Code::OutOfRange, def.key)
                .with("min", def.min)
                .with("max", def.max),
        ))
    }
}
