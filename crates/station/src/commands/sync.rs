//! `telerehab sync`: deliver the summaries an earlier run could not, now.

use crate::home::{Home, HomeArg};
use crate::link::{queue, uploads};
use anyhow::{Context, bail};
use std::time::Duration;

/// `telerehab sync`.
#[derive(Debug, clap::Args)]
pub struct SyncArgs {
    /// Hub address, `host:port`; default the paired hub.
    #[arg(long)]
    pub therapist: Option<String>,
    /// Seconds allowed for each queued session (20 times that for the recordings).
    #[arg(long, default_value_t = 30.0)]
    pub timeout: f64,
    /// Upload bandwidth cap for recordings, bytes/s.
    #[arg(long, default_value_t = uploads::UPLOAD_BYTES_PER_S)]
    pub upload_rate: u64,
    /// The station's home (its queue and pairing).
    #[command(flatten)]
    pub home: HomeArg,
}

/// Sends every queued session and says what is left; fails if anything is left.
pub fn run(args: &SyncArgs) -> anyhow::Result<()> {
    let home = Home::resolve(&args.home)?;
    let pairing = home.pairing()?;
    let (address, tls) = match (&args.therapist, &pairing) {
        (Some(a), _) => (a.clone(), None),
        (None, Some(p)) => (p.hub.clone(), Some(home.client_tls(p))),
        (None, None) => bail!(
            "this station is not paired and no --therapist was given: nowhere to send the queue"
        ),
    };
    if !(args.timeout.is_finite() && args.timeout > 0.0) {
        bail!("--timeout must be a positive number of seconds");
    }
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(1)
        .enable_all()
        .build()
        .context("cannot start the network runtime")?;
    let timeout = Duration::from_secs_f64(args.timeout);
    let report = runtime.block_on(queue::deliver(
        &home.queue_dir(),
        &address,
        tls.clone(),
        timeout,
    ))?;
    println!(
        "sync: {} queued sessions, {} delivered, {} summaries still queued",
        report.sessions, report.delivered, report.remaining
    );
    let uploads = runtime.block_on(uploads::upload_all(
        &home.uploads_dir(),
        &address,
        tls.as_ref(),
        args.upload_rate,
        timeout.saturating_mul(20),
    ));
    println!("sync: recordings {}", uploads.describe());
    // The therapist's messages the hub sent on these connections, kept for the next start
    // card as the live link's are (a regimen waits for the next run, which is pushed it).
    let received = report
        .messages
        .iter()
        .cloned()
        .chain(uploads.pushed.messages);
    if crate::messages::Inbox::load(&home.messages_path()).keep_received(received) {
        println!("sync: a message from the therapist is kept for the next session");
    }
    if report.delivered < report.sessions {
        bail!(
            "{} sessions not delivered to {address}: {}",
            report.sessions - report.delivered,
            report
                .last_error
                .as_deref()
                .unwrap_or("no acknowledgement in time")
        );
    }
    Ok(())
}
