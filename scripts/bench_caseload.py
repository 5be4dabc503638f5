"""Times the caseload by need (GET /api/patients?sort=need, issue 41) on a SQLite clinic of N
patients with S sessions each (41 measures and a check-in a session), through `hub serve`.

    TELEREHAB_BIN=target/debug/telerehab python3 scripts/bench_caseload.py 25 60
"""
import json, os, re, sqlite3, ssl, subprocess, sys, tempfile, time, urllib.request, statistics
from pathlib import Path
BIN = os.environ.get("TELEREHAB_BIN", "target/debug/telerehab")
N, S = int(sys.argv[1]), int(sys.argv[2])
tmp = Path(tempfile.mkdtemp(prefix="bench-caseload-"))
data = tmp / "clinic"
out = subprocess.run([BIN, "hub", "init", "--data", str(data), "--admin", "ana@clinic.example"], capture_output=True, text=True).stdout
pw = re.search(r"one-time password: (\S+)", out).group(1)
for i in range(N):
    subprocess.run([BIN, "hub", "patient", "add", "--data", str(data), "--pseudonym", f"P-{i:04d}"], capture_output=True, check=True)
con = sqlite3.connect(data / "hub.db")
now = int(time.time() * 1000); DAY = 86_400_000
for i, (pid,) in enumerate(con.execute("SELECT id FROM patients").fetchall()):
    st = f"st-{i:016x}"
    con.execute("INSERT INTO stations (station_id, patient_id, cert_fingerprint, paired_at_ms, last_seen_ms) VALUES (?,?,?,?,?)", (st, pid, f"{i:064x}", now - 400*DAY, now - DAY))
    for k in range(S):
        sid = f"s-{i}-{k}"; start = now - (S - k) * DAY // 2
        con.execute("INSERT INTO sessions (session_id, station_id, patient_id, exercise, started_unix_ms, software_version, opened_at_ms, closed_at_ms, end_reason, last_seq) VALUES (?,?,?,?,?,'x',?,?,'complete',0)", (sid, st, pid, "sine-road" if k % 2 else "dial-sine", start, start, start + 600000))
        for m in range(40):
            con.execute("INSERT INTO session_metrics VALUES (?,?,?)", (sid, f"m{m}", float(m)))
        con.execute("INSERT INTO session_metrics VALUES (?,?,?)", (sid, "wheel_rom_deg", 40.0 - k * 0.01))
        con.execute("INSERT INTO session_checkins (session_id, patient_id, started_unix_ms, pain_0_10, received_at_ms) VALUES (?,?,?,?,?)", (sid, pid, start, k % 5, start))
con.commit(); con.close()
hub = subprocess.Popen([BIN, "hub", "serve", "--data", str(data), "--stations", "127.0.0.1:0", "--web", "127.0.0.1:0"], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
try:
    hub.stdout.readline(); web = re.search(r"https://(\S+)/api/", hub.stdout.readline()).group(1)
    ctx = ssl.create_default_context(); ctx.check_hostname = False; ctx.verify_mode = ssl.CERT_NONE
    cookie = None
    def call(method, path, body=None):
        global cookie
        req = urllib.request.Request(f"https://{web}{path}", method=method, data=None if body is None else json.dumps(body).encode(), headers={"Content-Type": "application/json", **({"Cookie": cookie} if cookie else {})})
        r = urllib.request.urlopen(req, context=ctx)
        sc = r.headers.get("Set-Cookie")
        if sc and sc.startswith("telerehab"): cookie = sc.split(";")[0]
        return r.read()
    call("POST", "/api/login", {"email": "ana@clinic.example", "password": pw})
    call("POST", "/api/me/password", {"current": pw, "new": "a long bench passphrase"})
    times = []
    for _ in range(7):
        t = time.perf_counter(); body = call("GET", "/api/patients?sort=need"); times.append((time.perf_counter() - t) * 1000)
    print(f"{N} patients x {S} sessions: GET /api/patients?sort=need median {statistics.median(times):.0f} ms, max {max(times):.0f} ms, {len(body)} bytes; runs {[round(x) for x in times]}")
finally:
    hub.terminate(); hub.wait()
