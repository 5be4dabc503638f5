# Die Karten der Sitzung, die das Lenkrad beantwortet. Drücken = kurz; halten = 1,5 Sekunden.

controls-paused-title = Pause
controls-paused-go-on = Weiter
controls-paused-rest = Ausruhen
controls-paused-end = Beenden
controls-paused-how = Drehen Sie zum Wählen. Drücken Sie dann eine Taste.
controls-paused-keys = Tastatur: Leertaste weiter, R ausruhen, Esc beenden.
controls-end-title = Jetzt beenden?
controls-end-press = Taste drücken: beenden.
controls-end-hold = Taste halten: weitermachen.
controls-end-keys = Tastatur: Esc beendet, Leertaste macht weiter.
controls-ready-title = Bereit?
controls-ready-press = Drücken Sie eine Taste am Lenkrad. Dann geht es los.
controls-ready-countdown = { $seconds ->
    [one] Es geht in 1 Sekunde los.
   *[other] Es geht in { $seconds } Sekunden los.
}
controls-unplugged-title = Stecken Sie das Lenkrad wieder ein
controls-unplugged-waits = Die Übung wartet auf Sie.
controls-unplugged-left = { $seconds ->
    [one] Die Sitzung endet in 1 Sekunde.
   *[other] Die Sitzung endet in { $seconds } Sekunden.
}
controls-unplugged-keys = Das Kabel verbindet Lenkrad und Computer.
controls-arm-unplugged-title = Stecken Sie den Armsensor wieder ein
controls-arm-unplugged-keys = Der Sensor an Ihrem Arm hat ein Kabel zum Computer.
controls-start = Drücken Sie eine Taste am Lenkrad. Dann geht es los.
controls-go-on-now = Drücken Sie eine Taste am Lenkrad. Dann geht es gleich weiter.
