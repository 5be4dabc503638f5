//! What this build is: its release, the station–hub link protocol it speaks and the recording
//! format it writes — said by `telerehab --version` and checked by `telerehab doctor`.

/// What `telerehab --version` says: the release, the station–hub link protocol and the
/// recording format it writes (it reads every earlier one).
pub fn version() -> String {
    format!(
        "{} (link protocol {}, accepts {}–{}; recording format {}, reads 1–{})",
        env!("CARGO_PKG_VERSION"),
        netlink::frame::PROTOCOL_VERSION,
        netlink::frame::MIN_PROTOCOL_VERSION,
        netlink::frame::PROTOCOL_VERSION,
        record::FORMAT_VERSION,
        record::FORMAT_VERSION,
    )
}
