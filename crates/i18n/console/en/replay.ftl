# The replay of a stored session and the list of sessions to replay (crates/hub/console/
# replay.js, replays.js). Panel headings shared with the live view come from live.ftl.

replay-loading = Loading the recording…
replay-none-sent = the hub sent no replay
replay-heading = Replay of the session of { $when } ({ $exercise })
replay-unknown-time = an unknown time
replay-receiving = Receiving the recording…
replay-playback = Playback
replay-play = Play
replay-pause = Pause
replay-position = Position
replay-speed = Speed
replay-marks-label = Where each exercise ends and the next follows
replay-car-heading = Car from above (30 s before the cursor)
replay-car-canvas = The car's path from above
replay-chart-tracking = Lateral deviation and dial error
replay-axis-tracking = deviation (m) / error (°)
replay-series-dial-error = dial tracking error (°)
replay-chart-torque = Torque at the wheel
replay-series-motor = motor torque (N·m)
replay-series-assist = assistance torque (N·m)
replay-series-ceiling = torque ceiling (N·m)
replay-mark = { $named ->
    [yes] { $seconds } s: end of exercise { $ended }, then exercise { $next } ({ $name })
   *[no] { $seconds } s: end of exercise { $ended }, then exercise { $next }
}
replay-cut-short = the recording stopped arriving before its end
replay-frames = { $frames } frames at { $rate } per second.
replay-stopped = The replay stopped: { $reason }

replay-list-heading = Replay a session
replay-list-running = Still running: its recording arrives after the session ends.
replay-list-not-arrived = Its recording has not arrived yet. The station uploads it after the session, when it can reach the hub.
replay-list-arriving = Its recording is arriving: { $percent }% so far. The replay opens once all of it is here.
replay-list-stalled = Its recording stopped arriving at { $percent }%: nothing since { $at }. The station sends the rest when it is next online.
replay-list-ready = Recording ready: open it by its date and time.
replay-list-note = { $count ->
    [one] { $ready } of 1 session can be replayed from the recording the station uploaded: the arm, the car and the charts as they were, with play, pause and seek.
   *[other] { $ready } of { $count } sessions can be replayed from the recording the station uploaded: the arm, the car and the charts as they were, with play, pause and seek.
}
replay-list-none = No session yet: a session can be replayed once the station has uploaded its recording.
replay-list-caption = The patient's sessions, newest first
replay-list-col-started = Started
replay-list-col-exercise = Exercise
replay-list-col-recording = Recording
