# Words used on many pages. Plain words, short sentences (at most 12 words).
common-yes = Yes
common-no = No
common-ok = OK
common-back = Back
common-minutes = { $minutes ->
    [one] { $minutes } minute
   *[other] { $minutes } minutes
}
