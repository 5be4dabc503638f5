# Das Verordnungsformular (crates/hub/console/prescribe.js).

prescribe-heading = Trainingsplan
prescribe-version = Version { $version }, verordnet von { $by } am { $when }.
prescribe-version-gone = einer Fachkraft, die nicht mehr in der Klinik ist
prescribe-version-none = Noch nichts verordnet: Die Station führt ihre Standardübung aus.
prescribe-version-now = Version { $version }, soeben verordnet von { $by }.
prescribe-sessions-label = Sitzungen pro Woche
prescribe-assessment-label = Standardtest alle … Tage (leer: keiner)
prescribe-trunk-cue-label = Ans Aufrichten erinnern, wenn der Rumpf sich über … Grad bewegt (leer: nie)
prescribe-no-exercise = Noch keine Übung: Fügen Sie eine hinzu.
prescribe-add-label = Übung hinzufügen
prescribe-add-button = Hinzufügen
prescribe-full = Höchstens { $max } Übungen in einem Plan, Sätze mitgezählt.
prescribe-message-note = Um { $name } über die Änderung zu informieren, schreiben Sie in das Nachrichtenfeld unten. Die Nachricht wird beim Speichern mit der Verordnung gesendet.
prescribe-save = Als neue Version speichern
prescribe-saving = Wird gespeichert …
prescribe-saved = { $message ->
    [yes] Als Version { $version } gespeichert, mit der Nachricht.
   *[no] Als Version { $version } gespeichert.
}
prescribe-message-problem = Die Nachricht: { $problem }
prescribe-out-of-bounds = Ein Wert liegt außerhalb seiner Grenzen (daneben angegeben).
prescribe-too-many = { $count } Übungen mit den Sätzen gezählt: höchstens { $max }.
prescribe-total = { $untimed ->
    [0] Etwa { $minutes } min Übung und { $rests } min Pausen.
    [one] Etwa { $minutes } min Übung und { $rests } min Pausen, dazu eine Übung ohne Minutenangabe (einmal gefahren oder von der Übung selbst getaktet).
   *[other] Etwa { $minutes } min Übung und { $rests } min Pausen, dazu { $untimed } Übungen ohne Minutenangabe (einmal gefahren oder von der Übung selbst getaktet).
}

prescribe-exercise-legend = Übung { $n }: { $name }
prescribe-kind-unknown = Eine Übungsart, die dieser Hub nicht kennt: Bearbeiten Sie sie in der Textfassung.
prescribe-remove = Übung { $n } entfernen
prescribe-levels-legend = Schwierigkeit
prescribe-level-easy = Leicht
prescribe-level-medium = Mittel
prescribe-level-hard = Schwer
prescribe-level-own = Eigene Einstellungen
prescribe-level-own-note = von den Stufen abweichend (siehe Details)
prescribe-minutes-label = Minuten
prescribe-minutes-road = einmal die Strecke entlang
prescribe-sets-label = Sätze (die Übung nach einer Pause wiederholt)
prescribe-rest-label = Pause nach jedem Satz, Sekunden
prescribe-rest-default = nur die kurze Karte
prescribe-dial-other = Das Ziel bewegt sich nicht in einer Schwingung: Seine Einstellungen stehen in der Textfassung.
prescribe-dial-range-label = Drehung des Lenkrads zu jeder Seite, Grad
prescribe-dial-pace-label = Eine Schwingung hin und zurück, Sekunden
prescribe-dial-words = Das Lenkrad dreht bis zu { $degrees }° zu jeder Seite ({ $range ->
    [small] eine kleine Drehung
    [quarter] bis zu einer Vierteldrehung
   *[more] mehr als eine Vierteldrehung
}), eine Schwingung hin und zurück alle { $seconds } s ({ $pace ->
    [slow] langsam
    [moderate] mäßig
   *[brisk] zügig
}).
prescribe-dial-sine = Das Ziel: ein Sinus von { $degrees }° bei { $rate } rad/s (amplitude_deg, frequency_rad_s).
prescribe-ceiling-label = Stärkster Druck des Lenkrads (Drehmomentgrenze), N·m (leer: die der Station)
prescribe-pedals-label = Der Patient bestimmt das Tempo mit den Pedalen (braucht Minuten; leer lassen für automatisches Tempo)
prescribe-details-summary = Details: die Einstellungen hinter der Stufe

prescribe-text-summary = Als Text bearbeiten (jede Einstellung, wie im Ordner regimens der Station)
prescribe-text-label = Trainingsplan (TOML)
prescribe-text-save = Den Text als neue Version speichern

prescribe-bounds-heading = Sicherheitsgrenzen, die die Station einhält
prescribe-bounds-ceiling = Drehmomentgrenze
prescribe-bounds-ceiling-text = Höchstens { $nm } N·m in einer Verordnung ({ $wheel ->
    [patient] was das Lenkrad dieses Patienten leisten kann
   *[consumer] das stärkste handelsübliche Lenkrad
}), darüber abgelehnt. Die Station begrenzt dann auf die Grenze ihres eigenen Lenkrads: Eine Verordnung kann die Grenze des Patienten senken, nie erhöhen.
prescribe-bounds-slew = Drehmomentänderungen
prescribe-bounds-slew-text = Von der Sicherheitskette der Station in der Änderungsrate begrenzt, unabhängig von der Verordnung.
prescribe-bounds-session = Sitzung
prescribe-bounds-session-text = Höchstens { $max } Übungen (jeder Satz zählt als eine), zusammen höchstens { $minutes } min geplant, Pausen und Karten zwischen den Übungen eingeschlossen.
prescribe-bounds-levels = Stufen
prescribe-bounds-levels-text = Jede leichte, mittlere und schwere Stufe wird vom Validator der Station selbst geprüft.
prescribe-bounds-other = Jede andere Einstellung
prescribe-bounds-other-text = Innerhalb des daneben angegebenen Bereichs.
prescribe-bounds-note = Die Bereiche des Formulars stammen aus dem Schema des Trainingsplans, das der Hub aus dem Validator der Station ableitet. Der Hub prüft den ganzen Plan mit diesem Validator, bevor er ihn speichert; die Station übernimmt die neue Version zur nächsten Sitzung.

prescribe-difficulty-legend = Schwierigkeit, die sich dem Patienten anpasst
prescribe-difficulty-adapt = Die Schwierigkeit jeder Sitzung an den Patienten anpassen (Ziel ist die Erfolgsquote; „zu leicht“ und „zu schwer“ werden berücksichtigt)
prescribe-difficulty-changes = Ändert:
prescribe-difficulty-note = Schwierigkeit 1 ist der Plan wie geschrieben; 0 ist halbes Tempo und halbe Form mit voller Unterstützung. Nie über die Verordnung hinaus; die Drehmomentgrenze ändert sich nie.
prescribe-difficulty-target_success = Die Erfolgsquote, die die Anpassung anstrebt
prescribe-difficulty-lowest = Die leichteste erlaubte Schwierigkeit
prescribe-difficulty-highest = Die schwerste erlaubte Schwierigkeit
prescribe-difficulty-start = Die Schwierigkeit der ersten Sitzung
prescribe-aspect-speed = Tempo
prescribe-aspect-shape = Form
prescribe-aspect-assist = Unterstützung

prescribe-kind-straight = Gerade Straße
prescribe-kind-sine = Sinusstraße
prescribe-kind-triangle = Dreieckstraße
prescribe-kind-clothoid = Klothoidenstraße
prescribe-kind-sharp-turns = Scharfe Kurven
prescribe-kind-s-bend = S-Kurve
prescribe-kind-lane-change = Spurwechsel
prescribe-kind-slalom = Slalom
prescribe-kind-dial = Zeiger
prescribe-kind-strength = Kraft
prescribe-kind-haptic-sweep = Haptik-Durchlauf

prescribe-preset-straight-easy = Eine breite Spur, langsam gefahren.
prescribe-preset-straight-medium = Eine normale Spur mit Stadttempo.
prescribe-preset-straight-hard = Eine schmale Spur, schneller gefahren.
prescribe-preset-sine-easy = Lange sanfte Wellen in einer breiten Spur, langsam.
prescribe-preset-sine-medium = Die kurvige Straße aus der Dissertation.
prescribe-preset-sine-hard = Große, engere Wellen in einer schmalen Spur.
prescribe-preset-triangle-easy = Flache Zickzacks mit weiten Ecken, langsam.
prescribe-preset-triangle-medium = Zickzacks mit abgerundeten Ecken.
prescribe-preset-triangle-hard = Steile Zickzacks mit engen Ecken.
prescribe-preset-clothoid-easy = Eine Kurve, die etwas enger wird, langsam.
prescribe-preset-clothoid-medium = Eine Kurve, die stetig enger wird.
prescribe-preset-clothoid-hard = Eine Kurve, die in einer schmalen Spur stark enger wird.
prescribe-preset-sharp-turns-easy = Einige halbe Wenden in weiten Bögen.
prescribe-preset-sharp-turns-medium = Rechtwinklige Abbiegungen, links und rechts.
prescribe-preset-sharp-turns-hard = Mehr rechtwinklige Abbiegungen, enger und dichter.
prescribe-preset-s-bend-easy = Zwei sanfte Kurven in einer breiten Spur.
prescribe-preset-s-bend-medium = Eine Links-, dann eine Rechtskurve.
prescribe-preset-s-bend-hard = Zwei enge Kurven in einer schmalen Spur.
prescribe-preset-lane-change-easy = Drei langsame, lange Spurwechsel.
prescribe-preset-lane-change-medium = Vier Spurwechsel mit Stadttempo.
prescribe-preset-lane-change-hard = Sechs schnelle Spurwechsel.
prescribe-preset-slalom-easy = Sechs weit auseinanderstehende Hütchen, langsam.
prescribe-preset-slalom-medium = Acht Hütchen.
prescribe-preset-slalom-hard = Zehn dicht stehende Hütchen in einer schmalen Spur.
prescribe-preset-dial-easy = Kleine Drehungen zu jeder Seite, langsam.
prescribe-preset-dial-medium = Drehungen von einer Vierteldrehung und mehr zu jeder Seite.
prescribe-preset-dial-hard = Große Drehungen zu jeder Seite, schneller.
prescribe-preset-strength-easy = Ein sanfter Test: Die Feder wird langsam steifer.
prescribe-preset-strength-medium = Der Standardtest.
prescribe-preset-strength-hard = Ein schnellerer Test: Die Feder wird schneller steifer.
prescribe-preset-haptic-sweep-easy = Drei Stufen zu je einer halben Minute, kleine langsame Schwingungen.
prescribe-preset-haptic-sweep-medium = Die sechs Stufen zu je einer Minute aus der Dissertation.
prescribe-preset-haptic-sweep-hard = Sechs Stufen zu je einer Minute, schnellere Schwingungen.

## Die Einstellungen hinter der Stufe einer Übung (Details), je ein Feld des Plans: Einheiten wie im Plan.
prescribe-field-lane-width-m = Spurbreite, m
prescribe-field-length-m = Länge des Übungsteils, m
prescribe-field-speed-m-s = Zielgeschwindigkeit, m/s
prescribe-field-amplitude-m = Ausschlag der Kurven, m
prescribe-field-periods = Anzahl ganzer Wellen
prescribe-field-wavelength-m = Wellenlänge, m
prescribe-field-corner-radius-m = Radius der gerundeten Ecken, m
prescribe-field-end-curvature-1-m = Krümmung am Ende, 1/m (positiv: nach links)
prescribe-field-unwind-m = Länge der sich öffnenden Kurve, m
prescribe-field-angle-deg = Kurvenwinkel, °
prescribe-field-count = Anzahl der Kurven oder Wechsel
prescribe-field-radius-m = Kurvenradius, m
prescribe-field-straight-m = Gerade zwischen den Kurven, m
prescribe-field-hold-m = Gerade nach jedem Wechsel, m
prescribe-field-offset-m = Seitliche Verschiebung, m
prescribe-field-transition-m = Länge eines Wechsels, m
prescribe-field-cone-count = Anzahl der Hütchen
prescribe-field-cone-spacing-m = Abstand zwischen den Hütchen, m
prescribe-field-weave-m = Seitlicher Abstand des Wegs zu jedem Hütchen, m
prescribe-field-drift-deg = So weit wandert das Ziel zur vernachlässigten Seite, ° Lenkraddrehung
prescribe-field-ramp-nm-per-s = Wie schnell die Federgrenze zur Obergrenze steigt, N·m/s
prescribe-field-side-s = Zeitgrenze je Seite, s
prescribe-field-stiffness-nm-per-rad = Steifigkeit der Feder, die das Lenkrad mittig hält, N·m/rad
prescribe-field-amplitude-deg = Ausschlag zu jeder Seite, °
prescribe-field-frequency-rad-s = Frequenz der Schwingung, rad/s
prescribe-field-level-s = Zeit je Stufe, s
