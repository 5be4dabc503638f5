"""axe-core over every screen of the therapist console (Chromium, headless): the login, the
forced change of the one-time password, the caseload, a patient's live view, progress, each
exercise of a session, its replay and their list, the prescribe form, the alert thresholds, the
password form, the names page, the audit log, the clinic screen with its pairing sheet and a
patient's stations, each with zero violations of WCAG 2.2 A/AA and axe's best practices, in
English and in German, Spanish, Chinese and the pseudo-locale en-XA. A screen added to the
console is added here.

With TELEREHAB_SCREENSHOTS=DIR every screen in every language is also saved as
DIR/<language>/<screen>.png (the window as the test opens it); the docs' set is
docs/screenshots/console/ (docs/SCREENS.md), looked at as a therapist between two patients
would."""

import os
import time
from pathlib import Path

import pytest
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select

from axe_audit import LANGUAGES, assert_no_violations_in_language, use_language
from test_console_browser import browser, serve_clinic, shot, telerehab, wait  # noqa: F401 (fixture)

PASSWORD = "an audited passphrase"


@pytest.fixture(scope="module")
def clinic(tmp_path_factory):
    """A clinic with patient P-0042 whose paired station ran one short simulated session."""
    # The pairing sheet needs the address stations at home connect to (not loopback).
    with serve_clinic(tmp_path_factory.mktemp("clinic"),
                      ("--public-station-address", "stations.clinic.test:47878")) as served:
        telerehab("run", "--sim", "--headless", "--speed", "max", "--duration", "4", "--seed", "2",
                  home=served["home"])
        yield served


def audit(d, screen, ready, tag="en"):
    """Wait for the screen's `ready` element, shoot it, and audit it in language `tag`."""
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, ready))
    shot(d, f"axe-{screen}-{tag}")
    if os.environ.get("TELEREHAB_SCREENSHOTS"):
        d.execute_script("document.activeElement.blur(); window.scrollTo(0, 0)")
        out = Path(os.environ["TELEREHAB_SCREENSHOTS"]) / tag
        out.mkdir(parents=True, exist_ok=True)
        d.save_screenshot(str(out / f"{screen}.png"))
    assert_no_violations_in_language(d, screen, tag)


def test_every_console_screen_has_no_accessibility_violation(clinic, browser):
    d, web = browser, clinic["web"]
    d.delete_all_cookies()
    d.get(web + "/")
    audit(d, "login", "#login")
    d.find_element(By.ID, "email").send_keys("ana@clinic.example")
    d.find_element(By.ID, "password").send_keys(clinic["password"])
    d.find_element(By.CSS_SELECTOR, "#login button").click()
    audit(d, "password-forced", "#password-forced")
    d.find_element(By.ID, "current-password").send_keys(clinic["password"])
    d.find_element(By.ID, "new-password").send_keys(PASSWORD)
    d.find_element(By.ID, "repeat-password").send_keys(PASSWORD)
    d.find_element(By.CSS_SELECTOR, "#password-form button").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#caseload tbody tr[data-pseudonym]"))
    every_screen(d, web, "en")


def every_screen(d, web, tag):
    """Audits every screen a logged-in therapist opens, the page in language `tag`."""
    audit(d, "caseload", "#caseload tbody tr[data-pseudonym]", tag)
    patient = d.find_element(By.CSS_SELECTOR, "tr[data-pseudonym='P-0042'] a").get_attribute("href").split("#")[1]
    d.get(f"{web}/#{patient}/live")
    audit(d, "live", "#live-status", tag)
    d.get(f"{web}/#{patient}/progress")
    audit(d, "progress", "#tab[data-sessions='1']", tag)
    exercises = d.find_element(By.CSS_SELECTOR, "#tab a[data-link='exercises']").get_attribute("href")
    replay = d.find_element(By.CSS_SELECTOR, "#tab a[href*='/replay/']").get_attribute("href")
    d.get(exercises)
    audit(d, "each-exercise", "#tab table", tag)
    deadline = time.time() + 40
    while True:  # the station uploads its recording just after the session
        d.get(replay)
        found = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-frames], p.error"))[0]
        if found.get_attribute("data-frames") or time.time() > deadline:
            break
        time.sleep(1)
    audit(d, "replay", "#tab[data-frames]", tag)
    d.get(f"{web}/#{patient}/replay")
    audit(d, "replay-list", "#tab a[href*='/replay/']", tag)
    d.get(f"{web}/#{patient}/prescribe")
    audit(d, "prescribe", "#rx-form", tag)
    d.get(f"{web}/#/password")
    audit(d, "password", "#password-form", tag)
    d.get(f"{web}/#/attention-settings")
    audit(d, "attention-settings", "#settings-form", tag)
    d.get(f"{web}/#/names")
    audit(d, "names", "#names-table", tag)
    d.get(f"{web}/#/audit")
    audit(d, "audit", "#audit-table", tag)
    d.get(f"{web}/#/clinic")
    audit(d, "clinic", "#new-patient", tag)
    d.find_element(By.ID, "np-pseudonym").send_keys(f"P-07{LANGUAGES.index(tag):02}")
    d.find_element(By.CSS_SELECTOR, "#new-patient button").click()
    audit(d, "pairing-sheet", "#pairing-sheet", tag)
    d.get(f"{web}/#/clinic/patients/{patient.rsplit('/', 1)[1]}")
    audit(d, "patient-stations", "#stations", tag)


@pytest.mark.parametrize("tag", [t for t in LANGUAGES if t != "en"])
def test_every_console_screen_has_no_accessibility_violation_in_each_language(clinic, browser, tag):
    d, web = browser, clinic["web"]
    d.get(web + "/")
    wait(d, lambda d: d.find_elements(By.ID, "login") or d.find_elements(By.ID, "caseload")
         or d.find_elements(By.ID, "password-forced"))
    if d.find_elements(By.ID, "login"):
        d.find_element(By.ID, "email").send_keys("ana@clinic.example")
        d.find_element(By.ID, "password").send_keys(PASSWORD)
        d.find_element(By.CSS_SELECTOR, "#login button").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#caseload tbody tr[data-pseudonym]"))
    use_language(d, tag)
    every_screen(d, web, tag)
    # The login page in the language chosen from its menu (no one logged in).
    d.delete_all_cookies()
    d.get(web + "/")
    wait(d, lambda d: d.find_elements(By.ID, "login"))
    if tag == "en-XA":  # the pseudo-locale is no therapist's language: not on the menu
        d.execute_script("const m = document.getElementById('language');"
                         "m.add(new Option('en-XA', 'en-XA'));")
    Select(d.find_element(By.ID, "language")).select_by_value(tag)
    wait(d, lambda d: d.execute_script("return document.documentElement.lang") == tag)
    audit(d, "login", "#login", tag)
    d.find_element(By.ID, "email").send_keys("ana@clinic.example")
    d.find_element(By.ID, "password").send_keys(PASSWORD)
    d.find_element(By.CSS_SELECTOR, "#login button").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#caseload tbody tr[data-pseudonym]"))
    use_language(d, "en")


def test_the_audit_names_an_unlabelled_field_and_an_image_without_words(browser):
    """The audit itself can fail: a page with an unlabelled input and an image without
    alternative text gives both violations, each named."""
    browser.get("data:text/html,<!doctype html><html lang=en><title>t</title><main>"
                "<h1>t</h1><input id=x><img src=x.png></main></html>")
    from axe_audit import violations
    found = "\n".join(violations(browser))
    assert "label" in found and "image-alt" in found, found
