"""The clinic from the browser (Chromium, headless): the first login forced to replace the
one-time password, adding a patient and printing their pairing sheet (one page) whose code then
pairs a real station, adding a therapist whose own first login is forced to change the printed
password, and revoking a station — each change in the audit log under the therapist who made it.
Screenshots (clinic-*.png) go to $TELEREHAB_ARTIFACTS (default target/test-artifacts/console)."""

import base64
import json
import re
import time
import tomllib
import urllib.parse

import pytest
from selenium.webdriver.common.by import By

from test_console_browser import browser, serve_clinic, shot, telerehab, wait  # noqa: F401 (fixture)

NEW_PASSWORD = "a clinic passphrase of my own"


# What `hub serve --public-station-address` says stations at home connect to: the sheet prints
# it, not an address guessed from the browser's.
PUBLIC_STATIONS = "stations.clinic.test:47878"


@pytest.fixture(scope="module")
def clinic(tmp_path_factory):
    """A clinic (admin ana, patient P-0042 with a paired station) served on loopback, its
    public station address configured."""
    with serve_clinic(tmp_path_factory.mktemp("clinic"),
                      ("--public-station-address", PUBLIC_STATIONS)) as served:
        yield served


def fetch_json(d, path):
    """GET `path` of the console API with the browser's login cookie."""
    return json.loads(d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "fetch(arguments[0], {credentials: 'same-origin'}).then(r => r.text()).then(done);", path))


def log_in_and_replace_the_one_time_password(d, web, email, one_time):
    d.get(web + "/")
    wait(d, lambda d: d.find_elements(By.ID, "email"))
    d.find_element(By.ID, "email").send_keys(email)
    d.find_element(By.ID, "password").send_keys(one_time)
    d.find_element(By.CSS_SELECTOR, "#login button").click()
    wait(d, lambda d: d.find_elements(By.ID, "password-forced"))
    assert not d.find_elements(By.CSS_SELECTOR, "table"), "nothing else is shown before the change"
    d.find_element(By.ID, "current-password").send_keys(one_time)
    d.find_element(By.ID, "new-password").send_keys(NEW_PASSWORD)
    d.find_element(By.ID, "repeat-password").send_keys(NEW_PASSWORD + " typo")
    d.find_element(By.CSS_SELECTOR, "#password-form button").click()
    wait(d, lambda d: d.find_element(By.ID, "password-error").text)
    d.find_element(By.ID, "repeat-password").clear()
    d.find_element(By.ID, "repeat-password").send_keys(NEW_PASSWORD)
    d.find_element(By.CSS_SELECTOR, "#password-form button").click()
    wait(d, lambda d: d.find_elements(By.ID, "caseload"))


def pdf_pages(d):
    pdf = base64.b64decode(d.execute_cdp_cmd("Page.printToPDF", {"paperWidth": 8.27, "paperHeight": 11.69})["data"])
    return len(re.findall(rb"/Type\s*/Page[^s]", pdf))


def test_a_clinic_adds_a_patient_prints_the_pairing_sheet_adds_a_therapist_and_revokes_a_station(clinic, browser):
    d, web = browser, clinic["web"]
    log_in_and_replace_the_one_time_password(d, web, "ana@clinic.example", clinic["password"])
    shot(d, "clinic-1-own-password-chosen")

    # Add a patient: a pseudonym that is a name is refused in plain words.
    d.find_element(By.ID, "clinic-link").click()
    wait(d, lambda d: d.find_elements(By.ID, "new-patient"))
    d.find_element(By.ID, "np-pseudonym").send_keys("Jane Doe")
    d.find_element(By.CSS_SELECTOR, "#new-patient button").click()
    wait(d, lambda d: d.find_element(By.ID, "np-error").text.strip())
    d.find_element(By.ID, "np-pseudonym").clear()
    d.find_element(By.ID, "np-pseudonym").send_keys("P-0043")
    shot(d, "clinic-2-add-a-patient")
    d.find_element(By.CSS_SELECTOR, "#new-patient button").click()
    wait(d, lambda d: d.find_elements(By.ID, "pairing-sheet"))
    code = d.find_element(By.ID, "sheet-code").text
    assert re.fullmatch(r"[0-9A-Z]{4}-[0-9A-Z]{4}", code), code
    assert d.find_element(By.ID, "sheet-patient").text == "P-0043"
    assert d.find_element(By.ID, "sheet-address").text == PUBLIC_STATIONS
    assert int(d.find_element(By.ID, "sheet-expiry").get_attribute("data-expires-ms")) > time.time() * 1000
    steps = [li.text for li in d.find_elements(By.CSS_SELECTOR, ".steps li")]
    assert len(steps) == 6 and all(steps) and "telerehab" in steps[1], steps
    # The pairing card for a USB stick: the station's card file, with this address and code
    # (the station then pairs with one press of the wheel: tests/wheel_alone_e2e.rs).
    card_href = d.find_element(By.ID, "pairing-card").get_attribute("href")
    assert card_href.startswith("data:application/toml"), card_href
    assert d.find_element(By.ID, "pairing-card").get_attribute("download") == "telerehab-pairing.toml"
    card = tomllib.loads(urllib.parse.unquote(card_href.split(",", 1)[1]))
    assert card == {"clinic_address": PUBLIC_STATIONS, "code": code}, card
    shot(d, "clinic-3-pairing-sheet")
    assert pdf_pages(d) == 1, "the pairing sheet prints on one A4 page"
    d.execute_cdp_cmd("Emulation.setEmulatedMedia", {"media": "print"})
    shot(d, "clinic-4-pairing-sheet-as-printed")
    assert not d.find_element(By.ID, "print-sheet").is_displayed()
    d.execute_cdp_cmd("Emulation.setEmulatedMedia", {"media": ""})
    # The printed code pairs a real station with the new patient.
    telerehab("pair", "--hub", clinic["address"], "--code", code, home=clinic["tmp"] / "station-2")

    # Add a therapist (admins only): the one-time password is shown once.
    d.get(web + "/#/clinic")
    wait(d, lambda d: d.find_elements(By.ID, "new-therapist"))
    d.find_element(By.ID, "nt-email").send_keys("bo@clinic.example")
    d.find_element(By.CSS_SELECTOR, "#new-therapist button").click()
    wait(d, lambda d: d.find_elements(By.ID, "nt-password"))
    bo_password = d.find_element(By.ID, "nt-password").text
    assert len(bo_password) == 20
    assert "bo@clinic.example" in d.find_element(By.ID, "therapists").text
    shot(d, "clinic-5-therapist-added")

    # Revoke P-0042's station from the patient's page, after a confirmation.
    patients = fetch_json(d, "/api/patients")
    p42 = next(p for p in patients if p["pseudonym"] == "P-0042")
    d.get(web + f"/#/patients/{p42['id']}/progress")
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "nav.tabs a[data-tab='stations']"))
    d.find_element(By.CSS_SELECTOR, "nav.tabs a[data-tab='stations']").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "[data-revoke]"))
    station = d.find_element(By.CSS_SELECTOR, "[data-revoke]").get_attribute("data-revoke")
    d.find_element(By.CSS_SELECTOR, "[data-revoke]").click()
    wait(d, lambda d: d.find_elements(By.ID, "rv-yes"))
    shot(d, "clinic-6-revoke-confirm")
    d.find_element(By.ID, "rv-yes").click()
    wait(d, lambda d: d.find_elements(By.ID, "revoked"))
    assert d.find_elements(By.CSS_SELECTOR, "#stations [data-state='revoked']")
    assert not d.find_elements(By.CSS_SELECTOR, "[data-revoke]")
    shot(d, "clinic-7-station-revoked")
    revoked = fetch_json(d, f"/api/patients/{p42['id']}")["stations"][0]
    assert revoked["station_id"] == station and revoked["revoked_at_ms"] is not None

    # Every change audited with the admin who made it.
    me = fetch_json(d, "/api/me")
    audit = fetch_json(d, "/api/audit?limit=500")["entries"]
    mine = {e["action"] for e in audit if e["actor"] == f"therapist:{me['id']}"}
    assert {"password_changed", "add_patient", "pairing_code", "add_therapist", "revoke_station"} <= mine, mine

    # The new therapist's first login is forced to change the printed password; no clinic admin.
    d.find_element(By.ID, "logout").click()
    wait(d, lambda d: d.find_elements(By.ID, "email"))
    log_in_and_replace_the_one_time_password(d, web, "bo@clinic.example", bo_password)
    d.find_element(By.ID, "clinic-link").click()
    wait(d, lambda d: d.find_elements(By.ID, "new-patient"))
    assert not d.find_elements(By.ID, "new-therapist")
    assert d.find_elements(By.ID, "np-in-your-care")
    shot(d, "clinic-8-therapist-clinic-screen")


def test_the_pairing_sheet_refuses_a_loopback_station_address_and_says_why(tmp_path, browser):
    """A hub told no public station address and listening on loopback: the sheet is not
    printed (no address a patient's station could reach), and the page says why."""
    d = browser
    with serve_clinic(tmp_path) as loopback:
        log_in_and_replace_the_one_time_password(d, loopback["web"], "ana@clinic.example", loopback["password"])
        d.find_element(By.ID, "clinic-link").click()
        wait(d, lambda d: d.find_elements(By.ID, "new-patient"))
        d.find_element(By.ID, "np-pseudonym").send_keys("P-0044")
        d.find_element(By.CSS_SELECTOR, "#new-patient button").click()
        wait(d, lambda d: d.find_elements(By.ID, "sheet-refused"))
        assert not d.find_elements(By.ID, "pairing-sheet")
        assert not d.find_elements(By.ID, "print-sheet")
        assert d.find_element(By.CSS_SELECTOR, "#sheet-refused [role=alert]").text.strip()
        pairing = json.loads(d.execute_async_script(
            "const done = arguments[arguments.length - 1];"
            "fetch('/api/patients', {credentials: 'same-origin'}).then(r => r.json())"
            ".then(ps => ps.find(p => p.pseudonym === 'P-0044'))"
            ".then(p => fetch(`/api/patients/${p.id}/pairing-code`, {method: 'POST', credentials: 'same-origin',"
            " headers: {'content-type': 'application/json'}, body: '{}'})).then(r => r.text()).then(done);"))
        assert pairing["station_address"] is None and pairing["station_address_problem"], pairing
        shot(d, "clinic-9-pairing-sheet-refused-loopback")
        d.find_element(By.ID, "logout").click()
