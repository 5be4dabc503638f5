# The end of a session: the results, three questions, and the page after strong pain.
# Plain words, short sentences (at most 12 words). The station speaks each question.
checkin-results-title = Well done! You finished.
checkin-results-stopped-title = The session stopped early.
checkin-results-wheel-stopped = The wheel stopped working. Its force is off. Please tell the clinic.
checkin-results-exercised = You exercised for { $time }.
checkin-results-lane = You stayed in your lane { $percent } % of the time.
checkin-results-dial = Your pointer stayed { $degrees }° from the target, on average.
checkin-results-better-lane = More time in your lane: { $percent } % (before: { $was } %)
checkin-results-better-dial = Closer on the dial: { $degrees }° (before: { $was }°)
checkin-results-better-time = Longer exercise: { $time } (before: { $was })
checkin-results-first = Next time you will see how you compare.
checkin-results-same = About the same as last time. Well done!
checkin-results-better = Better than last time:
checkin-seconds = { $seconds ->
    [one] { $seconds } second
   *[other] { $seconds } seconds
}
# The pain scale: six faces, from no pain to the worst pain.
checkin-pain-question = How much pain do you have now?
checkin-pain-0 = No pain
checkin-pain-1 = A little pain
checkin-pain-2 = Some pain
checkin-pain-3 = A lot of pain
checkin-pain-4 = Very bad pain
checkin-pain-5 = Worst pain
# Effort: the words of Borg's CR10 scale at 0, 1, 2, 3, 4, 5, 7 and 10.
checkin-effort-question = How hard was the exercise for you?
checkin-effort-0 = Nothing at all
checkin-effort-1 = Very weak
checkin-effort-2 = Weak
checkin-effort-3 = Moderate
checkin-effort-4 = Somewhat strong
checkin-effort-5 = Strong
checkin-effort-7 = Very strong
checkin-effort-10 = Extremely strong
checkin-difficulty-question = How was today's exercise?
checkin-difficulty-too-easy = Too easy
checkin-difficulty-just-right = Just right
checkin-difficulty-too-hard = Too hard
checkin-chosen-score = { $value } of 10: { $words }
checkin-choose-first = Turn the wheel to choose an answer.
checkin-key-turn = Turn the wheel: choose
checkin-key-press = Press: OK
checkin-key-hold = Hold: skip
checkin-key-keyboard = Keys: left and right choose, Enter OK, Esc skip
checkin-key-start = Press: three short questions
checkin-key-close = Press: close
checkin-key-close-esc = Esc: close
checkin-thanks-title = Thank you!
checkin-thanks-text = Your therapist will see your answers.
checkin-thanks-bye = See you next time.
# After pain at or over the clinic's limit: never the ordinary thanks.
checkin-stop-title = Please stop and rest.
checkin-stop-rest = Rest your arm now.
checkin-stop-no-more = Do not exercise any more today.
checkin-stop-call = Please call your clinic: { $phone }
checkin-stop-call-clinic = Please call your clinic today.
checkin-stop-told = Your therapist will hear about your pain.
# Today's page after such a pain, until the therapist says the patient may go on.
checkin-rest-today-title = Rest today
checkin-rest-today-pain = You had a lot of pain today.
checkin-rest-today-no-exercise = Please do not exercise today.
checkin-rest-today-wait = Your therapist can let you exercise again.
