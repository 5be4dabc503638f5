# The live view of a running session (crates/hub/console/live.js, live-road.js,
# live-strength.js).

live-waiting = Waiting for a session to start…
live-arm-heading = Arm and wheel
live-arm-canvas = 3-D view of the patient's arm and the wheel; drag or use the arrow keys to turn it
live-tracking = Tracking
live-torque-heading = Torque and assistance
live-joints-heading = Joint angles
live-scene-road = Road and lane around the car
live-scene-dial = Dial: target and wheel
live-scene-strength = Strength test: each side
live-tracking-road = Lateral deviation
live-tracking-dial = Dial target and wheel angle
live-tracking-strength = Strength: the push against the ceiling
live-axis-time = session time (s)
live-axis-deviation = deviation (m)
live-axis-angle = angle (°)
live-axis-torque = torque (N·m)
live-series-deviation = lateral deviation (m)
live-series-wheel = wheel angle (°)
live-series-target = target (°)
live-series-push = push now (N·m)
live-series-peak = highest push, this side (N·m)
live-series-ceiling = ceiling (N·m)
live-series-motor = motor (N·m)
live-series-assist = assistance (N·m)
live-series-shoulder = shoulder elevation (°)
live-series-elbow = elbow flexion (°)

live-just-now = just now
live-status-session = Session of { $when }
live-status-seconds = { $seconds } s
live-state-running = running
live-state-paused = paused
live-state-fault = safety fault: torque fading to zero
live-status-torque = torque { $nm } of { $ceiling } N·m ceiling
live-status-lane = in lane { $pct } %
live-status-push = push { $nm } N·m
live-status-dial-off = off the dial's target by { $degrees }°
live-status-delay = delay { $seconds } s
live-recording-stopped = recording stopped at { $seconds } s
live-no-arm-sensors = No arm sensors in this session.
live-angles = Shoulder elevation { $shoulder }°, elbow flexion { $elbow }°, forearm pronation { $forearm }°
live-delayed-silent = delayed: nothing from the station for { $seconds } s (its home connection may be down); the view shows the last data that arrived
live-delayed-late = delayed: this data reached the hub { $seconds } s late (the station is catching up after a break in its connection)
live-lagged = { $count ->
    [one] The view fell behind and skipped one summary.
   *[other] The view fell behind and skipped { $count } summaries.
}
live-stopped-login-ended = Live view stopped: your login ended. Log in again to watch.
live-stopped-login-unchecked = Live view stopped: the hub cannot check your login now. Try again soon.
live-stopped-not-your-patient = Live view stopped: this patient is no longer in your care.
live-ended-unknown = ended (how is not recorded)
live-ended-complete = ended: complete, as prescribed
live-path-note = The car's path over the last { $seconds } s

live-road-not-sent = Road not sent by this station: the car's path over the last { $seconds } s
live-road-note = Lane { $lane } m wide, { $behind } m behind the car to { $ahead } m ahead (scale bar { $bar } m); blue: its path.
live-road-car-side = { $side ->
    [left] The car is { $metres } m left of centre.
    [right] The car is { $metres } m right of centre.
   *[centre] The car is on the lane centre.
}
live-path-none = A dial exercise: no car on a road.
live-path-across = { $what } ({ $metres } m across).
live-dial-waiting = The dial task: waiting for the wheel.
live-dial-note = Target { $target }° (orange, dashed), the patient's wheel { $wheel }° (blue): { $side ->
    [left] { $off }° to the left of the target.
    [right] { $off }° to the right of the target.
   *[on] on the target.
}

live-strength-left = Pushing left
live-strength-right = Pushing right
live-strength-now-label = { $side } (now)
live-strength-resting = Strength test: resting between the sides, or done. The ceiling is { $ceiling }.
live-strength-note = Strength test, { $side ->
    [left] pushing left
   *[right] pushing right
}: { $now } now{ $share }, peak { $peak } so far, against the { $ceiling } ceiling (blue: now; orange mark: peak; green line: ceiling).
live-strength-share = ({ $pct } % of the ceiling)
live-strength-caption = The strength test's numbers
live-strength-col-side = Side
live-strength-col-now = Push now
live-strength-col-peak = Peak so far
live-strength-col-ceiling = Ceiling
live-strength-not-yet = not yet
