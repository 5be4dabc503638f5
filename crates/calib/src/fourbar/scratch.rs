//! Reusable per-sample buffers for the batch calibration.
//!
//! A calibration of a long recording needs a few dozen arrays of one `f64` per sample (unit
//! vectors, noise variances, gains, weights, residual norms). Freed at the end of a call,
//! they return the top of the heap to the system (glibc trims above 128 KiB), so the next
//! call page-faults every one of them in again: about 370 faults, a quarter of the time of a
//! 6 000-sample default calibration. Buffers handed back with [`give`] are kept per thread
//! (at most [`MAX_BUFFERS`], [`MAX_BYTES`] in all) and handed out again by [`take`]; their
//! contents are never reused, only their memory.

use std::cell::RefCell;

/// Most buffers kept per thread.
pub const MAX_BUFFERS: usize = 48;

/// Most bytes kept per thread (a 60 000-sample recording's buffers).
pub const MAX_BYTES: usize = 24 << 20;

thread_local! {
    static POOL: RefCell<Vec<Vec<f64>>> = const { RefCell::new(Vec::new()) };
}

/// An empty buffer with room for `n` values: the smallest kept one that is large enough, else
/// a new one.
pub(crate) fn take(n: usize) -> Vec<f64> {
    let reused = POOL.with(|p| {
        let mut p = p.borrow_mut();
        let best = p
            .iter()
            .enumerate()
            .filter(|(_, v)| v.capacity() >= n)
            .min_by_key(|(_, v)| v.capacity())
            .map(|(i, _)| i);
        best.map(|i| p.swap_remove(i))
    });
    match reused {
        Some(mut v) => {
            v.clear();
            v
        }
        None => Vec::with_capacity(n),
    }
}

/// A buffer of `n` copies of `value`.
pub(crate) fn filled(n: usize, value: f64) -> Vec<f64> {
    let mut v = take(n);
    v.resize(n, value);
    v
}

/// `v`'s values into a pooled buffer.
pub(crate) fn collect(values: impl Iterator<Item = f64>, n: usize) -> Vec<f64> {
    let mut v = take(n);
    v.extend(values);
    v
}

/// Keep `v`'s memory for a later [`take`] on this thread (dropped when the pool is full).
pub(crate) fn give(v: Vec<f64>) {
    if v.capacity() == 0 {
        return;
    }
    POOL.with(|p| {
        let mut p = p.borrow_mut();
        let bytes: usize = p.iter().map(|b| b.capacity() * 8).sum();
        if p.len() < MAX_BUFFERS && bytes + v.capacity() * 8 <= MAX_BYTES {
            p.push(v);
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_given_buffer_is_taken_again_empty_and_the_pool_stays_bounded() {
        let mut v = filled(1000, 2.5);
        let ptr = v.as_ptr();
        v[3] = 1.0;
        give(v);
        let again = take(900);
        assert_eq!(again.as_ptr(), ptr, "the kept buffer is reused");
        assert!(again.is_empty() && again.capacity() >= 1000);
        give(again);
        for _ in 0..2 * MAX_BUFFERS {
            give(Vec::with_capacity(10));
        }
        POOL.with(|p| {
            let p = p.borrow();
            assert!(p.len() <= MAX_BUFFERS);
            assert!(p.iter().map(|b| b.capacity() * 8).sum::<usize>() <= MAX_BYTES);
        });
        // One buffer larger than the pool's byte limit (capacity counts f64s, 8 bytes each).
        give(Vec::with_capacity(MAX_BYTES / 8 + 1));
        POOL.with(|p| assert!(p.borrow().iter().all(|b| b.capacity() * 8 <= MAX_BYTES)));
    }
}
