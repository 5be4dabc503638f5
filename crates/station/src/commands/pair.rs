//! `telerehab pair`: turn the clinic's one-time code into this station's own credential.

use crate::home::{Home, HomeArg};
use anyhow::Context;
use std::time::Duration;

/// `telerehab pair`.
#[derive(Debug, clap::Args)]
pub struct PairArgs {
    /// The clinic hub's address for stations, `host:port`.
    #[arg(long)]
    pub hub: String,
    /// The pairing code the clinic gave the patient, e.g. `7KQ2-M9XD`.
    #[arg(long)]
    pub code: String,
    /// Where to store the credential.
    #[command(flatten)]
    pub home: HomeArg,
}

/// Pairs, stores the credential in the home directory and says what happened.
pub fn run(args: &PairArgs) -> anyhow::Result<()> {
    let home = Home::resolve(&args.home)?;
    let runtime = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .context("cannot start the network runtime")?;
    let credential = runtime
        .block_on(netlink::pairing::pair(
            &args.hub,
            &args.code,
            Duration::from_secs(30),
        ))
        .context("pairing failed")?;
    let now_ms = clock::Clock::real().unix_ns() / 1_000_000;
    let pairing = home.save_pairing(&args.hub, &credential, now_ms)?;
    // The patient as the clinic knows them; a hub older than the pseudonym gives its id only.
    let patient = pairing
        .patient_pseudonym
        .clone()
        .unwrap_or_else(|| pairing.patient_id.clone());
    println!(
        "paired: this station is {} for patient {patient} at {} (stored in {})",
        pairing.station_id,
        pairing.hub,
        home.dir().display()
    );
    println!("`telerehab run` now sends every session to this hub over mutual TLS.");
    Ok(())
}
