# Das Ende einer Sitzung: Ergebnisse, drei Fragen, die Seite nach starken Schmerzen.
# Einfache Wörter, kurze Sätze (höchstens 12 Wörter), „Sie“.
checkin-results-title = Gut gemacht! Sie sind fertig.
checkin-results-stopped-title = Die Sitzung hat früher aufgehört.
checkin-results-wheel-stopped = Das Lenkrad hat aufgehört zu arbeiten. Seine Kraft ist aus. Bitte sagen Sie es der Klinik.
checkin-results-exercised = Sie haben { $time } geübt.
checkin-results-lane = Sie blieben { $percent } % der Zeit in der Spur.
checkin-results-dial = Ihr Zeiger war im Mittel { $degrees }° vom Ziel entfernt.
checkin-results-better-lane = Mehr Zeit in der Spur: { $percent } % (vorher: { $was } %)
checkin-results-better-dial = Näher am Ziel: { $degrees }° (vorher: { $was }°)
checkin-results-better-time = Länger geübt: { $time } (vorher: { $was })
checkin-results-first = Beim nächsten Mal sehen Sie den Vergleich.
checkin-results-same = Etwa wie beim letzten Mal. Gut gemacht!
checkin-results-better = Besser als beim letzten Mal:
checkin-seconds = { $seconds ->
    [one] { $seconds } Sekunde
   *[other] { $seconds } Sekunden
}
checkin-pain-question = Wie stark sind Ihre Schmerzen jetzt?
checkin-pain-0 = Keine Schmerzen
checkin-pain-1 = Leichte Schmerzen
checkin-pain-2 = Etwas Schmerzen
checkin-pain-3 = Starke Schmerzen
checkin-pain-4 = Sehr starke Schmerzen
checkin-pain-5 = Schlimmste Schmerzen
# Anstrengung: die Wörter der Borg-CR10-Skala bei 0, 1, 2, 3, 4, 5, 7 und 10.
checkin-effort-question = Wie anstrengend war die Übung für Sie?
checkin-effort-0 = Überhaupt nicht
checkin-effort-1 = Sehr schwach
checkin-effort-2 = Schwach
checkin-effort-3 = Mäßig
checkin-effort-4 = Etwas stark
checkin-effort-5 = Stark
checkin-effort-7 = Sehr stark
checkin-effort-10 = Extrem stark
checkin-difficulty-question = Wie war die Übung heute?
checkin-difficulty-too-easy = Zu leicht
checkin-difficulty-just-right = Genau richtig
checkin-difficulty-too-hard = Zu schwer
checkin-chosen-score = { $value } von 10: { $words }
checkin-choose-first = Drehen Sie das Lenkrad, um zu wählen.
checkin-key-turn = Lenkrad drehen: wählen
checkin-key-press = Drücken: OK
checkin-key-hold = Halten: überspringen
checkin-key-keyboard = Tasten: links und rechts wählen, Enter OK, Esc überspringen
checkin-key-start = Drücken: drei kurze Fragen
checkin-key-close = Drücken: schließen
checkin-key-close-esc = Esc: schließen
checkin-thanks-title = Vielen Dank!
checkin-thanks-text = Ihr Therapieteam sieht Ihre Antworten.
checkin-thanks-bye = Bis zum nächsten Mal.
checkin-stop-title = Bitte hören Sie auf und ruhen Sie sich aus.
checkin-stop-rest = Ruhen Sie Ihren Arm jetzt aus.
checkin-stop-no-more = Bitte üben Sie heute nicht mehr.
checkin-stop-call = Bitte rufen Sie Ihre Klinik an: { $phone }
checkin-stop-call-clinic = Bitte rufen Sie heute Ihre Klinik an.
checkin-stop-told = Ihr Therapieteam erfährt von Ihren Schmerzen.
checkin-rest-today-title = Heute ausruhen
checkin-rest-today-pain = Sie hatten heute starke Schmerzen.
checkin-rest-today-no-exercise = Bitte üben Sie heute nicht.
checkin-rest-today-wait = Ihr Therapieteam kann das Üben wieder freigeben.
