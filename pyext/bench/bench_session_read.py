"""Time and peak memory of ``telerehab.session.read`` on a recording.

    python pyext/bench/bench_session_read.py session.mcap [--runs 3] [--reader old_session.py]

Each run is a fresh Python process (so its peak RSS is the read's own): it imports numpy and the
reader, notes its RSS, reads the recording, and reports the wall time of the read, the peak RSS
of the process (``ru_maxrss``), the RSS before the read and the bytes of the numpy columns
returned. ``--reader`` reads with another ``session.py`` loaded as a stand-alone module (e.g.
the pure-Python decoder of an earlier version: ``git show 0bf130f:pyext/python/telerehab/
session.py > old_session.py``; it needs the ``mcap`` and ``protobuf`` packages). The
recording's session time comes from its ``/wheel`` channel (the last ``t_s``).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

CHILD = r"""
import importlib.util, json, resource, sys, time
import numpy as np

def rss_kib():
    with open("/proc/self/status") as f:
        return next(int(l.split()[1]) for l in f if l.startswith("VmRSS:"))

path, reader = sys.argv[1], sys.argv[2]
if reader:
    spec = importlib.util.spec_from_file_location("old_session", reader)
    session = importlib.util.module_from_spec(spec)
    sys.modules["old_session"] = session
    spec.loader.exec_module(session)
else:
    from telerehab import session
before = rss_kib()
t0 = time.perf_counter()
s = session.read(path)
wall = time.perf_counter() - t0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
columns = sum(a.nbytes for ch in s.channels.values() for a in ch.values() if isinstance(a, np.ndarray))
print(json.dumps({"wall_s": wall, "peak_rss_kib": peak, "before_kib": before,
                  "columns_bytes": columns, "session_s": float(s.channels["/wheel"]["t_s"][-1])}))
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("recording")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--reader", default="", help="a session.py to read with instead of telerehab.session")
    args = ap.parse_args()
    runs = []
    for i in range(args.runs):
        out = subprocess.run(
            [sys.executable, "-c", CHILD, args.recording, os.path.abspath(args.reader) if args.reader else ""],
            check=True,
            capture_output=True,
            text=True,
        )
        r = json.loads(out.stdout)
        runs.append(r)
        print(
            f"run {i + 1}: read {r['wall_s']:.2f} s, peak RSS {r['peak_rss_kib'] / 1024:.0f} MiB "
            f"(before the read {r['before_kib'] / 1024:.0f} MiB), columns {r['columns_bytes'] / 2**20:.0f} MiB"
        )
    wall = statistics.median(r["wall_s"] for r in runs)
    peak = statistics.median(r["peak_rss_kib"] for r in runs) / 1024
    session_s = runs[0]["session_s"]
    size = os.path.getsize(args.recording) / 1e6
    print(
        f"{args.recording}: {size:.1f} MB, {session_s:.0f} s of session; median of {len(runs)}: "
        f"read {wall:.2f} s ({session_s / wall:.0f}x real time), peak RSS {peak:.0f} MiB, "
        f"columns {runs[0]['columns_bytes'] / 2**20:.0f} MiB"
    )


if __name__ == "__main__":
    main()
