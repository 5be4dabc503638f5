"""The report for a record (`telerehab report`) as a clinician reads it, in a real browser
(Debian's chromium, headless): sessions recorded by a station paired with a clinic name the
patient by the clinic's pseudonym, never an internal id; each session is named by date and
time with its exercises prescribed against performed, how it ended and its arm calibration;
trends compare only sessions of one kind that ran as prescribed; seeds, paths and versions are
only in the technical appendix at the end; and axe-core finds no violation. Screenshots
(report-*.png) go to $TELEREHAB_ARTIFACTS (default target/test-artifacts/console)."""

import os
import re
import signal
import subprocess
import time

import pytest
from selenium.webdriver.common.by import By

from axe_audit import assert_no_violations
from test_console_browser import ARTIFACTS, BIN, browser, shot, telerehab  # noqa: F401 (fixture)


def run(home, exercise, seed):
    """A short simulated session at full speed, recorded in the paired station's home."""
    telerehab("run", "--sim", "--headless", "--speed", "max", "--duration", "12",
               "--exercise", exercise, "--seed", str(seed), "--checkin-timeout-s", "0", home=home)


def run_stopped_early(home, exercise, seed):
    """A real-time session the patient stops after a few seconds (a stop signal)."""
    env = {k: v for k, v in os.environ.items() if k != "TELEREHAB_HOME"} | {"TELEREHAB_HOME": str(home)}
    proc = subprocess.Popen(
        [BIN, "run", "--sim", "--headless", "--duration", "60", "--exercise", exercise,
         "--seed", str(seed), "--checkin-timeout-s", "0"],
        env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    time.sleep(4)
    proc.send_signal(signal.SIGINT)
    out, err = proc.communicate(timeout=60)
    assert proc.returncode == 0, f"{out}\n{err}"


@pytest.fixture(scope="module")
def recordings(tmp_path_factory):
    """Four sessions of a station paired for P-0042: a road, a dial task, a road the patient
    stopped early, and the sine road ana@clinic.example prescribed — oldest first."""
    tmp = tmp_path_factory.mktemp("report")
    data = tmp / "clinic"
    telerehab("hub", "init", "--data", str(data), "--admin", "ana@clinic.example")
    added = telerehab("hub", "patient", "add", "--data", str(data), "--pseudonym", "P-0042")
    code = re.search(r"pairing code: (\S+)", added).group(1)
    hub = subprocess.Popen(
        [BIN, "hub", "serve", "--data", str(data), "--stations", "127.0.0.1:0", "--web", "127.0.0.1:0"],
        stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
    )
    try:
        stations = re.search(r"stations listening on (\S+)", hub.stdout.readline()).group(1)
        home = tmp / "station"
        telerehab("pair", "--hub", "localhost:" + stations.rsplit(":", 1)[1], "--code", code, home=home)
        run(home, "sine-road", 11)
        run(home, "dial-step", 12)
        run_stopped_early(home, "sine-road", 13)
        # The fourth runs the regimen the clinic prescribed (the hub names its prescriber).
        regimen = tmp / "sine.toml"
        regimen.write_text('[[exercise]]\nkind = "sine"\nduration_s = 12.0\n')
        telerehab("hub", "patient", "regimen", "--data", str(data), "P-0042", "--file", str(regimen),
                  "--by", "ana@clinic.example")
        telerehab("run", "--sim", "--headless", "--speed", "max", "--seed", "14", "--checkin-timeout-s", "0",
                  home=home)
    finally:
        hub.terminate()
        hub.wait(timeout=20)
    files = sorted((home / "recordings").glob("*.mcap"))
    assert len(files) == 4, files
    return {"files": files, "tmp": tmp, "internal_id": added}


def write_report(recordings, files, name):
    out = recordings["tmp"] / f"{name}.html"
    telerehab("report", *map(str, files), "--out", str(out))
    return out


def text_of(driver, css):
    return driver.find_element(By.CSS_SELECTOR, css).text


def test_a_paired_stations_report_names_the_patient_and_says_prescribed_against_performed(browser, recordings):
    files = recordings["files"]
    # The brief's three sessions: two kinds, one ended early.
    out = write_report(recordings, files[:3], "report-3")
    html = out.read_text()
    browser.set_window_size(1366, 768)
    browser.get(out.as_uri())
    assert browser.title == "Rehabilitation report: P-0042 — telerehab"
    header = text_of(browser, "header")
    assert "Patient\nP-0042" in header or "Patient P-0042" in header, header
    assert "Clinic" in header and "3 sessions" in header, header
    shot(browser, "report-3-front-1366")
    assert_no_violations(browser, "report of three sessions")

    # No internal ids, anywhere.
    internal = re.findall(r"p-[0-9a-f]{16}", html)
    assert not internal, internal
    assert "patient-0" not in html

    # Seeds, paths and versions only in the appendix, which is last.
    main = browser.find_element(By.TAG_NAME, "main")
    appendix = browser.find_element(By.ID, "technical")
    body_text = main.text.replace(appendix.text, "")
    for technical in ("seed", ".mcap", str(recordings["tmp"]), "format"):
        assert technical not in body_text.lower(), technical
    assert "Seed" in appendix.text and ".mcap" in appendix.text
    sections = main.find_elements(By.CSS_SELECTOR, ":scope > section")
    assert sections[-1].get_attribute("id") == "technical"

    # At a glance: prescribed against performed, the end reason in words, the early one marked.
    glance = text_of(browser, "#glance")
    assert "Prescribed (min)" in glance and "Performed, active (min)" in glance
    assert "Ended: complete" in glance
    assert "Ended early by the patient" in glance, glance
    assert "no: not as prescribed" in glance
    # Each session: its exercises by name, per exercise prescribed vs active, the arm line.
    s1 = text_of(browser, "#session-1")
    assert re.search(r"Session 1, \d+ \w+ \d{4}, \d\d:\d\d UTC: Sine road", s1), s1
    assert "Prescribed against performed, per exercise" in s1
    assert re.search(r"1\. Sine road 12 12 yes", s1), s1
    assert re.search(r"Arm calibration: upper arm \d+\.\d cm", s1), s1
    assert "Dial step" in text_of(browser, "#session-2")
    s3 = text_of(browser, "#session-3")
    assert "Ended early by the patient" in s3 and "left out of the trends" in s3, s3
    # Two kinds: neither trended with the other.
    progress = text_of(browser, "#progress")
    assert "Road exercises" in progress and "Dial exercises" in progress
    assert "not in the trends" in progress
    assert "better" not in progress and "worse" not in progress
    browser.get(out.as_uri() + "#session-3")
    shot(browser, "report-3-session-ended-early-1366")


def test_trends_count_only_sessions_of_one_kind_that_ran_as_prescribed(browser, recordings):
    out = write_report(recordings, recordings["files"], "report-4")
    browser.set_window_size(1366, 768)
    browser.get(out.as_uri())
    assert_no_violations(browser, "report of four sessions")
    # The prescribed session names its prescriber as the clinic does (the hub told the station).
    assert "ana@clinic.example" in text_of(browser, "header"), text_of(browser, "header")
    road = text_of(browser, "#progress-road")
    assert "2 sessions as prescribed; not in the trends:" in road, road
    assert "Baseline" in road and "Latest" in road and "Trend" in road
    # The charts' session axis: dates and times at whole sessions, never 1.5.
    svg = browser.find_element(By.CSS_SELECTOR, "#progress-road svg").get_attribute("outerHTML")
    labels = [label.strip() for label in re.findall(r">([^<>]+)</text>", svg)]
    assert any(re.fullmatch(r"\d+ \w{3} \d\d:\d\d(:\d\d)?", label) for label in labels), labels
    assert not any(re.fullmatch(r"\d+\.5", label) for label in labels), labels
    # Every chart's numbers are also a table.
    figures = browser.find_elements(By.CSS_SELECTOR, "figure.chart")
    assert figures and all(f.find_elements(By.CSS_SELECTOR, "details table") for f in figures)
    browser.get(out.as_uri() + "#progress")
    shot(browser, "report-4-progress-1366")
    # Printed: the first page is the front and the sessions at a glance.
    pdf = recordings["tmp"] / "report-4.pdf"
    subprocess.run(["/usr/bin/chromium", "--headless=new", "--no-sandbox", "--disable-gpu",
                    f"--print-to-pdf={pdf}", "--no-pdf-header-footer", out.as_uri()],
                   check=True, capture_output=True, timeout=120)
    assert pdf.stat().st_size > 10_000
    ARTIFACTS.mkdir(parents=True, exist_ok=True)
    (ARTIFACTS / "report-4.pdf").write_bytes(pdf.read_bytes())
