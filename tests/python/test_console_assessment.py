"""The standard assessment (issue 42) in the console: a station session whose regimen makes
the assessment due runs it first, then the prescribed dial; the Progress view leads with the
assessment's own section, its numbers as text to the words table's decimals, matching what the
hub serves at /api/patients/{id}/assessments, while the session compares with dial sessions
(its kind `dial`, the assessment left out). axe-core finds no violation. Screenshot at
1366×768 in $TELEREHAB_ARTIFACTS (default target/test-artifacts/console)."""

from selenium.webdriver.common.by import By

from axe_audit import assert_no_violations
from console_messages import message
from test_console_browser import browser, clinic, shot, telerehab, wait  # noqa: F401 (fixtures)
from test_console_clinic import fetch_json
from test_console_progress import api_sessions_with_metrics
from test_console_words import log_in

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
    log_in(d, clinic)
    d.find_element(By.LINK_TEXT, "P-0042").click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Progress"))[0].click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-sessions='1']"), timeout=60)
    # The assessment's section comes first on the page.
    first = d.execute_script("return document.querySelector('#tab section.panel').id")
    assert first == "assessment", first
    assert d.find_element(By.ID, "assessment-h").text == message(d, "progress-assessment-title")
    pid = d.execute_script("return location.hash.split('/')[2]")
    assessments = fetch_json(d, f"/api/patients/{pid}/assessments")
    assert len(assessments) == 1 and assessments[0]["protocol"] == 1, assessments
    parts = {p["kind"]: p for p in assessments[0]["parts"]}
    assert len(parts) == 6, list(parts)
    decimals = {m["key"]: m["decimals"] for m in fetch_json(d, "/api/measures/words")["measures"]}
    # Every number of the table is the hub's, as text.
    for part, key in [("range", "wheel_rom_deg"), ("tracking-slow", "dial_rms_error_deg"),
                      ("steps", "reaction_time_s_median"), ("strength", "strength_peak_left_nm")]:
        v = parts[f"assessment-{part}"]["scores"][key]
        cell = d.find_element(By.CSS_SELECTOR, f"#assessment-table tr[data-part='{part}'] td[data-key='{key}']")
        assert cell.text == f"{v:.{decimals[key]}f}", (part, key, v, cell.text)
    # The session is a dial session in the trends: the assessment is not part of its kind.
    sessions = api_sessions_with_metrics(d)
    assert [s["exercise_kind"] for s in sessions] == ["dial"], sessions
    assert "step_responses" not in sessions[0]["metrics"], sessions[0]["metrics"]
    assert_no_violations(d, "Progress, standard assessment")
    shot(d, "progress-assessment-1366x768")
