//! Pain that stops the day: the clinic's pain threshold and phone number as the hub sent them
//! ([`CareSettings`], kept in the home's `care.json`), and a pain at or over that threshold
//! answered on this station ([`PainStop`], kept in `pain-stop.json`). Until the therapist
//! clears it (a later [`CareSettings::cleared_unix_ms`]), the rest of that local calendar day
//! offers no session: today's page says to rest ([`rest_today_page`]).

use render::{StatusLine, Welcome};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The pain (0–10) at or over which a session ends on the page that says to stop, when the
/// hub has not said otherwise.
pub const DEFAULT_PAIN_THRESHOLD_0_10: u8 = netlink::frame::DEFAULT_PAIN_THRESHOLD_0_10;

/// What the clinic says about pain, as the hub last sent it ([`netlink::Care`]).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CareSettings {
    /// Pain at or over this (0–10) stops the day's training.
    pub pain_threshold_0_10: u8,
    /// The clinic's phone number for patients, as the clinic writes it.
    #[serde(default)]
    pub clinic_phone: Option<String>,
    /// When the therapist last cleared the patient to train after a pain stop, ms since the
    /// Unix epoch (hub clock).
    #[serde(default)]
    pub cleared_unix_ms: Option<u64>,
}

impl Default for CareSettings {
    fn default() -> Self {
        Self {
            pain_threshold_0_10: DEFAULT_PAIN_THRESHOLD_0_10,
            clinic_phone: None,
            cleared_unix_ms: None,
        }
    }
}

impl From<&netlink::Care> for CareSettings {
    fn from(c: &netlink::Care) -> Self {
        Self {
            pain_threshold_0_10: c.pain_threshold_0_10,
            clinic_phone: c.clinic_phone.clone().filter(|p| !p.trim().is_empty()),
            cleared_unix_ms: c.cleared_unix_ms,
        }
    }
}

impl CareSettings {
    /// The settings kept at `path`; the defaults if none were kept or the file is damaged.
    pub fn load(path: &Path) -> Self {
        std::fs::read(path)
            .ok()
            .and_then(|b| serde_json::from_slice(&b).ok())
            .unwrap_or_default()
    }

    /// Keeps these settings at `path` (0600).
    pub fn save(&self, path: &Path) -> anyhow::Result<()> {
        session::files::write_private(path, &serde_json::to_vec(self)?)
    }

    /// Whether `pain` (0–10) is at or over the clinic's threshold.
    pub fn stops(&self, pain_0_10: u8) -> bool {
        pain_0_10 >= self.pain_threshold_0_10
    }
}

/// A pain at or over the threshold answered on this station.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct PainStop {
    /// When it was answered, ms since the Unix epoch (station clock).
    pub at_unix_ms: u64,
    /// The pain answered, 0–10.
    pub pain_0_10: u8,
}

impl PainStop {
    /// The pain stop kept at `path`, if any (a damaged file counts as a stop now: the safe
    /// side).
    pub fn load(path: &Path, now_unix_ms: u64) -> Option<Self> {
        let bytes = std::fs::read(path).ok()?;
        Some(serde_json::from_slice(&bytes).unwrap_or(Self {
            at_unix_ms: now_unix_ms,
            pain_0_10: 10,
        }))
    }

    /// Keeps this stop at `path` (0600).
    pub fn save(&self, path: &Path) -> anyhow::Result<()> {
        session::files::write_private(path, &serde_json::to_vec(self)?)
    }

    /// Whether this stop still holds at `now_unix_ms`: the same local calendar day, and the
    /// therapist has not cleared the patient since.
    pub fn holds(&self, care: &CareSettings, now_unix_ms: u64) -> bool {
        let cleared = care.cleared_unix_ms.is_some_and(|c| c >= self.at_unix_ms);
        !cleared && same_local_day(self.at_unix_ms, now_unix_ms)
    }
}

/// Whether two instants (ms since the Unix epoch) fall on the same calendar day in the
/// station's time zone.
pub fn same_local_day(a_unix_ms: u64, b_unix_ms: u64) -> bool {
    use chrono::TimeZone;
    let day = |ms: u64| {
        chrono::Local
            .timestamp_millis_opt(i64::try_from(ms).unwrap_or(i64::MAX))
            .single()
            .map(|t| t.date_naive())
    };
    match (day(a_unix_ms), day(b_unix_ms)) {
        (Some(a), Some(b)) => a == b,
        _ => false,
    }
}

/// Today's page while a pain stop holds: rest today, call the clinic, the therapist can clear
/// it. No key starts a session from it; a press of the wheel (or Esc) closes it.
pub fn rest_today_page(care: &CareSettings) -> Welcome {
    let plain = |text: String| StatusLine { ok: None, text };
    let mut lines = vec![
        plain(i18n::tr!("checkin-rest-today-pain")),
        StatusLine {
            ok: Some(false),
            text: i18n::tr!("checkin-rest-today-no-exercise"),
        },
    ];
    lines.push(plain(match &care.clinic_phone {
        Some(phone) => i18n::tr!("checkin-stop-call", phone = phone.clone()),
        None => i18n::tr!("checkin-stop-call-clinic"),
    }));
    lines.push(plain(i18n::tr!("checkin-rest-today-wait")));
    Welcome {
        title: i18n::tr!("checkin-rest-today-title"),
        lines,
        keys: vec![
            i18n::tr!("checkin-key-close"),
            i18n::tr!("checkin-key-close-esc"),
        ],
        picture: Some(render::Picture::Wheel {
            hold: false,
            turn: false,
        }),
        ..Welcome::default()
    }
}

/// Notes in `home` a pain at or over the clinic's threshold in the session's `checkin` (the
/// rest of the day then offers no session). A pain under it, or none, changes nothing.
pub fn note_pain(home: &crate::home::Home, checkin: &netlink::CheckIn) {
    let Some(pain) = checkin.pain_0_10 else {
        return;
    };
    let care = CareSettings::load(&home.care_path());
    if !care.stops(pain) {
        return;
    }
    let stop = PainStop {
        at_unix_ms: now_unix_ms(),
        pain_0_10: pain,
    };
    match stop.save(&home.pain_stop_path()) {
        Ok(()) => tracing::warn!(
            pain,
            threshold = care.pain_threshold_0_10,
            "pain at or over the clinic's threshold: no more sessions today"
        ),
        Err(e) => tracing::error!("the pain stop is not kept: {e:#}"),
    }
}

/// Now, ms since the Unix epoch (station clock).
pub fn now_unix_ms() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| u64::try_from(d.as_millis()).unwrap_or(u64::MAX))
}

/// Today's page instead of the session, while a pain stop kept in `home` holds at
/// `now_unix_ms`; `None` when the patient may train.
pub fn rest_today(home: &crate::home::Home, now_unix_ms: u64) -> Option<Welcome> {
    let stop = PainStop::load(&home.pain_stop_path(), now_unix_ms)?;
    let care = CareSettings::load(&home.care_path());
    stop.holds(&care, now_unix_ms)
        .then(|| rest_today_page(&care))
}
