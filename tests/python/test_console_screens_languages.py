"""Issue 40, the console's other screens in every language (Chromium, headless): the prescribe
form with the patient's station settings, the clinic, a patient's stations, the live view, the
replay and its list, the names page and the audit log. In the pseudo-locale (`en-XA`, accented
and 40 % longer) no visible sentence is left as the English render shows it (a literal that
escaped the catalogues would be), and nothing overflows sideways at 1366×768 (axe-core on every
screen in every language is test_console_axe.py's). With TELEREHAB_SCREENSHOTS=DIR the station
settings of the prescribe form and a live session in every language are saved at 1366×768 as
DIR/<language>/{prescribe-patient-settings,live-session}.png (the docs' set:
docs/screenshots/console/, docs/SCREENS.md)."""

import json
import os
import re
import subprocess
import time
from pathlib import Path

import pytest
from selenium.common.exceptions import TimeoutException
from selenium.webdriver.common.by import By

from test_console_browser import BIN, browser, serve_clinic, telerehab, wait  # noqa: F401 (fixture)
from test_console_forms import fetch_json, log_in

SIZE = (1366, 768)

# What a visible text node of the page says, for every text node under #app that is shown and
# not deliberately in another language (an element with its own `lang`, such as the station's
# languages named in their own words) nor the regimen's own text (TOML, code).
VISIBLE_TEXTS = """
const out = [];
const walker = document.createTreeWalker(document.getElementById('app'), NodeFilter.SHOW_TEXT);
for (let n = walker.nextNode(); n; n = walker.nextNode()) {
  const text = n.textContent.replace(/\\s+/g, ' ').trim();
  const el = n.parentElement;
  if (!text || !el || el.closest('[lang]:not(html), textarea, code, script, style')) continue;
  if (!el.checkVisibility({ checkOpacity: true, checkVisibilityCSS: true })) continue;
  out.push(text);
}
return out;
"""


@pytest.fixture(scope="module")
def clinic(tmp_path_factory):
    """A clinic (admin ana, patient P-0042 with a paired station) served on loopback."""
    with serve_clinic(tmp_path_factory.mktemp("clinic")) as served:
        yield served


def send_json(d, method, path, body):
    """`method` `path` of the console API with a JSON body: [status, answer]."""
    return d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "fetch(arguments[0], {method: arguments[1], credentials: 'same-origin',"
        " headers: {'Content-Type': 'application/json'}, body: JSON.stringify(arguments[2])})"
        ".then(async r => done([r.status, await r.text()]));", path, method, body)


def use_language(d, tag):
    """The therapist's console language set on the hub, the page reloaded in it."""
    status, answer = send_json(d, "PUT", "/api/me/language", {"language": tag})
    assert status == 200, answer
    d.refresh()
    # The page's first screen drawn in the language (a screen asked for before it would be
    # drawn over by it).
    wait(d, lambda d: d.execute_script(
        "return document.documentElement.dataset.booted === 'true' && document.documentElement.lang") == tag)


def english_sentence(text):
    """Whether `text` reads as English words (two or more lowercase words of three letters or
    more): numbers, dates, units, e-mails and pseudonyms do not."""
    text = re.sub(r"\S+@\S+|\bP-\d+\b", "", text)
    return len(re.findall(r"(?<![\w-])[a-z]{3,}(?![\w-])", text)) >= 2


def start_session(clinic, exercise, seconds):
    """A real-time simulated session of `exercise` on the paired station."""
    return subprocess.Popen(
        [BIN, "run", "--sim", "--headless", "--duration", str(seconds), "--seed", "4", "--exercise", exercise],
        env={**os.environ, "TELEREHAB_HOME": str(clinic["home"])},
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )


@pytest.fixture(scope="module")
def patient(clinic, browser):
    """Logged in as ana; P-0042 has a prescription with station settings and one recorded
    session (its replay uploaded): {id, session}."""
    d = browser
    d.set_window_size(*SIZE)
    telerehab("run", "--sim", "--headless", "--speed", "max", "--duration", "3", "--seed", "7",
              "--exercise", "sine-road", home=clinic["home"])
    log_in(d, clinic).click()
    patient_id = d.current_url.split("#/patients/")[1].split("/")[0]
    presets = fetch_json(d, "/api/regimen/presets")
    dial = next(p for p in presets if p["kind"] == "dial" and p["level"] == "easy")["fields"]
    road = next(p for p in presets if p["kind"] == "sine" and p["level"] == "medium")["fields"]
    fields = {
        "sessions_per_week": 5,
        "patient": {"language": "de", "neglected_side": "left", "speech": False, "start_after_rest_s": 10.0},
        "exercise": [{**dial, "duration_s": 60.0, "rest_s": 20.0}, {**dial, "duration_s": 60.0}, road],
    }
    status, answer = send_json(d, "PUT", f"/api/patients/{patient_id}/regimen", {"fields": fields})
    assert status == 200, answer
    deadline = time.time() + 60
    while True:  # the station uploads its recording just after the session
        sessions = fetch_json(d, f"/api/patients/{patient_id}/sessions")
        ready = [s for s in sessions if s["recording_uploaded"]]
        if ready or time.time() > deadline:
            break
        time.sleep(1)
    assert ready, sessions
    yield {"id": patient_id, "session": ready[0]["session_id"]}
    send_json(d, "PUT", "/api/me/language", {"language": None})


def screens(patient):
    """Each screen: its name, its route, and what shows that it has rendered."""
    pid, session = patient["id"], patient["session"]
    return [
        ("prescribe", f"#/patients/{pid}/prescribe", "#rx-patient"),
        ("clinic", "#/clinic", "#new-patient"),
        ("stations", f"#/clinic/patients/{pid}", "#stations"),
        ("live", f"#/patients/{pid}/live", "#live-status"),
        ("replays", f"#/patients/{pid}/replay", "#replays"),
        ("replay", f"#/patients/{pid}/replay/{session}", "#tab[data-frames]"),
        ("names", "#/names", "#names-file"),
        ("audit", "#/audit", "#audit-table"),
    ]


def show(d, route, ready):
    d.execute_script("location.hash = arguments[0]", route)
    try:
        return wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, ready), timeout=60)[0]
    except TimeoutException:
        shown = d.execute_script("return document.getElementById('app').innerText")
        raise AssertionError(f"{route}: no {ready} within 60 s; the page says:\n{shown[:2000]}") from None


def shoot(d, tag, name):
    """With TELEREHAB_SCREENSHOTS=DIR, the page as shown into DIR/<tag>/<name>.png."""
    if not os.environ.get("TELEREHAB_SCREENSHOTS"):
        return
    out = Path(os.environ["TELEREHAB_SCREENSHOTS"]) / tag
    out.mkdir(parents=True, exist_ok=True)
    d.save_screenshot(str(out / f"{name}.png"))


def test_no_english_sentence_is_left_on_these_screens_in_the_pseudo_locale(patient, browser):
    d = browser
    use_language(d, "en")
    english = {}
    for name, route, ready in screens(patient):
        show(d, route, ready)
        english[name] = set(d.execute_script(VISIBLE_TEXTS))
        assert any(english_sentence(t) for t in english[name]), f"{name}: the check sees English in English"
    use_language(d, "en-XA")
    left = {}
    for name, route, ready in screens(patient):
        show(d, route, ready)
        shown = d.execute_script(VISIBLE_TEXTS)
        assert shown, f"{name}: no text at all"
        same = [t for t in shown if t in english[name] and english_sentence(t)]
        if same:
            left[name] = same
        # 40 % longer words still fit: nothing pushes the page sideways.
        overflow = d.execute_script(
            "return document.documentElement.scrollWidth - document.documentElement.clientWidth")
        assert overflow <= 0, f"{name} in en-XA scrolls sideways by {overflow} px"
    assert not left, "English left in the pseudo-locale:\n" + json.dumps(left, indent=1, ensure_ascii=False)


@pytest.mark.parametrize("tag", ["en", "de", "es", "zh", "en-XA"])
def test_the_station_settings_and_a_live_session_draw_in_each_language(clinic, patient, browser, tag):
    d = browser
    d.set_window_size(*SIZE)
    use_language(d, tag)
    pid = patient["id"]
    form = show(d, f"#/patients/{pid}/prescribe", "#rx-patient")
    d.execute_script("arguments[0].scrollIntoView()", form)
    shoot(d, tag, "prescribe-patient-settings")
    # The live view open before the session starts: it counts every summary the session sends.
    show(d, f"#/patients/{pid}/live", "#live-status")
    session = start_session(clinic, "sine-road", 12)
    try:
        # Found again each time: the view may draw the status anew as summaries arrive.
        wait(d, lambda d: int(d.find_element(By.ID, "live-status").get_attribute("data-summaries") or 0) >= 20,
             timeout=90)
        assert d.execute_script("return document.documentElement.lang") == tag
        shoot(d, tag, "live-session")
    finally:
        assert session.wait(timeout=60) == 0
