//! The station side of the therapist link (filled in by the netlink integration).

use crate::config::StationConfig;
use crate::report::LinkReport;
use crate::session::LiveSummary;

/// The therapist link of one session.
pub struct Link {}

impl Link {
    /// Start the link if the configuration names a therapist.
    pub fn start(cfg: &StationConfig) -> anyhow::Result<Self> {
        if !cfg.therapist.address.is_empty() {
            anyhow::bail!("the therapist link is not in this build yet");
        }
        Ok(Self {})
    }

    /// Hand one summary to the link without waiting.
    pub fn send(&self, _summary: &LiveSummary, _cfg: &StationConfig) {}

    /// End the link; report delivery.
    pub fn finish(self, _produced: u64) -> Option<LinkReport> {
        None
    }
}
