//! The session's words: exercise names and instructions from their short names, never
//! internal ids. [`plain_name`] is the clinic's English name (the reports, the hub's
//! records); [`patient_name`] and [`patient_instruction`] are the patient's, from the
//! catalogue (`session.ftl`) in the language in force.

use i18n::tr;

/// An exercise's name in the clinic's English (`sine-road` → "Sine road"): one spelling for
/// the station, the hub and the console.
pub use regimen::plain_name;

/// `s` with its first letter upper-case (words shown to the patient).
pub fn capitalised(s: &str) -> String {
    let mut chars = s.chars();
    chars.next().map_or_else(String::new, |first| {
        first.to_uppercase().chain(chars).collect()
    })
}

/// The catalogue's id of an exercise's name for the patient (`exercise-sine-road`), from its
/// short name; `exercise-other` for a name this build does not know.
pub fn name_id(short: &str) -> &'static str {
    match short {
        "straight-road" => "exercise-straight-road",
        "sine-road" => "exercise-sine-road",
        "triangle-road" => "exercise-triangle-road",
        "clothoid-road" => "exercise-clothoid-road",
        "sharp-turns" => "exercise-sharp-turns",
        "s-bend" => "exercise-s-bend",
        "lane-change" => "exercise-lane-change",
        "slalom" => "exercise-slalom",
        "dial-sine" => "exercise-dial-sine",
        "dial-multi-sine" => "exercise-dial-multi-sine",
        "dial-step" => "exercise-dial-step",
        "dial-ramp" => "exercise-dial-ramp",
        "dial-chirp" => "exercise-dial-chirp",
        "strength" => "exercise-strength",
        "haptic-sweep" => "exercise-haptic-sweep",
        "assessment-range" => "exercise-assessment-range",
        "assessment-tracking-slow" => "exercise-assessment-tracking-slow",
        "assessment-tracking-medium" => "exercise-assessment-tracking-medium",
        "assessment-tracking-fast" => "exercise-assessment-tracking-fast",
        "assessment-steps" => "exercise-assessment-steps",
        "assessment-strength" => "exercise-assessment-strength",
        s if s.starts_with("dial") => "exercise-dial-sine",
        _ => "exercise-other",
    }
}

/// An exercise's name for the patient, by what they do, in the language in force.
pub fn patient_name(short: &str) -> String {
    tr!(name_id(short))
}

/// The catalogue's id of what an exercise asks of the patient, from its short name.
pub fn instruction_id(short: &str) -> &'static str {
    match short {
        "assessment-range" => "instruction-assessment-range",
        "assessment-steps" => "instruction-assessment-steps",
        "assessment-strength" => "instruction-strength",
        s if s.starts_with("assessment-tracking") => "instruction-assessment-tracking",
        s if s.starts_with("dial") || s == "haptic-sweep" => "instruction-dial",
        "strength" => "instruction-strength",
        "slalom" => "instruction-slalom",
        "lane-change" => "instruction-lane-change",
        "straight-road" => "instruction-straight-road",
        "sharp-turns" | "s-bend" => "instruction-bends",
        _ => "instruction-road",
    }
}

/// What an exercise asks of the patient, in plain words, in the language in force.
pub fn patient_instruction(short: &str) -> String {
    tr!(instruction_id(short))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_exercise_has_a_name_and_an_instruction_in_the_catalogue() {
        let english = i18n::Catalogue::load("en").unwrap();
        for short in exercises::EXERCISE_NAMES {
            assert_ne!(name_id(short), "exercise-other", "{short}");
            assert!(english.has(name_id(short)), "{short}");
            assert!(english.has(instruction_id(short)), "{short}");
        }
        // The standard assessment's parts, each with its own name and what it asks.
        for spec in exercises::ExerciseSpec::assessment_protocol(0) {
            let short = spec.name();
            assert_ne!(name_id(&short), "exercise-other", "{short}");
            assert!(english.has(name_id(&short)), "{short}");
            assert!(english.has(instruction_id(&short)), "{short}");
            assert_ne!(instruction_id(&short), "instruction-road", "{short}");
        }
        assert_eq!(name_id("dial-newer"), "exercise-dial-sine");
        assert_eq!(name_id("newer"), "exercise-other");
    }
}
