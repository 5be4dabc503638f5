# Notizen der Therapeutin / des Therapeuten zu einer Sitzung (nur für die Klinikakte).

notes-empty = Die Notiz ist leer: Schreiben Sie ein paar Worte.
notes-too-long = Die Notiz ist zu lang: { $chars } Zeichen, höchstens { $max }.
notes-control = Die Notiz enthält Steuerzeichen: nur reiner Text.
notes-by = { $by }, { $when }
notes-by-gone = eine Fachkraft, die nicht mehr in der Klinik ist
notes-none = Noch keine Notiz.
notes-add-label = Notiz zu { $session } hinzufügen (für die Klinikakte; der Patient sieht sie nicht)
notes-save = Notiz speichern
notes-saved = Notiz gespeichert.
notes-cell = Notiz
notes-heading = Notizen zu dieser Sitzung
notes-this-session = dieser Sitzung
