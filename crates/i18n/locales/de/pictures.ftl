# Bildunterschriften (crates/station/src/render/pictures). Jede wird auch gesprochen.
picture-road-winding = Drehen Sie das Lenkrad nach links und rechts.
picture-road-straight = Halten Sie das Auto in der Mitte der Straße.
picture-road-zigzag = Folgen Sie der Zickzack-Straße mit dem Lenkrad.
picture-road-tightening = Die Kurve wird enger. Lenken Sie etwas mehr.
picture-road-sharp-turns = Lenken Sie um die scharfen Ecken.
picture-road-s-bend = Lenken Sie durch die S-Kurve.
picture-road-lane-change = Wechseln Sie die Spur. Bleiben Sie dann dort.
picture-road-slalom = Lenken Sie zwischen den Hütchen hindurch.
picture-dial = Drehen Sie das Lenkrad. Die schwarze Nadel folgt der roten.
picture-strength = Drücken Sie fest gegen das Lenkrad. Es bewegt sich nicht.
picture-rest = Ruhen Sie sich aus. Lassen Sie das Lenkrad los.
picture-pause = Pause. Lassen Sie sich Zeit.
picture-buttons = Drücken Sie eine Taste am Lenkrad.
picture-yes = Ja
picture-no = Nein
picture-done = Gut gemacht. Das war alles für heute.
picture-today = Ihre Übungen für heute.
