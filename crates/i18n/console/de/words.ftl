# Messgrößen, Beendigungsgründe, Übungsarten, Trends und Zeiten in der Sprache der Klinik.
# Schlüssel, Einheiten, Nachkommastellen und Bereiche stehen allein in
# crates/metrics/src/words.rs; hier nur die Namen.

## Namen der Messgrößen

words-measure-active-s = Aktive Zeit
words-measure-session-s = Sitzungsdauer
words-measure-paused-s = Pausenzeit
words-measure-active-pct = Zeit in Bewegung
words-measure-movements = Bewegungen
words-measure-movements-per-min = Bewegungen pro Minute
words-measure-reversals-per-min = Lenkrichtungswechsel pro Minute
words-measure-sparc-median = Flüssigkeit (näher an 0 ist flüssiger)
words-measure-ldlj-median = Flüssigkeit der Beschleunigung (näher an 0 ist flüssiger)
words-measure-movement-peak-speed-deg-s-median = Höchste Drehgeschwindigkeit einer Bewegung
words-measure-movement-time-s-median = Dauer einer Bewegung
words-measure-speed-peaks-median = Stopps und Anläufe in einer Bewegung
words-measure-speed-metric-median = Gleichmäßigkeit der Geschwindigkeit (1 ist gleichmäßig)
words-measure-reaction-time-s-median = Reaktionszeit
words-measure-initial-direction-error-deg-mean = Start in die falsche Richtung
words-measure-reaction-time-left-s-median = Reaktionszeit, Ziele links
words-measure-reaction-time-right-s-median = Reaktionszeit, Ziele rechts
words-measure-initial-direction-error-left-deg-mean = Start in die falsche Richtung, Ziele links
words-measure-initial-direction-error-right-deg-mean = Start in die falsche Richtung, Ziele rechts
words-measure-path-length-ratio-median = Drehung über das Nötige hinaus (1 ist keine)
words-measure-wheel-rom-deg = Drehbereich des Lenkrads
words-measure-shoulder-elevation-rom-deg = Hebebereich der Schulter
words-measure-elbow-flexion-rom-deg = Beugebereich des Ellenbogens
words-measure-trunk-flexion-max-deg = Rumpf nach vorn gebeugt, am weitesten
words-measure-trunk-flexion-mean-deg = Rumpf nach vorn gebeugt, im Mittel
words-measure-trunk-lean-max-deg = Rumpf seitlich geneigt, am weitesten
words-measure-trunk-lean-mean-deg = Rumpf seitlich geneigt, im Mittel
words-measure-trunk-rotation-max-deg = Rumpf gedreht, am weitesten
words-measure-trunk-rotation-mean-deg = Rumpf gedreht, im Mittel
words-measure-trunk-beyond-pct = Zeit mit zu viel Rumpfbewegung
words-measure-trunk-compensated-movements-pct = Drehungen mit Hilfe des Rumpfes
words-measure-pct-in-lane = Zeit in der Spur
words-measure-rms-lateral-m = Abstand zur Spurmitte
words-measure-heading-rms-error-deg = Abweichung von der Straßenrichtung
words-measure-cone-hits = Getroffene Hütchen
words-measure-completion-time-s = Zeit bis zum Ziel
words-measure-tracking-rms-error-deg = Abstand zum geforderten Winkel
words-measure-dial-rms-error-deg = Drehscheibe: Abstand zum geforderten Winkel
words-measure-dial-mean-abs-error-deg = Drehscheibe: mittlerer Abstand zum geforderten Winkel
words-measure-strength-peak-left-nm = Kraft beim Drehen nach links, Spitze
words-measure-strength-sustained-left-nm = Kraft beim Drehen nach links, 1 s gehalten
words-measure-strength-peak-right-nm = Kraft beim Drehen nach rechts, Spitze
words-measure-strength-sustained-right-nm = Kraft beim Drehen nach rechts, 1 s gehalten
words-measure-assist-level-mean = Hilfe durch das Lenkrad (0 keine, 1 volle)
words-measure-patient-work-pct = Anteil des Patienten an der Arbeit
words-name-unit = { $name } ({ $unit })

## Wie eine Sitzung endete

words-end-complete = Abgeschlossen
words-end-stopped-by-patient = Vom Patienten vorzeitig beendet
words-end-paused-too-long = Vorzeitig beendet: zu lange pausiert
words-end-screen-failed = Vorzeitig beendet: Bildschirm ausgefallen
words-end-wheel-unplugged = Vorzeitig beendet: Lenkrad getrennt
words-end-arm-sensor-unplugged = Vorzeitig beendet: Armsensor getrennt
words-end-safety-stop = Vorzeitig beendet: Sicherheitsstopp (die Kraft des Lenkrads wurde abgeschaltet)
words-end-running = Läuft noch
words-end-unreported = Beendet; wie, wurde nicht gemeldet
words-end-other = Vorzeitig beendet
words-end-recording-stopped = { $end }; die Aufzeichnung endete vorzeitig
words-not-in-trends = (nicht in den Trends)

## Übungsarten

words-kind-road = Straße
words-kind-dial = Drehscheibe
words-kind-strength = Krafttest
words-kind-haptic-sweep = Haptik-Messung
words-kind-regimen = Programm
words-kinds-and = { $first } und { $last }
words-regimen = { $count ->
        [one] Ein Programm aus { $count } Übung
       *[other] Ein Programm aus { $count } Übungen
    }

## Trends, Zeiten, Stationen

words-trend-better = besser
words-trend-worse = schlechter
words-trend-steady = gleich
words-seconds = { $n } s
words-minutes = { $n } Min.
words-of-prescribed = { $done } von { $prescribed } verordnet
words-station-paired = Station gekoppelt am { $day }

## Übungen nach ihren Kurznamen (denen des Plans) und die Übungen einer Sitzung der Reihe nach

words-exercise-straight-road = Gerade Straße
words-exercise-sine-road = Sinusstraße
words-exercise-triangle-road = Dreiecksstraße
words-exercise-clothoid-road = Klothoidenstraße
words-exercise-sharp-turns = Scharfe Kurven
words-exercise-s-bend = S-Kurve
words-exercise-lane-change = Spurwechsel
words-exercise-slalom = Slalom
words-exercise-dial-sine = Zeiger, Sinus
words-exercise-dial-multi-sine = Zeiger, Mehrfachsinus
words-exercise-dial-step = Zeiger, Sprung
words-exercise-dial-ramp = Zeiger, Rampe
words-exercise-dial-chirp = Zeiger, Chirp
words-exercise-strength = Kraft
words-exercise-haptic-sweep = Haptik-Durchlauf
words-exercises-then = { $first }, dann { $next }
