//! Today's session as the patient reads it before starting: the exercises in plain words
//! with their minutes.

use crate::render::StatusLine;
use regimen::Regimen;
use vehicle::exercise::ExerciseSpec;

/// Today's session: each exercise's name in plain words and its planned length.
#[derive(Debug, Clone, PartialEq)]
pub struct TodayPlan {
    /// (name, planned length in s), in the order they are done.
    pub exercises: Vec<(String, f64)>,
    /// The clinic has prescribed this (false: the station's default while none has arrived).
    pub prescribed: bool,
}

pub use crate::screen::plain_name;

/// `m:ss` of a planned length.
fn minutes(seconds: f64) -> String {
    let s = seconds.max(0.0).round() as u64;
    format!("{}:{:02}", s / 60, s % 60)
}

impl TodayPlan {
    /// The clinic's regimen; an exercise that cannot be built is named as such.
    pub fn from_regimen(r: &Regimen) -> Self {
        let exercises = r
            .exercises
            .iter()
            .map(|e| match e.exercise.build() {
                Ok(x) => (plain_name(&x.name), x.planned_duration_s()),
                Err(_) => ("An exercise this version cannot show".into(), 0.0),
            })
            .collect();
        Self {
            exercises,
            prescribed: true,
        }
    }

    /// No regimen has arrived yet: the station's default exercise for `duration_s`.
    pub fn default_drive(exercise: &str, duration_s: f64) -> Self {
        let name = ExerciseSpec::from_name(exercise)
            .ok()
            .and_then(|s| s.build().ok())
            .map_or_else(|| plain_name(exercise), |x| plain_name(&x.name));
        Self {
            exercises: vec![(name, duration_s)],
            prescribed: false,
        }
    }

    /// The whole session's planned length, s.
    pub fn total_s(&self) -> f64 {
        self.exercises.iter().map(|(_, s)| s).sum()
    }

    /// The lines of the "Today's session" page.
    pub fn lines(&self) -> Vec<StatusLine> {
        let n = self.exercises.len();
        let mut head = format!(
            "{n} exercise{}, about {} minute{}",
            if n == 1 { "" } else { "s" },
            (self.total_s() / 60.0).ceil().max(1.0),
            if self.total_s() > 60.0 { "s" } else { "" },
        );
        if !self.prescribed {
            head.push_str(" (your clinic has not sent your plan yet)");
        }
        let mut lines = vec![StatusLine {
            ok: None,
            text: head,
        }];
        lines.extend(
            self.exercises
                .iter()
                .enumerate()
                .map(|(i, (name, s))| StatusLine {
                    ok: None,
                    text: format!("   {}. {name}   {}", i + 1, minutes(*s)),
                }),
        );
        lines
    }
}
