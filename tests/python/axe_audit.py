"""axe-core's accessibility audit run inside a page the browser tests opened.

axe-core is fetched by scripts/fetch_axe.sh (pinned by version and SHA-256; run by
scripts/setup.sh) into .cache/; it is never skipped: a missing copy fails the test with the fix.
axe cannot judge what a canvas draws, so every chart must also give its numbers as text."""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
AXE_JS = next(iter(sorted((ROOT / ".cache").glob("axe-core-*/axe.min.js"))), None)

# The standard audit: WCAG 2.0/2.1/2.2 A and AA rules and axe's best practices.
TAGS = ["wcag2a", "wcag2aa", "wcag21a", "wcag21aa", "wcag22aa", "best-practice"]


def violations(driver):
    """axe-core's violations on the page as shown, one line each: rule, impact, what it asks,
    and the first elements it found."""
    assert AXE_JS is not None, "axe-core is missing: run bash scripts/fetch_axe.sh (scripts/setup.sh does)"
    if not driver.execute_script("return typeof window.axe === 'object'"):
        driver.execute_script(AXE_JS.read_text())
    driver.set_script_timeout(60)
    result = driver.execute_async_script(
        "const done = arguments[arguments.length - 1];"
        "axe.run(document, {runOnly: {type: 'tag', values: arguments[0]}, resultTypes: ['violations']})"
        ".then(r => done(r.violations.map(v => ({id: v.id, impact: v.impact, help: v.help,"
        " nodes: v.nodes.slice(0, 3).map(n => n.target.join(' '))}))))"
        ".catch(e => done([{id: 'axe-error', impact: 'critical', help: String(e), nodes: []}]));",
        TAGS,
    )
    return [f"{v['id']} ({v['impact']}): {v['help']} — {', '.join(v['nodes'])}" for v in result]


def assert_no_violations(driver, screen):
    """Fail naming every violation axe-core finds on `screen`."""
    found = violations(driver)
    assert not found, f"axe-core on {screen}:\n" + "\n".join(found)


def assert_no_violations_in_language(driver, screen, tag):
    """Fail naming every violation axe-core finds on `screen`, after checking that the page is
    in language `tag` (its `<html lang>`), so that an audit never passes on the wrong words."""
    lang = driver.execute_script("return document.documentElement.lang")
    assert lang == tag, f"{screen}: the page is in {lang!r}, not {tag!r}"
    assert_no_violations(driver, f"{screen} ({tag})")
