//! Today's session as the patient reads it before starting: the exercises in plain words
//! with their minutes, and the whole session's length with its rests and the cards between
//! exercises ("about N minutes" is what the patient sits through, not only the driving).

use exercises::exercise::ExerciseSpec;
use regimen::Regimen;
use render::StatusLine;

/// Today's session: each exercise and its planned length.
#[derive(Debug, Clone, PartialEq)]
pub struct TodayPlan {
    /// (the exercise's short name, `None` for one that cannot be built; planned length in s),
    /// in the order they are done. Named in the patient's words, in the language in force,
    /// when the page is drawn ([`crate::screen::patient_name`]).
    pub exercises: Vec<(Option<String>, f64)>,
    /// The clinic has prescribed this (false: the station's default while none has arrived).
    pub prescribed: bool,
    /// The rests and the cards between exercises, s.
    pub between_s: f64,
}

/// `m:ss` of a planned length.
fn minutes_text(seconds: f64) -> String {
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
                Ok(x) => (Some(x.name.clone()), x.planned_duration_s()),
                Err(_) => (None, 0.0),
            })
            .collect();
        let last = r.exercises.len().saturating_sub(1);
        let between_s = r
            .exercises
            .iter()
            .take(last)
            .map(|e| session::course::Break::after(e.rest_s).length_s)
            .sum();
        Self {
            exercises,
            prescribed: true,
            between_s,
        }
    }

    /// No regimen has arrived yet: the station's default exercise for `duration_s`.
    pub fn default_drive(exercise: &str, duration_s: f64) -> Self {
        let name = ExerciseSpec::from_name(exercise)
            .ok()
            .and_then(|s| s.build().ok())
            .map_or_else(|| exercise.to_owned(), |x| x.name);
        Self {
            exercises: vec![(Some(name), duration_s)],
            prescribed: false,
            between_s: 0.0,
        }
    }

    /// The whole session's planned length, its rests and cards between exercises included, s.
    pub fn total_s(&self) -> f64 {
        self.exercises.iter().map(|(_, s)| s).sum::<f64>() + self.between_s
    }

    /// The lines of the "Today's session" page.
    pub fn lines(&self) -> Vec<StatusLine> {
        let minutes = (self.total_s() / 60.0).ceil().max(1.0) as u64;
        let mut lines = vec![StatusLine {
            ok: None,
            text: i18n::tr!(
                "front-today-summary",
                exercises = self.exercises.len(),
                minutes = minutes
            ),
        }];
        if !self.prescribed {
            lines.push(StatusLine {
                ok: None,
                text: i18n::tr!("front-today-no-plan"),
            });
        }
        lines.extend(self.exercises.iter().enumerate().map(|(i, (short, s))| {
            let name = short.as_deref().map_or_else(
                || i18n::tr!("front-today-unbuildable"),
                crate::screen::patient_name,
            );
            StatusLine {
                ok: None,
                text: format!("   {}. {name}   {}", i + 1, minutes_text(*s)),
            }
        }));
        lines
    }
}
