"""Clinical scales (issues 32, 41), in a real browser (Debian's chromium, headless): a therapist
records a Fugl-Meyer score in the Progress tab and sees it on its own chart (one measure a chart:
never on a second axis beside a station measure), on the scale's own range, with the numbers in a
table; a score out of its range
is refused by the form and, were the form bypassed, by the hub naming the field and its range;
axe-core finds no violation. Screenshots (1366×768) go to $TELEREHAB_ARTIFACTS (default
target/test-artifacts/console); look at them."""

from selenium.webdriver.common.by import By

from axe_audit import assert_no_violations
from console_messages import message
from test_console_browser import browser, clinic, shot, telerehab, wait  # noqa: F401 (fixtures)
from test_console_words import log_in, run_session


def open_progress(d, clinic, sessions):
    d.find_element(By.LINK_TEXT, "P-0042").click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Progress"))[0].click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, f"#tab[data-sessions='{sessions}']"))
    return wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#scales[data-entries]"))[0]


def test_a_fugl_meyer_score_is_charted_on_its_own_scale_and_an_out_of_range_score_is_refused(clinic, browser):
    for seed in (2, 3):
        run_session(clinic, "sine-road", seed)
    d = browser
    d.set_window_size(1366, 768)
    log_in(d, clinic)
    scales = open_progress(d, clinic, 2)
    assert scales.get_attribute("data-entries") == "0"
    assert scales.find_elements(By.ID, "scales-none")
    assert not scales.find_elements(By.CSS_SELECTOR, ".chart"), "no chart before a score"
    d.find_element(By.CSS_SELECTOR, "#scale-form-details summary").click()

    # The form carries the scale's bounds, so the browser says it first.
    score = d.find_element(By.ID, "scale-fugl_meyer_ue-score")
    assert (score.get_attribute("min"), score.get_attribute("max")) == ("0", "66")
    assert score.get_attribute("required") == "true"
    day = d.find_element(By.ID, "scale-day")
    assert day.get_attribute("value") == day.get_attribute("max"), "today by default, and no later"
    score.send_keys("70")
    d.find_element(By.CSS_SELECTOR, "#scale-form button[type=submit]").click()
    assert d.execute_script("return document.getElementById('scale-fugl_meyer_ue-score').validity.rangeOverflow")
    assert d.find_element(By.ID, "scale-result").text == ""
    assert scales.get_attribute("data-entries") == "0", "the browser refused it: nothing sent"
    # A form bypassed (its bound removed) meets the hub's own check, which names the field.
    d.execute_script("document.getElementById('scale-fugl_meyer_ue-score').removeAttribute('max')")
    d.find_element(By.CSS_SELECTOR, "#scale-form button[type=submit]").click()
    result = d.find_element(By.ID, "scale-result")
    wait(d, lambda d: result.text)
    assert "invalid score" in result.text and "from 0 to 66 points" in result.text, result.text
    assert scales.get_attribute("data-entries") == "0"

    # A valid score: saved, listed, and charted on its own chart.
    score = d.find_element(By.ID, "scale-fugl_meyer_ue-score")
    score.clear()
    score.send_keys("34")
    d.find_element(By.CSS_SELECTOR, "#scale-form button[type=submit]").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#scales[data-entries='1']"))
    assert d.find_element(By.ID, "scale-result").get_attribute("data-saved") == "1"
    chart = d.find_element(By.ID, "p-scale-fugl_meyer_ue")
    assert chart.get_attribute("data-points") == "1", "one score"
    assert chart.get_attribute("data-y-range") == "0 66", "the scale's own range"
    assert len(scales.find_elements(By.CSS_SELECTOR, ".chart")) == 1, "no station measure beside it"
    row = d.find_element(By.CSS_SELECTOR, "#scales-table tbody tr[data-scale='fugl_meyer_ue']")
    assert message(d, "scales-points", {"score": 34}) in row.text and "ana@clinic.example" in row.text
    # The numbers of the chart as a table under it.
    numbers = chart.find_element(By.XPATH, "..").find_element(By.CSS_SELECTOR, "details.numbers table")
    values = [td.get_attribute("textContent").strip() for td in numbers.find_elements(By.CSS_SELECTOR, "tbody td.num")]
    assert values == ["34"], values
    # The one-page print keeps the section (the form and buttons are hidden in print).
    assert "print-hide" not in (scales.get_attribute("class") or "")
    d.execute_script("document.getElementById('scales').scrollIntoView()")
    shot(d, "scales-1-fugl-meyer-on-its-own-chart")
    chart.find_element(By.XPATH, "..").find_element(By.CSS_SELECTOR, "details.numbers summary").click()
    assert_no_violations(d, "Progress with clinical scales")
    # The Box and Block Test shows its own fields and a chart under the first, same dates.
    kind = d.find_element(By.ID, "scale-kind")
    kind.find_element(By.CSS_SELECTOR, "option[value='box_and_block']").click()
    assert not d.find_element(By.ID, "scale-fugl_meyer_ue-score").is_displayed()
    for field, value in (("affected", "12"), ("unaffected", "45")):
        d.find_element(By.ID, f"scale-box_and_block-{field}_blocks_per_min").send_keys(value)
    d.find_element(By.CSS_SELECTOR, "#scale-form button[type=submit]").click()
    wait(d, lambda d: d.find_elements(By.CSS_SELECTOR, "#scales[data-entries='2']"))
    bbt = d.find_element(By.ID, "p-scale-box_and_block")
    assert bbt.is_displayed() and bbt.get_attribute("data-points") == "1"
    d.execute_script("document.getElementById('scales').scrollIntoView()")
    shot(d, "scales-2-box-and-block")
    assert_no_violations(d, "Progress with clinical scales and the Box and Block Test")
    # The one-page print: the scales' table is in it; the charts, form and buttons are not.
    d.execute_cdp_cmd("Emulation.setEmulatedMedia", {"media": "print"})
    try:
        assert d.find_element(By.ID, "scales-table").is_displayed()
        assert not d.find_element(By.ID, "p-scale-fugl_meyer_ue").is_displayed()
        assert not d.find_element(By.ID, "scale-form").is_displayed()
        assert not d.find_element(By.CSS_SELECTOR, "button.delete-scale").is_displayed()
        d.execute_script("document.getElementById('scales').scrollIntoView()")
        shot(d, "scales-3-print")
    finally:
        d.execute_cdp_cmd("Emulation.setEmulatedMedia", {"media": ""})


def fetch_text(d, path):
    """GET `path` with the page's login: [status, content type, content disposition, body]."""
    return d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "fetch(arguments[0], {credentials: 'same-origin'}).then(async r => done([r.status,"
        " r.headers.get('content-type'), r.headers.get('content-disposition'), await r.text()]));", path)


def test_the_progress_views_spreadsheet_opens_in_pandas_with_units_in_headers_and_the_apis_values(clinic, browser):
    import io

    import pandas

    run_session(clinic, "dial-sine", 7)
    d = browser
    d.set_window_size(1366, 768)
    d.get(clinic["web"] + "/")
    link = wait(d, lambda d: d.find_elements(By.LINK_TEXT, "P-0042"))[0]
    link.click()
    wait(d, lambda d: d.find_elements(By.LINK_TEXT, "Progress"))[0].click()
    csv_link = wait(d, lambda d: d.find_elements(By.ID, "measures-csv"))[0]
    assert csv_link.text.startswith("Download spreadsheet (CSV; times in ")
    shot(d, "scales-4-progress-with-the-spreadsheet-link")
    href = csv_link.get_attribute("href")
    status, kind, disposition, text = fetch_text(d, href)
    assert status == 200 and kind == "text/csv; charset=utf-8", (status, kind)
    assert disposition.startswith('attachment; filename="measures-P-0042-') and disposition.endswith('.csv"')
    # pandas 3 reads decimals exactly by default; older ones need the round-trip parser.
    exact = {} if int(pandas.__version__.split(".")[0]) >= 3 else {"float_precision": "round_trip"}
    # Plain words with units on the first header row, the technical names on the second.
    plain = pandas.read_csv(io.StringIO(text), nrows=0)
    for column in ("Smoothness (closer to 0 is smoother)", "Active time (s)", "Wheel turning range (°)", "Pain after (0–10)"):
        assert column in plain.columns, list(plain.columns)
    table = pandas.read_csv(io.StringIO(text), header=1, **exact)
    for column in ("sparc_median", "active_s", "wheel_rom_deg"):
        assert column in table.columns, list(table.columns)
    fixed = ["session_id", "started_local", "started_at_utc", "exercise", "end_reason", "ran_as_prescribed",
             "pain_0_10", "tiredness_0_10", "difficulty"]
    assert list(table.columns[:len(fixed)]) == fixed
    words = d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "fetch('/api/measures/words').then(r => r.json()).then(done);")
    decimals = {m["key"]: m["decimals"] for m in words["measures"]}
    # Every value equals the API's JSON measures of that session.
    sessions = d.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "const p = location.hash.split('/')[2];"
        "fetch(`/api/patients/${p}/sessions`).then(r => r.json()).then(async list => {"
        "  const out = {}; for (const s of list) out[s.session_id] = await (await fetch(`/api/sessions/${s.session_id}/metrics`)).json();"
        "  done(out); });")
    assert sorted(table["session_id"]) == sorted(sessions), "a row a session"
    compared = 0
    for _, row in table.iterrows():
        measures = sessions[row["session_id"]]
        for column in table.columns[len(fixed):]:
            if column in measures:
                # Rounded to the measure's meaningful decimals (half a step at most).
                step = 10 ** -decimals.get(column, 4)
                assert abs(row[column] - measures[column]) <= step / 2 + 1e-9 * abs(measures[column]) or \
                    abs(row[column] - measures[column]) <= 5e-4 * abs(measures[column]), \
                    (row["session_id"], column, row[column], measures[column])
                compared += 1
            else:
                assert pandas.isna(row[column]), (row["session_id"], column)
    assert compared >= 3 * 10, compared
    print(f"CSV: {len(table)} sessions, {len(table.columns) - len(fixed)} measures, {compared} values equal to the API's, rounded")
