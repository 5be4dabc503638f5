//! Movement measures of a rehabilitation session.
//!
//! - [`smoothness`]: [`sparc`] and [`ldlj_speed`], smoothness of one movement's speed
//!   profile, as the reference implementations compute them (Balasubramanian et al. 2015;
//!   monalysa).
//! - [`filter`]: the speed profile of an angle signal ([`speed_profile`]).
//! - [`segment`](mod@segment): discrete movements in a continuous speed profile
//!   ([`segment`](fn@segment): a speed threshold, gap merging, a minimum duration), each scored.
//! - [`session`]: [`session_measures`], a session's wheel movements, their smoothness, speed,
//!   time and peaks (medians and means), ranges of motion, time active — serialisable for the
//!   report.
//! - [`robot`]: measures as robot assessments of stroke report them (InMotion, Kinarm):
//!   [`speed_metric`], [`steering_reversals`], [`step_responses`] (reaction time, initial
//!   direction error, path length ratio), with their references.
//! - [`reliability`]: [`test_retest`], ICC(2,1), SEM and MDC95 of a measure from repeated
//!   measurements of the same subjects (Shrout & Fleiss 1979; Weir 2005).
//! - [`change`]: a patient's change since their first assessment told from measurement noise
//!   (their own MDC95, else the cohort's, else the published one): better, worse or within
//!   measurement noise.
//! - [`assessment_noise`]: the standard assessment's MDC95 per part and measure, measured on a
//!   simulated cohort (`telerehab hub cohort`).
//! - [`words`]: the one table of measure words (plain name, unit, decimals, axis range,
//!   noise, better) and one wording per way a session ends, for every page and file.
//! - [`live`]: [`LiveMeasures`], the cheap running subset for the live display.
//! - [`error`]: the errors, [`MetricError`].
//!
//! Pure: no I/O, no threads, no clock. Time comes in as a sampling rate `fs_hz`; angles in
//! rad, speeds in rad/s.

pub mod assessment_noise;
pub mod change;
pub mod error;
pub mod filter;
pub mod live;
pub mod reliability;
pub mod robot;
pub mod segment;
pub mod session;
pub mod smoothness;
pub mod words;

pub use error::MetricError;
pub use filter::{Biquad, derivative, speed_profile};
pub use live::LiveMeasures;
pub use reliability::{OWN_NOISE_MIN_REPEATS, OwnNoise, Reliability, own_mdc95, test_retest};
pub use robot::{
    DirectedResponse, DirectedStep, MIN_REACTION_TIME_S, ResponseParams, StepResponse, TargetStep,
    directed_step_responses, steering_reversals, step_responses,
};
pub use segment::{Movement, SegmentParams, segment, speed_metric, threshold};
pub use session::{
    JointRange, SessionMeasures, SessionParams, Summary, range_of_motion, session_measures,
    session_measures_of_runs, session_measures_with,
};
pub use smoothness::{MAX_PADLEVEL, MIN_SAMPLES, SparcParams, ldlj_speed, sparc};

#[cfg(test)]
mod tests {
    /// The station hands these to its recorder and report threads.
    #[test]
    fn live_measures_and_session_measures_are_send() {
        fn send<T: Send>() {}
        send::<crate::LiveMeasures>();
        send::<crate::SessionMeasures>();
    }
}
