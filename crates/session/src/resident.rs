//! The process's memory figures (`/proc/self/status`). The resident buffers themselves are
//! `common::resident`.

/// A figure of this process's `/proc/self/status` in KiB (`VmRSS`: resident memory now,
/// `VmHWM`: its peak), if readable.
pub fn status_kib(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status.lines().find_map(|l| {
        let value = l.strip_prefix(field)?.strip_prefix(':')?;
        value.trim().trim_end_matches("kB").trim().parse().ok()
    })
}
