# Die Ergebnisse einer Sitzung Übung für Übung.

exercises-ended = Beendet
exercises-running = Läuft noch
exercises-heading = Sitzung vom { $when }, Übung für Übung
exercises-back = Zurück zum Verlauf
exercises-none = Keine Ergebnisse pro Übung: Die Station dieser Sitzung war älter als diese Funktion, oder die Sitzung endete nicht regulär.
exercises-column = { $n }. { $name }
exercises-time-cell = { $active } von { $prescribed }
exercises-caption = Die Ergebnisse jeder einzelnen Übung; die Summen der Sitzung stehen im Verlauf.
exercises-col-result = Ergebnis
exercises-time-row = Zeit: aktiv von verordnet (s)
exercises-sweep-spring = Haptik-Durchlauf: Federsteifigkeit dieser Stufe
exercises-sweep-damper = Haptik-Durchlauf: Dämpfung dieser Stufe
exercises-sweep-inertia = Haptik-Durchlauf: zusätzliches Gewicht (Trägheit) dieser Stufe
exercises-sweep-frequency = Haptik-Durchlauf: wie schnell sich der Zeiger bewegt (Frequenz) auf dieser Stufe
