"""The console in words and like with like (issue 29), in a real browser (Debian's chromium,
headless): sessions named by date and time and their exercises as the patient saw them (never
an id), a session ended early shown and marked but left out of the trends, the trends
comparing the latest road session with earlier road sessions only (not the dial task), active
time against the prescribed time, the prescriber by e-mail, and a TOML slip refused in plain
words naming its line and field. Screenshots go to $TELEREHAB_ARTIFACTS (default
target/test-artifacts/console); look at them."""

import re
import time

from selenium.webdriver.common.by import By

from test_console_browser import browser, clinic, shot, telerehab, wait  # noqa: F401 (fixtures)

# A session id as the station makes them (2026-11-27T08-51-25.154Z-s7-f7575b1c): never shown.
SESSION_ID = re.compile(r"\d{4}-\d\d-\d\dT\d\d-\d\d-\d\d")

TYPO = """sessions_per_week = 3
[[exercise]]
kind = "sine"
duration_s = 30,5
"""
TWO_EXERCISES = """[[exercise]]
kind = "dial"
duration_s = 4.0

[[exercise]]
kind = "sine"
duration_s = 4.0
"""
VALID = """[[exercise]]
kind = "sine"
duration_s = 30.0
"""


def run_session(clinic, exercise, seed, *extra, check=True):
    telerehab("run", "--sim", "--headless", "--speed", "max", "--exercise", exercise, "--duration", "8",
              "--seed", str(seed), "--checkin-timeout-s", "0", *extra, home=clinic["home"], check=check)


def log_in(d, clinic):
    d.get(clinic["web"] + "/")
    wait(d, lambda d: d.find_elements(By.ID, "email"))[0].send_keys("ana@clinic.example")
    d.find_element(By.ID, "password").send_keys(clinic["password"])
    d.find_element(By.CSS_SELECTOR, "#login button").click()
    # The first login's one-time password must be changed before anything else.
    wait(d, lambda d: d.find_elements(By.ID, "password-form"))
    d.find_element(By.ID, "current-password").send_keys(clinic["password"])
    for field in ("new-password", "repeat-password"):
        d.find_element(By.ID, field).send_keys("a quieter clinic morning")
    d.find_element(By.CSS_SELECTOR, "#password-form button").click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "P-0042"))


def test_progress_names_sessions_in_words_and_trends_road_against_road(clinic, browser, tmp_path):
    # A regimen of a dial task and a road, a dial task, three road sessions, then a road
    # session cut short by an unplugged wheel.
    regimen = tmp_path / "two.toml"
    regimen.write_text(TWO_EXERCISES)
    telerehab("run", "--sim", "--headless", "--speed", "max", "--regimen", str(regimen), "--seed", "9",
              "--checkin-timeout-s", "0", home=clinic["home"])
    run_session(clinic, "dial-sine", 1)
    for seed in (2, 3, 4):
        run_session(clinic, "sine-road", seed)
    # (its exit status is the fault's business, not this test's)
    run_session(clinic, "sine-road", 5, "--fault", "wheel-unplug@3", check=False)
    d = browser
    log_in(d, clinic)

    # The caseload says which sessions its trends compare.
    row = d.find_element(By.XPATH, "//tr[td/a[text()='P-0042']]")
    assert row.find_elements(By.CSS_SELECTOR, ".trend-kind[data-exercise-kind='road'] [data-trend='pct_in_lane']"), row.text
    shot(d, "words-1-caseload")

    d.find_element(By.LINK_TEXT, "P-0042").click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Progress"))[0].click()
    tab = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-sessions='6']"))[0]
    text = tab.text
    assert not SESSION_ID.search(text), text
    rows = tab.find_elements(By.CSS_SELECTOR, "#sessions-h ~ table tbody tr")
    assert len(rows) == 6, text
    # Newest first: the early one, three roads, the dial task, the regimen by its exercises.
    names = [r.find_elements(By.TAG_NAME, "td")[1].text for r in rows]
    assert names[:5] == ["Sine road"] * 4 + ["Dial sine"], names
    assert names[5].startswith("Dial") and names[5].endswith(", then Sine road"), names
    assert "regimen:" not in text, text
    assert rows[0].get_attribute("data-early") == "1"
    assert "Stopped early: wheel unplugged" in rows[0].text and "not in the trends" in rows[0].text, rows[0].text
    assert all("Completed" in r.text and r.get_attribute("data-early") is None for r in rows[1:]), text

    compared = d.find_element(By.ID, "compared").text
    assert "road sessions" in compared and "Sine road" in compared, compared

    # The latest values are the last complete road session's, not the early one's.
    sessions = d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const p = location.hash.split('/')[2];"
        "fetch(`/api/patients/${p}/sessions`).then(r => r.json()).then(async list => {"
        "  for (const s of list) s.metrics = await (await fetch(`/api/sessions/${s.session_id}/metrics`)).json();"
        "  done(list); });")
    assert [s["ran_as_prescribed"] for s in sessions] == [False] + [True] * 5
    assert [s["exercise_kind"] for s in sessions] == ["road"] * 4 + ["dial", "dial+road"]
    latest = sessions[1]["metrics"]
    cell = lambda key: d.find_element(By.CSS_SELECTOR, f"#latest-table tr[data-key='{key}']").find_elements(By.TAG_NAME, "td")
    lane = cell("pct_in_lane")
    assert lane[0].text == f"{int(latest['pct_in_lane'] + 0.5)} %", (lane[0].text, latest)
    # (lane[1]: the patient's baseline, the mean of the first road sessions)
    assert re.search("(better|worse|steady)", lane[2].text), lane[2].text
    # The road mean: the three road sessions, never the dial task's wheel range.
    roads = [s["metrics"]["wheel_rom_deg"] for s in sessions[1:4]]
    mean = sum(roads[1:]) / 2
    word = lambda last, m: "steady" if abs(last - m) <= 0.02 * abs(m) else ("better" if last > m else "worse")
    rom = cell("wheel_rom_deg")
    assert rom[0].text == f"{int(roads[0] + 0.5)} °", (rom[0].text, roads)
    assert sessions[0]["metrics"]["wheel_rom_deg"] != roads[0], "the early session must differ to tell"
    assert word(roads[0], mean) in rom[2].text, (roads, rom[2].text)
    # Had the dial tasks been compared, the wheel's range would read far from the roads'.
    dials = [s["metrics"]["wheel_rom_deg"] for s in sessions[4:]]
    assert all(abs(v - mean) > 0.02 * abs(mean) for v in dials), (dials, mean)
    active = cell("active_s")
    assert re.fullmatch(r"\d+ (s|min)( of \d+ (s|min) prescribed)?", active[0].text), active[0].text
    assert "not a trend" in active[2].text and "better" not in active[2].text and "worse" not in active[2].text
    d.execute_script("document.getElementById('latest-h').scrollIntoView()")
    shot(d, "words-2-progress-like-with-like")
    d.execute_script("document.getElementById('sessions-h').scrollIntoView()")
    shot(d, "words-3-sessions-in-words")

    # A replay is named by the session's date and time, not its id.
    replay_url = rows[1].find_element(By.LINK_TEXT, "Replay").get_attribute("href")
    deadline = time.time() + 40
    while True:  # the station uploads its recording after the session (seconds on loopback)
        d.get(replay_url)
        # (a new hash, not a new page: wait for the replay's own heading or its error)
        found = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#replay-h, p.error"))[0]
        if found.tag_name == "h2" or time.time() > deadline:
            break
        time.sleep(1)
    head = found
    assert "Sine road" in head.text, head.text
    assert not SESSION_ID.search(head.text), head.text
    shot(d, "words-6-replay-named")


def test_prescribe_names_the_prescriber_and_a_toml_slip_in_plain_words(clinic, browser):
    d = browser  # logged in by the first test (module-scoped browser)
    d.get(clinic["web"] + "/#/patients")
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "P-0042"))[0].click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Prescribe"))[0].click()
    wait(d, lambda d: d.find_elements(By.ID, "rx"))
    d.find_element(By.CSS_SELECTOR, "#prescribe details summary").click()
    toml = d.find_element(By.ID, "toml")

    def save(text):
        toml.clear()
        toml.send_keys(text)
        d.find_element(By.CSS_SELECTOR, "#rx button").click()
        return wait(d, lambda d: [e for e in d.find_elements(By.ID, "rx-result")
                                  if "error" in e.get_attribute("class") or e.get_attribute("data-saved")])[0]

    refused = save(TYPO).text
    assert "Line 4" in refused and "duration_s" in refused and "30.5" in refused, refused
    assert "TOML parse error" not in refused and "expected newline" not in refused, refused
    d.execute_script("document.getElementById('rx-result').scrollIntoView({block: 'center'})")
    shot(d, "words-4-toml-slip-in-plain-words")
    assert save(VALID).get_attribute("data-saved") == "1"
    d.refresh()
    version = wait(d, lambda d: [e for e in d.find_elements(By.ID, "rx-version") if e.get_attribute("data-version") == "1"])[0].text
    assert "ana@clinic.example" in version and "t-" not in version, version
    shot(d, "words-5-prescribed-by")
