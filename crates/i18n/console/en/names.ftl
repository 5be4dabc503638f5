# The clinic's names for its pseudonyms, held in this browser only (crates/hub/console/
# names.js, names-page.js).

names-display = { $name } ({ $pseudonym })
names-problem-cells = Line { $line }: needs the pseudonym, then the name.
names-problem-long = Line { $line }: the name is longer than { $max } characters.
names-problem-twice = Line { $line }: { $pseudonym } is in the list twice; the first name is kept.
names-problem-many = Line { $line }: more than { $max } names; the rest are left out.
names-in-caseload = in your caseload
names-not-in-caseload = not in your caseload
names-heading = Your patients' names
names-stay-heading = Names stay on this computer
names-stay-text = The hub knows your patients by pseudonym only. You can give this browser your clinic's own list of names for them. The list stays in this browser, on this computer, and is never sent to the hub.
names-csv-text = Use a spreadsheet file (CSV) with two columns: the pseudonym, then the name. Importing a file replaces the list.
names-file-label = Import a list of names (CSV file)
names-shared-computer = On a computer others use too, forget the names when you finish.
names-forget = Forget the names on this computer
names-list-heading = Names in this browser
names-caption = { $count ->
    [one] One name, by pseudonym
   *[other] { $count } names, by pseudonym
}
names-col-pseudonym = Pseudonym
names-col-name = Name
names-col-patient = Patient
names-none = No names in this browser yet.
names-none-read = No name could be read from the file; the list is unchanged.
names-kept = { $count ->
    [one] One name kept in this browser.
   *[other] { $count } names kept in this browser.
}
names-forgotten = The names are forgotten on this computer.
