"""Time and peak memory of ``telerehab.session.read`` on a recording, whole or in part.

    python pyext/bench/bench_session_read.py session.mcap [--runs 3] [--reader old_session.py]
    python pyext/bench/bench_session_read.py s60.mcap --channels /wheel --start-s 1500 --end-s 2100 --whole

Each run is a fresh Python process (so its peak RSS is the read's own): it imports numpy and the
reader, notes its RSS, reads the recording, and reports the wall time of the read, the peak RSS
of the process (``ru_maxrss``), the RSS before the read and the bytes of the numpy columns
returned. ``--reader`` reads with another ``session.py`` loaded as a stand-alone module (e.g.
the pure-Python decoder of an earlier version: ``git show 0bf130f:pyext/python/telerehab/
session.py > old_session.py``; it needs the ``mcap`` and ``protobuf`` packages). The
recording's session time comes from its ``/wheel`` channel (the last ``t_s``).

``--channels``, ``--start-s``, ``--end-s`` read part of the recording
(``session.read(path, channels=…, start_s=…, end_s=…)``: through the file's summary, only the
chunks holding it decompressed); ``--whole`` also reads the whole file in the same run, the
two alternating run by run, and prints the ratio of their medians.
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

path, reader, part = sys.argv[1], sys.argv[2], json.loads(sys.argv[3])
if reader:
    spec = importlib.util.spec_from_file_location("old_session", reader)
    session = importlib.util.module_from_spec(spec)
    sys.modules["old_session"] = session
    spec.loader.exec_module(session)
else:
    from telerehab import session
before = rss_kib()
t0 = time.perf_counter()
s = session.read(path, **part)
wall = time.perf_counter() - t0
peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
columns = sum(a.nbytes for ch in s.channels.values() for a in ch.values() if isinstance(a, np.ndarray))
t_s = [ch["t_s"] for ch in s.channels.values() if "t_s" in ch and len(ch["t_s"])]
span = (min(float(t[0]) for t in t_s), max(float(t[-1]) for t in t_s)) if t_s else (0.0, 0.0)
print(json.dumps({"wall_s": wall, "peak_rss_kib": peak, "before_kib": before, "columns_bytes": columns,
                  "session_s": span[1], "first_s": span[0], "samples": max((len(t) for t in t_s), default=0)}))
"""


def measure(recording: str, reader: str, part: dict, label: str, i: int) -> dict:
    """One read in a fresh Python process, printed."""
    out = subprocess.run(
        [sys.executable, "-c", CHILD, recording, reader, json.dumps(part)],
        check=True,
        capture_output=True,
        text=True,
    )
    r = json.loads(out.stdout)
    print(
        f"{label} run {i + 1}: read {r['wall_s']:.3f} s, peak RSS {r['peak_rss_kib'] / 1024:.0f} MiB "
        f"(before the read {r['before_kib'] / 1024:.0f} MiB), columns {r['columns_bytes'] / 2**20:.1f} MiB, "
        f"t_s {r['first_s']:.3f}..{r['session_s']:.3f} s"
    )
    return r


def summary(label: str, runs: list, recording: str) -> float:
    """The medians of `runs`, printed; returns the median wall time, s."""
    wall = statistics.median(r["wall_s"] for r in runs)
    peak = statistics.median(r["peak_rss_kib"] for r in runs) / 1024
    span = runs[0]["session_s"] - runs[0]["first_s"]
    size = os.path.getsize(recording) / 1e6
    print(
        f"{label}: {recording} ({size:.1f} MB), {span:.0f} s of session read; median of {len(runs)}: "
        f"read {wall:.3f} s ({span / wall:.0f}x real time), peak RSS {peak:.0f} MiB, "
        f"columns {runs[0]['columns_bytes'] / 2**20:.1f} MiB"
    )
    return wall


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("recording")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--reader", default="", help="a session.py to read with instead of telerehab.session")
    ap.add_argument("--channels", nargs="+", help="the topics to read (default: all)")
    ap.add_argument("--start-s", type=float, help="read from this session time, s")
    ap.add_argument("--end-s", type=float, help="read up to this session time, s")
    ap.add_argument("--whole", action="store_true", help="also read the whole file, alternating")
    args = ap.parse_args()
    reader = os.path.abspath(args.reader) if args.reader else ""
    part = {k: v for k, v in (("channels", args.channels), ("start_s", args.start_s), ("end_s", args.end_s))
            if v is not None}
    runs, whole = [], []
    for i in range(args.runs):
        runs.append(measure(args.recording, reader, part, "part" if part else "whole", i))
        if part and args.whole:
            whole.append(measure(args.recording, reader, {}, "whole", i))
    wall = summary(f"part {part}" if part else "whole", runs, args.recording)
    if whole:
        whole_wall = summary("whole", whole, args.recording)
        print(f"the part reads {whole_wall / wall:.1f}x faster than the whole file")


if __name__ == "__main__":
    main()
