"""axe-core's accessibility audit run inside a page the browser tests opened.

axe-core is fetched by scripts/fetch_axe.sh (pinned by version and SHA-256; run by
scripts/setup.sh) into .cache/; it is never skipped: a missing copy fails the test with the fix.
axe cannot judge what a canvas draws, so every chart must also give its numbers as text."""

import re
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


# The console in every language (issue 40): the languages the axe tests run in, English first
# (the full list of screens), then the others and the pseudo-locale (a representative set).
LANGUAGES = ["en", "de", "es", "zh", "en-XA"]


def use_language(driver, tag):
    """Keeps `tag` as the logged-in therapist's console language (PUT /api/me/language) and
    reloads the page in it (waits for `<html lang>`)."""
    from selenium.webdriver.support.ui import WebDriverWait
    status = driver.execute_async_script(
        "const [tag, done] = arguments;"
        "fetch('/api/me/language', {method: 'PUT', credentials: 'same-origin',"
        " headers: {'Content-Type': 'application/json'}, body: JSON.stringify({language: tag})})"
        ".then(r => done(r.status));", tag)
    assert status == 200, f"PUT /api/me/language {tag}: {status}"
    driver.refresh()
    # The page's first screen drawn in the language (a screen asked for before it would be
    # drawn over by it).
    WebDriverWait(driver, 30).until(lambda d: d.execute_script(
        "return document.documentElement.dataset.booted === 'true' && document.documentElement.lang") == tag)


# Text a translation leaves as it is: numbers, dates and times (the pseudo-locale formats them
# as English does), pseudonyms, e-mails, units, the product's name.
KEPT = re.compile(r"\b(?:Jan|Feb|Mar|Apr|May|Jun|Jul|Aug|Sep|Oct|Nov|Dec|AM|PM|UTC)\b|P-\d+|[\w.]+@[\w.]+"
                  r"|\btelerehab\b|N·m|°|%")

# The page's visible text nodes, outside `arguments[0]` (a CSS selector of what not to check:
# the language menu names languages in their own language; what is marked translate="no" is a
# name).
TEXT_NODES = """
const skip = ['#language', '[translate="no"]', 'code', 'script', 'style', arguments[0]].filter(Boolean).join(', ');
const out = [];
const walk = document.createTreeWalker(document.body, NodeFilter.SHOW_TEXT);
for (let n = walk.nextNode(); n; n = walk.nextNode()) {
  const text = n.textContent.trim();
  const el = n.parentElement;
  if (!text || !el || el.closest(skip)) continue;
  if (!el.checkVisibility({ checkOpacity: true, checkVisibilityCSS: true })) continue;
  const r = el.getBoundingClientRect();
  if (r.width < 2 || r.height < 2) continue;
  out.push(text);
}
return out;
"""


def visible_texts(driver, skip=""):
    """The page's visible text nodes (trimmed), outside `skip` (a CSS selector)."""
    return driver.execute_script(TEXT_NODES, skip)


def english_left(en_texts, pseudo_texts):
    """The pseudo-locale's text nodes that are English: the same as a node of the English
    render and, with numbers, dates, pseudonyms and names removed, still holding a letter."""
    english = set(en_texts)
    return [t for t in pseudo_texts if t in english and re.search(r"[A-Za-z]", KEPT.sub("", t))]
