#!/usr/bin/env bash
# Install, use and uninstall telerehab's Windows installer silently under Wine (issue 46):
#   bash scripts/test_windows_installer.sh [SETUP.exe]   # default: target/windows/telerehab-setup-<version>.exe
# Checks: the silent install (/S, in German) puts the program, its icon, COPYRIGHT.txt and the
# uninstaller in %LOCALAPPDATA%\Programs\telerehab, the Start-menu shortcut (its description the
# German catalogue's) and the uninstall key under HKCU; the installed telerehab.exe says its
# version and runs a simulated headless session (10 s, seed 7) with its home in
# %APPDATA%\telerehab\config, that replays bit for bit; the silent uninstall removes program,
# shortcut and key and leaves the patient's home. Prints how long each step took.
# Runs Wine in a throwaway prefix (scripts/wine/prefix.sh); nothing is left.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT="$PWD"
VERSION="$(python3 -c 'import tomllib; print(tomllib.load(open("Cargo.toml", "rb"))["workspace"]["package"]["version"])')"
SETUP="${1:-$ROOT/target/windows/telerehab-setup-$VERSION.exe}"
case "$SETUP" in -h|--help) sed -n '2,8p' "$0"; exit 0 ;; esac
[ -f "$SETUP" ] || { echo "test_windows_installer.sh: no installer at $SETUP (bash scripts/package-windows.sh builds it)" >&2; exit 2; }
SETUP="$(cd "$(dirname "$SETUP")" && pwd)/$(basename "$SETUP")"

fail() { echo "test_windows_installer.sh: FAILED: $*" >&2; exit 1; }
step() { printf '\n== windows installer: %s\n' "$*"; STEP_START=$EPOCHREALTIME; }
took() { awk -v a="$STEP_START" -v b="$EPOCHREALTIME" 'BEGIN { printf "   (%.1f s)\n", b - a }'; }

# shellcheck source=wine/prefix.sh
source scripts/wine/prefix.sh
WORK="$(mktemp -d)"
trap 'wine_prefix_end; rm -rf "$WORK"' EXIT
step "a Wine prefix of its own"
wine_prefix "$WORK/wine"
took
wine() { command wine "$@" 2> >(grep -v ':fixme:' >&2); }
# A folder of the user's profile as Windows names it (%APPDATA% → C:\users\…\AppData\Roaming),
# and as a Linux path.
win_var() { wine cmd /c echo "%$1%" | tr -d '\r'; }
ROAMING_WIN="$(win_var APPDATA)"
LOCAL="$(winepath -u "$(win_var LOCALAPPDATA)" 2>/dev/null)"
ROAMING="$(winepath -u "$ROAMING_WIN" 2>/dev/null)"
INSTDIR="$LOCAL/Programs/telerehab"
SHORTCUT="$ROAMING/Microsoft/Windows/Start Menu/Programs/telerehab.lnk"
HOME_DIR="$ROAMING/telerehab/config"
KEY='HKCU\Software\Microsoft\Windows\CurrentVersion\Uninstall\telerehab'

step "install silently, in German: $(basename "$SETUP") /S"
# Windows' display language picks the installer's; under Wine, LANG does.
env LC_ALL=de_DE.UTF-8 LANG=de_DE.UTF-8 wine "$SETUP" /S
wineserver -w
took
for f in telerehab.exe telerehab.ico COPYRIGHT.txt uninstall.exe; do
  [ -s "$INSTDIR/$f" ] || fail "the installer left no $f in %LOCALAPPDATA%\\Programs\\telerehab"
done
[ -s "$SHORTCUT" ] || fail "the installer made no Start-menu shortcut"
# The shortcut's description is the German catalogue's (crates/i18n/locales/de/installer.ftl).
python3 - "$SHORTCUT" <<'PY' || fail "the Start-menu shortcut's description is not the German catalogue's"
import re, sys
ftl = open("crates/i18n/locales/de/installer.ftl", encoding="utf-8").read()
comment = re.search(r"^installer-shortcut-comment = (.+)$", ftl, re.M).group(1).strip()
sys.exit(0 if comment.encode("utf-16-le") in open(sys.argv[1], "rb").read() else 1)
PY
wine reg query "$KEY" /v DisplayVersion | tr -d '\r' | grep -q "REG_SZ[[:space:]]*$VERSION\$" \
  || fail "the uninstall key under HKCU does not say version $VERSION"
wine reg query "$KEY" /v QuietUninstallString | tr -d '\r' | grep -q 'uninstall.exe" /S' \
  || fail "the uninstall key names no silent uninstaller"
echo "installed: program, icon, COPYRIGHT.txt, uninstaller, Start-menu shortcut, HKCU uninstall key"

EXE="$INSTDIR/telerehab.exe"
step "the installed telerehab.exe --version"
wine "$EXE" --version | tr -d '\r' | tee "$WORK/version.txt"
grep -q "^telerehab $VERSION " "$WORK/version.txt" || fail "the installed program is not version $VERSION"
took

# An unpaired station uses no home unless one is named: name the one a paired station uses by
# default on Windows (`directories`' config dir), so that the session writes its log there.
step "a simulated headless session from the installed program, its home in %APPDATA% (10 s, seed 7)"
wine "$EXE" run --sim --headless --speed max --duration 10 --seed 7 --log warn \
  --home "$ROAMING_WIN"'\telerehab\config' \
  --record 'Z:'"$WORK/session.mcap" > "$WORK/session.txt" \
  || { cat "$WORK/session.txt"; fail "the simulated session failed"; }
[ -s "$WORK/session.mcap" ] || fail "the session left no recording"
ls "$HOME_DIR"/logs/session-*.log >/dev/null 2>&1 || fail "the session wrote no log in its home in %APPDATA%"
wine "$EXE" replay 'Z:'"$WORK/session.mcap" --log warn | tr -d '\r' | tee "$WORK/replay.txt"
grep -q '^replay: identical' "$WORK/replay.txt" || fail "the installed program does not reproduce its session"
took

step "uninstall silently: uninstall.exe /S"
wine "$INSTDIR/uninstall.exe" /S
wineserver -w   # the uninstaller runs from a copy in %TEMP%: wait for every process of the prefix
took
[ ! -e "$INSTDIR" ] || fail "the uninstaller left $(ls "$INSTDIR" | tr '\n' ' ')in the program's folder"
[ ! -e "$SHORTCUT" ] || fail "the uninstaller left the Start-menu shortcut"
if wine reg query "$KEY" >/dev/null 2>&1; then fail "the uninstaller left the HKCU uninstall key"; fi
[ -d "$HOME_DIR" ] || fail "the uninstaller removed the patient's home (it must stay)"

echo
echo "test_windows_installer.sh: installed, ran, replayed and uninstalled silently under Wine; the patient's home stays"
