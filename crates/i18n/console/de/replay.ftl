# Die Wiedergabe einer gespeicherten Sitzung und die Liste der Sitzungen.

replay-loading = Die Aufzeichnung wird geladen …
replay-none-sent = der Hub hat keine Wiedergabe gesendet
replay-heading = Wiedergabe der Sitzung vom { $when } ({ $exercise })
replay-unknown-time = unbekannten Zeitpunkt
replay-receiving = Die Aufzeichnung wird empfangen …
replay-playback = Wiedergabe
replay-play = Abspielen
replay-pause = Pause
replay-position = Position
replay-speed = Tempo
replay-marks-label = Wo jede Übung endet und die nächste folgt
replay-car-heading = Auto von oben (30 s vor dem Cursor)
replay-car-canvas = Der Weg des Autos von oben
replay-chart-tracking = Seitliche Abweichung und Zeigerfehler
replay-axis-tracking = Abweichung (m) / Fehler (°)
replay-series-dial-error = Folgefehler am Zeiger (°)
replay-chart-torque = Drehmoment am Lenkrad
replay-series-motor = Motordrehmoment (N·m)
replay-series-assist = Unterstützungsdrehmoment (N·m)
replay-series-ceiling = Drehmomentgrenze (N·m)
replay-mark = { $named ->
    [yes] { $seconds } s: Ende von Übung { $ended }, dann Übung { $next } ({ $name })
   *[no] { $seconds } s: Ende von Übung { $ended }, dann Übung { $next }
}
replay-cut-short = die Aufzeichnung kam vor ihrem Ende nicht mehr an
replay-frames = { $frames } Bilder mit { $rate } pro Sekunde.
replay-stopped = Die Wiedergabe wurde abgebrochen: { $reason }

replay-list-heading = Eine Sitzung wiedergeben
replay-list-running = Läuft noch: Die Aufzeichnung kommt nach dem Ende der Sitzung.
replay-list-not-arrived = Die Aufzeichnung ist noch nicht angekommen. Die Station lädt sie nach der Sitzung hoch, sobald sie den Hub erreicht.
replay-list-arriving = Die Aufzeichnung kommt gerade an: bisher { $percent } %. Die Wiedergabe öffnet sich, sobald alles da ist.
replay-list-stalled = Die Aufzeichnung kommt nicht mehr an: { $percent } % sind da, seit { $at } nichts mehr. Die Station schickt den Rest, sobald sie wieder online ist.
replay-list-ready = Aufzeichnung bereit: über Datum und Uhrzeit öffnen.
replay-list-note = { $count ->
    [one] { $ready } von 1 Sitzung kann aus der hochgeladenen Aufzeichnung wiedergegeben werden: Arm, Auto und Diagramme wie damals, mit Abspielen, Pause und Springen.
   *[other] { $ready } von { $count } Sitzungen können aus der hochgeladenen Aufzeichnung wiedergegeben werden: Arm, Auto und Diagramme wie damals, mit Abspielen, Pause und Springen.
}
replay-list-none = Noch keine Sitzung: Eine Sitzung kann wiedergegeben werden, sobald die Station ihre Aufzeichnung hochgeladen hat.
replay-list-caption = Die Sitzungen des Patienten, neueste zuerst
replay-list-col-started = Beginn
replay-list-col-exercise = Übung
replay-list-col-recording = Aufzeichnung
