# Ablehnungen des Hubs in der Sprache der Konsole (crates/hub/console/api.js refusalWords).

## Ablehnungen des Hubs in der Sprache der Konsole; die Worte des Hubs (Feld oder Sache)
## folgen auf Englisch, wo sie etwas sagen.

api-error-400 = Der Hub hat das nicht angenommen.
api-error-401 = Nicht angemeldet, oder E-Mail oder Passwort falsch.
api-error-403 = Das darf nur eine Administratorin oder ein Administrator der Klinik.
api-error-404 = Nicht gefunden. Vielleicht wurde es entfernt.
api-error-409 = Das widerspricht dem, was der Hub gespeichert hat.
api-error-413 = Das ist zu groß für den Hub.
api-error-415 = Der Hub hat diese Anfrage nicht verstanden.
api-error-422 = Abgelehnt: außerhalb der erlaubten Werte oder der Sicherheitsgrenzen.
api-error-429 = Zu viele Versuche. Bitte in { $seconds } s erneut versuchen.
api-error-503 = Der Hub ist ausgelastet. Bitte in { $seconds } s erneut versuchen.
api-error-other = Auf dem Hub ist etwas schiefgegangen. Sein Protokoll enthält die Einzelheiten.

## Warum der Hub abgelehnt hat, nach seinem Code (crates/hub-store/src/refusal.rs): je ein klarer Satz.
## $field und $what kommen schon in den Worten der Konsole.

api-why-field-refused = Der Hub hat das Feld „{ $field }“ nicht angenommen.
api-why-empty = Das Feld „{ $field }“ ist leer. Bitte ein paar Worte schreiben.
api-why-too-long = Das Feld „{ $field }“ ist zu lang: höchstens { $max } Zeichen.
api-why-control-characters = Das Feld „{ $field }“ enthält unsichtbare Steuerzeichen. Bitte nur einfachen Text.
api-why-missing = Das Feld „{ $field }“ fehlt.
api-why-not-one-of = Das Feld „{ $field }“ hat keinen der möglichen Werte.
api-why-out-of-range = Das Feld „{ $field }“ muss zwischen { $min } und { $max } liegen.
api-why-bad-date = Das Feld „{ $field }“ ist kein gültiger Tag. Bitte als Jahr-Monat-Tag schreiben.
api-why-future-date = Das Feld „{ $field }“ liegt in der Zukunft. Bitte den Tag wählen, an dem es war.
api-why-bad-id = Die Adresse nennt eine Kennung für „{ $field }“, die es nicht geben kann.
api-why-bad-email = Das ist keine E-Mail-Adresse. Sie sieht aus wie name@klinik.de.
api-why-bad-pseudonym = Bis zu { $max } Buchstaben, Ziffern, Punkte, Binde- oder Unterstriche. Nie ein Name.
api-why-password-invisible = Das Passwort enthält unsichtbare Zeichen. Bitte nur sichtbare Zeichen tippen.
api-why-password-length = Das Passwort braucht mindestens { $min } Zeichen.
api-why-password-spaces = Das Passwort besteht fast nur aus Leerzeichen.
api-why-password-email = Das Passwort darf nicht Ihre E-Mail-Adresse sein.
api-why-password-common = Dieses Passwort gehört zu den häufigsten. Bitte ein anderes wählen.
api-why-password-repeated = Das Passwort wiederholt sich. Bitte mindestens { $min } verschiedene Zeichen verwenden.
api-why-password-sequence = Das Passwort ist eine Folge wie abcdef oder 123456. Bitte ein anderes wählen.
api-why-password-guessable = Das Passwort ist zu leicht zu erraten. Ein paar Wörter ohne Zusammenhang sind gut.
api-why-password-same = Das neue Passwort muss sich vom bisherigen unterscheiden.
api-why-snooze-past = Eine Zurückstellung muss in der Zukunft enden. Bitte einen späteren Tag wählen.
api-why-not-found = { $what } ist nicht da. Vielleicht wurde es entfernt.
api-why-already-exists = { $what } gibt es schon. Bitte etwas anderes wählen.
api-why-no-endpoint = Diese Seite gibt es auf dem Hub nicht.
api-why-login-refused = E-Mail oder Passwort falsch.
api-why-log-in-first = Bitte zuerst anmelden.
api-why-one-time-password = Bitte zuerst Ihr Einmalpasswort ändern.
api-why-admin-only = Das darf nur eine Administratorin oder ein Administrator der Klinik.
api-why-own-care-only = Sie können Patientinnen und Patienten nur in Ihre eigene Betreuung aufnehmen. Die Administration kann eine andere Therapeutin oder einen anderen Therapeuten wählen.
api-why-no-therapist-email = Keine Therapeutin und kein Therapeut hat diese E-Mail-Adresse.
api-why-throttled = Zu viele Versuche. Bitte in { $seconds } s erneut versuchen.
api-why-alert-gone = Dieser Hinweis ist erledigt. Bitte die Fallliste neu laden.
api-why-alert-changed = Seit der Anzeige ist etwas Neues passiert. Bitte noch einmal ansehen. Nichts wurde gespeichert.
api-why-regimen-shape = Der Hub konnte diese Verordnung nicht lesen.
api-why-regimen-text = Der Text der Verordnung hat einen Fehler in Zeile { $line }.
api-why-regimen-unreadable = Der Text der Verordnung kann nicht gelesen werden.
api-why-regimen-exercise = Übung { $exercise } hat einen Wert außerhalb des erlaubten Bereichs.
api-why-above-wheel = Übung { $exercise } verlangt mehr Kraft, als das Lenkrad dieser Person gibt: höchstens { $max_nm } N·m.
api-why-recording-not-arrived = Die Aufzeichnung dieser Sitzung ist noch nicht vollständig angekommen.
api-why-recording-unreadable = Die Aufzeichnung dieser Sitzung kann auf dem Hub nicht gelesen werden.
api-why-recording-too-large = Diese Aufzeichnung hat { $mb } MB. Der Hub spielt höchstens { $max_mb } MB ab.
api-why-replay-pending = Ihre letzte Wiedergabe wird noch vorbereitet. Bitte warten, bis sie erscheint.
api-why-replay-busy = Der Hub bereitet gerade andere Wiedergaben vor. Bitte gleich noch einmal versuchen.
api-why-live-streams = Höchstens { $max } Live-Ansichten gleichzeitig. Bitte zuerst eine schließen.
api-why-unknown-language = Die Konsole hat keine Worte in dieser Sprache.
api-why-unknown-time-zone = Der Hub kennt diese Zeitzone nicht.
api-why-body-malformed = Der Hub konnte diese Anfrage nicht lesen.
api-why-body-too-large = Das ist zu groß für den Hub.
api-why-body-not-json = Der Hub hat diese Anfrage nicht verstanden.
api-why-internal = Auf dem Hub ist etwas schiefgegangen. Sein Protokoll enthält die Einzelheiten.

## Die Felder und Dinge, die eine Ablehnung nennt.

api-field-text = Text
api-field-note = Notiz
api-field-password = Passwort
api-field-email = E-Mail-Adresse
api-field-pseudonym = Pseudonym
api-field-snooze-until-ms = Ende der Zurückstellung
api-field-setting = Einstellung
api-field-scale = Skala
api-field-assessed-on = Tag der Erhebung
api-field-score = Punktwert
api-field-affected-blocks-per-min = Blöcke pro Minute, betroffene Seite
api-field-unaffected-blocks-per-min = Blöcke pro Minute, nicht betroffene Seite
api-field-sort = Reihenfolge
api-field-alert = Hinweis
api-field-query = Suche
api-field-key = Hinweis
api-field-regimen = Verordnung
api-field-path = Adresse
api-field-patient-id = Patientin oder Patient
api-field-session-id = Sitzung
api-field-station-id = Station
api-field-scale-id = Erhebung
api-thing-patient = Diese Patientin oder dieser Patient
api-thing-station = Diese Station
api-thing-session = Diese Sitzung
api-thing-therapist = Diese Therapeutin oder dieser Therapeut
api-thing-scale = Diese Erhebung
api-thing-pseudonym = Dieses Pseudonym
api-thing-email = Diese E-Mail-Adresse
api-thing-clinical-scale = Diese Erhebung
api-thing-station-or-certificate = Diese Station
