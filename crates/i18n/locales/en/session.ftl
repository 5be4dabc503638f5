# The session's screens: exercise names, instructions, the cards before and between
# exercises, the rest, the pause, the question before ending, the display during an
# exercise (HUD), the page when a session cannot start.
# Rules: every sentence at most 12 words, everyday words, one idea per page.

## What each exercise is called, by what the patient does.
exercise-straight-road = Straight road
exercise-sine-road = Winding road
exercise-triangle-road = Zigzag road
exercise-clothoid-road = Bends that get tighter
exercise-sharp-turns = Sharp bends
exercise-s-bend = Double bend
exercise-lane-change = Change lanes
exercise-slalom = Drive around the cones
exercise-dial-sine = Follow the needle
exercise-dial-multi-sine = Follow the wandering needle
exercise-dial-step = Follow the jumping needle
exercise-dial-ramp = Follow the slow needle
exercise-dial-chirp = Follow the needle as it speeds up
exercise-strength = Push the wheel
exercise-haptic-sweep = Feel the wheel
exercise-assessment-range = Check: how far you can turn
exercise-assessment-tracking-slow = Check: follow the slow needle
exercise-assessment-tracking-medium = Check: follow the needle
exercise-assessment-tracking-fast = Check: follow the fast needle
exercise-assessment-steps = Check: follow the jumping needle
exercise-assessment-strength = Check: push the wheel
exercise-other = Exercise

## What each exercise asks, in one or two short sentences.
instruction-dial = Turn the wheel. Keep the black needle on the red one.
instruction-strength = Push the wheel left, then right. Push as hard as is comfortable.
instruction-slalom = Steer around the cones. Stay on the road.
instruction-lane-change = When the road moves over, change lanes.
instruction-straight-road = Keep the car in the middle of the lane.
instruction-bends = Steer through the bends. Stay in your lane.
instruction-road = Follow the road. Stay in your lane.
instruction-pedals = Your feet set the speed. Right pedal to go, left to slow.
instruction-assessment-range = Turn the wheel as far as you can, left, then right. Hold it there.
instruction-assessment-tracking = This is a check. The wheel will not help. Keep the black needle on the red one.
instruction-assessment-steps = The red needle jumps. Follow it as fast as you can.

## The card before an exercise and between exercises.
card-get-ready = Get ready
card-rest-then-back = Rest, then back to
card-rest-then-next = Rest. Next:
card-next = Next
card-exercise-of = Exercise { $number } of { $total }: { $name }
card-start-key = Space or a wheel button: start
card-go-on-now-key = Space or a wheel button: go on now
card-message-from-therapist = A message from your therapist:

## The pause and the question before ending early.
pause-title = Paused
end-confirm-title = End the session?
end-confirm-yes = Press Esc again to end.
end-confirm-no = Press Space to go on.

## The simple cards of the window (when no exercise card is shown).
card-press-space-to-start = Press Space to start.
card-all-done = All done

## Setting up the arm sensors at the start.
setup-hold-still = Hold the wheel still
setup-hold-still-how = Rest both hands on the wheel. Relax.
setup-turn-slowly = Turn the wheel slowly
setup-turn-slowly-how = Left and right, as far as is comfortable.
setup-thank-you = Thank you
setup-getting-ready = Getting the arm sensors ready…
setup-seconds-left = { $seconds } s

## The display during an exercise.
hud-time-left = Time left
hud-in-lane = In the lane: { $percent } %
hud-middle-close = Close to the middle
hud-middle-off = A little off the middle
hud-middle-far = Far from the middle
hud-needle-close = Right on the red needle
hud-needle-near = Near the red needle
hud-needle-behind = Try to keep up
hud-push-left = Push the wheel left, as hard as is comfortable.
hud-push-right = Push the wheel right, as hard as is comfortable.
hud-let-go = Let go of the wheel and rest.
hud-speed = { $kmh } km/h
hud-help = Help: { $percent } %
hud-press-pedal = Press the right pedal to drive.
# The gentle cue when the trunk stays leant past the therapist's threshold (shown and
# spoken during an exercise, at most once in 20 s).
hud-sit-up = Sit back up straight.
hud-wheel-working = Wheel: working
hud-wheel-resting = Wheel: resting
hud-wheel-stopping = Wheel: stopping
hud-wheel-problem = Wheel: not working, no force
hud-wheel-simulated = Wheel: practice
hud-gentle-force = Gentle force only
hud-arm-working = Arm sensors: working
hud-arm-setting-up = Arm sensors: getting ready
hud-arm-not-working = Arm sensors: not working
hud-arm-not-answering = Arm sensors: no signal
hud-arm-simulated = Arm sensors: practice
hud-your-arm = Your arm
hud-your-wheel = Your wheel
hud-target = Target
hud-your-arm-measured = Your arm, measured

## The page when a session cannot start (no wheel, …).
cannot-start-title = The session cannot start yet
cannot-start-then = Then start telerehab again.
cannot-start-close-key = Press any key to close.

## When the window restarted during an exercise
pause-screen-restarted = The screen restarted, so the exercise paused.
