# The session's cards the wheel answers (crates/station/src/session/wheel_cards.rs). Plain
# words, at most 12 words a sentence. Press = a short press of a wheel button; hold = keep
# it pressed (1.5 s).

controls-paused-title = Paused
controls-paused-go-on = Go on
controls-paused-rest = Rest
controls-paused-end = End
controls-paused-how = Turn to choose. Press a button.
controls-paused-keys = Keyboard: Space goes on, R rests, Esc ends.
controls-end-title = End now?
controls-end-press = Press the button: end.
controls-end-hold = Hold the button: go on.
controls-end-keys = Keyboard: Esc ends, Space goes on.
controls-ready-title = Ready?
controls-ready-press = Press a wheel button to start.
controls-ready-countdown = { $seconds ->
    [one] Starts in 1 second.
   *[other] Starts in { $seconds } seconds.
}
controls-unplugged-title = Plug the wheel back in
controls-unplugged-waits = The exercise waits for you.
controls-unplugged-left = { $seconds ->
    [one] The session ends in 1 second.
   *[other] The session ends in { $seconds } seconds.
}
controls-unplugged-keys = The wheel's cable goes into the wheel and the computer.
controls-arm-unplugged-title = Plug the arm sensor back in
controls-arm-unplugged-keys = The sensor on your arm has a cable to the computer.
controls-start = Press a wheel button to start.
controls-go-on-now = Press a wheel button to go on now.
