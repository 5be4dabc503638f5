# One session's results exercise by exercise (crates/hub/console/exercises.js).

exercises-ended = Ended
exercises-running = Still running
exercises-heading = Session of { $when }, exercise by exercise
exercises-back = Back to the progress
exercises-none = No results per exercise: the station that ran this session was older than them, or the session did not end in order.
exercises-column = { $n }. { $name }
exercises-time-cell = { $active } of { $prescribed }
exercises-caption = Each exercise's own results; the session's totals are in the progress view.
exercises-col-result = Result
exercises-time-row = Time: active of prescribed (s)
exercises-sweep-spring = Haptic sweep: the spring stiffness of this level
exercises-sweep-damper = Haptic sweep: the damping of this level
exercises-sweep-inertia = Haptic sweep: the added weight (inertia) of this level
exercises-sweep-frequency = Haptic sweep: how fast the dial moves (frequency) at this level
