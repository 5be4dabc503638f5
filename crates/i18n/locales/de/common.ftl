common-yes = Ja
common-no = Nein
common-ok = OK
common-back = Zurück
common-minutes = { $minutes ->
    [one] { $minutes } Minute
   *[other] { $minutes } Minuten
}
