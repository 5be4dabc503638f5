# Die Bildschirme des Trainings. Anrede: „Sie“. Jeder Satz höchstens 12 Wörter.

## Übungsnamen
exercise-straight-road = Gerade Straße
exercise-sine-road = Kurvige Straße
exercise-triangle-road = Zickzack-Straße
exercise-clothoid-road = Immer engere Kurven
exercise-sharp-turns = Scharfe Kurven
exercise-s-bend = Doppelkurve
exercise-lane-change = Spur wechseln
exercise-slalom = Um die Hütchen fahren
exercise-dial-sine = Dem Zeiger folgen
exercise-dial-multi-sine = Dem wandernden Zeiger folgen
exercise-dial-step = Dem springenden Zeiger folgen
exercise-dial-ramp = Dem langsamen Zeiger folgen
exercise-dial-chirp = Dem immer schnelleren Zeiger folgen
exercise-strength = Gegen das Lenkrad drücken
exercise-haptic-sweep = Das Lenkrad spüren
exercise-assessment-range = Test: wie weit Sie drehen können
exercise-assessment-tracking-slow = Test: dem langsamen Zeiger folgen
exercise-assessment-tracking-medium = Test: dem Zeiger folgen
exercise-assessment-tracking-fast = Test: dem schnellen Zeiger folgen
exercise-assessment-steps = Test: dem springenden Zeiger folgen
exercise-assessment-strength = Test: gegen das Lenkrad drücken
exercise-other = Übung

## Was jede Übung verlangt
instruction-dial = Drehen Sie das Lenkrad. Halten Sie den schwarzen Zeiger auf dem roten.
instruction-strength = Drücken Sie das Lenkrad nach links, dann nach rechts. So fest, wie es angenehm ist.
instruction-slalom = Lenken Sie um die Hütchen. Bleiben Sie auf der Straße.
instruction-lane-change = Wenn die Straße zur Seite geht, wechseln Sie die Spur.
instruction-straight-road = Halten Sie das Auto in der Mitte der Spur.
instruction-bends = Lenken Sie durch die Kurven. Bleiben Sie in Ihrer Spur.
instruction-road = Folgen Sie der Straße. Bleiben Sie in Ihrer Spur.
instruction-pedals = Ihre Füße bestimmen das Tempo. Rechtes Pedal: fahren. Linkes: bremsen.
instruction-assessment-range = Drehen Sie das Lenkrad so weit Sie können. Erst links, dann rechts. Halten Sie es dort.
instruction-assessment-tracking = Dies ist ein Test. Das Lenkrad hilft nicht. Halten Sie den schwarzen Zeiger auf dem roten.
instruction-assessment-steps = Der rote Zeiger springt. Folgen Sie ihm so schnell Sie können.

## Die Karte vor und zwischen den Übungen
card-get-ready = Machen Sie sich bereit
card-rest-then-back = Pause. Danach noch einmal:
card-rest-then-next = Pause. Danach:
card-next = Als Nächstes
card-exercise-of = Übung { $number } von { $total }: { $name }
card-start-key = Leertaste oder Lenkradtaste: starten
card-go-on-now-key = Leertaste oder Lenkradtaste: jetzt weiter
card-message-from-therapist = Eine Nachricht von Ihrem Therapieteam:

## Pause und Frage vor dem Beenden
pause-title = Pause
end-confirm-title = Training beenden?
end-confirm-yes = Drücken Sie noch einmal Esc zum Beenden.
end-confirm-no = Drücken Sie die Leertaste, um weiterzumachen.

## Einfache Karten
card-press-space-to-start = Drücken Sie die Leertaste zum Starten.
card-all-done = Geschafft!

## Armsensoren einrichten
setup-hold-still = Halten Sie das Lenkrad still
setup-hold-still-how = Legen Sie beide Hände auf das Lenkrad. Entspannen Sie sich.
setup-turn-slowly = Drehen Sie das Lenkrad langsam
setup-turn-slowly-how = Nach links und rechts, so weit es angenehm ist.
setup-thank-you = Danke
setup-getting-ready = Die Armsensoren werden vorbereitet …
setup-seconds-left = { $seconds } s

## Anzeige während der Übung
hud-time-left = Restzeit
hud-in-lane = In der Spur: { $percent } %
hud-middle-close = Nah an der Mitte
hud-middle-off = Etwas neben der Mitte
hud-middle-far = Weit weg von der Mitte
hud-needle-close = Genau auf dem roten Zeiger
hud-needle-near = Nah am roten Zeiger
hud-needle-behind = Bleiben Sie dran
hud-push-left = Drücken Sie das Lenkrad nach links, so fest es angenehm ist.
hud-push-right = Drücken Sie das Lenkrad nach rechts, so fest es angenehm ist.
hud-let-go = Lassen Sie das Lenkrad los und ruhen Sie sich aus.
hud-speed = { $kmh } km/h
hud-help = Hilfe: { $percent } %
hud-press-pedal = Treten Sie das rechte Pedal, um zu fahren.
hud-sit-up = Setzen Sie sich wieder gerade hin.
hud-wheel-working = Lenkrad: bereit
hud-wheel-resting = Lenkrad: Pause
hud-wheel-stopping = Lenkrad: hält an
hud-wheel-problem = Lenkrad: Störung, keine Kraft
hud-wheel-simulated = Lenkrad: Übungsmodus
hud-gentle-force = Nur sanfte Kraft
hud-arm-working = Armsensoren: bereit
hud-arm-setting-up = Armsensoren: werden vorbereitet
hud-arm-not-working = Armsensoren: Störung
hud-arm-not-answering = Armsensoren: kein Signal
hud-arm-simulated = Armsensoren: Übungsmodus
hud-your-arm = Ihr Arm
hud-your-wheel = Ihr Lenkrad
hud-target = Ziel
hud-your-arm-measured = Ihr Arm, gemessen

## Wenn das Training nicht beginnen kann
cannot-start-title = Das Training kann noch nicht beginnen
cannot-start-then = Starten Sie telerehab dann erneut.
cannot-start-close-key = Drücken Sie eine beliebige Taste zum Schließen.

## Wenn das Fenster neu gestartet wurde
pause-screen-restarted = Der Bildschirm hat neu gestartet. Die Übung ist pausiert.
