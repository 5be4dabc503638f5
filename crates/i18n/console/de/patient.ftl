# Die Stationseinstellungen des Patienten im Verordnungsformular (Tabelle [patient] des Plans).

patient-legend = Station des Patienten
patient-intro = Diese Einstellungen gelten mit der Verordnung: Die Station übernimmt sie ab der nächsten Sitzung.
patient-language-label = Sprache der Bildschirme und der Stimme an der Station
patient-language-station = Wie an der Station gewählt
patient-side-legend = Vernachlässigte Seite (Neglect)
patient-side-none = Keine
patient-side-none-note = Die Bildschirme sind wie üblich aufgebaut.
patient-side-left = Links
patient-side-left-note = Nichts Wichtiges im linken Bildschirmteil. Vor jeder Übung ein pulsierender orangefarbener Balken am linken Rand und ein gesprochenes „Schauen Sie hierher“ von links.
patient-side-right = Rechts
patient-side-right-note = Nichts Wichtiges im rechten Bildschirmteil. Vor jeder Übung ein pulsierender orangefarbener Balken am rechten Rand und ein gesprochenes „Schauen Sie hierher“ von rechts.
patient-speech-label = Den Hauptsatz jeder Seite vorlesen
patient-volume-label = Lautstärke der Stimme, %
patient-countdown-label = Nach einer Pause die nächste Übung nach diesem Countdown starten, Sekunden
patient-countdown-wait = auf den Patienten warten
patient-saved-words = An der Station: { $language }; vernachlässigte Seite: { $side ->
    [left] links
    [right] rechts
   *[none] keine
}; Sprachausgabe { $speech ->
    [off] aus
   *[on] an, Lautstärke { $volume } %
}; nach einer Pause: { $countdown ->
    [count] die nächste Übung startet nach { $seconds } s
   *[wait] die Station wartet auf den Patienten
}.
