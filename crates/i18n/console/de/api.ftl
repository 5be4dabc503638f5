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
api-error-detail = { $lead } Der Hub meldet: { $detail }
