# Messgrößen, Beendigungsgründe, Übungsarten, Trends und Zeiten in der Sprache der Klinik.
# Schlüssel, Einheiten, Nachkommastellen und Bereiche stehen allein in
# crates/metrics/src/words.rs; hier nur die Namen.

## Namen der Messgrößen

words-measure-active-s = Aktive Zeit
words-measure-session-s = Sitzungsdauer
words-measure-paused-s = Pausenzeit
words-measure-active-pct = Zeit in Bewegung
words-measure-movements = Bewegungen
words-measure-discrete-movements = Bewegungen aus der Ruhe in die Ruhe
words-measure-movements-per-min = Bewegungen pro Minute
words-measure-reversals-per-min = Lenkrichtungswechsel pro Minute
words-measure-sparc-median = Flüssigkeit (näher an 0 ist flüssiger)
words-measure-ldlj-median = Flüssigkeit der Beschleunigung (näher an 0 ist flüssiger)
words-measure-movement-peak-speed-deg-s-median = Höchste Drehgeschwindigkeit einer Bewegung
words-measure-movement-time-s-median = Dauer einer Bewegung
words-measure-speed-peaks-median = Stopps und Anläufe in einer Bewegung
words-measure-speed-metric-median = Gleichmäßigkeit der Geschwindigkeit (1 ist gleichmäßig)
words-measure-reaction-time-s-median = Reaktionszeit
words-measure-anticipation-pct = Spurwechsel vor dem Wechsel begonnen
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
words-measure-trunk-cues = Erinnerungen, aufrecht zu sitzen
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

## Was jedes Maß misst, für die Fachkraft (words-definition-<key>; docs/MEASURES.md)

words-definition-active-s = Zeit, in der sich das Lenkrad bewegte: die Summe der Bewegungsdauern, ohne Pausen.
words-definition-session-s = Zeit vom Beginn bis zum Ende der Sitzung, mit Pausen.
words-definition-paused-s = Zeit, in der die Sitzung vom Patienten oder zur Erholung pausiert war.
words-definition-active-pct = Anteil der Übungszeit, in dem sich das Lenkrad bewegte.
words-definition-movements = Bewegungen des Lenkrads: seine Geschwindigkeit über 5 % der höchsten der Sitzung (mindestens 2,9 °/s), Lücken unter 0,1 s verbunden, Abschnitte unter 0,2 s verworfen.
words-definition-discrete-movements = Bewegungen aus der Ruhe in die Ruhe: mindestens 0,2 s still davor und danach, höchstens 5 s lang. Nur sie werden auf Flüssigkeit bewertet.
words-definition-movements-per-min = Bewegungen je Minute Übung: die Übungsdosis.
words-definition-reversals-per-min = Wechsel der Drehrichtung des Lenkrads um mindestens 2° je Minute Übung.
words-definition-sparc-median = Spektrale Bogenlänge der Lenkradgeschwindigkeit, Median über die Bewegungen aus der Ruhe in die Ruhe; keine bei einer fortlaufenden Aufgabe. Näher an 0 ist flüssiger.
words-definition-ldlj-median = Logarithmischer dimensionsloser Ruck der Lenkradgeschwindigkeit, Median über die Bewegungen aus der Ruhe in die Ruhe; keiner bei einer fortlaufenden Aufgabe. Näher an 0 ist flüssiger.
words-definition-movement-peak-speed-deg-s-median = Höchste Drehgeschwindigkeit innerhalb einer Bewegung, Median über die Bewegungen.
words-definition-movement-time-s-median = Dauer einer Bewegung, vom Überschreiten der Geschwindigkeitsschwelle bis zum Zurückfallen, Median.
words-definition-speed-peaks-median = Geschwindigkeitsgipfel innerhalb einer Bewegung (mindestens 10 % ihrer Höchstgeschwindigkeit), Median; 1 ist eine einzige flüssige Bewegung.
words-definition-speed-metric-median = Mittlere Geschwindigkeit einer Bewegung durch ihre Höchstgeschwindigkeit, Median; steigt, wenn Bewegungen sich mit der Erholung füllen.
words-definition-reaction-time-s-median = Zeit von einem unvorhersehbaren Sprung des Ziels (des Zeigers) bis zum Beginn der Lenkradbewegung, Median.
words-definition-anticipation-pct = Anteil der vorab sichtbaren Spurwechsel, deren Lenken früher als 0,1 s nach dem Wechsel begann: vorweggenommen, nicht darauf reagiert.
words-definition-initial-direction-error-deg-mean = Ob eine Bewegung nach einem Sprung des Ziels in die falsche Richtung beginnt: 0° richtig, 180° falsch, Mittelwert.
words-definition-reaction-time-left-s-median = Reaktionszeit auf unvorhersehbare Sprünge des Ziels nach links, Median.
words-definition-reaction-time-right-s-median = Reaktionszeit auf unvorhersehbare Sprünge des Ziels nach rechts, Median.
words-definition-initial-direction-error-left-deg-mean = Falsche Startrichtung bei Zielen links, Mittelwert (0° richtig, 180° falsch).
words-definition-initial-direction-error-right-deg-mean = Falsche Startrichtung bei Zielen rechts, Mittelwert (0° richtig, 180° falsch).
words-definition-path-length-ratio-median = Gedrehter Weg nach einem Sprung des Ziels durch den nötigen Weg bis zum Ziel, Median; 1 ist direkt.
words-definition-wheel-rom-deg = Größter minus kleinster Lenkradwinkel während der Übung.
words-definition-shoulder-elevation-rom-deg = Größter minus kleinster Schulterhebewinkel, solange die Armsensoren folgten.
words-definition-elbow-flexion-rom-deg = Größter minus kleinster Ellenbogenbeugewinkel, solange die Armsensoren folgten.
words-definition-trunk-flexion-max-deg = Stärkste Vorbeugung des Rumpfes gegenüber der Anfangshaltung, vom Brustbeinsensor.
words-definition-trunk-flexion-mean-deg = Mittlere Vorbeugung des Rumpfes gegenüber der Anfangshaltung, vom Brustbeinsensor.
words-definition-trunk-lean-max-deg = Stärkste Seitneigung des Rumpfes gegenüber der Anfangshaltung, vom Brustbeinsensor.
words-definition-trunk-lean-mean-deg = Mittlere Seitneigung des Rumpfes gegenüber der Anfangshaltung, vom Brustbeinsensor.
words-definition-trunk-rotation-max-deg = Stärkste Drehung des Rumpfes gegenüber der Anfangshaltung, vom Brustbeinsensor.
words-definition-trunk-rotation-mean-deg = Mittlere Drehung des Rumpfes gegenüber der Anfangshaltung, vom Brustbeinsensor.
words-definition-trunk-beyond-pct = Anteil der Übungszeit mit einem Rumpfwinkel über der Schwelle der Station.
words-definition-trunk-compensated-movements-pct = Anteil der Lenkbewegungen, bei denen der Rumpf über die Schwelle ging.
words-definition-trunk-cues = Wie oft die Station bat, wieder aufrecht zu sitzen: Der Rumpf blieb eine Sekunde über der Hinweisschwelle der Therapeutin oder des Therapeuten; höchstens einmal in 20 s.
words-definition-pct-in-lane = Anteil der Fahrzeit, in dem das Auto in seiner Spur war.
words-definition-rms-lateral-m = Quadratischer Mittelwert des Abstands des Autos von der Spurmitte.
words-definition-heading-rms-error-deg = Quadratischer Mittelwert des Winkels zwischen Fahrtrichtung des Autos und Richtung der Straße.
words-definition-cone-hits = Pylonen, die das Auto berührte.
words-definition-completion-time-s = Zeit bis zum Ende der Strecke.
words-definition-tracking-rms-error-deg = Quadratischer Mittelwert des Unterschieds zwischen verlangtem und tatsächlichem Lenkradwinkel.
words-definition-dial-rms-error-deg = Quadratischer Mittelwert des Unterschieds zwischen Zielwinkel des Zeigers und der Nadel des Lenkrads.
words-definition-dial-mean-abs-error-deg = Mittlerer Betrag des Unterschieds zwischen Zielwinkel des Zeigers und der Nadel des Lenkrads.
words-definition-strength-peak-left-nm = Höchstes Drehmoment nach links gegen die Feder des Lenkrads, das Lenkrad fast still gehalten.
words-definition-strength-sustained-left-nm = Höchstes Drehmoment nach links, mindestens 1 s gehalten.
words-definition-strength-peak-right-nm = Höchstes Drehmoment nach rechts gegen die Feder des Lenkrads, das Lenkrad fast still gehalten.
words-definition-strength-sustained-right-nm = Höchstes Drehmoment nach rechts, mindestens 1 s gehalten.
words-definition-assist-level-mean = Wie viel das Lenkrad half, Mittelwert über die Übung: 0 keine Hilfe, 1 volle Hilfe.
words-definition-patient-work-pct = Anteil des Patienten an der mechanischen Arbeit am Lenkrad (Patient und Hilfe des Lenkrads zusammen).
