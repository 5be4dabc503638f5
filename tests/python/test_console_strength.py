"""The strength test (issue 30) in the console: while a simulated strength test runs on the
paired station, the live view shows the side being pushed, the push now against the ceiling and
each side's peak so far in N·m (a bar per side, the same numbers in a table); after it and a
second session, the Progress view groups the strength sessions and charts their peak and held
torque each way, the numbers in a table that matches what the hub stored. axe-core finds no
violation on either. Screenshots at 1366×768 in $TELEREHAB_ARTIFACTS (default
target/test-artifacts/console)."""

import os
import subprocess

from selenium.webdriver.common.by import By

from axe_audit import assert_no_violations
from console_messages import message
from test_console_browser import BIN, browser, clinic, shot, telerehab, wait  # noqa: F401 (fixtures)
from test_console_clinic import fetch_json
from test_console_progress import api_sessions_with_metrics
from test_console_words import log_in

STRENGTH_KEYS = ["strength_peak_left_nm", "strength_sustained_left_nm",
                 "strength_peak_right_nm", "strength_sustained_right_nm"]


def table_numbers(d, side):
    """The live table's push now and peak so far of `side` (None where it shows none), read at
    once: the table is redrawn at every summary."""
    return tuple(d.execute_script(
        "const row = document.querySelector(`#strength-table tr[data-side='${arguments[0]}']`);"
        "const v = a => { const x = row && row.querySelector(`td[${a}]`)?.getAttribute(a); return x ? Number(x) : null; };"
        "return [v('data-now'), v('data-peak')];", side))


def table_ceiling(d):
    """The ceiling the live table gives, N·m."""
    return d.execute_script(
        "return parseFloat(document.querySelector(\"#strength-table tr[data-side='left'] td:last-child\").textContent);")


def test_a_strength_test_shows_live_then_in_the_progress_charts_and_tables(clinic, browser):
    d = browser
    d.set_window_size(1366, 768)
    log_in(d, clinic)
    live = subprocess.Popen(
        [BIN, "run", "--sim", "--headless", "--duration", "14", "--seed", "4", "--exercise", "strength",
         "--checkin-timeout-s", "0"],
        env={**os.environ, "TELEREHAB_HOME": str(clinic["home"])},
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )
    try:
        d.find_element(By.LINK_TEXT, "P-0042").click()
        scene = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#road[data-mode='strength']"), timeout=60)[0]
        assert scene.get_attribute("data-road") == ""
        # Pushing left: the push now and the left side's peak so far, below the ceiling.
        wait(d, lambda d: (table_numbers(d, "left")[1] or 0) > 0.3, timeout=40)
        note = d.find_element(By.ID, "road-note").text
        assert "N·m" in note, note
        assert d.find_element(By.ID, "road-h").text == message(d, "live-scene-strength")
        assert d.find_element(By.ID, "c1-h").text == message(d, "live-tracking-strength")
        assert "lane" not in d.find_element(By.ID, "live").text.lower()
        status = d.find_element(By.ID, "live-status")
        assert status.get_attribute("data-mode") == "strength" and "N·m" in status.text, status.text
        ceiling = table_ceiling(d)
        _, left_peak = table_numbers(d, "left")
        assert 0.3 < left_peak <= ceiling + 1e-6, (left_peak, ceiling)
        assert_no_violations(d, "live view, strength test")
        shot(d, "live-strength-1366x768")
        # The right side follows the rest; the left peak stays shown.
        wait(d, lambda d: (table_numbers(d, "right")[1] or 0) > 0.3, timeout=60)
        assert table_numbers(d, "left")[1] >= left_peak
        shot(d, "live-strength-right-1366x768")
        assert live.wait(timeout=90) == 0
    finally:
        if live.poll() is None:
            live.kill()

    # A second strength session, then the progress view of the two.
    telerehab("run", "--sim", "--headless", "--speed", "max", "--exercise", "strength", "--duration", "12",
              "--seed", "5", "--checkin-timeout-s", "0", home=clinic["home"])
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Progress"))[0].click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#tab[data-sessions='2']"), timeout=60)
    sessions = api_sessions_with_metrics(d)
    assert [s["exercise_kind"] for s in sessions] == ["strength", "strength"], sessions
    # The strength group opens on its summary; one chart and one numbers table a measure.
    group = d.find_element(By.CSS_SELECTOR, "details.kind-group[data-kind='strength']")
    group.find_element(By.TAG_NAME, "summary").click()
    decimals = {m["key"]: m["decimals"] for m in fetch_json(d, "/api/measures/words")["measures"]}
    for key in STRENGTH_KEYS:
        chart = wait(d, lambda d: d.find_elements(By.ID, f"p-strength-{key}"))[0]
        assert chart.get_attribute("data-kind") == "strength"
        assert chart.get_attribute("data-key") == key
        panel = chart.find_element(By.XPATH, "..")
        panel.find_element(By.CSS_SELECTOR, "details.numbers summary").click()
        table = panel.find_element(By.CSS_SELECTOR, "details.numbers table")
        rows = table.find_elements(By.CSS_SELECTOR, "tbody tr")
        assert len(rows) == 2, table.text
        # Every peak and held torque the hub stored is in its table, to the words table's decimals.
        for s in sessions:
            v = s["metrics"][key]
            assert 0.0 < v <= 2.0, (key, v)
            assert f"{v:.{decimals[key]}f}" in table.text, (key, v, table.text)
    # The latest table's held torque is the newest session's, in N·m.
    latest = d.find_element(By.CSS_SELECTOR, "#latest-table tr[data-key='strength_sustained_left_nm'] td").text
    held = sessions[0]["metrics"]["strength_sustained_left_nm"]
    assert latest == f"{held:.{decimals['strength_sustained_left_nm']}f} N·m", latest
    assert_no_violations(d, "Progress, strength sessions")
    d.execute_script("document.getElementById('p-strength-strength_peak_left_nm').scrollIntoView()")
    shot(d, "progress-strength-1366x768")
