# The prescribe form (crates/hub/console/prescribe.js): a therapist's words, plain and clinical.

prescribe-heading = Regimen
prescribe-version = Version { $version }, prescribed by { $by } on { $when }.
prescribe-version-gone = a therapist no longer at the clinic
prescribe-version-none = Nothing prescribed yet: the station runs its default exercise.
prescribe-version-now = Version { $version }, prescribed by { $by } just now.
prescribe-sessions-label = Sessions a week
prescribe-assessment-label = Standard assessment every … days (empty: none)
prescribe-trunk-cue-label = Remind to sit up when the trunk moves over … degrees (empty: never)
prescribe-no-exercise = No exercise yet: add one.
prescribe-add-label = Add an exercise
prescribe-add-button = Add
prescribe-full = At most { $max } exercises in a regimen, sets counted.
prescribe-message-note = To tell { $name } about the change, write in the message box below. It is sent with the prescription when you save.
prescribe-save = Save as a new version
prescribe-saving = Saving…
prescribe-saved = { $message ->
    [yes] Saved as version { $version }, with the message.
   *[no] Saved as version { $version }.
}
prescribe-message-problem = The message: { $problem }
prescribe-out-of-bounds = A value is outside its bounds (shown beside it).
prescribe-too-many = { $count } exercises with the sets counted: at most { $max }.
prescribe-total = { $untimed ->
    [0] About { $minutes } min of exercise and { $rests } min of rests.
    [one] About { $minutes } min of exercise and { $rests } min of rests, and one exercise without minutes (driven once or timed by the exercise itself).
   *[other] About { $minutes } min of exercise and { $rests } min of rests, and { $untimed } exercises without minutes (driven once or timed by the exercise itself).
}

prescribe-exercise-legend = Exercise { $n }: { $name }
prescribe-kind-unknown = An exercise kind this hub does not know: edit it in the text version.
prescribe-remove = Remove exercise { $n }
prescribe-levels-legend = How hard
prescribe-level-easy = Easy
prescribe-level-medium = Medium
prescribe-level-hard = Hard
prescribe-level-own = Own settings
prescribe-level-own-note = changed from the levels (see the details)
prescribe-minutes-label = Minutes
prescribe-minutes-road = once along the road
prescribe-sets-label = Sets (the exercise done again after a rest)
prescribe-rest-label = Rest after each set, seconds
prescribe-rest-default = the short card only
prescribe-dial-other = The target moves in another pattern than a swing: its settings are in the text version.
prescribe-dial-range-label = How far the wheel turns each way, degrees
prescribe-dial-pace-label = One swing there and back, seconds
prescribe-dial-words = The wheel turns up to { $degrees }° each way ({ $range ->
    [small] a small turn
    [quarter] up to a quarter turn
   *[more] more than a quarter turn
}), one swing there and back every { $seconds } s ({ $pace ->
    [slow] slow
    [moderate] moderate
   *[brisk] brisk
}).
prescribe-dial-sine = The target: a sine of { $degrees }° at { $rate } rad/s (amplitude_deg, frequency_rad_s).
prescribe-ceiling-label = Strongest push of the wheel (torque ceiling), N·m (empty: the station's)
prescribe-pedals-label = The patient sets the speed with the pedals (needs minutes; leave unticked for automatic speed)
prescribe-details-summary = Details: the settings behind the level

prescribe-text-summary = Edit as text (every setting, as in the station's regimens folder)
prescribe-text-label = Regimen (TOML)
prescribe-text-save = Save the text as a new version

prescribe-bounds-heading = Safety bounds the station enforces
prescribe-bounds-ceiling = Torque ceiling
prescribe-bounds-ceiling-text = At most { $nm } N·m in a prescription ({ $wheel ->
    [patient] what this patient's wheel can give
   *[consumer] the strongest consumer wheel
}), refused above. The station then caps it at its own wheel's ceiling: a prescription can lower the patient's ceiling, never raise it.
prescribe-bounds-slew = Torque changes
prescribe-bounds-slew-text = Slew-limited by the station's safety chain, whatever the prescription.
prescribe-bounds-session = Session
prescribe-bounds-session-text = At most { $max } exercises (each set counts as one), planned to last at most { $minutes } min together, rests and the cards between exercises included.
prescribe-bounds-levels = Levels
prescribe-bounds-levels-text = Every easy, medium and hard level is checked by the station's own validator.
prescribe-bounds-other = Every other setting
prescribe-bounds-other-text = Within the range shown beside it.
prescribe-bounds-note = The form's ranges come from the regimen's schema, which the hub derives from the station's own validator. The hub checks the whole regimen with that validator before storing it; the station picks the new version up at its next session.

prescribe-difficulty-legend = Difficulty that follows the patient
prescribe-difficulty-adapt = Adapt each session's difficulty to the patient (aiming at the target success rate, honouring "too easy" and "too hard")
prescribe-difficulty-changes = Changes:
prescribe-difficulty-note = Difficulty 1 is the regimen as written; 0 is half its speed and shape with all its assistance. Never beyond the prescription; the torque ceiling never changes.
prescribe-difficulty-target_success = The success rate the adaptation aims at
prescribe-difficulty-lowest = The easiest difficulty allowed
prescribe-difficulty-highest = The hardest difficulty allowed
prescribe-difficulty-start = The first session's difficulty
prescribe-aspect-speed = speed
prescribe-aspect-shape = shape
prescribe-aspect-assist = assistance

# Exercise kinds as the form names them.
prescribe-kind-straight = Straight road
prescribe-kind-sine = Sine road
prescribe-kind-triangle = Triangle road
prescribe-kind-clothoid = Clothoid road
prescribe-kind-sharp-turns = Sharp turns
prescribe-kind-s-bend = S-bend
prescribe-kind-lane-change = Lane change
prescribe-kind-slalom = Slalom
prescribe-kind-dial = Dial
prescribe-kind-strength = Strength
prescribe-kind-haptic-sweep = Haptic sweep

# The presets' words (regimen::presets), by kind and level.
prescribe-preset-straight-easy = A wide lane, driven slowly.
prescribe-preset-straight-medium = An ordinary lane at town speed.
prescribe-preset-straight-hard = A narrow lane, driven faster.
prescribe-preset-sine-easy = Long gentle waves in a wide lane, slowly.
prescribe-preset-sine-medium = The thesis's winding road.
prescribe-preset-sine-hard = Large, closer waves in a narrow lane.
prescribe-preset-triangle-easy = Shallow zigzags with wide corners, slowly.
prescribe-preset-triangle-medium = Zigzags with rounded corners.
prescribe-preset-triangle-hard = Steep zigzags with tight corners.
prescribe-preset-clothoid-easy = A bend that tightens a little, slowly.
prescribe-preset-clothoid-medium = A bend that tightens steadily.
prescribe-preset-clothoid-hard = A bend that tightens sharply in a narrow lane.
prescribe-preset-sharp-turns-easy = A few half turns on wide curves.
prescribe-preset-sharp-turns-medium = Right-angle turns, left and right.
prescribe-preset-sharp-turns-hard = More right-angle turns, tighter and closer.
prescribe-preset-s-bend-easy = Two gentle bends in a wide lane.
prescribe-preset-s-bend-medium = A left then a right bend.
prescribe-preset-s-bend-hard = Two tight bends in a narrow lane.
prescribe-preset-lane-change-easy = Three slow, long lane changes.
prescribe-preset-lane-change-medium = Four lane changes at town speed.
prescribe-preset-lane-change-hard = Six quick lane changes.
prescribe-preset-slalom-easy = Six cones far apart, slowly.
prescribe-preset-slalom-medium = Eight cones.
prescribe-preset-slalom-hard = Ten cones close together in a narrow lane.
prescribe-preset-dial-easy = Small turns each way, slowly.
prescribe-preset-dial-medium = Turns of a quarter turn and more each way.
prescribe-preset-dial-hard = Large turns each way, faster.
prescribe-preset-strength-easy = A gentle test: the spring stiffens slowly.
prescribe-preset-strength-medium = The standard test.
prescribe-preset-strength-hard = A quicker test: the spring stiffens faster.
prescribe-preset-haptic-sweep-easy = Three steps of half a minute, small slow swings.
prescribe-preset-haptic-sweep-medium = The thesis's six steps of a minute.
prescribe-preset-haptic-sweep-hard = Six steps of a minute, faster swings.

## The settings behind an exercise's level (its details), one a field of the regimen: units as the regimen writes them.
prescribe-field-lane-width-m = Lane width, m
prescribe-field-length-m = Length of the exercise part, m
prescribe-field-speed-m-s = Target speed, m/s
prescribe-field-amplitude-m = Amplitude of the curves, m
prescribe-field-periods = Number of whole waves
prescribe-field-wavelength-m = Wavelength, m
prescribe-field-corner-radius-m = Radius of the rounded corners, m
prescribe-field-end-curvature-1-m = Curvature reached at the end, 1/m (positive: turning left)
prescribe-field-unwind-m = Length of the unwinding curve, m
prescribe-field-angle-deg = Turn angle, °
prescribe-field-count = Number of turns or changes
prescribe-field-radius-m = Turn radius, m
prescribe-field-straight-m = Straight between turns, m
prescribe-field-hold-m = Straight after each change, m
prescribe-field-offset-m = Sideways shift, m
prescribe-field-transition-m = Length of one change, m
prescribe-field-cone-count = Number of cones
prescribe-field-cone-spacing-m = Distance between cones, m
prescribe-field-weave-m = Sideways distance of the path from each cone, m
prescribe-field-drift-deg = The target drifts this far toward the neglected side, ° of wheel turn
prescribe-field-ramp-nm-per-s = How fast the spring's limit rises to the ceiling, N·m/s
prescribe-field-side-s = Time limit of each side, s
prescribe-field-stiffness-nm-per-rad = Stiffness of the spring holding the wheel at the centre, N·m/rad
prescribe-field-amplitude-deg = The swing each way, °
prescribe-field-frequency-rad-s = The swing's frequency, rad/s
prescribe-field-level-s = Time at each level, s
