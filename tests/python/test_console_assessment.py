"""The standard assessment (issue 42) in the console: a station session whose regimen makes
the assessment due runs it first, then the prescribed dial; the Progress view leads with the
assessment's own section, its numbers as text to the words table's decimals, matching what the
hub serves at /api/patients/{id}/assessments, while the session compares with dial sessions
(its kind `dial`, the assessment left out). Each measure's change since the first assessment
is told from measurement noise (the hub's verdict, metrics::change): better, worse or within
measurement noise, in words and for screen readers, in English and German, on the screen and
the one-page print. axe-core finds no violation. Screenshots at 1366×768 in
$TELEREHAB_ARTIFACTS (default target/test-artifacts/console)."""

import base64
import json
import re
import sqlite3
import time

from selenium.webdriver.common.by import By

from axe_audit import assert_no_violations, use_language
from console_messages import message
from test_console_browser import ARTIFACTS, browser, clinic, shot, telerehab, wait  # noqa: F401 (fixtures)
from test_console_clinic import fetch_json
from test_console_progress import api_sessions_with_metrics
from test_console_words import log_in

def printed_pages(d, name):
    """The page printed to A4 (kept as `name`.pdf beside the screenshots): its page count."""
    pdf = base64.b64decode(d.execute_cdp_cmd("Page.printToPDF", {"paperWidth": 8.27, "paperHeight": 11.69})["data"])
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    (ARTIFACTS / f"{name}.pdf").write_bytes(pdf)
    return len(re.findall(rb"/Type\s*/Page[^s]", pdf))


REGIMEN = """[assessment]
every_days = 7

[[exercise]]
kind = "dial"
duration_s = 10.0
"""


def test_progress_leads_with_the_standard_assessment_apart_from_the_exercise_trends(clinic, browser):
    d = browser
    d.set_window_size(1366, 768)
    regimen = clinic["tmp"] / "assessment.toml"
    regimen.write_text(REGIMEN)
    telerehab("run", "--sim", "--headless", "--speed", "max", "--regimen", str(regimen), "--seed", "6",
              "--checkin-timeout-s", "0", home=clinic["home"])
    # At full speed the session outruns the hub's intake and may end with its last summaries
    # and Bye queued at the station, which delivers them at its next connection: as the
    # cohort does, deliver them now.
    telerehab("sync", home=clinic["home"])
    log_in(d, clinic)
    d.find_element(By.LINK_TEXT, "P-0042").click()
    progress = wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Progress"))[0]
    pid = d.execute_script("return location.hash.split('/')[2]")
    # The session's results (its assessment among them) come with its Bye, which the hub may
    # still be storing on a loaded machine after the session's first summaries show: wait for
    # it, then open the page.
    assessments = wait(d, lambda d: fetch_json(d, f"/api/patients/{pid}/assessments"), timeout=60)
    assert len(assessments) == 1 and assessments[0]["protocol"] == 1, assessments
    progress.click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-sessions='1']"), timeout=60)
    # The assessment's section comes first on the page.
    first = d.execute_script("return document.querySelector('#tab section.panel').id")
    assert first == "assessment", first
    assert d.find_element(By.ID, "assessment-h").text == message(d, "progress-assessment-title")
    parts = {p["kind"]: p for p in assessments[0]["parts"]}
    assert len(parts) == 6, list(parts)
    decimals = {m["key"]: m["decimals"] for m in fetch_json(d, "/api/measures/words")["measures"]}
    # Every number of the table is the hub's, as text.
    for part, key in [("range", "wheel_rom_deg"), ("tracking-slow", "dial_rms_error_deg"),
                      ("steps", "reaction_time_s_median"), ("strength", "strength_peak_left_nm")]:
        v = parts[f"assessment-{part}"]["scores"][key]
        cell = d.find_element(By.CSS_SELECTOR, f"#assessment-table tr[data-part='{part}'] td[data-key='{key}']")
        assert cell.text == f"{v:.{decimals[key]}f}", (part, key, v, cell.text)
    # The assessments' own spreadsheet is offered beside the measures': a row a part's measure.
    link = d.find_element(By.ID, "assessments-csv")
    zone = d.execute_script("return Intl.DateTimeFormat().resolvedOptions().timeZone || 'UTC'")
    zone_words = message(d, "progress-zone-utc") if zone == "UTC" else message(d, "progress-zone", {"zone": zone})
    assert link.text == message(d, "progress-download-assessments", {"zone": zone_words}), link.text
    sheet = d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "fetch(arguments[0], {credentials: 'same-origin'}).then(r => r.text()).then(done);",
        link.get_attribute("href"))
    rows = sheet.splitlines()
    assert "assessment_protocol" in rows[1] and len(rows) > 2 + 6, rows[:3]
    assert any(",steps," in r and "reaction_time_s_median" in r for r in rows), rows[:6]
    # The session is a dial session in the trends: the assessment is not part of its kind.
    sessions = api_sessions_with_metrics(d)
    assert [s["exercise_kind"] for s in sessions] == ["dial"], sessions
    assert "step_responses" not in sessions[0]["metrics"], sessions[0]["metrics"]
    assert_no_violations(d, "Progress, standard assessment")
    shot(d, "progress-assessment-1366x768")
    # Every row of the assessment filled and the dial session's table beside it: one page.
    assert printed_pages(d, "progress-assessment-printed") == 1, "the Progress print is one page"


WEEK_MS = 7 * 86_400_000
# Eight weekly assessments of P-0077: active range gains 20° at the end (beyond the noise of
# its own repeats), reaction time wanders within its noise, strength on the left falls 2 N·m.
ROM_DEG = [120.0, 122.0, 119.0, 123.0, 121.0, 124.0, 122.0, 140.0]
REACTION_S = [0.60, 0.62, 0.58, 0.61, 0.59, 0.60, 0.62, 0.59]
STRENGTH_LEFT_NM = [5.0, 5.1, 4.9, 5.0, 5.1, 5.0, 4.9, 3.0]


def seed_assessments(db_path, now_ms):
    """P-0077's station and eight weekly standard assessments, the last a day ago, written into
    the hub's database as the station's Bye would have stored them."""
    con = sqlite3.connect(db_path, timeout=10)
    pid = con.execute("SELECT id FROM patients WHERE pseudonym = 'P-0077'").fetchone()[0]
    station = "st-77aa0000bb11cc22"
    con.execute("INSERT INTO stations (station_id, patient_id, cert_fingerprint, paired_at_ms, last_seen_ms) "
                "VALUES (?, ?, ?, ?, ?)", (station, pid, "7" * 64, now_ms - 60 * WEEK_MS, now_ms))
    for week in range(8):
        start = now_ms - 86_400_000 - (7 - week) * WEEK_MS
        sid = f"assessment-{week}"
        con.execute("INSERT INTO sessions (session_id, station_id, patient_id, exercise, started_unix_ms, "
                    "software_version, opened_at_ms, closed_at_ms, end_reason, last_seq) "
                    "VALUES (?, ?, ?, 'regimen:6', ?, 'telerehab 0.1.0', ?, ?, 'complete', 0)",
                    (sid, station, pid, start, start, start + 600_000))
        parts = [("assessment-range", {"wheel_rom_deg": ROM_DEG[week]}),
                 ("assessment-steps", {"reaction_time_s_median": REACTION_S[week]}),
                 ("assessment-strength", {"strength_peak_left_nm": STRENGTH_LEFT_NM[week]})]
        for i, (kind, scores) in enumerate(parts):
            con.execute("INSERT INTO session_exercises (session_id, exercise_index, kind, name, prescribed_s, "
                        "active_s, scores_json, assessment_protocol, assessment_seed) VALUES (?, ?, ?, ?, 30, 30, ?, 1, 7)",
                        (sid, i, kind, kind, json.dumps(scores)))
    con.commit()
    con.close()


def change_cell(d, part, key):
    return d.find_element(By.CSS_SELECTOR, f"#assessment-table tr[data-part='{part}'][data-key='{key}'] td.change")


def test_the_change_since_the_first_assessment_is_told_from_noise_in_two_languages(clinic, browser):
    d = browser
    d.set_window_size(1366, 768)
    data = clinic["tmp"] / "clinic"
    telerehab("hub", "patient", "add", "--data", str(data), "--pseudonym", "P-0077")
    seed_assessments(data / "hub.db", int(time.time() * 1000))
    # Logged in already when the test above ran first; else the first login.
    d.get(clinic["web"] + "/")
    wait(d, lambda d: d.find_elements(By.ID, "email") or d.find_elements(By.LINK_TEXT, "P-0042"))
    if d.find_elements(By.ID, "email"):
        log_in(d, clinic)
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "P-0077"))[0].click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Progress"))[0].click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#assessment-table td.change"), timeout=60)
    pid = d.execute_script("return location.hash.split('/')[2]")
    served = fetch_json(d, f"/api/patients/{pid}/assessments?limit=4")
    changes = {(c["part"], c["measure"]): c for c in served[0]["changes"]}
    rom = changes[("range", "wheel_rom_deg")]
    assert (rom["verdict"], rom["band_source"], rom["band"], rom["repeats"]) == ("better", "own", 15.0, 8), rom
    assert changes[("steps", "reaction_time_s_median")]["verdict"] == "within-noise", changes
    assert changes[("strength", "strength_peak_left_nm")]["verdict"] == "worse", changes

    def check(lang, rom_text, strength_text):
        cells = {(part, key): change_cell(d, part, key) for part, key in
                 [("range", "wheel_rom_deg"), ("steps", "reaction_time_s_median"), ("strength", "strength_peak_left_nm")]}
        for (part, key), cell in cells.items():
            verdict = changes[(part, key)]["verdict"]
            assert cell.get_attribute("data-verdict") == verdict, (lang, part, key)
            words = message(d, f"progress-assessment-verdict-{verdict}")
            # The verdict in plain words on the screen (not colour alone) ...
            assert cell.find_element(By.CSS_SELECTOR, ".verdict").text.endswith(words), (lang, cell.text)
            # ... and one sentence for screen readers, naming the band's source.
            spoken = cell.find_element(By.CSS_SELECTOR, ".visually-hidden").get_attribute("textContent")
            source = message(d, f"progress-assessment-source-{changes[(part, key)]['band_source']}", {"repeats": 8})
            assert words in spoken and source in spoken, (lang, spoken)
            assert cell.get_attribute("title") == source
        assert cells[("range", "wheel_rom_deg")].text.startswith(rom_text), (lang, cells[("range", "wheel_rom_deg")].text)
        assert cells[("strength", "strength_peak_left_nm")].text.startswith(strength_text), lang
        assert message(d, "progress-assessment-verdict-within-noise") in cells[("steps", "reaction_time_s_median")].text
        # A measure this patient has no values of says so, and gives no verdict.
        sparc = change_cell(d, "steps", "sparc_median")
        assert sparc.get_attribute("data-verdict") is None
        assert message(d, "progress-assessment-change-missing") in sparc.get_attribute("textContent")

    check("en", "+20 ° ± 15 ° (own)", "−2.0 N·m ± 1.5 N·m (own)")
    assert message(d, "progress-assessment-verdict-within-noise") == "within measurement noise"
    assert_no_violations(d, "Progress, change since the first assessment")
    shot(d, "progress-assessment-change-en-1366x768")
    # The print keeps the column, its verdicts in words and the note on the band, on one page.
    d.execute_cdp_cmd("Emulation.setEmulatedMedia", {"media": "print"})
    assert d.find_element(By.ID, "assessment-noise-note").is_displayed()
    assert change_cell(d, "range", "wheel_rom_deg").is_displayed()
    shot(d, "progress-assessment-change-printed")
    d.execute_cdp_cmd("Emulation.setEmulatedMedia", {"media": ""})
    assert printed_pages(d, "progress-assessment-change-printed") == 1, "the Progress print is one page"
    try:
        use_language(d, "de")
        wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#assessment-table td.change"), timeout=60)
        assert message(d, "progress-assessment-verdict-within-noise") == "im Bereich des Messrauschens"
        check("de", "+20 ° ± 15 ° (eigen)", "−2,0 N·m ± 1,5 N·m (eigen)")
        assert_no_violations(d, "Progress, change since the first assessment, German")
        shot(d, "progress-assessment-change-de-1366x768")
    finally:
        use_language(d, "en")
