# The therapist's messages to a patient (crates/hub/console/messages.js).

messages-empty = The message is empty.
messages-too-long = The message is too long: { $chars } characters, at most { $max }.
messages-control = The message has a line break or another control character: write it on one line.
messages-sent-at = sent { $when }
messages-not-seen = not seen yet
messages-seen-at = seen { $when }
messages-none = No messages yet.
messages-count = { $chars } of { $max } characters
messages-label = A message for the patient, shown in large type when their next session starts
messages-send = Send the message
messages-refresh = Refresh
messages-sent = Sent: the patient sees it when their next session starts.
messages-heading = Messages to the patient
