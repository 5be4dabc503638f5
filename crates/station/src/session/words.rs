//! The session's words for the patient: exercise names and instructions from their short
//! names, never internal ids. The screen, the end reasons and the recorder's per-exercise
//! results all speak them.

/// An exercise's name for the patient: its short name in words (`sine-road` → "Sine road").
pub fn plain_name(short: &str) -> String {
    capitalised(&short.replace('-', " "))
}

/// `s` with its first letter upper-case (words shown to the patient).
pub fn capitalised(s: &str) -> String {
    let mut chars = s.chars();
    chars.next().map_or_else(String::new, |first| {
        first.to_uppercase().chain(chars).collect()
    })
}

/// What an exercise asks of the patient, in plain words, from its short name.
pub fn plain_instruction(short: &str) -> &'static str {
    match short {
        s if s.starts_with("dial") || s == "haptic-sweep" => {
            "Turn the wheel so the black needle follows the red one"
        }
        "strength" => "Push the wheel left, then right, as hard as you comfortably can",
        "slalom" => "Steer between the cones and keep the car on the road",
        "lane-change" => "Move into the other lane when the road does, then hold it",
        "straight-road" => "Keep the car in the middle of the lane",
        "sharp-turns" | "s-bend" => "Steer through the bends, keep the car in the lane",
        _ => "Follow the winding road, keep the car in the lane",
    }
}
