"""The live view as a therapist needs it (Chromium, headless, a 1366×768 window): during a road
exercise the road and lane are drawn around the car from what the station streams; during the
dial task nothing speaks of lanes and the dial's target is shown against the wheel; the chart
legends give numbers; the tracking and torque charts are above the fold; axe-core finds no
violation. Screenshots (live-*.png) go to $TELEREHAB_ARTIFACTS (default
target/test-artifacts/console)."""

import os
import re
import signal
import subprocess
import time

import pytest
from selenium.webdriver.common.by import By

from axe_audit import assert_no_violations
from console_messages import message
from test_console_browser import BIN, browser, serve_clinic, shot, telerehab, wait  # noqa: F401 (fixture)
from test_console_clinic import log_in_and_replace_the_one_time_password

NUMBER = re.compile(r"^-?\d+(\.\d+)?$")


@pytest.fixture(scope="module")
def clinic(tmp_path_factory):
    """A clinic (admin ana, patient P-0042 with a paired station) served on loopback."""
    with serve_clinic(tmp_path_factory.mktemp("clinic")) as served:
        yield served


def start_session(clinic, exercise, seconds):
    """A real-time simulated session of `exercise` on the paired station."""
    return subprocess.Popen(
        [BIN, "run", "--sim", "--headless", "--duration", str(seconds), "--seed", "4", "--exercise", exercise],
        env={**os.environ, "TELEREHAB_HOME": str(clinic["home"])},
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
    )


def legend_values(d, chart_id):
    """The legend's value of each series of a chart (not the time axis's)."""
    cells = d.find_elements(By.CSS_SELECTOR, f"#{chart_id} .u-legend .u-series .u-value")
    return [c.text.strip() for c in cells[1:]]


def test_the_live_view_draws_the_road_around_the_car_then_the_dial_without_lanes(clinic, browser):
    d = browser
    d.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                      {"width": 1366, "height": 768, "deviceScaleFactor": 1, "mobile": False})
    try:
        log_in_and_replace_the_one_time_password(d, clinic["web"], "ana@clinic.example", clinic["password"])

        # A road exercise: the station streams the road, the console draws the lane.
        road_session = start_session(clinic, "sine-road", 10)
        d.find_element(By.LINK_TEXT, "P-0042").click()
        road = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#road[data-road='1']"), timeout=40)[0]
        status = d.find_element(By.ID, "live-status")
        wait(d, lambda d: int(status.get_attribute("data-summaries") or 0) >= 30, timeout=40)
        assert float(road.get_attribute("data-lane-width-m")) == pytest.approx(3.5), "the sine road's lane"
        note = d.find_element(By.ID, "road-note").text
        assert note and road.get_attribute("data-scale-bar-m") == "10", note
        # The ceiling's latest value in the legend is the one the status line gives.
        ceiling = float(status.get_attribute("data-ceiling-nm"))
        assert float(legend_values(d, "chart-torque")[2]) == pytest.approx(ceiling, abs=0.01)
        assert status.get_attribute("data-mode") == "road", status.text
        for chart in ("chart-tracking", "chart-torque", "chart-joints"):
            values = legend_values(d, chart)
            assert values and all(NUMBER.match(v) for v in values), (chart, values)
        # Above the fold: the whole chart, legend included, within the first 768 px of the page.
        d.execute_script("window.scrollTo(0, 0)")
        for chart in ("chart-tracking", "chart-torque"):
            top, bottom = d.execute_script(
                "const r = document.getElementById(arguments[0]).getBoundingClientRect();"
                "return [r.top + window.scrollY, r.bottom + window.scrollY];", chart)
            assert bottom <= 768, f"{chart} spans {top:.0f}–{bottom:.0f} px of the page, the window 768 px high"
        assert_no_violations(d, "live view, road exercise")
        shot(d, "live-1-road-1366x768")
        assert road_session.wait(timeout=60) == 0

        # The dial task: the dial's target against the wheel, nothing about lanes.
        dial_session = start_session(clinic, "dial-sine", 10)
        dial = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#road[data-mode='dial']"), timeout=40)[0]
        wait(d, lambda d: d.find_element(By.ID, "road-note").text)
        assert dial.get_attribute("data-road") == ""
        live = d.find_element(By.ID, "live")
        wait(d, lambda d: status.get_attribute("data-mode") == "dial", timeout=20)
        assert "lane" not in live.text.lower(), live.text
        assert d.find_element(By.ID, "road-h").text == message(d, "live-scene-dial")
        assert d.find_element(By.ID, "c1-h").text == message(d, "live-tracking-dial")
        values = legend_values(d, "chart-tracking")
        assert len(values) == 2 and all(NUMBER.match(v) for v in values), values
        assert_no_violations(d, "live view, dial task")
        shot(d, "live-2-dial-1366x768")
        assert dial_session.wait(timeout=60) == 0
        ended = wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#live-status [data-ended]"), timeout=20)[0]
        assert ended.get_attribute("data-reason") == "complete", ended.get_attribute("data-reason")
        assert ended.text == message(d, "live-ended-complete"), ended.text

        # At 200 % zoom (a 700 CSS px window) the panels stack in one column, nothing sideways.
        d.execute_cdp_cmd("Emulation.setDeviceMetricsOverride",
                          {"width": 700, "height": 550, "deviceScaleFactor": 2, "mobile": False})
        overflow = d.execute_script("return document.documentElement.scrollWidth - document.documentElement.clientWidth")
        assert overflow <= 0, f"the live view scrolls sideways by {overflow} px at 200 %"
        shot(d, "live-3-dial-200-percent")
    finally:
        d.execute_cdp_cmd("Emulation.clearDeviceMetricsOverride", {})


def badge_texts(d, kind):
    """The non-empty texts of the live status's `data-delayed=kind` badges (empty: none yet)."""
    found = d.find_elements(By.CSS_SELECTOR, f"#live-status [data-delayed='{kind}']")
    return [t for t in (e.text for e in found) if t]


def test_a_station_gone_quiet_is_shown_delayed_then_its_late_data_marked_late(clinic, browser):
    """Runs after the test above (the same login). A station that stops sending mid-session (its
    process stopped, as a home link that is down looks to the hub) is "delayed", not "running"
    on its last summary; the summaries it sends when it goes on are marked late (issue 45)."""
    d = browser
    d.get(clinic["web"] + "/")
    session = start_session(clinic, "sine-road", 12)
    try:
        wait(d, lambda d: d.find_elements(By.LINK_TEXT, "P-0042"), timeout=20)[0].click()
        status = wait(d, lambda d: d.find_elements(By.ID, "live-status"), timeout=20)[0]
        wait(d, lambda d: int(status.get_attribute("data-summaries") or 0) >= 20, timeout=40)
        assert status.find_elements(By.CSS_SELECTOR, ".badge.ok"), status.text
        session.send_signal(signal.SIGSTOP)
        stopped = time.monotonic()
        # The badges are drawn anew at every check: their text is read where they are found
        # (`wait` retries a badge replaced between the two).
        silent = wait(d, lambda d: badge_texts(d, "silent"), timeout=10)[0]
        assert time.monotonic() - stopped < 5, "delayed said late"
        assert silent.startswith(message(d, "live-delayed-silent", {"seconds": 9})[:8]), silent
        assert not status.find_elements(By.CSS_SELECTOR, ".badge.ok"), "still 'running' while silent"
        assert status.get_attribute("data-delayed") == "silent"
        shot(d, "live-4-delayed")
        time.sleep(3)
        session.send_signal(signal.SIGCONT)
        wait(d, lambda d: status.get_attribute("data-delayed") == "late", timeout=20)
        assert wait(d, lambda d: badge_texts(d, "late"), timeout=10)[0], status.text
    finally:
        session.send_signal(signal.SIGCONT)
        session.wait(timeout=60)
