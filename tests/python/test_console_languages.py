"""The therapist console in every language (issue 40), in a real browser (Chromium, headless),
on the caseload clinic of test_console_caseload (pain, a decline, an unplugged wheel, a
withdrawn station, a patient training as prescribed):

- (axe-core in every language is test_console_axe.py's;)
- the pseudo-locale leaves no English sentence on the caseload, the progress tab and the
  alert thresholds: every visible text node differs from the English render, or is a number,
  a date, a pseudonym or a name;
- a browser whose language is German gets the console in German before anyone chose (the hub's
  refusals too), and the language a therapist chooses is kept on the hub and survives a new
  sign-in in that browser.

No test waits on English text: screens are recognised by ids and data attributes, words are
compared with the catalogues the hub serves (/console/l10n/<tag>.ftl). Screenshots (1366×768)
of the caseload and the progress tab in each language go to $TELEREHAB_ARTIFACTS; the ones in
docs/screenshots were looked at."""

import json
import os
import re
import time
from pathlib import Path

import pytest
from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select

from axe_audit import assert_no_violations_in_language, english_left, use_language, visible_texts
from test_console_browser import serve_clinic, shot, telerehab, wait
from test_console_caseload import seed

PASSWORD = "a morning in every language"
LANGUAGES = ["de", "es", "zh", "en-XA"]  # besides English


def chromium(lang="en-US"):
    """A headless Chromium whose language (navigator.languages) is `lang`."""
    opts = webdriver.ChromeOptions()
    opts.binary_location = "/usr/bin/chromium"
    for arg in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--window-size=1366,768",
                f"--lang={lang}"):
        opts.add_argument(arg)
    opts.add_experimental_option("prefs", {"intl.accept_languages": lang})
    opts.accept_insecure_certs = True
    return webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=opts)


@pytest.fixture(scope="module")
def clinic(tmp_path_factory):
    with serve_clinic(tmp_path_factory.mktemp("languages")) as served:
        data = served["tmp"] / "clinic"
        for pseudonym in ("P-0101", "P-0102", "P-0103", "P-0104"):
            telerehab("hub", "patient", "add", "--data", str(data), "--pseudonym", pseudonym)
        seed(data / "hub.db", int(time.time() * 1000))
        yield served


@pytest.fixture(scope="module")
def browser(clinic):
    """An English browser, logged in (the one-time password changed)."""
    d = chromium("en-US")
    d.set_window_size(1366, 768)
    d.get(clinic["web"] + "/")
    wait(d, lambda d: d.find_elements(By.ID, "email"))[0].send_keys("ana@clinic.example")
    d.find_element(By.ID, "password").send_keys(clinic["password"])
    d.find_element(By.CSS_SELECTOR, "#login button").click()
    wait(d, lambda d: d.find_elements(By.ID, "password-form"))
    d.find_element(By.ID, "current-password").send_keys(clinic["password"])
    for field in ("new-password", "repeat-password"):
        d.find_element(By.ID, field).send_keys(PASSWORD)
    d.find_element(By.CSS_SELECTOR, "#password-form button").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#caseload tbody tr[data-pseudonym]"))
    yield d
    d.quit()


def fetch(d, method, path, body=None):
    """The hub's answer to `method path` from inside the page (its cookie): (status, text)."""
    return d.execute_async_script(
        "const [m, p, b, done] = arguments;"
        "const init = {method: m, credentials: 'same-origin', headers: {}};"
        "if (b !== null) { init.headers['Content-Type'] = 'application/json'; init.body = b; }"
        "fetch(p, init).then(async r => done([r.status, await r.text()]));",
        method, path, None if body is None else json.dumps(body))


def catalogue(d, tag):
    """The console's messages of `tag` as the hub serves them: {id: the value's first line}
    (for a message on one line: its text)."""
    status, text = fetch(d, "GET", f"/console/l10n/{tag}.ftl")
    assert status == 200, text
    return dict(m.groups() for m in re.finditer(r"^([a-z][a-z0-9-]*) = (.*)$", text, re.M))


def patient_id(d, pseudonym):
    status, text = fetch(d, "GET", "/api/patients")
    return next(p["id"] for p in json.loads(text) if p["pseudonym"] == pseudonym)


def open_screen(d, web, screen, pid):
    """Opens one of the screens checked in every language and waits for it."""
    ready = {
        "caseload": ("#/patients", "#caseload tbody tr[data-pseudonym]"),
        "progress": (f"#/patients/{pid}/progress", "#tab[data-sessions]"),
        "attention-settings": ("#/attention-settings", "#settings-form [data-key]"),
        "password": ("#/password", "#password-form"),
    }[screen]
    d.get(f"{web}/{ready[0]}")
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, ready[1]))
    d.execute_script("window.scrollTo(0, 0)")


# Opens what a therapist can open on these screens (the notes load from the hub: left shut).
OPEN_DETAILS = "document.querySelectorAll('#app details:not(.session-notes)').forEach(x => x.open = true)"

# What other modules draw (console-words-b's areas: the messages panel, the clinical scales,
# the notes, the session charts' number tables), checked by their own tests.
OTHERS = "#messages, #scales, .session-notes, .kind-group .grid"


def test_the_pseudo_locale_leaves_no_english_sentence_on_the_caseload_and_progress(clinic, browser):
    d, web = browser, clinic["web"]
    pid = patient_id(d, "P-0042")
    screens = ["caseload", "progress", "attention-settings"]
    en = {}
    for screen in screens:
        open_screen(d, web, screen, pid)
        d.execute_script(OPEN_DETAILS)
        en[screen] = visible_texts(d, OTHERS)
    use_language(d, "en-XA")
    try:
        for screen in screens:
            open_screen(d, web, screen, pid)
            d.execute_script(OPEN_DETAILS)
            pseudo = visible_texts(d, OTHERS)
            assert len(pseudo) > 20, (screen, pseudo)
            left = english_left(en[screen], pseudo)
            assert not left, f"English left on {screen} in en-XA: {left}"
            # Every accented letter is the pseudo-locale's: the page is not simply English.
            assert sum("~" in t for t in pseudo) > len(pseudo) // 3, (screen, pseudo[:20])
    finally:
        use_language(d, "en")


def test_the_english_check_finds_an_english_sentence():
    """The check above can fail: a sentence the English render has is found; a date, a
    pseudonym and a pseudo-locale text are not."""
    en = ["Patients", "6 Dec 2026, 09:30", "P-0042", "Ŧîɱé îñ ľåñé~~~~"]
    assert english_left(en, ["Patients", "6 Dec 2026, 09:30", "P-0042", "Ƥåŧîéñŧš~~~"]) == ["Patients"]


def test_a_german_browser_gets_german_and_a_chosen_language_survives_a_new_sign_in(clinic, browser):
    d = chromium("de-DE")
    try:
        web = clinic["web"]
        d.get(web + "/")
        wait(d, lambda d: d.find_elements(By.ID, "login"))
        assert d.execute_script("return navigator.languages[0]").startswith("de")
        assert d.execute_script("return document.documentElement.lang") == "de"
        german = catalogue(d, "de")
        assert d.find_element(By.CSS_SELECTOR, "#app h1").text == german["app-login-title"]
        assert d.find_element(By.CSS_SELECTOR, "label[for=email]").text == german["app-login-email"]

        # The hub's refusal in German: the catalogue's words for why, never the hub's English.
        d.find_element(By.ID, "email").send_keys("ana@clinic.example")
        d.find_element(By.ID, "password").send_keys("not the passphrase")
        d.find_element(By.CSS_SELECTOR, "#login button").click()
        wait(d, lambda d: d.find_element(By.ID, "login-error").text)
        assert d.find_element(By.ID, "login-error").text == german["api-why-login-refused"]
        for field in ("email", "password"):
            d.find_element(By.ID, field).clear()

        def log_in():
            d.find_element(By.ID, "email").send_keys("ana@clinic.example")
            d.find_element(By.ID, "password").send_keys(PASSWORD)
            d.find_element(By.CSS_SELECTOR, "#login button").click()
            wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#caseload tbody tr[data-pseudonym]"))

        log_in()
        # The other tests chose English for this therapist: back to "never chose".
        status, _ = fetch(d, "PUT", "/api/me/language", {"language": None})
        assert status == 200
        d.refresh()
        wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#caseload tbody tr[data-pseudonym]"))
        assert d.execute_script("return document.documentElement.lang") == "de"
        assert d.find_element(By.CSS_SELECTOR, "#app h1").text == german["caseload-title"]

        # Spanish from the header's menu: kept on the hub, audited.
        Select(d.find_element(By.ID, "language")).select_by_value("es")
        spanish = catalogue(d, "es")
        wait(d, lambda d: d.execute_script("return document.documentElement.lang") == "es")
        wait(d, lambda d: d.find_element(By.CSS_SELECTOR, "#app h1").text == spanish["caseload-title"])
        status, text = fetch(d, "GET", "/api/me/language")
        assert json.loads(text)["language"] == "es", text
        status, text = fetch(d, "GET", "/api/audit?limit=50")
        assert any(e["action"] == "change_language" for e in json.loads(text)["entries"]), text

        # Why a field was refused, through the console's own API module: the Spanish words
        # with the field named in Spanish, none of the hub's English sentence.
        pid = patient_id(d, "P-0101")
        for body, code, field in (({"text": "   "}, "empty", "text"),
                                  ({"text": "x" * 5000}, "too-long", "text")):
            said = d.execute_async_script(
                "const [path, body, done] = arguments;"
                "import('/console/api.js').then(m => m.api('POST', path, body))"
                ".then(() => done('accepted'), e => done([e.status, e.message, e.detail]));",
                f"/api/patients/{pid}/messages", body)
            status, message, english = said
            expected = spanish[f"api-why-{code}"].replace("{ $field }", spanish[f"api-field-{field}"])
            expected = expected.replace("{ $max }", "500")
            assert status == 400 and message == expected, (said, expected)
            assert english and english not in message, said

        # A new sign-in in the German browser: Spanish, the therapist's choice.
        d.find_element(By.ID, "logout").click()
        wait(d, lambda d: d.find_elements(By.ID, "login"))
        assert d.execute_script("return document.documentElement.lang") == "de", "the browser's before sign-in"
        log_in()
        wait(d, lambda d: d.execute_script("return document.documentElement.lang") == "es")
        assert d.find_element(By.CSS_SELECTOR, "#app h1").text == spanish["caseload-title"]
        assert Select(d.find_element(By.ID, "language")).first_selected_option.get_attribute("value") == "es"

        # A language the console does not have is refused, naming the ones it has.
        status, text = fetch(d, "PUT", "/api/me/language", {"language": "fr"})
        assert status == 400 and "en, de, es, zh" in text, text
        status, text = fetch(d, "GET", "/console/l10n/fr.ftl")
        assert status == 404 and "en, de, es, zh" in text, text
    finally:
        d.quit()


@pytest.mark.parametrize("tag", LANGUAGES)
def test_screenshots_of_the_caseload_and_progress_in_each_language(clinic, browser, tag):
    """1366×768 screenshots for docs/screenshots (looked at: no clipping, overlap or boxes);
    the page is never wider than the window."""
    d, web = browser, clinic["web"]
    pid = patient_id(d, "P-0101")
    use_language(d, tag)
    try:
        for screen in ("caseload", "progress"):
            open_screen(d, web, screen, pid)
            time.sleep(0.3)
            shot(d, f"console-{screen}-{tag}-1366")
            overflow = d.execute_script("return document.documentElement.scrollWidth - window.innerWidth")
            assert overflow <= 0, f"{screen} in {tag} is {overflow} px wider than the window"
    finally:
        use_language(d, "en")


@pytest.mark.parametrize("tag", ["en"] + LANGUAGES)
def test_a_refused_password_says_why_in_the_consoles_language(clinic, browser, tag):
    """The hub's refusal on a screen, as a therapist meets it: why the new password was
    refused, in the catalogue's words of the language in force, none of the hub's English (an
    English console shows the hub's own sentence, which names the rule in full)."""
    d, web = browser, clinic["web"]
    use_language(d, tag)
    try:
        open_screen(d, web, "password", None)
        d.find_element(By.ID, "current-password").send_keys(PASSWORD)
        for field in ("new-password", "repeat-password"):
            d.find_element(By.ID, field).send_keys("abcdefghijkl")
        d.find_element(By.CSS_SELECTOR, "#password-form button").click()
        said = wait(d, lambda d: d.find_element(By.ID, "password-error").text)
        if tag == "en":
            status, text = fetch(d, "POST", "/api/me/password",
                                 {"current": PASSWORD, "new": "abcdefghijkl"})
            assert status == 400 and said == json.loads(text)["error"], (said, text)
        else:
            assert said == catalogue(d, tag)["api-why-password-sequence"], (tag, said)
        status, text = fetch(d, "GET", "/api/me")
        assert status == 200, "the refusal changed nothing: still signed in"
        shot(d, f"console-password-refused-{tag}-1366")
        if os.environ.get("TELEREHAB_SCREENSHOTS"):
            out = Path(os.environ["TELEREHAB_SCREENSHOTS"]) / tag
            out.mkdir(parents=True, exist_ok=True)
            d.save_screenshot(str(out / "password-refused.png"))
        assert_no_violations_in_language(d, "password refused", tag)
    finally:
        use_language(d, "en")
