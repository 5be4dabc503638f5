"""The robot-grade movement measures (issue 30) reach the console: two simulated dial-step
sessions (the target steps, so the wheel's reaction time, initial direction error and path
length ratio are measured) send them in their Bye, and the Progress view charts the speed
metric, the movement and reaction times, the initial direction error, the path length ratio and
the dose, one unit an axis, each chart's numbers in a table; axe-core finds no violation.
Screenshot at 1366×768 in $TELEREHAB_ARTIFACTS (default target/test-artifacts/console)."""

from selenium.webdriver.common.by import By

from axe_audit import assert_no_violations
from test_console_browser import browser, clinic, shot, telerehab, wait  # noqa: F401 (fixtures)
from test_console_progress import api_sessions_with_metrics
from test_console_words import log_in, run_session

# One chart a measure (`p-<kind>-<measure key>`), drawn when the kind's group is opened.
ROBOT_KEYS = ["speed_metric_median", "movements_per_min", "reaction_time_s_median",
              "initial_direction_error_deg_mean", "path_length_ratio_median", "active_s"]


def test_a_dial_step_sessions_robot_measures_reach_the_progress_charts_and_tables(clinic, browser):
    for seed in (3, 4):
        run_session(clinic, "dial-step", seed)
    d = browser
    d.set_window_size(1366, 768)
    log_in(d, clinic)
    d.find_element(By.LINK_TEXT, "P-0042").click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Progress"))[0].click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-sessions='2']"))
    sessions = api_sessions_with_metrics(d)
    m = sessions[0]["metrics"]
    # The hub stored them from the Bye: a dial step every few seconds, the simulated patient
    # turning after its reaction delay (assist::human, 50 ms by default: what is measured).
    assert m["step_responses"] >= 1, m
    assert 0.02 <= m["reaction_time_s_median"] < 2.0, m
    assert 0.0 <= m["initial_direction_error_deg_mean"] <= 180.0, m
    assert m["path_length_ratio_median"] >= 0.5, m
    assert 0.0 < m["speed_metric_median"] <= 1.0, m
    assert m["movements_per_min"] > 0.0, m
    assert "reversals_per_min" in m, m

    group = d.find_element(By.CSS_SELECTOR, "details.kind-group[data-kind='dial']")
    group.find_element(By.TAG_NAME, "summary").click()
    for key in ROBOT_KEYS:
        chart = wait(d, lambda d: d.find_elements(By.ID, f"p-dial-{key}"))[0]
        assert chart.get_attribute("data-key") == key
        # One measure an axis: drawn, never two measures joined by " / ".
        wait(d, lambda d: chart.get_attribute("data-y-axis"))
        assert " / " not in chart.get_attribute("data-y-axis"), key
        table = chart.find_element(By.XPATH, "..").find_element(By.CSS_SELECTOR, "details.numbers table")
        assert len(table.find_elements(By.CSS_SELECTOR, "tbody tr")) == 2, key
    # The latest table's reaction time is the session's, to 2 decimals, in seconds.
    latest = d.find_element(By.CSS_SELECTOR, "#latest-table tr[data-key='reaction_time_s_median'] td").text
    assert latest == f"{m['reaction_time_s_median']:.2f} s", latest
    # Opened, so that axe-core and the screenshot see the numbers too.
    times = d.find_element(By.ID, "p-dial-reaction_time_s_median").find_element(By.XPATH, "..")
    times.find_element(By.CSS_SELECTOR, "details.numbers summary").click()
    assert_no_violations(d, "Progress, robot-grade measures")
    d.execute_script("document.getElementById('p-dial-speed_metric_median').scrollIntoView()")
    shot(d, "progress-robot-measures")
