# Charts of a measure session by session and their numbers (crates/hub/console/sessionchart.js).

sessionchart-ended-early = { $series }, ended early
sessionchart-axis-session = session (date and time)
sessionchart-counted = yes
sessionchart-counted-early = yes (ended early, included)
sessionchart-not-counted-early = no: ended early
sessionchart-not-counted-running = no: still running
sessionchart-numbers = Numbers of this chart ({ $title })
sessionchart-caption = { $title }, a row a session, oldest first
sessionchart-col-session = Session
sessionchart-col-counted = Counted
