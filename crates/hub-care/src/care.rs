//! What the clinic says about pain and how patients and stations reach it. The pain threshold
//! in force is the clinic's setting (the console's alert thresholds, table `clinic_settings`:
//! the caseload's pain alert, the station's pain page and the pain mail all read it through
//! [`CareConfig::pain_threshold_in`]); `hub serve --pain-threshold` puts a value there when
//! the clinic has set none ([`CareConfig::seed_pain_threshold`]). Also `--clinic-phone`, `--public-station-address` (what the pairing sheet prints),
//! `--console-url` (the link in a pain mail) and `--smtp-url`/`--smtp-from` (the mail).
//!
//! A check-in's pain at or over the threshold ends the station's session on a page that says
//! to stop, rest and call the clinic's phone; the station offers no session for the rest of
//! that day unless the therapist clears the patient (`POST /api/patients/{id}/pain-clearance`,
//! pushed to the station as a [`netlink::Care`]); and the patient's therapist is mailed
//! ([`crate::pain_mail`]).

use std::net::SocketAddr;

use hub_store::HubError;

/// How the hub mails a pain alert.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SmtpConfig {
    /// `smtp://host:port` (plain; `?tls=required` for STARTTLS) or `smtps://host:port`, with
    /// optional `user:password@` (never logged).
    pub url: String,
    /// The sender, e.g. `telerehab <hub@clinic.example>`.
    pub from: String,
    /// The first retry after a failed attempt waits this long, then twice as long each time
    /// up to [`crate::pain_mail::MAX_RETRY_MS`], ms.
    pub retry_min_ms: i64,
}

/// The clinic's settings for pain, pairing sheets and mail.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CareConfig {
    /// `--pain-threshold` (1–10): the clinic's pain threshold when it has set none
    /// ([`Self::seed_pain_threshold`]); the one in force is [`Self::pain_threshold_in`].
    pub pain_threshold_0_10: u8,
    /// The phone number patients call, as the clinic writes it.
    pub clinic_phone: Option<String>,
    /// The station address printed on pairing sheets (`host:port`), if one that a station at
    /// home can reach is known: [`public_station_address`].
    pub public_station_address: Result<String, String>,
    /// The console's address for links in mails, e.g. `https://hub.clinic.example:8443`.
    pub console_url: Option<String>,
    /// The mail, if configured.
    pub smtp: Option<SmtpConfig>,
}

impl Default for CareConfig {
    fn default() -> Self {
        Self {
            pain_threshold_0_10: netlink::frame::DEFAULT_PAIN_THRESHOLD_0_10,
            clinic_phone: None,
            public_station_address: Err(NO_ADDRESS.to_owned()),
            console_url: None,
            smtp: None,
        }
    }
}

/// Why a pairing sheet has no address when the hub was given none and listens on every
/// address.
const NO_ADDRESS: &str = "The hub was not told the address stations at home connect to. \
Ask your administrator to start it with --public-station-address (for example \
hub.clinic.example:7878).";

impl CareConfig {
    /// The pain threshold in force (1–10): the clinic's setting. Pain at or over it is urgent
    /// on the caseload, stops the day's training and is mailed to the therapist. Should the
    /// database not answer, `--pain-threshold` (logged).
    pub async fn pain_threshold_in(&self, db: &hub_store::Db) -> u8 {
        match db.pain_threshold().await {
            Ok(t) => u8::try_from(t.clamp(1, 10)).unwrap_or(self.pain_threshold_0_10),
            Err(e) => {
                tracing::warn!("cannot read the clinic's pain threshold: {e}");
                self.pain_threshold_0_10
            }
        }
    }

    /// Stores `--pain-threshold` as the clinic's pain threshold when the clinic has set none
    /// and it is not the default; a clinic that set its own keeps it (the flag is then
    /// ignored, and the log says so).
    pub async fn seed_pain_threshold(
        &self,
        db: &hub_store::Db,
        now_ms: i64,
    ) -> Result<(), HubError> {
        use hub_store::thresholds::PAIN_THRESHOLD;
        let flag = i64::from(self.pain_threshold_0_10);
        match db.clinic_settings().await?.get(PAIN_THRESHOLD) {
            Some(s)
                if s.value != flag
                    && flag != i64::from(netlink::frame::DEFAULT_PAIN_THRESHOLD_0_10) =>
            {
                tracing::warn!(
                    "--pain-threshold {flag} ignored: the clinic set its pain threshold to {} \
                     (the console's alert thresholds)",
                    s.value
                );
                Ok(())
            }
            Some(_) => Ok(()),
            None if flag == i64::from(netlink::frame::DEFAULT_PAIN_THRESHOLD_0_10) => Ok(()),
            None => {
                db.put_clinic_setting(PAIN_THRESHOLD, flag, "hub serve --pain-threshold", now_ms)
                    .await
            }
        }
    }

    /// Checks the threshold (1–10) and the phone number; the error names the option.
    pub fn validate(&self) -> Result<(), HubError> {
        let care = self.care_frame(self.pain_threshold_0_10, None);
        care.validate().map_err(|e| {
            HubError::Config(format!(
                "--pain-threshold / --clinic-phone: {e} (the hub was not started)"
            ))
        })?;
        if let Some(smtp) = &self.smtp
            && !(smtp.url.starts_with("smtp://") || smtp.url.starts_with("smtps://"))
        {
            return Err(HubError::Config(
                "--smtp-url must start with smtp:// or smtps:// (the hub was not started)".into(),
            ));
        }
        Ok(())
    }

    /// The frame telling a station the clinic's pain settings (`threshold`, the one in force:
    /// [`Self::pain_threshold_in`]), with the patient's clearance.
    pub fn care_frame(&self, threshold: u8, cleared_unix_ms: Option<u64>) -> netlink::Care {
        netlink::Care {
            pain_threshold_0_10: threshold,
            clinic_phone: self.clinic_phone.clone(),
            cleared_unix_ms,
        }
    }
}

/// The station address to print on pairing sheets: `configured` (`--public-station-address`)
/// when given, else the station listener `bound` when it is a specific address other than
/// loopback; otherwise why there is none, in plain words. A loopback address is refused
/// either way: a station at the patient's home cannot reach it.
pub fn public_station_address(
    configured: Option<&str>,
    bound: SocketAddr,
) -> Result<String, String> {
    let address = match configured.map(str::trim).filter(|a| !a.is_empty()) {
        Some(a) => a.to_owned(),
        None if bound.ip().is_unspecified() => return Err(NO_ADDRESS.to_owned()),
        None => bound.to_string(),
    };
    if is_loopback(&address) {
        return Err(format!(
            "{address} is this computer's own address: a station at a patient's home cannot \
             reach it. Ask your administrator to start the hub with \
             --public-station-address (the address stations at home connect to)."
        ));
    }
    Ok(address)
}

/// Whether `host:port` names this computer itself (127.0.0.0/8, ::1, `localhost`).
pub fn is_loopback(address: &str) -> bool {
    let host = match address.rsplit_once(':') {
        Some((h, port)) if port.chars().all(|c| c.is_ascii_digit()) => h,
        _ => address,
    };
    let host = host.trim_start_matches('[').trim_end_matches(']');
    host.eq_ignore_ascii_case("localhost")
        || host.to_ascii_lowercase().ends_with(".localhost")
        || host
            .parse::<std::net::IpAddr>()
            .is_ok_and(|ip| ip.is_loopback() || ip.is_unspecified())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_pairing_sheet_address_is_the_configured_one_and_never_loopback() {
        let any: SocketAddr = "0.0.0.0:47878".parse().unwrap();
        let lan: SocketAddr = "192.168.1.20:47878".parse().unwrap();
        let local: SocketAddr = "127.0.0.1:47878".parse().unwrap();
        assert_eq!(
            public_station_address(Some("hub.clinic.example:47878"), any),
            Ok("hub.clinic.example:47878".into())
        );
        assert_eq!(
            public_station_address(None, lan),
            Ok("192.168.1.20:47878".into())
        );
        assert!(public_station_address(None, any).is_err());
        assert!(public_station_address(None, local).is_err());
        for refused in [
            "127.0.0.1:7878",
            "localhost:7878",
            "[::1]:7878",
            "LOCALHOST",
        ] {
            let e = public_station_address(Some(refused), lan).unwrap_err();
            assert!(e.contains("cannot reach"), "{refused}: {e}");
        }
    }

    #[test]
    fn a_bad_threshold_or_phone_stops_the_hub_naming_the_option() {
        let bad = CareConfig {
            pain_threshold_0_10: 11,
            ..CareConfig::default()
        };
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("--pain-threshold")
        );
        let bad = CareConfig {
            clinic_phone: Some("call us".into()),
            ..CareConfig::default()
        };
        assert!(
            bad.validate()
                .unwrap_err()
                .to_string()
                .contains("phone number")
        );
        assert_eq!(CareConfig::default().pain_threshold_0_10, 7);
    }
}
