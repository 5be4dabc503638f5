# The console's shell: the page title, header, navigation, language menu, sign-in, the
# password screens, a patient's tabs and errors. Clinicians' words: plain and clinical.

app-title = telerehab — therapist console
app-loading = Loading…
app-nav =
    .aria-label = Main
app-nav-clinic = Clinic
app-nav-names = Names
app-nav-audit = Audit log
app-nav-change-password = Change password
app-nav-logout = Log out
app-language-label = Language
# The logged-in account in the header: e-mail and role.
app-who = { $email } ({ $role ->
        [admin] administrator
       *[other] therapist
    })
app-back-to-patients = Back to the patients

## Sign-in

app-login-title = Log in
app-login-email = E-mail
app-login-password = Password
app-login-submit = Log in

## Passwords

app-password-title = Change your password
app-password-title-forced = Choose your own password
app-password-forced = You logged in with a one-time password. Choose your own before you continue.
app-password-one-time = One-time password
app-password-current = Current password
app-password-new = New password
app-password-rules = (at least 10 characters, not only spaces, not your e-mail, not a common password or pattern; a few unrelated words are best)
app-password-repeat = New password again
app-password-submit = Change the password
app-password-differ = The two new passwords differ.

## A patient's page

# The heading of a patient's page; $name is the pseudonym or the clinic's name for them.
app-patient-title = Patient { $name }
app-tabs-label = Patient
app-tab-live = Live
app-tab-progress = Progress
app-tab-replay = Replay
app-tab-prescribe = Prescribe
app-tab-exercises = Exercises
app-tab-stations = Stations and pairing
