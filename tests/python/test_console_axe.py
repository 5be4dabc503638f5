"""axe-core over every screen of the therapist console (Chromium, headless): the login, the
forced change of the one-time password, the caseload, a patient's live view, progress, each
exercise of a session, its replay, the prescribe form, the clinic screen with its pairing sheet
and a patient's stations, each with zero violations of WCAG 2.2 A/AA and axe's best practices.
A screen added to the console is added here."""

import time

import pytest
from selenium.webdriver.common.by import By

from axe_audit import assert_no_violations
from test_console_browser import browser, serve_clinic, shot, telerehab, wait  # noqa: F401 (fixture)

PASSWORD = "an audited passphrase"


@pytest.fixture(scope="module")
def clinic(tmp_path_factory):
    """A clinic with patient P-0042 whose paired station ran one short simulated session."""
    with serve_clinic(tmp_path_factory.mktemp("clinic")) as served:
        telerehab("run", "--sim", "--headless", "--speed", "max", "--duration", "4", "--seed", "2",
                  home=served["home"])
        yield served


def audit(d, screen, ready):
    """Wait for the screen's `ready` element, shoot it, and audit it."""
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, ready))
    shot(d, f"axe-{screen}")
    assert_no_violations(d, screen)


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
    audit(d, "caseload", "a[href^='#/patients/']")
    patient = d.find_element(By.LINK_TEXT, "P-0042").get_attribute("href").split("#")[1]

    d.get(f"{web}/#{patient}/live")
    audit(d, "live", "#live-status")
    d.get(f"{web}/#{patient}/progress")
    audit(d, "progress", "#tab[data-sessions='1']")
    exercises = d.find_element(By.LINK_TEXT, "Each exercise").get_attribute("href")
    replay = d.find_element(By.CSS_SELECTOR, "#tab a[href*='/replay/']").get_attribute("href")
    d.get(exercises)
    audit(d, "each-exercise", "#tab table")
    deadline = time.time() + 40
    while True:  # the station uploads its recording just after the session
        d.get(replay)
        found = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-frames], p.error"))[0]
        if found.get_attribute("data-frames") or time.time() > deadline:
            break
        time.sleep(1)
    audit(d, "replay", "#tab[data-frames]")
    d.get(f"{web}/#{patient}/replay")
    audit(d, "replay-list", "#tab a[href*='/replay/']")
    d.get(f"{web}/#{patient}/prescribe")
    audit(d, "prescribe", "#rx-form")
    d.get(f"{web}/#/password")
    audit(d, "password", "#password-form")
    d.get(f"{web}/#/attention-settings")
    audit(d, "attention-settings", "#settings-form")
    d.get(f"{web}/#/names")
    audit(d, "names", "#names-table")
    d.get(f"{web}/#/audit")
    audit(d, "audit", "#audit-table")

    d.get(f"{web}/#/clinic")
    audit(d, "clinic", "#new-patient")
    d.find_element(By.ID, "np-pseudonym").send_keys("P-0043")
    d.find_element(By.CSS_SELECTOR, "#new-patient button").click()
    audit(d, "pairing-sheet", "#pairing-sheet")
    d.get(f"{web}/#/clinic/patients/{patient.rsplit('/', 1)[1]}")
    audit(d, "patient-stations", "#stations")


def test_the_audit_names_an_unlabelled_field_and_an_image_without_words(browser):
    """The audit itself can fail: a page with an unlabelled input and an image without
    alternative text gives both violations, each named."""
    browser.get("data:text/html,<!doctype html><html lang=en><title>t</title><main>"
                "<h1>t</h1><input id=x><img src=x.png></main></html>")
    from axe_audit import violations
    found = "\n".join(violations(browser))
    assert "label" in found and "image-alt" in found, found
