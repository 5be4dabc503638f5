# Die Mails des Hubs an das Klinikpersonal (crates/hub-care/src/pain_mail.rs), in der
# Konsolensprache der Empfänger. Eine Schmerz-Mail enthält keine Gesundheitsdaten.

mail-pain-subject = telerehab: { $pseudonym } hat starke Schmerzen gemeldet
mail-pain-reported = { $pseudonym } hat nach einer Sitzung Schmerzen auf oder über der Grenze Ihrer Klinik gemeldet.
mail-pain-told = Die Station hat gesagt: aufhören, ausruhen und die Klinik anrufen.
mail-pain-no-more = Heute bietet sie keine Übungen mehr an, außer Sie erlauben es.
mail-pain-open = Zur Seite der Person:
mail-pain-page = die Seite der Person in der telerehab-Konsole
mail-pain-signature = telerehab-Hub (diese Mail enthält keine Gesundheitsdaten; siehe Konsole)
