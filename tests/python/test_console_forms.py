"""The prescribe form with the patient's own bounds, assistance chosen in the form, and session
notes, in a real browser (Chromium, headless): a paired station runs one simulated session, so
the hub knows its wheel; the form names the wheel and bounds every torque by its effective
ceiling; a ceiling above it is refused in words naming exercise, field, value and wheel; an
assistance mode and level chosen in the form reach the saved TOML and come back into the form;
a note added to the session shows in the Progress list and on the per-exercise page. axe-core
audits each screen. Screenshots (forms-*.png) go to $TELEREHAB_ARTIFACTS."""

import json

from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select

from console_messages import message, wait_saved
from axe_audit import assert_no_violations
from test_console_browser import browser, clinic, shot, telerehab, wait  # noqa: F401 (fixtures)

OWN_PASSWORD = "ana's own passphrase"
ABOVE_THE_WHEEL = """[[exercise]]
kind = "sine"
duration_s = 30.0
[exercise.haptic]
ceiling_nm = 5.0
"""


def fetch_json(d, path):
    """GET `path` of the console API with the browser's login cookie."""
    return json.loads(d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "fetch(arguments[0], {credentials: 'same-origin'}).then(r => r.text()).then(done);", path))


def log_in(d, clinic):
    d.get(clinic["web"] + "/")
    wait(d, lambda d: d.find_elements(By.ID, "email"))
    d.find_element(By.ID, "email").send_keys("ana@clinic.example")
    d.find_element(By.ID, "password").send_keys(clinic["password"])
    d.find_element(By.CSS_SELECTOR, "#login button").click()
    wait(d, lambda d: d.find_elements(By.ID, "password-form"))
    d.find_element(By.ID, "current-password").send_keys(clinic["password"])
    d.find_element(By.ID, "new-password").send_keys(OWN_PASSWORD)
    d.find_element(By.ID, "repeat-password").send_keys(OWN_PASSWORD)
    d.find_element(By.CSS_SELECTOR, "#password-form button").click()
    return wait(d, lambda d: d.find_elements(By.LINK_TEXT, "P-0042"))[0]


def both_sizes(d, name):
    """A screenshot at the test's window size and one at 1366×768."""
    shot(d, name)
    size = d.get_window_size()
    d.set_window_size(1366, 768)
    shot(d, name + "-1366x768")
    d.set_window_size(size["width"], size["height"])


def test_the_form_bounds_torque_by_the_patients_wheel_sets_assistance_and_notes_a_session(clinic, browser):
    d = browser
    # One session on the paired station: its Hello tells the hub the simulated wheel.
    telerehab("run", "--sim", "--headless", "--speed", "max", "--duration", "2", "--seed", "3",
              home=clinic["home"])
    log_in(d, clinic).click()
    patient_id = d.current_url.split("#/patients/")[1].split("/")[0]
    wheel = fetch_json(d, f"/api/patients/{patient_id}")["wheel"]
    assert wheel["model"] == "simulated wheel" and wheel["stated_ceiling_nm"] == 1.87, wheel

    # The form names the wheel; every torque bound is the patient's own.
    d.find_element(By.LINK_TEXT, "Prescribe").click()
    line = wait(d, lambda d: d.find_elements(By.ID, "rx-wheel"))[0]
    assert line.get_attribute("data-ceiling-nm") == "1.87" and "simulated wheel" in line.text, line.text
    both_sizes(d, "forms-0-wheel")
    Select(d.find_element(By.ID, "rx-add")).select_by_value("sine")
    d.find_element(By.ID, "rx-add-btn").click()
    ceiling = wait(d, lambda d: d.find_elements(By.ID, "ex0-ceiling"))[0]
    assert (ceiling.get_attribute("min"), ceiling.get_attribute("max")) == ("0", "1.87")
    assert d.find_element(By.ID, "bounds").get_attribute("data-ceiling-nm") == "1.87"
    ceiling.send_keys("1.9")
    d.find_element(By.CSS_SELECTOR, "#rx-form button[type=submit]").click()
    assert "error" in d.find_element(By.ID, "rx-result").get_attribute("class")
    ceiling.clear()
    ceiling.send_keys("1.5")

    # Assistance in words, its level with the schema's bounds.
    modes = Select(d.find_element(By.ID, "ex0-assist"))
    words = {o.get_attribute("value"): o.text for o in modes.options}
    assert words[""] == message(d, "assist-mode-station") and words["motion"] == message(d, "assist-mode-motion"), words
    modes.select_by_value("motion")
    level = wait(d, lambda d: d.find_elements(By.ID, "ex0-assist-level"))[0]
    schema = fetch_json(d, "/api/regimen/schema")
    authority = schema["$defs"]["MotionParams"]["properties"]["authority"]
    assert float(level.get_attribute("max")) == authority["maximum"], level.get_attribute("max")
    assert float(level.get_attribute("min")) == authority["minimum"], level.get_attribute("min")
    assert d.find_element(By.ID, "ex0-ceiling").get_attribute("value") == "1.5", "kept across the change"
    level.send_keys("0.6")
    d.find_element(By.CSS_SELECTOR, "#rx-form button[type=submit]").click()
    wait_saved(d, 1, wait)
    toml = fetch_json(d, f"/api/patients/{patient_id}/regimen")["current"]["toml"]
    assert 'kind = "motion"' in toml and "authority = 0.6" in toml and "ceiling_nm = 1.5" in toml, toml
    # Back in the form as saved.
    assert Select(d.find_element(By.ID, "ex0-assist")).first_selected_option.get_attribute("value") == "motion"
    assert d.find_element(By.ID, "ex0-assist-level").get_attribute("value") == "0.6"
    assert_no_violations(d, "the prescribe form with the wheel and assistance")
    d.execute_script("arguments[0].scrollIntoView()", d.find_element(By.ID, "ex0-ceiling"))
    both_sizes(d, "forms-1-prescribe")

    # Above the wheel, as TOML: refused in words naming the exercise, field, value and wheel.
    d.find_element(By.CSS_SELECTOR, "#rx-toml summary").click()
    area = d.find_element(By.ID, "toml")
    area.clear()
    area.send_keys(ABOVE_THE_WHEEL)
    d.find_element(By.CSS_SELECTOR, "#rx button").click()
    result = wait(d, lambda d: [e for e in d.find_elements(By.ID, "rx-result") if "refused" in e.text])[0]
    assert result.text == ("regimen refused: ceiling_nm 5 N·m for exercise 1 (Sine road) is above what "
                           "P-0042's wheel (simulated wheel) can give: at most 1.87 N·m"), result.text
    assert_no_violations(d, "the prescribe form with a refusal")
    shot(d, "forms-2-refused")

    # A note on the session, in the Progress list and on the per-exercise page.
    d.find_element(By.LINK_TEXT, "Progress").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-sessions='1']"))
    cell = d.find_element(By.CSS_SELECTOR, "details.session-notes")
    cell.find_element(By.TAG_NAME, "summary").click()
    text = wait(d, lambda d: cell.find_elements(By.CSS_SELECTOR, "textarea"))[0]
    text.send_keys("Tired today; shoulder pain 3/10. Keep the ceiling low next week.")
    cell.find_element(By.CSS_SELECTOR, "button[type=submit]").click()
    wait(d, lambda d: cell.find_element(By.CSS_SELECTOR, "div").get_attribute("data-notes") == "1")
    assert "shoulder pain 3/10" in cell.find_element(By.CSS_SELECTOR, "ul.notes").text
    assert "ana@clinic.example" in cell.find_element(By.CSS_SELECTOR, "ul.notes").text
    assert_no_violations(d, "the progress with a session's notes open")
    d.execute_script("arguments[0].scrollIntoView()", cell)
    both_sizes(d, "forms-3-progress-note")
    d.find_element(By.LINK_TEXT, "Each exercise").click()
    box = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#session-notes-box[data-notes='1']"))[0]
    assert "shoulder pain 3/10" in box.text
    assert_no_violations(d, "the per-exercise page with its notes")
    d.execute_script("arguments[0].scrollIntoView()", box)
    both_sizes(d, "forms-4-exercise-notes")
    audit = fetch_json(d, "/api/audit?limit=50")
    entries = audit["entries"] if isinstance(audit, dict) else audit
    assert any(e["action"] == "post_note" for e in entries), entries
