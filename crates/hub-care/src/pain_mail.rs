//! Mails a pain at or over the clinic's threshold to the patient's therapist (every admin when
//! the patient has none), through SMTP ([`lettre`], rustls). Every such check-in is first put
//! in the database's outbox ([`Db::queue_pain_mails`]); a mail the server does not take is
//! retried with a doubling delay ([`retry_after_ms`]) and stays in the outbox until it is
//! taken, its last error logged and shown to admins (`GET /api/clinic/pain-mail`).
//!
//! The mail says only the patient's pseudonym and links to their page in the console: no
//! pain score, no other patient data. Each recipient reads it in the language they chose for
//! the console (English when they never chose): one mail a language.

use std::collections::BTreeMap;
use std::sync::Arc;
use std::time::Duration;

use lettre::message::header::ContentType;
use lettre::{AsyncSmtpTransport, AsyncTransport, Message, Tokio1Executor};

use crate::care::{CareConfig, SmtpConfig};
use crate::live::unix_ms;
use hub_store::db::{Db, PainMail};

/// How often the outbox is looked at.
pub const POLL: Duration = Duration::from_millis(500);

/// The longest wait between two attempts at one mail, ms: an hour.
pub const MAX_RETRY_MS: i64 = 3_600_000;

/// Longest one SMTP conversation may take.
pub const SMTP_TIMEOUT: Duration = Duration::from_secs(20);

/// Mails sent in one look at the outbox.
const BATCH: i64 = 20;

/// The wait before the next attempt after `attempts` failed ones, ms: `min_ms` doubled per
/// earlier failure, at most [`MAX_RETRY_MS`].
pub fn retry_after_ms(min_ms: i64, attempts: i64) -> i64 {
    let doublings = u32::try_from(attempts.saturating_sub(1).clamp(0, 30)).unwrap_or(30);
    min_ms
        .max(1)
        .saturating_mul(1_i64 << doublings)
        .min(MAX_RETRY_MS)
}

/// The subject and body of the mail about `pseudonym`, linking to `patient_id`'s page, in
/// console language `language` (English for none or one the console lacks).
pub fn mail_text(
    language: Option<&str>,
    pseudonym: &str,
    patient_id: &str,
    console_url: Option<&str>,
) -> (String, String) {
    let words = i18n::Catalogue::console_or_english(language);
    let mut args = i18n::FluentArgs::new();
    args.set("pseudonym", pseudonym.to_owned());
    let say = |id: &str| words.message(id, Some(&args));
    let link = match console_url {
        Some(url) => format!("{}/#/patients/{}", url.trim_end_matches('/'), patient_id),
        None => say("mail-pain-page"),
    };
    let body = [
        say("mail-pain-reported"),
        say("mail-pain-told"),
        say("mail-pain-no-more"),
        String::new(),
        say("mail-pain-open"),
        link,
        String::new(),
        "-- ".to_owned(),
        say("mail-pain-signature"),
    ]
    .join("\r\n");
    (say("mail-pain-subject"), format!("{body}\r\n"))
}

/// Runs the outbox until the task is dropped: queues new pain check-ins, sends what is due.
pub async fn run(
    db: Db,
    care: Arc<CareConfig>,
    clock: clock::Clock,
    telemetry: Arc<crate::telemetry::Telemetry>,
) {
    let Some(smtp) = care.smtp.clone() else {
        tracing::warn!(
            "no --smtp-url: pains at or over the threshold are shown in the console but not mailed"
        );
        return;
    };
    let transport = match transport(&smtp) {
        Ok(t) => t,
        Err(e) => {
            tracing::error!("pain mails cannot be sent: {e}");
            return;
        }
    };
    let mut tick = tokio::time::interval(POLL);
    loop {
        tick.tick().await;
        let now = unix_ms(&clock);
        match db
            .queue_pain_mails(care.pain_threshold_in(&db).await, now)
            .await
        {
            Ok(0) => {}
            Ok(n) => tracing::info!(mails = n, "pain at or over the threshold: mail queued"),
            Err(e) => tracing::warn!("cannot queue pain mails: {e}"),
        }
        let due = match db.due_pain_mails(now, BATCH).await {
            Ok(d) => d,
            Err(e) => {
                tracing::warn!("cannot read the pain mail outbox: {e}");
                continue;
            }
        };
        for mail in due {
            let sent = send_one(&db, &care, &smtp, &transport, &mail, &clock).await;
            telemetry.pain_mail(sent);
        }
    }
}

fn transport(smtp: &SmtpConfig) -> Result<AsyncSmtpTransport<Tokio1Executor>, String> {
    AsyncSmtpTransport::<Tokio1Executor>::from_url(&smtp.url)
        .map(|b| b.timeout(Some(SMTP_TIMEOUT)).build())
        .map_err(|e| format!("--smtp-url: {e}"))
}

/// Tries `mail` once; notes it sent, or failed with the time of its next attempt. Whether it
/// was sent.
async fn send_one(
    db: &Db,
    care: &CareConfig,
    smtp: &SmtpConfig,
    transport: &AsyncSmtpTransport<Tokio1Executor>,
    mail: &PainMail,
    clock: &clock::Clock,
) -> bool {
    let result: Result<usize, String> = async {
        let patient = db
            .patient(&mail.patient_id)
            .await
            .map_err(|e| e.to_string())?
            .ok_or("the patient no longer exists")?;
        let to = db
            .pain_mail_recipients(&mail.patient_id)
            .await
            .map_err(|e| e.to_string())?;
        if to.is_empty() {
            return Err(
                "nobody to tell: the patient has no therapist and the clinic no admin".into(),
            );
        }
        // One mail a language. A failure after one went out sends them all again on the next
        // attempt: a mail twice rather than a pain told to nobody.
        let mut by_language: BTreeMap<Option<&str>, Vec<&str>> = BTreeMap::new();
        for r in &to {
            by_language
                .entry(r.language.as_deref())
                .or_default()
                .push(&r.email);
        }
        for (language, addresses) in by_language {
            let (subject, body) = mail_text(
                language,
                &patient.pseudonym,
                &patient.id,
                care.console_url.as_deref(),
            );
            let mut builder = Message::builder()
                .from(smtp.from.parse().map_err(|e| format!("--smtp-from: {e}"))?)
                .subject(subject)
                .header(ContentType::TEXT_PLAIN);
            for address in addresses {
                builder = builder.to(address
                    .parse()
                    .map_err(|e| format!("the therapist's e-mail {address:?}: {e}"))?);
            }
            let message = builder.body(body).map_err(|e| e.to_string())?;
            transport
                .send(message)
                .await
                .map_err(|e| format!("the mail server: {e}"))?;
        }
        Ok(to.len())
    }
    .await;
    let now = unix_ms(clock);
    match result {
        Ok(n) => {
            tracing::info!(session = %mail.session_id, recipients = n, "pain mail sent");
            if let Err(e) = db.pain_mail_sent(&mail.session_id, now).await {
                tracing::warn!("cannot note the pain mail sent (it may be sent again): {e}");
            }
            true
        }
        Err(error) => {
            let next = now.saturating_add(retry_after_ms(smtp.retry_min_ms, mail.attempts + 1));
            tracing::error!(
                session = %mail.session_id,
                attempts = mail.attempts + 1,
                "pain mail not sent, tried again in {} s: {error}",
                (next - now) / 1000
            );
            if let Err(e) = db.pain_mail_failed(&mail.session_id, &error, next).await {
                tracing::warn!("cannot note the pain mail's failure: {e}");
            }
            false
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn retries_double_from_the_minimum_up_to_an_hour() {
        let waits: Vec<i64> = (1..=5).map(|a| retry_after_ms(30_000, a)).collect();
        assert_eq!(waits, [30_000, 60_000, 120_000, 240_000, 480_000]);
        assert_eq!(retry_after_ms(30_000, 40), MAX_RETRY_MS);
    }

    #[test]
    fn the_mail_names_the_pseudonym_and_links_to_the_page_and_nothing_else() {
        for language in [None, Some("de"), Some("es"), Some("zh"), Some("xx")] {
            let (subject, body) = mail_text(
                language,
                "P-0042",
                "p-00000000000000aa",
                Some("https://hub.example:8443/"),
            );
            assert!(subject.contains("P-0042"), "{language:?}: {subject}");
            assert!(
                body.contains("https://hub.example:8443/#/patients/p-00000000000000aa"),
                "{language:?}: {body}"
            );
            assert!(
                !body.contains("/10") && !subject.contains("/10"),
                "no pain score"
            );
            assert!(!body.contains('['), "every message found: {body}");
        }
        let (german, _) = mail_text(Some("de"), "P-0042", "p-1", None);
        let (english, _) = mail_text(None, "P-0042", "p-1", None);
        assert_ne!(german, english);
    }
}
