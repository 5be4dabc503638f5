"""Issue 42: the therapist sets the gentle trunk cue's threshold in the prescribe form
([trunk] cue_deg, bounded by the regimen's schema: 5–45 degrees), it comes back in the form,
the hub refuses a value out of bounds naming the key, and an empty field takes it off."""

import re

from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select

from test_console_browser import browser, clinic, telerehab, wait  # noqa: F401 (fixtures)
from test_console_forms import fetch_json, log_in
from test_console_prescribe import send_json


def save(d):
    before = int(d.find_element(By.ID, "rx-result").get_attribute("data-saved") or 0)
    d.find_element(By.CSS_SELECTOR, "#rx-form button[type=submit]").click()
    wait(d, lambda d: int(d.find_element(By.ID, "rx-result").get_attribute("data-saved") or 0) > before)


def test_the_therapist_sets_the_trunk_cue_in_the_form_and_can_take_it_off(clinic, browser):
    d = browser
    log_in(d, clinic).click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Prescribe"))[0].click()
    wait(d, lambda d: d.find_elements(By.ID, "rx-form"))
    patient_id = d.current_url.split("#/patients/")[1].split("/")[0]
    Select(d.find_element(By.ID, "rx-add")).select_by_value("dial")
    d.find_element(By.ID, "rx-add-btn").click()
    cue = wait(d, lambda d: d.find_elements(By.ID, "rx-trunk-cue"))[0]
    assert (cue.get_attribute("min"), cue.get_attribute("max")) == ("5", "45")
    cue.clear()
    cue.send_keys("15")
    save(d)
    stored = fetch_json(d, f"/api/patients/{patient_id}/regimen")
    assert stored["current_fields"]["trunk"] == {"cue_deg": 15}, stored["current_fields"]
    assert re.search(r"\[trunk\]\s*\ncue_deg = 15(\.0)?\n", stored["current"]["toml"]), stored["current"]["toml"]
    d.refresh()
    cue = wait(d, lambda d: d.find_elements(By.ID, "rx-trunk-cue"))[0]
    assert float(cue.get_attribute("value")) == 15
    # Out of bounds, the hub refuses it and names the key.
    regimen = {**stored["current_fields"], "trunk": {"cue_deg": 60}}
    status, answer = send_json(d, "PUT", f"/api/patients/{patient_id}/regimen", {"fields": regimen})
    assert status >= 400 and "trunk.cue_deg" in answer, (status, answer)
    cue.clear()
    save(d)
    assert "trunk" not in fetch_json(d, f"/api/patients/{patient_id}/regimen")["current_fields"]
