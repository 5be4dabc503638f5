#!/usr/bin/env python3
"""Check the crate layering of DESIGN.md ("Crates and the direction of dependencies").

Reads `cargo metadata --format-version 1 --no-deps` (or a JSON file given with --metadata) and
fails, naming the crate and the dependency, when

- a pure crate (common, vehicle, calib, assist, metrics) depends on anything outside its allow list
  (in particular an I/O crate on the deny list: tokio, evdev, hidapi, wgpu, mcap, rustls...);
- any arrow points up the diagram: a crate depends on one of our crates it may not use
  (e.g. netlink on station, vehicle on haptic-wheel, pyext on netlink).

Normal and build dependencies count; dev-dependencies (tests, benches, examples) are allowed
our own lower crates and anything else, since they never reach the shipped code — but a
dev-dependency that points up the diagram is still an error.

On the real workspace it also walks the FULL dependency graph with features as cargo resolves
them for each of the hub's three crates (hub-store, hub-care, hub) and the Python package
alone (`cargo tree -p <crate> -e normal,build`), and fails when any reaches a device library
(DEVICE_LIBRARIES): the clinic's server and an analyst's `pip install` must not need libudev
or a wheel's driver stack.

Python 3 standard library only. Exit 0 with a one-line summary when clean, 1 otherwise.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

# What the station binary sits on: every crate of ours below it in the diagram.
BELOW_STATION = {
    "common",
    "clock",
    "exercises",
    "assist",
    "metrics",
    "calib",
    "gyro-imu",
    "haptic-wheel",
    "wheel-devices",
    "netlink",
    "record",
    "regimen",
    "i18n",
    "render",
    "arm",
    "measures",
}

# Our crates, and which of our crates each one may depend on (the arrows of DESIGN.md).
OUR_CRATES: dict[str, set[str]] = {
    "common": set(),
    # The words of every page (Fluent catalogues): a leaf any crate that speaks to a person uses.
    "i18n": set(),
    # The one injectable clock: a leaf the device crates and the link may use; never a pure
    # crate (they get `dt` or timestamps).
    "clock": set(),
    "exercises": {"common"},
    "assist": {"common"},
    # Movement measures of a session (SPARC, LDLJ, segmentation, range of motion).
    "metrics": {"common"},
    "calib": {"common", "gyro-imu"},
    "gyro-imu": {"common", "clock"},
    "haptic-wheel": {"common", "clock"},
    # The real wheels (evdev, DirectInput 8), pedals and gamepads: the device libraries live here.
    "wheel-devices": {"haptic-wheel", "clock"},
    "netlink": {"common", "clock"},
    # The recording format: sample types of the sensing, wheel, calibration and metrics crates.
    "record": {"common", "calib", "gyro-imu", "haptic-wheel", "metrics"},
    # The prescription: exercises, haptic and assistance settings, and their safety bounds.
    "regimen": {"common", "exercises", "assist", "haptic-wheel", "i18n"},
    # The patient's window: scenes drawn with wgpu; knows no session, thread or device.
    "render": {"common", "gyro-imu", "i18n", "regimen"},
    # The clinic's records: the hub's database, migrations, errors, refusal codes, thresholds.
    "hub-store": {"netlink", "regimen", "metrics"},
    # The hub's clinical logic and station link: ingest, recordings, alerts, pain care, FHIR.
    "hub-care": {"hub-store", "clock", "netlink", "regimen", "i18n", "metrics"},
    # The hub's top: the console's API, `hub serve`, its command line, backup, patient rights.
    "hub": {
        "hub-store",
        "hub-care",
        "common",
        "clock",
        "netlink",
        "record",
        "regimen",
        "i18n",
        "metrics",
    },
    # The patient's arm from the IMUs (tracker, HID and simulated sensing, trunk, calibration,
    # the `[arm]` settings): devices (HID) and a solver thread, below the session. Not pure.
    "arm": {"common", "clock", "calib", "gyro-imu", "record"},
    # A session's measures from its ticks (the collector the recorder feeds): below the
    # session; no device, thread or clock, its one I/O the series' temporary file. Not pure.
    "measures": {"common", "arm", "assist", "gyro-imu", "metrics", "record", "exercises"},
    # A patient's session: the 1 kHz loop, recorder, window supervisor, simulated body, faults.
    "session": BELOW_STATION,
    # The end-of-session text and the clinician's HTML report.
    "report": BELOW_STATION | {"session"},
    # The patient's station: it knows no hub (the link speaks netlink's protocol).
    "station": BELOW_STATION | {"session", "report"},
    # The measurements and drills: they run stations and hubs.
    "tools": BELOW_STATION | {"session", "station", "hub"},
    # The one binary: its command line names the station's, the hub's and the tools' commands.
    "telerehab": BELOW_STATION | {"session", "report", "station", "hub", "tools"},
    "telerehab-py": {"common", "exercises", "assist", "calib", "gyro-imu", "metrics", "record"},
    "telerehab-tests": BELOW_STATION | {"session", "report", "station", "hub", "telerehab"},
}

PURE = ("common", "exercises", "calib", "assist", "metrics")

# Third-party crates a pure crate may use: math, randomness with explicit seeds, errors, serde.
PURE_ALLOW = {
    "nalgebra",
    "rapier2d",
    "rapier2d-f64",
    "rand",
    "rand_chacha",
    "rand_distr",
    "thiserror",
    "serde",
    "serde_json",
    "approx",
    "glam",
    "num-traits",
    # FFT of the SPARC measure (metrics): pure math, no I/O, threads or clocks.
    "rustfft",
    # JSON Schema of the regimen's types (vehicle, assist): serde-like derives, no I/O.
    "schemars",
}

# Crates that do I/O, spawn threads, read clocks or render: never in a pure crate, not even
# as a dev-dependency (named here so the message says why).
IO_DENY = {
    "tokio",
    "tokio-rustls",
    "rustls",
    "rustls-webpki",
    "mio",
    "evdev",
    "hidapi",
    "gilrs",
    "wgpu",
    "winit",
    "egui",
    "egui-wgpu",
    "mcap",
    "rtrb",
    "triple_buffer",
    "thread-priority",
    "core_affinity",
    "signal-hook",
    "tracing-subscriber",
    "pyo3",
    "numpy",
    "png",
    "pollster",
    "anyhow",
}


# Libraries that talk to devices (the kernel's input and force-feedback interfaces, udev, HID).
DEVICE_LIBRARIES = {"evdev", "gilrs", "gilrs-core", "hidapi", "libudev-sys", "libudev", "udev"}

# Our crates that must link no device library, through any path of the graph.
DEVICE_FREE = ("haptic-wheel", "hub-store", "hub-care", "hub", "telerehab-py", "render")


def device_libraries_of(package: str) -> list[str]:
    """The device libraries `package` links, with the features cargo resolves for it alone."""
    out = subprocess.run(
        ["cargo", "tree", "-p", package, "-e", "normal,build", "--prefix", "none", "-f", "{p}"],
        check=True,
        capture_output=True,
        text=True,
    )
    names = {line.split(" ", 1)[0] for line in out.stdout.splitlines() if line.strip()}
    return sorted(names & DEVICE_LIBRARIES)


def load_metadata(path: str | None) -> dict:
    if path:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    out = subprocess.run(
        ["cargo", "metadata", "--format-version", "1", "--no-deps"],
        check=True,
        capture_output=True,
        text=True,
    )
    return json.loads(out.stdout)


def violations(metadata: dict) -> tuple[list[str], int]:
    """The layering errors of the workspace in `metadata`, and how many edges were checked."""
    members = set(metadata.get("workspace_members", []))
    errors: list[str] = []
    edges = 0
    for pkg in metadata["packages"]:
        if members and pkg["id"] not in members:
            continue
        name = pkg["name"]
        for dep in pkg.get("dependencies", []):
            dep_name = dep["name"]
            kind = dep.get("kind") or "normal"
            edges += 1
            where = f"{name} -> {dep_name} ({kind} dependency)"
            if dep_name in OUR_CRATES or dep.get("path"):
                allowed = OUR_CRATES.get(name)
                if allowed is None:
                    errors.append(
                        f"{where}: crate `{name}` is not in the layering table of "
                        "scripts/check_layering.py; add it with the crates it may use"
                    )
                elif dep_name not in allowed and dep_name != name:
                    if kind == "dev" and dep_name not in OUR_CRATES:
                        continue
                    errors.append(
                        f"{where}: points up or across the DESIGN.md diagram; "
                        f"`{name}` may use only {sorted(allowed) or 'no crate of ours'}"
                    )
                continue
            if name in PURE:
                if dep_name in IO_DENY:
                    errors.append(
                        f"{where}: pure crate `{name}` must not depend on the I/O crate "
                        f"`{dep_name}`"
                    )
                elif kind != "dev" and dep_name not in PURE_ALLOW:
                    errors.append(
                        f"{where}: `{dep_name}` is not on the allow list of the pure crates "
                        "(PURE_ALLOW in scripts/check_layering.py); add it there if it does "
                        "no I/O, threads or clocks"
                    )
    return errors, edges


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--metadata", help="read this `cargo metadata` JSON instead of running cargo"
    )
    args = parser.parse_args(argv)
    metadata = load_metadata(args.metadata)
    errors, edges = violations(metadata)
    if not args.metadata:
        for package in DEVICE_FREE:
            reached = device_libraries_of(package)
            if reached:
                errors.append(
                    f"{package} links the device libraries {', '.join(reached)} through its full "
                    "dependency graph (cargo tree -p " + package + " -e normal,build -i <lib>): "
                    "take our device crates without their default features"
                )
    if errors:
        for e in errors:
            print(f"layering: {e}", file=sys.stderr)
        print(f"layering: {len(errors)} violation(s)", file=sys.stderr)
        return 1
    crates = sum(
        1 for p in metadata["packages"] if p["id"] in set(metadata.get("workspace_members", []))
    )
    device_free = "" if args.metadata else f"; no device library in {' or '.join(DEVICE_FREE)}"
    print(f"layering OK: {crates} crates, {edges} dependency edges, pure: {', '.join(PURE)}{device_free}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
