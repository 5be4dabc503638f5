# Der Reiter „Verlauf“ eines Patienten.

progress-list-separator = {", "}
progress-percent = { $n } %

## Schmerzen, Therapietreue und Hinweise

progress-summary-title = Schmerzen, Therapietreue und Hinweise
progress-pain-title = Schmerzen
progress-pain-latest = Schmerzen { $pain }/10
progress-pain-after = nach der Sitzung vom { $at }.
progress-pain-before = Davor: { $list } (neueste zuerst).
progress-pain-none = Noch keine Schmerzangabe.
progress-pain-chart-label = Schmerzen nach jeder Sitzung, 0 bis 10: die Zahlen stehen in der Liste der Sitzungen
progress-pain-axis = Schmerzen (0–10)
progress-checkin-pain = Schmerzen { $pain }/10
progress-checkin-effort = Anstrengung { $effort }/10
progress-checkin-skipped = übersprungen
progress-felt = empfunden als { $felt }
progress-felt-too-easy = zu leicht
progress-felt-about-right = genau richtig
progress-felt-too-hard = zu schwer
progress-after-last = Nach der letzten Sitzung: { $answers }.
progress-adherence-title = Therapietreue
progress-week = Letzte 7 Tage: { $sessionsPrescribed ->
        [none] { $sessions ->
            [one] { $sessions } Sitzung
           *[other] { $sessions } Sitzungen
        }
       *[other] { $sessions } von { $sessionsPrescribed } verordneten Sitzungen
    }, { $minutesPrescribed ->
        [none] { $minutes ->
            [one] { $minutes } aktive Minute
           *[other] { $minutes } aktive Minuten
        }
       *[other] { $minutes } von { $minutesPrescribed } verordneten aktiven Minuten
    }.
progress-week-repetitions = Wiederholungen in den letzten 7 Tagen: { $repetitions }.
progress-stopped-early = Vorzeitig beendet: { $stopped } { $count ->
        [one] der letzten Sitzung
       *[other] der letzten { $count } Sitzungen
    }.
progress-alerts-title = Hinweise
progress-alerts-none = Kein Hinweis.

## Die Dosis: aktive Trainingszeit und Wiederholungen nach Woche und Tag

progress-dose-title = Dosis: Trainingszeit und Wiederholungen
progress-dose-explain = Die aktive Trainingszeit zählt Pausen nicht mit. Wiederholungen sind die Bewegungen am Lenkrad. Die Wochen werden mit der aktuellen Verordnung verglichen.
progress-dose-weeks-caption = { $weeks ->
        [one] Nach Woche: die letzten 7 Tage
       *[other] Nach Woche, die letzten { $weeks } Wochen
    }
progress-dose-days-caption = Nach Tag, die letzten 7 Tage
progress-dose-col-week = Woche
progress-dose-col-day = Tag
progress-dose-col-sessions = Sitzungen
progress-dose-col-active = Aktives Training
progress-dose-col-repetitions = Wiederholungen
progress-dose-week-range = { $from } bis { $to }
progress-dose-below = unter der Verordnung

## Die letzte Sitzung im Vergleich

progress-latest-title = Übungen: die letzte Sitzung im Vergleich zu den früheren
progress-latest-title-kind = Übungen: die letzte Sitzung „{ $kind }“ im Vergleich zu den früheren
progress-compared = { $early ->
        [included] Die letzte beendete Sitzung (wie verordnet oder vorzeitig) ({ $session }) im Vergleich zum Ausgangswert des Patienten ({ $baseline ->
            [one] die erste Sitzung „{ $kind }“
           *[other] der Mittelwert der ersten { $baseline } Sitzungen „{ $kind }“
        }) und ihr Trend gegenüber bis zu { $earlier } früheren Sitzungen „{ $kind }“; eine Änderung innerhalb der Messschwankung einer Größe gilt als „gleich“. Vorzeitig beendete Sitzungen sind eingeschlossen.
       *[left-out] Die letzte wie verordnet abgeschlossene Sitzung ({ $session }) im Vergleich zum Ausgangswert des Patienten ({ $baseline ->
            [one] die erste Sitzung „{ $kind }“
           *[other] der Mittelwert der ersten { $baseline } Sitzungen „{ $kind }“
        }) und ihr Trend gegenüber bis zu { $earlier } früheren Sitzungen „{ $kind }“; eine Änderung innerhalb der Messschwankung einer Größe gilt als „gleich“. Vorzeitig beendete Sitzungen stehen in der Liste unten und werden nicht verglichen.
    }
progress-compared-none = Noch keine Sitzung lief wie verordnet: nichts zu vergleichen.
progress-col-measure = Messgröße
progress-col-latest = Zuletzt
progress-col-baseline = Ausgangswert
progress-col-trend = Trend
progress-against-prescription = im Vergleich zur Verordnung, kein Trend
progress-include-early = Vorzeitig beendete Sitzungen einbeziehen
progress-include-early-none = Vorzeitig beendete Sitzungen einbeziehen (keine vorhanden)

## Jede Übungsart

progress-kind-title = Sitzungen „{ $kind }“ ({ $count })
progress-kind-latest = : zuletzt { $list }
progress-headline-item = { $measure } { $value }
progress-kind-note = { $names }. Ein Diagramm je Messgröße, ein Schritt je Sitzung, die älteste links.
progress-kind-hollow = Hohle Punkte: { $count ->
        [one] { $count } Sitzung vorzeitig beendet
       *[other] { $count } Sitzungen vorzeitig beendet
    } ({ $early ->
        [included] einbezogen
       *[left-out] nicht mit der Linie verbunden
    }).
progress-kind-no-measures = Für diese Sitzungen wurden keine Messgrößen aufgezeichnet.
progress-prescribed-time = Verordnete Zeit ({ $unit })
progress-noise-band = Das schattierte Band ist die Messschwankung um den Ausgangswert: Ein Punkt darin ist keine Änderung.
progress-chart-label = { $measure } je Sitzung: die Zahlen stehen in der Tabelle darunter

## Schwierigkeit

progress-difficulty-title = Schwierigkeit, die sich dem Patienten anpasst
progress-difficulty-now = : jetzt { $now } (0 am leichtesten, 1 wie verordnet)
progress-difficulty-explain = 0: halbe verordnete Geschwindigkeit und Form mit voller Unterstützung; 1: das Programm wie verordnet. Von der Station innerhalb der Grenzen des Programms eingestellt.
progress-difficulty-axis = Schwierigkeit (0–1)
progress-difficulty-why-adapt-off = Anpassung aus: die Einstellung der Therapie.
progress-difficulty-why-first-start = Erste Sitzung: der Startwert der Therapie.
progress-difficulty-why-first-midway = Erste Sitzung: in der Mitte zwischen den Grenzen der Therapie.
progress-difficulty-why-success-above = Erfolg { $success } % lag über dem Ziel von { $target } %.
progress-difficulty-why-success-below = Erfolg { $success } % lag unter dem Ziel von { $target } %.
progress-difficulty-why-success-at = Erfolg { $success } % lag genau beim Ziel von { $target } %.
progress-difficulty-why-no-rate = Keine Erfolgsquote aus der letzten Sitzung: gleich gelassen.
progress-difficulty-why-felt-too-hard = Die Person fand es zu schwer.
progress-difficulty-why-felt-too-easy = Die Person fand es zu leicht.
progress-difficulty-held-highest = Beim Höchstwert der Therapie gehalten.
progress-difficulty-held-lowest = Beim Mindestwert der Therapie gehalten.
progress-numbers-caption = Die Zahlen des Diagramms, neueste zuerst
progress-col-started = Beginn
progress-col-difficulty = Schwierigkeit
progress-col-change = Änderung
progress-col-success = Erfolg
progress-col-why = Grund

## Technische Namen

progress-technical-summary = Details: die technischen Namen dieser Messgrößen
progress-technical-caption = So benennen sie die zweite Kopfzeile der Tabellenkalkulation und der FHIR-Export
progress-col-data-name = Name in den Daten
progress-col-technical = Technischer Name

progress-definitions-summary = Was jedes Maß misst, und seine Quelle
progress-col-definition = Definition
progress-col-source = Quelle

## Liste der Sitzungen und Druck

progress-sessions-title = Sitzungen ({ $count })
progress-col-exercise = Übung
progress-col-ended = Wie sie endete
progress-col-checkin = Angaben des Patienten
progress-col-results = Ergebnisse und Aufzeichnung
progress-col-notes = Notizen des Therapeuten
progress-each-exercise = Jede Übung
progress-replay = Wiedergabe
progress-note-session = die Sitzung vom { $at }
progress-range = Sitzungen vom { $from } bis { $to }
progress-range-none = noch keine Sitzung
progress-zone-utc = Zeiten in UTC
progress-zone = Zeiten in { $zone } und UTC
progress-clinic-unnamed = Name der Klinik nicht festgelegt
progress-print-of = Verlauf von { $name }
progress-printed = gedruckt am { $day }
progress-print = Einseitige Zusammenfassung drucken
progress-download = Tabelle herunterladen (CSV; { $zone })
progress-download-assessments = Standardtests herunterladen (CSV; { $zone })
progress-scales-failed = Die klinischen Skalen konnten nicht angezeigt werden: { $error }

## Der Standardtest (Issue 42): jedes Mal derselbe kurze Test, zuerst auf der Seite

progress-assessment-title = Standardtest
progress-assessment-intro = Jedes Mal derselbe kurze Test, ohne Hilfe des Lenkrads (Protokoll { $protocol }). Der neueste zuerst. Er steht getrennt von den Übungen und ihren Verläufen.
progress-assessment-none = Noch kein Standardtest. Legen Sie im Therapieplan fest, wie oft er stattfindet (Test, alle so viele Tage).
progress-assessment-col-measure = Teil und Messwert
progress-assessment-row = { $part }: { $measure }
progress-assessment-part-range = Aktiver Bewegungsumfang
progress-assessment-part-tracking-slow = Folgen, langsam
progress-assessment-part-tracking-medium = Folgen, mittel
progress-assessment-part-tracking-fast = Folgen, schnell
progress-assessment-part-steps = Sprünge
progress-assessment-part-strength = Kraft

## Echte Veränderung, vom Messrauschen unterschieden (Issue 42): der neueste Test gegen den ersten

progress-assessment-col-change = Veränderung seit dem ersten ({ $day })
progress-assessment-col-change-none = Veränderung seit dem ersten
progress-assessment-band = ± { $band } ({ $source })
progress-assessment-verdict-better = besser
progress-assessment-verdict-worse = schlechter
progress-assessment-verdict-changed = verändert (keine Richtung ist besser)
progress-assessment-verdict-within-noise = im Bereich des Messrauschens
progress-assessment-verdict-no-noise-figure = noch kein Wert für das Messrauschen, daher keine Bewertung
progress-assessment-source-own = Rauschband aus den eigenen { $repeats } Tests des Patienten
progress-assessment-source-cohort = Rauschband aus simulierten Patienten mit demselben Test
progress-assessment-source-published = Rauschband aus einer veröffentlichten Studie
progress-assessment-source-short-own = eigen
progress-assessment-source-short-cohort = Kohorte
progress-assessment-source-short-published = Studie
progress-assessment-change-sr = Veränderung seit dem ersten Test: { $change }. Rauschband plus oder minus { $band } ({ $source }). Bewertung: { $verdict }.
progress-assessment-change-sr-none = Veränderung seit dem ersten Test: { $change }. Noch kein Wert für das Messrauschen, daher keine Bewertung.
progress-assessment-change-none = Bisher nur ein Test: noch nichts zu vergleichen.
progress-assessment-change-missing = Keine Veränderung anzuzeigen: Der Messwert fehlt im neuesten oder im ersten Test.
progress-assessment-noise-note = Besser oder schlechter nur, wenn die Veränderung größer ist als das Messrauschen (± kleinste echte Veränderung, MDC95). Ab 6 Tests ist das Rauschband das eigene des Patienten (eigen); davor stammt es von simulierten Patienten (Kohorte) oder aus einer veröffentlichten Studie (Studie).
