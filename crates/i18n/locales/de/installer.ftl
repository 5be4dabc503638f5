# The Windows installer's own words (see en/installer.ftl).
installer-shortcut-comment = Ihre Fahrübungen von Ihrer Klinik.
installer-finish = telerehab ist bereit. Stecken Sie das Lenkrad ein. Dann öffnen Sie telerehab im Startmenü.
