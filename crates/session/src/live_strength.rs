//! The strength test for the therapist's live view: in every live summary while a strength
//! test runs, the side being pushed, the patient's push the spring balances now and the
//! highest push so far of each side, N·m (the ceiling is the summary's `ceiling_nm`). They are
//! the haptic thread's test's own figures, carried on each tick's score
//! ([`record::StrengthNow`]), so the live figures are the ones the test records.

use record::ScoreSample;

/// The summary's names: the side pushed now (1 left, −1 right, 0 resting or done) …
pub const SIDE: &str = "strength_side";
/// … the push the spring balances now, in the side's direction, N·m …
pub const PUSH_NM: &str = "strength_push_nm";
/// … and the highest push so far of the left and right sides, N·m (once each side started).
pub const PEAK_NM: [&str; 2] = ["strength_peak_left_nm", "strength_peak_right_nm"];

/// The live figures of the strength test in `score`'s exercise (none for any other exercise).
pub fn extra(score: &ScoreSample) -> Vec<(String, f64)> {
    let Some(s) = score.strength else {
        return Vec::new();
    };
    let mut out = vec![(SIDE.to_owned(), s.side), (PUSH_NM.to_owned(), s.push_nm)];
    for (name, peak) in PEAK_NM.iter().zip([s.peak_left_nm, s.peak_right_nm]) {
        if let Some(p) = peak {
            out.push(((*name).to_owned(), p));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use record::StrengthNow;

    #[test]
    fn the_live_strength_says_the_side_the_push_and_each_sides_peak_of_strength_tests_only() {
        let get =
            |x: &[(String, f64)], name: &str| x.iter().find(|(n, _)| n == name).map(|(_, v)| *v);
        assert!(
            extra(&ScoreSample::default()).is_empty(),
            "a road or dial: nothing"
        );
        // Pushing left at 1 N·m, the right side not started.
        let left = ScoreSample {
            strength: Some(StrengthNow {
                side: 1.0,
                push_nm: 1.0,
                peak_left_nm: Some(1.0),
                peak_right_nm: None,
            }),
            ..ScoreSample::default()
        };
        let x = extra(&left);
        assert_eq!(get(&x, SIDE), Some(1.0));
        assert_eq!(get(&x, PUSH_NM), Some(1.0));
        assert_eq!(get(&x, PEAK_NM[0]), Some(1.0));
        assert_eq!(get(&x, PEAK_NM[1]), None, "the right side has not started");
        // Both sides over.
        let done = ScoreSample {
            strength: Some(StrengthNow {
                side: 0.0,
                push_nm: 0.0,
                peak_left_nm: Some(1.0),
                peak_right_nm: Some(0.8),
            }),
            ..ScoreSample::default()
        };
        let x = extra(&done);
        assert_eq!(get(&x, SIDE), Some(0.0));
        assert_eq!(
            (get(&x, PEAK_NM[0]), get(&x, PEAK_NM[1])),
            (Some(1.0), Some(0.8))
        );
    }
}
