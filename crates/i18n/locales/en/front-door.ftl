# The first-run pages and today's page (crates/station/src/front_door). Plain words, short
# sentences (at most 12 words). The wheel is the patient's control: turn, press, hold.

## Choosing the language (each language is shown in its own name)
front-language-title = Choose your language
front-language-how = Turn the wheel to choose. Press a button.

## Pairing with the clinic
front-pairing-title = Welcome
front-pairing-card = Your clinic's pairing card is here.
front-pairing-card-press = Press a wheel button to connect.
front-pairing-card-bad = The clinic's pairing card cannot be read. Please call your clinic.
front-pairing-ask-clinic = This computer does not know your clinic yet.
front-pairing-call-clinic = Please call your clinic. They will set it up.
front-pairing-code-intro = Enter the code from your clinic's letter.
front-pairing-code-how = Turn the wheel to choose a sign. Press to take it.
front-pairing-code-back = Hold the button to take back a sign.
front-pairing-code-label = Pairing code
front-pairing-address-label = Clinic address
front-pairing-keys = Keyboard: type, Enter to go on, Tab to change the address.
front-connecting-title = Connecting to your clinic
front-connecting-wait = Please wait.
front-connected = This computer is now connected to your clinic.

## What went wrong while pairing (the code stays on the page)
front-error-code = This code is not right. Check it on the clinic's letter.
front-error-code-length = The code has 8 signs. Check it on the clinic's letter.
front-error-unreachable = The clinic cannot be reached. Check the internet, then press again.
front-error-refused = The clinic did not accept this code. Check it on the letter.
front-error-not-authentic = The answer was not from your clinic. Nothing was saved.
front-error-save = Connected, but this computer could not save it. Call your clinic.
front-error-other = Connecting did not work. Please call your clinic.
front-error-no-address = Type the clinic's address first.

## Today's page
front-today-title = Today's session
front-today-summary = { $exercises ->
    [one] 1 exercise
   *[other] { $exercises } exercises
}, about { $minutes ->
    [one] 1 minute
   *[other] { $minutes } minutes
} with rests
front-today-no-plan = Your clinic has not sent your plan yet.
front-today-unbuildable = An exercise this computer cannot show
front-today-checking = Checking the wheel…
front-today-how = Turn the wheel to choose. Press a button.
front-today-wait-wheel = You can start once the wheel is ready.
front-today-start = Start
front-today-practice = Practice
front-today-close = Close
front-today-keys = Keyboard: Space starts, F2 practice, Esc closes.
front-today-offline = Your clinic cannot be reached now. Your session is kept here.
front-today-message = A message from your therapist:

## The device check, in plain words
front-device-no-wheel = No wheel found. Plug it in and switch it on.
front-device-wheel = Wheel: { $name }
front-device-wheel-unknown = Its force stays low until your clinic sets it.
front-device-simulated = Wheel: a practice wheel on the screen
front-device-permission = This computer cannot use the wheel yet. Please call your clinic.
front-device-arm-sensors = Arm sensors: { $names }
front-device-no-arm-sensors = No arm sensors. The session runs without them.

## The practice (try-out)
front-practice-banner = Practice · nothing is saved
