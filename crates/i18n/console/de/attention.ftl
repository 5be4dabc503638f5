# Hinweise in der Patientenliste: Namen der Hinweisarten, Dringlichkeit, der Satz jedes
# Hinweises (der Hub sendet Kennung und Argumente) und die Schwellenwerte der Klinik.

attention-severity-urgent = Dringend
attention-severity-warning = Heute ansehen
attention-severity-notice = Zur Kenntnis
attention-severity-label = { $severity }:

## Hinweisarten (Filter)

attention-kind-pain-high = Schmerzen
attention-kind-pain-rising = Zunehmende Schmerzen
attention-kind-station-revoked = Station entzogen
attention-kind-no-session = Keine Sitzung
attention-kind-decline = Verschlechterung
attention-kind-safety-stop = Sicherheitsstopp
attention-kind-ended-early = Vorzeitig beendet
attention-kind-effort = Hohe Anstrengung
attention-kind-low-activity = Wenig Training
attention-kind-wheel-unplugged = Lenkrad getrennt
attention-kind-sensor-unplugged = Armsensor getrennt
attention-kind-wheel-unseen = Lenkrad nicht erkannt
attention-kind-sensors-lost = Armsensoren verloren
attention-kind-station-silent = Station meldet sich nicht
attention-kind-torque-at-ceiling = Drehmoment am Limit

## Die Hinweise

attention-pain-high = Schmerzen { $pain_0_10 }/10 nach der Sitzung vom { $at }{ $sessions_since ->
        [0] {""}
        [one] {" "}(keine Schmerzangabe nach der folgenden Sitzung)
       *[other] {" "}(keine Schmerzangabe in den { $sessions_since } Sitzungen danach)
    }
attention-pain-rising = Zunehmende Schmerzen: { $first_0_10 }, dann { $middle_0_10 }, dann { $pain_0_10 }/10 nach der Sitzung vom { $at }
attention-station-revoked = Station am { $at } entzogen: Der Patient kann erst wieder trainieren, wenn eine neue gekoppelt ist
attention-no-session-yet = Noch keine Sitzung (hinzugefügt am { $at })
attention-no-session = Seit { $days } Tagen keine Sitzung (letzte: { $at })
attention-decline = { $measure } schlechter in den Sitzungen „{ $exercise_kind }“: { $latest } gegenüber { $usual } zuvor ({ $worse_percent } % schlechter)
attention-safety-stop = Sicherheitsstopp in der Sitzung vom { $at }
attention-ended-early = { $ended_early } der letzten { $sessions } Sitzungen vorzeitig beendet
attention-effort-high = Anstrengung { $effort_0_10 }/10 (Borg CR10) nach der Sitzung vom { $at }
attention-effort-too-hard = „Zu schwer“ nach den letzten { $too_hard_sessions } Sitzungen
attention-low-sessions = { $sessions } von { $sessions_prescribed } verordneten Sitzungen diese Woche
attention-low-minutes = { $active_minutes } von { $minutes_prescribed } verordneten aktiven Minuten diese Woche
attention-low-unprescribed = { $active_minutes ->
        [one] { $active_minutes } aktive Minute
       *[other] { $active_minutes } aktive Minuten
    } diese Woche; noch nichts verordnet (die Klinik erwartet mindestens { $minimum_minutes })
attention-wheel-unplugged = Sitzung vom { $at }: { $end }
attention-sensor-unplugged = Sitzung vom { $at }: { $end }
attention-wheel-unseen = Lenkrad seit { $days } Tagen nicht erkannt, obwohl die Station an war
attention-sensors-lost = Armsensoren verloren in { $sessions ->
        [one] der letzten Sitzung
       *[other] den letzten { $sessions } Sitzungen
    }
attention-station-silent = Station seit { $days } Tagen ohne Verbindung (zuletzt: { $at })
attention-torque-at-ceiling = Drehmoment in { $percent } % oder mehr der Sitzung vom { $at } am Limit

## Schwellenwerte der Klinik (#/attention-settings)

attention-settings-title = Schwellenwerte für Hinweise
attention-settings-intro = Wann die Patientenliste meldet, dass ein Patient Aufmerksamkeit braucht.
attention-settings-admin = Änderungen gelten sofort für alle Therapeuten der Klinik und werden im Protokoll festgehalten.
attention-settings-not-admin = Ein Administrator kann sie ändern.
attention-settings-save = Schwellenwerte speichern
attention-settings-saved = Gespeichert.
attention-settings-out-of-range = Ein Wert liegt außerhalb seines Bereichs (daneben angegeben).
attention-setting-range = ({ $min }–{ $max }; Standard { $default })
attention-setting-changed = Geändert von { $who } am { $at }.
attention-setting-default = Von der Klinik nicht geändert: Standardwert.
attention-setting-pain-threshold-0-10 = Dringende Schmerzen, 0–10 (ab)
    .why = Schmerzen von 7 oder mehr auf der Skala 0–10 sind starke Schmerzen; wer sie meldet, sollte nicht ohne Rücksprache mit der Klinik weitertrainieren.
attention-setting-pain-rise-points = Zunehmende Schmerzen: Punkte über drei Abfragen
    .why = Zwei Punkte sind etwa die kleinste Schmerzänderung, die Patienten als echt empfinden.
attention-setting-no-session-days = Tage ohne Sitzung
    .why = Drei Tage ohne Training unterbrechen den Rhythmus eines Heimprogramms; bei weniger verordneten Sitzungen pro Woche gilt der entsprechende Abstand (7 Tage bei einmal pro Woche).
attention-setting-min-active-minutes-week = Aktive Minuten pro Woche, wenn nichts verordnet ist (mindestens)
    .why = Eine halbe Stunde pro Woche liegt weit unter dem, was Patienten zu Hause schaffen (im Mittel etwa 2 Stunden pro Woche); weniger heißt, die Station wird kaum genutzt.
attention-setting-decline-percent = Verschlechterung: Prozent unter den früheren Sitzungen derselben Art
    .why = Bewegungsmaße schwanken von Sitzung zu Sitzung um bis zu etwa 10 %; 15 % liegen jenseits dieser Schwankung.
attention-setting-ended-early-sessions = Vorzeitig beendete Sitzungen von den letzten 5
    .why = Einmal kann ein Telefonanruf sein; zweimal in fünf Sitzungen ist ein Muster, nach dem man fragen sollte.
attention-setting-effort-threshold-0-10 = Anstrengung, die einen Blick braucht, Borg CR10 0–10 (ab)
    .why = Heimprogramme verlieren Patienten, denen das Training schwerfällt; 7 von 10 liegt deutlich über „schwer“.
attention-setting-devices-unseen-days = Tage, an denen die Station ohne Lenkrad läuft
    .why = Ein Lenkrad, das drei Tage fehlt, bedeutet meist ein Kabel oder ein Netzteil, keine Absicht.
attention-setting-station-silent-days = Tage, die eine Station stumm bleiben darf
    .why = Eine Station, mit der trainiert wird, verbindet sich bei jeder Sitzung; drei stumme Tage heißen, sie ist aus, ausgesteckt oder offline.
