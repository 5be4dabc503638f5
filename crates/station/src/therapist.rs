//! `telerehab therapist`: the hub.

use crate::cli::TherapistArgs;

/// Run the hub until interrupted.
pub fn run(_args: TherapistArgs) -> anyhow::Result<()> {
    anyhow::bail!("the therapist hub is not in this build yet")
}
