//! Medians: the robust scales of the four-bar fit (the Huber and Cauchy thresholds of the
//! residual norms, the glitch cap of the noise profile), taken over every value of a short
//! recording and over an even subset of a long one.

/// Median of `v` (reorders a copy in `scratch`).
pub(crate) fn median(v: &[f64], scratch: &mut Vec<f64>) -> f64 {
    median_every(v, 1, scratch)
}

/// Recordings at least this long take their robust scales (the median of the residual norms
/// or of the noise's fourth differences) from every [`MEDIAN_STRIDE`]-th value.
pub const MEDIAN_SUBSET_FROM: usize = 4000;

/// Stride of the values a long recording's medians are taken over.
pub const MEDIAN_STRIDE: usize = 4;

/// The stride of the values [`median_every`] takes a robust scale of `n` values over: every
/// value below [`MEDIAN_SUBSET_FROM`], else every [`MEDIAN_STRIDE`]-th (at least 1 000 values:
/// the median of squared norms then spreads by ≈ 5 %, the Huber threshold, its root, by
/// ≈ 2 %, which moves no estimate beyond its noise, and a glitch cap at 200× not at all; the
/// selections, about 5 % of a 6 000-sample calibration, cost a quarter). Short recordings keep
/// the exact median, so their results are unchanged.
pub(crate) fn median_stride(n: usize) -> usize {
    if n < MEDIAN_SUBSET_FROM {
        1
    } else {
        MEDIAN_STRIDE
    }
}

/// Median of `v[0], v[stride], v[2·stride], …` (reorders a copy in `scratch`).
pub(crate) fn median_every(v: &[f64], stride: usize, scratch: &mut Vec<f64>) -> f64 {
    let stride = stride.max(1);
    scratch.clear();
    // by index over a range (an exact-size iterator the vector fills without a capacity check
    // per value; `step_by` is not one): the same values
    scratch.extend((0..v.len().div_ceil(stride)).map(|j| v[j * stride]));
    let mid = scratch.len() / 2;
    *scratch.select_nth_unstable_by(mid, f64::total_cmp).1
}
