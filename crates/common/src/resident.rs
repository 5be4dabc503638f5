//! Resident memory: bounded buffers given their pages up front.
//!
//! A buffer that fills slowly up to a fixed bound over a session (the loop timing's counts,
//! the arm calibration's half hour of samples) would take its pages as it fills, which looks
//! like growth for as long as it fills; made resident when it is first needed, the process's
//! resident memory is flat from then on (what `telerehab bench soak` checks) and no page is
//! faulted in mid-session. Allocation only: no I/O (the tests read the process's memory map).

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

    /// The mapping that holds `v`'s buffer (its start) and its resident bytes: the process's
    /// whole RSS moved with the tests running beside this one. (Two large vectors made one
    /// after the other may share one anonymous mapping.)
    #[allow(
        clippy::disallowed_methods,
        reason = "the test reads the process's memory map to see what is resident"
    )]
    fn resident_bytes_of<T>(v: &[T]) -> (usize, u64) {
        let at = v.as_ptr() as usize;
        let smaps = std::fs::read_to_string("/proc/self/smaps").expect("/proc/self/smaps");
        let mut inside = None;
        for line in smaps.lines() {
            if let Some((range, _)) = line.split_once(' ')
                && let Some((lo, hi)) = range.split_once('-')
                && let (Ok(lo), Ok(hi)) =
                    (usize::from_str_radix(lo, 16), usize::from_str_radix(hi, 16))
            {
                inside = (lo..hi).contains(&at).then_some(lo);
            } else if let Some(start) = inside
                && let Some(kib) = line.strip_prefix("Rss:")
            {
                let kib: u64 = kib.trim().trim_end_matches("kB").trim().parse().unwrap();
                return (start, kib * 1024);
            }
        }
        panic!("no mapping holds the vector");
    }

    #[test]
    fn a_resident_buffer_is_in_memory_at_once_a_zeroed_one_is_not() {
        // 256 MiB of u32: far above what the tests running alongside allocate or free.
        const LEN: usize = 64 << 20;
        let mib = |from: u64, to: u64| (to as i64 - from as i64) / (1 << 20);
        let lazy = vec![0u32; LEN];
        let (lazy_map, lazy_b) = resident_bytes_of(&lazy);
        let resident = resident_vec(LEN, 1u32, 0);
        let (map, mut resident_b) = resident_bytes_of(&resident);
        if map == lazy_map {
            resident_b -= lazy_b;
        }
        assert!(
            mib(0, lazy_b) < 64,
            "a zeroed 256 MiB vector took {} MiB at once",
            mib(0, lazy_b)
        );
        assert!(
            mib(0, resident_b) >= 200,
            "a resident 256 MiB vector took only {} MiB",
            mib(0, resident_b)
        );
        assert!(resident.iter().all(|&c| c == 0));
        assert_eq!(lazy.len(), resident.len());
        let empty = resident_with_capacity(1000, [1.0f64; 3]);
        assert!(empty.is_empty() && empty.capacity() >= 1000);
    }
}
