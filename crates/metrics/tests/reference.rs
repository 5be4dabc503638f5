//! SPARC, LDLJ and the speed profile against published numbers and an independent
//! implementation (tests/reference/sparc_ldlj.py: numpy/scipy transcriptions of siva82kb/SPARC,
//! monalysa and scipy.signal.filtfilt; its output is the committed expected.json).

use metrics::{MetricError, SparcParams, ldlj_speed, sparc, speed_profile};
use serde::Deserialize;

/// The reference values are printed to 5 decimals, so they are exact to ±5e-6; 1e-5 allows
/// for that rounding and nothing else.
const PUBLISHED_TOL: f64 = 1e-5;

/// Relative tolerance against the numpy transcription: the same arithmetic in another FFT
/// (pocketfft vs rustfft), so only rounding differs (~1e-15); 1e-9 leaves room and would
/// still catch any difference of definition.
const REFERENCE_REL_TOL: f64 = 1e-9;

/// FIELD-NOTES "Movement-quality metrics": exp(−5t²) for t = −1, −0.99, …, 0.99
/// (`numpy.arange(-1, 1, 0.01)`: 200 samples; the closed interval, 201 samples, gives
/// −1.41399 / −5.83142 instead), fs = 100 Hz.
fn gaussian() -> Vec<f64> {
    (0..200)
        .map(|i| {
            let t = -1.0 + f64::from(i) * 0.01;
            (-5.0 * t * t).exp()
        })
        .collect()
}

/// 1 s minimum-jerk speed profile 30t² − 60t³ + 30t⁴, t = 0, 0.01, …, 1 (101 samples).
fn min_jerk() -> Vec<f64> {
    (0..=100)
        .map(|i| {
            let t = f64::from(i) * 0.01;
            30.0 * t.powi(2) - 60.0 * t.powi(3) + 30.0 * t.powi(4)
        })
        .collect()
}

#[test]
fn gaussian_profile_reproduces_the_published_sparc_and_ldlj() {
    let v = gaussian();
    let s = sparc(&v, 100.0, SparcParams::default()).unwrap();
    let l = ldlj_speed(&v, 100.0).unwrap();
    assert!((s - -1.41403).abs() < PUBLISHED_TOL, "SPARC {s}");
    assert!((l - -5.81636).abs() < PUBLISHED_TOL, "LDLJ {l}");
}

#[test]
fn minimum_jerk_profile_reproduces_the_published_sparc_and_ldlj() {
    let v = min_jerk();
    let s = sparc(&v, 100.0, SparcParams::default()).unwrap();
    let l = ldlj_speed(&v, 100.0).unwrap();
    assert!((s - -1.40583).abs() < PUBLISHED_TOL, "SPARC {s}");
    assert!((l - -5.30163).abs() < PUBLISHED_TOL, "LDLJ {l}");
}

#[derive(Deserialize)]
struct Expected {
    cases: Vec<Case>,
    speed_profile: Profile,
}

#[derive(Deserialize)]
struct Case {
    name: String,
    fs_hz: f64,
    speed: Vec<f64>,
    sparc: f64,
    ldlj: f64,
}

#[derive(Deserialize)]
struct Profile {
    fs_hz: f64,
    lowpass_hz: f64,
    angle: Vec<f64>,
    speed: Vec<f64>,
}

fn expected() -> Expected {
    serde_json::from_str(include_str!("reference/expected.json")).unwrap()
}

fn rel_err(got: f64, want: f64) -> f64 {
    (got - want).abs() / want.abs().max(1e-300)
}

#[test]
fn sparc_and_ldlj_match_the_numpy_reference_within_1e_9_relative() {
    let e = expected();
    assert!(e.cases.len() >= 20, "{} cases", e.cases.len());
    let mut worst = (0.0_f64, 0.0_f64);
    for c in &e.cases {
        let s = sparc(&c.speed, c.fs_hz, SparcParams::default()).unwrap();
        let l = ldlj_speed(&c.speed, c.fs_hz).unwrap();
        let (es, el) = (rel_err(s, c.sparc), rel_err(l, c.ldlj));
        assert!(
            es < REFERENCE_REL_TOL,
            "{}: SPARC {s} vs {}",
            c.name,
            c.sparc
        );
        assert!(el < REFERENCE_REL_TOL, "{}: LDLJ {l} vs {}", c.name, c.ldlj);
        worst = (worst.0.max(es), worst.1.max(el));
    }
    println!(
        "worst relative error: SPARC {:.1e}, LDLJ {:.1e}",
        worst.0, worst.1
    );
}

#[test]
fn speed_profile_matches_scipy_filtfilt_of_numpy_gradient() {
    let p = expected().speed_profile;
    let got = speed_profile(&p.angle, p.fs_hz, p.lowpass_hz);
    assert_eq!(got.len(), p.speed.len());
    let peak = p.speed.iter().copied().fold(0.0, f64::max);
    for (i, (g, w)) in got.iter().zip(&p.speed).enumerate() {
        assert!((g - w).abs() <= 1e-9 * peak, "sample {i}: {g} vs {w}");
    }
}

#[test]
fn nan_at_index_7_is_an_error_naming_index_7() {
    let mut v = min_jerk();
    v[7] = f64::NAN;
    for err in [
        sparc(&v, 100.0, SparcParams::default()).unwrap_err(),
        ldlj_speed(&v, 100.0).unwrap_err(),
        metrics::segment(&v, 100.0, metrics::SegmentParams::default()).unwrap_err(),
    ] {
        assert!(
            matches!(err, MetricError::NonFinite { index: 7, .. }),
            "{err:?}"
        );
        assert!(err.to_string().contains("index 7"), "{err}");
    }
    let err = metrics::session_measures(&v, 100.0, &[]).unwrap_err();
    assert!(
        err.to_string().contains("wheel angle: sample at index 7"),
        "{err}"
    );
    let err = metrics::session_measures(&min_jerk(), 100.0, &[("elbow", &v)]).unwrap_err();
    assert!(
        err.to_string().contains("\"elbow\": sample at index 7"),
        "{err}"
    );
}

#[test]
fn zero_negative_or_nan_sampling_rate_is_an_error() {
    let v = min_jerk();
    for fs in [0.0, -100.0, f64::NAN, f64::INFINITY] {
        let err = sparc(&v, fs, SparcParams::default()).unwrap_err();
        assert!(matches!(err, MetricError::BadSampleRate { .. }), "{err:?}");
        assert!(err.to_string().contains("must be finite and > 0"), "{err}");
        assert!(ldlj_speed(&v, fs).is_err());
        assert!(metrics::session_measures(&v, fs, &[]).is_err());
        assert!(metrics::LiveMeasures::new(fs, &[], &Default::default()).is_err());
    }
}

#[test]
fn empty_short_and_degenerate_inputs_are_errors() {
    let p = SparcParams::default();
    assert!(matches!(
        sparc(&[], 100.0, p),
        Err(MetricError::Empty { .. })
    ));
    let err = ldlj_speed(&[1.0, 2.0], 100.0).unwrap_err();
    assert_eq!(err.to_string(), "speed: 2 sample(s), at least 3 needed");
    assert!(matches!(
        sparc(&[0.0; 50], 100.0, p),
        Err(MetricError::Degenerate { .. })
    ));
    assert!(matches!(
        ldlj_speed(&[0.5; 50], 100.0),
        Err(MetricError::Degenerate { .. })
    ));
    let bad = SparcParams { amp_th: 1.5, ..p };
    let err = sparc(&min_jerk(), 100.0, bad).unwrap_err();
    assert!(err.to_string().contains("`amp_th` = 1.5"), "{err}");
}
