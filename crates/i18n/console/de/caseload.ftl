# Die Patientenliste (#/patients): wer zuerst Aufmerksamkeit braucht, das Training der Woche,
# die Trends, Hinweise quittieren und nach einem Schmerzstopp das Training wieder freigeben.

caseload-title = Patienten
caseload-order = Reihenfolge
caseload-order-need = Dringendste zuerst
caseload-order-last-session = Längste Zeit ohne Sitzung zuerst
caseload-order-pseudonym = Nach Pseudonym
caseload-show = Anzeigen
caseload-show-all = Alle Patienten
caseload-show-only = Nur: { $kind }
caseload-mine = Nur meine eigenen Patienten
caseload-caption-need = Ihre Patienten, die dringendsten zuerst. Öffnen Sie einen Patienten, um eine laufende Sitzung zu verfolgen, den Verlauf zu sehen oder zu verordnen.
caseload-caption-chosen = Ihre Patienten in der gewählten Reihenfolge. Öffnen Sie einen Patienten, um eine laufende Sitzung zu verfolgen, den Verlauf zu sehen oder zu verordnen.
caseload-col-patient = Patient
caseload-col-needs = Braucht Aufmerksamkeit
caseload-col-last-session = Letzte Sitzung
caseload-col-last-7-days = Letzte 7 Tage
caseload-col-trend = Trend
caseload-none = Noch keine Patienten.
caseload-none-with-alert = Kein Patient hat diesen Hinweis zurzeit.
caseload-add-patient = Patienten hinzufügen
caseload-add-patient-note = (und das Kopplungsblatt drucken)
caseload-thresholds-link = Schwellenwerte für Hinweise
caseload-nothing-needed = Nichts zu tun
caseload-more = { $count } weitere
caseload-acknowledged = { $count ->
        [one] { $count } Hinweis quittiert
       *[other] { $count } Hinweise quittiert
    }
caseload-week = { $sessionsPrescribed ->
        [none] { $sessions ->
            [one] { $sessions } Sitzung
           *[other] { $sessions } Sitzungen
        }
       *[other] { $sessions } von { $sessionsPrescribed } verordneten Sitzungen
    }, { $minutesPrescribed ->
        [none] { $minutes } aktive Min.
       *[other] { $minutes } von { $minutesPrescribed } verordneten aktiven Min.
    }
# The week's repetitions (wheel movements) in the caseload's week column.
caseload-repetitions = { $repetitions ->
        [one] { $repetitions } Wiederholung
       *[other] { $repetitions } Wiederholungen
    }
caseload-trend-kind = Sitzungen „{ $kind }“:
caseload-trend-pct-in-lane = Zeit in der Spur
caseload-trend-wheel-rom-deg = Lenkradbereich
caseload-trend-sparc-median = Flüssigkeit
caseload-trend-better = besser
caseload-trend-worse = schlechter
caseload-trend-steady = gleich
caseload-acknowledge = Quittieren
caseload-quiet-former = ein Therapeut, der nicht mehr in der Klinik ist
caseload-quiet-snoozed = zurückgestellt bis { $until } von { $who } am { $at }: { $note }
caseload-quiet-acknowledged = quittiert (ruhig bis sich etwas ändert) von { $who } am { $at }: { $note }

## Hinweis quittieren

caseload-ack-legend = Ruhig stellen
caseload-ack-until-new = Bis sich etwas Neues ergibt
caseload-ack-until-day = Bis zu einem Tag:
caseload-ack-snooze-until = Zurückstellen bis
caseload-ack-note = Notiz
caseload-ack-note-hint = (was getan wurde, z. B. „Angerufen: ruht sich aus, geht Montag zum Hausarzt“)
caseload-ack-no-day = Wählen Sie den Tag, an dem der Hinweis wiederkommen darf.
caseload-save = Speichern
caseload-cancel = Abbrechen

## Training nach einem Schmerzstopp wieder freigeben

caseload-allow-training = Training heute freigeben
caseload-allow-question = Training heute trotz der gemeldeten Schmerzen wieder freigeben?
caseload-allow-explain = Die Station hat das Training nach dieser Schmerzangabe für heute beendet. Wenn Sie mit dem Patienten gesprochen haben und das Training sicher ist, kann er heute wieder trainieren. Dies wird im Protokoll festgehalten.
caseload-allow-confirm = Ja, Training heute freigeben
caseload-allow-done = Training wieder freigegeben ({ $at }). Die Station erfährt es sofort oder bei der nächsten Verbindung.
caseload-training-allowed = Training am { $at } wieder freigegeben.
