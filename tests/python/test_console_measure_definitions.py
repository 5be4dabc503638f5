"""Each measure where it is defined (issue 42), in the console: a 60 s slalom (one continuous
task) reports no smoothness of its long continuous movement, a lane change reports its anticipations as such and no reaction
time, and the Progress tab says what every measure it shows measures and where it comes from
(`words-definition-<key>` of the console's catalogues; the sources of docs/MEASURES.md); axe-core
finds no violation. Screenshot at 1366×768 in $TELEREHAB_ARTIFACTS (default
target/test-artifacts/console); progress-measure-definitions.png is in docs/screenshots."""

from selenium.webdriver.common.by import By

from axe_audit import assert_no_violations
from test_console_browser import browser, clinic, shot, telerehab, wait  # noqa: F401 (fixtures)
from test_console_progress import api_sessions_with_metrics
from test_console_words import log_in


def run_for(clinic, exercise, seconds, seed):
    telerehab("run", "--sim", "--headless", "--speed", "max", "--exercise", exercise, "--duration", str(seconds),
              "--seed", str(seed), "--checkin-timeout-s", "0", home=clinic["home"])


def test_a_slaloms_long_movement_is_not_scored_a_lane_change_anticipates_and_every_measure_is_defined(clinic, browser):
    run_for(clinic, "slalom", 60, 7)
    run_for(clinic, "lane-change", 60, 8)
    d = browser
    d.set_window_size(1366, 768)
    log_in(d, clinic)
    d.find_element(By.LINK_TEXT, "P-0042").click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Progress"))[0].click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-sessions='2']"))
    sessions = api_sessions_with_metrics(d)
    by_exercise = {s["exercise"]: s["metrics"] for s in sessions}
    slalom, lane = by_exercise["slalom"], by_exercise["lane-change"]
    assert slalom["movements"] >= 1, slalom
    # The slalom is steered without rest for ~55 s (issue 42 measured SPARC −6.44 over that one
    # "movement"): it is not discrete and not scored; smoothness, if any, is of the short
    # movements from rest to rest alone (seed 7: one of 0.4 s, SPARC about −1.5).
    assert slalom["movement_time_s_mean"] * slalom["movements"] > 50.0, slalom
    assert slalom["discrete_movements"] < slalom["movements"], slalom
    if "sparc_median" in slalom:
        assert slalom["discrete_movements"] >= 1 and slalom["sparc_median"] > -3.0, slalom
    assert "pct_in_lane" in slalom and "reversals_per_min" in slalom, slalom
    # The lane change's shifts are seen coming: an anticipation share, no reaction time.
    assert 0.0 <= lane["anticipation_pct"] <= 100.0, lane
    assert "reaction_time_s_median" not in lane, lane

    panel = d.find_element(By.ID, "definitions")
    panel.find_element(By.TAG_NAME, "summary").click()
    rows = panel.find_elements(By.CSS_SELECTOR, "tbody tr")
    shown = {r.get_attribute("data-key") for r in rows}
    assert {"anticipation_pct", "discrete_movements", "pct_in_lane"} <= shown, shown
    for r in rows:
        key = r.get_attribute("data-key")
        definition = r.find_element(By.CSS_SELECTOR, "td.definition").text
        assert len(definition) > 15 and "words-definition" not in definition, (key, definition)
        source = r.find_element(By.CSS_SELECTOR, "td.note").text
        assert len(source) > 10, (key, source)
    # The latest table's names carry their definitions too.
    names = d.find_elements(By.CSS_SELECTOR, "#latest-table tbody th[scope='row']")
    assert names and all(len(n.get_attribute("title")) > 15 for n in names)
    assert_no_violations(d, "Progress, measure definitions")
    d.execute_script("document.getElementById('definitions').scrollIntoView()")
    shot(d, "progress-measure-definitions")
