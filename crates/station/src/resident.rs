//! Resident memory: bounded buffers given theirs up front, and the process's figures.
//!
//! A buffer that fills slowly up to a fixed bound over a session (the loop timing's counts,
//! the arm calibration's half hour of samples) would take its pages as it fills, which looks
//! like growth for as long as it fills; made resident when it is first needed, the process's
//! resident memory is flat from then on (what `telerehab bench soak` checks) and no page is
//! faulted in mid-session.

use std::hint::black_box;

/// `len` copies of `value`, every page of them resident. `scratch` must not be all zero bits:
/// it is written first, so that the allocator cannot hand out lazily mapped zero pages (as it
/// does for a zero-filled allocation), then overwritten with `value`.
pub fn resident_vec<T: Clone>(len: usize, scratch: T, value: T) -> Vec<T> {
    let mut v = vec![scratch; len];
    black_box(&mut v);
    v.fill(value);
    v
}

/// A figure of this process's `/proc/self/status` in KiB (`VmRSS`: resident memory now,
/// `VmHWM`: its peak), if readable.
pub fn status_kib(field: &str) -> Option<u64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    status.lines().find_map(|l| {
        let value = l.strip_prefix(field)?.strip_prefix(':')?;
        value.trim().trim_end_matches("kB").trim().parse().ok()
    })
}

/// An empty vector with room for `capacity` elements, all of it resident (`scratch` as in
/// [`resident_vec`]).
pub fn resident_with_capacity<T: Clone>(capacity: usize, scratch: T) -> Vec<T> {
    let mut v = vec![scratch; capacity];
    black_box(&mut v);
    v.clear();
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Resident memory of this process, bytes.
    fn rss_bytes() -> u64 {
        status_kib("VmRSS").expect("VmRSS in /proc/self/status") * 1024
    }

    #[test]
    fn a_resident_buffer_is_in_memory_at_once_a_zeroed_one_is_not() {
        // 256 MiB of u32: far above what the tests running alongside allocate or free.
        const LEN: usize = 64 << 20;
        let mib = |from: u64, to: u64| (to as i64 - from as i64) / (1 << 20);
        let before = rss_bytes();
        let lazy = vec![0u32; LEN];
        let after_lazy = rss_bytes();
        let resident = resident_vec(LEN, 1u32, 0);
        let after_resident = rss_bytes();
        assert!(
            mib(before, after_lazy) < 64,
            "a zeroed 256 MiB vector took {} MiB at once",
            mib(before, after_lazy)
        );
        assert!(
            mib(after_lazy, after_resident) >= 200,
            "a resident 256 MiB vector took only {} MiB",
            mib(after_lazy, after_resident)
        );
        assert!(resident.iter().all(|&c| c == 0));
        assert_eq!(lazy.len(), resident.len());
        let empty = resident_with_capacity(1000, [1.0f64; 3]);
        assert!(empty.is_empty() && empty.capacity() >= 1000);
    }
}
