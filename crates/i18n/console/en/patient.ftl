# The patient's station settings in the prescribe form (the regimen's [patient] table;
# crates/hub/console/patient-settings.js).

patient-legend = The patient's station
patient-intro = These settings travel with the prescription: the station uses them from its next session.
patient-language-label = Language of the station's screens and voice
patient-language-station = As chosen on the station
patient-side-legend = Neglected side
patient-side-none = None
patient-side-none-note = The screens are laid out as usual.
patient-side-left = Left
patient-side-left-note = Nothing essential in the left part of the screen. Before each exercise, a pulsing orange bar on the left edge and a spoken "Look over here" from the left.
patient-side-right = Right
patient-side-right-note = Nothing essential in the right part of the screen. Before each exercise, a pulsing orange bar on the right edge and a spoken "Look over here" from the right.
patient-speech-label = Read each page's main sentence aloud
patient-volume-label = Volume of the voice, %
patient-countdown-label = After a rest, start the next exercise after this countdown, seconds
patient-countdown-wait = wait for the patient
patient-saved-words = On the station: { $language }; neglected side: { $side ->
    [left] left
    [right] right
   *[none] none
}; speech { $speech ->
    [off] off
   *[on] on, volume { $volume } %
}; after a rest: { $countdown ->
    [count] the next exercise starts after { $seconds } s
   *[wait] the station waits for the patient
}.
