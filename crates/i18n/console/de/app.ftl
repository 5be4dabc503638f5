# Die Konsole: Seitentitel, Kopfzeile, Navigation, Sprachmenü, Anmeldung, Passwort, die
# Reiter eines Patienten, Fehler.

app-title = telerehab — Konsole für Therapeuten
app-loading = Wird geladen …
app-nav =
    .aria-label = Hauptmenü
app-nav-clinic = Klinik
app-nav-names = Namen
app-nav-audit = Protokoll
app-nav-change-password = Passwort ändern
app-nav-logout = Abmelden
app-language-label = Sprache
app-who = { $email } ({ $role ->
        [admin] Administrator
       *[other] Therapeut
    })
app-back-to-patients = Zurück zu den Patienten

## Anmeldung

app-login-title = Anmelden
app-login-email = E-Mail
app-login-password = Passwort
app-login-submit = Anmelden

## Passwörter

app-password-title = Passwort ändern
app-password-title-forced = Eigenes Passwort wählen
app-password-forced = Sie haben sich mit einem Einmalpasswort angemeldet. Wählen Sie ein eigenes, bevor Sie fortfahren.
app-password-one-time = Einmalpasswort
app-password-current = Aktuelles Passwort
app-password-new = Neues Passwort
app-password-rules = (mindestens 10 Zeichen, nicht nur Leerzeichen, nicht Ihre E-Mail-Adresse, kein gängiges Passwort oder Muster; am besten einige Wörter ohne Zusammenhang)
app-password-repeat = Neues Passwort wiederholen
app-password-submit = Passwort ändern
app-password-differ = Die beiden neuen Passwörter stimmen nicht überein.

## Seite eines Patienten

app-patient-title = Patient { $name }
app-tabs-label = Patient
app-tab-live = Live
app-tab-progress = Verlauf
app-tab-replay = Wiedergabe
app-tab-prescribe = Verordnen
app-tab-exercises = Übungen
app-tab-stations = Stationen und Kopplung

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
api-error-detail = { $lead } Der Hub meldet: { $detail }
