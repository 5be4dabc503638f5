# The Windows installer's own words (packaging/windows/telerehab.nsi; scripts/package-windows.sh
# turns them into the installer's language strings). NSIS translates its standard pages itself.
# Plain words, short sentences (at most 12 words); one line each (the script reads one line).
installer-shortcut-comment = Your driving exercises from the clinic.
installer-finish = telerehab is ready. Plug in the wheel. Then open telerehab from the Start menu.
