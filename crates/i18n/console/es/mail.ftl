# Los correos del hub al personal clínico (crates/hub-care/src/pain_mail.rs), en el idioma de la
# consola de quien lo recibe. Un correo de dolor no contiene datos de salud.

mail-pain-subject = telerehab: { $pseudonym } indicó dolor fuerte
mail-pain-reported = { $pseudonym } indicó dolor en el límite de su clínica o por encima tras una sesión.
mail-pain-told = La estación le dijo que parara, descansara y llamara a la clínica.
mail-pain-no-more = Hoy no ofrece más ejercicio, salvo que usted lo permita.
mail-pain-open = Abra su página:
mail-pain-page = la página del paciente en la consola de telerehab
mail-pain-signature = hub de telerehab (este correo no contiene datos de salud; vea la consola)
