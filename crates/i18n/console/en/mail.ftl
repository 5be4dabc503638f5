# The hub's mails to clinicians (crates/hub-care/src/pain_mail.rs), in the recipient's console
# language. A pain mail holds no health data: the pseudonym and a link only.

mail-pain-subject = telerehab: { $pseudonym } reported strong pain
mail-pain-reported = { $pseudonym } reported pain at or over your clinic's limit after a session.
mail-pain-told = The station told them to stop, rest and call the clinic.
mail-pain-no-more = It offers no more exercise today unless you allow it.
mail-pain-open = Open their page:
mail-pain-page = the patient's page in the telerehab console
mail-pain-signature = telerehab hub (this mail holds no health data; see the console)
