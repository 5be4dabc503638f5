# Measures, end reasons, exercise kinds, trends and times in a clinician's words. The measure
# keys, units, decimals and ranges are the one table of crates/metrics/src/words.rs; only the
# plain names are here (words-measure-<key>, words-end-<kind>).

## Measures' plain names

words-measure-active-s = Active time
words-measure-session-s = Session length
words-measure-paused-s = Time paused
words-measure-active-pct = Time moving
words-measure-movements = Movements
words-measure-movements-per-min = Movements a minute
words-measure-reversals-per-min = Changes of steering direction a minute
words-measure-sparc-median = Smoothness (closer to 0 is smoother)
words-measure-ldlj-median = Smoothness of acceleration (closer to 0 is smoother)
words-measure-movement-peak-speed-deg-s-median = Top turning speed of a movement
words-measure-movement-time-s-median = Length of a movement
words-measure-speed-peaks-median = Stops and starts in a movement
words-measure-speed-metric-median = Evenness of speed (1 is even)
words-measure-reaction-time-s-median = Reaction time
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
