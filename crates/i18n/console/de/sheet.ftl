# Die Wörter der Tabelle der Messwerte (crates/hub-care/src/sheet_words.rs): die erste
# Kopfzeile und die Wörter für Menschen; die zweite Kopfzeile behält die technischen Namen.

sheet-col-patient = Patientin/Patient
sheet-col-session = Sitzungskennung
sheet-col-started-local = Beginn (Ortszeit, { $zone })
sheet-col-started-utc = Beginn (UTC)
sheet-col-exercises = Übungen
sheet-col-ended = Wie sie endete
sheet-col-as-prescribed = Wie verordnet
sheet-col-pain = Schmerz danach (0–10)
sheet-col-effort = Anstrengung danach (Borg CR10 0–10)
sheet-col-felt = Wie schwer es sich anfühlte
sheet-yes = ja
sheet-no = nein

# Die Tabelle des Standardtests: eine Zeile je Messgröße eines Testteils.
sheet-assessment-col-protocol = Protokollversion
sheet-assessment-col-seed = Startwert der Zielsprünge
sheet-assessment-col-part-key = Teil (Code)
sheet-assessment-col-part = Teil
sheet-assessment-col-measure-key = Messgröße (Code)
sheet-assessment-col-measure = Messgröße
sheet-assessment-col-value = Wert
sheet-assessment-col-unit = Einheit
