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
