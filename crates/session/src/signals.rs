//! SIGINT/SIGTERM for a running session: the first asks it to stop (the torque fades out and
//! everything is recorded and delivered), a second exits at once.

use anyhow::Context;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

/// Stop flag set by SIGINT/SIGTERM; a second signal exits at once (the kernel then stops
/// every force-feedback effect of the closed device).
pub fn install_stop_flag() -> anyhow::Result<Arc<AtomicBool>> {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let stop = Arc::new(AtomicBool::new(false));
    for sig in [SIGINT, SIGTERM] {
        signal_hook::flag::register_conditional_shutdown(sig, 130, stop.clone())
            .context("cannot install the signal handler")?;
        signal_hook::flag::register(sig, stop.clone())
            .context("cannot install the signal handler")?;
    }
    Ok(stop)
}
