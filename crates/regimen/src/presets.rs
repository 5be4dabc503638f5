//! Easy, medium and hard starting points for every exercise kind (issue 41): what the console's
//! prescribe form offers a therapist in words, each setting the kind's engineering parameters
//! (amplitude, wavelength, speed, lane width, the dial's range and pace…). A preset sets how
//! hard an exercise is, never how long: the exercise's time (`duration_s`), sets and rests
//! stay the therapist's. No preset names a haptic model, a torque ceiling or assistance: the
//! station's own settings and safety chain apply, and every preset passes
//! [`crate::Regimen::from_toml`] (tested below), so a form built from them can only prescribe
//! what the station accepts.

use exercises::DialSignal;
use exercises::exercise::{
    ClothoidSpec, DialSpec, HapticSweepSpec, LaneChangeSpec, SBendSpec, SharpTurnsSpec, SineSpec,
    SlalomSpec, StraightSpec, StrengthSpec, TriangleSpec,
};
use exercises::{ExerciseSpec, SweepParameter};
use serde::Serialize;

/// How hard a preset is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Level {
    /// A first session, or a patient with little control.
    Easy,
    /// The thesis's own settings, about.
    Medium,
    /// Tighter, faster, larger.
    Hard,
}

impl Level {
    /// Every level, easiest first.
    pub const ALL: [Level; 3] = [Level::Easy, Level::Medium, Level::Hard];
}

/// One preset: an exercise kind at a level, in a therapist's words.
#[derive(Clone, Debug, PartialEq)]
pub struct Preset {
    /// How hard.
    pub level: Level,
    /// What the patient meets, in plain words (no field names, no engineering units).
    pub words: &'static str,
    /// The exercise with the preset's parameters (its time left at the kind's default).
    pub exercise: ExerciseSpec,
}

impl Preset {
    /// The exercise's `kind` as a regimen writes it (`"sine"`, `"lane-change"`).
    pub fn kind(&self) -> String {
        toml::Value::try_from(&self.exercise)
            .ok()
            .and_then(|v| v.get("kind").and_then(|k| k.as_str()).map(str::to_owned))
            .unwrap_or_default()
    }

    /// The preset's fields as a regimen's `[[exercise]]` table holds them (TOML values as
    /// JSON, unset optional fields left out), without `duration_s`: a preset sets how hard,
    /// not how long.
    pub fn fields(&self) -> serde_json::Value {
        let mut table = toml::Value::try_from(&self.exercise)
            .ok()
            .and_then(|v| v.as_table().cloned())
            .unwrap_or_default();
        table.remove("duration_s");
        serde_json::to_value(table).unwrap_or_default()
    }
}

/// The presets of every exercise kind, three per kind (easy, medium, hard), in the order of
/// [`ExerciseSpec`]'s kinds.
pub fn presets() -> Vec<Preset> {
    [
        straight_and_waves(),
        bends(),
        lanes_and_cones(),
        dial_and_measures(),
    ]
    .concat()
}

/// A preset of `exercise` at `level`, in `words`.
fn p(level: Level, words: &'static str, exercise: ExerciseSpec) -> Preset {
    Preset {
        level,
        words,
        exercise,
    }
}

/// Straight, sine and triangle roads.
fn straight_and_waves() -> Vec<Preset> {
    use Level::{Easy, Hard, Medium};
    vec![
        p(
            Easy,
            "A wide lane, driven slowly.",
            ExerciseSpec::Straight(StraightSpec {
                length_m: 200.0,
                lane_width_m: 4.5,
                speed_m_s: 6.0,
                ..Default::default()
            }),
        ),
        p(
            Medium,
            "An ordinary lane at town speed.",
            ExerciseSpec::Straight(StraightSpec {
                length_m: 300.0,
                lane_width_m: 3.5,
                speed_m_s: 10.0,
                ..Default::default()
            }),
        ),
        p(
            Hard,
            "A narrow lane, driven faster.",
            ExerciseSpec::Straight(StraightSpec {
                length_m: 400.0,
                lane_width_m: 2.8,
                speed_m_s: 14.0,
                ..Default::default()
            }),
        ),
        p(
            Easy,
            "Long gentle waves in a wide lane, slowly.",
            ExerciseSpec::Sine(SineSpec {
                amplitude_m: 2.0,
                wavelength_m: 150.0,
                periods: 2,
                lane_width_m: 4.0,
                speed_m_s: 8.0,
                duration_s: None,
            }),
        ),
        p(
            Medium,
            "The thesis's winding road.",
            ExerciseSpec::Sine(SineSpec {
                amplitude_m: 4.0,
                wavelength_m: 120.0,
                periods: 4,
                lane_width_m: 3.5,
                speed_m_s: 12.0,
                duration_s: None,
            }),
        ),
        p(
            Hard,
            "Large, closer waves in a narrow lane.",
            ExerciseSpec::Sine(SineSpec {
                amplitude_m: 6.5,
                wavelength_m: 90.0,
                periods: 5,
                lane_width_m: 3.0,
                speed_m_s: 12.0,
                duration_s: None,
            }),
        ),
        p(
            Easy,
            "Shallow zigzags with wide corners, slowly.",
            ExerciseSpec::Triangle(TriangleSpec {
                amplitude_m: 2.0,
                wavelength_m: 150.0,
                corner_radius_m: 30.0,
                periods: 2,
                lane_width_m: 4.0,
                speed_m_s: 8.0,
                duration_s: None,
            }),
        ),
        p(
            Medium,
            "Zigzags with rounded corners.",
            ExerciseSpec::Triangle(TriangleSpec {
                amplitude_m: 4.0,
                wavelength_m: 120.0,
                corner_radius_m: 25.0,
                periods: 3,
                lane_width_m: 3.5,
                speed_m_s: 12.0,
                duration_s: None,
            }),
        ),
        p(
            Hard,
            "Steep zigzags with tight corners.",
            ExerciseSpec::Triangle(TriangleSpec {
                amplitude_m: 6.0,
                wavelength_m: 100.0,
                corner_radius_m: 12.0,
                periods: 4,
                lane_width_m: 3.0,
                speed_m_s: 11.0,
                duration_s: None,
            }),
        ),
    ]
}

/// Clothoid roads, sharp turns and S-bends.
fn bends() -> Vec<Preset> {
    use Level::{Easy, Hard, Medium};
    vec![
        p(
            Easy,
            "A bend that tightens a little, slowly.",
            ExerciseSpec::Clothoid(ClothoidSpec {
                length_m: 200.0,
                end_curvature_1_m: 0.015,
                unwind_m: 60.0,
                lane_width_m: 4.0,
                speed_m_s: 8.0,
                duration_s: None,
            }),
        ),
        p(
            Medium,
            "A bend that tightens steadily.",
            ExerciseSpec::Clothoid(ClothoidSpec {
                length_m: 150.0,
                end_curvature_1_m: 0.025,
                unwind_m: 40.0,
                lane_width_m: 3.5,
                speed_m_s: 12.0,
                duration_s: None,
            }),
        ),
        p(
            Hard,
            "A bend that tightens sharply in a narrow lane.",
            ExerciseSpec::Clothoid(ClothoidSpec {
                length_m: 150.0,
                end_curvature_1_m: 0.04,
                unwind_m: 40.0,
                lane_width_m: 3.0,
                speed_m_s: 12.0,
                duration_s: None,
            }),
        ),
        p(
            Easy,
            "A few half turns on wide curves.",
            ExerciseSpec::SharpTurns(SharpTurnsSpec {
                angle_deg: 45.0,
                radius_m: 25.0,
                straight_m: 60.0,
                count: 4,
                lane_width_m: 4.0,
                speed_m_s: 8.0,
                duration_s: None,
            }),
        ),
        p(
            Medium,
            "Right-angle turns, left and right.",
            ExerciseSpec::SharpTurns(SharpTurnsSpec {
                angle_deg: 90.0,
                radius_m: 15.0,
                straight_m: 50.0,
                count: 4,
                lane_width_m: 3.5,
                speed_m_s: 10.0,
                duration_s: None,
            }),
        ),
        p(
            Hard,
            "More right-angle turns, tighter and closer.",
            ExerciseSpec::SharpTurns(SharpTurnsSpec {
                angle_deg: 90.0,
                radius_m: 12.0,
                straight_m: 40.0,
                count: 6,
                lane_width_m: 3.0,
                speed_m_s: 10.0,
                duration_s: None,
            }),
        ),
        p(
            Easy,
            "Two gentle bends in a wide lane.",
            ExerciseSpec::SBend(SBendSpec {
                radius_m: 40.0,
                angle_deg: 45.0,
                lane_width_m: 4.0,
                speed_m_s: 7.0,
                duration_s: None,
            }),
        ),
        p(
            Medium,
            "A left then a right bend.",
            ExerciseSpec::SBend(SBendSpec {
                radius_m: 30.0,
                angle_deg: 60.0,
                lane_width_m: 3.5,
                speed_m_s: 9.0,
                duration_s: None,
            }),
        ),
        p(
            Hard,
            "Two tight bends in a narrow lane.",
            ExerciseSpec::SBend(SBendSpec {
                radius_m: 20.0,
                angle_deg: 75.0,
                lane_width_m: 3.0,
                speed_m_s: 8.0,
                duration_s: None,
            }),
        ),
    ]
}

/// Lane changes and slaloms.
fn lanes_and_cones() -> Vec<Preset> {
    use Level::{Easy, Hard, Medium};
    vec![
        p(
            Easy,
            "Three slow, long lane changes.",
            ExerciseSpec::LaneChange(LaneChangeSpec {
                offset_m: 3.0,
                transition_m: 50.0,
                hold_m: 60.0,
                count: 3,
                lane_width_m: 4.0,
                speed_m_s: 8.0,
                duration_s: None,
            }),
        ),
        p(
            Medium,
            "Four lane changes at town speed.",
            ExerciseSpec::LaneChange(LaneChangeSpec {
                offset_m: 3.5,
                transition_m: 30.0,
                hold_m: 50.0,
                count: 4,
                lane_width_m: 3.5,
                speed_m_s: 12.0,
                duration_s: None,
            }),
        ),
        p(
            Hard,
            "Six quick lane changes.",
            ExerciseSpec::LaneChange(LaneChangeSpec {
                offset_m: 3.5,
                transition_m: 20.0,
                hold_m: 30.0,
                count: 6,
                lane_width_m: 3.0,
                speed_m_s: 12.0,
                duration_s: None,
            }),
        ),
        p(
            Easy,
            "Six cones far apart, slowly.",
            ExerciseSpec::Slalom(SlalomSpec {
                cone_spacing_m: 25.0,
                cone_count: 6,
                weave_m: 1.2,
                lane_width_m: 3.5,
                speed_m_s: 5.0,
                duration_s: None,
            }),
        ),
        p(
            Medium,
            "Eight cones.",
            ExerciseSpec::Slalom(SlalomSpec {
                cone_spacing_m: 18.0,
                cone_count: 8,
                weave_m: 1.5,
                lane_width_m: 3.0,
                speed_m_s: 7.0,
                duration_s: None,
            }),
        ),
        p(
            Hard,
            "Ten cones close together in a narrow lane.",
            ExerciseSpec::Slalom(SlalomSpec {
                cone_spacing_m: 15.0,
                cone_count: 10,
                weave_m: 1.5,
                lane_width_m: 2.8,
                speed_m_s: 7.0,
                duration_s: None,
            }),
        ),
    ]
}

/// The dial, the strength test and the haptic sweep.
fn dial_and_measures() -> Vec<Preset> {
    use Level::{Easy, Hard, Medium};
    vec![
        p(Easy, "Small turns each way, slowly.", dial(45.0, 0.5)),
        p(
            Medium,
            "Turns of a quarter turn and more each way.",
            dial(90.0, 1.0),
        ),
        p(Hard, "Large turns each way, faster.", dial(120.0, 1.5)),
        p(
            Easy,
            "A gentle test: the spring stiffens slowly.",
            ExerciseSpec::Strength(StrengthSpec {
                stiffness_nm_per_rad: 40.0,
                ramp_nm_per_s: 0.3,
                side_s: 15.0,
            }),
        ),
        p(
            Medium,
            "The standard test.",
            ExerciseSpec::Strength(StrengthSpec::default()),
        ),
        p(
            Hard,
            "A quicker test: the spring stiffens faster.",
            ExerciseSpec::Strength(StrengthSpec {
                stiffness_nm_per_rad: 60.0,
                ramp_nm_per_s: 1.0,
                side_s: 10.0,
            }),
        ),
        p(
            Easy,
            "Three steps of half a minute, small slow swings.",
            ExerciseSpec::HapticSweep(HapticSweepSpec {
                parameter: SweepParameter::Spring,
                levels: vec![0.0, 0.2, 0.4],
                level_s: 30.0,
                amplitude_deg: 60.0,
                frequency_rad_s: 0.5,
            }),
        ),
        p(
            Medium,
            "The thesis's six steps of a minute.",
            ExerciseSpec::HapticSweep(HapticSweepSpec::default()),
        ),
        p(
            Hard,
            "Six steps of a minute, faster swings.",
            ExerciseSpec::HapticSweep(HapticSweepSpec {
                frequency_rad_s: 1.5,
                ..Default::default()
            }),
        ),
    ]
}

/// The dial following a sine of `amplitude_deg` each way at `frequency_rad_s`.
fn dial(amplitude_deg: f64, frequency_rad_s: f64) -> ExerciseSpec {
    ExerciseSpec::Dial(DialSpec {
        reference: DialSignal::Sine {
            amplitude_deg,
            frequency_rad_s,
        },
        ..Default::default()
    })
}

/// A preset as the API gives it (`GET /api/regimen/presets`).
#[derive(Clone, Debug, Serialize)]
pub struct PresetView {
    /// The exercise kind (`"sine"`).
    pub kind: String,
    /// `"easy"`, `"medium"` or `"hard"`.
    pub level: Level,
    /// What the patient meets, in plain words.
    pub words: &'static str,
    /// The fields the preset sets in the exercise's table (no `duration_s`).
    pub fields: serde_json::Value,
}

/// Every preset as the API gives it.
pub fn preset_views() -> Vec<PresetView> {
    presets()
        .iter()
        .map(|p| PresetView {
            kind: p.kind(),
            level: p.level,
            words: p.words,
            fields: p.fields(),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{MAX_DEVICE_TORQUE_NM, Regimen};

    /// Every kind the regimen's schema lists.
    fn schema_kinds() -> Vec<String> {
        let schema = Regimen::json_schema();
        schema["$defs"]["RegimenEntry"]["oneOf"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| {
                v["properties"]["kind"]["const"]
                    .as_str()
                    .unwrap()
                    .to_owned()
            })
            .collect()
    }

    /// A regimen's TOML listing `exercises`.
    fn regimen_of(exercises: Vec<toml::Table>) -> String {
        let mut root = toml::Table::new();
        root.insert(
            "exercise".into(),
            toml::Value::Array(exercises.into_iter().map(toml::Value::Table).collect()),
        );
        toml::to_string(&root).unwrap()
    }

    #[test]
    fn every_exercise_kind_has_an_easy_a_medium_and_a_hard_preset() {
        let all = presets();
        for kind in schema_kinds() {
            let levels: Vec<Level> = all
                .iter()
                .filter(|p| p.kind() == kind)
                .map(|p| p.level)
                .collect();
            assert_eq!(levels, Level::ALL, "{kind}");
            let fields: Vec<_> = all
                .iter()
                .filter(|p| p.kind() == kind)
                .map(Preset::fields)
                .collect();
            assert!(
                fields[0] != fields[1] && fields[1] != fields[2],
                "{kind}: {fields:?}"
            );
        }
    }

    /// A preset is prescribed as the form sends it: its fields, a time of the therapist's,
    /// in sets with rests. Each is accepted by the validator the hub and station use, alone
    /// and as the longest the form offers (ten sets of ten minutes would be over the
    /// session's bound; three sets of five minutes with two-minute rests are not).
    #[test]
    fn every_preset_of_every_kind_passes_the_regimens_validator_within_the_safety_bounds() {
        for p in presets() {
            let mut table: toml::Table = serde_json::from_value(p.fields()).unwrap();
            assert!(
                !table.contains_key("haptic") && !table.contains_key("assist"),
                "a preset never sets the torque: {table:?}"
            );
            let one = regimen_of(vec![table.clone()]);
            let r = Regimen::from_toml(&one, "preset")
                .unwrap_or_else(|e| panic!("{} {:?}: {e}", p.kind(), p.level));
            assert_eq!(r.exercises[0].exercise, p.exercise, "{one}");
            if p.kind() != "strength" && p.kind() != "haptic-sweep" {
                table.insert("duration_s".into(), 300.0.into());
            }
            table.insert("rest_s".into(), 120.0.into());
            let sets = regimen_of(vec![table.clone(), table.clone(), table]);
            let r = Regimen::from_toml(&sets, "preset in sets")
                .unwrap_or_else(|e| panic!("{} {:?}: {e}", p.kind(), p.level));
            for e in &r.exercises {
                if let Some(h) = &e.haptic {
                    assert!(h.ceiling_nm.unwrap_or(0.0) <= MAX_DEVICE_TORQUE_NM);
                }
            }
        }
    }

    #[test]
    fn a_preset_says_what_the_patient_meets_in_words_without_field_names() {
        for p in presets() {
            assert!(p.words.len() > 5 && p.words.ends_with('.'), "{:?}", p.words);
            assert!(
                !p.words.contains('_') && !p.words.contains("rad") && !p.words.contains(" m/s"),
                "{:?}",
                p.words
            );
        }
        let views = preset_views();
        assert_eq!(views.len(), 3 * schema_kinds().len());
        assert!(views.iter().all(|v| v.fields.get("duration_s").is_none()));
        let json = serde_json::to_value(&views[0]).unwrap();
        assert_eq!(json["kind"], "straight");
        assert_eq!(json["level"], "easy");
    }
}
