# Die Seiten vor der ersten Sitzung und die Seite „Heute“. Kurze Sätze, Anrede „Sie“.

## Sprache wählen
front-language-title = Wählen Sie Ihre Sprache
front-language-how = Drehen Sie das Lenkrad. Drücken Sie dann eine Taste.

## Mit der Praxis verbinden
front-pairing-title = Willkommen
front-pairing-card = Die Karte Ihrer Praxis ist da.
front-pairing-card-press = Drücken Sie eine Taste am Lenkrad. Dann verbinden wir.
front-pairing-card-bad = Die Karte Ihrer Praxis ist nicht lesbar. Bitte rufen Sie Ihre Praxis an.
front-pairing-ask-clinic = Dieser Computer kennt Ihre Praxis noch nicht.
front-pairing-call-clinic = Bitte rufen Sie Ihre Praxis an. Sie richtet ihn ein.
front-pairing-code-intro = Geben Sie den Code aus dem Brief Ihrer Praxis ein.
front-pairing-code-how = Drehen Sie das Lenkrad zum Zeichen. Drücken Sie dann.
front-pairing-code-back = Taste halten: ein Zeichen zurück.
front-pairing-code-label = Code
front-pairing-address-label = Adresse der Praxis
front-pairing-keys = Tastatur: tippen, Enter zum Weitergehen, Tab für die Adresse.
front-connecting-title = Verbindung mit Ihrer Praxis
front-connecting-wait = Bitte warten Sie.
front-connected = Dieser Computer ist jetzt mit Ihrer Praxis verbunden.

## Fehler beim Verbinden (der Code bleibt stehen)
front-error-code = Dieser Code stimmt nicht. Prüfen Sie ihn im Brief.
front-error-code-length = Der Code hat 8 Zeichen. Prüfen Sie ihn im Brief.
front-error-unreachable = Die Praxis ist nicht erreichbar. Prüfen Sie das Internet. Drücken Sie dann erneut.
front-error-refused = Die Praxis nimmt diesen Code nicht an. Prüfen Sie den Brief.
front-error-not-authentic = Die Antwort kam nicht von Ihrer Praxis. Nichts wurde gespeichert.
front-error-save = Verbunden, aber nicht gespeichert. Bitte rufen Sie Ihre Praxis an.
front-error-other = Das Verbinden hat nicht geklappt. Bitte rufen Sie Ihre Praxis an.
front-error-no-address = Tippen Sie zuerst die Adresse der Praxis.

## Heute
front-today-title = Ihre Übungen heute
front-today-summary = { $exercises ->
    [one] 1 Übung
   *[other] { $exercises } Übungen
}, etwa { $minutes ->
    [one] 1 Minute
   *[other] { $minutes } Minuten
} mit Pausen
front-today-no-plan = Ihre Praxis hat Ihren Plan noch nicht geschickt.
front-today-unbuildable = Eine Übung, die dieser Computer nicht zeigen kann
front-today-checking = Das Lenkrad wird geprüft …
front-today-how = Drehen Sie das Lenkrad. Drücken Sie dann eine Taste.
front-today-wait-wheel = Sie können beginnen, sobald das Lenkrad bereit ist.
front-today-start = Beginnen
front-today-practice = Ausprobieren
front-today-close = Schließen
front-today-keys = Tastatur: Leertaste beginnt, F2 übt, Esc schließt.
front-today-offline = Ihre Praxis ist gerade nicht erreichbar. Die Übungen bleiben hier gespeichert.
front-today-message = Eine Nachricht von Ihrer Therapeutin oder Ihrem Therapeuten:

## Die Geräte
front-device-no-wheel = Kein Lenkrad gefunden. Stecken Sie es ein und schalten Sie es an.
front-device-wheel = Lenkrad: { $name }
front-device-wheel-unknown = Seine Kraft bleibt gering, bis Ihre Praxis sie einstellt.
front-device-simulated = Lenkrad: ein Übungslenkrad auf dem Bildschirm
front-device-permission = Dieser Computer darf das Lenkrad noch nicht nutzen. Bitte rufen Sie Ihre Praxis an.
front-device-arm-sensors = Arm-Sensoren: { $names }
front-device-no-arm-sensors = Keine Arm-Sensoren. Es geht auch ohne sie.

## Üben
front-practice-banner = Probe · nichts wird gespeichert
