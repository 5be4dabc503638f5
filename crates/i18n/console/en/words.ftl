# Measures, end reasons, exercise kinds, trends and times in a clinician's words. The measure
# keys, units, decimals and ranges are the one table of crates/metrics/src/words.rs; only the
# plain names are here (words-measure-<key>, words-end-<kind>).

## Measures' plain names

words-measure-active-s = Active time
words-measure-session-s = Session length
words-measure-paused-s = Time paused
words-measure-active-pct = Time moving
words-measure-movements = Movements
words-measure-discrete-movements = Movements from rest to rest
words-measure-movements-per-min = Movements a minute
words-measure-reversals-per-min = Changes of steering direction a minute
words-measure-sparc-median = Smoothness (closer to 0 is smoother)
words-measure-ldlj-median = Smoothness of acceleration (closer to 0 is smoother)
words-measure-movement-peak-speed-deg-s-median = Top turning speed of a movement
words-measure-movement-time-s-median = Length of a movement
words-measure-speed-peaks-median = Stops and starts in a movement
words-measure-speed-metric-median = Evenness of speed (1 is even)
words-measure-reaction-time-s-median = Reaction time
words-measure-anticipation-pct = Lane changes started before they came
words-measure-initial-direction-error-deg-mean = Wrong-way start of a movement
words-measure-reaction-time-left-s-median = Reaction time, targets on the left
words-measure-reaction-time-right-s-median = Reaction time, targets on the right
words-measure-initial-direction-error-left-deg-mean = Wrong-way start, targets on the left
words-measure-initial-direction-error-right-deg-mean = Wrong-way start, targets on the right
words-measure-path-length-ratio-median = Turning beyond what was needed (1 is none)
words-measure-wheel-rom-deg = Wheel turning range
words-measure-shoulder-elevation-rom-deg = Shoulder lifting range
words-measure-elbow-flexion-rom-deg = Elbow bending range
words-measure-trunk-flexion-max-deg = Trunk bending forward, furthest
words-measure-trunk-flexion-mean-deg = Trunk bending forward, on average
words-measure-trunk-lean-max-deg = Trunk leaning sideways, furthest
words-measure-trunk-lean-mean-deg = Trunk leaning sideways, on average
words-measure-trunk-rotation-max-deg = Trunk twisting, furthest
words-measure-trunk-rotation-mean-deg = Trunk twisting, on average
words-measure-trunk-beyond-pct = Time the trunk moved too far
words-measure-trunk-compensated-movements-pct = Turns helped by the trunk
words-measure-trunk-cues = Reminders to sit up
words-measure-pct-in-lane = Time in lane
words-measure-rms-lateral-m = Distance from the lane's centre
words-measure-heading-rms-error-deg = Heading off the road's direction
words-measure-cone-hits = Cones hit
words-measure-completion-time-s = Time to finish
words-measure-tracking-rms-error-deg = Distance from the angle asked
words-measure-dial-rms-error-deg = Dial: distance from the angle asked
words-measure-dial-mean-abs-error-deg = Dial: average distance from the angle asked
words-measure-strength-peak-left-nm = Strength turning left, at its peak
words-measure-strength-sustained-left-nm = Strength turning left, held 1 s
words-measure-strength-peak-right-nm = Strength turning right, at its peak
words-measure-strength-sustained-right-nm = Strength turning right, held 1 s
words-measure-assist-level-mean = Help from the wheel (0 none, 1 full)
words-measure-patient-work-pct = Patient's share of the work
# A measure's name with its unit, as a column header: "Time in lane (%)".
words-name-unit = { $name } ({ $unit })

## How a session ended (the one wording, metrics::words::EndKind)

words-end-complete = Completed
words-end-stopped-by-patient = Stopped early by the patient
words-end-paused-too-long = Stopped early: paused too long
words-end-screen-failed = Stopped early: the screen failed
words-end-wheel-unplugged = Stopped early: wheel unplugged
words-end-arm-sensor-unplugged = Stopped early: arm sensor unplugged
words-end-safety-stop = Stopped early: safety stop (the wheel's force was switched off)
words-end-running = Still running
words-end-unreported = Ended; how was not reported
words-end-other = Stopped early
words-end-recording-stopped = { $end }; the recording stopped early
words-not-in-trends = (not in the trends)

## Kinds of exercise, as in "road sessions"

words-kind-road = road
words-kind-dial = dial
words-kind-strength = strength test
words-kind-haptic-sweep = haptic sweep
words-kind-regimen = regimen
words-kinds-and = { $first } and { $last }
words-regimen = { $count ->
        [one] A regimen of { $count } exercise
       *[other] A regimen of { $count } exercises
    }

## Trends, times, stations

words-trend-better = better
words-trend-worse = worse
words-trend-steady = steady
words-seconds = { $n } s
words-minutes = { $n } min
words-of-prescribed = { $done } of { $prescribed } prescribed
words-station-paired = station paired { $day }

## Exercises by their short names (the regimen's), and a session's exercises in order

words-exercise-straight-road = Straight road
words-exercise-sine-road = Sine road
words-exercise-triangle-road = Triangle road
words-exercise-clothoid-road = Clothoid road
words-exercise-sharp-turns = Sharp turns
words-exercise-s-bend = S-bend
words-exercise-lane-change = Lane change
words-exercise-slalom = Slalom
words-exercise-dial-sine = Dial sine
words-exercise-dial-multi-sine = Dial multi sine
words-exercise-dial-step = Dial step
words-exercise-dial-ramp = Dial ramp
words-exercise-dial-chirp = Dial chirp
words-exercise-strength = Strength
words-exercise-haptic-sweep = Haptic sweep
words-exercises-then = { $first }, then { $next }

## What each measure measures, for the clinician (words-definition-<key>; docs/MEASURES.md)

words-definition-active-s = Time the wheel was moving: the sum of the movements' durations, pauses left out.
words-definition-session-s = Time from the session's start to its end, pauses included.
words-definition-paused-s = Time the session was paused by the patient or for rest.
words-definition-active-pct = Share of the exercise time the wheel was moving.
words-definition-movements = Movements of the wheel: its speed above 5 % of the session's top speed (at least 2.9 °/s), gaps under 0.1 s joined, runs under 0.2 s dropped.
words-definition-discrete-movements = Movements from rest to rest: at least 0.2 s still before and after, at most 5 s long. Only these are scored for smoothness.
words-definition-movements-per-min = Movements per minute of exercise: the dose of practice.
words-definition-reversals-per-min = Changes of the wheel's turning direction by at least 2° per minute of exercise.
words-definition-sparc-median = Spectral arc length of the wheel's speed, median over the movements from rest to rest; none for a continuous task. Closer to 0 is smoother.
words-definition-ldlj-median = Log dimensionless jerk of the wheel's speed, median over the movements from rest to rest; none for a continuous task. Closer to 0 is smoother.
words-definition-movement-peak-speed-deg-s-median = Highest turning speed within a movement, median over the movements.
words-definition-movement-time-s-median = Duration of a movement, from its speed rising above the threshold to falling back, median.
words-definition-speed-peaks-median = Peaks of speed within a movement (at least 10 % of its top speed), median; 1 is a single smooth movement.
words-definition-speed-metric-median = A movement's mean speed over its top speed, median; it rises as movements fill out with recovery.
words-definition-reaction-time-s-median = Time from an unpredictable jump of the target (the dial's) to the wheel starting to move, median.
words-definition-anticipation-pct = Share of lane changes seen ahead whose turn started sooner than 0.1 s after the change: anticipated, not reacted to.
words-definition-initial-direction-error-deg-mean = Whether a movement after a jump of the target starts the wrong way: 0° the right way, 180° the wrong way, mean.
words-definition-reaction-time-left-s-median = Reaction time to unpredictable jumps of the target to the left, median.
words-definition-reaction-time-right-s-median = Reaction time to unpredictable jumps of the target to the right, median.
words-definition-initial-direction-error-left-deg-mean = Wrong-way starts towards targets on the left, mean (0° the right way, 180° the wrong way).
words-definition-initial-direction-error-right-deg-mean = Wrong-way starts towards targets on the right, mean (0° the right way, 180° the wrong way).
words-definition-path-length-ratio-median = Turning travelled after a jump of the target over the turning needed to reach it, median; 1 is direct.
words-definition-wheel-rom-deg = Largest minus smallest wheel angle over the exercise.
words-definition-shoulder-elevation-rom-deg = Largest minus smallest shoulder lifting angle while the arm sensors tracked.
words-definition-elbow-flexion-rom-deg = Largest minus smallest elbow bending angle while the arm sensors tracked.
words-definition-trunk-flexion-max-deg = Largest forward bend of the trunk from its start posture, from the sternum sensor.
words-definition-trunk-flexion-mean-deg = Mean forward bend of the trunk from its start posture, from the sternum sensor.
words-definition-trunk-lean-max-deg = Largest sideways lean of the trunk from its start posture, from the sternum sensor.
words-definition-trunk-lean-mean-deg = Mean sideways lean of the trunk from its start posture, from the sternum sensor.
words-definition-trunk-rotation-max-deg = Largest twist of the trunk from its start posture, from the sternum sensor.
words-definition-trunk-rotation-mean-deg = Mean twist of the trunk from its start posture, from the sternum sensor.
words-definition-trunk-beyond-pct = Share of the exercise time with any trunk angle beyond the station's threshold.
words-definition-trunk-compensated-movements-pct = Share of wheel movements during which the trunk moved beyond the threshold.
words-definition-trunk-cues = Times the station asked the patient to sit up straight: the trunk stayed beyond the therapist's cue threshold for a second; at most one in 20 s.
words-definition-pct-in-lane = Share of driving time with the car inside its lane.
words-definition-rms-lateral-m = Root mean square distance of the car from the lane's centre.
words-definition-heading-rms-error-deg = Root mean square angle between the car's heading and the road's direction.
words-definition-cone-hits = Cones the car touched.
words-definition-completion-time-s = Time to reach the end of the course.
words-definition-tracking-rms-error-deg = Root mean square difference between the wheel angle asked and the wheel's angle.
words-definition-dial-rms-error-deg = Root mean square difference between the dial's target angle and the wheel's needle.
words-definition-dial-mean-abs-error-deg = Mean absolute difference between the dial's target angle and the wheel's needle.
words-definition-strength-peak-left-nm = Highest torque turning left against the wheel's spring, the wheel held nearly still.
words-definition-strength-sustained-left-nm = Highest torque turning left held for at least 1 s.
words-definition-strength-peak-right-nm = Highest torque turning right against the wheel's spring, the wheel held nearly still.
words-definition-strength-sustained-right-nm = Highest torque turning right held for at least 1 s.
words-definition-assist-level-mean = How much the wheel helped, mean over the exercise: 0 no help, 1 full help.
words-definition-patient-work-pct = Patient's share of the mechanical work done on the wheel (the patient's and the wheel's help together).
