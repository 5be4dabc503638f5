//! `hub serve`'s options for pain that reaches someone and for pairing sheets
//! ([`hub_care::care`]).

/// What the clinic says about pain, where stations at home connect, and how the hub mails.
#[derive(Debug, Clone, clap::Args)]
pub struct CareArgs {
    /// Pain (1–10) at or over which a patient's station stops the day's training, says to
    /// call the clinic, and the therapist is mailed.
    #[arg(long, value_name = "0-10", default_value_t = netlink::frame::DEFAULT_PAIN_THRESHOLD_0_10)]
    pub pain_threshold: u8,
    /// The clinic's phone number, shown to a patient in pain (e.g. "+49 30 1234567").
    #[arg(long, value_name = "PHONE")]
    pub clinic_phone: Option<String>,
    /// The address stations at patients' homes connect to, `host:port`, printed on pairing
    /// sheets (default: the station listener's, unless it is loopback or 0.0.0.0).
    #[arg(long, value_name = "HOST:PORT")]
    pub public_station_address: Option<String>,
    /// The console's address for links in mails (default https://NAME:PORT of the hub's
    /// first certificate name and the console's port).
    #[arg(long, value_name = "URL")]
    pub console_url: Option<String>,
    /// SMTP server for pain mails: smtp://host:port (?tls=required for STARTTLS) or
    /// smtps://host:port, optionally with user:password@. Without it nothing is mailed.
    #[arg(long, value_name = "URL", env = "TELEREHAB_HUB_SMTP_URL")]
    pub smtp_url: Option<String>,
    /// The pain mails' sender.
    #[arg(
        long,
        value_name = "ADDRESS",
        default_value = "telerehab hub <telerehab@localhost>"
    )]
    pub smtp_from: String,
    /// First wait before a failed mail is tried again, s (doubling up to an hour).
    #[arg(long, value_name = "S", default_value_t = 30)]
    pub smtp_retry_min_s: u64,
}

impl CareArgs {
    /// The hub's care settings (the station address is settled when the hub has bound).
    pub fn config(&self) -> hub_care::care::CareConfig {
        hub_care::care::CareConfig {
            pain_threshold_0_10: self.pain_threshold,
            clinic_phone: self
                .clinic_phone
                .as_deref()
                .map(str::trim)
                .filter(|p| !p.is_empty())
                .map(str::to_owned),
            console_url: self.console_url.clone(),
            smtp: self
                .smtp_url
                .as_ref()
                .map(|url| hub_care::care::SmtpConfig {
                    url: url.clone(),
                    from: self.smtp_from.clone(),
                    retry_min_ms: i64::try_from(self.smtp_retry_min_s.saturating_mul(1000))
                        .unwrap_or(i64::MAX),
                }),
            ..Default::default()
        }
    }
}
