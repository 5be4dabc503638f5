"""Issue 41, the therapist's day, in a real browser (Chromium, headless): prescribing in
clinical terms (an easy / medium / hard level per exercise from the hub's presets, minutes,
sets and a rest after each set, the dial's range and pace in words, the engineering settings
behind "details", one message box sent with the prescription); the dial replay's timeline
marking where each exercise starts, without an empty car panel; the clinic's names for its
pseudonyms held in the browser only (no request carries them, the hub's files never hold
them); the audit page for admins, refused to a therapist who is not one. axe-core audits each
screen; screenshots at 1366×768 go to docs/screenshots."""

import json
import math
import re
import time

from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import Select

from axe_audit import assert_no_violations
from console_messages import message
from test_console_browser import ROOT, browser, clinic, telerehab, wait  # noqa: F401 (fixtures)
from test_console_forms import fetch_json, log_in

SCREENSHOTS = ROOT / "docs" / "screenshots"
NAME = "Anna Berg"
MESSAGE = "From today: the easy dial, two sets with a rest between them."


def shoot_1366(d, name):
    """A screenshot of the page at 1366×768 into docs/screenshots."""
    size = d.get_window_size()
    d.set_window_size(1366, 768)
    time.sleep(0.3)
    SCREENSHOTS.mkdir(parents=True, exist_ok=True)
    d.save_screenshot(str(SCREENSHOTS / f"{name}.png"))
    d.set_window_size(size["width"], size["height"])


def click(d, by, selector):
    """Clicks the element once it is there (again if the page re-rendered it meanwhile)."""
    def go(d):
        found = d.find_elements(by, selector)
        if found:
            found[0].click()
        return bool(found)
    wait(d, go)


def send_json(d, method, path, body):
    """`method` `path` of the console API with a JSON body: [status, answer]."""
    return d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "fetch(arguments[0], {method: arguments[1], credentials: 'same-origin',"
        " headers: {'Content-Type': 'application/json'}, body: JSON.stringify(arguments[2])})"
        ".then(async r => done([r.status, await r.text()]));", path, method, body)


def spy_on_requests(d):
    """Every request the page makes from now on, with its body, kept in window.__sent."""
    d.execute_script("""
      window.__sent = [];
      const fetch0 = window.fetch;
      window.fetch = (url, init = {}) => {
        window.__sent.push(String(url) + ' ' + String(init.body ?? ''));
        return fetch0(url, init);
      };
      const open0 = XMLHttpRequest.prototype.open, send0 = XMLHttpRequest.prototype.send;
      XMLHttpRequest.prototype.open = function (m, url, ...rest) { this.__url = url; return open0.call(this, m, url, ...rest); };
      XMLHttpRequest.prototype.send = function (body) { window.__sent.push(String(this.__url) + ' ' + String(body ?? '')); return send0.call(this, body); };
      navigator.sendBeacon = () => { throw new Error('no beacons'); };
    """)


def test_a_level_minutes_sets_and_rests_prescribe_the_regimen_with_the_one_message(clinic, browser):
    d = browser
    log_in(d, clinic).click()
    click(d, By.LINK_TEXT, "Prescribe")
    wait(d, lambda d: d.find_elements(By.ID, "rx-form"))
    patient_id = d.current_url.split("#/patients/")[1].split("/")[0]
    # One message box on the page: the patient's, sent with the prescription.
    assert not d.find_elements(By.ID, "rx-note")
    assert len(d.find_elements(By.CSS_SELECTOR, "#msg-text")) == 1
    Select(d.find_element(By.ID, "rx-add")).select_by_value("dial")
    d.find_element(By.ID, "rx-add-btn").click()
    levels = wait(d, lambda d: d.find_elements(By.ID, "ex0-levels"))[0]
    assert levels.get_attribute("data-level-now") == "medium", "a new exercise starts at medium"
    presets = fetch_json(d, "/api/regimen/presets")
    easy = next(p for p in presets if p["kind"] == "dial" and p["level"] == "easy")
    # The engineering settings are behind "details", closed.
    details = d.find_element(By.ID, "ex0-details")
    assert details.get_attribute("open") is None
    assert "rad/s" not in d.find_element(By.CSS_SELECTOR, "fieldset[data-exercise='0']").text
    d.find_element(By.ID, "ex0-level-easy").click()
    wait(d, lambda d: d.find_element(By.ID, "ex0-levels").get_attribute("data-level-now") == "easy")
    # The dial's range and pace as the easy level sets them, in degrees and seconds.
    sine = easy["fields"]["reference"]
    assert float(d.find_element(By.ID, "ex0-dial-range").get_attribute("value")) == sine["amplitude_deg"]
    pace = float(d.find_element(By.ID, "ex0-dial-pace").get_attribute("value"))
    assert abs(pace - 2 * math.pi / sine["frequency_rad_s"]) < 0.06, pace
    assert d.find_element(By.ID, "ex0-dial-words").text
    for field, value in (("ex0-minutes", "0.1"), ("ex0-sets", "2"), ("ex0-rest", "10")):
        box = d.find_element(By.ID, field)
        box.clear()
        box.send_keys(value)
    # And a sine road at the hard level, driven once.
    Select(d.find_element(By.ID, "rx-add")).select_by_value("sine")
    d.find_element(By.ID, "rx-add-btn").click()
    click(d, By.ID, "ex1-level-hard")
    wait(d, lambda d: d.find_element(By.ID, "ex1-levels").get_attribute("data-level-now") == "hard")
    assert d.find_element(By.ID, "ex0-sets").get_attribute("value") == "2", "kept across the re-render"
    d.find_element(By.ID, "msg-text").send_keys(MESSAGE)
    assert_no_violations(d, "the prescribe form with levels, minutes, sets and rests")
    d.execute_script("arguments[0].scrollIntoView()", d.find_element(By.ID, "ex0-levels"))
    shoot_1366(d, "prescribe-levels")
    d.find_element(By.CSS_SELECTOR, "#ex1-details summary").click()
    d.execute_script("arguments[0].scrollIntoView()", d.find_element(By.ID, "ex1-details"))
    shoot_1366(d, "prescribe-details")
    d.find_element(By.CSS_SELECTOR, "#rx-form button[type=submit]").click()
    wait(d, lambda d: d.find_element(By.ID, "rx-result").get_attribute("data-saved") == "1")

    # Saved as the regimen: two sets of the easy dial, 6 s each with a 10 s rest, then the road.
    regimen = fetch_json(d, f"/api/patients/{patient_id}/regimen")["current_fields"]
    dials = regimen["exercise"][:2]
    hard = next(p for p in presets if p["kind"] == "sine" and p["level"] == "hard")["fields"]
    assert len(regimen["exercise"]) == 3, regimen
    for e in dials:
        assert e == {**easy["fields"], "duration_s": 6.0, "rest_s": 10.0}, e
    assert regimen["exercise"][2] == hard, regimen["exercise"][2]
    messages = fetch_json(d, f"/api/patients/{patient_id}/messages")
    assert [m["text"] for m in messages] == [MESSAGE], messages
    assert d.find_element(By.ID, "msg-text").get_attribute("value") == ""
    # Read back as one row of two sets at the easy level, the road at the hard one.
    assert len(d.find_elements(By.CSS_SELECTOR, "fieldset[data-exercise]")) == 2
    assert d.find_element(By.ID, "ex0-sets").get_attribute("value") == "2"
    assert d.find_element(By.ID, "ex0-levels").get_attribute("data-level-now") == "easy"
    assert d.find_element(By.ID, "ex1-levels").get_attribute("data-level-now") == "hard"
    # Saved again unchanged, the regimen is the same (nothing rounded on the way).
    d.find_element(By.CSS_SELECTOR, "#rx-form button[type=submit]").click()
    wait(d, lambda d: d.find_element(By.ID, "rx-result").get_attribute("data-saved") == "2")
    assert fetch_json(d, f"/api/patients/{patient_id}/regimen")["current_fields"] == regimen


def test_the_patients_station_settings_travel_with_the_prescription_and_come_back_in_the_form(clinic, browser):
    """Issue 40: the therapist sets the station's language, the neglected side and speech in the
    prescribe form; the same save stores them in the regimen's [patient] table; reopened, the
    form shows them, and the prescription says them in words."""
    d = browser
    patient_id = d.current_url.split("#/patients/")[1].split("/")[0]
    d.get(f"{clinic['web']}/#/patients/{patient_id}/prescribe")
    language = Select(wait(d, lambda d: d.find_elements(By.ID, "rx-p-language"))[0])
    # The station's languages, each named in its own language, and "as chosen on the station".
    offered = {o.get_attribute("value"): o.text for o in language.options}
    assert offered == {"": message(d, "patient-language-station"), "en": "English", "de": "Deutsch",
                       "es": "Español", "zh": "中文（简体）"}, offered
    assert [o.get_attribute("lang") for o in language.options][1:] == ["en", "de", "es", "zh"]
    # Three sides, each with what the station does for it.
    for side in ("none", "left", "right"):
        note = d.find_element(By.ID, f"rx-p-side-{side}-note")
        assert note.text == message(d, f"patient-side-{side}-note"), side
    assert d.find_element(By.ID, "rx-p-side-none").is_selected(), "no neglect until prescribed"
    assert d.find_element(By.ID, "rx-p-speech").is_selected(), "speech is on by default"
    volume = d.find_element(By.ID, "rx-p-volume")
    assert (volume.get_attribute("min"), volume.get_attribute("max")) == ("0", "100")
    countdown = d.find_element(By.ID, "rx-p-countdown")
    assert (countdown.get_attribute("min"), countdown.get_attribute("max")) == ("0", "60")

    language.select_by_value("de")
    d.find_element(By.ID, "rx-p-side-left").click()
    d.find_element(By.ID, "rx-p-speech").click()
    countdown.send_keys("10")
    assert_no_violations(d, "the prescribe form with the patient's station settings")
    d.execute_script("arguments[0].scrollIntoView()", d.find_element(By.ID, "rx-patient"))
    shoot_1366(d, "prescribe-patient-settings")
    before = int(d.find_element(By.ID, "rx-result").get_attribute("data-saved") or 0)
    d.find_element(By.CSS_SELECTOR, "#rx-form button[type=submit]").click()
    wait(d, lambda d: int(d.find_element(By.ID, "rx-result").get_attribute("data-saved") or 0) > before)

    # The hub's stored regimen has them, in the [patient] table of its TOML.
    stored = fetch_json(d, f"/api/patients/{patient_id}/regimen")
    toml = stored["current"]["toml"]
    table = toml.split("[patient]", 1)[1].split("\n[", 1)[0] if "[patient]" in toml else ""
    assert 'language = "de"' in table and 'neglected_side = "left"' in table, toml
    assert "speech = false" in table and re.search(r"start_after_rest_s = 10(\.0)?\n", table), toml
    assert "speech_volume_pct" not in table, "an empty volume stays the station's default"
    assert stored["current_fields"]["patient"] == {
        "language": "de", "neglected_side": "left", "speech": False, "start_after_rest_s": 10.0}

    # Reopened, the form shows them; the prescription says them in words.
    d.refresh()
    language = Select(wait(d, lambda d: d.find_elements(By.ID, "rx-p-language"))[0])
    assert language.first_selected_option.get_attribute("value") == "de"
    assert d.find_element(By.ID, "rx-p-side-left").is_selected()
    assert not d.find_element(By.ID, "rx-p-speech").is_selected()
    assert float(d.find_element(By.ID, "rx-p-countdown").get_attribute("value")) == 10
    words = d.find_element(By.ID, "rx-patient-words")
    assert (words.get_attribute("data-language"), words.get_attribute("data-side"),
            words.get_attribute("data-speech")) == ("de", "left", "off")
    assert words.text == message(d, "patient-saved-words", {
        "language": "Deutsch", "side": "left", "speech": "off", "volume": 80, "countdown": "count", "seconds": 10})
    # Saved again unchanged, nothing moves (the form writes back what it read).
    assert not d.find_element(By.ID, "rx-result").get_attribute("data-saved"), "a fresh page"
    d.find_element(By.CSS_SELECTOR, "#rx-form button[type=submit]").click()
    wait(d, lambda d: d.find_element(By.ID, "rx-result").get_attribute("data-saved"))
    assert fetch_json(d, f"/api/patients/{patient_id}/regimen")["current_fields"] == stored["current_fields"]

    # A language the station does not have is refused by the hub, naming the field.
    fields = {**stored["current_fields"], "patient": {"language": "tlh"}}
    status, answer = send_json(d, "PUT", f"/api/patients/{patient_id}/regimen", {"fields": fields})
    assert status >= 400 and "patient.language" in answer, (status, answer)


def test_the_therapist_schedules_the_standard_assessment_in_the_form_and_can_take_it_off(clinic, browser):
    """Issue 42: the standard assessment is scheduled from the prescribe form ([assessment]
    every_days, bounded by the regimen's schema), comes back in the form, and an empty field
    takes it off the regimen."""
    d = browser
    patient_id = d.current_url.split("#/patients/")[1].split("/")[0]
    d.get(f"{clinic['web']}/#/patients/{patient_id}/prescribe")
    days = wait(d, lambda d: d.find_elements(By.ID, "rx-assessment-days"))[0]
    assert (days.get_attribute("min"), days.get_attribute("max")) == ("1", "90")
    days.clear()
    days.send_keys("7")
    before = int(d.find_element(By.ID, "rx-result").get_attribute("data-saved") or 0)
    d.find_element(By.CSS_SELECTOR, "#rx-form button[type=submit]").click()
    wait(d, lambda d: int(d.find_element(By.ID, "rx-result").get_attribute("data-saved") or 0) > before)
    stored = fetch_json(d, f"/api/patients/{patient_id}/regimen")
    assert stored["current_fields"]["assessment"] == {"every_days": 7}, stored["current_fields"]
    assert re.search(r"\[assessment\]\s*\nevery_days = 7\n", stored["current"]["toml"]), stored["current"]["toml"]
    d.refresh()
    days = wait(d, lambda d: d.find_elements(By.ID, "rx-assessment-days"))[0]
    assert days.get_attribute("value") == "7"
    days.clear()
    d.find_element(By.CSS_SELECTOR, "#rx-form button[type=submit]").click()
    wait(d, lambda d: d.find_element(By.ID, "rx-result").get_attribute("data-saved"))
    assert "assessment" not in fetch_json(d, f"/api/patients/{patient_id}/regimen")["current_fields"]


def test_the_dial_replay_marks_where_each_exercise_starts_and_shows_no_empty_car_panel(clinic, browser):
    d = browser
    # The prescription above without the road: the dial twice, a rest between.
    patient_id = d.current_url.split("#/patients/")[1].split("/")[0]
    regimen = fetch_json(d, f"/api/patients/{patient_id}/regimen")["current_fields"]
    regimen["exercise"] = regimen["exercise"][:2]
    status, answer = send_json(d, "PUT", f"/api/patients/{patient_id}/regimen", {"fields": regimen})
    assert status == 200, answer
    telerehab("run", "--sim", "--headless", "--speed", "max", "--seed", "5", home=clinic["home"])
    deadline = time.time() + 60
    while True:  # the station uploads its recording just after the session
        d.get(f"{clinic['web']}/#/patients/{patient_id}/replay")
        ready = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-replays]"))[0]
        if int(ready.get_attribute("data-replays")) >= 1 or time.time() > deadline:
            break
        time.sleep(1)
    d.find_element(By.CSS_SELECTOR, "#replays tbody tr[data-recording='1'] a").click()
    tab = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-frames]"), timeout=60)[0]
    assert tab.get_attribute("data-marks") == "1", tab.get_attribute("data-marks")
    assert tab.get_attribute("data-car") == "0"
    assert not d.find_element(By.ID, "road-panel").is_displayed()
    mark = d.find_element(By.CSS_SELECTOR, "#marks-list button")
    assert len(d.find_elements(By.CSS_SELECTOR, "#timeline-marks .timeline-mark")) == 1
    mark.click()
    assert abs(float(tab.get_attribute("data-position")) - float(mark.get_attribute("data-mark-s"))) < 0.06
    assert_no_violations(d, "the dial replay with its marks")
    shoot_1366(d, "replay-dial-marks")


def test_names_show_for_pseudonyms_without_any_request_or_hub_file_holding_them(clinic, browser, tmp_path):
    d = browser
    d.get(clinic["web"] + "/#/names")
    wait(d, lambda d: d.find_elements(By.ID, "names-file"))
    spy_on_requests(d)
    csv = tmp_path / "names.csv"
    csv.write_text(f"pseudonym,name\nP-0042,{NAME}\nP-9999,Someone Else\n,no pseudonym\n")
    d.find_element(By.ID, "names-file").send_keys(str(csv))
    table = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#names-table[data-names='2']"))[0]
    assert NAME in table.text
    assert d.find_elements(By.CSS_SELECTOR, "#names-problems li"), "the line without a pseudonym is named"
    assert_no_violations(d, "the names page")
    shoot_1366(d, "names")
    # Wherever the pseudonym shows: the caseload, the patient's pages, the audit page.
    d.execute_script("location.hash = '#/patients'")
    link = wait(d, lambda d: d.find_elements(By.PARTIAL_LINK_TEXT, NAME))[0]
    assert link.text == f"{NAME} (P-0042)"
    shoot_1366(d, "names-caseload")
    link.click()
    for tab in ("Live", "Progress", "Replay", "Prescribe"):
        click(d, By.LINK_TEXT, tab)
        wait(d, lambda d: NAME in d.find_element(By.TAG_NAME, "h1").text)
    d.execute_script("location.hash = '#/audit'")
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#audit-table"))
    assert f"{NAME} (P-0042)" in [o.text for o in Select(d.find_element(By.ID, "audit-patient")).options]
    # Nothing the page sent carried the name, and no file of the hub holds it.
    sent = d.execute_script("return window.__sent")
    assert sent, "the spy saw the pages' requests"
    assert not [s for s in sent if NAME in s or "Anna" in s], sent
    for f in (clinic["tmp"] / "clinic").rglob("*"):
        if f.is_file():
            assert NAME.encode() not in f.read_bytes(), f
    # Forgotten on this computer: the pseudonym alone again.
    d.execute_script("location.hash = '#/names'")
    click(d, By.ID, "names-forget")
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#names-table[data-names='0']"))
    d.execute_script("location.hash = '#/patients'")
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "P-0042"))


def test_the_audit_page_lists_entries_in_words_filters_and_pages_for_admins_only(clinic, browser):
    d = browser
    d.get(clinic["web"] + "/#/audit")
    table = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#audit-table[data-entries]"))[0]
    assert int(table.get_attribute("data-entries")) == 50, "a page of 50"
    assert not d.find_element(By.ID, "audit-older").get_attribute("disabled")
    # No internal ids: the therapist by e-mail, the patient by pseudonym.
    assert "therapist:" not in table.text and not re.search(r"\bp-[0-9a-f]{8,}", table.text), table.text
    Select(d.find_element(By.ID, "audit-kind")).select_by_value("put_regimen")
    d.find_element(By.CSS_SELECTOR, "#audit-filter button[type=submit]").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#audit-table[data-page='1'] tr[data-action]")
         and all(r.get_attribute("data-action") == "put_regimen"
                 for r in d.find_elements(By.CSS_SELECTOR, "#audit-table tr[data-action]")))
    rows = d.find_elements(By.CSS_SELECTOR, "#audit-table tr[data-action]")
    # Two saves of the form, two of the station settings, two of the assessment's schedule,
    # the replay test's one.
    assert len(rows) == 7, [r.text for r in rows]
    assert all("ana@clinic.example" in r.text and "P-0042" in r.text for r in rows)
    assert_no_violations(d, "the audit page")
    shoot_1366(d, "audit")
    Select(d.find_element(By.ID, "audit-kind")).select_by_value("")
    d.find_element(By.CSS_SELECTOR, "#audit-filter button[type=submit]").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#audit-table[data-entries='50']"))
    d.find_element(By.ID, "audit-older").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#audit-table[data-page='2']"))

    # A therapist who is not an admin: no link, the page refused in words, the API 403.
    status, answer = send_json(d, "POST", "/api/therapists", {"email": "tom@clinic.example"})
    assert status == 201, answer
    one_time = json.loads(answer)["one_time_password"]
    # Logged out from the caseload (logging out goes there: no second rendering of the login).
    d.execute_script("location.hash = '#/patients'")
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "P-0042"))
    d.find_element(By.ID, "logout").click()
    wait(d, lambda d: d.find_elements(By.ID, "email"))
    d.find_element(By.ID, "email").send_keys("tom@clinic.example")
    d.find_element(By.ID, "password").send_keys(one_time)
    d.find_element(By.CSS_SELECTOR, "#login button").click()
    wait(d, lambda d: d.find_elements(By.ID, "password-form"))
    d.find_element(By.ID, "current-password").send_keys(one_time)
    for field in ("new-password", "repeat-password"):
        d.find_element(By.ID, field).send_keys("tom's own long passphrase")
    d.find_element(By.CSS_SELECTOR, "#password-form button").click()
    wait(d, lambda d: not d.find_elements(By.ID, "password-form") and d.find_element(By.ID, "names-link").is_displayed())
    assert not d.find_element(By.ID, "audit-link").is_displayed()
    d.execute_script("location.hash = '#/audit'")
    wait(d, lambda d: d.find_elements(By.ID, "audit-refused"))
    assert not d.find_elements(By.ID, "audit-table")
    status = d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "fetch('/api/audit', {credentials: 'same-origin'}).then(r => done(r.status));")
    assert status == 403
