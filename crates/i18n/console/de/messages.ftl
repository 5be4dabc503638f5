# Nachrichten an den Patienten.

messages-empty = Die Nachricht ist leer.
messages-too-long = Die Nachricht ist zu lang: { $chars } Zeichen, höchstens { $max }.
messages-control = Die Nachricht enthält einen Zeilenumbruch oder ein anderes Steuerzeichen: Schreiben Sie sie in eine Zeile.
messages-sent-at = gesendet { $when }
messages-not-seen = noch nicht gesehen
messages-seen-at = gesehen { $when }
messages-none = Noch keine Nachrichten.
messages-count = { $chars } von { $max } Zeichen
messages-label = Eine Nachricht an den Patienten, in großer Schrift zu Beginn seiner nächsten Sitzung angezeigt
messages-send = Nachricht senden
messages-refresh = Aktualisieren
messages-sent = Gesendet: Der Patient sieht sie zu Beginn seiner nächsten Sitzung.
messages-heading = Nachrichten an den Patienten
