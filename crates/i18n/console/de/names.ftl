# Die Namen der Klinik zu ihren Pseudonymen, nur in diesem Browser gespeichert.

names-display = { $name } ({ $pseudonym })
names-problem-cells = Zeile { $line }: braucht das Pseudonym, dann den Namen.
names-problem-long = Zeile { $line }: Der Name ist länger als { $max } Zeichen.
names-problem-twice = Zeile { $line }: { $pseudonym } steht doppelt in der Liste; der erste Name bleibt.
names-problem-many = Zeile { $line }: mehr als { $max } Namen; der Rest wird ausgelassen.
names-in-caseload = in Ihrer Patientenliste
names-not-in-caseload = nicht in Ihrer Patientenliste
names-heading = Die Namen Ihrer Patienten
names-stay-heading = Namen bleiben auf diesem Computer
names-stay-text = Der Hub kennt Ihre Patienten nur unter Pseudonym. Sie können diesem Browser die Namensliste Ihrer Klinik geben. Die Liste bleibt in diesem Browser auf diesem Computer und wird nie an den Hub gesendet.
names-csv-text = Verwenden Sie eine Tabellendatei (CSV) mit zwei Spalten: erst das Pseudonym, dann der Name. Der Import einer Datei ersetzt die Liste.
names-file-label = Namensliste importieren (CSV-Datei)
names-shared-computer = Auf einem Computer, den auch andere nutzen, löschen Sie die Namen, wenn Sie fertig sind.
names-forget = Namen auf diesem Computer löschen
names-list-heading = Namen in diesem Browser
names-caption = { $count ->
    [one] Ein Name, nach Pseudonym
   *[other] { $count } Namen, nach Pseudonym
}
names-col-pseudonym = Pseudonym
names-col-name = Name
names-col-patient = Patient
names-none = Noch keine Namen in diesem Browser.
names-none-read = Aus der Datei konnte kein Name gelesen werden; die Liste ist unverändert.
names-kept = { $count ->
    [one] Ein Name in diesem Browser gespeichert.
   *[other] { $count } Namen in diesem Browser gespeichert.
}
names-forgotten = Die Namen sind auf diesem Computer gelöscht.
