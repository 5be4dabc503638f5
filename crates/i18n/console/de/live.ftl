# Die Live-Ansicht einer laufenden Sitzung.

live-waiting = Warten auf den Beginn einer Sitzung …
live-arm-heading = Arm und Lenkrad
live-arm-canvas = 3-D-Ansicht von Arm und Lenkrad des Patienten; zum Drehen ziehen oder die Pfeiltasten nutzen
live-tracking = Spurführung
live-torque-heading = Drehmoment und Unterstützung
live-joints-heading = Gelenkwinkel
live-scene-road = Straße und Spur um das Auto
live-scene-dial = Zeiger: Ziel und Lenkrad
live-scene-strength = Krafttest: beide Seiten
live-tracking-road = Seitliche Abweichung
live-tracking-dial = Zeigerziel und Lenkradwinkel
live-tracking-strength = Kraft: der Druck gegen die Grenze
live-axis-time = Sitzungszeit (s)
live-axis-deviation = Abweichung (m)
live-axis-angle = Winkel (°)
live-axis-torque = Drehmoment (N·m)
live-series-deviation = seitliche Abweichung (m)
live-series-wheel = Lenkradwinkel (°)
live-series-target = Ziel (°)
live-series-push = Druck jetzt (N·m)
live-series-peak = höchster Druck, diese Seite (N·m)
live-series-ceiling = Grenze (N·m)
live-series-motor = Motor (N·m)
live-series-assist = Unterstützung (N·m)
live-series-shoulder = Schulterelevation (°)
live-series-elbow = Ellenbogenflexion (°)

live-just-now = soeben
live-status-session = Sitzung vom { $when }
live-status-seconds = { $seconds } s
live-state-running = läuft
live-state-paused = pausiert
live-state-fault = Sicherheitsfehler: Drehmoment wird auf null zurückgefahren
live-status-torque = Drehmoment { $nm } von { $ceiling } N·m Grenze
live-status-lane = in der Spur { $pct } %
live-status-push = Druck { $nm } N·m
live-status-dial-off = { $degrees }° neben dem Zeigerziel
live-status-delay = Verzögerung { $seconds } s
live-recording-stopped = Aufzeichnung bei { $seconds } s gestoppt
live-no-arm-sensors = In dieser Sitzung keine Armsensoren.
live-angles = Schulterelevation { $shoulder }°, Ellenbogenflexion { $elbow }°, Unterarmpronation { $forearm }°
live-delayed-silent = verzögert: seit { $seconds } s nichts von der Station (ihre Verbindung zu Hause ist vielleicht unterbrochen); die Ansicht zeigt die zuletzt eingetroffenen Daten
live-delayed-late = verzögert: diese Daten kamen { $seconds } s zu spät an (die Station holt nach einer Unterbrechung ihrer Verbindung auf)
live-lagged = { $count ->
    [one] Die Ansicht ist zurückgefallen und hat eine Zusammenfassung übersprungen.
   *[other] Die Ansicht ist zurückgefallen und hat { $count } Zusammenfassungen übersprungen.
}
live-stopped-login-ended = Live-Ansicht beendet: Ihre Anmeldung ist abgelaufen. Melden Sie sich erneut an, um zuzusehen.
live-stopped-login-unchecked = Live-Ansicht beendet: Der Hub kann Ihre Anmeldung gerade nicht prüfen. Bitte gleich noch einmal versuchen.
live-stopped-not-your-patient = Live-Ansicht beendet: Diese Person ist nicht mehr in Ihrer Betreuung.
live-ended-unknown = beendet (wie, ist nicht erfasst)
live-ended-complete = beendet: vollständig, wie verordnet
live-path-note = Der Weg des Autos in den letzten { $seconds } s

live-road-not-sent = Diese Station sendet keine Straße: der Weg des Autos in den letzten { $seconds } s
live-road-note = Spur { $lane } m breit, { $behind } m hinter dem Auto bis { $ahead } m voraus (Maßstab { $bar } m); blau: sein Weg.
live-road-car-side = { $side ->
    [left] Das Auto ist { $metres } m links der Mitte.
    [right] Das Auto ist { $metres } m rechts der Mitte.
   *[centre] Das Auto ist in der Spurmitte.
}
live-path-none = Eine Zeigerübung: kein Auto auf einer Straße.
live-path-across = { $what } ({ $metres } m Ausschnitt).
live-dial-waiting = Die Zeigerübung: Warten auf das Lenkrad.
live-dial-note = Ziel { $target }° (orange, gestrichelt), Lenkrad des Patienten { $wheel }° (blau): { $side ->
    [left] { $off }° links vom Ziel.
    [right] { $off }° rechts vom Ziel.
   *[on] auf dem Ziel.
}

live-strength-left = Drücken nach links
live-strength-right = Drücken nach rechts
live-strength-now-label = { $side } (jetzt)
live-strength-resting = Krafttest: Pause zwischen den Seiten oder beendet. Die Grenze liegt bei { $ceiling }.
live-strength-note = Krafttest, { $side ->
    [left] Drücken nach links
   *[right] Drücken nach rechts
}: jetzt { $now }{ $share }, Höchstwert bisher { $peak }, gegen die Grenze von { $ceiling } (blau: jetzt; orange Marke: Höchstwert; grüne Linie: Grenze).
live-strength-share = ({ $pct } % der Grenze)
live-strength-caption = Die Zahlen des Krafttests
live-strength-col-side = Seite
live-strength-col-now = Druck jetzt
live-strength-col-peak = Höchstwert bisher
live-strength-col-ceiling = Grenze
live-strength-not-yet = noch nicht
