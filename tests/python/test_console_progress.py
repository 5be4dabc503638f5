"""Readable progress and the Replay tab (issue 29), in a real browser (Debian's chromium,
headless): the progress charts grouped by exercise kind (newest kind first) with an axis by
session, so that sessions of one day sit apart; the latest table with the patient's own baseline;
every chart's numbers as a table; a session ended early drawn hollow and left out until the
therapist ticks "Include sessions that ended early"; the Replay tab listing the sessions and
opening a replay; axe-core finds no violation on Progress or the Replay tab. Screenshots (1366×768)
go to $TELEREHAB_ARTIFACTS (default target/test-artifacts/console); look at them."""

import datetime
import re
import sqlite3
import time

from selenium.webdriver.common.by import By

from axe_audit import assert_no_violations
from test_console_browser import browser, clinic, shot, telerehab, wait  # noqa: F401 (fixtures)
from test_console_words import log_in, run_session


def api_sessions_with_metrics(d):
    """The patient's sessions (newest first) as the API gives them, each with its metrics."""
    return d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const p = location.hash.split('/')[2];"
        "fetch(`/api/patients/${p}/sessions`).then(r => r.json()).then(async list => {"
        "  for (const s of list) s.metrics = await (await fetch(`/api/sessions/${s.session_id}/metrics`)).json();"
        "  done(list); });")


def degrees(cell):
    """A cell such as "268 °" as its whole number of degrees (the words table's resolution)."""
    number, unit = cell.split(" ")
    assert unit == "°" and re.fullmatch(r"-?\d+", number), cell
    return int(number)


def round_like_js(v):
    """`v` to a whole number as the console's toFixed(0) rounds it (half away from zero)."""
    return int(v + 0.5) if v >= 0 else -int(-v + 0.5)


def cells(d, key):
    row = d.find_element(By.CSS_SELECTOR, f"#latest-table tr[data-key='{key}']")
    return [td.text for td in row.find_elements(By.TAG_NAME, "td")]


def test_progress_charts_by_kind_and_session_with_a_baseline_and_an_early_session_set_aside(clinic, browser):
    # A dial task, three road sessions (all today: same-day sessions), then a road session cut
    # short by an unplugged wheel.
    run_session(clinic, "dial-sine", 1)
    for seed in (2, 3, 4):
        run_session(clinic, "sine-road", seed)
    run_session(clinic, "sine-road", 5, "--fault", "wheel-unplug@3", check=False)
    d = browser
    d.set_window_size(1366, 768)
    log_in(d, clinic)
    d.find_element(By.LINK_TEXT, "P-0042").click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Progress"))[0].click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-sessions='5']"))
    sessions = api_sessions_with_metrics(d)
    assert [s["exercise_kind"] for s in sessions] == ["road"] * 4 + ["dial"]
    assert [s["ran_as_prescribed"] for s in sessions] == [False] + [True] * 4

    # Grouped by kind, the newest kind first, named in words, each behind its summary.
    groups = d.find_elements(By.CSS_SELECTOR, "#charts .kind-group")
    assert [g.get_attribute("data-kind") for g in groups] == ["road", "dial"]
    assert groups[0].find_element(By.CSS_SELECTOR, "summary h3").text == "Road sessions (4)"
    assert groups[1].find_element(By.CSS_SELECTOR, "summary h3").text == "Dial sessions (1)"
    for g in groups:
        g.find_element(By.TAG_NAME, "summary").click()
    # No lane chart among the dial task's.
    assert not groups[1].find_elements(By.CSS_SELECTOR, "[id$='-pct_in_lane']")

    # One step a session: the four road sessions of one day at four x positions, four labels.
    lane = wait(d, lambda d: [e for e in d.find_elements(By.ID, "p-road-pct_in_lane") if e.get_attribute("data-xs")])[0]
    assert lane.get_attribute("data-xs") == "1 2 3 4"
    labels = lane.get_attribute("data-labels").split("|")
    assert len(set(labels)) == 4, labels
    # The early session drawn apart and not counted.
    assert lane.get_attribute("data-early") == "4"
    assert lane.get_attribute("data-counted") == "1 2 3"
    # One measure a chart: the lane's error and time in lane are separate charts.
    assert d.find_elements(By.ID, "p-road-rms_lateral_m")
    y_labels = [c.get_attribute("data-y-axis") for c in d.find_elements(By.CSS_SELECTOR, "#charts .chart")]
    assert "Time in lane (%)" in y_labels and "Distance from the lane's centre (m)" in y_labels, y_labels
    keys = [c.get_attribute("data-key") for c in d.find_elements(By.CSS_SELECTOR, "#charts .chart")]
    assert all(keys) and len(keys) == len(y_labels), keys

    # Every chart's numbers as a table, a row a session.
    for chart in d.find_elements(By.CSS_SELECTOR, "#charts .chart"):
        panel = chart.find_element(By.XPATH, "..")
        table = panel.find_element(By.CSS_SELECTOR, "details.numbers table")
        rows = table.find_elements(By.CSS_SELECTOR, "tbody tr")
        group = chart.get_attribute("data-kind")
        assert len(rows) == (4 if group == "road" else 1), chart.get_attribute("id")
        assert table.find_elements(By.CSS_SELECTOR, "caption")
        assert rows[0].find_elements(By.CSS_SELECTOR, "th[scope='row']")

    # The latest table: the newest complete road session, against its baseline (the mean of
    # the first three road sessions), with units.
    roads = [s["metrics"] for s in sessions[1:4]][::-1]  # oldest first
    base = sum(m["wheel_rom_deg"] for m in roads) / 3
    latest, baseline, trend = cells(d, "wheel_rom_deg")
    assert degrees(latest) == round_like_js(roads[-1]["wheel_rom_deg"]), latest
    assert degrees(baseline) == round_like_js(base), (baseline, roads)
    assert "steady" in trend or "better" in trend or "worse" in trend, trend
    active = cells(d, "active_s")
    assert "not a trend" in active[2] and "better" not in active[2] and "worse" not in active[2], active
    assert re.fullmatch(r"\d+ (s|min)( of \d+ (s|min) prescribed)?", active[1]), active
    assert not d.find_elements(By.CSS_SELECTOR, "#latest-table tr[data-key='dial_rms_error_deg']")
    assert_no_violations(d, "Progress")
    shot(d, "progress-1-latest-and-baseline")
    d.execute_script("document.getElementById('p-road-pct_in_lane').scrollIntoView()")
    shot(d, "progress-2-charts-by-session")

    # Ticked: the early session counts (latest and baseline unchanged: it is the fourth).
    early = sessions[0]["metrics"]
    assert early["wheel_rom_deg"] != roads[-1]["wheel_rom_deg"], "the early session must differ to tell"
    d.find_element(By.ID, "include-early").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-include-early='1']"))
    # (the kinds stay open as they were)
    lane = wait(d, lambda d: [e for e in d.find_elements(By.ID, "p-road-pct_in_lane") if e.get_attribute("data-counted") == "1 2 3 4"])[0]
    assert lane.get_attribute("data-early") == "4", "still drawn apart"
    latest, baseline, _ = cells(d, "wheel_rom_deg")
    assert degrees(latest) == round_like_js(early["wheel_rom_deg"]), latest
    assert degrees(baseline) == round_like_js(base), baseline
    assert "ended early are included" in d.find_element(By.ID, "compared").text
    lane_table = lane.find_element(By.XPATH, "..").find_element(By.CSS_SELECTOR, "details.numbers")
    lane_table.find_element(By.TAG_NAME, "summary").click()
    assert "ended early, included" in lane_table.text
    assert_no_violations(d, "Progress, sessions ended early included")
    d.execute_script("document.getElementById('p-road-pct_in_lane').scrollIntoView()")
    shot(d, "progress-3-early-included")
    d.find_element(By.ID, "include-early").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-include-early='0']"))
    wait(d, lambda d: d.find_element(By.ID, "p-road-pct_in_lane").get_attribute("data-counted") == "1 2 3")


def test_the_replay_tab_lists_the_sessions_and_opens_a_replay(clinic, browser):
    d = browser  # logged in by the first test (module-scoped browser)
    nav = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "nav.tabs"))[0]
    tabs = [a.get_attribute("data-tab") for a in nav.find_elements(By.TAG_NAME, "a")][:4]
    assert tabs == ["live", "progress", "replay", "prescribe"], tabs
    wait(d, lambda d: d.find_element(By.CSS_SELECTOR, "nav.tabs a[data-tab='replay']")).click()
    deadline = time.time() + 40
    while True:  # the station uploads its recording after the session (seconds on loopback)
        table = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-replays] #replays"))[0]
        rows = table.find_elements(By.CSS_SELECTOR, "tbody tr")
        if all(r.get_attribute("data-recording") == "1" for r in rows[1:]) or time.time() > deadline:
            break
        time.sleep(1)
        d.refresh()
    assert len(rows) == 5
    # Newest first, by date and time and exercise name; every session either opens or says why not.
    assert [r.find_elements(By.TAG_NAME, "td")[0].text for r in rows] == ["Sine road"] * 4 + ["Dial sine"]
    for r in rows:
        if r.get_attribute("data-recording") == "1":
            assert r.find_element(By.CSS_SELECTOR, "th a").get_attribute("href").count("/replay/") == 1
        else:
            assert any(why in r.text for why in ("has not arrived yet", "Still running", "is arriving")), r.text
    assert rows[1].get_attribute("data-recording") == "1", rows[1].text
    assert_no_violations(d, "Replay tab")
    shot(d, "progress-4-replay-tab")
    # An upload whose station went silent an hour ago says it stopped, not that it is arriving:
    # the newest session's recording is made a third arrived, its last part noted an hour ago.
    db = sqlite3.connect(clinic["tmp"] / "clinic" / "hub.db", timeout=10)
    with db:
        newest = db.execute("SELECT session_id FROM sessions ORDER BY started_unix_ms DESC LIMIT 1").fetchone()[0]
        was = db.execute("SELECT sha256, size_bytes, received_bytes, path, complete, last_part_ms FROM recordings "
                         "WHERE session_id = ?", (newest,)).fetchone()
        db.execute("INSERT INTO recordings (session_id, sha256, size_bytes, received_bytes, path, complete, last_part_ms) "
                   "VALUES (?, ?, 3000, 1000, 'x', 0, ?) ON CONFLICT (session_id) DO UPDATE SET complete = 0, "
                   "size_bytes = 3000, received_bytes = 1000, last_part_ms = excluded.last_part_ms",
                   (newest, "0" * 64, int(time.time() * 1000) - 3_600_000))
    d.refresh()
    stalled = wait(d, lambda d: [r for r in d.find_elements(By.CSS_SELECTOR, "#replays tbody tr")
                                 if "stopped arriving at 33%" in r.text])
    assert "The station sends the rest when it is next online." in stalled[0].text, stalled[0].text
    assert_no_violations(d, "Replay tab, an upload stopped")
    shot(d, "progress-4b-replay-tab-upload-stopped")
    with db:  # as it was, for the tests that follow
        if was is None:
            db.execute("DELETE FROM recordings WHERE session_id = ?", (newest,))
        else:
            db.execute("UPDATE recordings SET sha256 = ?, size_bytes = ?, received_bytes = ?, path = ?, complete = ?, "
                       "last_part_ms = ? WHERE session_id = ?", (*was, newest))
    db.close()
    d.refresh()
    rows = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-replays] #replays tbody tr"))
    started = rows[1].find_element(By.CSS_SELECTOR, "th a").text
    rows[1].find_element(By.CSS_SELECTOR, "th a").click()
    head = wait(d, lambda d: [e for e in d.find_elements(By.CSS_SELECTOR, "#tab h2") if e.text.startswith("Replay of the session of ")])[0]
    assert "Sine road" in head.text, head.text
    assert started in head.text, (started, head.text)
    assert d.find_element(By.CSS_SELECTOR, "nav.tabs a[aria-current='page']").get_attribute("data-tab") == "replay"
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-frames]"))
    shot(d, "progress-5-replay-opened")


def test_the_dose_sums_active_time_and_repetitions_by_week_and_day_from_the_sessions(clinic, browser):
    d = browser  # logged in by the first test (module-scoped browser); five sessions today
    d.get(clinic["web"] + "/#/patients")
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "P-0042"))[0].click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Progress"))[0].click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-sessions='5'] #dose-weeks"))
    sessions = api_sessions_with_metrics(d)
    # Every session that trained counts, the one ended early too: the dose is what was done.
    trained = [s for s in sessions if isinstance(s["metrics"].get("active_s"), (int, float))]
    assert len(trained) == 5, sessions
    # By local day (the browser runs on this machine, in its zone), today first.
    today = datetime.date.today()
    by_day = [[0.0, 0.0] for _ in range(7)]
    for s in trained:
        ago = (today - datetime.datetime.fromtimestamp(s["started_unix_ms"] / 1000).date()).days
        if 0 <= ago < 7:
            by_day[ago][0] += s["metrics"]["active_s"]
            by_day[ago][1] += s["metrics"].get("movements", 0)
    active_s = sum(s["metrics"]["active_s"] for s in trained)
    reps = sum(s["metrics"].get("movements", 0) for s in trained)
    assert reps > 0, "the simulated patient moves the wheel"
    weeks = d.find_elements(By.CSS_SELECTOR, "#dose-weeks tbody tr")
    days = d.find_elements(By.CSS_SELECTOR, "#dose-days tbody tr")
    # The sessions ran minutes ago, the first of them too: one week (none before the patient
    # started), seven days.
    assert len(weeks) == 1 and len(days) == 7, (len(weeks), len(days))
    assert weeks[0].get_attribute("data-sessions") == "5"
    assert int(weeks[0].get_attribute("data-active-s")) == round_like_js(active_s), weeks[0].text
    assert int(weeks[0].get_attribute("data-repetitions")) == round_like_js(reps), weeks[0].text
    assert str(round_like_js(reps)) in weeks[0].text, weeks[0].text
    for row, (a, r) in zip(days, by_day):
        assert int(row.get_attribute("data-active-s")) == round_like_js(a), (row.text, by_day)
        assert int(row.get_attribute("data-repetitions")) == round_like_js(r), (row.text, by_day)
    caption = d.find_element(By.CSS_SELECTOR, "#dose-weeks caption").text
    assert caption == "By week: the last 7 days", caption
    d.execute_script("document.getElementById('dose').scrollIntoView()")
    shot(d, "progress-6-dose")
    # The caseload's week column counts the same repetitions.
    d.get(clinic["web"] + "/#/patients")
    row = wait(d, lambda d: [r for r in d.find_elements(By.CSS_SELECTOR, "tbody tr") if "P-0042" in r.text])[0]
    week = row.find_element(By.CSS_SELECTOR, "td.week")
    assert week.get_attribute("data-repetitions") == str(round_like_js(reps)), week.text
    assert f"{round_like_js(reps)} repetitions" in week.text, week.text


def test_the_dose_puts_each_session_in_its_local_week_and_day_and_no_week_before_the_first(clinic, browser):
    d = browser  # logged in by the first test (module-scoped browser)
    # Sessions at local noon 0, 1, 8 and 20 days ago, one without active time (a Hello alone).
    totals = d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "import('/console/dose.js').then(m => {"
        "  const noon = new Date(); noon.setHours(12, 0, 0, 0);"
        "  const ago = n => { const x = new Date(noon); x.setDate(x.getDate() - n); return x.getTime(); };"
        "  const sessions = [20, 8, 1, 1, 0].map(n => ({ started_unix_ms: ago(n) }));"
        "  const metrics = [{ active_s: 100, movements: 10 }, { active_s: 200, movements: 20 },"
        "    { active_s: 300, movements: 30 }, {}, { active_s: 400 }];"
        "  const r = m.doseTotals(sessions, metrics, noon.getTime() + 3600000);"
        "  done({ days: r.days.map(w => [w.sessions, w.activeS, w.repetitions]),"
        "         weeks: r.weeks.map(w => [w.sessions, w.activeS, w.repetitions]) });"
        "}).catch(e => done(String(e)));")
    assert totals["days"] == [[1, 400, 0], [1, 300, 30]] + [[0, 0, 0]] * 5, totals
    # Weeks: today back to 6 days ago, 7–13, 14–20; none before the session 20 days ago.
    assert totals["weeks"] == [[2, 700, 30], [1, 200, 20], [1, 100, 10]], totals
