"""Every action the hub writes into its audit log has words in every console language and a
place in the audit page's filter (crates/hub/console/audit.js KINDS): a new action left without
them would show to an administrator as its code name ("read settings") in every language."""

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
HUB = ROOT / "crates" / "hub"
# The hub's three crates: the audit is written by the store, the clinical logic and the API.
HUB_CRATES = [ROOT / "crates" / c for c in ("hub-store", "hub-care", "hub")]
LANGUAGES = ["en", "de", "es", "zh"]


def written_actions():
    """The action names the hub's source passes to its audit log."""
    found = set()
    for path in (p for crate in HUB_CRATES for p in (crate / "src").rglob("*.rs")):
        text = path.read_text()
        found |= set(re.findall(r'\.audit\(\s*[^,]+,\s*"([a-z_]+)"', text))
        found |= set(re.findall(r'\(\s*"([a-z_]+_alert)"\s*,', text))
    return found


def test_the_scan_finds_the_hubs_audit_actions():
    found = written_actions()
    assert {"login", "put_regimen", "read_settings", "snooze_alert"} <= found, sorted(found)


def test_every_audit_action_has_words_in_every_language_and_a_filter_entry():
    actions = written_actions()
    js = (HUB / "console" / "audit.js").read_text()
    kinds = set(re.findall(r"'([a-z_]+)'", js[js.index("const KINDS"):js.index("const KNOWN")]))
    assert not actions - kinds, f"not in audit.js KINDS: {sorted(actions - kinds)}"
    for lang in LANGUAGES:
        ftl = (ROOT / "crates" / "i18n" / "console" / lang / "audit.ftl").read_text()
        worded = set(re.findall(r"^audit-kind-([a-z_]+) = ", ftl, re.M))
        assert not kinds - worded, f"{lang}: no words for {sorted(kinds - worded)}"
