#!/usr/bin/env bash
# CI's check of the Debian package (issue 27), as root on a Debian machine:
#   bash scripts/test_package.sh [target/debian/telerehab_<version>_<arch>.deb]
# Installs it with apt (dependencies from Debian), runs the installed binary (`--version`,
# `doctor --json` with no hardware), checks the hub's unit with systemd-analyze, pairs a station
# with a hub on loopback (both /usr/bin/telerehab, the hub as the package's system user) and
# delivers a 5 s simulated session, runs lintian, then purges the package and checks that
# nothing of it is left. Copes with no systemd or udev running (containers).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT="$PWD"

fail() { echo "test_package: FAILED: $*" >&2; exit 1; }
step() { echo "== test_package: $*"; }
[ "$(id -u)" -eq 0 ] || fail "must run as root (it installs and purges the package): sudo $0 $*"

DEB="${1:-$(ls -t "$ROOT"/target/debian/telerehab_*.deb 2>/dev/null | head -1)}"
[ -f "$DEB" ] || fail "no package: run scripts/package.sh first (or name the .deb)"
DEB="$(cd "$(dirname "$DEB")" && pwd)/$(basename "$DEB")"
if [ -n "$(ls -A /var/lib/telerehab-hub 2>/dev/null)" ]; then
  fail "/var/lib/telerehab-hub holds a hub's data: this check installs and purges the package, run it on a CI machine"
fi
T="$(mktemp -d)"; chmod 0755 "$T"
HUB_PID=""
cleanup() {
  if [ -n "$HUB_PID" ]; then kill "$HUB_PID" 2>/dev/null || true; wait "$HUB_PID" 2>/dev/null || true; fi
  if dpkg-query -W -f='${Status}' telerehab 2>/dev/null | grep -q installed; then
    echo "test_package: purging the package left by a failed step" >&2
    DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq telerehab >/dev/null 2>&1 || true
  fi
  rm -rf "$T"
}
trap cleanup EXIT
export XDG_RUNTIME_DIR="$T/run"; mkdir -m 0700 "$XDG_RUNTIME_DIR"
START_S=$SECONDS

step "install $(basename "$DEB")"
apt_install() { DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "$DEB"; }
# Its dependencies come from Debian: refresh the package lists once if they are stale or absent.
apt_install >"$T/apt.log" 2>&1 || { apt-get update -qq && apt_install; } >>"$T/apt.log" 2>&1 \
  || { cat "$T/apt.log"; fail "apt-get install"; }
dpkg -L telerehab | sort > "$T/files"
/usr/bin/telerehab --version | grep -q '^telerehab ' || fail "telerehab --version"
getent passwd telerehab-hub >/dev/null || fail "postinst made no telerehab-hub user"
[ "$(stat -c '%U %a' /var/lib/telerehab-hub)" = "telerehab-hub 700" ] \
  || fail "/var/lib/telerehab-hub is not the hub user's, mode 0700: $(stat -c '%U %a' /var/lib/telerehab-hub)"

step "doctor --json, no hardware: exit 1, the wheel named missing"
set +e; HOME="$T/patient" /usr/bin/telerehab doctor --json > "$T/doctor.json" 2>"$T/doctor.err"; rc=$?; set -e
[ "$rc" -eq 1 ] || { cat "$T/doctor.json" "$T/doctor.err"; fail "doctor exited $rc, not 1 (not ready)"; }
python3 - "$T/doctor.json" <<'EOF' || fail "doctor's JSON does not name the wheel as missing"
import json, sys
report = json.load(open(sys.argv[1]))
wheel = [c for c in report["checks"] if c["name"] == "wheel"]
assert report["ready"] is False and wheel and wheel[0]["status"] == "fail", report
assert "no force-feedback wheel found" in wheel[0]["detail"], wheel
EOF

step "the hub's unit: systemd-analyze verify and security"
UNIT=/usr/lib/systemd/system/telerehab-hub.service
systemd-analyze verify "$UNIT" || fail "systemd-analyze verify $UNIT"
EXPOSURE="$(systemd-analyze security --offline=true "$UNIT" 2>&1 \
  | sed -n 's/.*Overall exposure level for telerehab-hub.service: \([0-9.]*\).*/\1/p')"
[ -n "$EXPOSURE" ] || fail "no exposure figure from systemd-analyze security"
python3 -c "import sys; sys.exit(0 if float('$EXPOSURE') <= 2.0 else 1)" \
  || fail "the unit's exposure is $EXPOSURE, over 2.0"
echo "exposure $EXPOSURE"

step "a hub (as telerehab-hub) and a paired station on loopback, a 5 s simulated session"
as_hub() { runuser -u telerehab-hub -- /usr/bin/telerehab "$@"; }
install -d -o telerehab-hub -g telerehab-hub -m 0700 "$T/clinic"
as_hub hub init --data "$T/clinic" --admin ci@clinic.example > "$T/init.txt" \
  || fail "hub init"
grep -q "telerehab-hub.service" "$T/init.txt" || fail "hub init does not name the service"
CODE="$(as_hub hub patient add --data "$T/clinic" --pseudonym P-0099 \
  | sed -n 's/.*pairing code: *\([A-Z0-9-]*\).*/\1/p')"
[ -n "$CODE" ] || fail "hub patient add printed no pairing code"
runuser -u telerehab-hub -- /usr/bin/telerehab hub serve --data "$T/clinic" \
  --stations 127.0.0.1:0 > "$T/hub.out" 2> "$T/hub.err" &
HUB_PID=$!
for _ in $(seq 1 300); do grep -q '^stations listening on ' "$T/hub.out" && break; sleep 0.1; done
ADDR="$(sed -n 's/^stations listening on \([^ ]*\).*/\1/p' "$T/hub.out")"
[ -n "$ADDR" ] || { cat "$T/hub.out" "$T/hub.err"; fail "the hub printed no address"; }
ADDR="localhost:${ADDR##*:}"
/usr/bin/telerehab pair --hub "$ADDR" --code "$CODE" --home "$T/station" > "$T/pair.txt" \
  || fail "pair: $(cat "$T/pair.txt")"
grep -q '^paired: ' "$T/pair.txt" || fail "pair: $(cat "$T/pair.txt")"
/usr/bin/telerehab run --sim --headless --speed max --duration 5 --home "$T/station" \
  > "$T/run.txt" 2> "$T/run.err" || { cat "$T/run.txt" "$T/run.err"; fail "run"; }
grep '^therapist ' "$T/run.txt"
# "therapist HOST:PORT N summaries: N sent, N acknowledged, 0 NOT delivered"
N="$(awk '/^therapist /{for(i=2;i<=NF;i++) if ($i ~ /^[0-9]+$/) {print $i; exit}}' "$T/run.txt")"
grep -q "$N sent, $N acknowledged, 0 NOT delivered" "$T/run.txt" \
  || { cat "$T/run.txt"; fail "the station did not deliver every summary"; }
as_hub hub patient show --data "$T/clinic" P-0099 --json > "$T/show.json"
python3 - "$T/show.json" "$N" <<'EOF' || fail "the hub did not store the session's summaries"
import json, sys
shown, n = json.load(open(sys.argv[1])), int(sys.argv[2])
assert n > 0 and [s["summaries_stored"] for s in shown["sessions"]] == [n], (n, shown)
EOF
kill "$HUB_PID"; wait "$HUB_PID" || true; HUB_PID=""
echo "delivered $N summaries"

step "lintian"
# No error and no warning (packaging/README.md, "lintian", says what the info tags are).
lintian --fail-on error,warning "$DEB" || fail "lintian reports an error or a warning"

step "purge (a hub's data is kept, the rest goes)"
runuser -u telerehab-hub -- touch /var/lib/telerehab-hub/hub.db
DEBIAN_FRONTEND=noninteractive apt-get purge -y -qq telerehab >"$T/purge.log" 2>&1 \
  || { cat "$T/purge.log"; fail "apt-get purge"; }
[ -f /var/lib/telerehab-hub/hub.db ] || fail "purge deleted the hub's data in /var/lib/telerehab-hub"
grep -q "kept the clinic's data in /var/lib/telerehab-hub" "$T/purge.log" \
  || { cat "$T/purge.log"; fail "purge did not say it kept the hub's data"; }
rm -rf /var/lib/telerehab-hub
left=""
while read -r f; do
  # Shared directories (/usr/bin, /usr/share/man/man1...) stay; ours, and every file, go.
  if [ -d "$f" ]; then
    case "$f" in *telerehab*) left="$left $f" ;; esac
  elif [ -e "$f" ] || [ -L "$f" ]; then
    left="$left $f"
  fi
done < "$T/files"
[ -z "$left" ] || fail "left after purge:$left"
found="$(find /usr /etc -name '*telerehab*' 2>/dev/null)"
[ -z "$found" ] || fail "left after purge: $found"
echo "test_package: OK in $((SECONDS - START_S)) s"
