# Die Unterstützung einer Übung im Verordnungsformular.

assist-label = Unterstützung
assist-mode-station = Einstellung der Station (hier nichts verordnet)
assist-mode-none = Keine: Das Lenkrad hilft nicht
assist-mode-resist = Widerstand: Feder und Dämpfer gegen die Bewegung (Kräftigung)
assist-mode-motion = Bewegung: Das Lenkrad führt die Hände auf der idealen Bahn
assist-mode-force = Kraft: Das Lenkrad fügt einen Anteil der eigenen Kraft des Patienten hinzu
assist-mode-hybrid = Hybrid: frei innerhalb eines Bereichs, an seinen Rändern zurückgeführt
assist-mode-assist_as_needed = Nach Bedarf: Hilfe, die bei Fehlern wächst und sonst nachlässt
assist-level-guidance = Stufe: Anteil der Drehmomentgrenze, den die Führung nutzen darf
assist-level-effort = Stufe: Anteil der Kraft des Patienten, den das Lenkrad hinzufügt
